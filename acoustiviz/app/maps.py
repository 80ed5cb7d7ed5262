"""Where an impact is loud: peak SPL and SEL maps over a plane (``acoustiviz map`` and scene ``level_map``).

:func:`level_map` lays a regular grid over a plane through the scene, evaluates the peaks and
the exposure of the continuous pressure at every point in the fluid with
:func:`acoustiviz.field.fast_peaks` (no time loop), and returns a :class:`LevelMap`: the grid,
the peak pressure in Pa, the peak SPL in dB re 20 µPa, the SEL in dB re (20 µPa)²·s and the
time of the peak in s from the start of contact. Points inside the sphere hold NaN (left blank
in the plots and files).

The planes, in the scene frame of :mod:`acoustiviz.core.images` (floor ``z = 0``, wall
``x = -wall_distance``):

* ``"vertical"`` -- the vertical plane ``y = 0`` through the sphere's centre. It holds the
  acceleration axis and, in the wall-floor corner, is normal to the wall (the plane of
  ``acoustiviz render snapshot --sections xz`` and of the directivity circle).
* ``"horizontal"`` -- the horizontal plane ``z = height`` (default: the height of the sphere's
  centre), parallel to the floor.

Each map spans ``extent`` m from the sphere's centre to its far edges and is cut at the floor
and the wall, so no point lies behind a reflecting plane; ``resolution`` points lie along its
longer side, with square spacing. The settings and their ranges are defined once
(:data:`MAP_SETTINGS`); the command line and the scene files both read them, so the two can
never disagree.

Examples
--------
>>> from acoustiviz.app.impacts import impact_setup
>>> s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config="plane")
>>> m = level_map(s.pulse, s.geometry, medium=s.medium, extent=0.3, resolution=21)
>>> m.grid.shape  # (points along z, along x): the map is cut at the floor
(12, 21)
>>> top = m.grid.image(m.sel_db)[-1, 10]  # SEL 0.3 m above the sphere's centre, in dB
>>> round(float(top), 1)
64.6
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass

import numpy as np

from .._validate import check_choice, check_range
from ..core.medium import AIR, Medium
from ..errors import ParameterError
from .settings.base import vocabulary
from .settings.map import MAP_SETTINGS, PLANES
from .settings.vocabulary import MEMORY

__all__ = [
    "PLANES",
    "MAP_SETTINGS",
    "CLI_NAMES",
    "SCENE_NAMES",
    "MAP_CSV_COLUMNS",
    "LevelMap",
    "check_map_settings",
    "map_grid",
    "map_estimate",
    "map_on_grid",
    "plan_map",
    "level_map",
    "write_map_csv",
    "map_title",
    "summary_figures",
    "write_map_outputs",
    "points_bar",
]

_BY_NAME = {s.name: s for s in MAP_SETTINGS}
#: Most points of one map (160 times the default's 1e5): the work is bounded, not only its memory.
MAX_MAP_POINTS = 4000 * 4000
#: API parameter -> command-line option (errors in the user's terms).
CLI_NAMES = vocabulary("cli", MAP_SETTINGS + MEMORY)
#: API parameter -> scene key.
SCENE_NAMES = vocabulary("scene", MAP_SETTINGS + MEMORY)
#: Columns of the CSV file, in order.
MAP_CSV_COLUMNS = ("x_m", "y_m", "z_m", "peak_pa", "peak_spl_db", "sel_db", "time_of_peak_s")
_CSV_FORMATS = ("%.9e", "%.9e", "%.9e", "%.10e", "%.6f", "%.6f", "%.10e")
#: Bytes per grid point: points, grid, the evaluator's six results, the maps, masks, and the copies
#: made while writing the CSV, the figure and the VTK file, with a margin for VTK's own copies; and
#: the bytes per point of the CSV (7 columns) and VTK (points, quads, 5 arrays) files (the
#: measurements: ``benchmarks/results/design_timings.md``).
_MEMORY_PER_POINT = 8.0 * 64
_CSV_PER_POINT = 120.0
_VTK_PER_POINT = 8.0 * 16


@dataclass(frozen=True)
class LevelMap:
    """Peak SPL and SEL of one impact over a planar grid.

    Attributes
    ----------
    grid : acoustiviz.field.grids.PlanarGrid
        The points in m, ``u`` (along x) varying fastest.
    plane : str
        ``"vertical"`` or ``"horizontal"`` (see :data:`PLANES`).
    peak_pa : (n,) ndarray
        Largest absolute pressure max|p| in Pa (NaN inside the sphere).
    peak_spl_db : (n,) ndarray
        Peak SPL ``20 log10(peak_pa / 20 µPa)`` in dB.
    sel_db : (n,) ndarray
        Sound exposure level ``10 log10(∫p² dt / ((20 µPa)² · 1 s))`` in dB, over the whole response.
    time_of_peak_s : (n,) ndarray
        Time in s from the start of contact at which ``|p|`` reaches ``peak_pa``.
    exposure_pa2s : (n,) ndarray
        ``∫ p² dt`` in Pa²·s.
    """

    grid: object
    plane: str
    peak_pa: np.ndarray
    peak_spl_db: np.ndarray
    sel_db: np.ndarray
    time_of_peak_s: np.ndarray
    exposure_pa2s: np.ndarray

    def arrays(self) -> dict:
        """Point arrays with units in their names: ``{"peak_pa": ..., "peak_spl_db": ..., ...}``."""
        return {"peak_pa": self.peak_pa, "peak_spl_db": self.peak_spl_db, "sel_db": self.sel_db,
                "time_of_peak_s": self.time_of_peak_s, "exposure_pa2s": self.exposure_pa2s}

    def in_plane(self) -> tuple:
        """Names of the in-plane axes: ``("x", "z")`` (vertical) or ``("x", "y")`` (horizontal)."""
        return tuple(SECTION_OF_PLANE[self.plane])


def _defaults(plane, height, extent, resolution):
    return (_BY_NAME["plane"].default if plane is None else plane, height,
            _BY_NAME["extent"].default if extent is None else extent,
            _BY_NAME["resolution"].default if resolution is None else resolution)


def check_map_settings(geometry, *, plane=None, height=None, extent=None, resolution=None) -> tuple:
    """Check the settings of a map against :data:`MAP_SETTINGS` and the scene; return them resolved.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its planes.
    plane : {"vertical", "horizontal"}, optional
        Default ``"vertical"``.
    height : float, optional
        Height in m of a horizontal plane (default the sphere centre's); refused with the vertical plane.
    extent : float, optional
        Distance in m from the sphere's centre to the map's far edges (default 0.5), more than 2a.
    resolution : int, optional
        Points along the longer side (default 317).

    Returns
    -------
    (plane, height, extent, resolution)
        ``height`` in m (the centre's height when not given, ``None`` for the vertical plane).

    Raises
    ------
    ParameterError
        Named ``plane``, ``height``, ``extent`` or ``resolution`` with the allowed range.
    """
    plane, height, extent, resolution = _defaults(plane, height, extent, resolution)
    check_choice("plane", plane, PLANES)
    s = _BY_NAME["extent"]
    extent = check_range("extent", extent, s.low, s.high, unit="m", low_open=True)
    if extent <= 2.0 * geometry.radius:
        raise ParameterError("extent", f"must exceed the sphere's diameter {2 * geometry.radius:g} m (and be <= "
                                       f"{s.high:g} m), got {extent:g} m")
    s = _BY_NAME["resolution"]
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) \
            or not s.low <= resolution <= s.high:
        raise ParameterError("resolution", f"must be an integer in [{s.low:g}, {s.high:g}], got {resolution!r}")
    resolution = int(resolution)
    if plane == "vertical":
        if height is not None:
            raise ParameterError("height", "only used with the horizontal plane; the vertical plane goes through "
                                           "the sphere's centre")
        return plane, None, extent, resolution
    s = _BY_NAME["height"]
    if height is None:
        height = float(geometry.centre[2])
    low = s.low if geometry.floor_height is None else geometry.floor_height
    ceilings = [float(p.point[2]) for p in geometry.planes if p.normal[2] == -1.0]  # a room's ceiling
    height = check_range("height", height, low, min([s.high, *ceilings]), unit="m")
    if abs(height - geometry.centre[2]) >= extent:
        raise ParameterError("height", f"{height:g} m is farther from the sphere's centre (z = "
                                       f"{geometry.centre[2]:g} m) than the extent {extent:g} m: the plane would "
                                       "show no part of the map's box")
    return plane, height, extent, resolution


#: The planes of a map (:data:`PLANES`) as sections of :func:`acoustiviz.field.grids.section_grid`.
SECTION_OF_PLANE = {"vertical": "xz", "horizontal": "xy"}


def map_grid(geometry, *, plane=None, height=None, extent=None, resolution=None):
    """The planar grid of a map, cut at the floor and the wall (see the module notes).

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its planes.
    plane, height, extent, resolution
        As for :func:`check_map_settings`.

    Returns
    -------
    acoustiviz.field.grids.PlanarGrid
        Edges along x and z (vertical) or x and y (horizontal), lengths in m.
    """
    from ..field.grids import planar_grid

    centre, u, v, nu, nv = _grid_spec(geometry, *check_map_settings(geometry, plane=plane, height=height, extent=extent,
                                                                 resolution=resolution))
    return planar_grid(centre, u, v, n_u=nu, n_v=nv)


def _grid_spec(geometry, plane, height, extent, n):
    """Centre (m), edge vectors (m) and point counts of a map's grid, from checked settings."""
    from ..field.grids import section_rectangle

    return section_rectangle(geometry, SECTION_OF_PLANE[plane], extent, n, level=height)


def map_estimate(geometry, pulse, medium: Medium, n_points: int, *, options=("resolution",)):
    """Memory and output size of a map of ``n_points`` points (:class:`acoustiviz.app.budget.Estimate`).

    Memory: 512 B per point (points, results, maps, the copies made by the writers) plus the evaluator's
    observer-independent tables (two float64 tables of ``fine`` rows over the images' delay
    spread plus the pulse, in steps of ``min(T, a/c) / samples``; over the pulse only past
    :data:`acoustiviz.field.peaks.PULSE_TABLE_ABOVE` images); output: the CSV (about 120 B a
    point) and the VTK file (about 128 B a point).
    """
    from ..field.peaks import DEFAULT_FINE, DEFAULT_SAMPLES, PULSE_TABLE_ABOVE
    from .budget import Estimate

    pos = geometry.images().positions
    spread = 0.0
    if pos.shape[0] <= PULSE_TABLE_ABOVE:
        spread = float(np.max(np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1))) / medium.c
    step = min(float(pulse.duration), geometry.radius / medium.c) / DEFAULT_SAMPLES
    with np.errstate(all="ignore"):
        table = 16.0 * DEFAULT_FINE * ((2.0 * spread + float(pulse.duration)) / step + 64.0)
    n = float(n_points)
    return Estimate(_MEMORY_PER_POINT * n + table, (_CSV_PER_POINT + _VTK_PER_POINT) * n,
                    f"a map of {n:.3g} points", tuple(options))


def map_on_grid(pulse, geometry, grid, *, medium: Medium = AIR, plane: str = "vertical", progress=None) -> LevelMap:
    """Peak SPL, SEL and time of the peak of one impact at the points of any planar grid.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    grid : acoustiviz.field.grids.PlanarGrid
        The points in m; those inside the sphere or behind a plane get NaN.
    medium : Medium
        The fluid.
    plane : str
        The plane's name kept on the result (labels of the plot).
    progress : callable, optional
        ``progress(done, total)`` in points, as :func:`acoustiviz.field.fast_peaks` calls it.

    Returns
    -------
    LevelMap

    Notes
    -----
    Paper eqs 12-14 by :func:`acoustiviz.field.fast_peaks`: the peaks of the continuous pressure
    over all time and the exposure of the whole response, in closed form.
    """
    from ..field import fast_peaks

    r = fast_peaks(pulse, np.asarray(grid.points, dtype=float), geometry, medium=medium,  # NaN outside the fluid
                   progress=progress)
    time = np.where(r.peak_positive >= -r.peak_negative, r.time_positive, r.time_negative)
    return LevelMap(grid, plane, r.peak, r.peak_spl_db, r.sel_db, time, r.exposure)


#: A map of more points than this (ten times the default's) is announced on stderr before it starts.
MAP_LONG_POINTS = 1_000_000


def level_map(pulse, geometry, *, medium: Medium = AIR, plane=None, height=None, extent=None, resolution=None,
              max_memory_mb=None, names=None, progress=None) -> LevelMap:
    """Peak SPL and SEL of one impact over a plane through the scene.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    plane : {"vertical", "horizontal"}, optional
        The plane (default ``"vertical"``; see the module notes).
    height : float, optional
        Height in m of the horizontal plane above the floor (default: the sphere's centre).
    extent : float, optional
        Distance in m from the sphere's centre to the map's far edges (default 0.5 m).
    resolution : int, optional
        Points along the map's longer side, in [8, 20000] (default 317, about 1e5 points on a
        square map).
    max_memory_mb : float, optional
        Cap in MB on the estimated memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`);
        a larger map is refused before any work.
    names : mapping of str to str, optional
        API parameter -> the user's option or scene key (:data:`CLI_NAMES`, :data:`SCENE_NAMES`):
        every error is raised under the user's name.
    progress : callable, optional
        ``progress(done, total)`` in points, as :func:`acoustiviz.field.fast_peaks` calls it.

    Returns
    -------
    LevelMap

    Raises
    ------
    ParameterError
        Named ``plane``, ``height``, ``extent``, ``resolution`` or ``max_memory_mb`` (in the user's
        terms with ``names``), before any work.
    """
    grid = plan_map(pulse, geometry, medium=medium, plane=plane, height=height, extent=extent, resolution=resolution,
                    max_memory_mb=max_memory_mb, names=names)
    plane = _BY_NAME["plane"].default if plane is None else plane
    n = np.asarray(grid.points).shape[0]
    if n > MAP_LONG_POINTS:
        from .._jit import announce_long_work

        announce_long_work(f"map: {n:.3g} points, a long computation (Ctrl-C stops it)")
    return map_on_grid(pulse, geometry, grid, medium=medium, plane=plane, progress=progress)


def plan_map(pulse, geometry, *, medium: Medium = AIR, plane=None, height=None, extent=None, resolution=None,
             max_memory_mb=None, names=None):
    """Check a map's settings and its memory and output size, and return its grid, without evaluating anything.

    Parameters and errors as for :func:`level_map` (a scene calls this at load time, so that a
    bad map is refused before any output of the scene is produced).

    Returns
    -------
    acoustiviz.field.grids.PlanarGrid
    """
    from .budget import check_budget
    from .names import user_terms

    names = dict(names or {})
    with user_terms(names):
        settings = check_map_settings(geometry, plane=plane, height=height, extent=extent, resolution=resolution)
        nu, nv = _grid_spec(geometry, *settings)[3:]
        opts = (names.get("resolution", "resolution"),)
        check_budget(map_estimate(geometry, pulse, medium, nu * nv, options=opts), max_memory_mb,
                     cap_name=names.get("max_memory_mb", "max_memory_mb"))
        if nu * nv > MAX_MAP_POINTS:  # a bound on the work, whatever memory the caller allows
            raise ParameterError("resolution", f"a map of {nu} x {nv} = {nu * nv:.3g} points is more than the "
                                               f"{MAX_MAP_POINTS:.3g} a map may hold (a square map of resolution "
                                               f"{math.isqrt(MAX_MAP_POINTS)}), whatever the memory cap; lower it")
        plane, height, extent, resolution = settings
    return map_grid(geometry, plane=plane, height=height, extent=extent, resolution=resolution)


def write_map_csv(level: LevelMap, path):
    """Write the map as CSV (:data:`MAP_CSV_COLUMNS`, one row per grid point, ``nan`` inside the sphere), atomically."""
    from ..files import write_csv_atomic

    cols = [level.grid.points[:, 0], level.grid.points[:, 1], level.grid.points[:, 2], level.peak_pa,
            level.peak_spl_db, level.sel_db, level.time_of_peak_s]
    return write_csv_atomic(path, list(MAP_CSV_COLUMNS), cols, fmt=list(_CSV_FORMATS))


def map_title(level: LevelMap, geometry, setup_text: str = "") -> str:
    """A one-line title: configuration, plane and the impact."""
    where = (f"vertical plane y = {level.grid.points[0, 1]:.4g} m through the centre" if level.plane == "vertical"
             else f"horizontal plane z = {level.grid.points[0, 2]:.4g} m")
    return f"{geometry.name}: {where}" + (f"; {setup_text}" if setup_text else "")


def write_map_outputs(level: LevelMap, geometry, *, png=None, csv=None, vtk=None, title: str = "") -> list:
    """Write the requested files of a map (the same bytes from the command line and a scene).

    Parameters
    ----------
    level : LevelMap
        The map.
    geometry : acoustiviz.core.geometry.Geometry
        The scene (its sphere and planes are drawn and stored beside the VTK data).
    png, csv, vtk : path-like, optional
        The figure (:func:`acoustiviz.output.plot.maps.level_map_figure`), the CSV
        (:func:`write_map_csv`) and the VTK file (:func:`acoustiviz.output.vtk.write_map_vtk`,
        with ``<stem>_geometry.vtu`` beside it).
    title : str
        Title of the figure.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    out = []
    if csv is not None:
        out.append(write_map_csv(level, csv))
    if png is not None:
        from ..output.plot.maps import level_map_figure
        from ..output.plot.style import save_figure

        fig = level_map_figure(level.grid, level.peak_spl_db, level.sel_db, geometry, axes_names=level.in_plane(),
                               title=title)
        out.append(save_figure(fig, png))
    if vtk is not None:
        from ..output.vtk import write_map_vtk

        out += [p for p in write_map_vtk(level.grid, level.arrays(), geometry, vtk) if p is not None]
    return out


@contextlib.contextmanager
def points_bar(stream):
    """A ``progress(done, total)`` drawing a bar of points on ``stream`` if it is a terminal, else None.

    The bar is that of a sweep (:class:`acoustiviz.sweep.progress.Progress`), cleared when the map ends.
    """
    from ..sweep.progress import Progress, is_terminal

    if not is_terminal(stream):
        yield None
        return
    bars = []

    def progress(done, total):
        if not bars:  # the total is known at the first report
            bars.append(Progress(total, stream=stream, desc="map", unit="point", leave=False))
        bars[0].update(done - bars[0].count)

    try:
        yield progress
    finally:
        for bar in bars:
            bar.close()


def summary_figures(level: LevelMap) -> dict:
    """Key figures of a map for a summary: points, plane, and the ranges of peak SPL and SEL in dB."""
    ok = np.isfinite(level.peak_spl_db)
    figs = {"points": str(level.grid.points.shape[0]), "plane": level.plane}
    if np.any(ok):
        figs["spl_db_range"] = f"{np.nanmin(level.peak_spl_db):.1f}-{np.nanmax(level.peak_spl_db):.1f}"
        figs["sel_db_range"] = f"{np.nanmin(level.sel_db):.1f}-{np.nanmax(level.sel_db):.1f}"
    return figs
