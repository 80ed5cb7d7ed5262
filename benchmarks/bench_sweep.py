"""Wall time of a design sweep: 20 x 20 designs (gap x impact mass), 20 s of motion each.

Run ``python benchmarks/bench_sweep.py`` (or ``--quick`` for 5 x 4 designs of 5 s). The sweep
is the one of the paper's Figure 6: gaps 2-6 cm, impact masses 20-80 g, Table 1 otherwise,
the listener at 0.7 m and 45 degrees over a reflecting plane, every design's maximum SPL from
its impacts. It runs into a fresh temporary directory (so nothing is resumed) on a local
process pool, and prints

* the wall time of the sweep (designs only) and of the whole call (with pool start-up),
* the per-design cost: wall time per design, and core-seconds per design (wall x workers / n),
* the serial cost of one design in this process (the median over a few designs, CPU time), for
  reference, without and with the weighted levels of its run (``FixedSettings.levels``: LAFmax, LCpeak
  and LAeq of the click train at 96 kHz), and the extra cost of the levels per design;
* side by side on the same runs, the levels alone (:func:`acoustiviz.sweep.design_levels`) over
  the motion alone (the design without levels), computed from the clicks alone (``sparse``, what
  a sweep does) and by rendering and filtering every sample (``dense``, what it did before); the
  target is levels at most 2x the motion.

``--levels`` runs the sweep itself with the levels on, after the same sweep without them (the
workers' CPU time of both, side by side); ``--write`` also keeps the output in
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

    from acoustiviz.sweep import FixedSettings, SweepSpec, design_levels, evaluate_design, run_sweep, value_range

    t_import = time.perf_counter() - t_import
    ng, nm, duration = (5, 4, 5.0) if args.quick else (20, 20, 20.0)
    spec = SweepSpec(gap=value_range(0.02, 0.06, ng), m=value_range(0.02, 0.08, nm),
                     settings=FixedSettings(duration=duration, levels=args.levels))
    n = ng * nm
    workers = args.workers or os.cpu_count() or 1
    def sweep(settings):
        """The sweep's table, its wall time (s) and its workers' CPU time (s; a local process pool only)."""
        with tempfile.TemporaryDirectory() as tmp:
            t0, c0 = time.perf_counter(), os.times()
            out = run_sweep(replace(spec, settings=settings), tmp, executor=args.executor, workers=args.workers)
            c1 = os.times()
        return out, time.perf_counter() - t0, c1.children_user + c1.children_system - c0.children_user - \
            c0.children_system

    motion_cpu = None
    if args.levels:  # the same sweep without the levels first, for the side-by-side cost
        _, _, motion_cpu = sweep(replace(spec.settings, levels=False))
    table, wall, sweep_cpu = sweep(spec.settings)
    impacts = int(table["n_impacts"].sum())

    # serial cost of one design here (kernels already loaded by run_sweep's warm-up), CPU time
    designs = spec.designs()
    sample = designs[:: max(1, n // 8)]
    costs, with_levels, ratios, diff = [], [], {"sparse": [], "dense": []}, 0.0
    off, on = replace(spec.settings, levels=False), replace(spec.settings, levels=True)
    for d in sample:
        t1 = time.process_time()
        evaluate_design(d, off)
        t2 = time.process_time()
        evaluate_design(d, on)
        costs.append(t2 - t1)
        with_levels.append(time.process_time() - t2)
        run, kw = _levels_inputs(d, on)
        got = {}
        for method in ratios:
            t3 = time.process_time()
            got[method] = design_levels(run.impacts, method=method, **kw)
            ratios[method].append((time.process_time() - t3) / (t2 - t1))
        diff = max([diff] + [abs(got["sparse"][c] - got["dense"][c]) for c in got["dense"]])

    print(f"sweep: {ng} gaps x {nm} masses = {n} designs, {duration:g} s of motion each, "
          f"{impacts} impacts in all; executor {args.executor}, {workers} workers, "
          f"{os.cpu_count()} cores")
    print(f"import: {t_import:.2f} s")
    print(f"sweep wall time (pool start-up and warm-up included): {wall:.2f} s")
    print(f"per design: {1e3 * wall / n:.1f} ms wall, {1e3 * wall * workers / n:.1f} ms core time")
    base, lev = statistics.median(costs), statistics.median(with_levels)
    print(f"levels in the sweep: {'on' if args.levels else 'off'}")
    if motion_cpu and args.executor == "process":
        print(f"sweep workers' CPU time: {motion_cpu:.2f} s without levels, {sweep_cpu:.2f} s with: levels / motion "
              f"{(sweep_cpu - motion_cpu) / motion_cpu:.2f}")
    print(f"one design alone, serial (median of {len(costs)}): {1e3 * base:.1f} ms without levels, "
          f"{1e3 * lev:.1f} ms with LAFmax/LCpeak/LAeq (+{1e3 * (lev - base):.1f} ms, x{lev / base:.1f})")
    sparse, dense = (statistics.median(ratios[m]) for m in ("sparse", "dense"))
    print(f"levels / motion of a design (median of {len(costs)}, same runs side by side): "
          f"{sparse:.2f} from the clicks alone (sparse), {dense:.1f} rendering and filtering every sample "
          f"(dense); target <= 2: {'met' if sparse <= 2 else 'NOT met'}")
    print(f"largest |sparse - dense| level over those designs (LAFmax, LCpeak, LAeq): {diff:.1e} dB")
    if not args.quick:
        verdict = "met" if wall < 60 else "NOT met"
        print(f"goal (20 x 20 x 20 s under 60 s on this machine): {verdict}")
    return 0


def _levels_inputs(design, settings):
    """The damper run of ``design`` and the other arguments of ``design_levels``, as ``evaluate_design`` makes them."""
    from acoustiviz.core.medium import Medium
    from acoustiviz.dynamics import DamperModel, InitialState, simulate
    from acoustiviz.sweep.evaluate import listener_point, sound_setup

    s = settings
    model = DamperModel(M=s.M, K=s.K, C=s.C, m=design.m, gap=design.gap, k_hertz=design.k_hertz, c1=design.c1,
                        clip_tensile=s.clip_tensile)
    run = simulate(model, s.duration, solver=s.solver, initial=InitialState(v=design.v0), rtol=s.rtol)
    scene, clicks = sound_setup(design, s, Medium(c=s.c, rho=s.rho))
    point = listener_point(design.geometry(s), design.distance, design.angle)
    return run, {"scene": scene, "model": clicks, "point": point, "duration": s.duration}


if __name__ == "__main__":
    raise SystemExit(run_writing("bench_sweep", main))
