"""``acoustiviz design``: the quietest design of a sweep for a target damping inclination.

Example::

    acoustiviz design --sweep DIR --inclination 0.008 --tolerance 0.001

Among the designs of ``DIR/sweep.csv`` whose damping inclination lies within the tolerance of
the target, prints the quietest (m, d), its maximum SPL, and by how many dB it is quieter than
the loudest (the acoustic-based design of the paper, Table 2).
"""

from __future__ import annotations


def add_parser(subparsers):
    """Register the ``design`` subcommand."""
    p = subparsers.add_parser(
        "design",
        help="quietest damper design of a sweep for a target damping inclination (paper Table 2)",
        description=(
            "Read a sweep directory (acoustiviz sweep --out DIR) and answer: among the designs whose "
            "damping inclination is within TOLERANCE of INCLINATION, which (m, d) is quietest, and by "
            "how many dB over the loudest. Inclinations in m/s (0.008 m/s = 0.8 cm/s)."
        ),
    )
    p.add_argument("--sweep", required=True, metavar="DIR", help="sweep directory (holds sweep.csv)")
    p.add_argument("--inclination", required=True, type=float, metavar="M/S",
                   help="target damping inclination in m/s")
    p.add_argument("--tolerance", type=float, default=0.0005, metavar="M/S",
                   help="accepted deviation in m/s (default 0.0005)")
    p.add_argument("--definition", default="two-maxima", choices=("two-maxima", "fit"),
                   help="damping inclination: paper eq 16 from the first two maxima (default) or the "
                        "linear fit of the maxima envelope")
    p.add_argument("--table", action="store_true",
                   help="also print the design table (paper Table 2) of the whole sweep")
    p.add_argument("--band-width", type=float, default=0.001, metavar="M/S",
                   help="band width of --table in m/s (default 0.001)")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    """Run the ``design`` subcommand; return the exit status."""
    from pathlib import Path

    from .._validate import ParameterError, check_finite, check_nonnegative, check_positive
    from ..sweep import design, design_table, load_sweep

    check_finite("--inclination", args.inclination)
    check_nonnegative("--tolerance", args.tolerance, "m/s")
    check_positive("--band-width", args.band_width, "m/s")
    if not Path(args.sweep).is_dir():
        raise ParameterError("--sweep", f"no such directory: {args.sweep}")
    try:
        table = load_sweep(args.sweep)
    except ParameterError as exc:
        raise ParameterError("--sweep", str(exc).split(": ", 1)[-1]) from None
    if not table.complete:
        print(f"note: the sweep is unfinished ({len(table)} of {len(table.spec.designs())} designs)")
    try:
        choice = design(table, args.inclination, args.tolerance, definition=args.definition)
    except ParameterError as exc:
        raise ParameterError(f"--{exc.name}", str(exc).split(": ", 1)[-1]) from None
    print(choice.summary())
    if args.table:
        print()
        print(f"design table ({args.definition} damping inclination, bands of {100 * args.band_width:g} cm/s):")
        print(f"{'e (cm/s)':>9} {'n':>4} {'min SPLmax':>11} {'max SPLmax':>11} {'decrease':>9}  quietest (m, d)")
        for b in design_table(table, definition=args.definition, width=args.band_width):
            print(f"{100 * b.centre:9.2f} {b.n_designs:4d} {b.min_spl_db:11.1f} {b.max_spl_db:11.1f} "
                  f"{b.decrease_db:9.1f}  {1000 * b.quietest_mass:.1f} g, {100 * b.quietest_gap:.2f} cm")
    return 0
