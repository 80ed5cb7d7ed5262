"""Settings of a design sweep: ``acoustiviz sweep`` and a scene's ``[outputs.sweep]``."""

from __future__ import annotations

import dataclasses

from ...constants import DEFAULT_DURATION
from .base import Settings
from .table import Setting

__all__ = ["SWEEP", "SweepSettings"]

SWEEP = (
    # A scene's sweep is a quick look (5 s of motion per design); the command runs the paper's 20 s.
    Setting("duration", "--duration", "duration_s", "float", DEFAULT_DURATION, "simulated time per design", "s",
            low=0.0, high=1e4, low_open=True, scene_default=5.0, table="outputs.sweep"),
)


@dataclasses.dataclass(frozen=True)
class SweepSettings(Settings):
    """How long each design of a sweep runs."""

    TABLE = SWEEP
    duration: float = DEFAULT_DURATION
