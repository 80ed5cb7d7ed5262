"""
How loud is the damper? Weighted levels and band spectra of Table 1 against a quieter design
=============================================================================================

The peak SPL the paper reports is one number of one impact. The questions a noise regulation or a
listener asks are others: the C-weighted peak of the impulses (LCpeak), the A-weighted maximum
and average (LAFmax, LAeq), the exposure of the whole run (SEL(A)), where the energy sits in
frequency (1/3-octave bands), how loud and sharp it sounds (ISO 532-1 loudness in sone, DIN 45692
sharpness in acum) and how much of the energy each impact loses becomes sound.

Two designs, each run for 20 s from dx/dt(0) = 2 m/s (event solver) and heard 0.7 m from the
sphere at 45° above the rigid plane (both cavity walls radiating, the paper's half-sine pulses and
19.05 mm sphere):

* **Table 1**: m = 40.5 g, d = 4 cm;
* **quieter**: m = 60 g, d = 5 cm, which damps slightly faster (its fitted damping inclination is
  higher) with fewer, slower impacts.

The levels are evaluated on the signal computed at 96 kHz (clicks in closed form at >= 1.5 MHz,
band-limited flat to 43.2 kHz), not on a 48 kHz file. In fast mode (the test suite) the runs last
5 s and loudness is skipped.
"""

# %%
from dataclasses import replace

import numpy as np
from _gallery import fast_mode, output_dir
from matplotlib.figure import Figure

from acoustiviz import sound
from acoustiviz.app.levels import rendered_levels
from acoustiviz.dynamics import TABLE1, simulate
from acoustiviz.dynamics.metrics import envelope_inclination, positive_maxima, sample_times
from acoustiviz.levels import loudness_available
from acoustiviz.levels.energy import run_energy
from acoustiviz.output.plot.levels import plot_band_levels, plot_weighted_levels
from acoustiviz.output.plot.style import save_figure, style

DURATION = 5.0 if fast_mode() else 20.0
LISTENER = [0.495, 0.0, 0.514]  # m: 0.7 m from the sphere's centre at 45 deg
RADIUS = 0.01905  # m, the paper's sphere
DESIGNS = {"Table 1 (m = 40.5 g, d = 4 cm)": (TABLE1.m, TABLE1.gap), "quieter (m = 60 g, d = 5 cm)": (0.060, 0.050)}
out_dir = output_dir()
with_loudness = loudness_available() and not fast_mode()

# %%
results = {}
for name, (m, gap) in DESIGNS.items():
    model = replace(TABLE1, m=m, gap=gap)
    run = simulate(model, DURATION, t_eval=sample_times(DURATION, model))
    incl = envelope_inclination(positive_maxima(run.t, run.x)).value
    room = sound.CavityScene("plane", radius=RADIUS, gap=gap)
    clicks = sound.ClickModel(k_hertz=model.k_hertz, mass=m, main_mass=model.M)
    seq = run.impacts.sequence()
    report = rendered_levels(seq, room, clicks, LISTENER, duration=DURATION, channels=[name],
                             with_loudness=with_loudness)
    energy = run_energy(run.impacts, room, clicks, DURATION)
    results[name] = {"e": incl, "n": len(seq), "report": report, "energy": energy}

# %%
cols = ("lcpeak_db", "lafmax_db", "laeq_db", "sel_a_db")
print(f"{'design':32} {'e (cm/s)':>8} {'impacts':>7} {'LCpeak':>7} {'LAFmax':>7} {'LAeq':>6} {'SEL(A)':>7} "
      f"{'LW (dB)':>8} {'eff. loudest':>12}" + (f" {'N5 (sone)':>9} {'S (acum)':>8}" if with_loudness else ""))
for name, r in results.items():
    row = r["report"].levels.rows()[0]
    en = r["energy"]
    line = (f"{name:32} {r['e'] * 100:8.3f} {r['n']:7d} " + " ".join(f"{row[c]:7.1f}" for c in cols)
            + f" {en.sound_power_level_db:8.1f} {en.efficiency[en.loudest]:12.3g}")
    if with_loudness:
        ld = r["report"].loudness.rows()[0]
        line += f" {ld['n5_sone']:9.2f} {ld['sharpness_acum']:8.2f}"
    print(line)
print("levels in dB re 20 uPa (SEL re (20 uPa)^2 s), evaluated at 96 kHz over the whole run; LW re 1 pW")

# %%
# Band spectra (solid: Leq over the run, dashed: the band's LFmax) and the weighted levels.
with style():
    fig = Figure(figsize=(11.0, 4.4), layout="constrained")
    ax_b, ax_l = fig.subplots(1, 2, width_ratios=[1.4, 1.0])
    for name, r in results.items():
        bl = r["report"].bands
        plot_band_levels(bl.nominal_hz, bl.leq_db[0], lmax_db=bl.lmax_db[0], label=name.split(" (")[0], ax=ax_b)
    ax_b.set_title(f"1/3-octave bands over {DURATION:g} s at 0.7 m, 45°")
    plot_weighted_levels([n.split(" (")[0] for n in results],
                         [r["report"].levels.rows()[0] for r in results.values()], ax=ax_l, columns=cols)
    ax_l.set_ylim(bottom=np.floor(min(min(r["report"].levels.rows()[0][c] for c in cols)
                                      for r in results.values()) / 10) * 10 - 10)
    ax_l.set_title("weighted levels (computed at 96 kHz)")
    path = save_figure(fig, out_dir / "plot_14_levels.png")
print(f"wrote {path}")
