"""The sound of several balls in one cavity: every collision accelerates, and so radiates from, both its bodies.

A ball-wall contact radiates as the one ball of :func:`acoustiviz.sound.render` does: the ball's rigid
sphere at its position, accelerated away from the wall by the Hertz pulse of the contact, with the
cavity's image sources. A ball-ball contact radiates as two rigid spheres at their own positions with
equal and opposite impulses, each with the Hertz pulse of the pair (effective mass of the two balls,
their stiffness, the measured approach speed): the colliding-sphere dipole pair (Koss and Alfredson,
1973). The signal is the sum over every collision and both its bodies.

Left out: the acoustic interaction of the two touching spheres (each radiates as if alone; Morfey,
Sharpe and Smith, 1998), the spheres' own elastic modes, and the ringing of the cavity walls (the main
mass radiates nothing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np

from .._validate import ParameterError
from ..constants import WAV_RATE
from ..core.images import ImageSet, ImageSource
from ..core.signal import Signal
from ..field.sources import image_geometry
from .sources import CavityScene, ImpactSequence, check_listeners, wall_sources
from .synthesis import (
    _TAIL_DECADES,
    ClickModel,
    Rendering,
    _add_exact_clicks,
    _check_render_args,
    _oversampling,
    decimation_filter,
)

__all__ = ["LEFT_OUT", "BallClicks", "column_scene", "radiating_radius", "ball_clicks", "render_clicks", "render_balls"]

#: What the multi-ball sound leaves out (said in every rendering's description and the WAV sidecar).
LEFT_OUT = ("the acoustic interaction of touching spheres (each radiates as if alone; Morfey, Sharpe and Smith "
            "1998)", "the spheres' own elastic modes", "the ringing of the cavity walls")


@dataclass(frozen=True)
class BallClicks:
    """The radiating spheres of a multi-ball run: one per ball-wall contact, two per ball-ball contact.

    Attributes
    ----------
    times : (n,) ndarray
        Contact start in s.
    velocities : (n,) ndarray
        Approach speed of the contact in m/s.
    sources : tuple
        Per click, the sphere and its images (:class:`~acoustiviz.core.images.ImageSource`), the real
        sphere at the ball's centre in m with the unit axis of its acceleration.
    pulses : tuple
        Per click, its acceleration pulse in m/s² (:func:`acoustiviz.core.pulses.acceleration_pulse`).
    collision : (n,) ndarray of int
        Row of the impact table each click comes from.
    walls : (n,) ndarray of int
        The damper wall of a ball-wall contact (-1 or +1), 0 for a ball-ball contact.
    radii : (n,) ndarray or None
        Radius in m of each click's sphere (:func:`radiating_radius`); None: the scene's radius.
    """

    times: np.ndarray
    velocities: np.ndarray
    sources: tuple
    pulses: tuple
    collision: np.ndarray
    walls: np.ndarray
    radii: np.ndarray | None = None

    def __len__(self) -> int:
        return int(np.size(self.times))

    def take(self, index) -> BallClicks:
        """The clicks ``index`` (an integer array or a boolean mask) alone, in their order."""
        idx = np.arange(len(self))[index]
        return BallClicks(self.times[idx], self.velocities[idx], tuple(self.sources[i] for i in idx),
                          tuple(self.pulses[i] for i in idx), self.collision[idx], self.walls[idx],
                          None if self.radii is None else self.radii[idx])

    def describe(self) -> dict:
        """A JSON-ready summary: the counts of both kinds of contact and what the model leaves out."""
        wall = self.walls != 0
        out = {"clicks": len(self), "ball_wall_contacts": int(np.count_nonzero(wall)),
               "ball_ball_contacts": int(np.unique(self.collision[~wall]).size),
               "ball_ball_model": "two rigid spheres, equal and opposite impulses (colliding-sphere dipole pair)",
               "left_out": list(LEFT_OUT)}
        if self.radii is not None:
            out["sphere_radii_m"] = sorted({float(r) for r in self.radii})
        return out


def column_scene(scene: CavityScene, cavity) -> CavityScene:
    """The scene of a column of several balls: its geometry rebuilt around the ball on the struck wall.

    Several balls radiate each as a sphere of its own radius (:func:`radiating_radius`), so the ball that
    touches the struck surface has its centre its own radius from it (a wall strike: the wall at that
    radius). One ball, or a geometry already of that radius: ``scene`` itself. A room is refused
    (``balls``), as :func:`ball_clicks` refuses it.
    """
    if cavity.n_balls == 1:
        return scene
    r = float(cavity.radii[0] if scene.struck_wall == -1 else cavity.radii[-1])
    g = scene.geometry
    if g.radius == r:
        return scene
    if g.enclosed:
        raise ParameterError("balls", "several balls are heard in free field, on a plane or in a corner, not in "
                                      "a room: set balls = 1 or another configuration")
    moved = {"wall_distance": r} if getattr(g, "strike", "floor") == "wall" else {}
    return replace(scene, geometry=replace(g, radius=r, **moved), radius=None)


def radiating_radius(cavity, ball: int, scene_radius: float) -> float:
    """Radius in m of the sphere ball ``ball`` (0-based) of ``cavity`` radiates as: the one home of that rule.

    Several balls: the ball's own radius, the one the dynamics uses (``cavity.radii``, from its mass and
    the steel density), so the balls of a column radiate as the spheres that fill it. One ball: the
    scene's radius ``scene_radius`` (the sound's ``radius``, default the paper's 19.05 mm sphere), as
    :func:`acoustiviz.sound.render` does.
    """
    return float(scene_radius) if cavity.n_balls == 1 else float(cavity.radii[ball])


def _ball_index(name: str, n: int) -> int:
    """0-based ball of a body name ``ballK`` (-1 for ``wall-``, n for ``wall+``)."""
    if name == "wall-":
        return -1
    if name == "wall+":
        return n
    return int(name[4:]) - 1


def _sphere_sources(scene: CavityScene, position, axis, label: str) -> tuple:
    """The sphere at ``position`` (m) accelerated along ``axis`` and its images in the scene's planes."""
    srcs = scene.geometry.image_sources(ImageSource(position, axis, 0, label))
    if isinstance(srcs, ImageSet):
        raise ParameterError("balls", "several balls are heard in free field, on a plane or in a corner, not in "
                                      "a room: set balls = 1 or another configuration")
    return tuple(srcs)


