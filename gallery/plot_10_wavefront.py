"""
Wavefront of an impact, in 3-D: a snapshot series and an animation.
====================================================================

The paper's steel sphere strikes the floor 5 cm from a rigid wall. The pressure p(x, t) is
drawn on the vertical plane through the sphere normal to the wall, at four times after the
start of contact, with one diverging colour scale centred on zero (red: compression, blue:
rarefaction). The wave leaves the sphere as a compression above and a rarefaction in its
wake, the wall returns it about 0.3 ms later, and the two fronts run on together along the
floor.

The GIF follows the same wavefront frame by frame; each frame evaluates the field only at
the points whose arrival window (first arrival to the end of the last image's decay) holds
the frame time, and keeps the colour range of the first frame to the last.
"""

# %%
import math

from _gallery import fast_mode, output_dir

from acoustiviz import Impact, acceleration_pulse
from acoustiviz.core.geometry import geometry
from acoustiviz.field.sections import animation_field, section_field
from acoustiviz.output.render import mp4_available, render_animation, render_snapshot

RADIUS, U0, K_HZ, DENSITY, WALL = 0.01905, 1.4, 5.6e8, 7800.0, 0.05
impact = Impact(velocity=U0, k_hertz=K_HZ, mass=DENSITY * 4 / 3 * math.pi * RADIUS**3)
pulse = acceleration_pulse(impact, "hertz")
corner = geometry("wall-floor", RADIUS, wall_distance=WALL)
fast = fast_mode()
times = [0.3e-3, 0.6e-3, 0.9e-3, 1.2e-3]  # s from the start of contact
extent = 0.5  # m from the sphere's centre to the far edges of the planes

# %%
field = section_field(pulse, corner, times, extent=extent, sections=("xz",), n_u=61 if fast else 301)
path = render_snapshot(
    field,
    pulse,
    corner,
    output_dir() / "plot_10_wavefront.png",
    size=(900, 600) if fast else (1800, 1200),
)
print(f"wrote {path}")

# %%
frames = animation_field(pulse, corner, extent=extent, frames=6 if fast else 60, n_u=41 if fast else 201)
gif = render_animation(
    frames,
    pulse,
    corner,
    output_dir() / "plot_10_wavefront.gif",
    fps=12,
    size=(320, 240) if fast else (800, 600),
)
print(f"wrote {gif}")
if mp4_available() and not fast:
    video = animation_field(pulse, corner, extent=extent)
    print(f"wrote {render_animation(video, pulse, corner, output_dir() / 'plot_10_wavefront.mp4')}")
