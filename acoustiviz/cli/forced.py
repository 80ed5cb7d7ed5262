r"""``acoustiviz forced``: the damper in operation, frequency response under harmonic excitation.

argv -> :class:`~acoustiviz.app.settings.forced_job.ForcedJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.forced.run` -> :meth:`~acoustiviz.app.forced.ForcedResult.write` -> the report.

Example::

    acoustiviz forced --M 0.5 --K 500 --C 0.05 --m 0.0405 --gap 0.04 --k-hertz 5.6e8 --c1 20 \\
        --force 5 --freq 3:7:9 --starts 8 --rtol 1e-12 --tolerance 1e-9 --csv OUT.csv --png OUT.png
"""

from __future__ import annotations

import argparse

from ..app.settings.damper import BALL_START, BALLS
from ..app.settings.forced import (
    AMPLITUDES,
    FORCED,
    FORCED_EXECUTION,
    FORCED_OUTPUTS,
    FREQUENCIES,
    NOISE,
    NOISE_LISTENER,
)
from ..app.settings.table import add_option
from ._damper import add_model_options
from ._impact import add_room_options


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
    for record in AMPLITUDES.values():
        add_option(x, record)
    add_option(e, FREQUENCIES, type=str, default=None, required=True)
    s = p.add_argument_group("solver")
    for record in FORCED[:-1]:
        add_option(s, record, parse_choices=False)
    for record in FORCED_EXECUTION:
        add_option(s, record)
    n = p.add_argument_group(
        "noise in operation (on by default)",
        "The steady click train of each frequency at the listener, rendered at 96 kHz: LAeq, LCpeak and "
        "LAFmax (IEC 61672-1 weightings), LZpeak, LZeq and SEL per cycle, over a whole number of periods "
        "of the steady state after a 1 s lead-in of the same train (8 F time constants, so LAFmax has "
        "settled). Columns laeq_db, lcpeak_db, lafmax_db, lzpeak_db, lzeq_db, sel_per_cycle_db, "
        "sel_a_per_cycle_db, level_interval_s; -inf where nothing strikes.")
    add_option(n, NOISE, action=argparse.BooleanOptionalAction)
    add_option(n, NOISE_LISTENER)
    add_option(n, FORCED[-1])
    add_option(n, FORCED_OUTPUTS[0])
    add_room_options(p, duration=True)  # --duration: how long each click's reflections are heard
    b = p.add_argument_group("several balls (a column of equal spheres of mass --m; --gap is their free travel; "
                             "attractors by simulation; the noise hears every collision)")
    for record in (*BALLS, BALL_START[2]):
        add_option(b, record)
    o = p.add_argument_group("outputs")
    for record in FORCED_OUTPUTS[1:]:
        add_option(o, record)
    p.set_defaults(func=run)
    return p


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.forced_job.ForcedJob` of the options; errors name the options."""
    from ..app.damper import damper_model
    from ..app.settings.damper import MODEL
    from ..app.settings.forced_job import ForcedJob
    from ..app.settings.parse import parse_frequencies, parse_point
    from ..app.settings.table import check_values
    from ._impact import room_duration, room_settings_from_args

    kind = "force" if args.force is not None else "base"
    names = ForcedJob.names_for("cli", kind)
    frequencies = parse_frequencies(args.freq, FREQUENCIES.option)
    listener = None if args.listener is None else parse_point(args.listener, NOISE_LISTENER.option)
    room = room_settings_from_args(args, duration=room_duration(args))
    model = damper_model(**check_values({s.name: getattr(args, s.name) for s in MODEL}, MODEL, names), names=names)
    return ForcedJob(model, tuple(frequencies), kind=kind, amplitude=getattr(args, kind),
                     **{s.name: getattr(args, s.name) for s in (*FORCED, *FORCED_EXECUTION, NOISE, *FORCED_OUTPUTS)},
                     listener=None if listener is None else tuple(listener), config="plane" if room is None else "room",
                     surroundings={} if room is None else {"room": room},
                     max_memory_mb=getattr(args, "max_memory", None), names=names,
                     **{s.name: getattr(args, s.name) for s in (*BALLS, BALL_START[2])})


def run(args) -> int:
    """Check every input and output, find the attractors, print the report and write the requested files.

    Returns the exit status: 0, or 1 when a frequency's run failed (each one warned about).
    """
    import sys

    from ..app.forced import report
    from ..app.forced import run as run_job

    settings = settings_from_args(args)

    def progress(msg):  # to stderr: the table on stdout stays clean
        print(f"forced: {msg}", file=sys.stderr, flush=True)

    result = run_job(settings, progress=progress)
    for line in report(result):
        print(line)
    paths = result.write()
    if settings.wav is not None:  # the WAV and its sidecar first
        wav, sidecar, *paths = paths
        print(f"wrote {wav} (sidecar {sidecar})")
    for path in paths:
        print(f"wrote {path}")
    return 0 if result.success else 1
