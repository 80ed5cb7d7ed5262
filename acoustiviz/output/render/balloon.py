"""Directivity balloons: a level on a spherical grid drawn as a closed surface around the contact point."""

from __future__ import annotations

import dataclasses
import inspect
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..._validate import ParameterError, check_choice, check_positive, check_range
from ...constants import BALLOON_MIN_RADII, BALLOON_N_THETA_RANGE
from ...core.geometry import Geometry
from ...core.medium import AIR, Medium
from ...core.reach import check_view_radius, view_limit
from ...field import field_metrics
from ...field.directivity import room_window
from ...field.grids import SphericalGrid, spherical_grid
from ._common import (
    DEFAULT_SIZE,
    _add_bar,
    _add_geometry,
    _check_inputs,
    _check_path,
    _check_size,
    _configs,
    _font,
    _grab,
    _plotter,
    _scene_extent,
    _scene_label,
    _set_camera,
    _write_png,
    check_backend,
)

__all__ = [
    "BALLOON_FIELD_METRICS",
    "BalloonData",
    "balloon_data",
    "render_balloon",
]


#: Balloon metrics of the field itself: name -> (FieldMetrics attribute, colour-bar title with its unit).
BALLOON_FIELD_METRICS = {
    "peak": ("peak_spl_db", "peak SPL (dB re 20 µPa)"),
    "rms": ("rms_spl_db", "RMS level (dB re 20 µPa)"),
    "sel": ("sel_db", "SEL (dB re 20 µPa, 1 s)"),
}


# --------------------------------------------------------------------------- balloon
@dataclass(frozen=True)
class BalloonData:
    """Levels over a closed lattice of directions around an anchor point, for a balloon.

    Attributes
    ----------
    anchor : (3,) ndarray
        Centre of the balloon in m: the contact point (the sphere's centre in free field).
    directions : (n_t, n_p, 3) ndarray
        Unit directions of a lattice that closes the region: the quadrature grid's nodes
        padded with the poles, the rim on the planes and the seam.
    level : (n_t, n_p) ndarray
        Level in dB at ``anchor + distance * directions`` (see ``label`` for which).
    grid : SphericalGrid
        The quadrature grid (its nodes are the lattice's interior).
    grid_level : (n,) ndarray
        Level in dB at the grid's points.
    distance : float
        Radius in m at which the field was evaluated.
    metric : str
        ``"peak"``, ``"rms"`` or ``"sel"``.
    label : str
        Name and unit of the level, e.g. ``"peak SPL (dB re 20 µPa)"``.
    config_name : str
        Name of the configuration.
    metrics : FieldMetrics or None
        Every metric of :func:`acoustiviz.field.field_metrics` at the lattice's points, in lattice
        order, when the level is one of them (``"peak"``, ``"rms"``, ``"sel"``); None for a level
        computed by a function of its own.
    """

    anchor: np.ndarray
    directions: np.ndarray
    level: np.ndarray
    grid: SphericalGrid
    grid_level: np.ndarray
    distance: float
    metric: str
    label: str
    config_name: str
    metrics: object = None

    @property
    def max_level(self) -> float:
        """Largest level in dB."""
        return float(np.nanmax(self.level))

    @property
    def mean_level(self) -> float:
        """Energy average of the level over the region's solid angle, in dB.

        ``10 log10(∫ 10^(L/10) dΩ / Ω)`` with the grid's quadrature weights.
        """
        lin = np.where(np.isfinite(self.grid_level), 10.0 ** (self.grid_level / 10.0), 0.0)
        return float(10.0 * np.log10(self.grid.average(lin)))


def _region(config: Geometry):
    """Region, anchor, polar axis and azimuth origin of the balloon of ``config`` (its view region)."""
    reg = config.view_region()
    return reg.kind, reg.origin, reg.up, reg.side


