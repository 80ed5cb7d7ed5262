"""Speed and accuracy of the auralisation of a whole impact-damper run.

Run ``python benchmarks/bench_audio.py`` (or ``--quick``; ``--write`` also keeps the output in
``benchmarks/results/bench_audio.txt``, machine and date first). The run is the paper's Table 1 damper
(d = 4 cm, dx/dt(0) = 2 m/s, event solver) over 20 s; its impact table is rendered at the
listener 0.7 m from the 19.05 mm sphere at 45 degrees (plane configuration, both walls). Times
are CPU seconds of the synthesis only (the damper is solved once beforehand), best of ``--repeat``
warm runs. The accuracy column compares each output with the same output computed at twice the
internal rate (max |difference| / peak): it shows the internal rate is converged, i.e. nothing
from above the internal Nyquist frequency folds into the signal.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _timing import cpu_best_of, run_writing

from acoustiviz import sound
from acoustiviz.dynamics import TABLE1, simulate

LISTENER = [0.495, 0.0, 0.514]
GOAL_S = 2.0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true",
                        help="also write the output to benchmarks/results/bench_audio.txt (machine and date first)")
    parser.add_argument("--quick", action="store_true", help="48 kHz only, one repeat")
    parser.add_argument("--repeat", type=int, default=3, help="timed repeats; the best is shown (default 3)")
    args = parser.parse_args(argv)
    repeat = 1 if args.quick else max(1, args.repeat)

    t0 = time.perf_counter()
    run = simulate(TABLE1, 20.0, solver="event")
    t_dyn = time.perf_counter() - t0
    seq = run.impacts.sequence()
    scene = sound.CavityScene("plane", radius=0.01905, gap=TABLE1.gap)
    print(f"damper: Table 1, 20 s, {len(seq)} impacts ({seq.count(-1)} on wall -1, {seq.count(1)} on wall +1), "
          f"approach speeds {seq.velocities.min():.3g}-{seq.velocities.max():.3g} m/s; "
          f"solved in {t_dyn:.2f} s (not counted below)")
    ears = sound.ear_positions(LISTENER, scene)
    cases = []
    rates = (48000,) if args.quick else (44100, 48000, 96000)
    for fs in rates:
        cases.append((fs, "half-sine", "mono", [LISTENER]))
    cases.append((48000, "half-sine", "stereo", ears))
    cases.append((48000, "hertz", "mono", [LISTENER]))
    if not args.quick:
        cases.append((48000, "impulse-matched", "mono", [LISTENER]))
    sound.render(seq, scene, sound.ClickModel(), LISTENER, duration=20.0)  # warm-up (imports, FFT plans)

    hdr = (f"{'rate (Hz)':>9} {'pulse':>15} {'chan':>6} {'internal (kHz)':>14} {'synthesis CPU s':>16} "
           f"{'x real time':>11} {'peak SPL (dB)':>13} {'rel. diff. at 2x internal':>25} {'goal < 2 s':>10}")
    print(hdr)
    print("-" * len(hdr))
    worst = 0.0
    for fs, kind, chan, lis in cases:
        model = sound.ClickModel(pulse=kind)
        secs, out = cpu_best_of(lambda fs=fs, model=model, lis=lis: sound.render(
            seq, scene, model, lis, sample_rate=fs, duration=20.0), repeat)
        worst = max(worst, secs) if fs == 48000 else worst
        L = round(out.internal_rate / fs)
        fine = sound.render(seq, scene, model, lis, sample_rate=fs, duration=20.0, oversampling=2 * L)
        n = min(out.n_samples, fine.n_samples)
        diff = np.max(np.abs(out.pressure[:, :n] - fine.pressure[:, :n])) / np.max(np.abs(fine.pressure))
        print(f"{fs:>9} {kind:>15} {chan:>6} {out.internal_rate / 1e3:>14.1f} {secs:>16.3f} "
              f"{20.0 / secs:>11.0f} {out.peak_spl.max():>13.2f} {diff:>25.1e} "
              f"{'yes' if secs < GOAL_S else 'NO':>10}")
    print(f"slowest 48 kHz synthesis: {worst:.3f} s CPU (goal: 20 s of a Table 1 run in under {GOAL_S:g} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_writing("bench_audio", main))
