"""
Acoustic-based design: the range of the maximum SPL at equal damping (paper Table 2).
====================================================================================

For each band of damping inclination (paper eq 16, bands 0.1 cm/s wide centred on 0.7 ... 1.2
cm/s, as in Table 2) the designs of the Figure 6 sweep (``plot_07_design_maps.py``; gaps 2-6
cm, impact masses 20-80 g) that damp equally well span a range of maximum SPL at the listener;
the quietest of them is the acoustic-based choice, and the range is what that choice saves.

Where and why this differs from the paper. The quietest designs agree with the paper's
minima within about 2-3 dB (ours 101-106 dB, the paper's 100-104 dB), but over the full
20-80 g grid our loudest designs reach 110-116 dB and the saving 6-13 dB, against the paper's
105-108 dB and 2-8 dB. At a fixed 19.05 mm sphere the level falls 5-6 dB per doubling of the
impact mass, so the spread inside a band is mostly the spread of masses in it, and the paper
does not state the grid of its Figure 6. Keeping only the masses from Table 1's 40.5 g upwards
(green) gives maxima of 107-110 dB and savings of 1.4-8.9 dB, close to the paper's table. The
band a design falls in also depends on eq 16's two maxima, which one impact near a maximum can
move (the motion is chaotic), so the paper's Newmark runs and our event-driven solver can sort
individual designs into different bands.
"""

# %%
import sys

import numpy as np
from _gallery import fast_mode, output_dir
from matplotlib.figure import Figure

from acoustiviz.output.plot.design import plot_design_table
from acoustiviz.output.plot.style import save_figure, style
from acoustiviz.sweep import (
    PAPER_TABLE2,
    FixedSettings,
    SweepSpec,
    design,
    design_table,
    run_sweep,
    value_range,
    write_design_table,
)

n_gap, n_mass, duration = (4, 3, 3.0) if fast_mode() else (20, 20, 20.0)
spec = SweepSpec(gap=value_range(0.02, 0.06, n_gap), m=value_range(0.02, 0.08, n_mass),
                 settings=FixedSettings(duration=duration))
# the same directory as plot_07: if that script ran, nothing is recomputed
table = run_sweep(spec, output_dir() / "design_sweep", progress=sys.stderr)

centres = [row[0] for row in PAPER_TABLE2]
bands = design_table(table, centres=centres)
heavy = design_table(table.subset(table["mass_kg"] >= 0.0405 - 1e-12), centres=centres)
write_design_table(bands, output_dir() / "plot_08_design_table.csv")

# %%
paper = {round(100 * e, 3): (lo, hi, dec) for e, lo, hi, dec in PAPER_TABLE2}
lines = [f"{'e':>5} | {'paper Table 2':^17} | {'this sweep, 20-80 g':^26} | {'m >= 40.5 g':^17}",
         f"{'cm/s':>5} | {'min':>5} {'max':>5} {'dec':>5} | {'n':>3} {'min':>5} {'max':>5} {'dec':>5} "
         f"{'(m, d)':>6} | {'min':>5} {'max':>5} {'dec':>5}"]
ours = {round(100 * b.centre, 3): b for b in bands}
mine = {round(100 * b.centre, 3): b for b in heavy}
for e, (lo, hi, dec) in paper.items():
    b, h = ours.get(e), mine.get(e)
    our = (f"{b.n_designs:3d} {b.min_spl_db:5.1f} {b.max_spl_db:5.1f} {b.decrease_db:5.1f} "
           f"{1e3 * b.quietest_mass:2.0f}g,{1e2 * b.quietest_gap:.1f}") if b else f"{'-':>26}"
    hv = f"{h.min_spl_db:5.1f} {h.max_spl_db:5.1f} {h.decrease_db:5.1f}" if h else f"{'-':>17}"
    lines.append(f"{e:5.1f} | {lo:5.0f} {hi:5.0f} {dec:5.0f} | {our:>26} | {hv}")
print("\n".join(lines))
try:
    print(design(table, 0.008, 0.0005).summary())
except ValueError as exc:  # a small fast-mode sweep may have no design in the band
    print(exc)

# %%
with style():
    fig = Figure(figsize=(12.5, 5.2), layout="constrained")
    ax, ax_t = fig.subplots(1, 2, width_ratios=[1.0, 1.0])
    plot_design_table(bands, ax=ax, paper=PAPER_TABLE2, label="this sweep, m = 20-80 g",
                      others=[("this sweep, m >= 40.5 g", heavy)],
                      title="max SPL at equal damping inclination (numbers: decrease in dB)")
    ax.set_xlim(0.6, 1.3)
    ax_t.axis("off")
    ax_t.text(0.0, 0.97, "\n".join(lines), family="monospace", fontsize=8.6, va="top", ha="left",
              transform=ax_t.transAxes)
    note = ("The quietest designs (heavy masses, small gaps) agree with the paper's minima within\n"
            "about 2-3 dB. Over 20-80 g the spread is wider than the paper's: at a fixed 19.05 mm\n"
            "sphere the level falls 5-6 dB per doubling of the impact mass, and the paper does not\n"
            "give its grid. From Table 1's 40.5 g upwards the spread comes close to the paper's.\n"
            "Eq 16 takes two maxima of a chaotic motion, so single designs may change bands.")
    ax_t.text(0.0, 0.6, note, fontsize=9, va="top", ha="left", transform=ax_t.transAxes)
    ax_t.set_title("paper Table 2 beside this sweep\n(SPL in dB re 20 µPa; (m, d) of the quietest in g, cm)",
                   fontsize=10)
    path = save_figure(fig, output_dir() / "plot_08_design_table.png")
print(f"wrote {path}")
assert np.all(np.isfinite([b.min_spl_db for b in bands]))