def _closed_lattice(grid: SphericalGrid, up, side) -> np.ndarray:
    """Directions (n_t + 2, n_p + 1 or + 2, 3) closing the grid's region for display."""
    e3 = np.asarray(up, float) / np.linalg.norm(up)
    s = np.asarray(side, float) - np.dot(side, e3) * e3
    e1 = s / np.linalg.norm(s)
    e2 = np.cross(e3, e1)
    d = grid.directions.reshape(grid.n_theta, grid.n_phi, 3)
    mu = d[:, 0, :] @ e3
    phi = np.arctan2(d[0] @ e2, d[0] @ e1)
    if grid.region == "quarter":
        phi = np.r_[-0.5 * math.pi, phi, 0.5 * math.pi]
    else:
        phi = np.r_[np.mod(phi, 2 * math.pi), 2 * math.pi]
    mu = np.r_[-1.0 if grid.region == "sphere" else 0.0, mu, 1.0]
    st = np.sqrt(np.clip(1.0 - mu * mu, 0.0, None))
    return (
        (st[:, None, None] * np.cos(phi)[None, :, None]) * e1
        + (st[:, None, None] * np.sin(phi)[None, :, None]) * e2
        + mu[:, None, None] * e3
    )


def balloon_data(
    pulse,
    config: Geometry,
    *,
    medium: Medium = AIR,
    distance: float = 0.7,
    metric: str = "peak",
    n_theta: int = 32,
    levels=None,
) -> BalloonData:
    """Level over a sphere of directions at ``distance`` around the contact point.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Geometry
        ``"free"`` (whole sphere around the sphere's centre), ``"plane"`` (half space around
        the contact point), ``"wall-floor"`` (quarter space around the contact point,
        bounded by the floor and the wall) or ``"room"`` (the half space in front of the struck
        surface around the contact point, or the whole sphere around the centre of a sphere away
        from it; with every reflection of the room, :meth:`~acoustiviz.core.geometry.Geometry.view_region`).
    medium : Medium
        The fluid.
    distance : float
        Radius in m of the measuring sphere; larger than 1.05 times the sphere's diameter and, in a
        room, at most the distance from the anchor to the walls the region faces
        (:func:`acoustiviz.core.reach.view_limit`).
    metric : {"peak", "rms", "sel"}
        Peak SPL, level of the RMS pressure (same window length everywhere, see
        :func:`acoustiviz.field.field_metrics`; in a room the window of
        :func:`acoustiviz.field.directivity.room_window`), or sound exposure level.
    n_theta : int
        Gauss-Legendre nodes in polar angle (>= 4); azimuth nodes follow
        :func:`acoustiviz.field.grids.spherical_grid`.
    levels : tuple (function, label), optional
        Any other level: ``function(points)`` returns the level in dB at each of ``(k, 3)``
        points in m, and ``label`` names it with its unit (the weighted levels of
        :mod:`acoustiviz.levels` come this way, :func:`acoustiviz.app.views.point_levels`);
        ``metric`` then only names it.

    Returns
    -------
    BalloonData
    """
    _check_inputs(pulse, config, medium)
    if levels is None:
        check_choice("metric", metric, tuple(BALLOON_FIELD_METRICS))
    r = check_positive("distance", distance, "m")
    if r <= BALLOON_MIN_RADII * config.radius:
        raise ParameterError("distance", f"must exceed 1.05 × the sphere's diameter "
                             f"({BALLOON_MIN_RADII * config.radius:g} m), got {r:g} m")
    lo, hi = BALLOON_N_THETA_RANGE
    if int(n_theta) != n_theta or not lo <= n_theta <= hi:
        raise ParameterError("n_theta", f"must be an integer in [{lo}, {hi}], got {n_theta!r}")
    check_view_radius(config, r, BALLOON_MIN_RADII * config.radius)
    region, anchor, up, side = _region(config)
    grid = spherical_grid(r, region=region, centre=anchor, up=up, side=side, n_theta=int(n_theta))
    dirs = _closed_lattice(grid, up, side)
    pts = anchor + r * dirs.reshape(-1, 3)
    if not np.all(config.in_fluid(pts)):
        raise ParameterError("distance", f"{r:g} m puts measuring points inside the sphere or a wall")
    if levels is None:
        attr, label = BALLOON_FIELD_METRICS[metric]
        every = np.vstack([pts, grid.points])
        # a room: each point's window ends by the room's (the images that arrive within it), as for a directivity
        fm = field_metrics(pulse, every, config, medium=medium, window=room_window(config, every, medium))
        lev = np.asarray(getattr(fm, attr), dtype=float)
    else:
        function, label = levels
        lev = np.asarray(function(np.vstack([pts, grid.points])), dtype=float)
        fm = None
    n = pts.shape[0]
    return BalloonData(np.asarray(anchor, float), dirs, lev[:n].reshape(dirs.shape[:2]), grid, lev[n:], r,
                       metric, label, config.name, None if fm is None else _first_points(fm, n))


