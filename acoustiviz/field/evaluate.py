"""Pressure time series and snapshots of a sphere and its images over many points.

The evaluator computes each point only inside its own retarded window: ``Y(t') = 0`` for
``t' < 0``, and after the pulse (length ``T``) ``Y(t') = exp(s (t' - T)) Y(T)`` decays like
``exp(-c (t' - T)/a)``; it is dropped once that factor is below ``cutoff`` (default 1e-10, i.e.
``23 a/c`` after the pulse). On a uniform time grid a numba kernel advances ``exp(i ω t')`` and
``exp(s t')`` by one complex multiply per sample (the exact Hertz pulse: a short Taylor polynomial
per sample); other grids, and requests of at most :data:`acoustiviz.field._closed.SMALL_WORK`
points x samples x images (where compiling the kernel would cost more than the work), use the
vectorised closed form of :func:`acoustiviz.core.radiation.pulse_response` on the same samples with
the same tail cut. Points are processed in chunks within ``memory_limit`` bytes. Times in s from
the start of contact, points in m, pressures in Pa.
"""

from __future__ import annotations

import numpy as np

from .._validate import ParameterError, check_points, check_positive
from ..core.geometry import Geometry
from ..core.medium import AIR, Medium
from ..core.radiation import pulse_response_function
from . import _closed
from ._common import (
    DEFAULT_CUTOFF,
    DEFAULT_MEMORY_LIMIT,
    ImageArrays,
    check_geometry,
    check_pulse,
    chunk_size,
    geometry_bytes,
    prepare,
    uniform_step,
)
from ._kernels import _series_kernel
from .sources import chunk_geometry

__all__ = ["iter_time_series", "time_series", "snapshots"]


def iter_time_series(
    pulse,
    t,
    points,
    geometry: Geometry,
    *,
    medium: Medium = AIR,
    cutoff: float = DEFAULT_CUTOFF,
    memory_limit: float = DEFAULT_MEMORY_LIMIT,
):
    """Yield the pressure at consecutive blocks of points, each block within ``memory_limit``.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    t : (m,) array_like
        Times in s. A uniform grid uses the numba kernel (small blocks excepted); any other
        grid the vectorised closed form.
    points : (n, 3) array_like
        Observer positions in m. Points outside the fluid (inside the sphere or behind a
        plane) get NaN.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    cutoff : float
        Relative size of the dropped tail (see :func:`decay_time`).
    memory_limit : float
        Bytes of working memory per block, the yielded block included.

    Yields
    ------
    start, stop : int
        The block covers ``points[start:stop]``.
    block : (stop - start, m) ndarray
        Pressure in Pa.
    """
    pa, tail = prepare(pulse, geometry, medium, cutoff)
    pts = check_points("points", points)
    tt = np.atleast_1d(np.asarray(t, dtype=float))
    if tt.ndim != 1 or not np.all(np.isfinite(tt)):
        raise ParameterError("t", "expected a finite 1-D array of times in s")
    limit = check_positive("memory_limit", memory_limit, "B")
    nimg = len(geometry.images())
    dt, closed, chunk = _series_plan(tt, pts.shape[0], nimg, 8 * tt.size + geometry_bytes(nimg), 8 * tt.size * 2, limit)
    for start in range(0, pts.shape[0], chunk):
        stop = min(start + chunk, pts.shape[0])
        out = np.zeros((stop - start, tt.size))
        _series_chunk(out, pulse, tt, dt, closed, pts[start:stop], geometry, medium, pa, tail)
        yield start, stop, out


def _series_plan(tt, n: int, nimg: int, per_point: float, fixed: float, limit: float):
    """How to sum ``n`` points over the grid ``tt``: ``(dt, closed, chunk)``.

    ``dt``: the grid's step in s (None if not uniform); ``closed``: sum in numpy (a non-uniform grid,
    or a small request, :func:`._closed.is_small`, where compiling the kernel would cost more than
    the work, if its scratch fits in ``limit``) rather than by the compiled kernel; ``chunk``: points
    per block, from the bytes ``per_point`` and ``fixed`` (numpy's scratch added).
    """
    dt = uniform_step(tt)
    scratch = 8 * tt.size * 6  # retarded times, complex Y, masks of the vectorised sum
    closed = dt is None or _closed.is_small(n, tt.size, nimg, need=per_point + scratch, room=limit - fixed)
    return dt, closed, chunk_size(per_point + (scratch if closed else 0), fixed, limit)


def _series_chunk(out, pulse, tt, dt, closed, sub, geometry, medium, pa, tail):
    """Fill the zeroed ``out`` (len(sub), m) with the pressure in Pa at ``sub`` and times ``tt``.

    ``pa`` and ``tail`` (s) are those of :func:`._common.prepare`; ``dt`` the grid's step in s or None;
    ``closed``: sum in numpy (:func:`._closed.add_images`, the kernel's samples and tail) rather than
    by the compiled kernel.
    """
    delay, p0, cre, cim, inside = chunk_geometry(sub, geometry, medium)
    img = ImageArrays(delay, p0, cre, cim)
    t0 = np.full(sub.shape[0], tt[0])
    if not closed:
        _series_kernel(out, t0, dt, img, pa, tail)
    else:  # a small block or a non-uniform grid: the vectorised closed form, the same samples and tail
        y_of = pulse_response_function(pulse, radius=geometry.radius, medium=medium)
        _closed.add_images(out, y_of, img, pa.tau, tail, t0=t0, dt=dt, t=tt)
    out[inside] = np.nan


