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

Panel D: the same structure in operation, driven by a harmonic force of 5 N at three frequencies
around its resonance (4.6, 4.85 and 5.1 Hz), N = 1, 2, 3 and 5 balls of m / N each: every attractor
found from one start (the linear one) after up to 60 cycles, its noise at the paper's listener (0.7 m
at 45 degrees above the plane) from every collision, and the worst case over the band and the
attractors of LCpeak, LAeq and the vibration reduction (20 lg of the amplitude without the damper
over the amplitude with it). The operating noise of the five balls is written as a WAV.
"""

# %%
import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz.app.damper import damper_model
from acoustiviz.app.forced import ForcedJob
from acoustiviz.app.forced import run as run_forced
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
# In operation: the worst case over a band around the resonance, at equal total ball mass
FORCE = 5.0
FREQUENCIES = (5.1,) if fast_mode() else (4.6, 4.85, 5.1)
OPERATING = (1, 2) if fast_mode() else (1, 2, 3, 5)
MAX_CYCLES = 20 if fast_mode() else 60
resonance = float(np.sqrt(TABLE1.K / (TABLE1.M + TABLE1.m)) / (2 * np.pi))
operating = {}
for n in OPERATING:
    wav = str(output_dir() / "plot_17_balls_5.wav") if n == 5 else None
    job = ForcedJob(damper_model(m=TABLE1.m / n), FREQUENCIES, amplitude=FORCE, starts=1, max_cycles=MAX_CYCLES,
                    sweep="independent", noise_seconds=1.0, balls=n, wav=wav)
    forced = run_forced(job)
    forced.write()
    rows = [r for r in forced.rows if r["laeq_db"] is not None]
    operating[n] = {
        "attractors": len(forced.rows),
        "failed": len(forced.failed),
        "reduction_db": min(r["reduction_db"] for r in rows),
        "laeq_db": max(r["laeq_db"] for r in rows),
        "lcpeak_db": max(r["lcpeak_db"] for r in rows),
        "lafmax_db": max(r["lafmax_db"] for r in rows),
        "collisions_per_cycle": max(r["impacts_per_cycle"] for r in rows),
        "regimes": sorted({r["regime"] for r in rows}),
    }
print(f"in operation: {FORCE:g} N at {', '.join(f'{f:g}' for f in FREQUENCIES)} Hz (resonance {resonance:.2f} Hz), "
      f"1 start, up to {MAX_CYCLES} cycles; worst case over the band and the attractors")
print("balls  attractors  reduction dB  LAeq dB  LCpeak dB  LAFmax dB  collisions per cycle")
for n, r in operating.items():
    print(f"{n:5d}  {r['attractors']:10d}  {r['reduction_db']:12.1f}  {r['laeq_db']:7.1f}  {r['lcpeak_db']:9.1f}  "
          f"{r['lafmax_db']:9.1f}  {r['collisions_per_cycle']:20.1f}")

# %%
with style():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 11.5), layout="constrained")
    ax1, ax2, ax3, ax4 = fig.subplots(4, 1, height_ratios=(3, 2, 2, 2.2))
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

    no = np.array(OPERATING)
    ax4.plot(no, [r["lcpeak_db"] for r in operating.values()], "o-", color="C4", label="LCpeak")
    ax4.plot(no, [r["lafmax_db"] for r in operating.values()], "^:", color="C4", label="LAFmax")
    ax4.plot(no, [r["laeq_db"] for r in operating.values()], "s--", color="C4", label="LAeq")
    ax4.set_xscale("log")
    ax4.set_xticks(no, [str(n) for n in no])
    ax4.set_xlim(ax2.get_xlim())
    ax4.set_xlabel("number of balls N (equal total mass)")
    ax4.set_ylabel("worst level at the listener (dB)", color="C4")
    ax4.legend(fontsize=8, loc="center right")  # right of N = 5: clear of the curves
    ax4b = ax4.twinx()
    worst = [r["reduction_db"] for r in operating.values()]
    ax4b.plot(no, worst, "D-", color="C0")
    ax4b.set_ylim(min(worst) - 5.0, max(worst) + 5.0)  # a 10 dB span at least: no zoom into round-off
    ax4b.set_ylabel("worst vibration reduction (dB)", color="C0")
    ax4.set_title(f"D: in operation, {FORCE:g} N at {FREQUENCIES[0]:g}-{FREQUENCIES[-1]:g} Hz: worst case over "
                  "the band", loc="left", fontsize=10)
    path = save_figure(fig, output_dir() / "plot_17_balls.png")
print(f"wrote {path}")
