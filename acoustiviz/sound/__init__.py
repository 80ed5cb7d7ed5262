"""Sound synthesis: impact trains rendered into band-limited, calibrated pressure signals at listeners.

Each impact of a sequence (a time, the wall it strikes and its approach speed) becomes a Hertz
acceleration pulse of the impact mass (:mod:`acoustiviz.core.contact`); the rigid-sphere radiation
model (:mod:`acoustiviz.core.radiation`) and the image sources of the scene (:mod:`acoustiviz.core.geometry`)
give its pressure at each listener; the clicks are placed at their exact (sub-sample) times and
summed. The result is in pascals.

Band-limiting
-------------
A click has energy far above audio rates (contact times of a few hundred microseconds,
``l = c/a`` of tens of kilohertz, and a kink at the start and the end of the half-sine pulse).
Point-sampling it at 48 kHz would alias. Each click is therefore evaluated exactly (closed form)
on an internal grid ``L`` times finer than the output, aligned with the output samples, and
decimated with one linear-phase Kaiser-window FIR low-pass filter: passband flat to
``0.45 fs`` (ripple < 1e-5), at least 110 dB of attenuation from ``fs/2`` up, so nothing above
the output Nyquist frequency folds back. ``L`` is chosen so the internal rate is at least
16 times the output rate and 200 samples per shortest contact. The filter has zero delay (its
centre tap is aligned), so a click's timing is exact to the internal step's rounding -- and
no rounding happens at all: the internal samples are the closed form at the exact retarded
times ``t - t_k - (r - a)/c``.

How impacts map to sources
--------------------------
The damper's axis of motion (``x`` in :mod:`acoustiviz.dynamics`) is the axis ``n`` of the
real sphere of the scene's geometry (the normal of the struck surface, ``+z`` for ``"free"`` and
``"plane"``). The cavity's two walls are perpendicular to it:

* the **struck wall** (``struck_wall``, default ``-1``) lies on the geometry's struck surface
  (``z = 0`` for ``"plane"``). Its impacts are exactly the geometry's sources: the sphere at
  ``(0, 0, a)`` accelerating along ``+n`` and its images in the geometry's planes (paper
  eq 14 for ``"plane"``).
* the **far wall** (the other one) lies ``gap + 2a`` further along ``n``: its impacts put the
  sphere's centre at ``(0, 0, a + gap)`` accelerating along ``-n`` (it rebounds back towards the
  struck wall). The far wall is taken as acoustically small (a lid, smaller than the
  wavelengths of the click) and does not reflect; the geometry's planes still do, so the
  far-wall sphere has its own images in them (its image in ``z = 0`` sits at ``(0, 0, -a - gap)``
  with axis ``+n``).

With ``walls="one"`` every impact is heard as a strike on the struck wall (the paper's own
view, in which every impact is a sphere hitting the reflecting plane; an upper bound).
Wall ``-1`` is struck when the impact mass reaches ``y - x = -gap/2``, so with ``struck_wall=-1``
the damper's ``+x`` is ``+n``; with ``struck_wall=+1`` it is ``-n``. The cavity is at rest in
this frame: the main mass's displacement (a few cm) is neglected, as in the paper.

Several balls (:mod:`.balls_sound`, :func:`render_balls`): every collision accelerates both of its
bodies. A ball-wall contact radiates as above (the ball touching the far wall sits the other balls'
diameters further along ``n``); a ball-ball contact radiates as two rigid spheres at the balls' centres
with equal and opposite impulses (the colliding-sphere dipole pair), each with the Hertz pulse of the
pair's effective mass and stiffness, with the same images. Several cavities radiate each from its own
place; in a room every sphere has the room's images of its own position (:mod:`.balls_room`). Left out:
the acoustic interaction of the touching spheres, their own modes, the ringing of the cavity walls, the
screening and scattering by the main mass and the other cavities. In operation (:mod:`.balls_operating`)
a multi-ball attractor's motion is run again to place its balls, and its collisions levelled as one
ball's steady click train (:mod:`.operating`).

A room's sound (:mod:`.room_sound`) adds the exact early images, per-band absorption and a
statistical late tail. The signals are in pascals; this package writes no files (the WAV files
and their sidecars are written by :mod:`acoustiviz.output.audio`).

All quantities are SI (s, m, kg, m/s, Pa, Hz) unless a name says otherwise (``_db``).
"""

from __future__ import annotations

from .balls_sound import BallClicks, ball_clicks, render_balls, render_clicks
from .room_sound import RoomSound, parse_absorption_bands
from .sources import (
    MASS_MODELS,
    WALL_MODELS,
    CavityScene,
    ImpactSequence,
    check_listeners,
    ear_positions,
    periodic_train,
    spl,
    wall_sources,
)
from .synthesis import (
    PASSBAND_FRACTION,
    SAMPLE_RATES,
    STOPBAND_ATTENUATION_DB,
    ClickModel,
    Rendering,
    decimation_filter,
    oversampling_factor,
    render,
)

__all__ = [
    "SAMPLE_RATES",
    "PASSBAND_FRACTION",
    "STOPBAND_ATTENUATION_DB",
    "MASS_MODELS",
    "WALL_MODELS",
    "ImpactSequence",
    "periodic_train",
    "CavityScene",
    "ClickModel",
    "Rendering",
    "spl",
    "oversampling_factor",
    "decimation_filter",
    "wall_sources",
    "check_listeners",
    "ear_positions",
    "render",
    "BallClicks",
    "ball_clicks",
    "render_clicks",
    "render_balls",
    "RoomSound",
    "parse_absorption_bands",
]
