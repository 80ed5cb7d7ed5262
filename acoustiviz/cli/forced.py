r"""``acoustiviz forced``: the damper in operation, frequency response under harmonic excitation.

Example::

    acoustiviz forced --M 0.5 --K 500 --C 0.05 --m 0.0405 --gap 0.04 --k-hertz 5.6e8 --c1 20 \\
        --force 5 --freq 3:7:9 --starts 8 --rtol 1e-12 --tolerance 1e-9 --csv OUT.csv --png OUT.png
"""

from __future__ import annotations

import argparse
import math
import time

from ..constants import FORCED_MAX_CYCLES, FORCED_RTOL, FORCED_STARTS, FORCED_TOLERANCE
from ._damper import add_model_options


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
    s.add_argument("--sweep", default="up", metavar="{up,down,both,independent}",
                   help="continuation: the attractors of each frequency also start the next higher (up), "
                        "lower (down) or both neighbours, or none (independent) (default %(default)s)")
    s.add_argument("--solver", default="event", metavar="{event,impact-map,newmark}",
                   help="event (default; compliant Hertz contacts), impact-map (instantaneous impacts) "
                        "or newmark")
    s.add_argument("--restitution", type=float, default=None, metavar="E",
                   help="impact-map restitution in (0, 1] (default: the compliant contact's at each speed)")
    s.add_argument("--starts", type=int, default=FORCED_STARTS, metavar="N",
                   help="starts per frequency looking for coexisting attractors: the linear start, rest and "
                        "the impact mass spread over the cavity (default %(default)s)")
    s.add_argument("--tolerance", type=float, default=FORCED_TOLERANCE, metavar="TOL",
                   help="Newton residual of a periodic orbit, largest component of P^n(s) - s in m and m/s "
                        "(default %(default)g)")
    s.add_argument("--rtol", type=float, default=FORCED_RTOL,
                   help="relative tolerance of the contact integration, event solver (default %(default)g)")
    s.add_argument("--max-cycles", type=int, default=FORCED_MAX_CYCLES, metavar="N",
                   help="cycles each start runs before its motion is measured as non-periodic "
                        "(default %(default)s)")
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
    n.add_argument("--noise-seconds", type=float, default=1.0, metavar="S",
                   help="least length of the level interval in s, in (0, 60]; it spans whole periods "
                        "(default %(default)s)")
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


def _check_noise(args) -> None:
    """Refuse a WAV without the noise in operation and a noise interval out of (0, 60] s."""
    from ..errors import ParameterError

    if args.wav is not None and not args.noise:
        raise ParameterError("--wav", "needs the noise in operation: drop --no-noise")
    if not (math.isfinite(args.noise_seconds) and 0 < args.noise_seconds <= 60):
        raise ParameterError("--noise-seconds", f"must lie in (0, 60] s, got {args.noise_seconds!r}")


def _check_solver_settings(args) -> None:
    """Refuse cycle counts, starts and tolerances out of their ranges."""
    from ..constants import FORCED_MAX_STARTS, FORCED_MIN_CYCLES, FORCED_RTOL_RANGE, FORCED_TOLERANCE_RANGE
    from ..errors import ParameterError

    if not (isinstance(args.max_cycles, int) and args.max_cycles >= FORCED_MIN_CYCLES):
        raise ParameterError("--max-cycles", f"must be an integer >= {FORCED_MIN_CYCLES}, got {args.max_cycles!r}")
    if not 1 <= args.starts <= FORCED_MAX_STARTS:
        raise ParameterError("--starts", f"must lie in [1, {FORCED_MAX_STARTS}], got {args.starts}")
    for opt, v, (lo, hi) in (("--tolerance", args.tolerance, FORCED_TOLERANCE_RANGE),
                             ("--rtol", args.rtol, FORCED_RTOL_RANGE)):
        if not (math.isfinite(v) and lo <= v <= hi):
            raise ParameterError(opt, f"must lie in [{lo:g}, {hi:g}], got {v!r}")


