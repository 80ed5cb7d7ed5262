"""
Damping inclination and maximum SPL over gap and impact mass (paper Figure 6).
==============================================================================

A sweep of 20 gaps (2-6 cm) by 20 impact masses (20-80 g) of the Table 1 damper, each run
for 20 s of motion from the Figure 5 start (main mass at 2 m/s, impact mass centred at rest).
For every design: the damping inclination of paper eq 16 (first two positive maxima) and the
maximum sound pressure level at the paper's listener (0.7 m, 45 degrees, reflecting plane)
over all of its impacts, each impact radiated as the paper's 19.05 mm sphere with the
half-sine Hertz pulse of its own approach speed.

As the paper says, the damping inclination (A) does not vary uniformly with the gap and the
mass -- it even changes sign from one cell to the next, because an impact near one of the
first two maxima decides it -- while the maximum SPL (B) varies smoothly: it falls by 5-6 dB
per doubling of the mass (at a fixed radius the pulse's peak acceleration falls as m^(-2/5)
and its length grows as m^(2/5)) and rises by 2-4 dB from the smallest to the largest gap (the
impact mass strikes faster). A second figure shows the steadier envelope-fit inclination,
which grows with both gap and mass but stays below 0.6 cm/s over this grid.

The sweep directory is written row by row and shared with ``plot_08_design_table.py``:
running either script again recomputes nothing.
"""

# %%
import sys

from _gallery import fast_mode, output_dir
from matplotlib.figure import Figure

from acoustiviz.output.plot.design import plot_inclination_map, plot_spl_map
from acoustiviz.output.plot.style import save_figure, style
from acoustiviz.sweep import FixedSettings, SweepSpec, run_sweep, value_range

n_gap, n_mass, duration = (4, 3, 3.0) if fast_mode() else (20, 20, 20.0)
spec = SweepSpec(gap=value_range(0.02, 0.06, n_gap), m=value_range(0.02, 0.08, n_mass),
                 settings=FixedSettings(duration=duration))
table = run_sweep(spec, output_dir() / "design_sweep", progress=sys.stderr)

# %%
with style():
    fig = Figure(figsize=(12.5, 4.8), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2)
    plot_inclination_map(table, ax=ax_a)
    plot_spl_map(table, ax=ax_b)
    fig.suptitle(f"Paper Figure 6: {n_gap} gaps x {n_mass} impact masses, Table 1 damper, "
                 f"{duration:g} s each; listener 0.7 m, 45 deg, reflecting plane; sphere a = 19.05 mm")
    path = save_figure(fig, output_dir() / "plot_07_design_maps.png")

    fig2 = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig2.add_subplot()
    plot_inclination_map(table, ax=ax, definition="fit",
                         title="damping inclination, linear fit of the maxima above 30 % of the first")
    path2 = save_figure(fig2, output_dir() / "plot_07_inclination_fit.png")
print(f"wrote {path} and {path2}")
