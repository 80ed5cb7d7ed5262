r"""``acoustiviz sweep``: run (or resume) a design sweep of the impact damper.

Example::

    acoustiviz sweep --gap 0.02:0.06:5 --m 0.02:0.08:4 --duration 5 --out DIR \\
        [--executor process|dask://HOST:PORT] [--workers N]

Every swept option takes one value, a range ``start:stop:count`` (both ends included) or a
comma-separated list. Writes ``DIR/sweep.json`` (the settings), ``DIR/sweep.csv`` (one row per
design, as they finish), ``DIR/design_table.csv`` (paper Table 2) and the paper's Figure 6
maps ``DIR/inclination_map.png`` and ``DIR/max_spl_map.png``. Running the same command again
resumes an interrupted sweep and recomputes nothing that finished.
"""

from __future__ import annotations

import math

#: library parameter names whose option is not simply ``--name-with-dashes``
_OPTION = {"n_fastest": "--spl-fastest", "radius_mode": "--radius", "out": "--out", "angle": "--angle",
           "fit_window_fraction": "--fit-window", "settling_fraction": "--settling-fraction"}



def _option(name: str) -> str:
    if name.startswith("-"):
        return name
    return _OPTION.get(name, "--" + name.replace("_", "-"))


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
            "interrupted sweep."
        ),
    )
    a = p.add_argument_group("swept parameters (VALUE, START:STOP:COUNT or A,B,C; SI units)")
    a.add_argument("--gap", default="0.04", metavar="RANGE", help="total free travel d in m (default 0.04)")
    a.add_argument("--m", default=None, metavar="RANGE", help="impact mass in kg (default 0.0405)")
    a.add_argument("--mass-ratio", default=None, metavar="RANGE", help="mass ratio m/M instead of --m")
    a.add_argument("--c1", default="20", metavar="RANGE", help="contact damping in N s/m (default 20)")
    a.add_argument("--k-hertz", default=None, metavar="RANGE",
                   help="Hertz contact stiffness in N/m^1.5 (default 5.6e8)")
    a.add_argument("--material", default=None, metavar="NAMES",
                   help="sphere material(s) from the catalogue instead of --k-hertz: K_HZ from the "
                        "sphere radius and the materials (paper eq 2), density for --radius mass")
    a.add_argument("--v0", default="2", metavar="RANGE", help="initial main-mass velocity in m/s (default 2)")
    a.add_argument("--distance", default="0.7", metavar="RANGE",
                   help="listener distance in m from the sphere's centre (default 0.7)")
    a.add_argument("--angle", default="45", metavar="RANGE",
                   help="listener angle in degrees from the surface normal (default 45)")
    a.add_argument("--config", default="plane", metavar="NAMES",
                   help="free, plane (reflecting plane, default) or wall-floor; a comma list sweeps them")
    g = p.add_argument_group("damper (SI units)")
    g.add_argument("--M", type=float, default=0.5, help="main mass in kg (default 0.5)")
    g.add_argument("--K", type=float, default=500.0, help="main spring in N/m (default 500)")
    g.add_argument("--C", type=float, default=0.05, help="main dashpot in N s/m (default 0.05)")
    g.add_argument("--clip-tensile", action="store_true",
                   help="clip the contact force at zero (default: the paper's form, which may pull)")
    g.add_argument("--duration", type=float, default=20.0, help="simulated time per design in s (default 20)")
    g.add_argument("--solver", choices=("event", "impact-map", "newmark"), default="event",
                   help="damper solver (default event)")
    g.add_argument("--rtol", type=float, default=1e-10,
                   help="relative tolerance of the event solver's contacts (default 1e-10)")
    s = p.add_argument_group("sound (SI units)")
    s.add_argument("--radius", default="0.01905", metavar="M|mass",
                   help="radius of the radiating sphere in m (default 0.01905, the paper's Figure 2 "
                        "sphere, whose levels match the paper's), or 'mass': from the impact mass "
                        "and --density")
    s.add_argument("--density", type=float, default=None, metavar="KG/M^3",
                   help="sphere density for --radius mass (default 7800 or the material's)")
    s.add_argument("--surface", default=None, metavar="NAME",
                   help="surface material for K_HZ from --material (default: same as the sphere)")
    s.add_argument("--pulse", default="half-sine", choices=("half-sine", "impulse-matched", "hertz"),
                   help="acceleration pulse of each impact (default the paper's peak-matched half-sine)")
    s.add_argument("--pulse-mass", default="impact", choices=("impact", "effective"),
                   help="mass in the pulse: the impact mass alone against a fixed wall (default, paper "
                        "eq 3) or the effective mass m M/(m+M) of the two bodies")
    s.add_argument("--c", type=float, default=343.2, metavar="M/S", help="speed of sound (default 343.2)")
    s.add_argument("--rho", type=float, default=1.204, metavar="KG/M^3", help="air density (default 1.204)")
    s.add_argument("--wall-distance", type=float, default=0.05, metavar="M",
                   help="wall-floor: distance from the wall to the sphere's centre in m (default 0.05)")
    s.add_argument("--spl-fastest", type=int, default=4, metavar="N",
                   help="evaluate the N fastest impacts exactly (the loudest is the fastest); 0: all "
                        "(default 4)")
    o = p.add_argument_group("execution and outputs")
    o.add_argument("--out", required=True, metavar="DIR", help="output directory (resumed if it exists)")
    o.add_argument("--executor", default="process", metavar="process|dask://HOST:PORT",
                   help="local process pool (default) or a Dask distributed scheduler")
    o.add_argument("--workers", type=int, default=None, metavar="N",
                   help="processes of the local pool (default: all cores; a Dask cluster has its own)")
    o.add_argument("--overwrite", action="store_true",
                   help="if DIR holds a sweep with other settings, move its sweep.csv aside and start afresh")
    o.add_argument("--definition", default="two-maxima", choices=("two-maxima", "fit"),
                   help="damping inclination of the design table and map A: paper eq 16 (default) or "
                        "the envelope fit")
    o.add_argument("--band-width", type=float, default=0.001, metavar="M/S",
                   help="width of the design table's inclination bands in m/s (default 0.001 = 0.1 cm/s)")
    o.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)
    return p


