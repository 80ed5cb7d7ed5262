"""One-third-octave band levels of pressure signals (IEC 61260-1 filters).

The bank (:mod:`._filters`) is order-6 Butterworth band-pass filters, class 1 to IEC 61260-1:2014,
each band run at a rate decimated for its centre frequency (multirate). Here
each band's filtered signal is reduced to two numbers over the interval: its equivalent level
``Leq,T`` and its largest F-time-weighted (125 ms) level ``LFmax``. The default bands run from
25 Hz to 20 kHz nominal (28 bands); the top band needs a sample rate of at least 44.8 kHz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError
from ..constants import P_REF
from ..core.signal import Signal
from ._filters import sosfilt_normal
from ._library import library
from .weighted import _integer_rate, check_signal, level_db

__all__ = ["BAND_LIMITS", "BandLevels", "third_octave_levels", "band_energy_sum", "decimate"]

#: Nominal centre frequencies in Hz of the lowest and highest 1/3-octave band reported by default.
BAND_LIMITS = (25.0, 20000.0)

_ORDER = 6


@dataclass(frozen=True)
class BandLevels:
    """One-third-octave band levels of one or more channels over one interval.

    Attributes
    ----------
    centre_hz : (n_bands,) ndarray
        Exact (base-10) mid-band frequencies in Hz.
    nominal_hz : (n_bands,) ndarray
        Nominal mid-band frequencies in Hz (IEC 61260-1 Annex E: 25, 31.5, ..., 20000).
    leq_db : (n_channels, n_bands) ndarray
        Band equivalent levels over the interval in dB re 20 µPa.
    lmax_db : (n_channels, n_bands) ndarray
        Largest F-time-weighted (125 ms) band level within the interval in dB re 20 µPa.
    sample_rate : float
        Rate in Hz of the analysed signal.
    start, stop : float
        The interval in s.
    library : str
        The filters that computed the levels.
    """

    centre_hz: np.ndarray
    nominal_hz: np.ndarray
    leq_db: np.ndarray
    lmax_db: np.ndarray
    sample_rate: float
    start: float
    stop: float
    library: str

    def rows(self, channels=None) -> list:
        """One dict per channel and band: ``channel, band_hz, leq_db, lmax_db`` (band_hz nominal)."""
        n = self.leq_db.shape[0]
        names = list(channels) if channels is not None else [str(i + 1) for i in range(n)]
        return [{"channel": names[i], "band_hz": float(f), "leq_db": float(self.leq_db[i, k]),
                 "lmax_db": float(self.lmax_db[i, k])}
                for i in range(n) for k, f in enumerate(self.nominal_hz)]

    def total_leq_db(self) -> np.ndarray:
        """Energy sum of the band ``Leq`` per channel in dB re 20 µPa (see :func:`band_energy_sum`)."""
        return band_energy_sum(self.leq_db)


def band_energy_sum(levels_db) -> np.ndarray:
    """``10 log10(Σ 10^(L/10))`` over the last axis, in dB: the level of the summed band energies."""
    lv = np.asarray(levels_db, dtype=float)
    return 10.0 * np.log10(np.sum(10.0 ** (lv / 10.0), axis=-1))


#: Largest fraction of samples that hold sound for which :func:`decimate` works on the sound alone.
SPARSE_ABOVE = 0.25


def decimate(p, q: int, offset=0.0) -> np.ndarray:
    """``scipy.signal.resample_poly(p - offset, 1, q, axis=-1)``, working on the samples that hold sound.

    The decimation's low-pass filter is a zero-phase FIR of ``2 L + 1`` taps (``L = 10 q``):
    output ``m`` is ``Σ_k h[m q - k] x[k]`` over ``|m q - k| <= L``, with zeros outside the signal.
    A damper run is a few hundred clicks in 20 s of silence, so output ``m`` is zero wherever no
    nonzero input lies within ``L`` samples of ``m q``. The runs of nonzero samples (closer than
    ``2 (L + q)`` merged), each with ``L + q`` samples of silence either side on the grid of ``q``,
    are decimated at once, laid end to end, and put back in place: each output is the same sum
    of the same products. The constant ``offset`` (each channel's mean, which the bands remove) is
    decimated as a signal of ones: its taps' sum ``Σ h`` in the middle, and at both ends the
    values of a short signal of ones of the same length modulo ``q``. Where more than
    :data:`SPARSE_ABOVE` of the samples hold sound, ``resample_poly`` runs on the whole signal.

    Parameters
    ----------
    p : (n_channels, n_samples) ndarray
        The signal (any unit).
    q : int
        Decimation factor (>= 1).
    offset : float or (n_channels, 1) array_like
        Subtracted from every sample, in the unit of ``p``.

    Returns
    -------
    (n_channels, ceil(n_samples / q)) ndarray
    """
    from scipy.signal import resample_poly

    p = np.asarray(p, dtype=float)
    offset = np.broadcast_to(np.asarray(offset, dtype=float), (p.shape[0], 1))
    n = p.shape[1]
    if q == 1:
        return p - offset
    reach = 10 * q + q  # resample_poly's half length 10 q, and a step of the output grid
    nz = np.flatnonzero(np.any(p != 0.0, axis=0))
    if nz.size > SPARSE_ABOVE * n or n < 8 * reach:
        return resample_poly(p - offset, 1, q, axis=-1)
    out = np.zeros((p.shape[0], -(-n // q)))
    if nz.size:
        cut = np.flatnonzero(np.diff(nz) > 2 * reach + 2 * q)
        first, last = nz[np.r_[0, cut + 1]], nz[np.r_[cut, nz.size - 1]]
        a = np.maximum((first - reach) // q * q, 0)
        b = np.minimum(-(-(last + 1 + reach) // q) * q, n)
        y = resample_poly(np.concatenate([p[:, i:j] for i, j in zip(a.tolist(), b.tolist(), strict=True)], axis=1),
                          1, q, axis=-1)
        at = 0
        for i, j in zip(a.tolist(), b.tolist(), strict=True):
            m = -(-(j - i) // q)
            out[:, i // q:i // q + m] = y[:, at:at + m]
            at += m
    if np.any(offset != 0.0):
        short = n % q + q * (-(-4 * reach // q))  # as long as n modulo q, its two ends apart
        ones = resample_poly(np.ones(short), 1, q)
        edge = 2 * reach // q + 2
        r = np.full(out.shape[1], ones[ones.size // 2])
        r[:edge], r[-edge:] = ones[:edge], ones[-edge:]
        out -= offset * r[None, :]
    return out


def _nominal(label: str) -> float:
    text = str(label).strip().lower().replace("hz", "").strip()
    scale = 1000.0 if text.endswith("k") else 1.0
    return float(text.rstrip("k")) * scale


def third_octave_levels(signal: Signal, *, start=None, stop=None, limits=BAND_LIMITS) -> BandLevels:
    """Leq and LFmax per 1/3-octave band of pressure signals.

    Parameters
    ----------
    signal : Signal
        Sound pressure in Pa, one or more channels, at a whole number of Hz above 2 × the top
        band's upper edge (22.4 kHz for 20 kHz).
    start, stop : float, optional
        Interval in s on the signal's time axis (default: the whole signal).
    limits : (float, float)
        Lowest and highest nominal mid-band frequency in Hz.

    Returns
    -------
    BandLevels

    Notes
    -----
    Each band's signal is the input decimated by the bank's factor for that band and filtered by
    its second-order sections (the bank's multirate scheme); its ``Leq,T`` averages the
    square over the interval and its ``LFmax`` is the largest exponential average with time
    constant 125 ms (IEC 61672-1), both at the band's decimated rate. For a stationary signal
    the band energies add up to the energy of the band-limited signal (:func:`band_energy_sum`)
    within the overlap of neighbouring bands' skirts (a few tenths of a dB for a white signal).

    Examples
    --------
    >>> fs = 48000
    >>> t = np.arange(fs) / fs
    >>> bl = third_octave_levels(Signal(np.sqrt(2) * np.sin(2 * np.pi * 1000 * t), fs))
    >>> k = list(bl.nominal_hz).index(1000.0)
    >>> round(float(bl.leq_db[0, k]), 1)
    94.0
    """
    p = check_signal(signal).as_channels()
    fs = _integer_rate(signal.sample_rate)
    lo, hi = (float(v) for v in limits)
    if not (0 < lo < hi):
        raise ParameterError("limits", f"must be two increasing frequencies > 0 Hz, got {limits!r}")
    top_edge = hi * 2 ** (1 / 6)
    if fs <= 2 * top_edge:
        raise ParameterError("sample_rate", f"must exceed {2 * top_edge:.0f} Hz for bands up to {hi:g} Hz, "
                                            f"got {fs} Hz")
    win = signal.interval(start, stop)
    lib = library()
    bank = lib.OctaveFilterBank(fs, fraction=3, order=_ORDER, limits=[lo, hi])

    mean = np.mean(p[:, win], axis=1, keepdims=True)  # the bank's own default removes the mean too
    n_bands = len(bank.freq)
    leq = np.empty((p.shape[0], n_bands))
    lmax = np.empty_like(leq)
    decimated = {}
    for k in range(n_bands):
        q = int(bank.factor[k])
        if q not in decimated:
            decimated[q] = decimate(p, q, mean)
        y = sosfilt_normal(bank.sos[k], decimated[q])  # decimated by q, filtered from rest
        i0 = win.start // q
        i1 = max(min(-(-win.stop // q), y.shape[1]), i0 + 1)
        leq[:, k] = level_db(np.mean(y[:, i0:i1] ** 2, axis=1), P_REF)
        env = np.asarray(lib.time_weighting(y, fs // q if fs % q == 0 else fs / q, mode="fast"))
        lmax[:, k] = level_db(np.max(env[:, i0:i1], axis=1), P_REF)
    return BandLevels(np.asarray(bank.freq, dtype=float), np.array([_nominal(s) for s in bank.nominal_freq]),
                      leq, lmax, float(fs), signal.start + win.start / fs, signal.start + win.stop / fs, lib.name)
