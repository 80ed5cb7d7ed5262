r"""``acoustiviz sweep``: run (or resume) a design sweep of the impact damper.

Example::

    acoustiviz sweep --gap 0.02:0.06:5 --m 0.02:0.08:4 --duration 5 --out DIR \\
        [--executor process|dask://HOST:PORT] [--workers N]

Every swept option takes one value, a range ``start:stop:count`` (both ends included) or a
comma-separated list. Writes ``DIR/sweep.json`` (the settings), ``DIR/sweep.csv`` (one row per
design, as they finish), ``DIR/design_table.csv`` (paper Table 2) and the paper's Figure 6
maps ``DIR/inclination_map.png`` and ``DIR/max_spl_map.png``. Running the same command again
resumes an interrupted sweep and recomputes nothing that finished. This module only parses the
options; :mod:`acoustiviz.app.sweep` does the rest, with the defaults of
:mod:`acoustiviz.constants`.
"""

from __future__ import annotations

from ..constants import (
    DEFAULT_AIR_DENSITY,
    DEFAULT_DURATION,
    DEFAULT_RTOL,
    DEFAULT_SOUND_SPEED,
    DEFAULT_WALL_DISTANCE,
    PAPER_ANGLE_DEG,
    PAPER_DISTANCE,
    PAPER_GAP,
    PAPER_RADIUS,
    PAPER_V0,
    PULSES,
    SOLVERS,
    TABLE1,
)

#: option destination -> parameter of :func:`acoustiviz.app.sweep.sweep_spec`
_SPEC = {"gap": "gap", "m": "m", "mass_ratio": "mass_ratio", "c1": "c1", "k_hertz": "k_hertz",
         "material": "material", "v0": "v0", "distance": "distance", "angle": "angle_deg", "config": "config",
         "M": "M", "K": "K", "C": "C", "clip_tensile": "clip_tensile", "duration": "duration", "solver": "solver",
         "rtol": "rtol", "radius": "radius", "density": "density", "surface": "surface", "pulse": "pulse",
         "pulse_mass": "pulse_mass", "c": "c", "rho": "rho", "wall_distance": "wall_distance",
         "spl_fastest": "n_fastest", "levels": "levels"}


