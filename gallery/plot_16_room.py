"""
The click in a room: reflections from every wall, and the click train at a listener.
====================================================================================

The paper's steel sphere (a = 19.05 mm, 1.4 m/s, K_HZ = 5.6e8 N/m^1.5, half-sine pulse)
strikes the floor of a 6 x 4 x 3 m room whose six surfaces all absorb alpha = 0.1 of the
incident energy (pressure reflection sqrt(0.9) = 0.949). The room is one geometry value,
:class:`acoustiviz.core.room_geometry.Room`: its image sources (Allen and Berkley's lattice in
closed form) go to the order the window needs, and the field evaluator sums them like the
corner's three.

Top: the pressure on the vertical plane through the sphere (y = 1.5 m, the whole 6 x 3 m
section) at three times. The wavefront leaves the floor as a hemisphere, the x = 0 wall 2 m
away and the ceiling return it, and the reflected fronts cross the room.

Bottom: the pressure at a listener in the middle of the room, (3, 2, 1.5) m, over the first
0.3 s: the direct click, then the reflections, sparse at first and ever denser, each image's
click scaled by its reflections and its distance; the right panel magnifies the first 30 ms.
"""

# %%
import math

import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz import Impact, acceleration_pulse
from acoustiviz.core.room_geometry import Room
from acoustiviz.field import snapshots, time_series
from acoustiviz.field.grids import planar_grid
from acoustiviz.output.plot.style import save_figure, style

RADIUS, U0, K_HZ, DENSITY = 0.01905, 1.4, 5.6e8, 7800.0
DIMS, ALPHA, SOURCE, LISTENER = (6.0, 4.0, 3.0), 0.1, (2.0, 1.5, RADIUS), np.array([3.0, 2.0, 1.5])
impact = Impact(velocity=U0, k_hertz=K_HZ, mass=DENSITY * 4 / 3 * math.pi * RADIUS**3)
pulse = acceleration_pulse(impact, "half-sine")
fast = fast_mode()

# %% the field over the vertical section through the sphere
times = np.array([3.0e-3, 9.0e-3, 15.0e-3])  # s from the start of contact
room = Room(RADIUS, DIMS, ALPHA, SOURCE, duration=float(times[-1]))
n_u = 150 if fast else 600
grid = planar_grid((DIMS[0] / 2, SOURCE[1], DIMS[2] / 2), (DIMS[0], 0.0, 0.0), (0.0, 0.0, DIMS[2]), n_u=n_u)
field = snapshots(pulse, times, grid.points, room)
print(f"snapshot: image order {room.image_order}, {room.image_count} images")

# %% the click train at the listener
window = 0.08 if fast else 0.3
train = Room(RADIUS, DIMS, ALPHA, SOURCE, duration=window)
t = np.arange(0.0, window, 1e-5)
p = time_series(pulse, t, LISTENER[None, :], train)[0]
print(f"listener: image order {train.image_order}, {train.image_count} images, "
      f"neglected energy {train.neglected_energy_db} dB (every image that arrives within {window} s)")

# %%
from matplotlib.colors import TwoSlopeNorm  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

far = np.linalg.norm(grid.points - room.centre, axis=1) > 0.5
vmax = float(np.nanpercentile(np.abs(field[:, far]), 99.5))
norm = TwoSlopeNorm(vcenter=0.0, vmin=-vmax, vmax=vmax)
extent = (0.0, DIMS[0], 0.0, DIMS[2])

with style():
    fig = Figure(figsize=(14, 8.2), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.0, 0.95])
    axes = top.subplots(1, 3, sharey=True)
    for ax, tq, snap in zip(axes, times, field, strict=True):
        im = ax.imshow(grid.image(snap), origin="lower", extent=extent, cmap="RdBu_r", norm=norm,
                       interpolation="bilinear")
        ax.add_patch(Circle((SOURCE[0], SOURCE[2]), 0.05, facecolor="0.2", edgecolor="k", lw=0.6))
        ax.set_aspect("equal")
        ax.grid(False)
        ax.set_title(f"t = {tq * 1e3:.0f} ms: {room.image_count} images to order {room.image_order}")
        ax.set_xlabel("x (m)")
    axes[0].set_ylabel("z, height above the floor (m)")
    cb = top.colorbar(im, ax=axes, shrink=0.85, extend="both")
    cb.set_label("sound pressure (Pa)")
    top.suptitle(f"{DIMS[0]:g} x {DIMS[1]:g} x {DIMS[2]:g} m room, alpha = {ALPHA:g} on every surface: the "
                 f"pressure on the plane y = {SOURCE[1]:g} m through the sphere (marker enlarged)")
    ax1, ax2 = bottom.subplots(1, 2, width_ratios=[2.2, 1.0])
    for ax, stop in ((ax1, window), (ax2, 0.03)):
        sel = t <= stop
        ax.plot(t[sel] * 1e3, p[sel], lw=0.5, color="C0")
        ax.set_xlabel("time after the start of contact (ms)")
        ax.set_xlim(0.0, stop * 1e3)
    ax1.set_ylabel("sound pressure (Pa)")
    ax1.set_title(f"at the listener ({LISTENER[0]:g}, {LISTENER[1]:g}, {LISTENER[2]:g}) m: "
                  f"{train.image_count:,} images to order {train.image_order}")
    ax2.set_title("the first 30 ms")
    out = output_dir() / "plot_16_room.png"
    save_figure(fig, out)
print(f"wrote {out}")
