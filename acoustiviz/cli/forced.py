r"""``acoustiviz forced``: the damper in operation, frequency response under harmonic excitation.

Example::

    acoustiviz forced --M 0.5 --K 500 --C 0.05 --m 0.0405 --gap 0.04 --k-hertz 5.6e8 --c1 20 \\
        --force 5 --freq 3:7:9 --starts 8 --rtol 1e-12 --tolerance 1e-9 --csv OUT.csv --png OUT.png
"""

from __future__ import annotations

import argparse

from ..app.settings.forced import FORCED, FREQUENCIES
from ..app.settings.table import add_option
from ._damper import add_model_options
from ._impact import add_room_options

_METAVARS = {"sweep": "{up,down,both,independent}", "solver": "{event,impact-map,newmark}", "starts": "N",
             "tolerance": "TOL", "rtol": "RTOL", "max_cycles": "N"}


def add_parser(subparsers):
    """Register the ``forced`` subcommand."""
    p = subparsers.add_parser(
        "forced",
        help="frequency response of the damper under a harmonic force or base motion",
        description=(
            "Run the impact damper (paper eq 15) under a harmonic force F0 cos(wt) on the main mass "
            "(--force) or a harmonic base motion B cos(wt) (--base) from several starts at each "
            "frequency to every attractor they reach (periodic orbits refined by shooting, with their "
            "Floquet multipliers), and report for each the main-mass amplitude with and without the "
            "damper, the reduction, the regime (periodic-n, quasi-periodic, chaotic or unresolved), "
            "the fraction of starts that reached it and the impacts per cycle."
        ),
    )
    add_model_options(p.add_argument_group("damper (paper eq 15; defaults: Table 1, d = 4 cm)"))
    e = p.add_argument_group("excitation")
    x = e.add_mutually_exclusive_group(required=True)
    x.add_argument("--force", type=float, metavar="N", help="force amplitude F0 on the main mass in N")
    x.add_argument("--base", type=float, metavar="M", help="base displacement amplitude B in m (instead of --force)")
    e.add_argument(FREQUENCIES.option, required=True, metavar=FREQUENCIES.metavar,
                   help=f"{FREQUENCIES.doc}, each in {FREQUENCIES.range_text()}")
    s = p.add_argument_group("solver")
    for st in FORCED[:6]:
        add_option(s, st, metavar=_METAVARS.get(st.name), parse_choices=False)
    s.add_argument("--restitution", type=float, default=None, metavar="E",
                   help="impact-map restitution in (0, 1] (default: the compliant contact's at each speed)")
    s.add_argument("--workers", type=int, default=1, metavar="N",
                   help="processes running the frequencies in parallel (default %(default)s)")
    s.add_argument("--executor", default="process", metavar="process|dask://HOST:PORT",
                   help="where the frequencies run: local processes (--workers) or a Dask scheduler "
                        "(extra 'distributed'; default %(default)s)")
    n = p.add_argument_group(
        "noise in operation (on by default)",
        "The steady click train of each frequency at the listener, rendered at 96 kHz: LAeq, LCpeak and "
        "LAFmax (IEC 61672-1 weightings), LZpeak, LZeq and SEL per cycle, over a whole number of periods "
        "of the steady state after a 1 s lead-in of the same train (8 F time constants, so LAFmax has "
        "settled). Columns laeq_db, lcpeak_db, lafmax_db, lzpeak_db, lzeq_db, sel_per_cycle_db, "
        "sel_a_per_cycle_db, level_interval_s; -inf where nothing strikes.")
    n.add_argument("--noise", action=argparse.BooleanOptionalAction, default=True,
                   help="compute the levels (default; --no-noise leaves the level columns empty)")
    n.add_argument("--listener", default=None, metavar="X,Y,Z",
                   help="listener position in m (default: the paper's, 0.7 m from the sphere at 45 degrees "
                        "above the plane it rests on: 0.495,0,0.514)")
    add_option(n, FORCED[6], metavar="S")
    n.add_argument("--wav", metavar="PATH", default=None,
                   help="write the damper in operation, each frequency's interval in turn, as a 48 kHz WAV")
    add_room_options(p, duration=True)  # --duration: how long each click's reflections are heard
    o = p.add_argument_group("outputs")
    o.add_argument("--csv", metavar="PATH", default=None, help="write one row per frequency and attractor as CSV")
    o.add_argument("--png", metavar="PATH", default=None,
                   help="plot the frequency response and the bifurcation diagram as PNG")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    """Parse the options into a :class:`~acoustiviz.app.settings.forced.ForcedJob` and run it."""
    import sys

    from ..app.forced import forced_workflow
    from ..app.names import ROOM_OPTIONS, user_terms
    from ..app.settings.damper import MODEL, check_values
    from ..app.settings.forced import ForcedJob, ForcedSettings
    from ._impact import room_duration, room_settings_from_args

    with user_terms(ForcedSettings.cli_names()):
        st = ForcedSettings.from_values({s.name: getattr(args, s.name) for s in FORCED})
    with user_terms(ROOM_OPTIONS):
        room = room_settings_from_args(args, duration=room_duration(args))
    with user_terms({s.name: s.option for s in MODEL}):
        model = check_values({s.name: getattr(args, s.name) for s in MODEL}, MODEL)
    job = ForcedJob(st, model, args.freq, force=args.force, base=args.base, restitution=args.restitution,
                    workers=args.workers, executor=args.executor, noise=args.noise, listener=args.listener,
                    wav=args.wav, csv=args.csv, png=args.png, room=room,
                    max_memory=getattr(args, "max_memory", None))

    def progress(msg):  # to stderr: the table on stdout stays clean
        print(f"forced: {msg}", file=sys.stderr, flush=True)

    return forced_workflow(job, progress=progress)
