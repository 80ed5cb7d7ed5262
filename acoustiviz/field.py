"""Pressure of a sphere and its images over many points: time series, peaks, RMS, SPL, snapshots.

Every image source ``j`` (see :mod:`acoustiviz.images`) is a rigid sphere radiating in free
field; at an observer ``x`` its pressure is (paper eqs 12-14)::

    p_j(x, t) = P0_j Re[C_j Y(t - d_j)],   d_j = (|x - x_j| - a)/c,

with ``P0_j = ρ c a² cosθ_j / r_j²`` and ``C_j = r_j/a - i(1 - r_j/a)`` from
:func:`acoustiviz.radiation.radiation_coefficients`, and ``Y`` the observer-independent pulse
response of :func:`acoustiviz.radiation.pulse_response`. The evaluator

* computes each point only inside its own retarded window: ``Y(t') = 0`` for ``t' < 0``, and
  after the pulse (length ``T``) ``Y(t') = exp(s (t' - T)) Y(T)`` decays like
  ``exp(-c (t' - T)/a)``; it is dropped once that factor is below ``cutoff`` (default 1e-10,
  i.e. ``23 a/c`` after the pulse), so the neglected pressure is below
  ``cutoff · |P0||C| max|Y|`` for each image;
* on a uniform time grid advances ``exp(i ω t')`` and ``exp(s t')`` by one complex multiply per
  sample (a numba kernel), the closed form being re-entered exactly at the start of each
  interval; the sampled (Hertz) pulse is evaluated exactly per sample inside the pulse;
* processes the points in chunks so that its working memory stays under ``memory_limit``
  bytes (default 256 MiB); peak and RMS metrics reduce each point's series on the fly and never
  hold the series of all points.

Times are in s from the start of contact, points in m, pressures in Pa. This module imports
only the physics core (``radiation``, ``contact``, ``images``) and never plots.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._validate import ParameterError, check_points, check_positive, check_range
from .contact import HalfSinePulse, SampledPulse
from .images import Configuration, observer_points
from .medium import AIR, Medium
from .radiation import pulse_response, sphere_pole

__all__ = [
    "DEFAULT_CUTOFF",
    "DEFAULT_MEMORY_LIMIT",
    "P_REF",
    "FieldMetrics",
    "source_geometry",
    "decay_time",
    "arrival_windows",
    "waveform_span",
    "default_sample_interval",
    "time_series",
    "iter_time_series",
    "field_metrics",
    "snapshots",
    "spl_db",
    "Directivity",
    "circle_points",
    "directivity",
]

#: Relative size of the decaying tail below which a sphere's response is dropped.
DEFAULT_CUTOFF = 1e-10
#: Default cap on the evaluator's working memory, in bytes (256 MiB).
DEFAULT_MEMORY_LIMIT = 256 * 2**20
#: Reference sound pressure in Pa (20 µPa).
P_REF = 20e-6
#: Model names when no tolerance is given: the exact closed form serves every point.
MODEL_NAMES = ("exact",)
#: Largest number of points handled per chunk (keeps the geometry arrays in cache).
_MAX_CHUNK = 65536


# --------------------------------------------------------------------------- numba kernels
def _njit(*args, **kwargs):
    try:
        from numba import njit
    except ImportError:  # pragma: no cover - numba is a hard dependency in practice
        return lambda f: f
    return njit(*args, **kwargs)


#: 1/k! for k = 0..17, for the Taylor series of the φ-functions
_INV_FACT = np.array([1.0 / math.factorial(k) for k in range(18)])


@_njit(cache=True)
def _phi12_scalar(z):  # pragma: no cover - compiled
    """φ1(z) = (e^z - 1)/z and φ2(z) = (e^z - 1 - z)/z² for one complex z with Re z <= 0."""
    if abs(z) < 0.25:
        t1 = 0j
        t2 = 0j
        for j in range(14, -1, -1):  # 15 terms: < 1e-17 at |z| = 0.25
            t1 = t1 * z + _INV_FACT[j + 1]
            t2 = t2 * z + _INV_FACT[j + 2]
        return t1, t2
    ez = np.exp(z)
    return (ez - 1.0) / z, (ez - 1.0 - z) / (z * z)


@_njit(cache=True)
def _y_sampled(tr, xi, acc, yk, s):  # pragma: no cover - compiled
    """Exact pulse response of a piecewise-linear pulse at one retarded time (complex m/s)."""
    if tr < 0.0:
        return 0j
    nk = xi.size
    end = xi[nk - 1]
    if tr >= end:
        return np.exp(s * (tr - end)) * yk[nk - 1]
    k = np.searchsorted(xi, tr, side="right") - 1
    if k < 0:
        k = 0
    if k > nk - 2:
        k = nk - 2
    delta = tr - xi[k]
    slope = (acc[k + 1] - acc[k]) / (xi[k + 1] - xi[k])
    p1, p2 = _phi12_scalar(s * delta)
    return np.exp(s * delta) * yk[k] + delta * (acc[k] * p1 + slope * delta * p2)


@_njit(cache=True)
def _accumulate(buf, t0, dt, delay, p0, cre, cim, kind, amp, tau, xi, acc, yk, s, tail):  # pragma: no cover
    """Add one sphere's pressure to ``buf[k]`` at ``t0 + k dt``; return the touched index range."""
    m = buf.size
    end = tau if kind == 0 else xi[xi.size - 1]
    k0 = int(math.ceil((delay - t0) / dt))
    if k0 < 0:
        k0 = 0
    if k0 >= m:
        return m, m
    kt = int(math.ceil((delay + end - t0) / dt))
    kt = min(max(kt, k0), m)
    ke = int(math.ceil((delay + end + tail - t0) / dt))
    ke = min(max(ke, kt), m)
    dF = np.exp(s * dt)
    if kind == 0:
        w = math.pi / tau
        coef = amp / (s * s + w * w)
        if kt > k0:
            tr = t0 + k0 * dt - delay
            e = np.exp(1j * w * tr)
            de = np.exp(1j * w * dt)
            f = np.exp(s * tr)
            for k in range(k0, kt):
                y = coef * (-s * e.imag - w * e.real + w * f)
                buf[k] += p0 * (cre * y.real - cim * y.imag)
                e *= de
                f *= dF
        yend = coef * w * (1.0 + np.exp(s * tau))
    else:
        for k in range(k0, kt):
            y = _y_sampled(t0 + k * dt - delay, xi, acc, yk, s)
            buf[k] += p0 * (cre * y.real - cim * y.imag)
        yend = yk[yk.size - 1]
    if ke > kt:
        g = yend * np.exp(s * (t0 + kt * dt - delay - end))
        for k in range(kt, ke):
            buf[k] += p0 * (cre * g.real - cim * g.imag)
            g *= dF
    return k0, ke


