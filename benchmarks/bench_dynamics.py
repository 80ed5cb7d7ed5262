"""Error against run time of the impact-damper solvers (Table 1, Figure 5 start).

Usage::

    python benchmarks/bench_dynamics.py           # 3 s of motion (the first 40 impacts), ~1 min
    python benchmarks/bench_dynamics.py --full    # 20 s of motion, more settings (several minutes)
    python benchmarks/bench_dynamics.py --write   # the default run, also to results/bench_dynamics.txt

Prints one row per solver setting: warm run time, errors over the first 40 impacts (largest
relative error of the approach speeds, largest error of the contact start times), the relative
error of eq 16 (damping inclination from the first two exact positive maxima), the energy closure
and the speed against the paper's Newmark at 1e-7 s measured in the same run; then the cost of the
default contact tolerance against 1e-12. ``--full`` writes ``benchmarks/results/bench_dynamics.csv``
and ``bench_dynamics.png`` (error against run time); ``--write`` keeps the printed output in
``benchmarks/results/bench_dynamics.txt`` (machine and date first).

The reference is the event solver at rtol = 2e-15. Before the table the script checks it: energy
closure, agreement with the same solver at half and 2.5x its tolerance, and agreement with an
independent method (SciPy DOP853 on eq 15 with terminal events, rtol 3e-14, Python right-hand
side) over the first 10 and 40 impacts. The motion is chaotic: a change of one part in 1e14 grows
to about 1e-7 by the 40th impact, which bounds what the independent method can confirm there.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

import numpy as np
from _damper_reference import (
    IVP_RTOL,
    N_COMPARE,
    REFERENCE_RTOL,
    RESOLVED_BOUND,
    compare_impacts,
    reference,
    resolved_impacts,
    solve_ivp_impacts,
    speed_accuracy,
)
from _timing import run_writing

from acoustiviz.constants import DEFAULT_RTOL
from acoustiviz.dynamics import TABLE1, simulate
from acoustiviz.files import write_csv_atomic

RESULTS = Path(__file__).resolve().parent / "results"

FULL = [
    ("newmark", {"dt": 1e-5}),
    ("newmark", {"dt": 3e-6}),
    ("newmark", {"dt": 1e-6}),
    ("newmark", {"dt": 3e-7}),
    ("newmark", {"dt": 1e-7}),
    ("event", {"rtol": 1e-6}),
    ("event", {"rtol": 1e-8}),
    ("event", {"rtol": 1e-10}),
    ("event", {"rtol": 1e-12}),
    ("event", {"rtol": 1e-13}),
    ("event", {"rtol": 1e-14}),
    ("impact-map", {"rtol": 1e-8}),
    ("impact-map", {"rtol": 1e-12}),
]
QUICK = [
    ("newmark", {"dt": 1e-5}),
    ("newmark", {"dt": 1e-6}),
    ("newmark", {"dt": 1e-7}),
    ("event", {"rtol": 1e-8}),
    ("event", {"rtol": 1e-10}),
    ("event", {"rtol": 1e-12}),
    ("event", {"rtol": 1e-13}),
    ("event", {"rtol": 1e-14}),
    ("impact-map", {"rtol": 1e-12}),
]


def check_reference(duration):
    ref = reference(TABLE1, duration)
    print(f"reference: event solver rtol {REFERENCE_RTOL:g}, {len(ref.impacts)} impacts in {duration:g} s, "
          f"energy closure {ref.energy.relative_closure_error:.1e} of {ref.energy.initial:g} J")
    for rtol in (REFERENCE_RTOL / 2, 2.5 * REFERENCE_RTOL):
        c = compare_impacts(simulate(TABLE1, duration, rtol=rtol).impacts, ref.impacts)
        print(f"  vs event rtol {rtol:g}, first {c.n}: |dt| {c.time_error:.1e} s, "
              f"du/u {c.velocity_error:.1e}, walls match {c.walls_match}")
    t0 = time.perf_counter()
    ivp = solve_ivp_impacts(TABLE1, n_impacts=N_COMPARE, rtol=IVP_RTOL)
    el = time.perf_counter() - t0
    coarser = solve_ivp_impacts(TABLE1, n_impacts=N_COMPARE, rtol=10 * IVP_RTOL)
    n_resolved = resolved_impacts(ivp, coarser, RESOLVED_BOUND)
    for n in (n_resolved, N_COMPARE):
        c = compare_impacts(ivp, ref.impacts, n)
        print(f"  vs scipy DOP853 + events (independent, rtol {IVP_RTOL:g}, {el:.1f} s), first {c.n}"
              f"{f' (those it resolves to {RESOLVED_BOUND:g} s)' if n == n_resolved else ''}: "
              f"|dt| {c.time_error:.1e} s, du/u {c.velocity_error:.1e}, walls match {c.walls_match}")
    return ref


def run(cases, duration, repeats=5):
    """Warm up every solver, then time and compare each setting against the reference."""
    for solver in ("event", "newmark", "impact-map"):  # compile / load the kernels
        simulate(TABLE1, 0.01, solver=solver)
    ref = check_reference(duration)
    rows = speed_accuracy(cases, model=TABLE1, duration=duration, ref=ref, repeats=repeats)
    base = [r for r in rows if r.solver == "newmark" and r.label == "dt=1e-07"]
    t_base = base[0].time_s if base else float("nan")
    return rows, t_base


def default_cost(duration, repeats=101):
    """Solver time of the default tolerance over that of 1e-12 (interleaved runs, best of each)."""
    best = {DEFAULT_RTOL: np.inf, 1e-12: np.inf}
    for _ in range(repeats):
        for rtol in best:
            best[rtol] = min(best[rtol], simulate(TABLE1, duration, rtol=rtol).solver_time)
    return best[DEFAULT_RTOL], best[1e-12]


def print_table(rows, t_base):
    head = (f"{'solver':<11} {'setting':<11} {'time (ms)':>10} {'impacts':>7} "
            f"{'max du/u (40)':>13} {'max |dt| s (40)':>15} {'eq16 err':>8} {'walls':>5} {'agree':>5} "
            f"{'energy err':>10} {'speed-up':>9}")
    print(head)
    print("-" * len(head))
    for r in rows:
        c = r.comparison
        mark = " (default)" if r.solver == "event" and r.label == f"rtol={DEFAULT_RTOL:g}" else ""
        print(f"{r.solver:<11} {r.label:<11} {1000 * r.time_s:>10.2f} {r.n_impacts:>7d} "
              f"{c.velocity_error:>13.1e} {c.time_error:>15.1e} {r.inclination_error:>8.1e} "
              f"{'ok' if c.walls_match else 'DIFF':>5} {c.n_agree:>5d} {r.energy_error:>10.1e} "
              f"{t_base / r.time_s:>8.0f}x{mark}")
    print("eq16 err: relative error of the damping inclination from the first two exact maxima; "
          "agree: leading impacts (of 40) on the same wall with approach speed within 1e-3; "
          "energy err: relative energy closure error (< 0: energy gained); speed-up: run time of "
          "Newmark at 1e-7 s over this one's, measured in this run")


def draw_chart(rows, path, goal=None):
    """Error against run time (top) and impacts followed against run time (bottom), as PNG."""
    from matplotlib.figure import Figure

    from acoustiviz.output.plot.dynamics import plot_impacts_followed, plot_speed_accuracy
    from acoustiviz.output.plot.style import save_figure, style

    data = [{"solver": r.solver, "label": r.label, "time_s": r.time_s,
             "error": r.comparison.velocity_error, "n_agree": r.comparison.n_agree} for r in rows]
    with style():
        fig = Figure(figsize=(7.5, 8.0), layout="constrained")
        ax1, ax2 = fig.subplots(2, 1, height_ratios=(3, 2), sharex=True)
        plot_speed_accuracy(data, ax=ax1, goal=goal)
        plot_impacts_followed(data, ax=ax2)
        ax1.set_xlabel("")
        return save_figure(fig, path)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true",
                    help="also write the output to benchmarks/results/bench_dynamics.txt (machine and date first)")
    ap.add_argument("--full", action="store_true", help="20 s of motion and more settings")
    ap.add_argument("--quick", action="store_true", help="the default (kept for old scripts)")
    args = ap.parse_args(argv)
    cases, duration = (FULL, 20.0) if args.full else (QUICK, 3.0)
    print(f"python {sys.version.split()[0]}, {platform.machine()} {platform.processor()}".rstrip()
          + f"; {duration:g} s of motion")
    rows, t_base = run(cases, duration, repeats=15 if args.full else 7)
    print()
    print_table(rows, t_base)
    t_def, t_12 = default_cost(duration)
    print(f"\ndefault tolerance rtol {DEFAULT_RTOL:g}: {1e3 * t_def:.3f} ms against {1e3 * t_12:.3f} ms "
          f"at 1e-12 (x{t_def / t_12:.2f}; best of 101 interleaved runs)")
    if not args.full:  # the chart and its CSV in results/ are the --full run's
        return 0
    RESULTS.mkdir(parents=True, exist_ok=True)
    write_csv_atomic(
        RESULTS / "bench_dynamics.csv",
        ["solver", "setting", "time_s", "n_impacts", "velocity_error", "time_error", "inclination_error",
         "walls_match", "n_agree", "energy_error", "speedup_vs_newmark_1e-7"],
        [np.array([r.solver for r in rows]), np.array([r.label for r in rows]),
         np.array([f"{r.time_s:.6g}" for r in rows]), np.array([r.n_impacts for r in rows]),
         np.array([f"{r.comparison.velocity_error:.3g}" for r in rows]),
         np.array([f"{r.comparison.time_error:.3g}" for r in rows]),
         np.array([f"{r.inclination_error:.3g}" for r in rows]),
         np.array([str(r.comparison.walls_match) for r in rows]),
         np.array([r.comparison.n_agree for r in rows]),
         np.array([f"{r.energy_error:.3g}" for r in rows]),
         np.array([f"{t_base / r.time_s:.4g}" for r in rows])],
        fmt="%s",
    )
    path = draw_chart(rows, RESULTS / "bench_dynamics.png", goal=(0.05, 1e-6))
    print(f"\nwrote {RESULTS / 'bench_dynamics.csv'} and {path}")
    return 0


if __name__ == "__main__":
    sys.exit(run_writing("bench_dynamics", main))
