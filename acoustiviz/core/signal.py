"""A calibrated pressure signal: samples in Pa, their sample rate and the time of the first sample.

One value carries what the levels, the WAV files and the audio plots all need, so that none of them
takes a loose ``(pressure, sample_rate, start, stop)`` tail: a signal rendered at listeners, a WAV
read back with its calibration and a damper's operating noise are each one :class:`Signal`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_finite, check_positive

__all__ = ["Signal"]


def _readonly(p: np.ndarray) -> np.ndarray:
    """``p`` as a read-only float array the caller cannot change through a reference it still holds.

    An array that owns its float data and is already read-only is taken as it is (a renderer hands
    over its output without a second copy of a long signal); anything else is copied.
    """
    if p.dtype == np.float64 and p.flags.owndata and not p.flags.writeable:
        return p
    a = np.array(p, dtype=float)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class Signal:
    """Sound pressure sampled on a uniform time grid.

    Parameters
    ----------
    pressure : (n_samples,) or (n_channels, n_samples) array_like
        Calibrated sound pressure in Pa (finite); 1-D for one channel. Stored as a read-only
        float copy (a read-only float array that owns its data is kept without copying).
    sample_rate : float
        Sample rate in Hz (positive, finite).
    start : float
        Time of the first sample in s (default 0); sample ``n`` is at ``start + n / sample_rate``.

    Examples
    --------
    >>> sig = Signal([0.0, 1.0, 0.0, -1.0], 4.0, start=0.5)
    >>> sig.n_samples, sig.channels, sig.duration, sig.stop
    (4, 1, 1.0, 1.5)
    >>> sig.times.tolist()
    [0.5, 0.75, 1.0, 1.25]
    """

    pressure: np.ndarray
    sample_rate: float
    start: float = 0.0

    def __post_init__(self):
        try:
            p = np.asarray(self.pressure, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError("pressure", "expected an array of samples in Pa") from None
        if p.ndim not in (1, 2) or p.shape[-1] < 1:
            raise ParameterError("pressure", f"expected (n_samples,) or (n_channels, n_samples) Pa with at least one "
                                             f"sample, got shape {p.shape}")
        if not np.all(np.isfinite(p)):
            raise ParameterError("pressure", "pressure samples must be finite")
        object.__setattr__(self, "pressure", _readonly(p))
        object.__setattr__(self, "sample_rate", check_positive("sample_rate", self.sample_rate, "Hz"))
        object.__setattr__(self, "start", check_finite("start", self.start))

    @property
    def n_samples(self) -> int:
        """Number of samples per channel."""
        return int(self.pressure.shape[-1])

    @property
    def channels(self) -> int:
        """Number of channels (1 for a 1-D signal).

        Examples
        --------
        >>> Signal(np.zeros((2, 8)), 8000.0).channels
        2
        """
        return 1 if self.pressure.ndim == 1 else int(self.pressure.shape[0])

    @property
    def duration(self) -> float:
        """Length in s: ``n_samples / sample_rate``.

        Examples
        --------
        >>> Signal(np.zeros(48000), 48000.0).duration
        1.0
        """
        return self.n_samples / self.sample_rate

    @property
    def stop(self) -> float:
        """End of the signal in s: ``start + duration`` (one sample period after the last sample).

        Examples
        --------
        >>> Signal(np.zeros(10), 10.0, start=2.0).stop
        3.0
        """
        return self.start + self.duration

    @property
    def times(self) -> np.ndarray:
        """``(n_samples,)`` times of the samples in s, from ``start``.

        Examples
        --------
        >>> Signal(np.zeros(3), 2.0).times.tolist()
        [0.0, 0.5, 1.0]
        """
        return self.start + np.arange(self.n_samples) / self.sample_rate

    def as_channels(self) -> np.ndarray:
        """The samples as a read-only ``(n_channels, n_samples)`` array in Pa (a 1-D signal is one row).

        Examples
        --------
        >>> Signal([1.0, 2.0], 1.0).as_channels().shape
        (1, 2)
        """
        return self.pressure[None, :] if self.pressure.ndim == 1 else self.pressure

    def interval(self, start=None, stop=None) -> slice:
        """The samples whose times lie in ``[start, stop)`` s, as a slice of the sample axis.

        Parameters
        ----------
        start, stop : float, optional
            Interval in s on the signal's time axis (default: its start and its stop). Both must
            lie within the signal and the interval must hold at least two samples.

        Returns
        -------
        slice
            Sample indices, rounded to the nearest sample.

        Examples
        --------
        >>> Signal(np.zeros(100), 100.0, start=1.0).interval(1.25, 1.5)
        slice(25, 50, None)
        """
        t0 = self.start if start is None else check_finite("start", start)
        t1 = self.stop if stop is None else check_finite("stop", stop)
        lo, hi = self.start, self.stop
        if not lo <= t0 < hi:
            raise ParameterError("start", f"must lie in [{lo:g}, {hi:g}) s (the signal's length), got {t0:g} s")
        if not lo < t1 <= hi + self.duration * 1e-12:
            raise ParameterError("stop", f"must lie in (start, {hi:g}] s (the signal's length), got {t1:g} s")
        fs = self.sample_rate
        i0 = int(round((t0 - lo) * fs))
        i1 = min(int(round((t1 - lo) * fs)), self.n_samples)
        if i1 - i0 < 2:
            raise ParameterError("stop", f"the interval [{t0:g}, {t1:g}) s holds fewer than two samples at {fs:g} Hz")
        return slice(i0, i1)

    def window(self, start=None, stop=None) -> Signal:
        """The part of the signal in ``[start, stop)`` s, a new :class:`Signal` starting at its first sample.

        Parameters
        ----------
        start, stop : float, optional
            Interval in s on the signal's time axis (see :meth:`interval`).

        Returns
        -------
        Signal
            Same rate and channels; ``start`` is the time in s of the first sample kept.

        Examples
        --------
        >>> sig = Signal(np.arange(10.0), 10.0, start=1.0)
        >>> part = sig.window(1.2, 1.5)
        >>> part.pressure.tolist(), part.start
        ([2.0, 3.0, 4.0], 1.2)
        """
        win = self.interval(start, stop)
        return Signal(self.pressure[..., win], self.sample_rate, start=self.start + win.start / self.sample_rate)
