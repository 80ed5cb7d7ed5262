"""Evaluation modes of an optimisation: one function from a design's variables to a row of columns.

A mode is a picklable callable ``evaluate(index, params) -> dict`` (run in a worker of any executor)
with a ``columns`` tuple naming what its rows hold (the columns objectives and constraints may
name). :class:`FreeVibration`, the default, is the damper let go from the Figure 5 start, the row of
``sweep.csv`` (:func:`acoustiviz.sweep.evaluate.evaluate_design`). Another mode (the damper in
operation) plugs in by adding its callable to :data:`MODES`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .levels import SWEEP_LEVEL_COLUMNS
from .spec import FixedSettings, SweepSpec
from .store import ALL_COLUMNS, NUMERIC_COLUMNS

__all__ = ["FreeVibration", "MODES", "FREE_VIBRATION_COLUMNS", "SWEPT_VARIABLES", "failed_row"]

#: The variables of a free-vibration design (the parameters of :func:`acoustiviz.app.sweep.sweep_spec`
#: that ``acoustiviz sweep`` sweeps); ``material`` and ``config`` are names, the others numbers.
SWEPT_VARIABLES = ("gap", "m", "mass_ratio", "c1", "k_hertz", "material", "v0", "distance", "angle_deg", "config")
#: The columns objectives and constraints may name: the numbers of a ``sweep.csv`` row.
FREE_VIBRATION_COLUMNS = tuple(c for c in NUMERIC_COLUMNS if c not in ("design_id", "success"))


#: Variable -> the row's column holding its value.
_COLUMN_OF = {"gap": "gap_m", "m": "mass_kg", "mass_ratio": "mass_ratio", "c1": "c1_n_s_m", "k_hertz": "k_hertz_n_m1_5",
              "material": "material", "v0": "v0_m_s", "distance": "distance_m", "angle_deg": "angle_deg",
              "config": "config"}


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
    """

    settings: FixedSettings

    #: The columns of a row (those of ``sweep.csv``).
    columns = ALL_COLUMNS
    #: The numeric columns objectives and constraints may name.
    objective_columns = FREE_VIBRATION_COLUMNS
    #: The columns that need ``settings.levels``.
    level_columns = SWEEP_LEVEL_COLUMNS

    def design(self, index: int, params: dict):
        """The :class:`~acoustiviz.sweep.spec.Design` of ``params`` (API names, angle in degrees)."""
        from dataclasses import replace

        kw = {k: (v,) for k, v in params.items() if k != "angle_deg"}
        if "angle_deg" in params:
            kw["angle"] = (math.radians(params["angle_deg"]),)
        return replace(SweepSpec(**kw, settings=self.settings).designs()[0], design_id=int(index))

    def __call__(self, index: int, params: dict) -> dict:
        """The row of design ``index`` with variables ``params``; a design that fails is a row with its reason."""
        from .evaluate import evaluate_or_fail

        try:
            design = self.design(index, params)
        except Exception as exc:  # noqa: BLE001 - a design that cannot be built is a row with its reason
            row = failed_row(index, self.columns, f"{type(exc).__name__}: {exc}")
            row.update({_COLUMN_OF[k]: v for k, v in params.items()})
            return row
        return evaluate_or_fail(design, self.settings).row()

    def warm_up(self) -> None:
        """Compile (or load) the kernels a design runs."""
        from .evaluate import warm_up

        warm_up(self.settings)


#: Mode name -> its class, made from the fixed settings.
MODES = {"free": FreeVibration}
