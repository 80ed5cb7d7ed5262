"""Weighted levels of a transient: a signal that is silent after its first samples, without filtering the silence.

A click of a few milliseconds analysed over a 1 s interval is, at 96 kHz, a few hundred samples
of sound and some 95 000 zeros. :func:`sound_levels` runs the A and C weightings and the F and S
time weightings over all of them; :func:`transient_levels` gives the same levels from the sound
alone. The frequency weightings are the library's own second-order sections
(:func:`._library.weighting_sos`), run over the sound and a short settling stretch of zeros, so
those samples are the very samples :func:`sound_levels` computes. After them the weighted signal is
the filter's free response from its final state ``s``; its energy over the rest of the interval,
``H`` samples, is ``sᵀ G_H s`` with the finite-horizon observability Gramian

``G_H = Σ_{j<H} (Φ^j)ᵀ cᵀ c Φ^j``  (summed by doubling, ``G_{a+b} = G_a + (Φ^a)ᵀ G_b Φ^a``),

where ``Φ`` and ``c`` are the sections' state transition and output under zero input. So:

* exposure and equivalent levels (``sel-a``, ``laeq``; ``sel``, ``lzeq``, ``lzpeak`` need no
  filter) are exact: the energy of the computed samples plus that of the free response;
* ``lcpeak``: every later sample obeys ``|y| <= sqrt(sᵀ G_H s)``, so once that bound is below the
  peak found the peak is exact;
* ``lafmax``, ``lasmax``: the time-weighted square ``v[n] = (1-α) v[n-1] + α y[n]²`` obeys
  ``v[n] <= v[N] + α sᵀ G_H s`` after the last computed sample ``N``; the maximum found is
  accepted once that bound exceeds it by at most :data:`MAX_RELATIVE_GAP` (4e-6 dB).

Where a bound is not met the settling stretch is lengthened (x4) until it is, at worst up to the
whole interval. Where the library's filter is not a plain cascade of sections at the rate (it
resamples below 96 kHz), the levels fall back to :func:`sound_levels` on the zero-padded signal.
"""

from __future__ import annotations

import functools

import numpy as np

from .._validate import ParameterError
from ..core.signal import Signal
from ._library import library, weighting_sos
from .weighted import METRICS, _integer_rate, as_channels, level_db, sound_levels

__all__ = ["transient_levels", "free_response_energy", "MAX_RELATIVE_GAP", "SETTLE_SAMPLES"]

#: Largest accepted relative gap between a time-weighted maximum found and the bound on the rest
#: of the interval (1e-6: 4.3e-6 dB).
MAX_RELATIVE_GAP = 1e-6
#: First length in samples of the stretch of zeros run through the weighting after the sound.
SETTLE_SAMPLES = 1024

_TIME_MODES = {"lafmax": "fast", "lasmax": "slow"}


@functools.lru_cache(maxsize=16)
def _system(sample_rate: int, curve: str):
    """``(sos, Φ, c)`` of the library's ``curve`` weighting at ``sample_rate``, or ``None``.

    The state is scipy's ``sosfilt`` ``zi`` of one channel, ``(n_sections, 2)`` flattened; under
    zero input the output is ``c · s`` and the next state ``Φ s``.
    """
    from scipy.signal import sosfilt

    sos = weighting_sos(sample_rate, curve)
    if sos is None:
        return None
    sos = np.array(sos)  # a copy: the cached sections stay as the library gave them
    n_sec = sos.shape[0]
    n = 2 * n_sec
    zi = np.eye(n).reshape(n, n_sec, 2).transpose(1, 0, 2)  # channel j starts in basis state j
    y, zf = sosfilt(sos, np.zeros((n, 1)), axis=-1, zi=zi)
    phi = zf.transpose(1, 0, 2).reshape(n, n).T  # column j: the state after one step from state j
    return sos, phi, y[:, 0].copy()


@functools.lru_cache(maxsize=64)
def _gramian(sample_rate: int, curve: str, horizon: int) -> np.ndarray:
    """``G_H = Σ_{j<H} (Φ^j)ᵀ cᵀ c Φ^j`` by doubling (``G_{a+b} = G_a + (Φ^a)ᵀ G_b Φ^a``): sums of squares only."""
    _, phi, c = _system(sample_rate, curve)
    g_block, p_block = np.outer(c, c), phi  # G and Φ of 2^k steps
    g, p = np.zeros_like(g_block), np.eye(phi.shape[0])  # G and Φ of the steps summed so far
    h = int(horizon)
    while h:
        if h & 1:
            g = g + p.T @ g_block @ p
            p = p_block @ p
        h >>= 1
        if h:
            g_block = g_block + p_block.T @ g_block @ p_block
            p_block = p_block @ p_block
    return 0.5 * (g + g.T)


