"""
Wavefront of an impact in a wall-floor corner.
==============================================

The paper's steel sphere (a = 19.05 mm, 1.4 m/s, K_HZ = 5.6e8 N/m^1.5) strikes the floor
5 cm from a rigid wall. The method of images (paper eq 14, extended to two perpendicular
planes: three images) gives the pressure on the vertical plane through the sphere's centre
normal to the wall. Three snapshots show the pulse leaving the sphere, reflecting from the
wall and running along the floor; the field is evaluated on a planar grid by
:func:`acoustiviz.field.snapshots`, and the grid points inside the sphere are left blank.
"""

# %%
import math

import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz import Impact, acceleration_pulse
from acoustiviz.core.geometry import images_wall_floor
from acoustiviz.field import snapshots
from acoustiviz.field.grids import planar_grid
from acoustiviz.output.plot.style import save_figure, style

RADIUS, U0, K_HZ, DENSITY, WALL = 0.01905, 1.4, 5.6e8, 7800.0, 0.05
impact = Impact(velocity=U0, k_hertz=K_HZ, mass=DENSITY * 4 / 3 * math.pi * RADIUS**3)
pulse = acceleration_pulse(impact, "hertz")
geometry = images_wall_floor(RADIUS, WALL)

width, height = 0.60, 0.40  # m: x from the wall, z from the floor
n_u = 120 if fast_mode() else 480
grid = planar_grid((-WALL + width / 2, 0.0, height / 2), (width, 0.0, 0.0), (0.0, 0.0, height), n_u=n_u)
times = np.array([0.35e-3, 0.8e-3, 1.25e-3])  # s from the start of contact
field = snapshots(pulse, times, grid.points, geometry)

# %%
from matplotlib.colors import TwoSlopeNorm  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Circle, Rectangle  # noqa: E402

# colour scale: symmetric about zero, saturating the 1/r² near field of the sphere
far = np.linalg.norm(grid.points - geometry.centre, axis=1) > 0.1
vmax = float(np.nanpercentile(np.abs(field[:, far]), 99.5))
norm = TwoSlopeNorm(vcenter=0.0, vmin=-vmax, vmax=vmax)
extent = (-WALL * 100, (width - WALL) * 100, 0.0, height * 100)  # cm

with style():
    fig = Figure(figsize=(13, 4.4), layout="constrained")
    axes = fig.subplots(1, 3, sharey=True)
    for ax, tq, snap in zip(axes, times, field, strict=True):
        im = ax.imshow(
            grid.image(snap), origin="lower", extent=extent, cmap="RdBu_r", norm=norm, interpolation="bilinear"
        )
        ax.add_patch(Circle((0.0, RADIUS * 100), RADIUS * 100, facecolor="0.35", edgecolor="k", lw=0.8))
        ax.add_patch(
            Rectangle(
                (extent[0] - 2, -2),
                extent[1] - extent[0] + 4,
                2,
                facecolor="0.6",
                hatch="///",
                edgecolor="0.3",
                clip_on=False,
            )
        )
        ax.add_patch(
            Rectangle(
                (extent[0] - 2, -2), 2, extent[3] + 2, facecolor="0.6", hatch="\\\\\\", edgecolor="0.3", clip_on=False
            )
        )
        ax.set_xlim(extent[0] - 2, extent[1])
        ax.set_ylim(-2, extent[3])
        ax.set_aspect("equal")
        ax.grid(False)
        ax.set_title(f"t = {tq * 1e3:.2f} ms after contact")
        ax.set_xlabel("x from the sphere's centre (cm)")
        ax.text(extent[0] + 0.8, extent[3] * 0.92, "wall", rotation=90, ha="left", va="top", fontsize=8)
        ax.text(extent[1] * 0.9, 0.8, "floor", ha="center", va="bottom", fontsize=8)
    axes[0].set_ylabel("z, height above the floor (cm)")
    cb = fig.colorbar(im, ax=axes, shrink=0.9, extend="both")
    cb.set_label("sound pressure (Pa)")
    fig.suptitle(
        f"Sphere (a = {RADIUS * 1e3:g} mm, {U0} m/s, Hertz pulse) striking the floor "
        f"{WALL * 100:g} cm from a wall: pressure in the plane normal to the wall"
    )
    out = output_dir() / "plot_03_wall_floor_field.png"
    save_figure(fig, out)
print(f"wrote {out}")