def _first_points(fm, n: int):
    """The metrics ``fm`` of the first ``n`` points only (their per-point arrays cut, the rest kept)."""
    per_point = ("peak_positive", "peak_negative", "rms", "exposure", "window_start", "model")
    return dataclasses.replace(fm, **{k: getattr(fm, k)[:n] for k in per_point})


def _balloon_mesh(data: BalloonData, size: float, top: float, db_range: float):
    """PolyData of the balloon: radius ``size · clip((L - top + range)/range, 0, 1)`` in m, scalars ``level``."""
    pv = check_backend()
    frac = np.clip((np.nan_to_num(data.level, nan=-np.inf) - (top - db_range)) / db_range, 0.0, 1.0)
    pts = data.anchor + (size * frac)[..., None] * data.directions
    lev = data.level
    if data.grid.region != "sphere":  # close the surface along the floor: a row collapsed onto the anchor
        pts = np.concatenate([np.broadcast_to(data.anchor, pts[:1].shape), pts], axis=0)
        lev = np.concatenate([lev[:1], lev], axis=0)
    if data.grid.region == "quarter":  # and along the plane facing the wall
        cap = np.broadcast_to(data.anchor, pts[:, :1].shape)
        pts = np.concatenate([cap, pts, cap], axis=1)
        lev = np.concatenate([lev[:, :1], lev, lev[:, -1:]], axis=1)
    x, y, z = (pts[..., k].T[..., None] for k in range(3))
    mesh = pv.StructuredGrid(x, y, z)
    mesh.point_data["level"] = np.ascontiguousarray(lev).reshape(-1)
    # vtkDataSetSurfaceFilter: named where pyvista offers a choice of filter, the only one in older pyvista
    named = "algorithm" in inspect.signature(mesh.extract_surface).parameters
    choice = {"algorithm": "dataset_surface"} if named else {}
    surf = mesh.extract_surface(pass_pointid=False, pass_cellid=False, **choice)
    return surf.clean(tolerance=1e-9 * size)