def spec_from_args(args):
    """Build the :class:`acoustiviz.sweep.SweepSpec` from parsed options (errors name the option)."""
    from .._validate import ParameterError, check_range
    from ..sweep import Settings, SweepSpec, parse_values

    if args.m is not None and args.mass_ratio is not None:
        raise ParameterError("--m", "give either --m or --mass-ratio, not both")
    if args.k_hertz is not None and args.material is not None:
        raise ParameterError("--k-hertz", "give either --k-hertz or --material, not both")
    radius_text = str(args.radius).strip().lower()
    try:
        if radius_text == "mass":
            radius_mode, radius = "from-mass", 0.01905
        else:
            radius_mode = "fixed"
            try:
                radius = float(radius_text)
            except ValueError:
                raise ParameterError("--radius", f"expected a radius in m or 'mass', got {args.radius!r}") from None
        configs = parse_values("--config", args.config, str)
        angles_deg = parse_values("--angle", args.angle)
        limit = 180.0 if set(configs) == {"free"} else 90.0
        for a in angles_deg:
            check_range("--angle", a, 0.0, limit, unit="deg")
        settings = Settings(
            M=args.M, K=args.K, C=args.C, clip_tensile=bool(args.clip_tensile), duration=args.duration,
            solver=args.solver, rtol=args.rtol, radius_mode=radius_mode, radius=radius, density=args.density,
            surface=args.surface, pulse=args.pulse, pulse_mass=args.pulse_mass, c=args.c, rho=args.rho,
            wall_distance=args.wall_distance, n_fastest=args.spl_fastest,
        )
        return SweepSpec(
            gap=parse_values("--gap", args.gap),
            m=None if args.mass_ratio is not None else parse_values("--m", args.m or "0.0405"),
            mass_ratio=None if args.mass_ratio is None else parse_values("--mass-ratio", args.mass_ratio),
            c1=parse_values("--c1", args.c1),
            k_hertz=None if args.material is not None else parse_values("--k-hertz", args.k_hertz or "5.6e8"),
            material=None if args.material is None else parse_values("--material", args.material, str),
            v0=parse_values("--v0", args.v0),
            distance=parse_values("--distance", args.distance),
            angle=tuple(math.radians(a) for a in angles_deg),
            config=configs,
            settings=settings,
        )
    except ParameterError as exc:
        raise ParameterError(_option(exc.name), str(exc).split(": ", 1)[-1]) from None


def run(args) -> int:
    """Run the ``sweep`` subcommand; return the exit status."""
    import sys
    import time

    from .._validate import ParameterError, check_positive
    from ..app.budget import check_budget, sweep_estimate
    from ..app.outputs import check_output_dir
    from ..dynamics import DamperModel
    from ..pipeline import write_sweep_outputs
    from ..sweep import run_sweep

    check_output_dir("--out", args.out)
    swept = {o: getattr(args, o[2:].replace("-", "_")) for o in ("--gap", "--m", "--mass-ratio", "--c1", "--k-hertz",
                                                                 "--material", "--v0", "--distance", "--angle",
                                                                 "--config")}
    check_positive("--duration", args.duration, "s")
    try:
        model = DamperModel(M=args.M, K=args.K, C=args.C)
    except ParameterError as exc:
        raise exc.renamed(_option(exc.name)) from None
    check_budget(sweep_estimate(swept, model, args.duration, args.workers or 2), getattr(args, "max_memory", None))
    spec = spec_from_args(args)
    check_positive("--band-width", args.band_width, "m/s")
    if args.workers is not None and args.workers < 1:
        raise ParameterError("--workers", f"must be >= 1, got {args.workers}")
    executor = args.executor
    if executor != "process" and not str(executor).startswith("dask://"):
        raise ParameterError("--executor", f"expected 'process' or 'dask://HOST:PORT', got {executor!r}")
    t0 = time.perf_counter()
    try:
        table = run_sweep(spec, args.out, executor=executor, workers=args.workers,
                          progress=None if args.quiet else sys.stderr, overwrite=bool(args.overwrite))
    except ParameterError as exc:
        raise ParameterError(_option(exc.name), str(exc).split(": ", 1)[-1]) from None
    elapsed = time.perf_counter() - t0
    bands, paths, others = write_sweep_outputs(table, args.out, definition=args.definition, band_width=args.band_width)
    n = len(table)
    print(f"sweep: {n} designs in {args.out} ({elapsed:.1f} s this run)")
    for pth in paths:
        print(f"wrote {pth}")
    if others:
        print(f"maps skipped: they need only --gap and --m swept (also swept: {', '.join(others)})")
    best = max(bands, key=lambda b: b.decrease_db, default=None)
    if best is not None:
        print(f"largest acoustic saving at equal damping ({args.definition}): {best.decrease_db:.1f} dB in the band "
              f"{100 * best.low:.3g}-{100 * best.high:.3g} cm/s ({best.n_designs} designs)")
    return 0
