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

from ..app.settings.sweep import SWEEP_DAMPER, SWEEP_SOUND, SWEPT
from ..app.settings.table import add_option
from ._impact import add_room_options

#: ``--help`` group title -> its records; each option's destination is its sweep_spec parameter.
_GROUPS = (("swept parameters (VALUE, START:STOP:COUNT or A,B,C; SI units)", SWEPT),
           ("damper (SI units)", SWEEP_DAMPER), ("sound (SI units)", SWEEP_SOUND))


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
    for title, records in _GROUPS:
        g = p.add_argument_group(title)
        for s in records:
            add_option(g, s, dest=s.name, **({"metavar": "DURATION"} if s.option == "--duration" else {}))
    add_room_options(p)  # --config room with --room; the window its images reach is --room-window
    p.add_argument("--room-window", type=float, default=None, metavar="S",
                   help="with --room: the window in s from the start of each impact whose images the peak SPL "
                        "takes (required when a surface is rigid and --image-order is not given)")
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


def _given(args) -> dict:
    """The :func:`acoustiviz.app.sweep.sweep_spec` parameters the options give, ``--room``'s checked now."""
    from .._validate import ParameterError
    from ..app.names import ROOM_OPTIONS, user_terms
    from ..app.sweep import SWEEP_OPTIONS, with_room
    from ._impact import room_settings_from_args

    if args.room is None and args.room_window is not None:
        raise ParameterError("--room-window", "only applies with --room LX,LY,LZ")
    given = {s.name: getattr(args, s.name) for _, records in _GROUPS for s in records
             if getattr(args, s.name) is not None}
    with user_terms({**SWEEP_OPTIONS, **ROOM_OPTIONS, "duration": "--room-window"}):
        return with_room(given, room_settings_from_args(args, duration=args.room_window))


def spec_from_args(args):
    """The :class:`acoustiviz.sweep.SweepSpec` of parsed options (errors name the option)."""
    from ..app.names import user_terms
    from ..app.sweep import SWEEP_OPTIONS, sweep_spec

    with user_terms(SWEEP_OPTIONS):
        return sweep_spec(**_given(args))


def run(args) -> int:
    """Run the ``sweep`` subcommand; return the exit status."""
    import sys

    from ..app.sweep import sweep_workflow

    lines = sweep_workflow(_given(args), args.out, executor=args.executor, workers=args.workers,
                           max_memory_mb=getattr(args, "max_memory", None), progress=sys.stderr,
                           bar=False if args.quiet else None, overwrite=bool(args.overwrite),
                           definition=args.definition, band_width=args.band_width)
    for line in lines:
        print(line)
    return 0
