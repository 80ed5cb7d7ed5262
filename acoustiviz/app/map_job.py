"""The map job: peak SPL and SEL of one impact over a plane (``acoustiviz map``, scene ``[outputs.level_map]``).

Three parts, shared by ``acoustiviz map``, a scene's ``[outputs.level_map]`` and Python callers:

* :class:`~acoustiviz.app.settings.map_job.MapJob`, the settings, checked once when made;
* :func:`run`, which computes a :class:`MapResult` from them (physics only: no files, no printing);
* :meth:`MapResult.write`, which writes the files the settings asked for from the one map and returns their paths.

The map itself (its grid, planes and files) is :mod:`acoustiviz.app.maps`.

Examples
--------
>>> from acoustiviz.app.impacts import impact_setup
>>> s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config="plane")
>>> result = run(MapJob(impact=s.impact, pulse=s.pulse, medium=s.medium, geometry=s.geometry,
...                     extent=0.3, resolution=21))
>>> result.level.grid.shape  # (points along z, along x): the map is cut at the floor
(12, 21)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .maps import LevelMap, level_map, map_title, points_bar, summary_figures, write_map_outputs
from .settings.map_job import MapJob

__all__ = ["MapJob", "MapResult", "run", "map_settings", "produce_level_map"]


@dataclass(frozen=True, eq=False)
class MapResult:
    """The map of a :class:`~acoustiviz.app.settings.map_job.MapJob`.

    Attributes
    ----------
    settings : MapJob
        What was computed.
    level : LevelMap
        The grid in m, the peak pressure in Pa, the peak SPL in dB re 20 µPa, the SEL in dB re (20 µPa)²·s
        and the time of the peak in s.
    """

    settings: MapJob
    level: LevelMap

    def title(self) -> str:
        """The figure's title: the configuration, the plane, the speed, the sphere and the pulse."""
        s = self.settings
        return map_title(self.level, s.geometry, f"U0 = {s.impact.velocity:g} m/s, "
                                                     f"a = {s.geometry.radius * 1e3:g} mm, {s.pulse.kind} pulse")

    def write(self, folder=None) -> list:
        """Write the files the settings ask for into ``folder``; return their paths.

        The table (:func:`write_map_csv`), the figure and the VTK file with ``<stem>_geometry.vtu`` beside
        it (:func:`write_map_outputs`), each atomically, from the one map.

        Parameters
        ----------
        folder : path-like, optional
            Where relative file names are put (default: as given, the current folder).

        Returns
        -------
        list of pathlib.Path
        """
        files = {k: Path(v) if folder is None else Path(folder) / v for k, v in self.settings.files().items()}
        return write_map_outputs(self.level, self.settings.geometry, title=self.title(), **files)


def run(settings: MapJob, *, progress=None) -> MapResult:
    """Compute the map of ``settings`` (no files).

    Parameters
    ----------
    settings : MapJob
        The job, checked when it was made.
    progress : callable, optional
        ``progress(done, total)`` in points (:func:`points_bar`).

    Returns
    -------
    MapResult
    """
    s = settings
    level = level_map(s.pulse, s.geometry, medium=s.medium, plane=s.plane, height=s.height, extent=s.extent,
                      resolution=s.resolution, max_memory_mb=s.max_memory_mb, names=s.names, progress=progress)
    return MapResult(s, level)


def map_settings(scene, out=None):
    """The scene's ``[outputs.level_map]`` as a :class:`~acoustiviz.app.settings.map_job.MapJob`.

    The files are ``level_map.png``, ``level_map.csv`` and, with ``vtk = true``, ``level_map.vtu`` in folder
    ``out`` (None: no files, the checks of the scene's settings alone, made before the run folder exists);
    errors name scene keys.
    """
    opts, setup = scene.output("level_map"), scene.setup()
    kinds = ("png", "csv", "vtk") if opts["vtk"] else ("png", "csv")
    files = {} if out is None else {k: str(Path(out) / f"level_map.{'vtu' if k == 'vtk' else k}") for k in kinds}
    names = MapJob.names_for("scene")
    return MapJob(impact=setup.impact, pulse=setup.pulse, medium=setup.medium, geometry=setup.geometry,
                  plane=opts["plane"],
                  height=opts["height_m"], extent=opts["extent_m"], resolution=opts["resolution"],
                  max_memory_mb=scene.section("grids")["memory_limit_mb"], k_hertz_source=setup.k_hertz_source,
                  names=names, **files)


def produce_level_map(ctx):
    """Scene output ``level_map``: ``level_map.csv``, ``level_map.png`` and, with ``vtk``, ``level_map.vtu``."""
    from .products import Product

    settings = map_settings(ctx.scene, ctx.out)
    for path in settings.files().values():  # only the files checked before the run
        ctx.path(Path(path).name)
    with points_bar(ctx.stream) as bar:
        result = run(settings, progress=bar)
    paths = result.write()
    figs = summary_figures(result.level)
    return [Product("level_map", p, figs if i == 0 else {}) for i, p in enumerate(paths)]
