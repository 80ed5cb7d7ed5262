"""Wall time of a design sweep: 20 x 20 designs (gap x impact mass), 20 s of motion each.

Run ``python benchmarks/bench_sweep.py`` (or ``--quick`` for 5 x 4 designs of 5 s). The sweep
is the one of the paper's Figure 6: gaps 2-6 cm, impact masses 20-80 g, Table 1 otherwise,
the listener at 0.7 m and 45 degrees over a reflecting plane, every design's maximum SPL from
its impacts. It runs into a fresh temporary directory (so nothing is resumed) on a local
process pool, and prints

* the wall time of the sweep (designs only) and of the whole call (with pool start-up),
* the per-design cost: wall time per design, and core-seconds per design (wall x workers / n),
* the serial cost of one design in this process (the median over a few designs), for reference,
  without and with the weighted levels of its run (``Settings.levels``: the click train rendered
  at 96 kHz, LAFmax, LCpeak and LAeq), and the extra cost of the levels per design.

``--levels`` runs the sweep itself with the levels on; ``--write`` also keeps the output in
``benchmarks/results/bench_sweep.txt`` (the levels' cost quoted in ``docs/guide/sweeps.md`` is read
from it by ``docs/check_numbers.py``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time

from _timing import run_writing


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="5 x 4 designs of 5 s instead of 20 x 20 of 20 s")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    parser.add_argument("--executor", default="process", help="process (default) or dask://HOST:PORT")
    parser.add_argument("--levels", action="store_true", help="the sweep computes LAFmax, LCpeak and LAeq too")
    args = parser.parse_args(argv)

    t_import = time.perf_counter()
    from dataclasses import replace

    from acoustiviz.sweep import Settings, SweepSpec, evaluate_design, run_sweep, value_range

    t_import = time.perf_counter() - t_import
    ng, nm, duration = (5, 4, 5.0) if args.quick else (20, 20, 20.0)
    spec = SweepSpec(gap=value_range(0.02, 0.06, ng), m=value_range(0.02, 0.08, nm),
                     settings=Settings(duration=duration, levels=args.levels))
    n = ng * nm
    workers = args.workers or os.cpu_count() or 1
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        table = run_sweep(spec, tmp, executor=args.executor, workers=args.workers)
        wall = time.perf_counter() - t0
    impacts = int(table["n_impacts"].sum())

    # serial cost of one design here (kernels already loaded by run_sweep's warm-up)
    designs = spec.designs()
    sample = designs[:: max(1, n // 8)]
    costs, with_levels = [], []
    off, on = replace(spec.settings, levels=False), replace(spec.settings, levels=True)
    for d in sample:
        t1 = time.perf_counter()
        evaluate_design(d, off)
        t2 = time.perf_counter()
        evaluate_design(d, on)
        costs.append(t2 - t1)
        with_levels.append(time.perf_counter() - t2)

    print(f"sweep: {ng} gaps x {nm} masses = {n} designs, {duration:g} s of motion each, "
          f"{impacts} impacts in all; executor {args.executor}, {workers} workers, "
          f"{os.cpu_count()} cores")
    print(f"import: {t_import:.2f} s")
    print(f"sweep wall time (pool start-up and warm-up included): {wall:.2f} s")
    print(f"per design: {1e3 * wall / n:.1f} ms wall, {1e3 * wall * workers / n:.1f} ms core time")
    base, lev = statistics.median(costs), statistics.median(with_levels)
    print(f"levels in the sweep: {'on' if args.levels else 'off'}")
    print(f"one design alone, serial (median of {len(costs)}): {1e3 * base:.1f} ms without levels, "
          f"{1e3 * lev:.1f} ms with LAFmax/LCpeak/LAeq (+{1e3 * (lev - base):.1f} ms, x{lev / base:.1f})")
    if not args.quick:
        verdict = "met" if wall < 60 else "NOT met"
        print(f"goal (20 x 20 x 20 s under 60 s on this machine): {verdict}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_writing("bench_sweep", main))
