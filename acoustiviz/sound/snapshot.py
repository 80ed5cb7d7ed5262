"""The pressure of a whole damper run at points at one instant: every click sounding then, with its images.

Where :func:`acoustiviz.sound.render` samples the run's pressure in time at a few listeners, this
evaluates it at one time at many points (a snapshot over a plane): for each click whose sound is at a
point at that instant, the closed-form response of its sphere and of each of its images (paper eqs
12-14), not band-limited. One ball: the clicks of the impact sequence, each from its wall's sources
(:func:`~acoustiviz.sound.sources.wall_sources`); several balls: the spheres of :func:`~.balls_sound.ball_clicks`,
each with its own radius and images. Lengths in m, times in s, pressures in Pa.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import ParameterError
from ..core.radiation import pulse_response
from ..field.sources import image_geometry
from .sources import CavityScene, ImpactSequence, wall_sources
from .synthesis import _TAIL_DECADES, ClickModel

__all__ = ["snapshot_pressure", "snapshot_balls"]


def _geometry(points, sources, radius: float, medium) -> tuple:
    """``(delay, weight)``: ``(r - a)/c`` in s and ``P0 C`` in Pa s/m of each source at each point ``(n, k)``."""
    delay, p0, c_shape, _ = image_geometry(points, sources, radius, medium=medium)
    return delay, p0 * c_shape


def _add(out, since: float, pulse, geometry, radius: float, medium) -> None:
    """Add one click, ``since`` s after its contact began, from its sources' ``geometry`` (:func:`_geometry`)."""
    delay, weight = geometry
    tail = _TAIL_DECADES * math.log(10.0) * radius / medium.c
    if since < float(delay.min()) or since > float(delay.max()) + pulse.duration + tail:
        return  # not sounding at any point: not yet arrived, or died away
    y = pulse_response(pulse, since - delay, radius=radius, medium=medium)
    out += np.real(weight * y).sum(axis=1)


def snapshot_pressure(t: float, sequence: ImpactSequence, scene: CavityScene, click: ClickModel, points) -> np.ndarray:
    """The pressure in Pa at ``points`` at instant ``t`` of one ball's run, every click sounding then summed.

    Parameters
    ----------
    t : float
        The instant in s on the run's time axis (0 at the start of the run).
    sequence : ImpactSequence
        Contact start times (s), walls (-1/+1) and approach speeds (m/s).
    scene : CavityScene
        The cavity in its surroundings (its images) and the medium.
    click : ClickModel
        The Hertz pulse of each impact.
    points : (n, 3) array_like
        Points in m in the fluid.

    Returns
    -------
    (n,) ndarray
        The pressure in Pa (closed form, not band-limited).

    Examples
    --------
    Before the first click has arrived the field is silent:

    >>> seq = ImpactSequence([0.01], [-1], [1.4])
    >>> float(snapshot_pressure(0.005, seq, CavityScene("plane"), ClickModel(), [[0.3, 0.0, 0.3]])[0])
    0.0
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.zeros(len(pts))
    a, medium = scene.radius, scene.medium
    geometry = {w: _geometry(pts, wall_sources(scene, w), a, medium) for w in (-1, 1) if np.any(sequence.walls == w)}
    for tk, w, v in zip(sequence.times, sequence.walls, sequence.velocities, strict=True):
        if tk <= t:  # a click sounds from its contact on, at the earliest
            _add(out, float(t - tk), click.pulse_for(float(v)), geometry[int(w)], a, medium)
    return out


def snapshot_balls(t: float, clicks, scene: CavityScene, points) -> np.ndarray:
    """:func:`snapshot_pressure` of a multi-ball run's spheres (:func:`~.balls_sound.ball_clicks`), in Pa.

    Each click's spheres with their own radius (``clicks.radii``) and the images its sources hold; a room's
    images (made per position when the run is rendered) are not offered here.
    """
    if scene.geometry.enclosed:
        raise ParameterError("room", "the snapshot of several balls in a room is not offered (its images are "
                                     "made per position when the run is rendered)")
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.zeros(len(pts))
    radii = np.full(len(clicks), float(scene.radius)) if clicks.radii is None else np.asarray(clicks.radii, float)
    for k in range(len(clicks)):
        if clicks.times[k] <= t:
            a = float(radii[k])
            _add(out, float(t - clicks.times[k]), clicks.pulses[k], _geometry(pts, clicks.sources[k], a, scene.medium),
                 a, scene.medium)
    return out