def run(args) -> int:
    """Run the ``forced`` subcommand; return the exit status."""
    from ..app.budget import check_budget, forced_estimate
    from ..app.damper import damper_model
    from ..app.forced import FORCED_OPTIONS, parse_frequencies, run_forced
    from ..app.names import ROOM_OPTIONS, user_terms

    freqs = parse_frequencies(args.freq)
    listener = None
    if args.listener is not None:
        from ..app.forced import parse_point

        listener = parse_point(args.listener, "--listener")
    _check_outputs(args)
    _check_noise(args)
    room = _room(args, listener)
    with user_terms(FORCED_OPTIONS):
        model = damper_model(M=args.M, K=args.K, C=args.C, m=args.m, gap=args.gap, k_hertz=args.k_hertz,
                             c1=args.c1)
    _check_solver_settings(args)
    check_budget(forced_estimate(len(freqs) * args.starts, args.max_cycles,
                                 noise_seconds=args.noise_seconds if args.noise else 0.0,
                                 wav=args.wav is not None), getattr(args, "max_memory", None))
    if args.noise or listener is not None:
        from ..app.forced import check_listener

        with user_terms(ROOM_OPTIONS):  # a room's settings checked here, before any run
            check_listener(model, listener, settings=room)
    kind, amp = ("force", args.force) if args.force is not None else ("base", args.base)
    import sys

    def progress(msg):  # to stderr: the table on stdout stays clean
        print(f"forced: {msg}", file=sys.stderr, flush=True)

    fr = run_forced(model, freqs, amp, kind=kind, sweep=args.sweep, solver=args.solver,
                    restitution=args.restitution, tolerance=args.tolerance, rtol=args.rtol, starts=args.starts,
                    max_cycles=args.max_cycles, workers=args.workers, executor=args.executor, progress=progress)
    unit = "N" if kind == "force" else "m"
    print(f"{kind} amplitude {amp:g} {unit}; sweep {args.sweep}; solver {args.solver}; {args.starts} starts; "
          f"tolerance {args.tolerance:g} m, m/s; rtol {args.rtol:g}; max cycles {args.max_cycles}; "
          f"{len(freqs)} frequencies, {len(fr.rows)} attractors in {fr.elapsed:.2f} s")
    failed = [r for r in fr.steady_states if not r.success]
    if not args.noise:
        _print_table(fr, None)
    for r in failed:
        print(f"warning: {r.excitation.frequency:g} Hz: {r.message}")
    _write_outputs(args, fr, listener, room)
    return 0 if not failed else 1


def _room(args, listener):
    """The cavity's surroundings in a room (``{"room": settings}``), or None above the paper's plane.

    With ``--room`` the listener must be given (``--listener``) and ``--duration`` says how long
    after each click its reflections are heard (the images that arrive within it).
    """
    from ..errors import ParameterError
    from ._impact import room_duration, room_settings

    duration = room_duration(args)
    if args.room is None:
        return None
    if listener is None:
        raise ParameterError("--listener", "required with --room: the listener's position X,Y,Z in m in the room")
    return {"room": room_settings(args, duration=duration)}


def _write_outputs(args, fr, listener, room=None) -> None:
    """The noise in operation (table and WAV) when asked, then the CSV and the figure."""
    from ..app.forced import write_forced_csv, write_forced_png

    if args.noise:
        from ..app.forced import add_operating_noise, write_operating_wav
        from ..app.forced_noise import noise_statement

        t0 = time.perf_counter()
        noises = add_operating_noise(fr, listener=listener, seconds=args.noise_seconds, settings=room)
        where = "the paper's listener (0.7 m, 45 deg)" if listener is None else f"({args.listener}) m"
        print(f"noise in operation at {where}: {noise_statement(args.noise_seconds)}; "
              f"{time.perf_counter() - t0:.2f} s")
        _print_table(fr, noises)
        if args.wav:
            rec = write_operating_wav(noises, args.wav, listener=listener)
            print(f"wrote {args.wav} (sidecar {rec[0]['sidecar']})")
    if args.csv:
        print(f"wrote {write_forced_csv(fr, args.csv)}")
    if args.png:
        print(f"wrote {write_forced_png(fr, args.png)}")


def _print_table(fr, noises) -> None:
    """One line per (frequency, attractor), the worst case (largest amplitude, largest LCpeak) marked."""
    lv = noises is not None
    print(f"{'f (Hz)':>8} {'#':>2} {'A (mm)':>9} {'±':>7} {'A0 (mm)':>9} {'red dB':>7} {'imp/cyc':>7} {'basin':>5} "
          f"{'|mu|max':>8} {'stable':>6}" + (f" {'LAeq':>6} {'LAFmax':>6} {'LCpeak':>6}" if lv else "")
          + "  regime  (worst case)")
    for k, row in enumerate(fr.rows):
        mu = row["max_floquet_modulus"]
        line = (f"{row['frequency_hz']:8.3f} {row['attractor']:2d} {1e3 * row['amplitude_m']:9.3f} "
                f"{1e3 * row['amplitude_std_err_m']:7.3f} {1e3 * row['amplitude_without_damper_m']:9.3f} "
                f"{row['reduction_db']:7.2f} {row['impacts_per_cycle']:7.3f} {row['basin_fraction']:5.2f} "
                f"{'' if math.isnan(mu) else f'{mu:.4f}':>8} {'yes' if row['stable'] else 'no':>6}")
        if lv:
            nz = noises[k]
            line += (f" {nz.laeq_db:6.1f} {nz.lafmax_db:6.1f} {nz.lcpeak_db:6.1f}" if nz is not None
                     else f" {'':>6} {'':>6} {'':>6}")
        print(line + f"  {row['regime']}" + (f"  ({row['worst_case']})" if row["worst_case"] else ""))
    odd = [row for row in fr.rows if not row["regime"].startswith("periodic-")]
    for row in odd:
        print(f"{row['frequency_hz']:g} Hz #{row['attractor']}: {row['message']}")
