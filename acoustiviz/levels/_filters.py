"""IEC 61672-1 frequency and time weightings and IEC 61260-1 fractional-octave bands, from the standards' formulas.

Three things, each written from the text of its standard with SciPy's filter design and
filtering (so they work with any NumPy >= 2.2 / SciPy >= 1.15):

* :func:`weighting_filter` -- the A or C frequency weighting (IEC 61672-1:2013, Annex E): the
  analogue transfer function with the poles of Formulas (E.1)-(E.6), mapped to the z-plane by the
  bilinear transform at a rate of at least 96 kHz (the signal is oversampled by a whole factor of
  at most 8 and brought back), normalised to 0 dB at 1 kHz;
* :func:`time_weighting` -- the exponentially averaged square with time constant 125 ms (F),
  1 s (S), or 35 ms rising / 1.5 s falling (I) (IEC 61672-1:2013, 3.7-3.8; I, whose recursion
  depends on its own output, runs as a loop compiled by numba);
* :class:`OctaveFilterBank` -- base-10 fractional-octave Butterworth band-pass filters
  (IEC 61260-1:2014, 5.2-5.6), each band designed and run at the input rate decimated by a whole
  factor that keeps the band's upper edge below 1/1.25 of the decimated Nyquist frequency.

The weighting's digital response differs from the analogue one only by the bilinear transform's
frequency warping, ``f_a = (f_d / π) tan(π f / f_d)`` at the design rate ``f_d``: at
``f_d = 96 kHz`` 1.4 % at 10 kHz and 10 % at 16 kHz, inside the class 1 acceptance limits of
IEC 61672-1 Table 3 (checked in ``tests/test_levels_filters.py`` against the closed forms).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..constants import P_REF

__all__ = ["NAME", "weighting_poles_hz", "weighting_zpk", "WeightingFilter", "weighting_filter", "time_weighting",
           "TIME_CONSTANTS", "band_frequencies", "nominal_frequency", "OctaveFilterBank", "sosfilt_normal"]

#: How :func:`._library.backend` names these filters.
NAME = "acoustiviz IEC 61672-1/61260-1 filters"

#: Time constants in s of the F, S and I time weightings: ``(rising, falling)``.
TIME_CONSTANTS = {"fast": (0.125, 0.125), "slow": (1.0, 1.0), "impulse": (0.035, 1.5)}

#: Lowest rate in Hz at which the weighting filters are designed and run (the input is oversampled
#: by a whole factor, at most :data:`MAX_OVERSAMPLING`, to reach it).
DESIGN_RATE = 96000
MAX_OVERSAMPLING = 8

_G = 10.0 ** 0.3  # IEC 61260-1 octave frequency ratio, base 10 (5.2)
_HEADROOM = 1.25  # decimated Nyquist / band upper edge
_MAX_DECIMATION = 500


def weighting_poles_hz() -> tuple[float, float, float, float]:
    """The pole frequencies ``f1, f2, f3, f4`` in Hz of the A and C weightings (IEC 61672-1:2013 Annex E).

    From ``f_r = 1 kHz``, ``f_L = 10^1.5 Hz``, ``f_H = 10^3.9 Hz``, ``D² = 1/2`` and ``f_A = 10^2.45 Hz``:
    ``f1,4² = (-b ∓ sqrt(b² - 4c)) / 2`` with ``c = f_L² f_H²`` and
    ``b = (f_r² + f_L² f_H² / f_r² - D (f_L² + f_H²)) / (1 - D)`` (E.1-E.4), and
    ``f2,3 = (3 ∓ sqrt 5) / 2 · f_A`` (E.5-E.6): about 20.6, 107.7, 737.9 and 12194 Hz.
    """
    fr, fl, fh, d = 1000.0, 10.0**1.5, 10.0**3.9, math.sqrt(0.5)
    c = fl**2 * fh**2
    b = (fr**2 + fl**2 * fh**2 / fr**2 - d * (fl**2 + fh**2)) / (1.0 - d)
    root = math.sqrt(b * b - 4.0 * c)
    f1, f4 = math.sqrt((-b - root) / 2.0), math.sqrt((-b + root) / 2.0)
    fa = 10.0**2.45
    return f1, (3.0 - math.sqrt(5.0)) / 2.0 * fa, (3.0 + math.sqrt(5.0)) / 2.0 * fa, f4


def weighting_zpk(curve: str):
    """Zeros and poles in rad/s and the gain of the analogue A or C weighting, 0 dB at 1 kHz.

    ``C(s) = k s² / ((s + ω1)² (s + ω4)²)`` and ``A(s) = k s⁴ / ((s + ω1)² (s + ω2)(s + ω3)(s + ω4)²)``
    with ``ωi = 2π fi`` (:func:`weighting_poles_hz`); ``k`` sets ``|H(2π·1000 j)| = 1``.
    """
    f1, f2, f3, f4 = weighting_poles_hz()
    w = [2.0 * math.pi * f for f in (f1, f2, f3, f4)]
    if curve == "A":
        z, p = np.zeros(4), -np.array([w[0], w[0], w[1], w[2], w[3], w[3]])
    elif curve == "C":
        z, p = np.zeros(2), -np.array([w[0], w[0], w[3], w[3]])
    else:
        raise ValueError(f"curve: must be 'A' or 'C', got {curve!r}")
    s = 2j * math.pi * 1000.0
    k = 1.0 / abs(np.prod(s - z) / np.prod(s - p))
    return z, p, k


#: Amplitude, relative to the signal's largest |x|, of the tone at a quarter of the sample rate that
#: :func:`sosfilt_normal` adds to a filter's input (the result moves by about this fraction of the
#: signal's peak: 1e-150, far below any level or round-off).
FLOOR_TONE = 1e-150
#: Smallest absolute amplitude of that tone: a normal double with room to spare above 2.2e-308.
_FLOOR_MIN = 1e-290


def sosfilt_normal(sos, x) -> np.ndarray:
    """``scipy.signal.sosfilt(sos, x)`` along the last axis, with the sections' states kept normal numbers.

    After a click the states of a recursive filter decay geometrically; in a long silence they reach
    the subnormal range (below 2.2e-308), where each multiplication costs 20-100 times more on
    x86 processors. A rendered impact sequence is mostly silence, so filtering 20 s at 96 kHz took
    0.6 s instead of 0.03 s. Adding a tone ``d (1, 1, -1, -1, ...)`` at a quarter of the sample rate
    (passed by every weighting and band section, neither at 0 Hz nor at Nyquist) with
    ``d = FLOOR_TONE max|x|`` keeps every state near ``d`` at least, well inside the normal range.
    The filter is linear, so the output differs from the exact one by that tone's response: below
    ``1e-149`` of the signal's peak. An all-zero input is filtered as it is (its output is zero).

    Parameters
    ----------
    sos : (n_sections, 6) array_like
        Second-order sections as :func:`scipy.signal.sosfilt` takes them.
    x : array_like
        Signal, time on the last axis (any unit: the filter is linear).

    Returns
    -------
    ndarray
        The filtered signal, shaped like ``x``, from rest at the first sample.
    """
    from scipy.signal import sosfilt

    x = np.asarray(x, dtype=float)
    peak = max(float(np.max(x)), -float(np.min(x))) if x.size else 0.0
    if not peak > 0.0 or not math.isfinite(peak):
        return sosfilt(sos, x, axis=-1)
    d = max(FLOOR_TONE * peak, _FLOOR_MIN)
    n = x.shape[-1]
    tone = np.tile(np.array([d, d, -d, -d]), -(-n // 4))[:n]
    return sosfilt(sos, x + tone, axis=-1)


def _oversampling(fs: float) -> int:
    return int(min(MAX_OVERSAMPLING, max(1, math.ceil(DESIGN_RATE / fs))))


@functools.lru_cache(maxsize=32)
def _weighting_sos(fs: float, curve: str) -> np.ndarray:
    from scipy.signal import bilinear_zpk, sosfreqz, zpk2sos

    design_rate = fs * _oversampling(fs)
    zd, pd, kd = bilinear_zpk(*weighting_zpk(curve), design_rate)
    sos = zpk2sos(zd, pd, kd)
    _, h = sosfreqz(sos, worN=[1000.0], fs=design_rate)  # the warping moves 1 kHz by < 0.01 dB; restore 0 dB
    sos[0, :3] /= abs(h[0])
    return sos


class WeightingFilter:
    """The A or C weighting at one sample rate.

    Parameters
    ----------
    fs : float
        Sample rate of the signals to weight in Hz.
    curve : {"A", "C"}
        The frequency weighting.

    Attributes
    ----------
    sos : (n_sections, 6) ndarray
        Second-order sections at ``fs * oversample`` Hz.
    oversample : int
        Whole factor by which the signal is oversampled before the sections (1 at 96 kHz and above).
    """

    def __init__(self, fs: float, curve: str = "A"):
        if not fs > 0:
            raise ValueError(f"fs: must be a sample rate > 0 Hz, got {fs!r}")
        self.fs = float(fs)
        self.curve = curve
        self.oversample = _oversampling(self.fs)
        self.sos = _weighting_sos(self.fs, curve).copy()  # the cached sections stay as designed

    def filter(self, x) -> np.ndarray:
        """The weighted signal, shaped like ``x`` (time on the last axis), from rest at the first sample."""
        from scipy.signal import resample_poly

        x = np.asarray(x, dtype=float)
        if self.oversample == 1:
            return sosfilt_normal(self.sos, x)
        if x.shape[-1] == 0:
            return x.copy()
        up = resample_poly(x, self.oversample, 1, axis=-1)
        return resample_poly(sosfilt_normal(self.sos, up), 1, self.oversample, axis=-1)


def weighting_filter(x, fs: float, curve: str = "A") -> np.ndarray:
    """The A-, C- or Z-weighted signal (IEC 61672-1:2013, 5.5 and Annex E).

    Parameters
    ----------
    x : array_like
        Signal, time on the last axis (any unit: the weighting is linear).
    fs : float
        Sample rate in Hz.
    curve : {"A", "C", "Z"}
        The frequency weighting (Z: the signal unchanged).

    Returns
    -------
    ndarray
        The weighted signal, shaped like ``x``.
    """
    if curve == "Z":
        return np.array(x, dtype=float)
    return WeightingFilter(fs, curve).filter(x)


@functools.lru_cache(maxsize=1)
def _impulse_kernel():
    """The I time weighting's recursion over rows of squares, compiled on first use."""
    from .._jit import njit

    @njit(cache=False)  # a closure: numba cannot cache it on disk
    def run(x2, a_rise, a_fall):  # pragma: no cover - compiled
        out = np.empty_like(x2)
        for i in range(x2.shape[0]):
            v = 0.0
            for n in range(x2.shape[1]):
                step = x2[i, n] - v
                v += (a_rise if step > 0.0 else a_fall) * step
                out[i, n] = v
        return out

    return run


