"""Evaluation modes of an optimisation: one function from a design's variables to a row of columns.

A mode is a picklable callable ``evaluate(index, params) -> dict`` (run in a worker of any executor)
with a ``columns`` tuple naming what its rows hold (the columns objectives and constraints may
name). :class:`FreeVibration`, the default, is the damper let go from the Figure 5 start, the row of
``sweep.csv`` (:func:`acoustiviz.sweep.evaluate.evaluate_design`); :class:`InOperation` is the damper
under a harmonic excitation over a band, the row of a sweep in operation
(:func:`acoustiviz.sweep.operation.evaluate_in_operation`). Another mode plugs in by adding its
callable to :data:`MODES`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .levels import SWEEP_LEVEL_COLUMNS
from .operation import OPERATION_COLUMNS, Operation, operation_columns
from .spec import FixedSettings, SweepSpec
from .store import NUMERIC_COLUMNS, row_columns

__all__ = ["FreeVibration", "InOperation", "MODES", "FREE_VIBRATION_COLUMNS", "IN_OPERATION_COLUMNS", "SWEPT_VARIABLES",
           "failed_row"]

#: The variables of a free-vibration design (the parameters of :func:`acoustiviz.app.sweep.sweep_spec`
#: that ``acoustiviz sweep`` sweeps); ``material`` and ``config`` are names, the others numbers.
SWEPT_VARIABLES = ("gap", "m", "mass_ratio", "c1", "k_hertz", "material", "v0", "distance", "angle_deg", "config",
                   "balls", "fill")
#: The columns objectives and constraints may name: the numbers of a ``sweep.csv`` row.
FREE_VIBRATION_COLUMNS = tuple(c for c in NUMERIC_COLUMNS if c not in ("design_id", "success"))
#: The columns objectives and constraints may name in operation: the numbers of a sweep in operation's row.
IN_OPERATION_COLUMNS = tuple(c for c in OPERATION_COLUMNS if c not in ("design_id", "material", "config",
                                                                       "worst_regime", "warm_from", "success",
                                                                       "error"))


#: Variable -> the row's column holding its value.
_COLUMN_OF = {"gap": "gap_m", "m": "mass_kg", "mass_ratio": "mass_ratio", "c1": "c1_n_s_m", "k_hertz": "k_hertz_n_m1_5",
              "material": "material", "v0": "v0_m_s", "distance": "distance_m", "angle_deg": "angle_deg",
              "config": "config", "balls": "balls", "fill": "fill"}


def failed_row(index: int, columns, reason: str) -> dict:
    """The row of an evaluation that failed: NaN numbers, empty names, ``error`` the one-line reason."""
    row = {c: math.nan for c in columns}
    row.update({c: "" for c in ("material", "config") if c in row})
    row.update(design_id=index, success=0, error=" ".join(str(reason).split()) or "unknown error")
    return row


@dataclass(frozen=True)
class FreeVibration:
    """Free vibration: the damper from x = 0, dx/dt = v0 (paper Figure 5), one ``sweep.csv`` row per design.

    Attributes
    ----------
    settings : FixedSettings
        Everything held fixed (the damper, the solver, the sound, ``levels``).
    with_balls : bool
        The designs name their balls and fill (a variable ``balls`` or ``fill``, or the equal total
        mass): the rows then hold the columns ``balls`` and ``fill``.
    """

    settings: FixedSettings
    with_balls: bool = False

    @property
    def columns(self) -> tuple:
        """The columns of a row: those of ``sweep.csv``, with ``balls`` and ``fill`` when the designs name them."""
        return row_columns(self.with_balls)

    #: The numeric columns objectives and constraints may name.
    objective_columns = FREE_VIBRATION_COLUMNS
    #: The columns that need ``settings.levels``.
    level_columns = SWEEP_LEVEL_COLUMNS

    def design(self, index: int, params: dict):
        """The :class:`~acoustiviz.sweep.spec.Design` of ``params`` (API names, angle in degrees)."""
        return _design(self.settings, index, params)

    def __call__(self, index: int, params: dict) -> dict:
        """The row of design ``index`` with variables ``params``; a design that fails is a row with its reason."""
        from .evaluate import evaluate_or_fail

        try:
            design = self.design(index, params)
        except Exception as exc:  # noqa: BLE001 - a design that cannot be built is a row with its reason
            return _unbuilt_row(index, self.columns, params, exc)
        return evaluate_or_fail(design, self.settings).row()

    def warm_up(self) -> None:
        """Compile (or load) the kernels a design runs."""
        from .evaluate import warm_up

        warm_up(self.settings)


@dataclass(frozen=True)
class InOperation:
    """In operation: the damper under ``operation``'s excitation over its band, one sweep-in-operation row per design.

    Each design's attractors are searched from scratch (no warm start from the designs a worker
    evaluated before), so a row depends on the design alone, never on which worker ran it.

    Attributes
    ----------
    settings : FixedSettings
        Everything held fixed (the main system, the air, the listener's surroundings).
    operation : Operation
        The excitation (force F0 in N or base amplitude B in m), the frequencies in Hz and the search.
    with_balls : bool
        The designs name their balls and fill: the rows then hold the columns ``balls`` and ``fill``.
    """

    settings: FixedSettings
    operation: Operation
    with_balls: bool = False

    @property
    def columns(self) -> tuple:
        """The columns of a row: those of a sweep in operation's ``sweep.csv``."""
        return operation_columns(self.with_balls)
    #: The numeric columns objectives and constraints may name.
    objective_columns = IN_OPERATION_COLUMNS
    #: The level columns are always computed in operation (:attr:`Operation.levels`).
    level_columns = ()

    def design(self, index: int, params: dict):
        """The :class:`~acoustiviz.sweep.spec.Design` of ``params`` (API names, angle in degrees)."""
        return _design(self.settings, index, params)

    def __call__(self, index: int, params: dict) -> dict:
        """The row of design ``index`` in operation; a design that fails is a row with its reason."""
        from .operation import evaluate_in_operation_or_fail

        try:
            design = self.design(index, params)
        except Exception as exc:  # noqa: BLE001 - a design that cannot be built is a row with its reason
            return {**_unbuilt_row(index, self.columns, params, exc), "worst_regime": "", "warm_from": -1}
        return evaluate_in_operation_or_fail(design, self.settings, self.operation)

    def warm_up(self) -> None:
        """Compile (or load) the free run's kernels (the contact kernels the search shares)."""
        from .evaluate import warm_up

        warm_up(self.settings)


def _design(settings: FixedSettings, index: int, params: dict):
    """The :class:`~acoustiviz.sweep.spec.Design` ``index`` of ``params`` (API names, angle in degrees)."""
    from dataclasses import replace

    kw = {k: (v,) for k, v in params.items() if k != "angle_deg"}
    if "angle_deg" in params:
        kw["angle"] = (math.radians(params["angle_deg"]),)
    return replace(SweepSpec(**kw, settings=settings).designs()[0], design_id=int(index))


def _unbuilt_row(index: int, columns, params: dict, exc: Exception) -> dict:
    """The failed row of a design that could not be built: its reason and the variables it was given."""
    row = failed_row(index, columns, f"{type(exc).__name__}: {exc}")
    row.update({_COLUMN_OF[k]: v for k, v in params.items() if _COLUMN_OF[k] in row})
    return row


#: Mode name -> its class, made from the fixed settings (in operation, and the :class:`~acoustiviz.sweep.Operation`).
MODES = {"free": FreeVibration, "operation": InOperation}
