"""Off-screen 3-D renders with pyvista: directivity balloons, field snapshots and wavefront animations.

Every render draws a value computed beforehand by the physics layer (a
:class:`~acoustiviz.field.sections.SectionField` or a :class:`~acoustiviz.field.balloon.BalloonData`);
it evaluates nothing itself. Every render builds its own ``pyvista.Plotter(off_screen=True)``, draws, writes one file
atomically and closes the plotter in a ``finally`` block: no global pyvista state is touched,
no display or virtual X server is needed, and nothing leaks from one render to the next. If
VTK cannot open any off-screen OpenGL context a :class:`RuntimeError` says what to install.

* :func:`render_balloon` -- a directivity balloon: a surface around the contact point whose
  radius grows with the level (peak SPL, RMS level or sound exposure level) measured on a
  spherical grid (:func:`acoustiviz.field.balloon.balloon_data`) at a given distance, coloured by the same level, with
  the sphere, the floor and the wall drawn in. Free field: whole sphere; plane: half space;
  wall-floor corner: quarter space. Several configurations go side by side with one colour
  scale.
* :func:`render_snapshot` -- p(x, t) on one or more planar grids at one or more times, with a
  diverging colour map centred on zero and the time printed on the image.
* :func:`render_animation` -- the wavefront leaving the impact and reflecting, as GIF (always)
  or MP4 (when ``imageio`` and ``imageio-ffmpeg`` are installed), of the frames of
  :func:`acoustiviz.field.sections.animation_field`; the colour range is fixed over all frames.

Lengths are in m, times in s, pressures in Pa, levels in dB re 20 µPa. This module does the
drawing only; paths and argv belong to :mod:`acoustiviz.cli`.
"""

from __future__ import annotations

from ._common import DEFAULT_SIZE, check_backend, mp4_available
from .animation import render_animation
from .balloon import render_balloon
from .snapshot import render_snapshot

__all__ = [
    "DEFAULT_SIZE",
    "mp4_available",
    "check_backend",
    "render_balloon",
    "render_snapshot",
    "render_animation",
]
