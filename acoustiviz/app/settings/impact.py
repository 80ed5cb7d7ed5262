"""Settings of one impact heard at one observer: ``acoustiviz waveform`` and ``acoustiviz directivity``.

The same records build the scene's ``[outputs.directivity]`` keys and the room window
``configuration.window_s``; a waveform's sampling is a command-line setting (a scene tabulates
at the default).
"""

from __future__ import annotations

import dataclasses
import math

from ...constants import DIRECTIVITY_METRICS
from .base import Settings
from .table import Setting

__all__ = ["WAVEFORM", "DIRECTIVITY", "WaveformSettings", "DirectivitySettings", "MIN_SAMPLES_PER_DURATION"]

#: Fewest time samples per contact duration a waveform is drawn or tabulated with.
MIN_SAMPLES_PER_DURATION = 200

WAVEFORM = (
    Setting("samples_per_duration", "--samples-per-duration", None, "int", 400,
            "time samples per contact duration", low=MIN_SAMPLES_PER_DURATION, high=math.inf),
    Setting("window", "--duration", "window_s", "float", None,
            "with --room (required): the window from the start of contact that the waveform and its images "
            "reach", "s",
            low=0.0, high=1e4, low_open=True, table="configuration"),
)

DIRECTIVITY = (
    Setting("step_deg", "--step", "step_deg", "float", 5.0, "angle step", "deg", low=0.0,
            high=90.0, low_open=True, table="outputs.directivity"),
    Setting("metric", "--metric", "metric", "str", "peak-spl",
            "level shown against angle besides peak, RMS and SPL: a weighted level of one impact; peak-spl: none",
            choices=tuple(DIRECTIVITY_METRICS), table="outputs.directivity"),
)


@dataclasses.dataclass(frozen=True)
class WaveformSettings(Settings):
    """How a waveform is tabulated: its sampling and, in a room, its window in s."""

    TABLE = WAVEFORM
    samples_per_duration: int = 400
    window: float | None = None


@dataclasses.dataclass(frozen=True)
class DirectivitySettings(Settings):
    """The angles of a directivity and the further level shown against them."""

    TABLE = DIRECTIVITY
    step_deg: float = 5.0
    metric: str = "peak-spl"