def render_balloon(
    pulse,
    config,
    path,
    *,
    medium: Medium = AIR,
    distance: float = 0.7,
    metric: str = "peak",
    db_range: float = 30.0,
    n_theta: int = 32,
    size=DEFAULT_SIZE,
    balloon_size=None,
    title=None,
    show_scalar_bar: bool = True,
    cmap: str = "viridis",
    opacity: float = 0.7,
    data=None,
) -> Path:
    """Render a directivity balloon (or several side by side) into a PNG file.

    The balloon is centred on the contact point; in each direction its radius is
    ``balloon_size · (L - L_max + db_range)/db_range`` (clipped at zero), where ``L`` is the
    level at ``distance`` in that direction and ``L_max`` the largest level over all the
    balloons drawn, and its colour is ``L`` itself. The sphere, floor and wall are drawn to
    scale, the planes semi-transparent.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Geometry or sequence of Geometry
        The scene; several are drawn side by side with one colour scale.
    path : path-like
        Output ``.png`` file (written atomically).
    medium : Medium
        The fluid.
    distance : float
        Radius in m of the measuring sphere around the contact point.
    metric : {"peak", "rms", "sel"}
        Level drawn (see :func:`balloon_data`).
    db_range : float
        Range in dB from the balloon's centre to its largest radius, in (0, 200].
    n_theta : int
        Polar resolution of the measuring grid.
    size : (int, int)
        Image width and height in pixels.
    balloon_size : float, optional
        Largest balloon radius in m (default six sphere radii, at least 1.5 × the wall
        distance; in a room at most the distance to the walls the balloon faces), i.e. the scale of the
        drawing, not of the field.
    title : str, optional
        Text at the top left (default: the metric and the distance).
    show_scalar_bar : bool
        Draw the labelled colour bar.
    cmap : str
        Matplotlib colour map of the level.
    opacity : float
        Opacity of the balloon in (0, 1]; below 1 the sphere shows through. The balloon's
        outline in the plane ``y = 0`` (the polar pattern of ``acoustiviz directivity``) is
        drawn as a dark line.
    data : BalloonData or sequence of BalloonData, optional
        Levels already computed by :func:`balloon_data` for these configurations (one each);
        by default they are computed here.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> from acoustiviz import Impact, acceleration_pulse
    >>> from acoustiviz.core.geometry import geometry
    >>> pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=0.226), "half-sine")
    >>> corner = geometry("wall-floor", 0.01905, wall_distance=0.05)
    >>> render_balloon(pulse, corner, "balloon.png", size=(800, 600))  # doctest: +SKIP
    PosixPath('balloon.png')
    """
    path = _check_path(path, (".png",))
    size = _check_size(size)
    configs = _configs(config)
    for c in configs:
        _check_inputs(pulse, c, medium)
    rng = check_range("db_range", db_range, 0.0, 200.0, unit="dB", low_open=True)
    opacity = check_range("opacity", opacity, 0.0, 1.0, low_open=True)
    if data is None:
        datas = [balloon_data(pulse, c, medium=medium, distance=distance, metric=metric, n_theta=n_theta)
                 for c in configs]
    else:
        datas = [data] if isinstance(data, BalloonData) else list(data)
        if len(datas) != len(configs) or not all(isinstance(d, BalloonData) for d in datas):
            raise ParameterError("data", f"expected {len(configs)} BalloonData, one per configuration")
    top = max(d.max_level for d in datas)
    clim = (top - rng, top)
    if title is None:
        title = f"{datas[0].label.split(' (')[0]} at {datas[0].distance:g} m, {db_range:g} dB from centre to rim"
    with _plotter(size, shape=(1, len(configs))) as pl:
        for i, (c, d) in enumerate(zip(configs, datas, strict=True)):
            pl.subplot(0, i)
            actor = _draw_balloon(pl, pulse, c, d, top, rng, balloon_size, clim, cmap, size, len(configs), opacity)
            if show_scalar_bar and i == len(configs) - 1:
                _add_bar(pl, d.label, size, actor.mapper, n_views=len(configs))
        pl.subplot(0, 0)
        pl.add_text(title, position="upper_left", font_size=_font(size, 13), color="black")
        img = _grab(pl)
    return _write_png(img, path)


def _draw_balloon(pl, pulse, config, data, top, rng, balloon_size, clim, cmap, size, n_views, opacity):
    a = config.radius
    if balloon_size is None:
        bsize = min(max(6.0 * a, 1.5 * config.feature_distance), view_limit(config))  # inside a room's walls
    else:
        bsize = check_positive("balloon_size", balloon_size, "m")
    mesh = _balloon_mesh(data, bsize, top, rng)
    actor = pl.add_mesh(mesh, scalars="level", clim=clim, cmap=cmap, smooth_shading=True, split_sharp_edges=True,
                        show_scalar_bar=False,
                        specular=0.25, nan_color="#dddddd", opacity=opacity)
    section = mesh.slice(normal="y", origin=data.anchor)  # the polar pattern in the plane y = 0
    if section.n_points:
        pl.add_mesh(section, color="#202020", line_width=max(1.0, 2.5 * size[1] / 900.0))
    bounds = _scene_extent(config, 1.05 * bsize)
    _add_geometry(pl, config, bounds)
    line = _scene_label(pulse, config) + f"\nmax {data.max_level:.1f} dB, energy mean {data.mean_level:.1f} dB"
    pl.add_text(line, position="lower_left", font_size=_font((size[0] / n_views, size[1]), 11), color="#222222")
    x0, x1, y0, y1, z0, z1 = bounds
    focus = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    bounded = bool(config.planes)  # look down on a floor; all round a sphere in free field
    direction = (0.9, -1.7, 0.8) if bounded else (0.9, -1.7, 0.4)
    _set_camera(pl, focus, direction, zoom=1.35 if bounded else 1.05)
    return actor
