"""The samples a waveform or a directivity is shown on: one rule for the command line and scenes.

Examples
--------
>>> from acoustiviz.app.impacts import impact_setup, observer_point
>>> s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config="plane")
>>> t = waveform_times([s.pulse], observer_point(s, 0.7, 45.0), s.configuration, s.medium)
>>> float(t[0]), bool(t[-1] > 2.0e-3)
(0.0, True)
>>> directivity_angles(s.configuration, 30.0).round(4).tolist()
[0.0, 0.5236, 1.0472, 1.5708]
"""

from __future__ import annotations

import numpy as np

from .._validate import check_range
from ..errors import ParameterError
from ..field import waveform_span

__all__ = ["waveform_times", "directivity_angles", "check_samples_per_duration", "MIN_SAMPLES_PER_DURATION"]

#: Fewest time samples per contact duration a waveform is drawn or tabulated with.
MIN_SAMPLES_PER_DURATION = 200


def waveform_times(pulses, point, config, medium, samples_per_duration: int = 400) -> np.ndarray:
    """Times in s from the start of contact to the end of the sound of every pulse at ``point``.

    The step is the shortest pulse's duration / ``samples_per_duration``; the end is the latest
    :func:`acoustiviz.field.waveform_span` of the pulses (last arrival, pulse, 40 decay times).

    Parameters
    ----------
    pulses : sequence of pulse
        Acceleration pulses shown together.
    point : (3,) array_like
        Observer in m.
    config : Configuration
        The sphere and its images.
    medium : Medium
        The fluid.
    samples_per_duration : int
        Samples per contact duration, at least :data:`MIN_SAMPLES_PER_DURATION`.
    """
    check_samples_per_duration(samples_per_duration)
    end = max(waveform_span(p, point, config, medium=medium)[1] for p in pulses)
    dt = min(p.duration for p in pulses) / samples_per_duration
    return np.arange(0.0, end + dt, dt)


def check_samples_per_duration(samples_per_duration) -> int:
    """``samples_per_duration`` as an int, unless it is not an integer >= :data:`MIN_SAMPLES_PER_DURATION`."""
    ok = isinstance(samples_per_duration, (int, np.integer)) or (
        isinstance(samples_per_duration, float) and samples_per_duration.is_integer())
    if not ok or samples_per_duration < MIN_SAMPLES_PER_DURATION:
        raise ParameterError("samples_per_duration",
                             f"must be an integer >= {MIN_SAMPLES_PER_DURATION}, got {samples_per_duration}")
    return int(samples_per_duration)


def directivity_angles(config, step_deg: float) -> np.ndarray:
    """Polar angles in rad from 0 to the edge of the fluid (180° free, 90° plane and corner), both ends included.

    Parameters
    ----------
    config : Configuration
        The sphere and its images.
    step_deg : float
        Angle step in degrees, in (0, 90].
    """
    step = check_range("step_deg", step_deg, 0.0, 90.0, unit="deg", low_open=True)
    top = 180.0 if config.name == "free" else 90.0
    deg = np.arange(0.0, top + 1e-9 * top, step)
    if deg[-1] < top - 1e-9:
        deg = np.append(deg, top)
    return np.radians(deg)
