"""Settings of a level map (``acoustiviz map`` and the scene output ``[outputs.level_map]``).

The one home of the map's options, ranges and defaults; :mod:`acoustiviz.app.maps` computes the map.
"""

from __future__ import annotations

from .table import Setting

__all__ = ["MAP_SETTINGS", "PLANES", "MAP_SCENE_VTK"]

#: The planes a map can lie in (see :mod:`acoustiviz.app.maps`).
PLANES = ("vertical", "horizontal")


#: The scene table of a map's settings.
_TABLE = "outputs.level_map"
#: Settings of a level map, shared by ``acoustiviz map`` and the scene output ``[outputs.level_map]``.
MAP_SETTINGS = (
    Setting("plane", "--plane", "plane", "str", "vertical",
            "plane of the map: 'vertical', the plane y = 0 through the sphere's centre holding the "
            "acceleration axis (normal to the wall in the wall-floor corner); 'horizontal', the plane "
            "z = height parallel to the floor", choices=PLANES, table=_TABLE),
    Setting("height", "--plane-height", "height_m", "float", None,
            "horizontal plane only: its height z above the floor (default: the sphere's centre); in the free "
            "field any height, else >= 0", "m", low=-1e3, high=1e3, table=_TABLE),
    Setting("extent", "--extent", "extent_m", "float", 0.5,
            "distance from the sphere's centre to the far edges of the map (more than the sphere's diameter); "
            "the map is cut at the floor and the wall", "m", low=0.0, high=1e3, low_open=True, table=_TABLE),
    Setting("resolution", "--resolution", "resolution", "int", 317,
            "grid points along the longer side of the map (square spacing; the default gives about 1e5 points "
            "on a square map)", low=8, high=20000, table=_TABLE),
)

#: ``[outputs.level_map] vtk``: a scene names the map's VTK file itself (the command line's ``--vtk PATH``).
MAP_SCENE_VTK = Setting("vtk", None, "vtk", "bool", False,
                        "also write the map as level_map.vtu with the sphere and planes in level_map_geometry.vtu "
                        "(ParaView, pyvista, meshio)", table=_TABLE)
