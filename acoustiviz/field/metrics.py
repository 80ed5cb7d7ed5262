"""Peaks, RMS and sound exposure of the pressure at many points, without storing time series."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_points, check_positive
from ..constants import P_REF
from ..core.geometry import Geometry
from ..core.medium import AIR, Medium
from ..core.radiation import pulse_response_function
from . import _closed
from ._common import (
    DEFAULT_CUTOFF,
    DEFAULT_MEMORY_LIMIT,
    MODEL_NAMES,
    ImageArrays,
    chunk_size,
    default_sample_interval,
    geometry_bytes,
    prepare,
    uniform_step,
)
from ._kernels import _metrics_kernel
from .sources import arrival_windows, chunk_geometry

__all__ = ["FieldMetrics", "field_metrics", "spl_db"]


def spl_db(pressure_pa):
    """Sound pressure level ``20 log10(|p| / p_ref)`` in dB re :data:`~acoustiviz.constants.P_REF` (``-inf`` for zero).

    The one home of the formula. A scalar gives a float (``math.log10``), an array an array of
    the same shape (``numpy.log10``).

    Parameters
    ----------
    pressure_pa : float or array_like
        Pressure (a peak or an RMS value) in Pa.

    Examples
    --------
    >>> spl_db(1.0)  # 1 Pa
    93.97940008672037
    """
    p = np.abs(np.asarray(pressure_pa, dtype=float))
    if p.ndim == 0:
        return 20.0 * math.log10(float(p) / P_REF) if p > 0 else -math.inf
    with np.errstate(divide="ignore"):
        return 20.0 * np.log10(p / P_REF)


@dataclass(frozen=True)
class FieldMetrics:
    """Peak, RMS and exposure of the pressure at each point.

    Attributes
    ----------
    peak_positive, peak_negative : (n,) ndarray
        Largest and smallest pressure in Pa (``peak_negative <= 0``), of the continuous
        pressure in the window unless :func:`field_metrics` was told not to refine them.
    rms : (n,) ndarray
        Root-mean-square pressure in Pa over each point's window.
    exposure : (n,) ndarray
        Sound exposure ``∫ p² dt`` in Pa²·s over the window.
    window_start : (n,) ndarray
        Start of each point's window in s (its first arrival unless a grid was imposed).
    window : float
        Length of every point's window in s.
    sample_interval : float
        Time step in s used to sample the pressure (the window over a whole number of samples).
    model : (n,) ndarray of uint8
        Code of the model that served each point: an index into ``model_names``.
    model_names : tuple of str
        Names of the models (``"exact"`` first; cheaper ones under a tolerance).
    """

    peak_positive: np.ndarray
    peak_negative: np.ndarray
    rms: np.ndarray
    exposure: np.ndarray
    window_start: np.ndarray
    window: float
    sample_interval: float
    model: np.ndarray
    model_names: tuple = ("exact",)

    @property
    def model_name(self) -> np.ndarray:
        """Name of the model that served each point, as an array of str."""
        return np.asarray(self.model_names)[self.model]

    @property
    def peak_to_peak(self) -> np.ndarray:
        """Peak-to-peak pressure in Pa."""
        return self.peak_positive - self.peak_negative

    @property
    def peak(self) -> np.ndarray:
        """Largest absolute pressure max |p| in Pa."""
        return np.maximum(self.peak_positive, -self.peak_negative)

    @property
    def peak_spl_db(self) -> np.ndarray:
        """Peak sound pressure level ``20 log10(max|p| / 20 µPa)`` in dB."""
        return spl_db(self.peak)

    @property
    def rms_spl_db(self) -> np.ndarray:
        """Level of the RMS pressure over the window, dB re 20 µPa."""
        return spl_db(self.rms)

    @property
    def sel_db(self) -> np.ndarray:
        """Sound exposure level ``10 log10(∫p² dt / (p_ref² · 1 s))`` in dB re 20 µPa, 1 s."""
        with np.errstate(divide="ignore"):
            return 10.0 * np.log10(self.exposure / (P_REF**2 * 1.0))


def _window_samples(pulse, pts, geometry, medium, sample_interval, window, cutoff, limit):
    """Return ``(dt, m, window)``: the step in s, the samples that fill the window, the window in s.

    The window is ``window`` (s) or, by default, the longest arrival spread of the points in the
    fluid (:func:`arrival_windows`); ``m`` whole samples of a step at most the sample interval fill
    it (rounding it up to whole samples of the interval would lengthen it and lower the RMS).
    """
    dt = (
        default_sample_interval(pulse, geometry.radius, medium=medium)
        if sample_interval is None
        else check_positive("sample_interval", sample_interval, "s")
    )
    if window is None:
        win = dt
        n = pts.shape[0]
        step = chunk_size(geometry_bytes(len(geometry.images())) + 40, 8.0 * n * 5, limit)
        for lo in range(0, n, step):
            sub = pts[lo : lo + step]
            start, stop = arrival_windows(pulse, sub, geometry, medium=medium, cutoff=cutoff)
            ok = geometry.in_fluid(sub)
            if np.any(ok):
                win = max(win, float(np.max((stop - start)[ok])))
    else:
        win = check_positive("window", window, "s")
    m = max(1, int(math.ceil(win / dt - 1e-9)))
    return win / m, m, win


def _exact_metrics(pulse, geometry, medium, pa, tail, n: int, m: int, nimg: int, dt: float, refine: bool, per_point,
                   fixed, limit):
    """The exact model's metrics of blocks of points, and the points per block.

    Returns ``(run, chunk)``: ``run(res, t0, img)`` fills ``res[i] = (max p, min p, Σ p²)`` of the
    points of ``img`` (:class:`._common.ImageArrays`) on their grids ``t0[i] + k dt``, k < m; by the
    compiled ``_metrics_kernel``, or for a small request (:func:`._closed.is_small`, where compiling
    would cost more than the work) whose scratch fits in ``limit``, by its numpy twin
    :func:`._closed.numpy_window_metrics`. ``chunk`` from the bytes ``per_point`` and ``fixed``, the scratch added.
    """
    scratch = 8 * m * 7  # the samples, retarded times, complex Y and masks of the vectorised sum
    if _closed.is_small(n, m, nimg, refine=refine, need=per_point + scratch, room=limit - fixed):
        y_of = pulse_response_function(pulse, radius=geometry.radius, medium=medium)

        def run(res, t0, img):
            _closed.numpy_window_metrics(res, y_of, img, pa.tau, tail, t0, dt, m, refine)

        return run, chunk_size(per_point + scratch, fixed, limit)
    buf = np.zeros(m)

    def run(res, t0, img):
        _metrics_kernel(res, buf, t0, dt, img, pa, tail, refine)

    return run, chunk_size(per_point, fixed, limit)


def field_metrics(
    pulse,
    points,
    geometry: Geometry,
    *,
    medium: Medium = AIR,
    sample_interval=None,
    window=None,
    t=None,
    cutoff: float = DEFAULT_CUTOFF,
    memory_limit: float = DEFAULT_MEMORY_LIMIT,
    tolerance=None,
    refine: bool = True,
) -> FieldMetrics:
    """Peaks, RMS and sound exposure at each point, without storing the time series.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    points : (n, 3) array_like
        Observer positions in m; points outside the fluid get NaN.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    sample_interval : float, optional
        Largest time step in s (default :func:`default_sample_interval`, 64 samples per
        ``min(T, a/c)``); the step used is the window divided by a whole number of samples, so
        the samples fill the window exactly.
    window : float, optional
        Length in s of each point's window, which starts at the point's first arrival
        ``min_j (r_j - a)/c``. Default: long enough for every point to hold the whole
        non-zero response of all images (the largest arrival spread + ``T`` + the tail of
        :func:`decay_time`). The RMS is ``sqrt(∫_window p² dt / window)``.
    t : (m,) array_like, optional
        A uniform time grid in s shared by all points instead of ``window``; the RMS window
        is then ``[t[0], t[-1] + dt)``.
    cutoff : float
        Relative size of the dropped tail (see :func:`decay_time`).
    memory_limit : float
        Cap in bytes on working memory plus the returned arrays.
    tolerance : float, optional
        Absolute error in Pa allowed per point. When given, each point is served by the
        cheapest model of :mod:`acoustiviz.core.approximations` whose proven error bound is below
        it (``model`` says which); otherwise the exact closed form serves all points.

    refine : bool
        Refine each point's largest and smallest pressure between the samples (default): from
        the extreme sample, a bounded Brent search on the closed form within one sample interval
        either side (inside the window) to 1e-9 of a sample interval in time, so the peaks are
        those of the continuous pressure to about 1e-12 relative, whatever the sample interval.
        Points served by a cheap model (``tolerance``) keep their sampled extremes. RMS and
        exposure are always sums over the samples.

    Returns
    -------
    FieldMetrics

    Notes
    -----
    Paper eqs 12-14; the SPL of paper Figure 3 is ``peak_spl_db``. The exact model runs a compiled
    kernel, except on small requests (:func:`acoustiviz.field._closed.is_small`: a few tens of points
    of a default window), where compiling would cost more than the work: there the samples are summed
    in numpy from the closed form (:func:`acoustiviz.core.radiation.pulse_response`) on the same grid
    with the same tail cut, and the extremes refined by the same bounded Brent search (SciPy's
    ``fminbound`` algorithm), so both give the same numbers to round-off.

    Examples
    --------
    The paper's Figure 2 listener, 0.7 m from the sphere's centre at 45° above a reflecting
    plane: a peak SPL of 88.8 dB, the image's delayed, inverted arrival deepening the trough:

    >>> from acoustiviz.core.contact import Impact, acceleration_pulse
    >>> a = 0.01905  # the paper's Figure 2 sphere at 1.4 m/s, K = 5.6e8 N/m^1.5
    >>> pulse = acceleration_pulse(Impact(1.4, 5.6e8, 7800.0 * 4.0 / 3.0 * math.pi * a**3))
    >>> from acoustiviz.core.geometry import images_plane
    >>> listener = [[0.7 * math.sin(math.pi / 4), 0.0, a + 0.7 * math.cos(math.pi / 4)]]
    >>> m = field_metrics(pulse, listener, images_plane(a))
    >>> round(float(m.peak_positive[0]), 4), round(float(m.peak_negative[0]), 4)  # Pa
    (0.5514, -0.3409)
    >>> round(float(m.peak_spl_db[0]), 1)  # dB re 20 µPa
    88.8
    """
    pa, tail = prepare(pulse, geometry, medium, cutoff)
    pts = check_points("points", points)
    limit = check_positive("memory_limit", memory_limit, "B")
    n = pts.shape[0]
    nimg = len(geometry.images())
    if t is not None:
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        dt = uniform_step(tt)
        if dt is None:
            raise ParameterError("t", "field_metrics needs a uniform time grid (or none)")
        m = tt.size
        win = m * dt
    else:
        dt, m, win = _window_samples(pulse, pts, geometry, medium, sample_interval, window, cutoff, limit)
    out_bytes = 8.0 * n * 5 + n  # four float results, the window starts and the model codes
    if out_bytes + 8 * m > limit:
        raise ParameterError("memory_limit", f"the results and the window of {m} samples need "
                                             f"{out_bytes + 8 * m:.4g} B > {limit:.4g} B")
    fixed = out_bytes + 8 * m + (limit / 2 if tolerance is not None else 0)  # half for cheap models
    per_point = geometry_bytes(nimg) + 8 * 4 + 16 * nimg
    exact_metrics, chunk = _exact_metrics(pulse, geometry, medium, pa, tail, n, m, nimg, dt, refine, per_point, fixed,
                                          limit)
    pmax = np.empty(n)
    pmin = np.empty(n)
    ssq = np.empty(n)
    wstart = np.empty(n)
    models = np.zeros(n, dtype=np.uint8)
    if tolerance is not None:
        from ..core import approximations as _approx

        tol = check_positive("tolerance", tolerance, "Pa")
    for lo in range(0, n, chunk):
        hi = min(lo + chunk, n)
        delay, p0, cre, cim, inside = chunk_geometry(pts[lo:hi], geometry, medium)
        t0 = np.full(hi - lo, tt[0]) if t is not None else delay.min(axis=1)
        wstart[lo:hi] = t0
        res = np.empty((hi - lo, 3))
        exact = np.ones(hi - lo, dtype=bool)
        if tolerance is not None:
            choice = _approx.choose_models(pulse, delay, p0, cre + 1j * cim, tol, radius=geometry.radius, medium=medium)
            for code, name in enumerate(_approx.MODELS):
                sel = choice == code
                if name == "exact" or not np.any(sel):
                    continue
                exact &= ~sel
                res[sel] = _approx.window_metrics(
                    name, pulse, delay[sel], p0[sel], t0[sel], dt, m, radius=geometry.radius, medium=medium,
                    max_bytes=limit / 4,
                )  # fmt: skip
                models[lo:hi][sel] = code
        if np.all(exact):
            exact_metrics(res, t0, ImageArrays(delay, p0, cre, cim))
        elif np.any(exact):
            sub = np.empty((int(exact.sum()), 3))
            exact_metrics(
                sub, np.ascontiguousarray(t0[exact]),
                ImageArrays(*(np.ascontiguousarray(x[exact]) for x in (delay, p0, cre, cim))),
            )  # fmt: skip
            res[exact] = sub
        res[inside] = np.nan
        pmax[lo:hi], pmin[lo:hi], ssq[lo:hi] = res[:, 0], res[:, 1], res[:, 2]
    return FieldMetrics(
        peak_positive=pmax,
        peak_negative=pmin,
        rms=np.sqrt(ssq / m),
        exposure=ssq * dt,
        window_start=wstart,
        window=float(win),
        sample_interval=float(dt),
        model=models,
        model_names=MODEL_NAMES if tolerance is None else _approx.MODELS,
    )

