"""``acoustiviz design``: the quietest design of a sweep for a target damping inclination.

Example::

    acoustiviz design --sweep DIR --inclination 0.008 --tolerance 0.001

Among the designs of ``DIR/sweep.csv`` whose damping inclination lies within the tolerance of
the target, prints the quietest (m, d), its maximum SPL, and by how many dB it is quieter than
the loudest (the acoustic-based design of the paper, Table 2); ``--rank-by lafmax_db`` (or any
numeric column) ranks by another level. This module only parses the
options; :func:`acoustiviz.app.sweep.design_report` answers.
"""

from __future__ import annotations

from ..app.settings.design import DESIGN
from ..app.settings.table import add_option


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
    add_option(p, DESIGN[0], metavar="M/S", required=True)
    add_option(p, DESIGN[1], metavar="M/S")
    p.add_argument("--definition", default="two-maxima", choices=("two-maxima", "fit"),
                   help="damping inclination: paper eq 16 from the first two maxima (default) or the "
                        "linear fit of the maxima envelope")
    p.add_argument("--table", action="store_true",
                   help="also print the design table (paper Table 2) of the whole sweep")
    p.add_argument("--band-width", type=float, default=0.001, metavar="M/S",
                   help="band width of --table in m/s (default 0.001)")
    p.add_argument("--rank-by", default="max_spl_db", metavar="COLUMN",
                   help="numeric column of sweep.csv whose smallest value is the quietest: max_spl_db (default, "
                        "paper Table 2), lafmax_db, lcpeak_db, laeq_db (sweeps run with --levels), "
                        "settling_time_s, ...")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    """Run the ``design`` subcommand; return the exit status."""
    from pathlib import Path

    from ..app.budget import check_budget, design_estimate
    from ..app.names import user_terms
    from ..app.sweep import DESIGN_OPTIONS, design_report

    check_budget(design_estimate(Path(args.sweep) / "sweep.csv"), args.max_memory)
    with user_terms(DESIGN_OPTIONS):
        lines = design_report(args.sweep, args.inclination, args.tolerance, definition=args.definition,
                              table=args.table, band_width=args.band_width, rank_by=args.rank_by)
    for line in lines:
        print(line)
    return 0
