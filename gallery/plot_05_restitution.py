"""
Coefficient of restitution versus impact mass and velocity (paper Figure 7).
============================================================================

The damped Hertz contact of paper eq 15 (K_HZ = 5.6e8 N/m^1.5, c1 = 20 N·s/m) between an impact
mass m and the main mass M = 0.5 kg. The restitution depends only on the dimensionless damping
ζ = c1 α_max / (m_eff U0), which falls as U0^(-1/5) m_eff^(-3/5): the restitution rises with the
impact mass and with the approach speed. With the paper's force, which pulls as the bodies part,
it is lower than with the force clipped at zero.
"""

# %%
import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz.dynamics import TABLE1, DamperModel
from acoustiviz.dynamics.metrics import restitution_curve
from acoustiviz.files import write_csv_atomic
from acoustiviz.output.plot.dynamics import plot_restitution
from acoustiviz.output.plot.style import save_figure, style

masses = np.linspace(0.005, 0.1, 8 if fast_mode() else 20)  # kg
speeds = np.array([0.2, 0.5, 1.0, 2.0, 3.0])  # m/s
paper = restitution_curve(masses, speeds, TABLE1)
clipped = restitution_curve(masses, speeds, DamperModel(clip_tensile=True))
i40 = np.argmin(np.abs(masses - 0.04))
print(f"m = {1000 * masses[i40]:.0f} g, U0 = 2 m/s: e = {paper[i40, 3]:.4f} (paper's force), "
      f"{clipped[i40, 3]:.4f} (clipped)")
write_csv_atomic(
    output_dir() / "plot_05_restitution.csv",
    ["mass_kg"] + [f"e_paper_{u:g}_m_s" for u in speeds] + [f"e_clipped_{u:g}_m_s" for u in speeds],
    [masses, *paper.T, *clipped.T],
)

# %%
with style():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 4.0), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2, sharey=True)
    plot_restitution(masses, speeds, paper, ax=ax1)
    plot_restitution(masses, speeds, clipped, ax=ax2, clip_tensile=True)
    ax1.set_title("paper's force (pulls as contact ends)")
    ax2.set_title("force clipped at zero")
    fig.suptitle("Restitution of the damped Hertz contact, M = 0.5 kg, c1 = 20 N·s/m")
    path = save_figure(fig, output_dir() / "plot_05_restitution.png")
print(f"wrote {path}")
