r"""``acoustiviz sweep``: run (or resume) a design sweep of the impact damper.

Example::

    acoustiviz sweep --gap 0.02:0.06:5 --m 0.02:0.08:4 --duration 5 --out DIR \\
        [--executor process|dask://HOST:PORT] [--workers N]

Every swept option takes one value, a range ``start:stop:count`` (both ends included) or a
comma-separated list. Writes ``DIR/sweep.json`` (the settings), ``DIR/sweep.csv`` (one row per
design, as they finish), ``DIR/design_table.csv`` (paper Table 2) and the paper's Figure 6
maps ``DIR/inclination_map.png`` and ``DIR/max_spl_map.png``. Running the same command again
resumes an interrupted sweep and recomputes nothing that finished.

With ``--force F0`` (or ``--base B``) and ``--freq START:STOP:COUNT`` every design is evaluated in
operation over the band instead (:func:`acoustiviz.sweep.run_operation`, with the search options of
``acoustiviz forced``): ``DIR/sweep.csv`` holds one row of worst-case columns per design, written as
chains of designs finish, and ``acoustiviz design --rank-by`` ranks them.

argv -> :class:`~acoustiviz.app.settings.sweep_job.SweepJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.sweep.run` -> :meth:`~acoustiviz.app.sweep.SweepResult.write` -> the summary.
"""

from __future__ import annotations

from ..app.settings.sweep import SWEEP_DAMPER, SWEEP_RUN, SWEEP_SOUND, SWEPT
from ..app.settings.sweep_operation import OPERATION_OPTIONS, SEARCH
from ..app.settings.table import add_option, by_name
from ._impact import add_room_options

#: ``--help`` group title -> its records; each option's destination is its API name.
_GROUPS = (("swept parameters (VALUE, START:STOP:COUNT or A,B,C; SI units)", SWEPT),
           ("damper (SI units)", SWEEP_DAMPER), ("sound (SI units)", SWEEP_SOUND),
           ("in operation (as acoustiviz forced; --solver and --rtol then set the search's, default "
            f"{SEARCH['solver'].default} and {SEARCH['rtol'].default:g})", OPERATION_OPTIONS))
_RUN = by_name(SWEEP_RUN)


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
    add_room(p)
    o = p.add_argument_group("execution and outputs")
    for s in SWEEP_RUN:
        if s.name != "room_window":
            add_option(o, s, dest=s.name, **({"required": True} if s.name == "out" else {}))
    p.set_defaults(func=run)
    return p


def add_room(parser) -> None:
    """Add the room options of a sweep's designs (``acoustiviz sweep`` and ``acoustiviz optimize``).

    ``--room`` and the shoebox's other options (``--config room`` with ``--room``); the window its images
    reach is ``--room-window``.
    """
    add_room_options(parser)
    add_option(parser, _RUN["room_window"], dest="room_window")


def given_with_room(args, given: dict) -> dict:
    """``given`` with the room of the options (:func:`acoustiviz.app.sweep.with_room`), ``--room``'s checked now.

    Errors name the options; ``--room-window`` without ``--room`` is refused.
    """
    from .._validate import ParameterError
    from ..app.names import SWEEP_ROOM_OPTIONS
    from ..app.sweep import with_room
    from ._impact import room_settings_from_args

    if args.room is None and args.room_window is not None:
        raise ParameterError("--room-window", "only applies with --room LX,LY,LZ")
    return with_room(given, room_settings_from_args(args, duration=args.room_window), names=SWEEP_ROOM_OPTIONS)


def _given(args) -> dict:
    """The :func:`~acoustiviz.app.settings.sweep_job.sweep_job` values the options give, ``--room``'s checked now."""
    given = {s.name: getattr(args, s.name) for _, records in _GROUPS for s in records
             if getattr(args, s.name) is not None}
    return given_with_room(args, given)


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.sweep_job.SweepJob` of the options; errors name the options."""
    from ..app.names import SWEEP_OPTIONS
    from ..app.settings.sweep_job import sweep_job

    return sweep_job(_given(args), names=SWEEP_OPTIONS, out=args.out, executor=args.executor, workers=args.workers,
                     overwrite=args.overwrite, definition=args.definition, band_width=args.band_width,
                     max_memory_mb=getattr(args, "max_memory", None))


def spec_from_args(args):
    """The :class:`acoustiviz.sweep.SweepSpec` of parsed options (errors name the option)."""
    return settings_from_args(args).spec


def run(args) -> int:
    """Check every input and the folder, run (or resume) the sweep, write its reports and print a summary."""
    import sys

    from ..app.sweep import run as run_job
    from ..app.sweep import sweep_summary

    settings = settings_from_args(args)
    result = run_job(settings, progress=sys.stderr, bar=False if args.quiet else None)
    for line in sweep_summary(result, result.write()):
        print(line)
    return 0
