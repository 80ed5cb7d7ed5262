"""
The damper in operation: frequency response, bifurcation diagram, Masri-Caughey check.
======================================================================================

The Table 1 damper (M = 0.5 kg, K = 500 N/m, C = 0.05 N·s/m, m = 40.5 g, K_HZ = 5.6e8 N/m^1.5,
c1 = 20 N·s/m, gap d = 4 cm) driven by a harmonic force F0 cos(ωt) with F0 = 5 N on the main mass.
Without the impact mass the lightly damped structure (ζ = 0.16 %) would resonate at 5.03 Hz with
an amplitude of 3 m; with it, six starts per forcing frequency are each run to their attractor
(event solver: closed-form forced flight, compliant Hertz contacts), periodic orbits refined by
shooting with their Floquet multipliers, and the attractors continued up and down in frequency
(:func:`acoustiviz.dynamics.forced.attractor_response`).

* Top: main-mass amplitude with and without the damper; every attractor, coloured by regime,
  its marker growing with the share of starts that reach it; the largest amplitude joined.
* Middle: bifurcation diagram, the main-mass displacement at forcing phase 0 (Poincaré section):
  one dot for period-1 motion, n for period-n, a cloud for non-periodic motion; the unstable
  periodic orbits found on the way open and dashed.
* Second figure: the solvers against the closed-form symmetric two-impacts-per-cycle
  motion of Masri and Caughey (1966) for a damper where it is stable (C = 1 N·s/m, m = 0.1 kg,
  F0 = 2 N, instantaneous impacts e = 0.5).
* Third figure, the noise in operation: the click train of the loudest attractor of each frequency at
  the paper's listener (0.7 m at 45° above the plane), rendered at 96 kHz: LAeq over whole
  periods (at least 1 s, after a 1 s lead-in so the F time weighting has settled), LAFmax and
  LCpeak (IEC 61672-1 weightings), beside the amplitude reduction it buys.
* Fourth figure, the design map: amplitude reduction at 5 Hz, 5 N against the LAeq of the click
  train at the same listener, over impact mass and gap.
"""

# %%
import time

import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz.app.forced import design_map, operating_noise
from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics.forced import Excitation, attractor_response, steady_state
from acoustiviz.dynamics.periodic import masri_caughey
from acoustiviz.output.plot.forced import plot_bifurcation, plot_frequency_response, plot_operating_levels
from acoustiviz.output.plot.style import save_figure, style

FAST = fast_mode()
model = DamperModel()
freqs = np.linspace(3.0, 7.0, 9 if FAST else 41)
t0 = time.perf_counter()
resp = attractor_response(model, freqs, 5.0, sweep="both", starts=3 if FAST else 6)
print(f"{freqs.size} frequencies, {len(resp.entries())} attractors, {len(resp.unstable)} unstable orbits, "
      f"{resp.rounds} continuation rounds: {time.perf_counter() - t0:.1f} s")
