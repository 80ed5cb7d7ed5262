"""
Impact-damper solvers: error against run time.
==============================================

The Table 1 run from the Figure 5 start, solved by the paper's Newmark scheme at fixed steps, by
the event-driven solver at several tolerances and by the instantaneous impact map. The error is the
largest relative error of the approach speeds over the first 40 impacts against the converged
reference (event solver at rtol 2e-15); beyond about 50 impacts the chaotic motion makes any
impact-by-impact comparison meaningless. ``benchmarks/bench_dynamics.py`` draws the same chart
over 20 s with the timings of Newmark at 1e-7 s; in fast mode this script runs 2.5 s of motion
(enough for 40 impacts) with fewer settings.
"""

# %%
import sys
from pathlib import Path

from _gallery import fast_mode, output_dir

from acoustiviz.dynamics import TABLE1, simulate
from acoustiviz.output.plot.dynamics import plot_impacts_followed, plot_speed_accuracy
from acoustiviz.output.plot.style import save_figure, style

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))  # the reference harness
from _damper_reference import speed_accuracy  # noqa: E402

if fast_mode():
    DURATION = 2.5
    CASES = [("newmark", {"dt": 1e-5}), ("newmark", {"dt": 2e-6}), ("event", {"rtol": 1e-8}),
             ("event", {"rtol": 1e-12}), ("impact-map", {"rtol": 1e-12})]
else:
    DURATION = 20.0
    CASES = [("newmark", {"dt": dt}) for dt in (1e-5, 3e-6, 1e-6, 3e-7, 1e-7)]
    CASES += [("event", {"rtol": r}) for r in (1e-6, 1e-8, 1e-10, 1e-12, 1e-13, 1e-14)]
    CASES += [("impact-map", {"rtol": 1e-12})]

for solver in ("event", "newmark", "impact-map"):  # compile or load the kernels first
    simulate(TABLE1, 0.01, solver=solver)
rows = speed_accuracy(CASES, duration=DURATION, repeats=3)
for r in rows:
    print(f"{r.solver:<11} {r.label:<11} {1000 * r.time_s:9.2f} ms  "
          f"error {r.comparison.velocity_error:.1e}  walls {'ok' if r.comparison.walls_match else 'differ'}")

# %%
data = [{"solver": r.solver, "label": r.label, "time_s": r.time_s,
         "error": r.comparison.velocity_error, "n_agree": r.comparison.n_agree} for r in rows]
with style():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 8.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, height_ratios=(3, 2), sharex=True)
    plot_speed_accuracy(data, ax=ax1, goal=None if fast_mode() else (0.05, 1e-6))
    ax1.set_title(f"Impact damper, Table 1, {DURATION:g} s of motion: error against run time")
    ax1.set_xlabel("")
    plot_impacts_followed(data, ax=ax2)
    path = save_figure(fig, output_dir() / "plot_06_speed_accuracy.png")
print(f"wrote {path}")