@_njit(cache=True)
def _series_kernel(out, t0, dt, delays, p0s, cres, cims, kind, amp, tau, xi, acc, yk, s, tail):  # pragma: no cover
    n, nimg = delays.shape
    for i in range(n):
        for j in range(nimg):
            _accumulate(
                out[i], t0[i], dt, delays[i, j], p0s[i, j], cres[i, j], cims[i, j], kind, amp, tau, xi, acc, yk, s, tail
            )


@_njit(cache=True)
def _metrics_kernel(
    res, buf, t0, dt, delays, p0s, cres, cims, kind, amp, tau, xi, acc, yk, s, tail
):  # pragma: no cover
    """Per point: max p, min p, sum p² over the point's grid ``t0[i] + k dt``, k < buf.size."""
    n, nimg = delays.shape
    m = buf.size
    for i in range(n):
        lo = m
        hi = 0
        for j in range(nimg):
            a, b = _accumulate(
                buf, t0[i], dt, delays[i, j], p0s[i, j], cres[i, j], cims[i, j], kind, amp, tau, xi, acc, yk, s, tail
            )
            if b > a:
                lo = min(lo, a)
                hi = max(hi, b)
        pmax = 0.0
        pmin = 0.0
        ssq = 0.0
        for k in range(lo, hi):
            v = buf[k]
            if v > pmax:
                pmax = v
            if v < pmin:
                pmin = v
            ssq += v * v
            buf[k] = 0.0
        res[i, 0] = pmax
        res[i, 1] = pmin
        res[i, 2] = ssq


