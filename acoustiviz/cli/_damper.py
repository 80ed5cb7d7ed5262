"""Options that define an impact-damper run, shared by ``acoustiviz damper`` and ``acoustiviz auralize``.

Defaults: the paper's Table 1 with d = 4 cm, started as in Figure 5 (x = 0, dx/dt = V0, impact
mass centred and at rest). SI units.
"""

from __future__ import annotations

__all__ = ["add_damper_options", "DEFAULT_RTOL", "SOLVER_NAMES"]

#: The solvers of :func:`acoustiviz.dynamics.simulate`.
SOLVER_NAMES = ("event", "newmark", "impact-map")
#: The event solver's default relative tolerance, as in :func:`acoustiviz.dynamics.simulate`.
DEFAULT_RTOL = 1e-12


def add_damper_options(parser, *, duration_help: str = "simulated time in s (default %(default)s)") -> None:
    """Add the damper model, initial velocity and solver options to ``parser``."""
    g = parser.add_argument_group("damper (paper eq 15; defaults: Table 1, Figure 5)")
    g.add_argument("--M", type=float, default=0.5, metavar="KG", help="main mass in kg (default %(default)s)")
    g.add_argument("--K", type=float, default=500.0, metavar="N/M", help="main spring in N/m (default %(default)s)")
    g.add_argument("--C", type=float, default=0.05, metavar="N*S/M", help="main dashpot in N s/m (default %(default)s)")
    g.add_argument("--m", type=float, default=0.0405, metavar="KG", help="impact mass in kg (default %(default)s)")
    g.add_argument("--gap", type=float, default=0.04, metavar="M",
                   help="total free travel d of the impact mass in m (default %(default)s)")
    g.add_argument("--k-hertz", type=float, default=5.6e8, metavar="N/M^1.5",
                   help="Hertz contact stiffness in N/m^1.5 (default %(default)s)")
    g.add_argument("--c1", type=float, default=20.0, metavar="N*S/M",
                   help="contact damping in N s/m (default %(default)s)")
    g.add_argument("--clip-tensile", action="store_true",
                   help="clip the contact force at zero (default: the paper's form, which may pull)")
    g.add_argument("--v0", type=float, default=2.0, metavar="M/S",
                   help="initial main-mass velocity in m/s (default %(default)s)")
    s = parser.add_argument_group("solver")
    s.add_argument("--duration", type=float, default=20.0, metavar="S", help=duration_help)
    s.add_argument("--solver", choices=SOLVER_NAMES, default="event",
                   help="event (default; exact free flight, adaptive contacts), newmark (the paper's "
                        "fixed-step scheme) or impact-map (instantaneous impacts)")
    s.add_argument("--dt", type=float, default=None, metavar="S",
                   help="Newmark step in s (default: 1/50 of the shortest possible contact)")
    s.add_argument("--rtol", type=float, default=DEFAULT_RTOL,
                   help="relative tolerance of the event solver's contacts (default %(default)s)")