def time_series(
    pulse,
    t,
    points,
    geometry: Geometry,
    *,
    medium: Medium = AIR,
    cutoff: float = DEFAULT_CUTOFF,
    memory_limit: float = DEFAULT_MEMORY_LIMIT,
):
    """Pressure in Pa at every point and time, summed over the sphere and its images.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    t : (m,) array_like
        Times in s from the start of contact.
    points : (n, 3) array_like
        Observer positions in m; points outside the fluid get NaN.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images (:func:`acoustiviz.core.geometry.geometry`).
    medium : Medium
        The fluid (default air at 20 °C).
    cutoff : float
        Relative size of the dropped tail (see :func:`decay_time`).
    memory_limit : float
        Cap in bytes on the working memory *and* the returned array; a request whose result
        alone exceeds it raises (use :func:`iter_time_series` or :func:`field_metrics`).

    Returns
    -------
    (n, m) ndarray
        Pressure in Pa.

    Notes
    -----
    Paper eqs 12-14 summed over images; see the module notes for the windowing and cutoff.

    Examples
    --------
    >>> from acoustiviz.core.contact import Impact, acceleration_pulse
    >>> from acoustiviz.core.geometry import images_plane
    >>> pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=0.2264))
    >>> p = time_series(pulse, np.linspace(0, 4e-3, 4001), [[0.495, 0, 0.495]], images_plane(0.01905))
    >>> p.shape
    (1, 4001)
    """
    pts = check_points("points", points)
    tt = np.atleast_1d(np.asarray(t, dtype=float))
    limit = check_positive("memory_limit", memory_limit, "B")
    need = 8.0 * pts.shape[0] * tt.size
    if need > limit:
        raise ParameterError(
            "memory_limit",
            f"the result alone needs {need:.4g} B > {limit:.4g} B; use iter_time_series or field_metrics",
        )
    pa, tail = prepare(pulse, geometry, medium, cutoff)
    if tt.ndim != 1 or not np.all(np.isfinite(tt)):
        raise ParameterError("t", "expected a finite 1-D array of times in s")
    nimg = len(geometry.images())
    dt, closed, chunk = _series_plan(tt, pts.shape[0], nimg, geometry_bytes(nimg), need, limit)
    out = np.zeros((pts.shape[0], tt.size))
    for start in range(0, pts.shape[0], chunk):
        stop = min(start + chunk, pts.shape[0])
        _series_chunk(out[start:stop], pulse, tt, dt, closed, pts[start:stop], geometry, medium, pa, tail)
    return out



def snapshots(
    pulse,
    times,
    points,
    geometry: Geometry,
    *,
    medium: Medium = AIR,
    memory_limit: float = DEFAULT_MEMORY_LIMIT,
):
    """Pressure field p(x, t) over a set of points at a few given times.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    times : (k,) array_like
        Snapshot times in s.
    points : (n, 3) array_like
        Grid points in m (e.g. ``PlanarGrid.points``); points outside the fluid get NaN.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    memory_limit : float
        Cap in bytes on the working memory and the returned array.

    Returns
    -------
    (k, n) ndarray
        Pressure in Pa, one row per snapshot time.

    Examples
    --------
    Above a reflecting plane, 0.7 m up the axis and 0.7 m along the floor: silence before the
    sound can arrive (``(r - a)/c`` = 1.98 ms), then a pressure; a point below the floor is NaN:

    >>> import math
    >>> from acoustiviz.core.contact import Impact, acceleration_pulse
    >>> a = 0.01905  # the paper's Figure 2 sphere at 1.4 m/s, K = 5.6e8 N/m^1.5
    >>> pulse = acceleration_pulse(Impact(1.4, 5.6e8, 7800.0 * 4.0 / 3.0 * math.pi * a**3))
    >>> from acoustiviz.core.geometry import images_plane
    >>> points = [[0.0, 0.0, a + 0.7], [0.7, 0.0, a], [0.0, 0.0, -0.1]]
    >>> np.round(snapshots(pulse, [1e-3, 2.3e-3], points, images_plane(a)), 4)  # Pa
    array([[ 0.    ,  0.    ,     nan],
           [-0.5939, -0.0066,     nan]])
    """
    check_pulse(pulse)
    check_geometry(geometry)
    pts = check_points("points", points)
    tt = np.atleast_1d(np.asarray(times, dtype=float))
    if tt.ndim != 1 or not np.all(np.isfinite(tt)):
        raise ParameterError("times", "expected a finite 1-D array of times in s")
    limit = check_positive("memory_limit", memory_limit, "B")
    need = 8.0 * pts.shape[0] * tt.size
    per_point = geometry_bytes(len(geometry.images())) + 8 * 6
    chunk = chunk_size(per_point, need, limit)
    out = np.empty((tt.size, pts.shape[0]))
    y_of = pulse_response_function(pulse, radius=geometry.radius, medium=medium)  # the pulse's tables once
    for lo in range(0, pts.shape[0], chunk):
        hi = min(lo + chunk, pts.shape[0])
        delay, p0, cre, cim, inside = chunk_geometry(pts[lo:hi], geometry, medium)
        for q, tq in enumerate(tt):
            acc = np.zeros(hi - lo)
            for j in range(delay.shape[1]):
                y = y_of(tq - delay[:, j])
                acc += p0[:, j] * (cre[:, j] * y.real - cim[:, j] * y.imag)
            acc[inside] = np.nan
            out[q, lo:hi] = acc
    return out