def _centres(result, cav, times: np.ndarray, index: int) -> np.ndarray:
    """Distance in m of ball ``index``'s centre from ball 1's centre at the wall- contact, at ``times``."""
    if np.size(result.t) < 2:
        raise ParameterError("result", "the sound of several balls needs their sampled motion (t_eval)")
    base = cav.offsets[0] - 0.5 * cav.gap
    return np.interp(times, result.t, result.y[:, index] - result.x) - base


def ball_clicks(result, scene: CavityScene, click: ClickModel) -> BallClicks:
    """The radiating spheres of every collision of a multi-ball run.

    Parameters
    ----------
    result : acoustiviz.dynamics.MultiBallResult
        The run (one cavity), with its motion sampled (``t_eval``) finely enough to place the balls.
    scene : CavityScene
        The damper's surroundings; its struck wall holds ball 1 (``struck_wall=-1``) or ball N (``+1``)
        at the geometry's centre (several balls: :func:`column_scene`), the others further along its axis.
        One ball radiates as a sphere of the scene's radius, several each as a sphere of its own radius
        (:func:`radiating_radius`).
    click : ClickModel
        The contact and pulse of a ball on a wall (its ``mass`` is replaced by each ball's mass).

    Returns
    -------
    BallClicks
        In order of first touch; a ball-ball contact gives the lower ball's sphere, then the upper's.

    Notes
    -----
    A ball on a wall is where it touches the wall (exactly); two balls in contact are placed touching,
    their mean centre interpolated linearly in the sampled motion. A ball-ball pulse is that of
    :class:`ClickModel` with ``mass_model="effective"``: approach and duration from the effective mass
    ``m_j m_k / (m_j + m_k)`` and the pair's Hertz stiffness, the acceleration the peak force over each
    ball's own mass (equal and opposite forces).
    """
    model = result.model
    if len(model.cavities) != 1:
        raise ParameterError("cavities", f"the sound is rendered for one cavity, got {len(model.cavities)}")
    cav = model.cavities[0]
    n, imp = cav.n_balls, result.impacts
    scene = column_scene(scene, cav)
    axis = scene.axis
    up = -scene.struck_wall * axis  # direction from wall- to wall+ in the scene
    top = cav.gap + cav.offsets[-1] - cav.offsets[0]  # ball N's distance at the wall+ contact

    def where(u):
        return np.asarray(scene.geometry.centre, dtype=float) + (u if scene.struck_wall == -1 else top - u) * axis

    times, speeds, sources, pulses, rows, walls, radii = [], [], [], [], [], [], []
    for k in range(len(imp)):
        t, v = float(imp.time[k]), abs(float(imp.approach_velocity[k]))
        if not v > 0.0:  # a contact made at rest (a column settling) accelerates nothing audibly: silent
            continue
        i, j = _ball_index(str(imp.first[k]), n), _ball_index(str(imp.second[k]), n)
        if i == -1 or j == n:  # a ball on a wall: as the one ball of render(), of this ball's mass
            ball, wall = (j, -1) if i == -1 else (i, 1)
            u = 0.0 if wall == -1 else top
            if wall == scene.struck_wall or scene.walls == "one" or n == 1:
                srcs = wall_sources(scene, wall)
            else:
                srcs = _sphere_sources(scene, where(u), -axis, "far")
            found = [(srcs, replace(click, mass=cav.masses[ball]), radiating_radius(cav, ball, scene.radius))]
        else:  # two balls touching: the lower one pushed towards wall-, the upper towards wall+
            half = 0.5 * (cav.radii[i] + cav.radii[j])
            mid = 0.5 * (_centres(result, cav, t, i) + _centres(result, cav, t, j))
            pair = dict(k_hertz=cav.k_ball[i], mass_model="effective", pulse=click.pulse,
                        hertz_samples=click.hertz_samples)
            found = [(_sphere_sources(scene, where(mid - half), -up, f"ball{i + 1}"),
                      ClickModel(mass=cav.masses[i], main_mass=cav.masses[j], **pair),
                      radiating_radius(cav, i, scene.radius)),
                     (_sphere_sources(scene, where(mid + half), up, f"ball{j + 1}"),
                      ClickModel(mass=cav.masses[j], main_mass=cav.masses[i], **pair),
                      radiating_radius(cav, j, scene.radius))]
            wall = 0
        for srcs, model_k, radius in found:
            times.append(t)
            speeds.append(v)
            sources.append(srcs)
            pulses.append(model_k.pulse_for(v))
            rows.append(k)
            walls.append(wall)
            radii.append(radius)
    return BallClicks(np.asarray(times, dtype=float), np.asarray(speeds, dtype=float), tuple(sources), tuple(pulses),
                      np.asarray(rows, dtype=np.int64), np.asarray(walls, dtype=np.int64),
                      np.asarray(radii, dtype=float))


