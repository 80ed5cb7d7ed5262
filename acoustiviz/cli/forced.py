r"""``acoustiviz forced``: the damper in operation, frequency response under harmonic excitation.

Example::

    acoustiviz forced --M 0.5 --K 500 --C 0.05 --m 0.0405 --gap 0.04 --k-hertz 5.6e8 --c1 20 \\
        --force 5 --freq 3:7:9 --csv OUT.csv --png OUT.png
"""

from __future__ import annotations

import argparse
import math
import time

from ._damper import add_model_options


def add_parser(subparsers):
    """Register the ``forced`` subcommand."""
    p = subparsers.add_parser(
        "forced",
        help="frequency response of the damper under a harmonic force or base motion",
        description=(
            "Run the impact damper (paper eq 15) under a harmonic force F0 cos(wt) on the main mass "
            "(--force) or a harmonic base motion B cos(wt) (--base) to its periodic steady state at "
            "each frequency, and report the main-mass amplitude with and without the damper, the "
            "reduction, the regime (periodic-n or non-periodic) and the impacts per cycle."
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
                   help="continuation direction (each frequency starts from the last state), both "
                        "(up and down, hysteresis marked) or independent runs (default %(default)s)")
    s.add_argument("--solver", default="event", metavar="{event,impact-map,newmark}",
                   help="event (default; compliant Hertz contacts), impact-map (instantaneous impacts) "
                        "or newmark")
    s.add_argument("--restitution", type=float, default=None, metavar="E",
                   help="impact-map restitution in (0, 1] (default: the compliant contact's at each speed)")
    s.add_argument("--tolerance", type=float, default=1e-6,
                   help="Poincare return tolerance of the steady state (default %(default)s)")
    s.add_argument("--max-cycles", type=int, default=2000, metavar="N",
                   help="cycle limit per frequency; beyond it the motion is reported non-periodic "
                        "(default %(default)s)")
    s.add_argument("--workers", type=int, default=1, metavar="N",
                   help="processes for --sweep independent (default %(default)s)")
    s.add_argument("--executor", default="process", metavar="process|dask://HOST:PORT",
                   help="where --sweep independent runs: local processes (--workers) or a Dask scheduler "
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
    o = p.add_argument_group("outputs")
    o.add_argument("--csv", metavar="PATH", default=None, help="write one row per frequency as CSV")
    o.add_argument("--png", metavar="PATH", default=None,
                   help="plot the frequency response and the bifurcation diagram as PNG")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    """Run the ``forced`` subcommand; return the exit status."""
    from ..app.damper import damper_model
    from ..app.forced import FORCED_OPTIONS, parse_frequencies, run_forced, write_forced_csv, write_forced_png
    from ..app.names import user_terms

    freqs = parse_frequencies(args.freq)
    listener = None
    if args.listener is not None:
        from ..app.forced import parse_point

        listener = parse_point(args.listener, "--listener")
    from ..app.outputs import check_distinct, check_output_file
    from ..errors import ParameterError

    outputs = {"--csv": args.csv and check_output_file("--csv", args.csv, "csv"),
               "--png": args.png and check_output_file("--png", args.png, "figure")}
    if args.wav is not None:
        outputs["--wav"] = check_output_file("--wav", args.wav, "wav")
        outputs["--wav (sidecar)"] = check_output_file("--wav", outputs["--wav"].with_suffix(".json"), "json")
    check_distinct(outputs)
    if args.wav is not None and not args.noise:
        raise ParameterError("--wav", "needs the noise in operation: drop --no-noise")
    if not (math.isfinite(args.noise_seconds) and 0 < args.noise_seconds <= 60):
        raise ParameterError("--noise-seconds", f"must lie in (0, 60] s, got {args.noise_seconds!r}")
    with user_terms(FORCED_OPTIONS):
        model = damper_model(M=args.M, K=args.K, C=args.C, m=args.m, gap=args.gap, k_hertz=args.k_hertz,
                             c1=args.c1)
    from ..app.budget import check_budget, forced_estimate

    if not (isinstance(args.max_cycles, int) and args.max_cycles >= 1):
        raise ParameterError("--max-cycles", f"must be an integer >= 1, got {args.max_cycles!r}")
    check_budget(forced_estimate(len(freqs), args.max_cycles, noise_seconds=args.noise_seconds if args.noise else 0.0,
                                 wav=args.wav is not None), getattr(args, "max_memory", None))
    if args.noise or listener is not None:
        from ..app.forced import check_listener

        check_listener(model, listener)
    kind, amp = ("force", args.force) if args.force is not None else ("base", args.base)
    fr = run_forced(model, freqs, amp, kind=kind, sweep=args.sweep, solver=args.solver,
                    restitution=args.restitution, tolerance=args.tolerance, max_cycles=args.max_cycles,
                    workers=args.workers, executor=args.executor)
    unit = "N" if kind == "force" else "m"
    print(f"{kind} amplitude {amp:g} {unit}; sweep {args.sweep}; solver {args.solver}; "
          f"{len(freqs)} frequencies in {fr.elapsed:.2f} s")
    print(f"{'f (Hz)':>8} {'A (mm)':>10} {'A0 (mm)':>10} {'red (dB)':>9} {'imp/cyc':>8}  regime")
    for row in fr.rows:
        print(f"{row['frequency_hz']:8.3f} {1e3 * row['amplitude_m']:10.4f} "
              f"{1e3 * row['amplitude_without_damper_m']:10.4f} {row['reduction_db']:9.2f} "
              f"{row['impacts_per_cycle']:8.3f}  {row['regime']}"
              + (f"  (down: {row['regime_down']}, {1e3 * row['amplitude_down_m']:.4f} mm"
                 f"{', hysteresis' if row['hysteresis'] else ''})" if 'regime_down' in row else ""))
    unsettled = [r for r in fr.response.primary if r.success and not r.converged]
    if unsettled:
        r = unsettled[0]
        print(f"non-periodic at {', '.join(f'{u.excitation.frequency:g}' for u in unsettled)} Hz: no period of up "
              f"to 8 cycles within {r.cycles} cycles (tolerance {args.tolerance:g}); amplitude and impacts "
              f"there are over the last {r.measured_cycles} cycles, not a steady state")
    failed = [r for r in fr.response.primary + (fr.response.down or ()) if not r.success]
    for r in failed:
        print(f"warning: {r.excitation.frequency:g} Hz: {r.message}")
    if args.noise:
        from ..app.forced import add_operating_noise, write_operating_wav
        from ..app.forced_noise import noise_statement

        t0 = time.perf_counter()
        noises = add_operating_noise(fr, listener=listener, seconds=args.noise_seconds)
        where = "the paper's listener (0.7 m, 45 deg)" if listener is None else f"({args.listener}) m"
        print(f"noise in operation at {where}: {noise_statement(args.noise_seconds)}; "
              f"{time.perf_counter() - t0:.2f} s")
        print(f"{'f (Hz)':>8} {'LAeq':>7} {'LAFmax':>7} {'LCpeak':>7} {'LZpeak':>7} {'LZeq':>7} {'T (s)':>6}"
              "  (dB re 20 uPa)")
        for row, nz in zip(fr.rows, noises, strict=True):
            if nz is None:
                print(f"{row['frequency_hz']:8.3f}  (no levels: the run failed)")
                continue
            note = "" if nz.settled else "  (F weighting not settled: non-periodic record too short)"
            print(f"{row['frequency_hz']:8.3f} {nz.laeq_db:7.1f} {nz.lafmax_db:7.1f} {nz.lcpeak_db:7.1f} "
                  f"{nz.lzpeak_db:7.1f} {nz.lzeq_db:7.1f} {nz.duration:6.3f}{note}")
        if args.wav:
            rec = write_operating_wav(noises, args.wav, listener=listener)
            print(f"wrote {args.wav} (sidecar {rec[0]['sidecar']})")
    if args.csv:
        print(f"wrote {write_forced_csv(fr, args.csv)}")
    if args.png:
        print(f"wrote {write_forced_png(fr, args.png)}")
    return 0 if not failed else 1
