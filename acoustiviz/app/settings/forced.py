"""Settings of the damper in operation: `acoustiviz forced`, a scene's [excitation] and [outputs.operating_noise]."""

from __future__ import annotations

import dataclasses

from ...constants import (
    FORCED_MAX_CYCLES,
    FORCED_MAX_STARTS,
    FORCED_MIN_CYCLES,
    FORCED_RTOL,
    FORCED_RTOL_RANGE,
    FORCED_SOLVERS,
    FORCED_STARTS,
    FORCED_TOLERANCE,
    FORCED_TOLERANCE_RANGE,
    FREQUENCY_SWEEPS,
)
from .base import Settings
from .table import Setting

__all__ = ["AMPLITUDE", "FORCED", "FREQUENCIES", "ForcedSettings", "MAX_FORCED_CYCLES", "MAX_FREQUENCIES"]

#: Most cycles one start runs before its motion is measured (a bound on the work of each start).
MAX_FORCED_CYCLES = 1_000_000
#: Largest number of frequencies of one run.
MAX_FREQUENCIES = 10_000

#: The forcing frequencies, each in its range; written as text, START:STOP:COUNT (both ends included), a comma
#: list F1,F2,... or one value, and read by :func:`acoustiviz.app.settings.parse.parse_frequencies` alone.
FREQUENCIES = Setting("frequencies", "--freq", "frequencies_hz", "float", "3:7:9",
                      "forcing frequencies: START:STOP:COUNT (both ends included), a comma list F1,F2,... or one "
                      f"value; at most {MAX_FREQUENCIES}, none repeated", "Hz", low=0.0, high=1e4, low_open=True,
                      table="excitation", metavar="START:STOP:COUNT|F1,F2,...")

FORCED = (
    Setting("sweep", "--sweep", "sweep", "str", "up",
            "continuation: the attractors of each frequency also start the next higher (up), lower (down) or both "
            "neighbours, or none (independent)", choices=FREQUENCY_SWEEPS, table="excitation"),
    Setting("solver", "--solver", "solver", "str", "event",
            "event (compliant Hertz contacts), impact-map (instantaneous impacts) or newmark",
            choices=FORCED_SOLVERS, table="excitation"),
    Setting("starts", "--starts", "starts", "int", FORCED_STARTS,
            "starts per frequency looking for coexisting attractors: the linear start, rest and the impact mass "
            "spread over the cavity", low=1, high=FORCED_MAX_STARTS, table="excitation"),
    Setting("tolerance", "--tolerance", "tolerance", "float", FORCED_TOLERANCE,
            "Newton residual of a periodic orbit, largest component of P^n(s) - s", "m, m/s",
            low=FORCED_TOLERANCE_RANGE[0], high=FORCED_TOLERANCE_RANGE[1], table="excitation"),
    Setting("rtol", "--rtol", "rtol", "float", FORCED_RTOL, "relative tolerance of the contact integration, event "
            "solver", low=FORCED_RTOL_RANGE[0], high=FORCED_RTOL_RANGE[1], table="excitation"),
    Setting("max_cycles", "--max-cycles", "max_cycles", "int", FORCED_MAX_CYCLES,
            "cycles each start runs before its motion is measured as non-periodic", low=FORCED_MIN_CYCLES,
            high=MAX_FORCED_CYCLES, table="excitation"),
    Setting("noise_seconds", "--noise-seconds", "seconds", "float", 1.0,
            "least length of the level interval per frequency; it spans whole periods", "s", low=0.0, high=60.0,
            low_open=True, table="outputs.operating_noise"),
)


#: The excitation's amplitude: F0 in N (``--force``, a force) or B in m (``--base``, a base motion); the
#: cap keeps the response within floating point.
AMPLITUDE = Setting("amplitude", None, "amplitude", "float", 5.0, "F0 in N (kind force) or B in m (kind base)",
                    "N or m", low=0.0, high=1e9, table="excitation")


@dataclasses.dataclass(frozen=True)
class ForcedSettings(Settings):
    """How the attractors of each forcing frequency are found and their noise measured."""

    TABLE = FORCED
    sweep: str = "up"
    solver: str = "event"
    starts: int = FORCED_STARTS
    tolerance: float = FORCED_TOLERANCE
    rtol: float = FORCED_RTOL
    max_cycles: int = FORCED_MAX_CYCLES
    noise_seconds: float = 1.0


@dataclasses.dataclass(frozen=True)
class ForcedJob:
    """One run of the damper in operation as given: what to excite, where to listen, what to write.

    ``model`` holds the damper's parameters (:func:`acoustiviz.app.damper.damper_model`); ``freq``
    the frequencies in Hz as text (``START:STOP:COUNT`` or a comma list); ``force`` in N or
    ``base`` in m (one of them); ``listener`` ``X,Y,Z`` in m as text; ``room`` the room's settings
    (None: the free plane); ``max_memory`` the working-memory cap in MB.
    """

    settings: ForcedSettings
    model: dict
    freq: str
    force: float | None = None
    base: float | None = None
    restitution: float | None = None
    workers: int = 1
    executor: str = "process"
    noise: bool = True
    listener: str | None = None
    wav: str | None = None
    csv: str | None = None
    png: str | None = None
    room: dict | None = None
    max_memory: float | None = None

    def __post_init__(self):
        for option, kind in (("--force", "force"), ("--base", "base")):
            value = getattr(self, kind)
            if value is not None:  # the scene key's range (:data:`AMPLITUDE`), in this option's unit
                unit = "N" if kind == "force" else "m"
                object.__setattr__(self, kind, dataclasses.replace(AMPLITUDE, unit=unit).check(value, option))

