"""The sound of one impact at observer points, band-limited and sampled, and its weighted levels.

:func:`impact_signals` samples the closed-form pressure (:func:`acoustiviz.field.time_series`) of one
impact at points, band-limited by the auraliser's decimation filter (:mod:`.synthesis`);
:func:`points_metric_levels` gives its weighted levels (:data:`acoustiviz.levels.METRICS`) over
:data:`LEVEL_INTERVAL` from the sound alone, checked against :func:`reference_metric_levels`,
the levels of the whole interval straight from the definition.
"""

from __future__ import annotations

import numpy as np

from ..constants import ANALYSIS_RATE
from ..errors import ParameterError
from ..field import waveform_spans
from ..levels import METRICS

__all__ = ["LEVEL_INTERVAL", "impact_signals", "sound_samples", "impact_sound", "points_metric_levels",
           "reference_metric_levels", "check_metrics"]

#: Interval in s over which one impact's equivalent levels (LAeq, LZeq) are averaged, from its first arrival.
LEVEL_INTERVAL = 1.0


def _signal_grid(pulse, points, geometry, medium, sample_rate: int, interval: float):
    """The oversampled times of :func:`impact_signals` and what decimates them.

    Returns ``(points, t, L, h, K, n_sound, n_out)``: the ``(k, 3)`` points in m, the times in s at
    ``L × sample_rate`` from the earliest arrival (rounded down to the output grid) to the end of the
    latest sound (in a room, at most to the end of its window ``duration``), the decimation filter
    ``h`` (``2KL + 1`` taps), the output samples of sound and of the whole interval.
    """
    from .synthesis import decimation_filter, oversampling_factor

    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    spans = waveform_spans(pulse, pts, geometry, medium=medium)
    L = oversampling_factor(sample_rate, pulse.duration)
    h = decimation_filter(L)
    K = (h.size - 1) // (2 * L)
    t0 = np.floor(spans[:, 0].min() * sample_rate) / sample_rate
    n_out = int(round(interval * sample_rate))
    end = float(spans[:, 1].max())
    reach = getattr(geometry, "duration", None)  # a room: the sound within its window (every image arriving in it)
    if reach is not None:
        end = max(min(end, float(reach)), t0)
    n_sound = int(np.ceil((end - t0) * sample_rate)) + 1
    if n_sound + K >= n_out:
        raise ParameterError("interval", f"must exceed the sound of one impact ({(n_sound + K) / sample_rate:g} s)")
    t = t0 + np.arange(n_sound * L) / (L * sample_rate)
    return pts, t, L, h, K, n_sound, n_out


def impact_signals(pulse, points, geometry, medium, *, sample_rate: int = ANALYSIS_RATE,
                   interval: float = LEVEL_INTERVAL) -> np.ndarray:
    """Pressure of one impact at each point, band-limited and sampled at ``sample_rate`` over ``interval``.

    The closed-form pressure (:func:`acoustiviz.field.time_series`) is evaluated at
    ``L × sample_rate`` (``L`` >= 16 and >= 200 samples per contact,
    :func:`acoustiviz.sound.oversampling_factor`), from the earliest arrival at any point to
    the end of the latest sound (:func:`acoustiviz.field.waveform_span`), low-passed flat to
    0.45 × ``sample_rate`` by the auraliser's zero-delay decimation filter
    (:func:`acoustiviz.sound.decimation_filter`) and decimated, so nothing aliases.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        The sphere's acceleration pulse.
    points : (k, 3) array_like
        Observers in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    sample_rate : int
        Output rate in Hz (default :data:`~acoustiviz.constants.ANALYSIS_RATE`).
    interval : float
        Signal length in s from the earliest arrival (zeros after the sound).

    Returns
    -------
    (k, round(interval × sample_rate)) ndarray
        Pressure in Pa; sample 0 is the earliest arrival (rounded down to the output grid).
    """
    from scipy.signal import upfirdn

    from ..field import time_series

    pts, t, L, h, K, n_sound, n_out = _signal_grid(pulse, points, geometry, medium, sample_rate, interval)
    hi = time_series(pulse, t, pts, geometry, medium=medium)
    low = upfirdn(h, hi, up=1, down=L, axis=1)[:, K:K + n_sound + K]
    out = np.zeros((pts.shape[0], n_out))
    out[:, :low.shape[1]] = low
    return out


def sound_samples(pulse, points, geometry, medium, *, sample_rate: int = ANALYSIS_RATE,
                  interval: float = LEVEL_INTERVAL) -> int:
    """Oversampled times per point at which :func:`impact_sound` evaluates the closed form (no pressure computed).

    :func:`acoustiviz.app.budget.metric_estimate` counts its memory from them before the work.
    """
    return int(_signal_grid(pulse, points, geometry, medium, sample_rate, interval)[1].size)


