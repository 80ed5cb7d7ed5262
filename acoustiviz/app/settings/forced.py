"""Records of the damper in operation: `acoustiviz forced`, a scene's [excitation] and [outputs.operating_noise].

Each option of ``acoustiviz forced`` and each key of a scene's ``[excitation]`` is a record here; the
settings object that checks them together is :class:`~acoustiviz.app.settings.forced_job.ForcedJob`.
"""

from __future__ import annotations

import dataclasses
import math

from ...constants import (
    EXCITATIONS,
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
from .table import Setting

__all__ = ["AMPLITUDE", "AMPLITUDES", "EXCITATION_KIND", "FORCED_EXECUTION", "FORCED", "FORCED_OUTPUTS", "FREQUENCIES",
           "NOISE_LISTENER", "MAX_FORCED_CYCLES", "MAX_FREQUENCIES", "NOISE"]

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
            "neighbours, or none (independent)", choices=FREQUENCY_SWEEPS, table="excitation",
            metavar="{up,down,both,independent}"),
    Setting("solver", "--solver", "solver", "str", "event",
            "event (compliant Hertz contacts), impact-map (instantaneous impacts) or newmark",
            choices=FORCED_SOLVERS, table="excitation", metavar="{event,impact-map,newmark}"),
    Setting("starts", "--starts", "starts", "int", FORCED_STARTS,
            "starts per frequency looking for coexisting attractors: the linear start, rest and the impact mass "
            "spread over the cavity", low=1, high=FORCED_MAX_STARTS, table="excitation"),
    Setting("tolerance", "--tolerance", "tolerance", "float", FORCED_TOLERANCE,
            "Newton residual of a periodic orbit, largest component of P^n(s) - s", "m, m/s",
            low=FORCED_TOLERANCE_RANGE[0], high=FORCED_TOLERANCE_RANGE[1], table="excitation", metavar="TOL"),
    Setting("rtol", "--rtol", "rtol", "float", FORCED_RTOL, "relative tolerance of the contact integration, event "
            "solver", low=FORCED_RTOL_RANGE[0], high=FORCED_RTOL_RANGE[1], table="excitation", metavar="RTOL"),
    Setting("max_cycles", "--max-cycles", "max_cycles", "int", FORCED_MAX_CYCLES,
            "cycles each start runs before its motion is measured as non-periodic", low=FORCED_MIN_CYCLES,
            high=MAX_FORCED_CYCLES, table="excitation"),
    Setting("noise_seconds", "--noise-seconds", "seconds", "float", 1.0,
            "least length of the level interval per frequency; it spans whole periods", "s", low=0.0, high=60.0,
            low_open=True, table="outputs.operating_noise", metavar="S"),
)

#: The kind of excitation: a scene's ``excitation.kind``; the command line tells it by ``--force`` or ``--base``.
EXCITATION_KIND = Setting("kind", None, "kind", "str", "force",
                          "a harmonic force F0 cos(wt) on the main mass, or a base displacement B cos(wt) acting "
                          "through K and C", choices=EXCITATIONS, table="excitation")

#: The excitation's amplitude: F0 in N (``--force``, a force) or B in m (``--base``, a base motion); the
#: cap keeps the response within floating point.
AMPLITUDE = Setting("amplitude", None, "amplitude", "float", 5.0, "F0 in N (kind force) or B in m (kind base)",
                    "N or m", low=0.0, high=1e9, table="excitation")

#: Excitation kind -> the command line's amplitude option: the range of :data:`AMPLITUDE` in the kind's unit.
AMPLITUDES = {
    "force": dataclasses.replace(AMPLITUDE, name="force", option="--force", key=None, table="", default=None,
                                 unit="N", doc="force amplitude F0 on the main mass", metavar="N"),
    "base": dataclasses.replace(AMPLITUDE, name="base", option="--base", key=None, table="", default=None,
                                unit="m", doc="base displacement amplitude B (instead of --force)", metavar="M"),
}

#: How the attractors are run: the impact map's restitution and where the frequencies run.
FORCED_EXECUTION = (
    Setting("restitution", "--restitution", None, "float", None,
            "impact-map restitution (default: the compliant contact's at each speed)", low=0.0, high=1.0,
            low_open=True, metavar="E"),
    Setting("workers", "--workers", None, "int", 1, "processes running the frequencies in parallel", low=1,
            high=math.inf),
    Setting("executor", "--executor", None, "str", "process",
            "where the frequencies run: local processes (--workers) or a Dask scheduler (extra 'distributed')",
            metavar="process|dask://HOST:PORT"),
)

#: The noise in operation: on or off (a scene: whether it asks for ``[outputs.operating_noise]``).
NOISE = Setting("noise", "--noise", None, "bool", True,
                "compute the levels (default; --no-noise leaves the level columns empty)")

#: The listener of the noise in operation, typed as text (a scene's: its first listener).
NOISE_LISTENER = Setting("listener", "--listener", None, "str", None,
                   "listener position in m (default: the paper's, 0.7 m from the sphere at 45 degrees above the "
                   "plane it rests on: 0.495,0,0.514)", metavar="X,Y,Z")

#: The files of ``acoustiviz forced`` (a scene names its own: ``frequency_response.csv`` and ``.png``,
#: ``bifurcation.png``, ``operating_noise.csv`` and ``operating_noise_NAME.wav``).
FORCED_OUTPUTS = (
    Setting("wav", "--wav", None, "str", None,
            "write the damper in operation, each frequency's interval in turn, as a 48 kHz WAV", metavar="PATH"),
    Setting("csv", "--csv", None, "str", None, "write one row per frequency and attractor as CSV", metavar="PATH"),
    Setting("png", "--png", None, "str", None, "plot the frequency response and the bifurcation diagram as PNG",
            metavar="PATH"),
)
