"""Options that define an impact-damper run, shared by ``acoustiviz damper`` and ``acoustiviz auralize``.

Defaults: the paper's Table 1 with d = 4 cm, started as in Figure 5 (x = 0, dx/dt = V0, impact
mass centred and at rest). SI units.
"""

from __future__ import annotations

from ..constants import DEFAULT_DURATION, DEFAULT_RTOL, PAPER_GAP, PAPER_V0, TABLE1
from ..constants import SOLVERS as SOLVER_NAMES

__all__ = ["add_model_options", "add_damper_options", "damper_from_args", "DEFAULT_RTOL", "SOLVER_NAMES"]


def add_model_options(group) -> None:
    """Add the damper model's options (paper eq 15: --M --K --C --m --gap --k-hertz --c1) to ``group``."""
    g = group
    g.add_argument("--M", type=float, default=TABLE1["M"], metavar="KG", help="main mass in kg (default %(default)s)")
    g.add_argument("--K", type=float, default=TABLE1["K"], metavar="N/M",
                   help="main spring in N/m (default %(default)s)")
    g.add_argument("--C", type=float, default=TABLE1["C"], metavar="N*S/M",
                   help="main dashpot in N s/m (default %(default)s)")
    g.add_argument("--m", type=float, default=TABLE1["m"], metavar="KG", help="impact mass in kg (default %(default)s)")
    g.add_argument("--gap", type=float, default=PAPER_GAP, metavar="M",
                   help="total free travel d of the impact mass in m (default %(default)s)")
    g.add_argument("--k-hertz", type=float, default=TABLE1["k_hertz"], metavar="N/M^1.5",
                   help="Hertz contact stiffness in N/m^1.5 (default %(default)s)")
    g.add_argument("--c1", type=float, default=TABLE1["c1"], metavar="N*S/M",
                   help="contact damping in N s/m (default %(default)s)")


def add_damper_options(parser, *, duration_help: str = "simulated time in s (default %(default)s)") -> None:
    """Add the damper model, initial velocity and solver options to ``parser``."""
    g = parser.add_argument_group("damper (paper eq 15; defaults: Table 1, Figure 5)")
    add_model_options(g)
    g.add_argument("--clip-tensile", action="store_true",
                   help="clip the contact force at zero (default: the paper's form, which may pull)")
    g.add_argument("--v0", type=float, default=PAPER_V0, metavar="M/S",
                   help="initial main-mass velocity in m/s (default %(default)s)")
    s = parser.add_argument_group("solver")
    s.add_argument("--duration", type=float, default=DEFAULT_DURATION, metavar="S", help=duration_help)
    s.add_argument("--solver", choices=SOLVER_NAMES, default="event",
                   help="event (default; exact free flight, adaptive contacts), newmark (the paper's "
                        "fixed-step scheme) or impact-map (instantaneous impacts)")
    s.add_argument("--dt", type=float, default=None, metavar="S",
                   help="Newmark step in s (default: 1/50 of the shortest possible contact)")
    s.add_argument("--rtol", type=float, default=DEFAULT_RTOL,
                   help="relative tolerance of the event solver's contacts (default %(default)s)")


def damper_from_args(args):
    """Build and run the damper of the shared options (:func:`acoustiviz.app.damper.run_damper_settings`).

    Returns
    -------
    model : DamperModel
    run : acoustiviz.app.damper.DamperRun
    """
    import dataclasses

    from ..app.damper import run_damper_settings
    from ..app.settings.auralize import DamperSettings

    names = {f.name for f in dataclasses.fields(DamperSettings)}
    settings = DamperSettings(**{k: v for k, v in vars(args).items() if k in names})
    return run_damper_settings(settings, getattr(args, "max_memory", None))
