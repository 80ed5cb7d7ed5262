"""The samples a waveform or a directivity is shown on: one rule for the command line and scenes.

Examples
--------
>>> from acoustiviz.app.impacts import impact_setup, observer_point
>>> s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config="plane")
>>> t = waveform_times([s.pulse], observer_point(s, 0.7, 45.0), s.geometry, s.medium)
>>> float(t[0]), bool(t[-1] > 2.0e-3)
(0.0, True)
>>> directivity_angles(s.geometry, 30.0).round(4).tolist()
[0.0, 0.5236, 1.0472, 1.5708]
"""

from __future__ import annotations

import numpy as np

from .._validate import check_range
from ..constants import BALLOON_METRICS, DIRECTIVITY_METRICS, P_REF
from ..errors import ParameterError
from ..field import field_metrics, waveform_span
from ..levels import METRICS
from .settings.impact import MIN_SAMPLES_PER_DURATION

__all__ = ["waveform_times", "waveform_peaks", "directivity_angles", "check_samples_per_duration",
           "MIN_SAMPLES_PER_DURATION", "DIRECTIVITY_METRICS", "directivity_metric", "metric_label",
           "directivity_metric_figure", "point_levels", "BALLOON_METRICS", "balloon_levels"]

def waveform_times(pulses, point, geometry, medium, samples_per_duration: int = 400, *, window=None) -> np.ndarray:
    """Times in s from the start of contact to the end of the sound of every pulse at ``point``.

    The step is the shortest pulse's duration / ``samples_per_duration``; the end is the latest
    :func:`acoustiviz.field.waveform_span` of the pulses (last arrival, pulse, 40 decay times).

    Parameters
    ----------
    pulses : sequence of pulse
        Acceleration pulses shown together.
    point : (3,) array_like
        Observer in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    samples_per_duration : int
        Samples per contact duration, at least :data:`MIN_SAMPLES_PER_DURATION`.
    window : float, optional
        End in s of the times instead of the end of the sound (a room's window: its reverberation
        outlasts any useful span).
    """
    check_samples_per_duration(samples_per_duration)
    dt = min(p.duration for p in pulses) / samples_per_duration
    if window is not None:
        return np.arange(0.0, float(window) + 0.5 * dt, dt)
    end = max(waveform_span(p, point, geometry, medium=medium)[1] for p in pulses)
    return np.arange(0.0, end + dt, dt)


def waveform_peaks(pulse, point, geometry, medium, *, memory_limit=None) -> tuple[float, float]:
    """Largest and smallest pressure in Pa of the continuous waveform at ``point``.

    The peaks of :func:`acoustiviz.field.field_metrics` over the whole response (sampled at 64
    samples per ``min(T, a/c)``, then refined between the samples by a bounded search on the closed
    form, paper eqs 12-14), not the extreme samples of a tabulated waveform.

    Parameters
    ----------
    pulse : pulse
        Acceleration pulse of the sphere.
    point : (3,) array_like
        Observer in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    memory_limit : float, optional
        Working-memory cap in bytes (:func:`acoustiviz.field.field_metrics`).

    Returns
    -------
    peak_positive, peak_negative : float
        Pressure in Pa (``peak_negative <= 0``).
    """
    kw = {} if memory_limit is None else {"memory_limit": memory_limit}
    fm = field_metrics(pulse, np.asarray(point, dtype=float)[None, :], geometry, medium=medium, **kw)
    return float(fm.peak_positive[0]), float(fm.peak_negative[0])


def check_samples_per_duration(samples_per_duration) -> int:
    """``samples_per_duration`` as an int, unless it is not an integer >= :data:`MIN_SAMPLES_PER_DURATION`."""
    ok = isinstance(samples_per_duration, (int, np.integer)) or (
        isinstance(samples_per_duration, float) and samples_per_duration.is_integer())
    if not ok or samples_per_duration < MIN_SAMPLES_PER_DURATION:
        raise ParameterError("samples_per_duration",
                             f"must be an integer >= {MIN_SAMPLES_PER_DURATION}, got {samples_per_duration}")
    return int(samples_per_duration)


def directivity_angles(geometry, step_deg: float) -> np.ndarray:
    """Polar angles in rad from 0 to the edge of the fluid (180° free, 90° plane and corner), both ends included.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    step_deg : float
        Angle step in degrees, in (0, 90].
    """
    step = check_range("step_deg", step_deg, 0.0, 90.0, unit="deg", low_open=True)
    top = geometry.polar_limit_deg
    deg = np.arange(0.0, top + 1e-9 * top, step)
    if deg[-1] < top - 1e-9:
        deg = np.append(deg, top)
    return np.radians(deg)


