"""
Directivity of a sphere striking a reflecting plane (paper Figure 3).
====================================================================

Peak sound pressure level (A) and RMS pressure (B) on a circle of radius 0.7 m around the
sphere's centre, against the angle from the surface normal, for the paper's steel sphere
(a = 19.05 mm, 1.4 m/s, K_HZ = 5.6e8 N/m^1.5) on a rigid plane. The sphere and its image
radiate as a dipole pointing along the normal, loudest straight above the impact and quiet
along the plane. The RMS is taken over a window of the same length at every angle, starting
at the first arrival and holding the whole pulse of both spheres plus ten decay times a/c.
The half-sine pulse of the paper (eq 4) is compared with the exact Hertz pulse.
"""

# %%
import math

import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz import Impact, acceleration_pulse
from acoustiviz.core.geometry import images_plane
from acoustiviz.field import directivity
from acoustiviz.files import write_csv_atomic
from acoustiviz.output.plot.directivity import half_space_axes, plot_directivity
from acoustiviz.output.plot.style import save_figure, style

RADIUS, U0, K_HZ, DENSITY, DISTANCE = 0.01905, 1.4, 5.6e8, 7800.0, 0.7
impact = Impact(velocity=U0, k_hertz=K_HZ, mass=DENSITY * 4 / 3 * math.pi * RADIUS**3)
geometry = images_plane(RADIUS)
step = 15.0 if fast_mode() else 2.5
angles = np.radians(np.arange(0.0, 90.0 + step / 2, step))
results = {
    kind: directivity(acceleration_pulse(impact, kind), geometry, DISTANCE, angles) for kind in ("half-sine", "hertz")
}

out = output_dir()
d = results["half-sine"]
write_csv_atomic(
    out / "plot_02_directivity.csv",
    ["angle_deg", "peak_pa", "rms_pa", "spl_db"],
    [d.angle_deg, d.peak, d.rms, d.spl_db],
)

# %%
from matplotlib.figure import Figure  # noqa: E402

with style():
    fig = Figure(figsize=(10, 5), layout="constrained")
    ax1 = fig.add_subplot(1, 2, 1, projection="polar")
    ax2 = fig.add_subplot(1, 2, 2, projection="polar")
    for kind, colour in (("half-sine", "C0"), ("hertz", "C3")):
        plot_directivity(results[kind], "spl", ax=ax1, label=f"{kind} pulse", color=colour)
        plot_directivity(results[kind], "rms", ax=ax2, label=f"{kind} pulse", color=colour)
    for ax, title in ((ax1, "(A) peak SPL, dB re 20 µPa"), (ax2, "(B) RMS pressure, Pa")):
        ax.set_title(title + "\nangle from the surface normal (deg)", fontsize=10)
    fig.suptitle(
        f"Figure 3: sphere on a reflecting plane, r = {DISTANCE} m from its centre, "
        f"a = {RADIUS * 1e3:g} mm, U0 = {U0} m/s"
    )
    half_space_axes(fig)  # 0-90°, the half space above the plane, with room for the radial labels
    save_figure(fig, out / "plot_02_directivity.png")
print(f"wrote {out / 'plot_02_directivity.png'}")
