"""
Impact waveform of a sphere striking a reflecting plane (paper Figure 2).
=======================================================================

A steel sphere of radius 19.05 mm strikes a rigid surface at 1.4 m/s with
K_HZ = 5.6e8 N/m^1.5; the listener is 0.7 m from the sphere's centre at 45° from the
surface normal. In free field the sphere alone gives a positive-then-negative pulse; the
reflecting plane (method of images, paper eq 14) turns it into the M-shaped waveform of
Akay and Hodgson (1978). The second panel compares the three acceleration pulses: only
the exact Hertz pulse gives the "larger negative pressure peak than the two positive
values" that the paper describes; its own half-sine (eq 4) gives the opposite, because its
kinks at the start and end of contact sharpen the two positive lobes.
"""

# %%
import math

import numpy as np
from _gallery import output_dir

from acoustiviz import AIR, Impact, acceleration_pulse
from acoustiviz.core.geometry import geometry
from acoustiviz.field import time_series
from acoustiviz.files import write_csv_atomic
from acoustiviz.output.plot.style import save_figure, style
from acoustiviz.output.plot.waveform import plot_waveform

RADIUS, U0, K_HZ, DENSITY = 0.01905, 1.4, 5.6e8, 7800.0
DISTANCE, ANGLE = 0.7, math.radians(45.0)
impact = Impact(velocity=U0, k_hertz=K_HZ, mass=DENSITY * 4 / 3 * math.pi * RADIUS**3)


def listener_pressure(pulse, t, geometry):
    """Pressure in Pa at the Figure 2 listener: the sphere and its images (paper eq 14)."""
    point = geometry.sources[0].position + DISTANCE * np.array([math.sin(ANGLE), 0.0, math.cos(ANGLE)])
    return time_series(pulse, t, point[None, :], geometry, medium=AIR)[0]


t = np.linspace(1.8e-3, 3.2e-3, 2801)  # s from the start of contact
half_sine = acceleration_pulse(impact, "half-sine")
free = listener_pressure(half_sine, t, geometry("free", RADIUS))
plane = listener_pressure(half_sine, t, geometry("plane", RADIUS))

# %%
from matplotlib.figure import Figure  # noqa: E402

with style():
    fig = Figure(figsize=(10, 4), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2, sharey=True)
    plot_waveform(t, free, ax=ax1, label="free field (sphere alone)", color="0.55")
    plot_waveform(t, plane, ax=ax1, label="reflecting plane (with image)", color="C0", lw=1.8)
    ax1.set_title("(A) Figure 2: half-sine pulse (paper eq 4)")
    ax1.set_ylim(-1.05, 0.75)
    ax1.legend(loc="lower center", fontsize=8)
    for kind, colour in (("half-sine", "C0"), ("impulse-matched", "C1"), ("hertz", "C3")):
        p = listener_pressure(acceleration_pulse(impact, kind), t, geometry("plane", RADIUS))
        plot_waveform(t, p, ax=ax2, label=f"{kind}: peaks {p.max():.2f} / {p.min():.2f} Pa", color=colour)
    ax2.set_title("(B) reflecting plane: three acceleration pulses")
    ax2.legend(loc="lower center", fontsize=8)
    fig.suptitle(
        f"a = {RADIUS * 1e3:.2f} mm, U0 = {U0} m/s, K_HZ = {K_HZ:.2g} N/m$^{{1.5}}$, "
        f"r = {DISTANCE} m, θ = 45°, contact {impact.duration * 1e6:.0f} µs"
    )
    path = save_figure(fig, output_dir() / "plot_01_impact_waveform.png")
write_csv_atomic(output_dir() / "plot_01_impact_waveform.csv", ["time_s", "pressure_pa"], [t, plane])
print(f"wrote {path}")