def render_clicks(clicks: BallClicks, scene: CavityScene, click: ClickModel, listeners, *,
                  sample_rate: int = WAV_RATE, duration: float | None = None,
                  oversampling: int | None = None) -> Rendering:
    """Render radiating spheres into band-limited pressure signals at the listeners (Pa).

    The same synthesis as :func:`acoustiviz.sound.render` (each click in closed form on the internal
    grid, filtered and decimated, added in time order), with each click's own spheres and radius
    (``clicks.radii``; the clicks of one radius are added together, in time order).

    Parameters
    ----------
    clicks : BallClicks
        The spheres (:func:`ball_clicks`).
    scene : CavityScene
        The scene (medium, listener checks).
    click : ClickModel
        The ball-wall contact model, recorded in the rendering.
    listeners : (n, 3) or (3,) array_like
        Listener positions in m.
    sample_rate : {44100, 48000, 96000}
        Output rate in Hz.
    duration : float, optional
        Minimum signal length in s.
    oversampling : int, optional
        Internal rate over output rate; default from the shortest contact.

    Returns
    -------
    Rendering
        Its ``sequence`` holds the ball-wall contacts; :meth:`Rendering.describe` adds the ball-ball ones
        and what the model leaves out.
    """
    if not isinstance(clicks, BallClicks):
        raise ParameterError("clicks", f"expected BallClicks, got {type(clicks).__name__}")
    wall = clicks.walls != 0
    seq = ImpactSequence(clicks.times[wall], clicks.walls[wall], clicks.velocities[wall])
    pts, fs, duration = _check_render_args(seq, scene, click, listeners, sample_rate, duration)
    medium = scene.medium
    taus = np.array([p.duration for p in clicks.pulses]) if len(clicks) else np.array([1.0])
    L = _oversampling(fs, taus, oversampling)
    h = decimation_filter(L)
    half = (h.size - 1) // (2 * L)
    f_int = float(L * fs)
    radii = np.full(len(clicks), float(scene.radius)) if clicks.radii is None else np.asarray(clicks.radii, float)
    tails = _TAIL_DECADES * math.log(10.0) * radii / medium.c
    geom, end = {}, 0.0
    for k, srcs in enumerate(clicks.sources):
        delay, p0, c_shape, _ = image_geometry(pts, srcs, float(radii[k]), medium=medium)
        geom[k] = (delay, p0 * c_shape)
        end = max(end, float(clicks.times[k] + taus[k]) + float(delay.max()) + float(tails[k]))
    n_out = max(math.ceil(end * fs) + half + 1, math.ceil((duration or 0.0) * fs))
    out = np.zeros((pts.shape[0], n_out))
    for a in np.unique(radii):  # one ball, or equal balls: one radius, one pass
        sel = np.flatnonzero(radii == a)
        order = SimpleNamespace(times=clicks.times[sel], walls=sel)
        tail = _TAIL_DECADES * math.log(10.0) * float(a) / medium.c
        _add_exact_clicks(out, order, [clicks.pulses[k] for k in sel], geom, (fs, L, f_int, h, half, tail),
                          float(a), medium)
    out.flags.writeable = False
    return Rendering(Signal(out, fs), f_int, pts, seq, scene, click, balls=clicks.describe())


def render_balls(result, scene: CavityScene, click: ClickModel, listeners, **options) -> Rendering:
    """The sound of a multi-ball run at the listeners: :func:`render_clicks` of :func:`ball_clicks`.

    ``options``: ``sample_rate``, ``duration``, ``oversampling`` of :func:`render_clicks`.
    """
    column = result.model.cavities[0] if len(result.model.cavities) == 1 else None
    if column is not None:
        scene = column_scene(scene, column)
    check_listeners(listeners, scene, column=column)
    return render_clicks(ball_clicks(result, scene, click), scene, click, listeners, **options)