def _impulse(x2: np.ndarray, a_rise: float, a_fall: float) -> np.ndarray:
    rows = np.ascontiguousarray(x2.reshape(-1, x2.shape[-1]) if x2.ndim else x2.reshape(1, 1))
    return _impulse_kernel()(rows, a_rise, a_fall).reshape(x2.shape)


def time_weighting(x, fs: float, mode: str = "fast") -> np.ndarray:
    """The exponentially time-weighted square of a signal (IEC 61672-1:2013, 3.7-3.8).

    ``v[n] = (1 - α) v[n-1] + α x[n]²`` from ``v[-1] = 0``, with ``α = 1 - exp(-1 / (fs τ))``: the
    exact sampled response of ``τ dv/dt + v = x²`` to a square held over each sample, so a step of
    ``x²`` rises as ``1 - exp(-t/τ)`` and a silence after it decays by ``10 lg(e) / τ`` dB/s
    (34.7 dB/s for F). ``τ`` is 125 ms (``"fast"``), 1 s (``"slow"``), or for ``"impulse"`` 35 ms
    while ``x²`` exceeds ``v`` and 1.5 s while it does not.

    Parameters
    ----------
    x : array_like
        Signal, time on the last axis (in Pa for a level in Pa²).
    fs : float
        Sample rate in Hz.
    mode : {"fast", "slow", "impulse"}
        The time weighting.

    Returns
    -------
    ndarray
        The time-weighted mean square, shaped like ``x``.
    """
    from scipy.signal import lfilter

    if mode not in TIME_CONSTANTS:
        raise ValueError(f"mode: must be one of {', '.join(TIME_CONSTANTS)}, got {mode!r}")
    if not fs > 0:
        raise ValueError(f"fs: must be a sample rate > 0 Hz, got {fs!r}")
    x2 = np.square(np.asarray(x, dtype=float))
    rise, fall = (-math.expm1(-1.0 / (fs * tau)) for tau in TIME_CONSTANTS[mode])
    if mode != "impulse":
        return lfilter([rise], [1.0, rise - 1.0], x2, axis=-1)
    return _impulse(x2, rise, fall)


