"""
Directivity balloons: a reflecting plane and a wall-floor corner.
=================================================================

The paper's steel sphere (a = 19.05 mm, 1.4 m/s, K_HZ = 5.6e8 N/m^1.5) strikes the floor,
first on an open floor (the sphere and its image, paper eq 14) and then 5 cm from a rigid
wall (three images). Around the contact point a spherical grid of radius 0.7 m -- the
paper's listening distance -- measures the peak SPL in every direction of the fluid: the half
space above the floor, the quarter space of the corner. Each balloon's radius grows with that
level over a 30 dB range and its colour is the level itself, on one colour scale for both.

On the open floor the sound leaves mostly upward, along the rebound, and fades to grazing
incidence: the sphere and its image move in opposite directions, a pair that radiates like
cos²θ. In the corner the wall's images add about 6 dB straight up and tilt the loud lobe
towards the wall; the dark outline is the polar pattern of Figure 3 in the plane through the
sphere normal to the wall.
"""

# %%
import math

from _gallery import fast_mode, output_dir

from acoustiviz import Impact, acceleration_pulse
from acoustiviz.core.geometry import geometry
from acoustiviz.field.balloon import balloon_data
from acoustiviz.output.render import render_balloon

RADIUS, U0, K_HZ, DENSITY, WALL, DISTANCE = 0.01905, 1.4, 5.6e8, 7800.0, 0.05, 0.7
impact = Impact(velocity=U0, k_hertz=K_HZ, mass=DENSITY * 4 / 3 * math.pi * RADIUS**3)
pulse = acceleration_pulse(impact, "half-sine")
plane = geometry("plane", RADIUS)
corner = geometry("wall-floor", RADIUS, wall_distance=WALL)
n_theta = 8 if fast_mode() else 32
size = (900, 400) if fast_mode() else (1800, 800)

# %%
# The levels themselves, computed once; the balloons are drawn from them.
datas = [balloon_data(pulse, geom, distance=DISTANCE, n_theta=n_theta) for geom in (plane, corner)]
for geom, d in zip((plane, corner), datas, strict=True):
    print(f"{geom.name:>10}: peak SPL at {DISTANCE} m from {d.level.min():.1f} to {d.max_level:.1f} dB, "
          f"energy mean over the {d.grid.region} space {d.mean_level:.1f} dB")

# %%
path = render_balloon(
    datas,
    pulse,
    [plane, corner],
    output_dir() / "plot_09_balloon.png",
    size=size,
    title=f"peak SPL at {DISTANCE} m around the contact point, 30 dB from centre to rim\n"
    f"left: reflecting plane; right: wall-floor corner, wall {WALL * 100:g} cm from the sphere's centre",
)
print(f"wrote {path}")
