"""Zwicker loudness (ISO 532-1) and DIN 45692 sharpness of pressure signals, via mosqito.

mosqito is an optional dependency (``pip install acoustiviz[hearing]``): :func:`loudness_available` says
whether it is installed and :func:`loudness` raises a :class:`~acoustiviz.errors.ParameterError`
naming it when it is not. The signal is resampled to 48 kHz (the rate ISO 532-1's filter bank is
specified at) before the analysis.

Reported per channel:

* ``N5`` -- the loudness exceeded 5 % of the time (95th percentile of the time-varying loudness
  ``N(t)``, ISO 532-1:2017 5.2 recommends it for time-varying sounds), and ``Nmax``, in sone;
* the sharpness in acum (DIN 45692:2009) of the time-averaged specific loudness -- the
  loudness-weighted mean of the time-varying sharpness ``Σ N_i S_i / Σ N_i``.
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice
from ..core.signal import Signal
from .weighted import _integer_rate, check_signal

__all__ = ["LOUDNESS_RATE", "Loudness", "loudness_available", "loudness"]

#: Sample rate in Hz at which the loudness model runs.
LOUDNESS_RATE = 48000


def loudness_available() -> bool:
    """True if mosqito (the loudness and sharpness library) is installed."""
    return importlib.util.find_spec("mosqito") is not None


@dataclass(frozen=True)
class Loudness:
    """Loudness and sharpness of one or more channels.

    Attributes
    ----------
    n5_sone, nmax_sone : (n_channels,) ndarray
        Percentile loudness N5 and largest loudness in sone (ISO 532-1, time-varying).
    sharpness_acum : (n_channels,) ndarray
        DIN 45692 sharpness of the time-averaged specific loudness, in acum.
    field : str
        ``"free"`` or ``"diffuse"`` sound field assumed by ISO 532-1.
    start, stop : float
        The interval analysed, in s.
    library : str
        ``"mosqito <version>"``.
    """

    n5_sone: np.ndarray
    nmax_sone: np.ndarray
    sharpness_acum: np.ndarray
    field: str
    start: float
    stop: float
    library: str

    def rows(self, channels=None) -> list:
        """One dict per channel: ``channel, n5_sone, nmax_sone, sharpness_acum``."""
        n = self.n5_sone.size
        names = list(channels) if channels is not None else [str(i + 1) for i in range(n)]
        return [{"channel": names[i], "n5_sone": float(self.n5_sone[i]), "nmax_sone": float(self.nmax_sone[i]),
                 "sharpness_acum": float(self.sharpness_acum[i])} for i in range(n)]


def loudness(signal: Signal, *, start=None, stop=None, field: str = "free") -> Loudness:
    """N5, Nmax (sone) and sharpness (acum) of pressure signals.

    Parameters
    ----------
    signal : Signal
        Sound pressure in Pa, one or more channels, at a whole number of Hz.
    start, stop : float, optional
        Interval in s on the signal's time axis (default: the whole signal); it should last at
        least 0.2 s.
    field : {"free", "diffuse"}
        Sound field of ISO 532-1.

    Returns
    -------
    Loudness

    Notes
    -----
    ISO 532-1:2017 method for time-varying sounds (mosqito ``loudness_zwtv``), sharpness by
    DIN 45692:2009 weighting of the specific loudness (mosqito ``sharpness_din_from_loudness``).
    A 1 kHz tone at 40 dB SPL in a free field is 1 sone by definition.
    """
    if not loudness_available():
        raise ParameterError("mosqito", "loudness and sharpness need mosqito: pip install 'acoustiviz[hearing]'")
    check_choice("field", field, ("free", "diffuse"))
    p = check_signal(signal).as_channels()
    fs = _integer_rate(signal.sample_rate)
    win = signal.interval(start, stop)
    x = p[:, win]
    if fs != LOUDNESS_RATE:
        from math import gcd

        from scipy.signal import resample_poly

        g = gcd(LOUDNESS_RATE, fs)
        x = resample_poly(x, LOUDNESS_RATE // g, fs // g, axis=-1)
    if x.shape[1] < LOUDNESS_RATE // 5:
        raise ParameterError("stop", f"the interval must last at least 0.2 s for loudness, got {x.shape[1] / 48e3:g} s")
    from importlib import metadata

    from mosqito.sq_metrics import loudness_zwtv, sharpness_din_from_loudness

    n5, nmax, sharp = [], [], []
    for row in x:
        n_t, n_spec, _, _ = loudness_zwtv(row, LOUDNESS_RATE, field_type=field)
        n_t = np.asarray(n_t, dtype=float)
        n5.append(float(np.percentile(n_t, 95)))
        nmax.append(float(n_t.max()))
        mean_spec = np.mean(np.asarray(n_spec, dtype=float), axis=1)
        total = float(np.mean(n_t))
        sharp.append(float(sharpness_din_from_loudness(total, mean_spec)) if total > 0 else 0.0)
    return Loudness(np.array(n5), np.array(nmax), np.array(sharp), field, signal.start + win.start / fs,
                    signal.start + win.stop / fs,
                    f"mosqito {metadata.version('mosqito')}")
