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
    """Build and run the damper of the shared options (:mod:`acoustiviz.app.damper`), errors naming options.

    Returns
    -------
    model : DamperModel
    run : acoustiviz.app.damper.DamperRun
    """
    from .._validate import check_positive
    from ..app.budget import check_budget, damper_estimate
    from ..app.damper import damper_model, run_damper
    from ..app.names import DAMPER_OPTIONS, user_terms

    with user_terms(DAMPER_OPTIONS):
        model = damper_model(M=args.M, K=args.K, C=args.C, m=args.m, gap=args.gap, k_hertz=args.k_hertz,
                             c1=args.c1, clip_tensile=bool(args.clip_tensile))
        duration = check_positive("duration", args.duration, "s")
        if args.dt is not None:
            check_positive("dt", args.dt, "s")
        check_budget(damper_estimate(model, duration, solver=args.solver, dt=args.dt, options=("--duration",)),
                     getattr(args, "max_memory", None))
        run = run_damper(model, args.duration, solver=args.solver, v0=args.v0, rtol=args.rtol, dt=args.dt)
    return model, run
