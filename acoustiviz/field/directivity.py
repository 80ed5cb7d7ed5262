"""Directivity: peak and RMS pressure and peak SPL versus polar angle on a circle (paper Figure 3)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_positive
from ..core.geometry import Geometry, observer_points
from ..core.medium import AIR, Medium
from ..core.reach import circle_limit
from ._common import check_geometry, check_pulse
from .metrics import FieldMetrics, field_metrics
from .sources import source_geometry

__all__ = ["Directivity", "circle_points", "directivity", "room_window"]


@dataclass(frozen=True)
class Directivity:
    """Peak, RMS and SPL versus polar angle on a circle around the sphere's centre.

    Attributes
    ----------
    angle : (k,) ndarray
        Polar angle in rad from the acceleration axis.
    points : (k, 3) ndarray
        Observer positions in m.
    distance : float
        Radius of the circle in m, from the sphere's centre.
    metrics : FieldMetrics
        Peaks, RMS and exposure at each angle.
    """

    angle: np.ndarray
    points: np.ndarray
    distance: float
    metrics: FieldMetrics

    @property
    def angle_deg(self) -> np.ndarray:
        """Polar angle in degrees."""
        return np.degrees(self.angle)

    @property
    def peak(self) -> np.ndarray:
        """Largest absolute pressure max|p| in Pa."""
        return self.metrics.peak

    @property
    def rms(self) -> np.ndarray:
        """RMS pressure in Pa over the window (see :func:`directivity`)."""
        return self.metrics.rms

    @property
    def spl_db(self) -> np.ndarray:
        """Peak SPL ``20 log10(max|p| / 20 µPa)`` in dB (paper Figure 3A)."""
        return self.metrics.peak_spl_db


def circle_points(geometry: Geometry, distance: float, angles) -> np.ndarray:
    """Points on a circle of radius ``distance`` (m) around the sphere's centre.

    The circle lies in the plane spanned by the acceleration axis and the horizontal direction
    ``+x`` (for a wall strike, whose axis is ``+x``, the vertical ``+z``): for the wall-floor
    corner that is the plane through the centre normal to the wall, on the side away from it.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    distance : float
        Radius of the circle in m (> sphere radius).
    angles : (k,) array_like
        Polar angles in rad from the acceleration axis.

    Returns
    -------
    (k, 3) ndarray
        Positions in m.
    """
    check_geometry(geometry)
    r = check_positive("distance", distance, "m")
    top = circle_limit(geometry)
    if r <= geometry.radius and not math.isfinite(top):
        raise ParameterError("distance", f"must exceed the sphere radius {geometry.radius:g} m, got {r:g} m")
    if r <= geometry.radius or r > top:
        raise ParameterError("distance", f"must lie in ({geometry.radius:g}, {top:.6g}] m for the circle around the "
                                         f"sphere's centre {_xyz(geometry.centre)} m to stay in the fluid "
                                         f"({geometry.fluid_text()}), got {r:g} m")
    return observer_points(geometry, r, angles)


def _xyz(p) -> str:
    return "(" + ", ".join(f"{float(x):.6g}" for x in p) + ")"


def room_window(geometry: Geometry, points, medium: Medium = AIR):
    """The directivity's window length in s in a geometry with a window of its own (a room), else None.

    A room's images are those that can arrive within its ``duration`` from the start of contact
    (:class:`acoustiviz.core.room_geometry.Room`); each point's window starts at its first arrival
    ``(r - a)/c`` and has the same length at every point, so it ends by ``duration`` at the point
    reached last: ``duration - max (r - a)/c``. Refused (naming ``distance``) when the sound reaches
    the circle only after the room's window.
    """
    reach = getattr(geometry, "duration", None)
    if reach is None:
        return None
    first = float(np.max(np.linalg.norm(np.asarray(points) - geometry.centre, axis=1) - geometry.radius)) / medium.c
    if first >= reach:
        raise ParameterError("distance", f"the sound reaches the circle at {first:.6g} s, after the room's window "
                                         f"of {reach:g} s: make the window longer or the circle smaller")
    return reach - first


def directivity(
    pulse,
    geometry: Geometry,
    distance: float,
    angles,
    *,
    medium: Medium = AIR,
    sample_interval=None,
    window=None,
) -> Directivity:
    """Peak pressure, RMS pressure and peak SPL versus polar angle (paper Figure 3).

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²).
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    distance : float
        Distance in m from the sphere's centre.
    angles : (k,) array_like
        Polar angles in rad from the acceleration axis (see :func:`circle_points`).
    medium : Medium
        The fluid.
    sample_interval : float, optional
        Time step in s (default :func:`default_sample_interval`).
    window : float, optional
        RMS window length in s. Default: the same length at every angle, starting at each
        angle's first arrival and holding the whole pulse from every image plus ten decay
        times: ``T + Δ + 10 a/c`` with ``Δ`` the largest spread of image arrival times on the
        circle (the neglected tail carries < 3e-9 of the energy). In a room (a geometry with a
        ``duration``): ``duration - max (r - a)/c`` (:func:`room_window`), so every point's window
        ends within the room's and holds every image that arrives in it.

    Returns
    -------
    Directivity

    Notes
    -----
    Paper eqs 12-14 and Figure 3; SPL is the peak level ``20 log10(max|p|/20 µPa)``.

    Examples
    --------
    The paper's Figure 3 at 0.7 m above a reflecting plane: loudest along the axis, 4.4 dB less
    at 45°, and 25 dB less at grazing incidence, where the sphere's dipole and its image nearly
    cancel:

    >>> import math
    >>> from acoustiviz.core.contact import Impact, acceleration_pulse
    >>> a = 0.01905  # the paper's Figure 2 sphere at 1.4 m/s, K = 5.6e8 N/m^1.5
    >>> pulse = acceleration_pulse(Impact(1.4, 5.6e8, 7800.0 * 4.0 / 3.0 * math.pi * a**3))
    >>> from acoustiviz.core.geometry import images_plane
    >>> d = directivity(pulse, images_plane(a), 0.7, np.radians([0.0, 45.0, 90.0]))
    >>> np.round(d.spl_db, 1)  # peak SPL in dB re 20 µPa
    array([93.2, 88.8, 68.2])
    """
    check_pulse(pulse)
    pts = circle_points(geometry, distance, angles)
    if not np.all(geometry.in_fluid(pts)):
        raise ParameterError("angles", "some observers on the circle lie outside the fluid")
    if window is None:
        window = room_window(geometry, pts, medium)
    if window is None:
        delay, _, _, _ = source_geometry(pts, geometry, medium=medium)
        spread = float(np.max(delay.max(axis=1) - delay.min(axis=1)))
        window = pulse.duration + spread + 10.0 * geometry.radius / medium.c
    fm = field_metrics(pulse, pts, geometry, medium=medium, sample_interval=sample_interval, window=window)
    th = np.atleast_1d(np.asarray(angles, dtype=float))
    return Directivity(th, pts, float(distance), fm)
