"""``acoustiviz directivity``: peak SPL and RMS pressure versus angle on a circle (paper Figure 3)."""

from __future__ import annotations

from ..app.settings.impact import DIRECTIVITY
from ..app.settings.table import add_option
from ._impact import add_impact_options, add_observer_options, add_room_options


def add_parser(subparsers) -> None:
    """Register the ``directivity`` subcommand."""
    p = subparsers.add_parser(
        "directivity",
        help="peak SPL and RMS pressure versus angle around the sphere (CSV and PNG)",
        description="Pressure radiated by one impact, on a circle around the sphere's centre. Angles "
        "are in degrees from the acceleration axis (the normal of the struck surface): 0 to 90 for "
        "--config plane and wall-floor (the circle lies in the plane through the centre normal to the "
        "wall, on the side away from it), 0 to 180 for free. peak_pa is max|p|, spl_db = "
        "20 log10(peak_pa / 20e-6), and rms_pa is the RMS over a window of the same length at every "
        "angle, starting at the first arrival and holding the whole pulse from every image plus ten "
        "decay times a/c of the sphere. With --room the circle lies in the room (0 to 90 degrees for a sphere on "
        "the struck surface, else 0 to 180), its radius --distance at most the distance from the sphere's centre "
        "to the walls it would cross, and the levels include every image that arrives within the window: each "
        "angle's window starts at its first arrival and ends by --duration from the start of contact.",
    )
    add_impact_options(p)
    add_observer_options(p, angle=False)
    add_room_options(p, duration=True)
    add_option(p, DIRECTIVITY[0], metavar="DEG")
    p.add_argument("--metric", default="peak-spl", metavar="NAME",
                   help="level shown against angle: peak-spl (default, max|p|), rms (RMS level over the window), "
                        "or a weighted level computed from the impact's pressure at each angle, band-limited at "
                        "96 kHz: lcpeak, lafmax, laeq (over 1 s from the first arrival), sel-a, lzpeak, lasmax, "
                        "lzeq, sel")
    p.add_argument("--csv", default=None, metavar="PATH",
                   help="write columns angle_deg,peak_pa,rms_pa,spl_db and, for another --metric, its column "
                        "(rms_db, lcpeak_db, lafmax_db, laeq_db, sel_a_db, ...)")
    p.add_argument("--png", default=None, metavar="PATH", help="draw SPL and RMS polar plots")
    p.set_defaults(func=run)


def run(args) -> int:
    """Compute the directivity, print it, and write the requested files."""
    from ..app.directivity import directivity_at, directivity_lines, write_directivity_outputs
    from ..app.names import user_terms
    from ..app.outputs import check_distinct, check_output_file
    from ..app.settings.impact import DirectivitySettings
    from ._impact import impact_from_args, room_duration

    with user_terms(DirectivitySettings.cli_names()):
        settings = DirectivitySettings(args.step, args.metric)
    if args.csv is not None:
        check_output_file("--csv", args.csv, "csv")
    if args.png is not None:
        check_output_file("--png", args.png, "figure")
    check_distinct({"--csv": args.csv, "--png": args.png})
    window = room_duration(args)
    setup = impact_from_args(args)
    res = directivity_at(setup, args.distance, settings, max_memory_mb=getattr(args, "max_memory", None))
    for line in directivity_lines(setup, args.distance, res, window):
        print(line)
    for path in write_directivity_outputs(setup, args.distance, res, csv=args.csv, png=args.png):
        print(f"wrote {path}")
    return 0