def band_frequencies(fraction: int, limits) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact mid-band, lower and upper edge frequencies in Hz of the bands from ``limits[0]`` to ``limits[1]``.

    IEC 61260-1:2014 base-10 bands of bandwidth designator ``1/b``: mid-band frequencies
    ``f_m = 1000 G^(x/b)`` (odd ``b``, Formula 3) or ``1000 G^((2x+1)/(2b))`` (even ``b``, Formula 4) Hz
    with ``G = 10^(3/10)``, and edges ``f_m G^(∓1/(2b))`` (Formulas 5-6). The bands are those from the one
    that holds ``limits[0]`` to the one that holds ``limits[1]``.
    """
    b = int(fraction)
    if b != fraction or b < 1:
        raise ValueError(f"fraction: must be a whole number >= 1 (1 octave, 3 one-third octave), got {fraction!r}")
    lo, hi = (float(v) for v in limits)
    if not 0 < lo <= hi:
        raise ValueError(f"limits: must be two non-decreasing frequencies > 0 Hz, got {limits!r}")
    shift = 0.0 if b % 2 else 0.5

    def index(f):  # the band x whose edges hold f
        return int(math.floor(b * math.log(f / 1000.0) / math.log(_G) - shift + 0.5))

    x = np.arange(index(lo), index(hi) + 1)
    mid = 1000.0 * _G ** ((x + shift) / b)
    edge = _G ** (1.0 / (2 * b))
    return mid, mid / edge, mid * edge


_R10 = (1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0)


def nominal_frequency(mid_hz: float, fraction: int) -> float:
    """Nominal mid-band frequency in Hz (IEC 61260-1:2014 Annex E).

    Octave and one-third-octave bands: the R10 preferred number (1, 1.25, 1.6, 2, 2.5, 3.15, 4, 5,
    6.3, 8 × 10^k) nearest the exact frequency (E.1-E.2); other fractions: the exact frequency to
    three significant figures when its first digit is 1 to 4, two when it is 5 to 9 (E.3).
    """
    f = float(mid_hz)
    if int(fraction) in (1, 3):
        n = int(round(10.0 * math.log10(f)))  # 10^(n/10) within 1 % of the R10 number n
        return _R10[n % 10] * 10.0 ** (n // 10)
    exponent = math.floor(math.log10(f))
    step = 10.0 ** (exponent - (2 if f / 10.0**exponent < 5 else 1))
    return round(f / step) * step


class OctaveFilterBank:
    """A bank of IEC 61260-1:2014 fractional-octave Butterworth band-pass filters.

    Parameters
    ----------
    fs : float
        Sample rate in Hz.
    fraction : int
        Bands per octave ``b`` (1 octave, 3 one-third octave).
    order : int
        Order of the Butterworth low-pass prototype; each band-pass filter has ``2 × order`` poles.
    limits : (float, float)
        Frequencies in Hz held by the lowest and highest band (default 12 Hz to 20 kHz). Bands whose
        upper edge exceeds ``fs / 2`` are left out.

    Attributes
    ----------
    freq, freq_d, freq_u : (n_bands,) ndarray
        Exact mid-band, lower and upper edge frequencies in Hz.
    nominal_freq : list of float
        Nominal mid-band frequencies in Hz (:func:`nominal_frequency`).
    factor : (n_bands,) ndarray of int
        Decimation factor of each band: the largest whole ``q <= 500`` with
        ``fs / (2q) >= 1.25 × freq_u`` (1 where there is none).
    sos : list of (order, 6) ndarray
        Each band's second-order sections at ``fs / factor`` Hz.

    Notes
    -----
    A band's signal is ``scipy.signal.resample_poly(x, 1, q)`` (a polyphase FIR low-pass ahead of
    the decimation) filtered by its sections from rest; the relative attenuation of each band meets
    the class 1 acceptance limits of IEC 61260-1:2014 Table 1 (``tests/test_levels_filters.py``).
    """

    def __init__(self, fs: float, fraction: int = 1, order: int = 6, limits=None):
        from scipy.signal import butter

        if not fs > 0:
            raise ValueError(f"fs: must be a sample rate > 0 Hz, got {fs!r}")
        if int(order) != order or order < 1:
            raise ValueError(f"order: must be a whole number >= 1, got {order!r}")
        self.fs, self.fraction, self.order = float(fs), int(fraction), int(order)
        self.limits = [12.0, 20000.0] if limits is None else [float(v) for v in limits]
        mid, lower, upper = band_frequencies(self.fraction, self.limits)
        keep = upper <= self.fs / 2.0
        self.freq, self.freq_d, self.freq_u = mid[keep], lower[keep], upper[keep]
        self.nominal_freq = [nominal_frequency(f, self.fraction) for f in self.freq]
        self.factor = np.clip(np.floor(self.fs / (2.0 * _HEADROOM * self.freq_u)), 1, _MAX_DECIMATION).astype(int)
        self.sos = [butter(self.order, [lo, hi], btype="bandpass", output="sos", fs=self.fs / q)
                    for lo, hi, q in zip(self.freq_d, self.freq_u, self.factor, strict=True)]

    def band_signal(self, x, k: int) -> np.ndarray:
        """Band ``k`` of ``x`` (time on the last axis) at ``fs / factor[k]`` Hz, filtered from rest."""
        from scipy.signal import resample_poly

        q = int(self.factor[k])
        xd = resample_poly(x, 1, q, axis=-1) if q > 1 else np.asarray(x, dtype=float)
        return sosfilt_normal(self.sos[k], xd)

    def filter(self, x, detrend: bool = True):
        """Band levels of a pressure signal over its whole length.

        Parameters
        ----------
        x : (n_samples,) or (n_channels, n_samples) array_like
            Sound pressure in Pa.
        detrend : bool
            Remove each channel's mean first.

        Returns
        -------
        levels : (n_bands,) or (n_channels, n_bands) ndarray
            ``10 lg(mean(y²) / (20 µPa)²)`` of each band's signal ``y`` in dB re 20 µPa.
        freq : list of float
            Exact mid-band frequencies in Hz.
        """
        x = np.asarray(x, dtype=float)
        if detrend:
            x = x - np.mean(x, axis=-1, keepdims=True)
        levels = np.stack([10.0 * np.log10(np.maximum(np.mean(self.band_signal(x, k) ** 2, axis=-1), 1e-300)
                                           / P_REF**2) for k in range(len(self.freq))], axis=-1)
        return levels, [float(f) for f in self.freq]
