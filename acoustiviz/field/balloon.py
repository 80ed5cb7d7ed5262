"""Directivity balloons: a level over a closed lattice of directions around the contact point, computed once.

:func:`balloon_data` evaluates a level (peak SPL, RMS level, SEL, or any level a function gives) on a
spherical grid (:func:`acoustiviz.field.grids.spherical_grid`) padded to a closed lattice of directions
and returns a :class:`BalloonData`; the PNG render, the VTK file and the HTML page of the same balloon
all take that one value. Lengths in m, levels in dB re 20 µPa.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice, check_positive
from ..constants import BALLOON_MIN_RADII, BALLOON_N_THETA_RANGE
from ..core.geometry import Geometry
from ..core.medium import AIR, Medium
from ..core.reach import check_view_radius
from ._common import check_inputs
from .directivity import room_window
from .grids import SphericalGrid, spherical_grid
from .metrics import field_metrics

__all__ = [
    "BALLOON_FIELD_METRICS",
    "BalloonData",
    "balloon_data",
    "balloon_metrics",
]


#: Balloon metrics of the field itself: name -> (FieldMetrics attribute, colour-bar title with its unit).
BALLOON_FIELD_METRICS = {
    "peak": ("peak_spl_db", "peak SPL (dB re 20 µPa)"),
    "rms": ("rms_spl_db", "RMS level (dB re 20 µPa)"),
    "sel": ("sel_db", "SEL (dB re 20 µPa, 1 s)"),
}


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


def _region(geometry: Geometry):
    """Region, anchor, polar axis and azimuth origin of the balloon of ``geometry`` (its view region)."""
    reg = geometry.view_region()
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
    geometry: Geometry,
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
    geometry : Geometry
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
    check_inputs(pulse, geometry, medium)
    if levels is None:
        check_choice("metric", metric, tuple(BALLOON_FIELD_METRICS))
    r = check_positive("distance", distance, "m")
    if r <= BALLOON_MIN_RADII * geometry.radius:
        raise ParameterError("distance", f"must exceed 1.05 × the sphere's diameter "
                             f"({BALLOON_MIN_RADII * geometry.radius:g} m), got {r:g} m")
    lo, hi = BALLOON_N_THETA_RANGE
    if int(n_theta) != n_theta or not lo <= n_theta <= hi:
        raise ParameterError("n_theta", f"must be an integer in [{lo}, {hi}], got {n_theta!r}")
    check_view_radius(geometry, r, BALLOON_MIN_RADII * geometry.radius)
    region, anchor, up, side = _region(geometry)
    grid = spherical_grid(r, region=region, centre=anchor, up=up, side=side, n_theta=int(n_theta))
    dirs = _closed_lattice(grid, up, side)
    pts = anchor + r * dirs.reshape(-1, 3)
    if not np.all(geometry.in_fluid(pts)):
        raise ParameterError("distance", f"{r:g} m puts measuring points inside the sphere or a wall")
    if levels is None:
        attr, label = BALLOON_FIELD_METRICS[metric]
        every = np.vstack([pts, grid.points])
        # a room: each point's window ends by the room's (the images that arrive within it), as for a directivity
        fm = field_metrics(pulse, every, geometry, medium=medium, window=room_window(geometry, every, medium))
        lev = np.asarray(getattr(fm, attr), dtype=float)
    else:
        function, label = levels
        lev = np.asarray(function(np.vstack([pts, grid.points])), dtype=float)
        fm = None
    n = pts.shape[0]
    return BalloonData(np.asarray(anchor, float), dirs, lev[:n].reshape(dirs.shape[:2]), grid, lev[n:], r,
                       metric, label, geometry.name, None if fm is None else _first_points(fm, n))


def _first_points(fm, n: int):
    """The metrics ``fm`` of the first ``n`` points only (their per-point arrays cut, the rest kept)."""
    per_point = ("peak_positive", "peak_negative", "rms", "exposure", "window_start", "model")
    return dataclasses.replace(fm, **{k: getattr(fm, k)[:n] for k in per_point})


def balloon_metrics(pulse, geometry: Geometry, data: BalloonData, *, medium: Medium = AIR) -> BalloonData:
    """``data`` holding every metric of :func:`acoustiviz.field.field_metrics` at its lattice's points.

    A balloon of a level of the field itself carries them already (``data`` is returned as is); one of
    a level computed by a function of its own (a weighted level) gets them here, with the free window
    of :func:`acoustiviz.field.field_metrics`.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    geometry : Geometry
        The scene of ``data``.
    data : BalloonData
        The balloon, from :func:`balloon_data`.
    medium : Medium
        The fluid.

    Returns
    -------
    BalloonData
    """
    if not isinstance(data, BalloonData):
        raise ParameterError("data", f"expected a BalloonData, got {type(data).__name__}")
    if data.metrics is not None:
        return data
    lattice = data.anchor + data.distance * data.directions.reshape(-1, 3)
    return dataclasses.replace(data, metrics=field_metrics(pulse, lattice, geometry, medium=medium))
