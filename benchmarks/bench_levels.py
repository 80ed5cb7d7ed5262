"""Speed and accuracy of the levels: weighted levels, bands, loudness and radiated energy.

Run ``python benchmarks/bench_levels.py`` (or ``--quick``; ``--write`` also keeps the output in
``benchmarks/results/bench_levels.txt``, machine and date first). Part 1: the paper's Table 1 damper
(20 s, event solver) rendered at the listener 0.7 m from the 19.05 mm sphere at 45 degrees; the
time of each analysis of the 96 kHz signal (the weighted levels and the bands' decimation also over
every sample, as they were computed before they worked on the clicks alone, with the largest
difference in dB), and how much each level moves when it is evaluated
on the 48 kHz (or 44.1 kHz) rendering instead -- what a 48 kHz file would cost. Part 2: the energy
of the fastest impact by the closed form, the surface work and the far-field intensity over the
spherical grids (free, plane, corner) at increasing resolution, with the relative change per
refinement (the free grid against the closed form). Times are CPU seconds of this process, best of
``--repeat`` warm runs.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _timing import cpu_best_of, run_writing

from acoustiviz import sound
from acoustiviz.app.levels import ANALYSIS_RATE
from acoustiviz.core.geometry import geometry
from acoustiviz.core.signal import Signal
from acoustiviz.dynamics import TABLE1, simulate
from acoustiviz.field.grids import spherical_grid_for
from acoustiviz.levels import (
    LEVEL_COLUMNS,
    bands,
    loudness,
    loudness_available,
    radiated_energy_free,
    radiated_energy_grid,
    sound_levels,
    surface_work_free,
    third_octave_levels,
)
from acoustiviz.levels.energy import run_energy
from acoustiviz.levels.train import signal_levels

LISTENER = [0.495, 0.0, 0.514]
RADIUS = 0.01905


def part_levels(seq, scene, repeat: int, quick: bool) -> None:
    model = sound.ClickModel()
    t_render, hi = cpu_best_of(lambda: sound.render(seq, scene, model, LISTENER, sample_rate=ANALYSIS_RATE,
                                                duration=20.0), repeat)
    p = hi.pressure
    print(f"\n1. levels of 20 s at {ANALYSIS_RATE / 1e3:g} kHz ({p.shape[1]} samples); rendering {t_render:.2f} s CPU")
    hdr = f"{'analysis':>28} {'CPU (s)':>9}"
    print(hdr)
    print("-" * len(hdr))
    t, lv = cpu_best_of(lambda: sound_levels(Signal(p, ANALYSIS_RATE)), repeat)
    print(f"{'weighted levels (8 levels)':>28} {t:9.3f}")
    t_sp, sp = cpu_best_of(lambda: signal_levels(Signal(p, ANALYSIS_RATE)), repeat)
    gap = max(float(np.max(np.abs(getattr(sp, c) - getattr(lv, c)))) for c in LEVEL_COLUMNS)
    print(f"{'  from the sound alone':>28} {t_sp:9.3f}   {t / t_sp:.1f}x faster, largest difference {gap:.1e} dB")
    t, bl = cpu_best_of(lambda: third_octave_levels(Signal(p, ANALYSIS_RATE)), repeat)
    print(f"{'1/3-octave bands (30)':>28} {t:9.3f}")
    sparse_above, bands.SPARSE_ABOVE = bands.SPARSE_ABOVE, -1.0  # decimate every sample
    try:
        t_d, bd = cpu_best_of(lambda: third_octave_levels(Signal(p, ANALYSIS_RATE)), repeat)
    finally:
        bands.SPARSE_ABOVE = sparse_above
    gap = max(float(np.max(np.abs(bl.leq_db - bd.leq_db))), float(np.max(np.abs(bl.lmax_db - bd.lmax_db))))
    print(f"{'  decimating every sample':>28} {t_d:9.3f}   {t_d / t:.1f}x slower, largest difference {gap:.1e} dB")
    if loudness_available() and not quick:
        t, ld = cpu_best_of(lambda: loudness(Signal(p, ANALYSIS_RATE)), 1)
        print(f"{'loudness + sharpness':>28} {t:9.3f}   N5 {ld.n5_sone[0]:.2f} sone, S {ld.sharpness_acum[0]:.2f} acum")
    rates = (48000,) if quick else (48000, 44100)
    print(f"\nlevel at {ANALYSIS_RATE / 1e3:g} kHz and its change (dB) when evaluated on a lower-rate rendering")
    hdr = f"{'level':>10} {ANALYSIS_RATE / 1e3:>8g} kHz" + "".join(f" {f'{fs / 1e3:g} kHz':>10}" for fs in rates)
    print(hdr)
    print("-" * len(hdr))
    lows = {fs: sound_levels(Signal(sound.render(seq, scene, model, LISTENER, sample_rate=fs,
                                                  duration=20.0).pressure, fs))
            for fs in rates}
    for c in LEVEL_COLUMNS:
        ref = float(getattr(lv, c)[0])
        print(f"{c:>10} {ref:12.2f}" + "".join(f" {float(getattr(lows[fs], c)[0]) - ref:+10.3f}" for fs in rates))


def part_energy(seq, repeat: int, quick: bool) -> None:
    model = sound.ClickModel()
    k = int(np.argmax(seq.velocities))
    pulse = model.pulse_for(seq.velocities[k])
    print(f"\n2. energy of the fastest impact ({seq.velocities[k]:.3g} m/s, half-sine, a = {RADIUS * 1e3:g} mm)")
    t_cf, e_cf = cpu_best_of(lambda: radiated_energy_free(pulse, radius=RADIUS), repeat)
    t_sw, e_sw = cpu_best_of(lambda: surface_work_free(pulse, radius=RADIUS), repeat)
    print(f"closed form {e_cf:.6e} J in {t_cf * 1e3:.3f} ms CPU; surface work {e_sw:.6e} J "
          f"(rel. diff. {abs(e_sw / e_cf - 1):.1e}) in {t_sw * 1e3:.1f} ms CPU")
    hdr = f"{'config':>10} {'n_theta':>7} {'directions':>10} {'energy (J)':>13} {'rel. change':>12} {'CPU (s)':>9}"
    print(hdr)
    print("-" * len(hdr))
    levels = (4, 8) if quick else (4, 8, 16)
    for name in ("free", "plane", "wall-floor"):
        cfg = geometry(name, RADIUS, lenient=True, wall_distance=0.05)
        prev = e_cf if name == "free" else None
        for n in levels:
            grid = spherical_grid_for(cfg, 1.0, n_theta=n)
            t, e = cpu_best_of(lambda grid=grid, cfg=cfg: radiated_energy_grid(pulse, cfg.sources, grid, radius=RADIUS),
                           repeat)
            change = f"{abs(e / prev - 1):.1e}" if prev is not None else "-"
            print(f"{name:>10} {n:>7} {grid.weights.size:>10} {e:13.6e} {change:>12} {t:9.3f}")
            prev = e
    print("(free: change against the closed form; plane, corner: against the previous resolution)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true",
                        help="also write the output to benchmarks/results/bench_levels.txt (machine and date first)")
    parser.add_argument("--quick", action="store_true", help="fewer cases, one repeat, no loudness")
    parser.add_argument("--repeat", type=int, default=2, help="timed repeats; the best is shown (default 2)")
    args = parser.parse_args(argv)
    repeat = 1 if args.quick else max(1, args.repeat)
    t0 = time.perf_counter()
    run = simulate(TABLE1, 20.0, solver="event")
    seq = run.impacts.sequence()
    scene = sound.CavityScene("plane", radius=RADIUS, gap=TABLE1.gap)
    print(f"damper: Table 1, 20 s, {len(seq)} impacts, solved in {time.perf_counter() - t0:.2f} s (not counted)")
    part_levels(seq, scene, repeat, args.quick)
    part_energy(seq, repeat, args.quick)
    t, en = cpu_best_of(lambda: run_energy(run.impacts, scene, sound.ClickModel(), 20.0), 1)
    k = en.loudest
    print(f"\n3. run energy: {len(seq)} impacts in {t:.2f} s CPU; sound power {en.sound_power_w:.3e} W "
          f"({en.sound_power_level_db:.1f} dB re 1 pW); loudest impact {en.energy_j[k]:.3e} J of "
          f"{en.energy_lost_j[k]:.3e} J lost: radiation efficiency {en.efficiency[k]:.3g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_writing("bench_levels", main))
