"""Options that define an impact-damper run, shared by ``acoustiviz damper`` and ``acoustiviz auralize``.

Defaults: the paper's Table 1 with d = 4 cm, started as in Figure 5 (x = 0, dx/dt = V0, impact
mass centred and at rest). SI units.
"""

from __future__ import annotations

import dataclasses

from ..app.settings.damper import CONTACT_LAW, MODEL, RUN, SOLVER
from ..app.settings.table import add_option, by_name
from ..constants import DEFAULT_RTOL
from ..constants import SOLVERS as SOLVER_NAMES

__all__ = ["add_model_options", "add_damper_options", "DEFAULT_RTOL", "SOLVER_NAMES"]


def add_model_options(group) -> None:
    """Add the damper model's options (paper eq 15: --M --K --C --m --gap --k-hertz --c1) to ``group``."""
    for s in MODEL:
        add_option(group, s)


def add_damper_options(parser, *, duration_help: str = "simulated time") -> None:
    """Add the damper model, initial velocity and solver options to ``parser``; their ranges are the records'."""
    (clip,) = CONTACT_LAW
    run = by_name(RUN)
    g = parser.add_argument_group("damper (paper eq 15; defaults: Table 1, Figure 5)")
    add_model_options(g)
    add_option(g, clip)
    add_option(g, run["v0"])
    s = parser.add_argument_group("solver")
    add_option(s, dataclasses.replace(run["duration"], doc=duration_help))
    for record in SOLVER:
        add_option(s, record)
    add_option(s, run["rtol"])