# --------------------------------------------------------------------------- helpers
def _check_pulse(pulse):
    if not isinstance(pulse, (HalfSinePulse, SampledPulse)):
        raise ParameterError("pulse", f"expected a HalfSinePulse or SampledPulse, got {type(pulse).__name__}")
    return pulse


def _check_config(config):
    if not isinstance(config, Configuration):
        raise ParameterError("config", f"expected an images.Configuration, got {type(config).__name__}")
    return config


def _pulse_args(pulse, radius: float, medium: Medium):
    """Flatten a pulse into the kernel's arguments."""
    s = sphere_pole(radius, medium)
    if isinstance(pulse, HalfSinePulse):
        empty = np.zeros(2)
        return 0, float(pulse.amplitude), float(pulse.duration), empty, empty, np.zeros(2, complex), s
    from .radiation import _knot_states

    xi = np.ascontiguousarray(pulse.times, dtype=float)
    acc = np.ascontiguousarray(pulse.acceleration_samples, dtype=float)
    return 1, 0.0, float(xi[-1]), xi, acc, _knot_states(xi, acc, s), s


def decay_time(radius: float, *, medium: Medium = AIR, cutoff: float = DEFAULT_CUTOFF) -> float:
    """Time in s after the pulse ends over which a sphere's response is kept.

    The response after the pulse decays like ``exp(-c t/a)``; it is kept until that factor
    falls to ``cutoff``: ``(a/c) ln(1/cutoff)``.

    Parameters
    ----------
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.
    cutoff : float
        Relative amplitude, in (0, 1).

    Returns
    -------
    float
        Tail length in s.
    """
    a = check_positive("radius", radius, "m")
    c = check_range("cutoff", cutoff, 0.0, 1.0, low_open=True, high_open=True)
    return a / medium.c * math.log(1.0 / c)


def source_geometry(points, config: Configuration, *, medium: Medium = AIR):
    """Delays, amplitudes and shape coefficients of every image at every point.

    Parameters
    ----------
    points : (n, 3) array_like
        Observer positions in m.
    config : Configuration
        The sphere and its images.
    medium : Medium
        The fluid.

    Returns
    -------
    delay : (n, k) ndarray
        ``(r_j - a)/c`` in s for each of the ``k`` sources.
    p0 : (n, k) ndarray
        ``ρ c a² cosθ_j / r_j²`` in Pa/(m/s).
    c_shape : (n, k) complex ndarray
        ``r_j/a - i(1 - r_j/a)``.
    distance : (n, k) ndarray
        ``r_j`` in m.

    Notes
    -----
    Paper eqs 11-14; the sign of each image is carried by its mirrored axis.
    """
    pts = check_points("points", points)
    a = config.radius
    n, k = pts.shape[0], len(config.sources)
    r = np.empty((n, k))
    ct = np.empty((n, k))
    for j, src in enumerate(config.sources):
        d = pts - src.position
        r[:, j] = np.sqrt(np.einsum("ij,ij->i", d, d))
        with np.errstate(invalid="ignore", divide="ignore"):
            ct[:, j] = (d @ src.axis) / r[:, j]
    ra = r / a
    with np.errstate(invalid="ignore", divide="ignore"):
        p0 = medium.rho * medium.c * a * a * ct / (r * r)
    return (r - a) / medium.c, p0, ra - 1j * (1.0 - ra), r


