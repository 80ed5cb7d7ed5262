"""Impact-damper dynamics (paper eq 15): model, solvers, impact table, exact maxima, metrics.

Modules: ``model`` (the damper and its start), ``solve`` (:func:`simulate` and its three
solvers), ``forced`` (harmonic excitation, steady states, frequency response), ``result``
(impact table, energy balance, turning points), ``maxima`` (positive maxima, exact from a run),
``metrics`` (damping inclination, eq 16, and settling time). The compiled kernels serve free
decay and forced operation alike: ``_flight`` (closed-form flight, contact detection),
``_contact`` (DOP853 contact, tableau vendored in ``_dop853``), ``_newmark``, ``_status``,
``_records`` (the named records the kernels take and return), and the drivers ``_kernels``
(free decay) and ``_forced_driver`` (forced operation). ``balls`` (cavities of balls in columns on
the main mass) and ``balls_solve`` (:func:`simulate_balls`, compiled kernel ``_balls``) extend the
damper to multi-unit and particle-column dampers.
Files are written by :mod:`acoustiviz.output.tables`, never here.

Wall convention: ``wall = +1`` is struck when ``z = y - x`` reaches ``+d/2`` (the impact mass
moving in ``+x`` relative to the main mass), ``wall = -1`` when ``z`` reaches ``-d/2``.

The physics here imports nothing from plotting or the command line.
"""

from .maxima import Maxima, exact_maxima
from .model import TABLE1, DamperModel, InitialState
from .result import EnergyBalance, Extrema, ImpactTable, SimulationResult
from .sequence import ImpactSequence
from .solve import (
    METHODS,
    SOLVERS,
    AccuracyWarning,
    central_difference_excursion,
    cheapest_solver,
    default_step,
    explicit_step_limit,
    shortest_contact,
    simulate,
    solver_method,
)

__all__ = [
    "BallState",
    "Cavity",
    "MultiBallModel",
    "equal_balls",
    "BallImpactTable",
    "MultiBallResult",
    "simulate_balls",
    "TABLE1",
    "DamperModel",
    "InitialState",
    "EnergyBalance",
    "Extrema",
    "Maxima",
    "exact_maxima",
    "ImpactTable",
    "ImpactSequence",
    "SimulationResult",
    "SOLVERS",
    "AccuracyWarning",
    "central_difference_excursion",
    "cheapest_solver",
    "default_step",
    "explicit_step_limit",
    "shortest_contact",
    "simulate",
    "METHODS",
    "solver_method",
]


#: The several-balls damper, imported when first asked for (its compiled kernels are not needed by one ball).
_BALLS = {"BallState": "balls", "Cavity": "balls", "MultiBallModel": "balls", "equal_balls": "balls",
          "BallImpactTable": "balls_solve", "MultiBallResult": "balls_solve", "simulate_balls": "balls_solve"}


def __getattr__(name: str):
    if name in _BALLS:
        import importlib

        return getattr(importlib.import_module(f".{_BALLS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