def free_response_energy(sample_rate: int, curve: str, state, horizon: int) -> np.ndarray:
    """Energy ``Σ y[n]²`` (Pa² × samples) of the weighting's free response over ``horizon`` samples.

    Parameters
    ----------
    sample_rate : int
        Sample rate in Hz.
    curve : {"A", "C"}
        The frequency weighting (the library's sections, :func:`._library.weighting_sos`).
    state : (n_sections, k, 2) array_like
        The filter state of ``k`` channels in Pa, as ``scipy.signal.sosfilt`` returns it (``zf``).
    horizon : int
        Number of output samples of zero input, from the sample after the state.

    Returns
    -------
    (k,) ndarray
        ``sᵀ G_H s`` per channel in Pa² × samples (divide by the rate for Pa²·s).

    Raises
    ------
    ParameterError
        If the library's weighting at ``sample_rate`` is not a cascade of sections.
    """
    system = _system(int(sample_rate), curve)
    if system is None:
        raise ParameterError("sample_rate", f"the {curve} weighting of the filter library at {sample_rate} Hz "
                                            "is not a plain cascade of sections")
    n_sec = system[0].shape[0]
    z = np.asarray(state, dtype=float)
    if z.ndim != 3 or z.shape[0] != n_sec or z.shape[2] != 2:
        raise ParameterError("state", f"expected ({n_sec}, k, 2) as sosfilt's zf, got shape {z.shape}")
    s = z.transpose(1, 0, 2).reshape(z.shape[1], -1)
    h = int(horizon)
    if h <= 0:
        return np.zeros(s.shape[0])
    return np.maximum(np.einsum("ki,ij,kj->k", s, _gramian(int(sample_rate), curve, h), s), 0.0)


def _run(curve: str, fs: int, x: np.ndarray, stop: int, n_samples: int):
    """The weighted samples ``[0, stop)`` of ``x`` followed by zeros, and the energy of the rest of the interval."""
    from scipy.signal import sosfilt

    sos = _system(fs, curve)[0]
    xp = x if stop <= x.shape[1] else np.pad(x, ((0, 0), (0, stop - x.shape[1])))
    y, zf = sosfilt(sos, xp[:, :stop], axis=-1, zi=np.zeros((sos.shape[0], x.shape[0], 2)))
    return y, free_response_energy(fs, curve, zf, n_samples - stop)


@functools.lru_cache(maxsize=8)
def _alpha(fs: int, mode: str):
    """The library's ``α`` of the ``mode`` time weighting at ``fs``: ``v[n] = (1-α) v[n-1] + α x²``, else ``None``."""
    v = np.asarray(library().time_weighting(np.array([1.0, 0.0, 0.0, 0.0]), fs, mode=mode), dtype=float)
    a = float(v[0])
    ok = 0.0 < a < 1.0 and np.allclose(v[1:], a * (1.0 - a) ** np.arange(1, 4), rtol=1e-12, atol=0.0)
    return a if ok else None


def _time_weighted_max(x: np.ndarray, fs: int, mode: str, n_samples: int, first) -> np.ndarray:
    """Largest A-weighted ``mode``-time-weighted mean square (Pa²) over the interval, per channel."""
    alpha = _alpha(fs, mode)
    out = np.empty(x.shape[0])
    todo = np.arange(x.shape[0])
    stop, (y, tail) = first
    while todo.size:
        env = np.asarray(library().time_weighting(y, fs, mode=mode), dtype=float)
        top = env.max(axis=1)
        done = (env[:, -1] + alpha * tail <= top * (1.0 + MAX_RELATIVE_GAP)) | (stop >= n_samples)
        out[todo[done]] = top[done]
        todo = todo[~done]
        if todo.size:
            stop = min(n_samples, x.shape[1] + 4 * (stop - x.shape[1]))
            y, tail = _run("A", fs, x[todo], stop, n_samples)
    return out