def waveform_span(pulse, point, config: Configuration, *, medium: Medium = AIR, decay_times: float = 40.0):
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
    config : Configuration
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
    delay = source_geometry(np.asarray(point, dtype=float)[None, :], config, medium=medium)[0][0]
    return float(delay.min()), float(delay.max()) + pulse.duration + decay_times * config.radius / medium.c


def arrival_windows(pulse, points, config: Configuration, *, medium: Medium = AIR, cutoff: float = DEFAULT_CUTOFF):
    """Interval of each point in which its pressure is non-zero (to ``cutoff``).

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    points : (n, 3) array_like
        Observer positions in m.
    config : Configuration
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
    _check_pulse(pulse)
    _check_config(config)
    delay, _, _, _ = source_geometry(points, config, medium=medium)
    tail = decay_time(config.radius, medium=medium, cutoff=cutoff)
    return delay.min(axis=1), delay.max(axis=1) + pulse.duration + tail


def default_sample_interval(pulse, radius: float, *, medium: Medium = AIR, samples: int = 64) -> float:
    """A sample interval in s resolving both the pulse and the sphere's decay time.

    ``min(T, a/c) / samples``: ``samples`` points per pulse length ``T`` or per decay time
    ``a/c`` of the sphere, whichever is shorter.
    """
    a = check_positive("radius", radius, "m")
    if int(samples) < 4:
        raise ParameterError("samples", f"must be >= 4, got {samples}")
    return min(_check_pulse(pulse).duration, a / medium.c) / int(samples)


def _uniform_step(t: np.ndarray):
    """Return the step of a uniform grid, or None if ``t`` is not uniform (to 1e-9 of a step)."""
    if t.size < 2:
        return None
    dt = (t[-1] - t[0]) / (t.size - 1)
    if not dt > 0:
        return None
    if np.max(np.abs(t - (t[0] + dt * np.arange(t.size)))) > 1e-9 * dt:
        return None
    return float(dt)


def _chunk_size(bytes_per_point: float, fixed: float, memory_limit: float, name="memory_limit") -> int:
    room = memory_limit - fixed
    if room < bytes_per_point:
        raise ParameterError(
            name,
            f"{memory_limit:.4g} B is too small: the results and fixed buffers need {fixed:.4g} B, plus "
            f"{bytes_per_point:.4g} B per point of a chunk",
        )
    return int(max(1, min(_MAX_CHUNK, room // bytes_per_point)))


def _geometry_bytes(nimg: int) -> int:
    # delay, p0, c (complex), r, ct, ra + per-source temporaries (d (n,3), r, ct) and the mask
    return 8 * (nimg * 9 + 12)


def _prepare(pulse, config, medium, cutoff):
    _check_pulse(pulse)
    _check_config(config)
    if not isinstance(medium, Medium):
        raise ParameterError("medium", f"expected a Medium, got {type(medium).__name__}")
    tail = decay_time(config.radius, medium=medium, cutoff=cutoff)
    return _pulse_args(pulse, config.radius, medium), tail


def _chunk_geometry(pts, config, medium):
    inside = ~config.in_fluid(pts)
    delay, p0, cc, _ = source_geometry(pts, config, medium=medium)
    if np.any(inside):
        delay[inside] = 0.0
        p0[inside] = 0.0
        cc[inside] = 0.0
    return delay, p0, np.ascontiguousarray(cc.real), np.ascontiguousarray(cc.imag), inside


# --------------------------------------------------------------------------- time series
def iter_time_series(
    pulse,
    t,
    points,
    config: Configuration,
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
        Times in s. A uniform grid uses the numba kernel; any other grid the vectorised
        closed form.
    points : (n, 3) array_like
        Observer positions in m. Points outside the fluid (inside the sphere or behind a
        plane) get NaN.
    config : Configuration
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
    (kind, amp, tau, xi, acc, yk, s), tail = _prepare(pulse, config, medium, cutoff)
    pts = check_points("points", points)
    tt = np.atleast_1d(np.asarray(t, dtype=float))
    if tt.ndim != 1 or not np.all(np.isfinite(tt)):
        raise ParameterError("t", "expected a finite 1-D array of times in s")
    limit = check_positive("memory_limit", memory_limit, "B")
    nimg = len(config.sources)
    dt = _uniform_step(tt)
    per_point = 8 * tt.size + _geometry_bytes(nimg)
    if dt is None:
        per_point += 8 * tt.size * 6  # retarded times, complex Y, masks of the vectorised path
    chunk = _chunk_size(per_point, 8 * tt.size * 2, limit)
    for start in range(0, pts.shape[0], chunk):
        stop = min(start + chunk, pts.shape[0])
        out = np.zeros((stop - start, tt.size))
        _series_chunk(out, pulse, tt, dt, pts[start:stop], config, medium, (kind, amp, tau, xi, acc, yk, s), tail)
        yield start, stop, out


def _series_chunk(out, pulse, tt, dt, sub, config, medium, pargs, tail):
    """Fill the zeroed ``out`` (len(sub), m) with the pressure in Pa at ``sub`` and times ``tt``."""
    kind, amp, tau, xi, acc, yk, s = pargs
    delay, p0, cre, cim, inside = _chunk_geometry(sub, config, medium)
    if dt is not None:
        t0 = np.full(sub.shape[0], tt[0])
        _series_kernel(out, t0, dt, delay, p0, cre, cim, kind, amp, tau, xi, acc, yk, s, tail)
    else:
        for j in range(delay.shape[1]):
            y = pulse_response(pulse, tt[None, :] - delay[:, j : j + 1], radius=config.radius, medium=medium)
            out += p0[:, j : j + 1] * (cre[:, j : j + 1] * y.real - cim[:, j : j + 1] * y.imag)
            del y
    out[inside] = np.nan


def time_series(
    pulse,
    t,
    points,
    config: Configuration,
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
    config : Configuration
        The sphere and its images (:func:`acoustiviz.images.configuration`).
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
    >>> from acoustiviz.contact import Impact, acceleration_pulse
    >>> from acoustiviz.images import images_plane
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
    pargs, tail = _prepare(pulse, config, medium, cutoff)
    if tt.ndim != 1 or not np.all(np.isfinite(tt)):
        raise ParameterError("t", "expected a finite 1-D array of times in s")
    dt = _uniform_step(tt)
    per_point = _geometry_bytes(len(config.sources)) + (0 if dt is not None else 8 * tt.size * 6)
    chunk = _chunk_size(per_point, need, limit)
    out = np.zeros((pts.shape[0], tt.size))
    for start in range(0, pts.shape[0], chunk):
        stop = min(start + chunk, pts.shape[0])
        _series_chunk(out[start:stop], pulse, tt, dt, pts[start:stop], config, medium, pargs, tail)
    return out


# --------------------------------------------------------------------------- metrics
def spl_db(pressure_pa):
    """Sound pressure level ``20 log10(|p| / 20 µPa)`` in dB (``-inf`` for zero)."""
    p = np.abs(np.asarray(pressure_pa, dtype=float))
    with np.errstate(divide="ignore"):
        return 20.0 * np.log10(p / P_REF)


@dataclass(frozen=True)
class FieldMetrics:
    """Peak, RMS and exposure of the pressure at each point.

    Attributes
    ----------
    peak_positive, peak_negative : (n,) ndarray
        Largest and smallest pressure in Pa (``peak_negative <= 0``).
    rms : (n,) ndarray
        Root-mean-square pressure in Pa over each point's window.
    exposure : (n,) ndarray
        Sound exposure ``∫ p² dt`` in Pa²·s over the window.
    window_start : (n,) ndarray
        Start of each point's window in s (its first arrival unless a grid was imposed).
    window : float
        Length of every point's window in s.
    sample_interval : float
        Time step in s used to sample the pressure.
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


