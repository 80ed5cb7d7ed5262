"""
Several balls in the cavity at equal total impact mass.
=======================================================

The Table 1 structure (M = 0.5 kg, K = 500 N/m, C = 0.05 N·s/m) starts from x = 0 with dx/dt = 2 m/s.
Its cavity holds N = 1, 2, 3, 5 or 10 equal steel spheres of total mass 40.5 g (each m / N) in a
column, with the free travel (the cavity's length less the sum of the diameters) kept at 4 cm, the
wall contact of Table 1 (K_HZ = 5.6e8 N/m^1.5, c1 = 20 N·s/m) and, between two balls, paper eq 2
with both radii and the same c1. The balls start at rest, the free travel split into N + 1 equal
spaces. Each run lasts 20 s.

Panel A: the main mass's positive maxima, without the damper and with N balls. Panel B: the
vibration reduction (1 - RMS of x with the damper / RMS without it, over the run) and the settling
time (maxima below 5 % of the first). Panel C: the largest and the median peak contact force, and
the number of collisions.
"""

# %%
import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz.dynamics import TABLE1, MultiBallModel, equal_balls, simulate_balls
from acoustiviz.dynamics.metrics import free_response, positive_maxima, sample_times, settling_time
from acoustiviz.output.plot.style import save_figure, style

DURATION = 5.0 if fast_mode() else 20.0
BALLS = (1, 2, 3, 5, 10)
t = sample_times(DURATION, TABLE1)
alone = free_response(t)
rms_alone = float(np.sqrt(np.mean(alone**2)))
results = {}
for n in BALLS:
    cavity = equal_balls(n, TABLE1.m / n, TABLE1.gap, TABLE1.k_hertz, TABLE1.c1)
    run = simulate_balls(MultiBallModel((cavity,), TABLE1.M, TABLE1.K, TABLE1.C), DURATION, t_eval=t)
    maxima = positive_maxima(t, run.x)
    imp = run.impacts
    results[n] = {
        "maxima": maxima,
        "reduction": 1.0 - float(np.sqrt(np.mean(run.x**2))) / rms_alone,
        "settling": settling_time(maxima),
        "collisions": len(imp),
        "peak_force": float(imp.peak_force.max()),
        "median_force": float(np.median(imp.peak_force)),
        "radius": cavity.radii[0],
        "closure": run.energy.relative_closure_error,
    }
print(f"{DURATION:g} s of the Table 1 structure, 40.5 g of steel balls in total, free travel 4 cm")
print("balls  ball radius mm  RMS reduction %  settling s  collisions  largest force N  median force N")
for n, r in results.items():
    print(f"{n:5d}  {1000 * r['radius']:14.2f}  {100 * r['reduction']:15.1f}  {r['settling']:10.2f}  "
          f"{r['collisions']:10d}  {r['peak_force']:15.0f}  {r['median_force']:14.0f}")

# %%
with style():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 9.0), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(3, 1, height_ratios=(3, 2, 2))
    ref = positive_maxima(t, alone)
    ax1.plot(ref.time, 100 * ref.value, "o-", ms=2, lw=0.8, color="0.6", label="without damper")
    for i, (n, r) in enumerate(results.items()):
        ax1.plot(r["maxima"].time, 100 * r["maxima"].value, "o-", ms=2, lw=0.8, color=f"C{i}",
                 label=f"N = {n}")
    ax1.set_xlabel("time t (s)")
    ax1.set_ylabel("positive maxima of x (cm)")
    ax1.set_title("A: free vibration of the main mass", loc="left", fontsize=10)
    ax1.legend(fontsize=8, ncol=3)

    ns = np.array(BALLS)
    ax2.plot(ns, [100 * r["reduction"] for r in results.values()], "o-", color="C0")
    ax2.set_xscale("log")
    ax2.set_xticks(ns, [str(n) for n in ns])
    ax2.set_xlabel("number of balls N (equal total mass)")
    ax2.set_ylabel("RMS reduction of x (%)", color="C0")
    ax2b = ax2.twinx()
    ax2b.plot(ns, [r["settling"] for r in results.values()], "s--", color="C1")
    ax2b.set_ylabel("settling time (s)", color="C1")
    ax2.set_title("B: vibration reduction against the undamped structure", loc="left", fontsize=10)

    ax3.plot(ns, [r["peak_force"] for r in results.values()], "o-", color="C3", label="largest")
    ax3.plot(ns, [r["median_force"] for r in results.values()], "o:", color="C3", label="median")
    ax3.set_xscale("log")
    ax3.set_yscale("log")
    ax3.set_xticks(ns, [str(n) for n in ns])
    ax3.set_xlabel("number of balls N (equal total mass)")
    ax3.set_ylabel("peak contact force (N)", color="C3")
    ax3.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 0.2))
    ax3b = ax3.twinx()
    ax3b.plot(ns, [r["collisions"] for r in results.values()], "s--", color="C2")
    ax3b.set_ylabel("collisions in the run", color="C2")
    ax3.set_title("C: contact forces and collisions", loc="left", fontsize=10)
    path = save_figure(fig, output_dir() / "plot_17_balls.png")
print(f"wrote {path}")
