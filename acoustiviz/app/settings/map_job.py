"""The settings of the map job: one impact, its surroundings, the plane, its extent and resolution, and the files.

:class:`MapJob` is the whole of what :func:`acoustiviz.app.maps.run` needs, checked once when it is made
(the table's ranges, the plane against the scene, the memory budget and the number of points, the files
to write), so ``acoustiviz map``, a scene's ``[outputs.level_map]`` and a Python caller build the same
object and hand it to the same run. The records of its files (``--png``, ``--csv``, ``--vtk``) live here
beside :data:`~acoustiviz.app.settings.map.MAP_SETTINGS`.
"""

from __future__ import annotations

import dataclasses

from .impact import ImpactJob
from .map import MAP_SETTINGS
from .table import Setting
from .vocabulary import OUTPUT_TABLES

__all__ = ["MAP_OUTPUTS", "MapJob"]

#: The files of the job (a scene names them itself: ``level_map.png``, ``.csv`` and ``.vtu`` in its folder).
MAP_OUTPUTS = (
    Setting("png", "--png", None, "str", None, "two panels, peak SPL and SEL, with the sphere and planes",
            metavar="PATH"),
    Setting("csv", "--csv", None, "str", None,
            "columns x_m,y_m,z_m,peak_pa,peak_spl_db,sel_db,time_of_peak_s, one row per grid point "
            "(nan inside the sphere)", metavar="PATH"),
    Setting("vtk", "--vtk", None, "str", None,
            "the map for ParaView, pyvista or meshio: a .vtu (or .vtkhdf) file with point arrays "
            "peak_pa, peak_spl_db, sel_db, time_of_peak_s, exposure_pa2s, and the sphere and planes "
            "beside it in PATH_geometry.vtu", metavar="PATH"),
)
_BY_NAME = {s.name: s for s in MAP_SETTINGS}


@dataclasses.dataclass(frozen=True, kw_only=True)
class MapJob(ImpactJob):
    """Peak SPL and SEL of one impact over a plane through the scene, and its files.

    Attributes
    ----------
    impact : acoustiviz.core.contact.Impact
        Speed (m/s), K_HZ (N/m^1.5) and masses (kg) of the impact.
    pulse : pulse
        The acceleration pulse (m/s² against s).
    medium : acoustiviz.core.medium.Medium
        The fluid.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its image sources (in a room, every image arriving within its window).
    plane : {"vertical", "horizontal"}
        The plane of the map (:data:`~acoustiviz.app.settings.map.PLANES`).
    height : float, optional
        Height in m of a horizontal plane (None: the sphere centre's); refused with the vertical plane.
    extent : float
        Distance in m from the sphere's centre to the map's far edges, more than the sphere's diameter.
    resolution : int
        Points along the map's longer side (square spacing).
    max_memory_mb : float, optional
        Cap in MB on the estimated memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).
    png, csv, vtk : str, optional
        The figure, the table and the VTK file (with ``<stem>_geometry.vtu`` beside it), relative to the
        folder :meth:`acoustiviz.app.maps.MapResult.write` is given.
    k_hertz_source : str
        Where K_HZ came from (reported; not compared).
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name
        (not compared; default: the API names).
    """

    TABLE = (*MAP_SETTINGS, *MAP_OUTPUTS)
    DERIVED_NAMES = {"scene": OUTPUT_TABLES["level_map"]}
    pulse: object
    plane: str = _BY_NAME["plane"].default
    height: float | None = None
    extent: float = _BY_NAME["extent"].default
    resolution: int = _BY_NAME["resolution"].default
    png: str | None = None
    csv: str | None = None
    vtk: str | None = None

    def files(self) -> dict:
        """``{"png": path, "csv": path, "vtk": path}`` as asked (strings)."""
        return {key: getattr(self, key) for key in ("png", "csv", "vtk") if getattr(self, key) is not None}

    def validate(self) -> None:
        """The files, then the plane against the scene, the memory budget and the number of points."""
        from ..maps import plan_map

        self._check_files()
        plan_map(self.pulse, self.geometry, medium=self.medium, plane=self.plane, height=self.height,
                 extent=self.extent, resolution=self.resolution, max_memory_mb=self.max_memory_mb, names=self.names)

    def _check_files(self) -> None:
        from ...output.vtk import geometry_path
        from ..outputs import check_distinct, check_output_file

        kinds = {"png": "figure", "csv": "csv", "vtk": "vtk"}
        paths = {}
        for key, path in self.files().items():
            paths[self._name(key)] = path
            check_output_file(self._name(key), path, kinds[key])
        if self.vtk is not None:
            name = self._name("vtk")
            paths[f"{name} (geometry)"] = check_output_file(name, geometry_path(self.vtk), "vtk")
        check_distinct(paths)
