"""The field's sums in numpy: the vectorised closed form of ``Y``, with the kernels' tail cut.

Small requests (:func:`is_small`: at most :data:`SMALL_WORK` points x samples x images) and
non-uniform time grids are summed here rather than by the numba kernels of
:mod:`acoustiviz.field._kernels`: at such sizes the work takes milliseconds in numpy, while compiling
a kernel on an empty cache takes seconds. Each
image adds ``p0 Re[C Y(t - delay)]`` (paper eqs 12-14) with ``Y`` from
:func:`acoustiviz.core.radiation.pulse_response_function`, on exactly the samples the kernels'
``_accumulate`` touches (retarded times ``0 <= t' < T + tail``, ``T`` the pulse's end, ``tail`` the
kept free decay after it), so both agree to round-off. Times in s, pressures in Pa.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

#: Largest work (points x samples x images) of a request summed in numpy instead of by the
#: compiled kernels: below it numpy takes a small fraction of the time a kernel needs to compile on
#: an empty numba cache, so a small request (a waveform, the command line's default directivity)
#: never waits for a compilation. Figures: ``benchmarks/results/design_timings.md``.
SMALL_WORK = 1_000_000
#: Work (in units of :data:`SMALL_WORK`) of refining one point's two extremes in numpy (two bounded
#: Brent searches of about 20 evaluations of ``p`` each), so that the few tens of points of a
#: directivity are refined in numpy while a map's thousands go to the kernels.
#: Figures: ``benchmarks/results/design_timings.md``.
REFINE_WORK = 20_000


def is_small(points: int, samples: int, images: int, *, refine: bool = False, need: float = 0.0,
             room: float = math.inf) -> bool:
    """Whether a request of ``points x samples x images`` (each point's extremes refined or not) is summed in numpy.

    The work ``points (samples images + REFINE_WORK [refine])`` against :data:`SMALL_WORK`, and the
    bytes ``need`` of one point in numpy (its samples and scratch) against the ``room`` left in the
    memory budget: a request that does not fit goes to the compiled kernel, which needs less.
    """
    return points * (samples * images + (REFINE_WORK if refine else 0)) <= SMALL_WORK and need <= room


def add_images(out, y_of, img, end: float, tail: float, *, t0=None, dt=None, t=None):
    """Add into ``out[i, k]`` the pressure in Pa of every image of point ``i``, with the kernels' tail cut.

    Parameters
    ----------
    out : (n, m) ndarray
        Pressure in Pa, added to in place.
    y_of : callable
        ``Y`` in m/s of retarded times in s (:func:`~acoustiviz.core.radiation.pulse_response_function`).
    img : ImageArrays
        The images seen from each point (:class:`acoustiviz.field._common.ImageArrays`).
    end : float
        The pulse's end ``T`` in s.
    tail : float
        Free decay kept after the pulse's end, in s.
    t0 : (n,) ndarray, optional
        With ``dt``: point ``i``'s samples are at ``t0[i] + k dt`` (s), and image ``j`` is added
        on the samples ``k0 <= k < ke`` of the kernels' ``_accumulate``, by its index arithmetic.
    dt : float, optional
        Uniform time step in s.
    t : (m,) ndarray, optional
        Otherwise, the times in s shared by all points; image ``j`` is added where
        ``0 <= t' < end + tail``.
    """
    n, m = out.shape
    if dt is not None:
        k = np.arange(m)
        start = t0[:, None]
        times = start + k * dt
    else:
        times = t[None, :]
    for j in range(img.delay.shape[1]):
        d = img.delay[:, j : j + 1]
        tr = times - d
        y = y_of(tr)
        if dt is not None:  # as _accumulate: k0 = ceil((delay - t0)/dt), kt, ke likewise, clipped to [0, m]
            k0 = np.maximum(np.ceil((d - start) / dt), 0.0)
            kt = np.clip(np.ceil((d + end - start) / dt), k0, m)
            ke = np.clip(np.ceil((d + end + tail - start) / dt), kt, m)
            y[(k < k0) | (k >= ke)] = 0.0
        else:
            y[tr >= end + tail] = 0.0
        del tr
        out += img.p0[:, j : j + 1] * (img.cre[:, j : j + 1] * y.real - img.cim[:, j : j + 1] * y.imag)
        del y


def numpy_window_metrics(res, y_of, img, end: float, tail: float, t0, dt: float, m: int, refine: bool):
    """Per point ``i``: ``res[i] = (max p, min p, Σ p²)`` (Pa, Pa, Pa²) over its grid ``t0[i] + k dt``, k < m.

    The numpy twin of :func:`acoustiviz.field._kernels._metrics_kernel`: the samples with the tail
    cut of :func:`add_images`, extremes starting from 0 (a silent point has ``max p = min p = 0``),
    and with ``refine`` the extreme samples refined between the samples inside
    ``[t0[i], t0[i] + (m - 1) dt]`` by :func:`refine_extreme`. Arguments as :func:`add_images`.
    """
    n = img.delay.shape[0]
    p = np.zeros((n, m))
    add_images(p, y_of, img, end, tail, t0=t0, dt=dt)
    kmax = np.argmax(p, axis=1)
    kmin = np.argmin(p, axis=1)
    rows = np.arange(n)
    res[:, 0] = np.maximum(p[rows, kmax], 0.0)
    res[:, 1] = np.minimum(p[rows, kmin], 0.0)
    res[:, 2] = np.sum(p * p, axis=1)
    if not refine:
        return
    for i in range(n):
        live = img.p0[i] != 0.0
        delay, p0, cre, cim = (x[i, live] for x in img)

        def p_at(time, delay=delay, p0=p0, cre=cre, cim=cim):
            y = y_of(time - delay)
            return float((p0 * (cre * y.real - cim * y.imag)).sum())

        lo, hi = t0[i], t0[i] + (m - 1) * dt
        if res[i, 0] > 0.0:
            res[i, 0] = refine_extreme(p_at, 1.0, t0[i] + kmax[i] * dt, dt, lo, hi)
        if res[i, 1] < 0.0:
            res[i, 1] = -refine_extreme(p_at, -1.0, t0[i] + kmin[i] * dt, dt, lo, hi)


def refine_extreme(p_at, sign: float, tk: float, dt: float, lo: float, hi: float) -> float:
    """Largest ``sign · p`` in Pa on ``[max(lo, tk - dt), min(hi, tk + dt)]`` (s), ``p_at(t)`` the pressure.

    The same algorithm as the kernels' ``_refine``: a bounded Brent search (golden section with
    parabolic steps; SciPy's ``fminbound``, here through ``minimize_scalar(method="bounded")``) in
    ``x = (t - tk)/dt`` on ``[max(lo - tk, -dt)/dt, min(hi - tk, dt)/dt]`` to ``|Δx| < 1e-9``;
    the result is never below the sample ``sign · p(tk)``.
    """
    a = max(lo - tk, -dt) / dt
    b = min(hi - tk, dt) / dt
    best = sign * p_at(tk)
    if not b > a:
        return best
    found = minimize_scalar(
        lambda x: -sign * p_at(tk + x * dt), bounds=(a, b), method="bounded", options={"xatol": 1e-9, "maxiter": 200}
    )
    return max(best, -float(found.fun))