def _peak(x: np.ndarray, fs: int, n_samples: int, first) -> np.ndarray:
    """Largest |C-weighted pressure| (Pa) over the interval, per channel."""
    out = np.empty(x.shape[0])
    todo = np.arange(x.shape[0])
    stop, (y, tail) = first
    while todo.size:
        top = np.max(np.abs(y), axis=1)
        done = (tail <= top * top) | (stop >= n_samples)
        out[todo[done]] = top[done]
        todo = todo[~done]
        if todo.size:
            stop = min(n_samples, x.shape[1] + 4 * (stop - x.shape[1]))
            y, tail = _run("C", fs, x[todo], stop, n_samples)
    return out


def transient_levels(head, sample_rate: float, n_samples: int, metrics) -> dict:
    """Levels of ``head`` followed by zeros up to ``n_samples``, as :func:`sound_levels` gives them.

    Parameters
    ----------
    head : (n_head,) or (n_channels, n_head) array_like
        The sound pressure in Pa up to its last non-zero sample, sample ``n`` at ``n / sample_rate`` s.
    sample_rate : float
        Sample rate in Hz (whole Hz).
    n_samples : int
        Length of the whole signal in samples (``>= n_head``): the interval is
        ``n_samples / sample_rate`` s from sample 0.
    metrics : sequence of str
        Keys of :data:`METRICS` (``"lcpeak"``, ``"lafmax"``, ``"laeq"``, ``"sel-a"``, ...).

    Returns
    -------
    dict
        Metric -> ``(n_channels,)`` level in dB re 20 µPa (exposure levels re (20 µPa)²·s): equal to
        ``getattr(sound_levels(Signal(padded, sample_rate)), METRICS[metric])`` up to rounding (exposure,
        peaks) or :data:`MAX_RELATIVE_GAP` (time-weighted maxima).

    Examples
    --------
    >>> fs = 96000
    >>> click = np.sin(np.pi * np.arange(48) / 48) ** 2
    >>> fast = transient_levels(click, fs, fs, ["sel-a", "lafmax"])
    >>> full = sound_levels(Signal(np.r_[click, np.zeros(fs - 48)], fs))
    >>> bool(abs(fast["sel-a"][0] - full.sel_a_db[0]) < 1e-9), bool(abs(fast["lafmax"][0] - full.lafmax_db[0]) < 1e-4)
    (True, True)
    """
    x = as_channels(head, "head")
    fs = _integer_rate(sample_rate)
    n = int(n_samples)
    if n != n_samples or n < x.shape[1]:
        raise ParameterError("n_samples", f"must be an integer >= the head's {x.shape[1]} samples, got {n_samples!r}")
    names = list(metrics)
    for m in names:
        if m not in METRICS:
            raise ParameterError("metrics", f"each must be one of {', '.join(METRICS)}, got {m!r}")
    need = {"A"} if {"lafmax", "lasmax", "laeq", "sel-a"} & set(names) else set()
    need |= {"C"} if "lcpeak" in names else set()
    if any(_system(fs, c) is None for c in need) or any(_alpha(fs, _TIME_MODES[m]) is None
                                                        for m in names if m in _TIME_MODES):
        full = sound_levels(Signal(np.pad(x, ((0, 0), (0, n - x.shape[1]))), fs))
        return {m: getattr(full, METRICS[m]) for m in names}
    stop = min(n, x.shape[1] + SETTLE_SAMPLES)
    runs = {c: (stop, _run(c, fs, x, stop, n)) for c in need}
    seconds = n / fs
    ez = np.sum(x * x, axis=1) / fs
    out = {}
    for m in names:
        if m == "lzpeak":
            out[m] = level_db(np.max(np.abs(x), axis=1) ** 2)
        elif m in ("sel", "lzeq"):
            out[m] = level_db(ez if m == "sel" else ez / seconds)
        elif m in ("sel-a", "laeq"):
            y, tail = runs["A"][1]
            ea = (np.sum(y * y, axis=1) + tail) / fs
            out[m] = level_db(ea if m == "sel-a" else ea / seconds)
        elif m == "lcpeak":
            out[m] = level_db(_peak(x, fs, n, runs["C"]) ** 2)
        else:
            out[m] = level_db(_time_weighted_max(x, fs, _TIME_MODES[m], n, runs["A"]))
    return out