def impact_sound(pulse, points, geometry, medium, *, sample_rate: int = ANALYSIS_RATE,
                 interval: float = LEVEL_INTERVAL, memory_limit=None) -> tuple[np.ndarray, int]:
    """The samples of :func:`impact_signals` up to the end of the sound, and the interval's length.

    The same oversampled closed form and decimation filter, the filter applied by FFT convolution
    (equal to :func:`impact_signals`' direct sums to ~1e-14 of the peak) and only the output
    samples before the zeros computed.

    Parameters
    ----------
    pulse, points, geometry, medium, sample_rate, interval
        As for :func:`impact_signals`.
    memory_limit : float, optional
        Cap in bytes on the closed form's samples (:func:`acoustiviz.field.time_series`; default its own).

    Returns
    -------
    sound : (k, n_sound) ndarray
        Pressure in Pa: the first ``n_sound`` samples of :func:`impact_signals` (all later ones are 0).
    n_samples : int
        ``round(interval × sample_rate)``, the length of :func:`impact_signals`' rows.
    """
    from scipy.signal import fftconvolve

    from ..field import time_series

    pts, t, L, h, K, n_sound, n_out = _signal_grid(pulse, points, geometry, medium, sample_rate, interval)
    kw = {} if memory_limit is None else {"memory_limit": memory_limit}
    hi = time_series(pulse, t, pts, geometry, medium=medium, **kw)
    full = fftconvolve(hi, h[None, :], axes=1)  # output j of the decimation is full[:, j L]
    return np.ascontiguousarray(full[:, K * L:(2 * K + n_sound) * L:L]), n_out


def _groups(n: int, chunk):
    """Slices of ``n`` points taken together: all at once (``chunk`` None) or ``chunk`` at a time."""
    step = n if chunk is None else int(chunk)
    return [slice(lo, lo + step) for lo in range(0, n, max(step, 1))]


def points_metric_levels(metrics, pulse, points, geometry, medium, *, chunk=None, memory_limit=None) -> dict:
    """Weighted levels of one impact at each point: :func:`reference_metric_levels` from the sound alone.

    The points are taken ``chunk`` at a time, as by the reference (sample 0 of a chunk is its
    earliest arrival); each chunk's sound (:func:`impact_sound`) is computed once for all
    ``metrics`` and its levels over :data:`LEVEL_INTERVAL` come from
    :func:`acoustiviz.levels.transient.transient_levels`, which filters the sound and a settling
    stretch only and adds the exact energy (or a rigorous bound) of the filters' free response over
    the rest of the interval.

    Parameters
    ----------
    metrics : sequence of str
        Keys of :data:`acoustiviz.levels.METRICS`.
    pulse, geometry, medium
        The impact, sphere and fluid.
    points : (k, 3) array_like
        Observers in m.
    chunk : int, optional
        Points whose signals share one time grid (default: all).
    memory_limit : float, optional
        Cap in bytes on each chunk's closed-form samples (:func:`impact_sound`).

    Returns
    -------
    dict
        Metric -> ``(k,)`` level in dB re 20 µPa (exposure levels re (20 µPa)²·s).
    """
    from ..levels.transient import transient_levels

    names = check_metrics(metrics)
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = {m: np.empty(pts.shape[0]) for m in names}
    for g in _groups(pts.shape[0], chunk):
        sound, n_out = impact_sound(pulse, pts[g], geometry, medium, memory_limit=memory_limit)
        for m, v in transient_levels(sound, ANALYSIS_RATE, n_out, names).items():
            out[m][g] = v
    return out


def reference_metric_levels(metrics, pulse, points, geometry, medium, *, chunk=None) -> dict:
    """The same levels as :func:`points_metric_levels`, straight from the definition.

    :func:`impact_signals` at :data:`~acoustiviz.constants.ANALYSIS_RATE` over the whole
    :data:`LEVEL_INTERVAL` (``chunk`` points at a time, default all), then
    :func:`acoustiviz.levels.sound_levels` over all its samples: the computation the fast path is
    checked against.

    Parameters
    ----------
    metrics, pulse, points, geometry, medium, chunk
        As for :func:`points_metric_levels`.

    Returns
    -------
    dict
        Metric -> ``(k,)`` level in dB.
    """
    from ..core.signal import Signal
    from ..levels import sound_levels

    names = check_metrics(metrics)
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = {m: np.empty(pts.shape[0]) for m in names}
    for g in _groups(pts.shape[0], chunk):
        lv = sound_levels(Signal(impact_signals(pulse, pts[g], geometry, medium), ANALYSIS_RATE))
        for m in names:
            out[m][g] = getattr(lv, METRICS[m])
    return out


def check_metrics(metrics) -> list:
    """``metrics`` (one name or several) as a list, each a key of :data:`acoustiviz.levels.METRICS`."""
    names = [metrics] if isinstance(metrics, str) else list(metrics)
    for m in names:
        if m not in METRICS:
            raise ParameterError("metric", f"must be one of {', '.join(METRICS)}, got {m!r}")
    return names