def directivity_metric(directivity, metric: str, pulse, geometry, medium, *, memory_limit=None) -> np.ndarray:
    """The level ``metric`` in dB at each angle of a directivity.

    Parameters
    ----------
    directivity : acoustiviz.field.Directivity
        Peaks and RMS on the circle (its points are used).
    metric : str
        A key of :data:`DIRECTIVITY_METRICS`: ``"peak-spl"`` (its peak SPL), ``"rms"`` (the level of
        its RMS pressure over its window), or a weighted level of :data:`acoustiviz.levels.METRICS`
        (``"lcpeak"``, ``"lafmax"``, ``"laeq"``, ``"sel-a"``, ...): the levels
        :func:`acoustiviz.levels.sound_levels` gives of
        :func:`~acoustiviz.sound.impact_levels.impact_signals` at :data:`~acoustiviz.constants.ANALYSIS_RATE`
        over :data:`~acoustiviz.sound.impact_levels.LEVEL_INTERVAL` (1 s from the first arrival at any angle:
        LAeq,1s of one impact, numerically equal to its SEL(A)), computed by
        :func:`~acoustiviz.sound.impact_levels.points_metric_levels` from the sound alone.
    pulse, geometry, medium
        The impact, sphere and fluid of the directivity.
    memory_limit : float, optional
        Cap in bytes on the weighted level's closed-form samples
        (:func:`~acoustiviz.sound.impact_levels.points_metric_levels`).

    Returns
    -------
    (k,) ndarray
        dB re 20 µPa (exposure levels re (20 µPa)²·s).
    """
    if metric not in DIRECTIVITY_METRICS:
        raise ParameterError("metric", f"must be one of {', '.join(DIRECTIVITY_METRICS)}, got {metric!r}")
    if metric == "peak-spl":
        return np.asarray(directivity.spl_db, dtype=float)
    if metric == "rms":
        with np.errstate(divide="ignore"):
            return 20.0 * np.log10(np.asarray(directivity.rms, dtype=float) / P_REF)
    from ..sound.impact_levels import points_metric_levels

    return points_metric_levels([metric], pulse, directivity.points, geometry, medium,
                                memory_limit=memory_limit)[metric]


def point_levels(metric: str, pulse, geometry, medium, *, chunk: int = 64):
    """The weighted level ``metric`` of one impact as a function of observer points, and its label.

    Parameters
    ----------
    metric : str
        A key of :data:`acoustiviz.levels.METRICS` (``"lcpeak"``, ``"lafmax"``, ``"laeq"``,
        ``"sel-a"``, ...): computed as for :func:`directivity_metric`, by
        :func:`~acoustiviz.sound.impact_levels.points_metric_levels` (the levels of
        :func:`~acoustiviz.sound.impact_levels.impact_signals` at :data:`~acoustiviz.constants.ANALYSIS_RATE`
        over :data:`~acoustiviz.sound.impact_levels.LEVEL_INTERVAL`).
    pulse, geometry, medium
        The impact, sphere and fluid.
    chunk : int
        Points whose signals share one time grid (sample 0 at the chunk's earliest arrival); it
        bounds the memory to ``chunk`` oversampled sounds.

    Returns
    -------
    function, label : callable, str
        ``function(points)`` gives the level in dB at ``(k, 3)`` points in m; ``label`` its name and unit.
    """
    if metric not in METRICS:
        raise ParameterError("metric", f"must be one of {', '.join(METRICS)}, got {metric!r}")

    from ..sound.impact_levels import points_metric_levels

    def function(points):
        return points_metric_levels([metric], pulse, points, geometry, medium, chunk=chunk)[metric]

    return function, metric_label(metric)


def balloon_levels(metric: str, pulse, geometry, medium):
    """The ``levels`` argument of :func:`acoustiviz.field.balloon.balloon_data` for ``metric``.

    ``None`` for the closed form's ``"peak"``, ``"rms"`` and ``"sel"``; :func:`point_levels`
    for a weighted level of :data:`BALLOON_METRICS`.
    """
    if metric not in BALLOON_METRICS:
        raise ParameterError("metric", f"must be one of {', '.join(BALLOON_METRICS)}, got {metric!r}")
    return None if metric in ("peak", "rms", "sel") else point_levels(metric, pulse, geometry, medium)


def metric_label(metric: str) -> str:
    """How a directivity metric is named on a plot axis, with its unit."""
    from ..sound.impact_levels import LEVEL_INTERVAL

    names = {"peak-spl": "peak SPL", "rms": "RMS level", "lzpeak": "LZpeak", "lcpeak": "LCpeak",
             "lafmax": "LAFmax", "lasmax": "LASmax", "laeq": f"LAeq,{LEVEL_INTERVAL:g}s",
             "lzeq": f"LZeq,{LEVEL_INTERVAL:g}s", "sel": "SEL", "sel-a": "SEL(A)"}
    unit = "dB re (20 µPa)² s" if metric.startswith("sel") else "dB re 20 µPa"
    return f"{names.get(metric, metric)} ({unit})"


def directivity_metric_figure(directivity, values, metric: str, *, title: str = "", half_space: bool = True):
    """Paper Figure 3 (peak SPL, RMS pressure) and a third polar plot of ``values`` (``metric``, dB)."""
    from types import SimpleNamespace

    from matplotlib.figure import Figure

    from ..output.plot.directivity import half_space_axes, plot_directivity
    from ..output.plot.style import style

    with style():
        fig = Figure(figsize=(13.5, 5.2), layout="constrained")
        axes = [fig.add_subplot(1, 3, k, projection="polar") for k in (1, 2, 3)]
        plot_directivity(directivity, "spl", ax=axes[0])
        plot_directivity(directivity, "rms", ax=axes[1])
        plot_directivity(SimpleNamespace(angle=directivity.angle, spl_db=np.asarray(values, dtype=float)), "spl",
                         ax=axes[2])
        label = metric_label(metric)
        axes[2].set_title(f"{label} vs angle from the acceleration axis (deg)", fontsize=9)
        axes[2].set_xlabel(f"radial axis: {label}", fontsize=8)
        if title:
            fig.suptitle(title, fontsize=10)
        if half_space:
            half_space_axes(fig)
    return fig
