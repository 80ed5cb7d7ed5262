"""Image-source geometry: the delay, amplitude and shape coefficient of every source at every point.

Every image source ``j`` (see :mod:`acoustiviz.core.images`) is a rigid sphere radiating in free
field; at an observer ``x`` its pressure is (paper eqs 12-14)::

    p_j(x, t) = P0_j Re[C_j Y(t - d_j)],   d_j = (|x - x_j| - a)/c,

with ``P0_j = w_j ρ c a² cosθ_j / r_j²`` (``w_j`` the image's reflection weight) and
``C_j = r_j/a - i(1 - r_j/a)``. :func:`image_geometry` computes these for any set of sources
(the field evaluator and the auralisation both use it); :func:`source_geometry` for the images of
a geometry (:meth:`acoustiviz.core.geometry.Geometry.images`).
"""

from __future__ import annotations

import numpy as np

from .._validate import check_points
from ..core.geometry import Geometry
from ..core.images import ImageSet
from ..core.medium import AIR, Medium
from ._common import DEFAULT_CUTOFF, check_geometry, check_pulse, decay_time

__all__ = ["image_geometry", "source_geometry", "waveform_span", "waveform_spans", "arrival_windows"]


def image_geometry(points, sources, radius: float, *, medium: Medium = AIR):
    """Delays, amplitudes and shape coefficients of the given sources at every point.

    Parameters
    ----------
    points : (n, 3) array_like
        Observer positions in m.
    sources : ImageSet or sequence of ImageSource
        The radiating spheres (position in m, unit acceleration axis, reflection weight; an
        image's sign is carried by its mirrored axis).
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    delay : (n, k) ndarray
        ``(r_j - a)/c`` in s for each of the ``k`` sources.
    p0 : (n, k) ndarray
        ``w_j ρ c a² cosθ_j / r_j²`` in Pa/(m/s) (``w_j`` the image's reflection weight).
    c_shape : (n, k) complex ndarray
        ``r_j/a - i(1 - r_j/a)``.
    distance : (n, k) ndarray
        ``r_j`` in m.

    Notes
    -----
    Paper eqs 11-14. A point at a source's centre gets NaN for that source.
    """
    pts = check_points("points", points)
    imgs = ImageSet.of(sources)
    pos, axes = imgs.positions, imgs.weighted_axes
    a = float(radius)
    n, k = pts.shape[0], len(imgs)
    r = np.empty((n, k))
    ct = np.empty((n, k))
    if k <= max(n, 64):  # few sources (the paper's geometries): one vectorised pass per source
        for j in range(k):
            d = pts - pos[j]
            r[:, j] = np.sqrt(np.einsum("ij,ij->i", d, d))
            with np.errstate(invalid="ignore", divide="ignore"):
                ct[:, j] = (d @ axes[j]) / r[:, j]
    else:  # many sources (a room's images): one vectorised pass per point
        for i in range(n):
            d = pts[i] - pos
            r[i] = np.sqrt(np.einsum("ij,ij->i", d, d))
            with np.errstate(invalid="ignore", divide="ignore"):
                ct[i] = np.einsum("ij,ij->i", d, axes) / r[i]
    ra = r / a
    with np.errstate(invalid="ignore", divide="ignore"):
        p0 = medium.rho * medium.c * a * a * ct / (r * r)
    return (r - a) / medium.c, p0, ra - 1j * (1.0 - ra), r


def source_geometry(points, geometry: Geometry, *, medium: Medium = AIR):
    """:func:`image_geometry` of the sources of a geometry (its sphere and images).

    Parameters
    ----------
    points : (n, 3) array_like
        Observer positions in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.

    Returns
    -------
    delay, p0, c_shape, distance : (n, k) ndarray
        As :func:`image_geometry`: s, Pa/(m/s), dimensionless, m.
    """
    return image_geometry(points, geometry.images(), geometry.radius, medium=medium)


def waveform_span(pulse, point, geometry: Geometry, *, medium: Medium = AIR, decay_times: float = 40.0):
    """First arrival and end in s (from the start of contact) of one impact's sound at ``point``.

    The end is the last image's arrival plus the pulse plus ``decay_times`` decay times a/c of
    the sphere (the response decays like exp(-c t'/a): 40 leaves exp(-40) of the tail), the
    window a plotted or tabulated waveform should cover.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    point : (3,) array_like
        Observer position in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    decay_times : float
        Length of the kept tail in units of a/c.

    Returns
    -------
    first, end : float
        Times in s.
    """
    first, end = waveform_spans(pulse, np.asarray(point, dtype=float)[None, :], geometry, medium=medium,
                                decay_times=decay_times)[0]
    return float(first), float(end)


def waveform_spans(pulse, points, geometry: Geometry, *, medium: Medium = AIR, decay_times: float = 40.0):
    """:func:`waveform_span` of many points at once.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    points : (n, 3) array_like
        Observer positions in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    decay_times : float
        Length of the kept tail in units of a/c.

    Returns
    -------
    (n, 2) ndarray
        First arrival and end of each point's sound, in s from the start of contact.
    """
    delay = source_geometry(np.asarray(points, dtype=float).reshape(-1, 3), geometry, medium=medium)[0]
    tail = pulse.duration + decay_times * geometry.radius / medium.c
    return np.column_stack([delay.min(axis=1), delay.max(axis=1) + tail])


def arrival_windows(pulse, points, geometry: Geometry, *, medium: Medium = AIR, cutoff: float = DEFAULT_CUTOFF):
    """Interval of each point in which its pressure is non-zero (to ``cutoff``).

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    points : (n, 3) array_like
        Observer positions in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    cutoff : float
        Relative size of the dropped tail (see :func:`decay_time`).

    Returns
    -------
    start, stop : (n,) ndarray
        First arrival ``min_j (r_j - a)/c`` and the end of the last image's response
        ``max_j (r_j - a)/c + T + (a/c) ln(1/cutoff)``, in s.
    """
    check_pulse(pulse)
    check_geometry(geometry)
    delay, _, _, _ = source_geometry(points, geometry, medium=medium)
    tail = decay_time(geometry.radius, medium=medium, cutoff=cutoff)
    return delay.min(axis=1), delay.max(axis=1) + pulse.duration + tail



def chunk_geometry(pts, geometry, medium):
    inside = ~geometry.in_fluid(pts)
    delay, p0, cc, _ = source_geometry(pts, geometry, medium=medium)
    if np.any(inside):
        delay[inside] = 0.0
        p0[inside] = 0.0
        cc[inside] = 0.0
    return delay, p0, np.ascontiguousarray(cc.real), np.ascontiguousarray(cc.imag), inside

