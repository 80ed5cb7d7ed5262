"""Frequency- and time-weighted sound levels of pressure signals (IEC 61672-1).

Every function here is a pure function of a :class:`~acoustiviz.core.signal.Signal` (pressure in Pa,
its sample rate in Hz and the time of its first sample in s), so it serves a computed waveform, a
damper run at a listener, a WAV file read back with its calibration, one design of a sweep or one
point of a directivity alike. The A and C frequency weightings and the
F and S time weightings are the IEC 61672-1 filters of :mod:`._filters`; here is the level
arithmetic (peaks, energy averages over an interval, exposure).

Levels in dB re 20 µPa (``P_REF``); exposure levels in dB re (20 µPa)²·1 s:

* ``LZpeak``, ``LCpeak``: the largest |p| of the unweighted and the C-weighted signal;
* ``LAFmax``, ``LASmax``: the largest A-weighted, F (125 ms) or S (1 s) time-weighted level;
* ``LAeq,T``, ``LZeq,T``: the energy average over the interval ``T = stop - start`` (times on the
  signal's own axis, which starts at ``signal.start``);
* ``SEL`` (``LZE``) and ``SEL(A)`` (``LAE``): the exposure ``∫ p² dt`` over the interval re
  ``P_REF² × 1 s``, so ``SEL = Leq,T + 10 log10(T / 1 s)``.

The filters run over the whole signal from its first sample, so a filter's memory of what came
before ``start`` is kept; only the statistics are restricted to the interval.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_positive
from ..constants import LEVEL_METRICS, P_REF
from ..core.signal import Signal
from ._library import library

__all__ = ["LEVEL_COLUMNS", "METRICS", "SoundLevels", "as_channels", "check_signal", "weighted", "sound_levels",
           "level_db", "metric_levels"]

#: The level columns of :meth:`SoundLevels.rows`, in order.
LEVEL_COLUMNS = ("lzpeak_db", "lcpeak_db", "lafmax_db", "lasmax_db", "laeq_db", "lzeq_db", "sel_db", "sel_a_db")

#: Metric names as front-ends spell them (``--metric lcpeak``) -> the :class:`SoundLevels` field.
METRICS = LEVEL_METRICS

def level_db(mean_square, reference: float = P_REF) -> np.ndarray:
    """``10 log10(mean_square / reference²)`` in dB; ``-inf`` for silence.

    Parameters
    ----------
    mean_square : array_like
        Mean-square (or squared peak) pressure in Pa².
    reference : float
        Reference pressure in Pa (default 20 µPa).
    """
    ms = np.asarray(mean_square, dtype=float)
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(ms / reference**2)


def as_channels(pressure, name: str = "pressure") -> np.ndarray:
    """``pressure`` as a finite float ``(n_channels, n_samples)`` array in Pa (1-D becomes one channel)."""
    p = np.asarray(pressure, dtype=float)
    if p.ndim == 1:
        p = p[None, :]
    if p.ndim != 2 or p.shape[1] < 2:
        raise ParameterError(name, f"expected (n_samples,) or (n_channels, n_samples) Pa with >= 2 samples, "
                                   f"got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ParameterError(name, "pressure samples must be finite")
    return p


def check_signal(signal, name: str = "signal") -> Signal:
    """``signal`` unless it is not a :class:`~acoustiviz.core.signal.Signal` of at least two samples."""
    if not isinstance(signal, Signal):
        raise ParameterError(name, f"expected an acoustiviz.Signal (pressure in Pa with its sample rate in Hz), "
                                   f"got {type(signal).__name__}")
    if signal.n_samples < 2:
        raise ParameterError(name, f"expected at least two samples, got {signal.n_samples}")
    return signal


def weighted(signal: Signal, curve: str) -> Signal:
    """The A-, C- or Z-weighted signal (IEC 61672-1).

    Parameters
    ----------
    signal : Signal
        Sound pressure in Pa at a whole number of Hz.
    curve : {"A", "C", "Z"}
        The frequency weighting.

    Returns
    -------
    Signal
        The weighted pressure in Pa, same shape, rate and start as ``signal``.

    Examples
    --------
    >>> fs = 48000
    >>> tone = Signal(np.sin(2 * np.pi * 100 * np.arange(fs) / fs), fs)
    >>> a = weighted(tone, "A")  # A(100 Hz) = -19.1 dB
    >>> round(float(level_db(np.mean(a.pressure[fs // 2:] ** 2) / np.mean(tone.pressure[fs // 2:] ** 2), 1.0)), 1)
    -19.1
    """
    if curve not in ("A", "C", "Z"):
        raise ParameterError("curve", f"must be one of 'A', 'C', 'Z', got {curve!r}")
    return Signal(_weighted(signal.pressure, signal.sample_rate, curve), signal.sample_rate, start=signal.start)


def _weighted(p: np.ndarray, sample_rate, curve: str) -> np.ndarray:
    """``p`` (Pa, samples on the last axis) weighted by ``curve`` at ``sample_rate`` Hz, as a new array."""
    fs = _integer_rate(sample_rate)
    if curve == "Z":
        return np.array(p, dtype=float)
    return np.asarray(library().weighting_filter(p, fs, curve))


def _integer_rate(sample_rate) -> int:
    fs = check_positive("sample_rate", sample_rate, "Hz")
    if fs != int(fs):
        raise ParameterError("sample_rate", f"must be a whole number of Hz, got {sample_rate!r}")
    return int(fs)


def _time_weighted_max(x: np.ndarray, fs: int, mode: str, window: slice) -> np.ndarray:
    """Largest F- or S-time-weighted mean square (Pa²) within ``window``, per channel."""
    env = np.asarray(library().time_weighting(x, fs, mode=mode))
    return np.max(env[:, window], axis=1)


@dataclass(frozen=True)
class SoundLevels:
    """Weighted levels of one or more channels over one interval.

    Attributes
    ----------
    lzpeak_db, lcpeak_db : (n_channels,) ndarray
        Z- and C-weighted peak sound pressure levels in dB re 20 µPa.
    lafmax_db, lasmax_db : (n_channels,) ndarray
        Largest A-weighted F- and S-time-weighted levels in dB re 20 µPa.
    laeq_db, lzeq_db : (n_channels,) ndarray
        A- and Z-weighted equivalent continuous levels over the interval in dB re 20 µPa.
    sel_db, sel_a_db : (n_channels,) ndarray
        Z- and A-weighted sound exposure levels over the interval in dB re (20 µPa)²·s.
    sample_rate : float
        Rate in Hz of the signal the levels were computed from.
    start, stop : float
        The interval in s.
    library : str
        The filters that computed the levels.
    """

    lzpeak_db: np.ndarray
    lcpeak_db: np.ndarray
    lafmax_db: np.ndarray
    lasmax_db: np.ndarray
    laeq_db: np.ndarray
    lzeq_db: np.ndarray
    sel_db: np.ndarray
    sel_a_db: np.ndarray
    sample_rate: float
    start: float
    stop: float
    library: str

    @property
    def interval(self) -> float:
        """Length of the interval in s."""
        return self.stop - self.start

    def rows(self, channels=None) -> list:
        """One dict per channel: ``channel`` then :data:`LEVEL_COLUMNS` (dB), ready for a CSV."""
        n = self.lzpeak_db.size
        names = list(channels) if channels is not None else [str(i + 1) for i in range(n)]
        return [{"channel": names[i], **{c: float(getattr(self, c)[i]) for c in LEVEL_COLUMNS}} for i in range(n)]

    def describe(self) -> dict:
        """How the levels were computed (JSON-ready)."""
        return {"sample_rate_hz": self.sample_rate, "interval_s": [self.start, self.stop], "library": self.library,
                "weighting": "IEC 61672-1 A/C/Z frequency weighting, F (125 ms) / S (1 s) time weighting",
                "reference": "dB re 20 uPa; exposure levels re (20 uPa)^2 s"}


def sound_levels(signal: Signal, *, start=None, stop=None) -> SoundLevels:
    """LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL and SEL(A) of pressure signals.

    Parameters
    ----------
    signal : Signal
        Sound pressure in Pa, one or more channels of at least two samples, at a whole number of
        Hz. The weightings are accurate to IEC 61672-1 class 1 up to 16 kHz at 48 kHz and above
        (the weighting oversamples internally below 96 kHz).
    start, stop : float, optional
        The interval in s on the signal's time axis (default: the whole signal). Peaks and maxima
        are taken within it, equivalent levels average over it and exposure levels integrate over it.

    Returns
    -------
    SoundLevels
        One value per channel of each level.

    Notes
    -----
    ``Leq,T = 10 log10((1/T) ∫_T p_w² dt / p_ref²)`` and ``SEL = 10 log10(∫_T p_w² dt / (p_ref² · 1 s))``
    (IEC 61672-1:2013, 3.8-3.9); ``LXFmax`` is the largest value of the exponentially averaged
    square with time constant 125 ms (F) or 1 s (S) started from rest at the first sample.

    Examples
    --------
    >>> fs = 48000
    >>> t = np.arange(fs) / fs
    >>> lv = sound_levels(Signal(np.sqrt(2) * np.sin(2 * np.pi * 1000 * t), fs))
    >>> round(float(lv.laeq_db[0]), 1), round(float(lv.lzpeak_db[0] - lv.lzeq_db[0]), 2)
    (94.0, 3.01)
    """
    p = check_signal(signal).as_channels()
    fs = _integer_rate(signal.sample_rate)
    win = signal.interval(start, stop)
    pa, pc = _weighted(p, fs, "A"), _weighted(p, fs, "C")
    n = win.stop - win.start

    def peak(x):
        return level_db(np.max(np.abs(x[:, win]), axis=1) ** 2)

    def exposure(x):  # ∫ p² dt over the interval, Pa² s
        return np.sum(x[:, win] ** 2, axis=1) / fs

    ez, ea = exposure(p), exposure(pa)
    t = n / fs
    return SoundLevels(
        lzpeak_db=peak(p), lcpeak_db=peak(pc),
        lafmax_db=level_db(_time_weighted_max(pa, fs, "fast", win)),
        lasmax_db=level_db(_time_weighted_max(pa, fs, "slow", win)),
        laeq_db=level_db(ea / t), lzeq_db=level_db(ez / t),
        sel_db=level_db(ez), sel_a_db=level_db(ea),
        sample_rate=float(fs), start=signal.start + win.start / fs, stop=signal.start + win.stop / fs,
        library=library().name,
    )


def metric_levels(signal: Signal, metric: str, *, start=None, stop=None) -> np.ndarray:
    """One level per channel of ``signal`` (a design, a listener, a point of a directivity grid).

    Parameters
    ----------
    signal : Signal
        Sound pressure in Pa, one channel per row, at a whole number of Hz.
    metric : str
        A key of :data:`METRICS`: ``"lzpeak"``, ``"lcpeak"``, ``"lafmax"``, ``"lasmax"``, ``"laeq"``,
        ``"lzeq"``, ``"sel"`` or ``"sel-a"``.
    start, stop : float, optional
        Interval in s (see :func:`sound_levels`).

    Returns
    -------
    (n_rows,) ndarray
        The level in dB re 20 µPa (exposure levels re (20 µPa)²·s).
    """
    if metric not in METRICS:
        raise ParameterError("metric", f"must be one of {', '.join(METRICS)}, got {metric!r}")
    return getattr(sound_levels(signal, start=start, stop=stop), METRICS[metric])