def field_metrics(
    pulse,
    points,
    config: Configuration,
    *,
    medium: Medium = AIR,
    sample_interval=None,
    window=None,
    t=None,
    cutoff: float = DEFAULT_CUTOFF,
    memory_limit: float = DEFAULT_MEMORY_LIMIT,
    tolerance=None,
) -> FieldMetrics:
    """Peaks, RMS and sound exposure at each point, without storing the time series.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    points : (n, 3) array_like
        Observer positions in m; points outside the fluid get NaN.
    config : Configuration
        The sphere and its images.
    medium : Medium
        The fluid.
    sample_interval : float, optional
        Time step in s (default :func:`default_sample_interval`, 64 samples per
        ``min(T, a/c)``).
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
        cheapest model of :mod:`acoustiviz.approximations` whose proven error bound is below
        it (``model`` says which); otherwise the exact closed form serves all points.

    Returns
    -------
    FieldMetrics

    Notes
    -----
    Paper eqs 12-14; the SPL of paper Figure 3 is ``peak_spl_db``.
    """
    (kind, amp, tau, xi, acc, yk, s), tail = _prepare(pulse, config, medium, cutoff)
    pts = check_points("points", points)
    limit = check_positive("memory_limit", memory_limit, "B")
    n = pts.shape[0]
    nimg = len(config.sources)
    if t is not None:
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        dt = _uniform_step(tt)
        if dt is None:
            raise ParameterError("t", "field_metrics needs a uniform time grid (or none)")
        m = tt.size
        win = m * dt
    else:
        dt = (
            default_sample_interval(pulse, config.radius, medium=medium)
            if sample_interval is None
            else check_positive("sample_interval", sample_interval, "s")
        )
        if window is None:
            win = dt
            step = _chunk_size(_geometry_bytes(nimg) + 40, 8.0 * n * 5, limit)
            for lo in range(0, n, step):
                sub = pts[lo : lo + step]
                start, stop = arrival_windows(pulse, sub, config, medium=medium, cutoff=cutoff)
                ok = config.in_fluid(sub)
                if np.any(ok):
                    win = max(win, float(np.max((stop - start)[ok])))
        else:
            win = check_positive("window", window, "s")
        m = max(1, int(math.ceil(win / dt - 1e-9)))
        win = m * dt
    out_bytes = 8.0 * n * 5 + n  # four float results, the window starts and the model codes
    if out_bytes + 8 * m > limit:
        raise ParameterError("memory_limit", f"the results alone need {out_bytes:.4g} B > {limit:.4g} B")
    fixed = out_bytes + 8 * m + (limit / 2 if tolerance is not None else 0)  # half for cheap models
    chunk = _chunk_size(_geometry_bytes(nimg) + 8 * 4 + 16 * nimg, fixed, limit)
    pmax = np.empty(n)
    pmin = np.empty(n)
    ssq = np.empty(n)
    wstart = np.empty(n)
    models = np.zeros(n, dtype=np.uint8)
    buf = np.zeros(m)
    if tolerance is not None:
        from . import approximations as _approx

        tol = check_positive("tolerance", tolerance, "Pa")
    for lo in range(0, n, chunk):
        hi = min(lo + chunk, n)
        delay, p0, cre, cim, inside = _chunk_geometry(pts[lo:hi], config, medium)
        t0 = np.full(hi - lo, tt[0]) if t is not None else delay.min(axis=1)
        wstart[lo:hi] = t0
        res = np.empty((hi - lo, 3))
        exact = np.ones(hi - lo, dtype=bool)
        if tolerance is not None:
            choice = _approx.choose_models(pulse, delay, p0, cre + 1j * cim, tol, radius=config.radius, medium=medium)
            for code, name in enumerate(_approx.MODELS):
                sel = choice == code
                if name == "exact" or not np.any(sel):
                    continue
                exact &= ~sel
                res[sel] = _approx.window_metrics(
                    name, pulse, delay[sel], p0[sel], t0[sel], dt, m, radius=config.radius, medium=medium,
                    max_bytes=limit / 4,
                )  # fmt: skip
                models[lo:hi][sel] = code
        if np.all(exact):
            _metrics_kernel(res, buf, t0, dt, delay, p0, cre, cim, kind, amp, tau, xi, acc, yk, s, tail)
        elif np.any(exact):
            sub = np.empty((int(exact.sum()), 3))
            _metrics_kernel(
                sub, buf, np.ascontiguousarray(t0[exact]), dt, np.ascontiguousarray(delay[exact]),
                np.ascontiguousarray(p0[exact]), np.ascontiguousarray(cre[exact]),
                np.ascontiguousarray(cim[exact]), kind, amp, tau, xi, acc, yk, s, tail,
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


# --------------------------------------------------------------------------- snapshots
def snapshots(
    pulse,
    times,
    points,
    config: Configuration,
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
    config : Configuration
        The sphere and its images.
    medium : Medium
        The fluid.
    memory_limit : float
        Cap in bytes on the working memory and the returned array.

    Returns
    -------
    (k, n) ndarray
        Pressure in Pa, one row per snapshot time.
    """
    _check_pulse(pulse)
    _check_config(config)
    pts = check_points("points", points)
    tt = np.atleast_1d(np.asarray(times, dtype=float))
    if tt.ndim != 1 or not np.all(np.isfinite(tt)):
        raise ParameterError("times", "expected a finite 1-D array of times in s")
    limit = check_positive("memory_limit", memory_limit, "B")
    need = 8.0 * pts.shape[0] * tt.size
    per_point = _geometry_bytes(len(config.sources)) + 8 * 6
    chunk = _chunk_size(per_point, need, limit)
    out = np.empty((tt.size, pts.shape[0]))
    for lo in range(0, pts.shape[0], chunk):
        hi = min(lo + chunk, pts.shape[0])
        delay, p0, cre, cim, inside = _chunk_geometry(pts[lo:hi], config, medium)
        for q, tq in enumerate(tt):
            acc = np.zeros(hi - lo)
            for j in range(delay.shape[1]):
                y = pulse_response(pulse, tq - delay[:, j], radius=config.radius, medium=medium)
                acc += p0[:, j] * (cre[:, j] * y.real - cim[:, j] * y.imag)
            acc[inside] = np.nan
            out[q, lo:hi] = acc
    return out


# --------------------------------------------------------------------------- directivity
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


def circle_points(config: Configuration, distance: float, angles) -> np.ndarray:
    """Points on a circle of radius ``distance`` (m) around the sphere's centre.

    The circle lies in the plane spanned by the acceleration axis and the horizontal direction
    ``+x`` (for a wall strike, whose axis is ``+x``, the vertical ``+z``): for the wall-floor
    corner that is the plane through the centre normal to the wall, on the side away from it.

    Parameters
    ----------
    config : Configuration
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
    _check_config(config)
    r = check_positive("distance", distance, "m")
    if r <= config.radius:
        raise ParameterError("distance", f"must exceed the sphere radius {config.radius:g} m, got {r:g} m")
    return observer_points(config, r, angles)


def directivity(
    pulse,
    config: Configuration,
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
    config : Configuration
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
        circle (the neglected tail carries < 3e-9 of the energy).

    Returns
    -------
    Directivity

    Notes
    -----
    Paper eqs 12-14 and Figure 3; SPL is the peak level ``20 log10(max|p|/20 µPa)``.
    """
    _check_pulse(pulse)
    pts = circle_points(config, distance, angles)
    if not np.all(config.in_fluid(pts)):
        raise ParameterError("angles", "some observers on the circle lie outside the fluid")
    if window is None:
        delay, _, _, _ = source_geometry(pts, config, medium=medium)
        spread = float(np.max(delay.max(axis=1) - delay.min(axis=1)))
        window = pulse.duration + spread + 10.0 * config.radius / medium.c
    fm = field_metrics(pulse, pts, config, medium=medium, sample_interval=sample_interval, window=window)
    th = np.atleast_1d(np.asarray(angles, dtype=float))
    return Directivity(th, pts, float(distance), fm)
