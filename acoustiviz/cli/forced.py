r"""``acoustiviz forced``: the damper in operation, frequency response under harmonic excitation.

Example::

    acoustiviz forced --M 0.5 --K 500 --C 0.05 --m 0.0405 --gap 0.04 --k-hertz 5.6e8 --c1 20 \\
        --force 5 --freq 3:7:9 --starts 8 --rtol 1e-12 --tolerance 1e-9 --csv OUT.csv --png OUT.png
"""

from __future__ import annotations

import argparse

from ..app.settings.forced import FORCED
from ..app.settings.table import add_option
from ._damper import add_model_options

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
    e.add_argument("--freq", required=True, metavar="START:STOP:COUNT|F1,F2,...",
                   help="forcing frequencies in Hz: START:STOP:COUNT (inclusive) or a comma list")
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
    from ._impact import add_room_options

    add_room_options(p, duration=True)  # --duration: how long each click's reflections are heard
    o = p.add_argument_group("outputs")
    o.add_argument("--csv", metavar="PATH", default=None, help="write one row per frequency and attractor as CSV")
    o.add_argument("--png", metavar="PATH", default=None,
                   help="plot the frequency response and the bifurcation diagram as PNG")
    p.set_defaults(func=run)
    return p


def _check_outputs(args) -> None:
    """Refuse unwritable or clashing output files (before any work)."""
    from ..app.outputs import check_distinct, check_output_file

    outputs = {"--csv": args.csv and check_output_file("--csv", args.csv, "csv"),
               "--png": args.png and check_output_file("--png", args.png, "figure")}
    if args.wav is not None:
        outputs["--wav"] = check_output_file("--wav", args.wav, "wav")
        outputs["--wav (sidecar)"] = check_output_file("--wav", outputs["--wav"].with_suffix(".json"), "json")
    check_distinct(outputs)


def run(args) -> int:
    """Run the ``forced`` subcommand; return the exit status."""
    from ..app.budget import check_budget, forced_estimate
    from ..app.damper import damper_model
    from ..app.forced import FORCED_OPTIONS, forced_table, parse_frequencies, room_surroundings, run_forced
    from ..app.names import ROOM_OPTIONS, user_terms
    from ..app.settings.forced import ForcedSettings
    from ..errors import ParameterError
    from ._impact import room_duration, room_settings

    freqs = parse_frequencies(args.freq)
    listener = None
    if args.listener is not None:
        from ..app.settings.parse import parse_point

        listener = parse_point(args.listener, "--listener")
    _check_outputs(args)
    if args.wav is not None and not args.noise:
        raise ParameterError("--wav", "needs the noise in operation: drop --no-noise")
    with user_terms(ForcedSettings.cli_names()):
        st = ForcedSettings.from_values({s.name: getattr(args, s.name) for s in FORCED})
    with user_terms({**ROOM_OPTIONS, "listener": "--listener"}):
        room = room_surroundings(room_settings(args, duration=room_duration(args)), listener, room_name="--room")
    with user_terms(FORCED_OPTIONS):
        model = damper_model(M=args.M, K=args.K, C=args.C, m=args.m, gap=args.gap, k_hertz=args.k_hertz,
                             c1=args.c1)
    check_budget(forced_estimate(len(freqs) * st.starts, st.max_cycles,
                                 noise_seconds=st.noise_seconds if args.noise else 0.0,
                                 wav=args.wav is not None), getattr(args, "max_memory", None))
    if args.noise or listener is not None:
        from ..app.forced import check_listener

        with user_terms(ROOM_OPTIONS):  # a room's settings checked here, before any run
            check_listener(model, listener, settings=room)
    kind, amp = ("force", args.force) if args.force is not None else ("base", args.base)
    import sys

    def progress(msg):  # to stderr: the table on stdout stays clean
        print(f"forced: {msg}", file=sys.stderr, flush=True)

    fr = run_forced(model, freqs, amp, kind=kind, sweep=st.sweep, solver=st.solver, restitution=args.restitution,
                    tolerance=st.tolerance, rtol=st.rtol, starts=st.starts, max_cycles=st.max_cycles,
                    workers=args.workers, executor=args.executor, progress=progress)
    unit = "N" if kind == "force" else "m"
    print(f"{kind} amplitude {amp:g} {unit}; sweep {st.sweep}; solver {st.solver}; {st.starts} starts; "
          f"tolerance {st.tolerance:g} m, m/s; rtol {st.rtol:g}; max cycles {st.max_cycles}; "
          f"{len(freqs)} frequencies, {len(fr.rows)} attractors in {fr.elapsed:.2f} s")
    failed = [r for r in fr.steady_states if not r.success]
    if not args.noise:
        print(forced_table(fr, None))
    for r in failed:
        print(f"warning: {r.excitation.frequency:g} Hz: {r.message}")
    _write_outputs(args, fr, listener, room)
    return 0 if not failed else 1


def _write_outputs(args, fr, listener, room=None) -> None:
    """The noise in operation (table and WAV) when asked, then the CSV and the figure."""
    from ..app.forced import write_forced_csv, write_forced_png

    if args.noise:
        from ..app.forced import operating_noise_report

        for line in operating_noise_report(fr, listener, args.noise_seconds, wav=args.wav, settings=room):
            print(line)
    if args.csv:
        print(f"wrote {write_forced_csv(fr, args.csv)}")
    if args.png:
        print(f"wrote {write_forced_png(fr, args.png)}")