for i, j, a, basin in resp.entries()[:: max(1, len(resp.entries()) // 12)]:
    print(f"{freqs[i]:5.2f} Hz  #{j + 1}  {1e3 * a.amplitude:8.2f} mm "
          f"(alone {1e3 * a.amplitude_without_damper:8.2f} mm)  {a.reduction_db:6.2f} dB  "
          f"{a.impacts_per_cycle:5.2f} impacts/cycle  basin {basin:.2f}  {a.regime}")
print(f"several attractors at {sum(len(fa.attractors) > 1 for fa in resp.per_frequency)} of {freqs.size} frequencies")

# %%
with style():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 8.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    plot_frequency_response(resp, ax=ax1)
    ax1.set_xlabel("")
    ax1.set_title("Table 1 damper, F0 = 5 N")
    plot_bifurcation(resp, ax=ax2)
    path = save_figure(fig, output_dir() / "plot_13_frequency_response.png")
print(f"wrote {path}")

# %%
# Masri and Caughey: closed form against the impact map and the compliant event solver.
mc_model = DamperModel(C=1.0, m=0.1)
e = 0.5
fmc = np.linspace(4.8, 5.5, 5 if FAST else 15)
rows = []
for f in fmc:
    ex = Excitation(float(f), 2.0)
    sols = [s for s in masri_caughey(mc_model, ex, e) if s.valid]
    r = steady_state(mc_model, ex, solver="impact-map", restitution=e, tolerance=1e-12)
    sym = (r.regime == "periodic-1" and r.impacts_per_cycle == 2
           and abs(abs(r.impact_phases[1] - r.impact_phases[0]) - np.pi) < 1e-4)
    ref = min(sols, key=lambda s: abs(s.approach_speed - r.impact_speeds[0])) if sols and sym else None
    rows.append((f, [s.amplitude for s in sols], r.amplitude, ref.amplitude if ref else np.nan, sym))
    if ref is not None:
        print(f"{f:5.3f} Hz  Masri-Caughey {1e3 * ref.amplitude:.6f} mm  impact map {1e3 * r.amplitude:.6f} mm"
              f"  relative difference {abs(r.amplitude / ref.amplitude - 1):.1e}")

with style():
    fig = Figure(figsize=(7.0, 4.0), layout="constrained")
    ax = fig.subplots()
    for f, amps, _, _, _ in rows:
        for a in amps:
            ax.plot(f, 1e3 * a, "o", ms=9, mfc="none", color="0.4")
    ax.plot([], [], "o", ms=9, mfc="none", color="0.4", label="Masri-Caughey closed form (both roots)")
    sym = [row for row in rows if row[4]]
    ax.plot([r[0] for r in sym], [1e3 * r[2] for r in sym], "x", color="C3", ms=7,
            label="impact map, e = 0.5 (symmetric 2 impacts/cycle)")
    other = [row for row in rows if not row[4]]
    if other:
        ax.plot([r[0] for r in other], [1e3 * r[2] for r in other], "+", color="C0", ms=7,
                label="impact map, other regimes")
    ax.set_xlabel("forcing frequency (Hz)")
    ax.set_ylabel("main-mass amplitude (mm)")
    ax.set_title("C = 1 N s/m, m = 0.1 kg, F0 = 2 N")
    ax.legend(fontsize=8)
    path = save_figure(fig, output_dir() / "plot_13_masri_caughey.png")
print(f"wrote {path}")

# %%
# The noise in operation: weighted levels of the loudest attractor's click train at each frequency.
t0 = time.perf_counter()
loudest = []
for fa in resp.per_frequency:
    ok = [a for a in fa.attractors if a.success]
    nz = [operating_noise(a) for a in ok]
    k = int(np.argmax([n.lcpeak_db for n in nz])) if nz else -1
    loudest.append((ok[k], nz[k]) if nz else (None, None))
noises = [n for _, n in loudest]
print(f"levels of {freqs.size} click trains at 96 kHz: {time.perf_counter() - t0:.1f} s")
lev = {c: np.array([getattr(n, c) if n is not None else np.nan for n in noises])
       for c in ("laeq_db", "lafmax_db", "lcpeak_db")}
with style():
    fig = Figure(figsize=(7.5, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(2, 1))
    plot_operating_levels(freqs, lev, [a.regime if a is not None else "unresolved" for a, _ in loudest], ax=ax1)
    ax1.set_xlabel("")
    ax1.set_ylabel("level at 0.7 m, 45° (dB re 20 µPa)")
    ax1.set_title("Table 1 damper, F0 = 5 N, the loudest attractor: the noise it makes while it works")
    ax2.plot(freqs, [a.reduction_db if a is not None else np.nan for a, _ in loudest], "-o", ms=3, color="k")
    ax2.axhline(0, color="0.6", lw=0.8)
    ax2.set_ylabel("amplitude reduction (dB)")
    ax2.set_xlabel("forcing frequency (Hz)")
    path = save_figure(fig, output_dir() / "plot_13_operating_noise.png")
print(f"wrote {path}")

# %%
# Design map: what each design buys (amplitude reduction) and what it costs (LAeq) at 5 Hz, 5 N.
masses = np.array([0.02, 0.06]) if FAST else np.array([0.02, 0.03, 0.0405, 0.06, 0.08])
gaps = np.array([0.02, 0.06]) if FAST else np.array([0.02, 0.03, 0.04, 0.06, 0.08])
t0 = time.perf_counter()
dm = design_map(model, masses, gaps, 5.0, 5.0, max_cycles=300 if FAST else 2000)
print(f"design map, {masses.size} x {gaps.size} designs: {time.perf_counter() - t0:.1f} s")
for i, m in enumerate(masses):
    print("  m = %5.1f g: " % (1e3 * m) + "  ".join(
        f"d={100 * g:g} cm {dm.reduction_db[i, j]:6.2f} dB/{dm.laeq_db[i, j]:5.1f} dB(A) {dm.regime[i, j]}"
        for j, g in enumerate(gaps)))
with style():
    fig = Figure(figsize=(7.0, 4.6), layout="constrained")
    ax = fig.subplots()
    for j, g in enumerate(gaps):
        ok = np.isfinite(dm.laeq_db[:, j])
        ax.plot(dm.laeq_db[ok, j], dm.reduction_db[ok, j], "-o", ms=4, label=f"gap {100 * g:g} cm")
        for i in np.flatnonzero(ok):
            if dm.regime[i, j] == "non-periodic":
                ax.plot(dm.laeq_db[i, j], dm.reduction_db[i, j], "o", ms=9, mfc="none", color="tab:red")
    if any(dm.regime[i, j] == "non-periodic" for i in range(masses.size) for j in range(gaps.size)):
        ax.plot([], [], "o", ms=9, mfc="none", color="tab:red", label="non-periodic")
    for i, m in enumerate(masses):
        j = int(np.flatnonzero(np.isfinite(dm.laeq_db[i]))[-1]) if np.isfinite(dm.laeq_db[i]).any() else None
        if j is not None:
            ax.annotate(f"{1e3 * m:g} g", (dm.laeq_db[i, j], dm.reduction_db[i, j]), fontsize=7,
                        xytext=(4, 0), textcoords="offset points")
    ax.set_xlabel("LAeq of the click train at 0.7 m, 45° (dB(A) re 20 µPa)")
    ax.set_ylabel("amplitude reduction at 5 Hz (dB)")
    ax.set_title("Design map, F0 = 5 N at 5 Hz: impact mass along each line")
    ax.legend(fontsize=8)
    path = save_figure(fig, output_dir() / "plot_13_design_map.png")
print(f"wrote {path}")