def add_parser(subparsers):
    """Register the ``sweep`` subcommand."""
    p = subparsers.add_parser(
        "sweep",
        help="sweep damper designs: damping inclination and maximum SPL (paper Figure 6, Table 2)",
        description=(
            "Simulate every design of a grid (paper eq 15; defaults Table 1 and the Figure 5 start) "
            "and the sound of every impact at a listener (default the paper's: 0.7 m, 45 deg, "
            "reflecting plane). Swept options take VALUE, START:STOP:COUNT (inclusive) or A,B,C. "
            "Rows are written to OUT/sweep.csv as designs finish; the same command resumes an "
            "interrupted sweep. A design that fails is a row with its reason in the error column."
        ),
    )
    a = p.add_argument_group("swept parameters (VALUE, START:STOP:COUNT or A,B,C; SI units)")
    a.add_argument("--gap", metavar="RANGE", help=f"total free travel d in m (default {PAPER_GAP:g})")
    a.add_argument("--m", metavar="RANGE", help=f"impact mass in kg (default {TABLE1['m']:g})")
    a.add_argument("--mass-ratio", metavar="RANGE", help="mass ratio m/M instead of --m")
    a.add_argument("--c1", metavar="RANGE", help=f"contact damping in N s/m (default {TABLE1['c1']:g})")
    a.add_argument("--k-hertz", metavar="RANGE",
                   help=f"Hertz contact stiffness in N/m^1.5 (default {TABLE1['k_hertz']:g})")
    a.add_argument("--material", metavar="NAMES",
                   help="sphere material(s) from the catalogue instead of --k-hertz: K_HZ from the "
                        "sphere radius and the materials (paper eq 2), density for --radius mass")
    a.add_argument("--v0", metavar="RANGE", help=f"initial main-mass velocity in m/s (default {PAPER_V0:g})")
    a.add_argument("--distance", metavar="RANGE",
                   help=f"listener distance in m from the sphere's centre (default {PAPER_DISTANCE:g})")
    a.add_argument("--angle", metavar="RANGE",
                   help=f"listener angle in degrees from the surface normal (default {PAPER_ANGLE_DEG:g})")
    a.add_argument("--config", metavar="NAMES",
                   help="free, plane (reflecting plane, default) or wall-floor; a comma list sweeps them")
    g = p.add_argument_group("damper (SI units)")
    g.add_argument("--M", type=float, help=f"main mass in kg (default {TABLE1['M']:g})")
    g.add_argument("--K", type=float, help=f"main spring in N/m (default {TABLE1['K']:g})")
    g.add_argument("--C", type=float, help=f"main dashpot in N s/m (default {TABLE1['C']:g})")
    g.add_argument("--clip-tensile", action="store_true", default=None,
                   help="clip the contact force at zero (default: the paper's form, which may pull)")
    g.add_argument("--duration", type=float, help=f"simulated time per design in s (default {DEFAULT_DURATION:g})")
    g.add_argument("--solver", choices=SOLVERS, help="damper solver (default event)")
    g.add_argument("--rtol", type=float,
                   help=f"relative tolerance of the event solver's contacts (default {DEFAULT_RTOL:g})")
    s = p.add_argument_group("sound (SI units)")
    s.add_argument("--radius", metavar="M|mass",
                   help=f"radius of the radiating sphere in m (default {PAPER_RADIUS:g}, the paper's Figure 2 "
                        "sphere, whose levels match the paper's), or 'mass': from the impact mass "
                        "and --density")
    s.add_argument("--density", type=float, metavar="KG/M^3",
                   help="sphere density for --radius mass (default 7800 or the material's)")
    s.add_argument("--surface", metavar="NAME",
                   help="surface material for K_HZ from --material (default: same as the sphere)")
    s.add_argument("--pulse", choices=PULSES,
                   help="acceleration pulse of each impact (default the paper's peak-matched half-sine)")
    s.add_argument("--pulse-mass", choices=("impact", "effective"),
                   help="mass in the pulse: the impact mass alone against a fixed wall (default, paper "
                        "eq 3) or the effective mass m M/(m+M) of the two bodies")
    s.add_argument("--c", type=float, metavar="M/S", help=f"speed of sound (default {DEFAULT_SOUND_SPEED:g})")
    s.add_argument("--rho", type=float, metavar="KG/M^3", help=f"air density (default {DEFAULT_AIR_DENSITY:g})")
    s.add_argument("--wall-distance", type=float, metavar="M",
                   help=f"wall-floor: distance from the wall to the sphere's centre in m "
                        f"(default {DEFAULT_WALL_DISTANCE:g})")
    s.add_argument("--spl-fastest", type=int, metavar="N",
                   help="evaluate the N fastest impacts exactly (the loudest is the fastest); 0: all "
                        "(default 4)")
    s.add_argument("--levels", action="store_true", default=None,
                   help="also render each run's click train at the listener at 96 kHz and report its LAFmax, "
                        "LCpeak and LAeq over the run (columns lafmax_db, lcpeak_db, laeq_db; many times the "
                        "cost of the motion, so off by default)")
    o = p.add_argument_group("execution and outputs")
    o.add_argument("--out", required=True, metavar="DIR", help="output directory (resumed if it exists)")
    o.add_argument("--executor", default="process", metavar="process|dask://HOST:PORT",
                   help="local process pool (default) or a Dask distributed scheduler")
    o.add_argument("--workers", type=int, default=None, metavar="N",
                   help="processes of the local pool (default: all cores; a Dask cluster has its own)")
    o.add_argument("--overwrite", action="store_true",
                   help="if DIR holds a sweep with other settings, move its sweep.csv and sweep.json aside "
                        "(sweep.previous-N.csv and .json, N = 1, 2, ...) and start afresh")
    o.add_argument("--definition", default="two-maxima", choices=("two-maxima", "fit"),
                   help="damping inclination of the design table and map A: paper eq 16 (default) or "
                        "the envelope fit")
    o.add_argument("--band-width", type=float, default=0.001, metavar="M/S",
                   help="width of the design table's inclination bands in m/s (default 0.001 = 0.1 cm/s)")
    o.add_argument("--quiet", action="store_true",
                   help="no progress bar (it is drawn only on a terminal anyway; the resume count is still shown)")
    p.set_defaults(func=run)
    return p


def spec_from_args(args):
    """The :class:`acoustiviz.sweep.SweepSpec` of parsed options (errors name the option)."""
    from ..app.names import user_terms
    from ..app.sweep import SWEEP_OPTIONS, sweep_spec

    given = {param: getattr(args, dest) for dest, param in _SPEC.items() if getattr(args, dest) is not None}
    with user_terms(SWEEP_OPTIONS):
        return sweep_spec(**given)


def run(args) -> int:
    """Run the ``sweep`` subcommand; return the exit status."""
    import sys

    from .._validate import ParameterError, check_positive
    from ..app.budget import check_budget, sweep_estimate
    from ..app.names import user_terms
    from ..app.outputs import check_output_dir
    from ..app.sweep import SWEEP_OPTIONS, check_executor, run_sweep_outputs, sweep_summary
    from ..dynamics import DamperModel

    check_output_dir("--out", args.out)
    swept = {o: getattr(args, o[2:].replace("-", "_")) for o in ("--gap", "--m", "--mass-ratio", "--c1", "--k-hertz",
                                                                 "--material", "--v0", "--distance", "--angle",
                                                                 "--config")}
    duration = check_positive("--duration", DEFAULT_DURATION if args.duration is None else args.duration, "s")
    main = {k: TABLE1[k] if getattr(args, k) is None else getattr(args, k) for k in ("M", "K", "C")}
    try:
        model = DamperModel(**main)
    except ParameterError as exc:
        raise exc.renamed(SWEEP_OPTIONS.get(exc.name, exc.name)) from None
    check_budget(sweep_estimate(swept, model, duration, args.workers or 2), getattr(args, "max_memory", None))
    spec = spec_from_args(args)
    with user_terms(SWEEP_OPTIONS):
        check_executor(args.executor, args.workers)
        result = run_sweep_outputs(spec, args.out, executor=args.executor, workers=args.workers, progress=sys.stderr,
                                   bar=False if args.quiet else None, overwrite=bool(args.overwrite),
                                   definition=args.definition, band_width=args.band_width)
    for line in sweep_summary(result):
        print(line)
    return 0
