"""The impact damper in operation: harmonic excitation, periodic orbits, attractors, frequency response.

The public names of forced operation, gathered from the modules that implement them (imports
point one way, ``forced -> _forced_response -> _attractors -> _shooting -> _forced_steady``):

* :mod:`._forced_steady`: the excitation, the settings, the solvers advanced cycle by cycle
  (``"event"``, ``"impact-map"``, ``"newmark"``), :class:`SteadyState`;
* :mod:`._shooting`: periodic orbits ``P^n(s) = s`` on the Poincaré section at forcing phase 0
  by Newton's method, with their Floquet multipliers;
* :mod:`._attractors`: several starts per frequency, each run to its attractor, periodic orbits
  refined by shooting, non-periodic motion measured with batch statistics and its largest
  Lyapunov exponent;
* :mod:`._forced_response`: the attractors over a list of frequencies, with continuation.
"""

from __future__ import annotations

from ..constants import EXCITATIONS, FORCED_SOLVERS
from ._attractors import (
    SCREENED_CHECKPOINT_RETURN,
    FrequencyAttractors,
    attractors_at,
    same_motion,
    start_states,
    steady_state,
)
from ._forced_response import (
    SWEEPS,
    AttractorResponse,
    FrequencyResponse,
    _seed,
    attractor_response,
    describe,
    frequency_response,
)
from ._forced_steady import (
    MAX_PERIOD,
    NONPERIODIC_CYCLES,
    Excitation,
    SteadyState,
    SteadyStateOptions,
    _params,
    _together,
    check_settings,
    default_steps_per_cycle,
    linear_start,
    simulate_cycles,
)
from ._shooting import PoincareMap, ShootResult, section_scale, shoot

#: ``(state, period)`` that continues an attractor elsewhere (a neighbouring frequency or design): the
#: first section point of a periodic orbit with its period, the final state of a non-periodic motion.
continuation_seed = _seed

__all__ = [
    "continuation_seed",
    "SCREENED_CHECKPOINT_RETURN",
    "EXCITATIONS",
    "FORCED_SOLVERS",
    "MAX_PERIOD",
    "NONPERIODIC_CYCLES",
    "SWEEPS",
    "AttractorResponse",
    "Excitation",
    "SteadyStateOptions",
    "FrequencyAttractors",
    "FrequencyResponse",
    "PoincareMap",
    "ShootResult",
    "SteadyState",
    "_params",
    "_together",
    "attractor_response",
    "attractors_at",
    "check_settings",
    "default_steps_per_cycle",
    "describe",
    "frequency_response",
    "linear_start",
    "same_motion",
    "section_scale",
    "shoot",
    "simulate_cycles",
    "start_states",
    "steady_state",
]
