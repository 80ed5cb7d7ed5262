"""The sound of several balls in one cavity: every collision accelerates, and so radiates from, both its bodies.

A ball-wall contact radiates as the one ball of :func:`acoustiviz.sound.render` does: the ball's rigid
sphere at its position, accelerated away from the wall by the Hertz pulse of the contact, with the
cavity's image sources. A ball-ball contact radiates as two rigid spheres at their own positions with
equal and opposite impulses, each with the Hertz pulse of the pair (effective mass of the two balls,
their stiffness, the measured approach speed): the colliding-sphere dipole pair (Koss and Alfredson,
1973). The signal is the sum over every collision and both its bodies.

Several cavities on one main mass (:class:`acoustiviz.dynamics.MultiBallModel`) radiate each from its own
place (:func:`cavity_places`): the clicks of every cavity are summed. In a room every sphere radiates
with the room's images of its own position (:meth:`acoustiviz.core.room_geometry.Room.image_sources`, to
the room's order and tolerance), summed as :func:`acoustiviz.sound.render` sums them (the first images
exactly, the rest through fractional-delay trains); the spheres within ``POSITION_STEP`` of each other
share their images (the direct sound stays at each sphere's own place; :mod:`.balls_room`).

Left out: the acoustic interaction of the two touching spheres (each radiates as if alone; Morfey,
Sharpe and Smith, 1998), the spheres' own elastic modes, the ringing of the cavity walls (the main
mass radiates nothing), and the screening and scattering of the sound by the main mass and the other
cavities (each sphere radiates into the configuration, or the room, alone).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np

from .._validate import ParameterError
from ..constants import WAV_RATE
from ..core.images import ImageSource
from ..core.signal import Signal
from ..field.sources import image_geometry
from .balls_room import POSITION_STEP, RoomGroups
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

__all__ = ["LEFT_OUT", "CAVITY_PLACEMENT", "POSITION_STEP", "BallClicks", "column_scene", "radiating_radius",
           "cavity_places", "ball_clicks", "render_clicks", "render_balls", "check_ball_scene",
           "check_ball_listeners"]

#: What the multi-ball sound leaves out (said in every rendering's description and the WAV sidecar).
LEFT_OUT = ("the acoustic interaction of touching spheres (each radiates as if alone; Morfey, Sharpe and Smith "
            "1998)", "the spheres' own elastic modes", "the ringing of the cavity walls",
            "the screening and scattering of the sound by the main mass and the other cavities")

#: How several cavities are placed (said in the WAV sidecar; :func:`cavity_places`).
CAVITY_PLACEMENT = ("each cavity moved rigidly by its offset from the scene's, its struck-wall ball touching the "
                    "struck surface at offset zero; by default cavity k (from 0) is k times the longest cavity's "
                    "length plus the largest ball's diameter along the horizontal direction perpendicular to the "
                    "axis with the most room; every cavity radiates from its own place, their clicks summed")


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
    places : (n_cavities, 3) ndarray or None
        Offset in m of each cavity's struck wall from the scene's (:func:`cavity_places`); None: one cavity
        in the scene's place.

    Notes
    -----
    In a room a click's ``sources`` hold its real sphere alone: the room's images of it (thousands) are
    made when it is rendered (:func:`render_clicks`).
    """

    times: np.ndarray
    velocities: np.ndarray
    sources: tuple
    pulses: tuple
    collision: np.ndarray
    walls: np.ndarray
    radii: np.ndarray | None = None
    places: np.ndarray | None = None

    def __len__(self) -> int:
        return int(np.size(self.times))

    def take(self, index) -> BallClicks:
        """The clicks ``index`` (an integer array or a boolean mask) alone, in their order."""
        idx = np.arange(len(self))[index]
        return BallClicks(self.times[idx], self.velocities[idx], tuple(self.sources[i] for i in idx),
                          tuple(self.pulses[i] for i in idx), self.collision[idx], self.walls[idx],
                          None if self.radii is None else self.radii[idx], self.places)

    def shifted(self, seconds: float) -> BallClicks:
        """The same clicks ``seconds`` s later (earlier when negative)."""
        return replace(self, times=self.times + float(seconds))

    def repeat(self, period: float, copies: int) -> BallClicks:
        """The clicks repeated ``copies`` times, each copy ``period`` s after the last (a periodic train).

        The collision rows of copy ``j`` are offset by ``j`` times one more than the largest row, so each
        copy's ball-ball contacts count apart (:meth:`describe`).
        """
        copies = int(copies)
        n = len(self)
        step = int(self.collision.max()) + 1 if n else 0
        return BallClicks(np.concatenate([self.times + j * period for j in range(copies)]) if n else self.times,
                          np.tile(self.velocities, copies), self.sources * copies, self.pulses * copies,
                          np.concatenate([self.collision + j * step for j in range(copies)]) if n else self.collision,
                          np.tile(self.walls, copies), None if self.radii is None else np.tile(self.radii, copies),
                          self.places)

    def describe(self) -> dict:
        """A JSON-ready summary: the counts of both kinds of contact and what the model leaves out."""
        wall = self.walls != 0
        out = {"clicks": len(self), "ball_wall_contacts": int(np.count_nonzero(wall)),
               "ball_ball_contacts": int(np.unique(self.collision[~wall]).size),
               "ball_ball_model": "two rigid spheres, equal and opposite impulses (colliding-sphere dipole pair)",
               "left_out": list(LEFT_OUT)}
        if self.radii is not None:
            out["sphere_radii_m"] = sorted({float(r) for r in self.radii})
        if self.places is not None and len(self.places) > 1:
            out["cavity_offsets_m"] = np.asarray(self.places, dtype=float).tolist()
            out["cavity_placement"] = CAVITY_PLACEMENT
        return out


def column_scene(scene: CavityScene, cavity) -> CavityScene:
    """The scene of a column of several balls: its geometry rebuilt around the ball on the struck wall.

    Several balls radiate each as a sphere of its own radius (:func:`radiating_radius`), so the ball that
    touches the struck surface has its centre its own radius from it (a wall strike: the wall at that
    radius; a room: the sphere's ``source`` moved to touch the struck surface if it touched it). One ball,
    or a geometry already of that radius: ``scene`` itself.
    """
    if cavity.n_balls == 1:
        return scene
    r = float(cavity.radii[0] if scene.struck_wall == -1 else cavity.radii[-1])
    g = scene.geometry
    if g.radius == r:
        return scene
    if g.enclosed:  # a room: the sphere's centre keeps touching the struck surface
        src = list(g.source)
        if g.touches_struck_surface:
            ax = g.contact_coordinate[0]
            src[ax] += float(g.direction[ax]) * (r - g.radius)
        moved = {"source": tuple(src)}
    else:
        moved = {"wall_distance": r} if getattr(g, "strike", "floor") == "wall" else {}
    return replace(scene, geometry=replace(g, radius=r, **moved), radius=None)


def radiating_radius(cavity, ball: int, scene_radius: float, *, several: bool | None = None) -> float:
    """Radius in m of the sphere ball ``ball`` (0-based) of ``cavity`` radiates as: the one home of that rule.

    Several balls (in the cavity, or in all the cavities of the run: ``several``, default whether this
    cavity has more than one): the ball's own radius, the one the dynamics uses (``cavity.radii``, from its
    mass and the steel density), so the balls of a column radiate as the spheres that fill it. One ball:
    the scene's radius ``scene_radius`` (the sound's ``radius``, default the paper's 19.05 mm sphere), as
    :func:`acoustiviz.sound.render` does.
    """
    several = cavity.n_balls > 1 if several is None else several
    return float(cavity.radii[ball]) if several else float(scene_radius)


def _column(cav, radius: float, several: bool) -> tuple:
    """``(radius of each ball, largest radius, span)`` in m of a cavity's radiating spheres."""
    r = [radiating_radius(cav, i, radius, several=several) for i in range(cav.n_balls)]
    return r, max(r), float(cav.gap + 2.0 * sum(r) - r[0] - r[-1])


def cavity_places(model, scene: CavityScene, positions=None, *, name: str = "positions[{k}]") -> np.ndarray:
    """Offset in m of each cavity's struck wall from the scene's, ``(n_cavities, 3)``: given or spaced apart.

    Each cavity is moved rigidly by its offset: at offset zero its struck-wall ball touches the scene's
    struck surface where the scene's sphere does (its centre its own radius from it), and the column runs
    along the scene's axis. By default cavity k (from 0) lies ``k s h`` away: ``s`` the longest cavity's
    length plus the largest ball's diameter, ``h`` the horizontal unit vector (x or y) perpendicular to the
    axis along which the scene's planes leave the most room.

    Parameters
    ----------
    model : acoustiviz.dynamics.MultiBallModel
        The cavities.
    scene : CavityScene
        The surroundings (for several balls in the first cavity, :func:`column_scene`).
    positions : sequence, optional
        Per cavity a ``(3,)`` offset in m, or None for its default (None: every default).
    name : str
        Name of cavity ``k``'s offset in error messages (``{k}`` is replaced by its index).

    Raises
    ------
    ParameterError
        When an offset is not three finite numbers, a ball of its cavity would leave the fluid (closer to
        a plane than its radius) or two cavities overlap (their columns closer than their radii's sum).
    """
    cavs = model.cavities
    given = [None] * len(cavs) if positions is None else list(positions)
    if len(given) != len(cavs):
        raise ParameterError(name.format(k=len(given)), f"one position per cavity: {len(cavs)} cavities, got "
                                                        f"{len(given)}")
    cols = [_column(c, scene.radius, model.n_balls > 1) for c in cavs]
    n, c0 = scene.axis, np.asarray(scene.geometry.centre, dtype=float)
    h = _roomiest(scene, n, c0)
    step = max(span + r[0] + r[-1] for r, _, span in cols) + 2.0 * max(rm for _, rm, _ in cols)
    places = np.zeros((len(cavs), 3))
    for k, p in enumerate(given):
        if p is None:
            places[k] = k * step * h
            continue
        try:
            v = np.asarray(p, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            v = np.array([np.nan])
        if v.shape != (3,) or not np.all(np.isfinite(v)):
            raise ParameterError(name.format(k=k), f"expected three offsets x, y, z in m, got {p!r}")
        places[k] = v
    ends = []
    for k, (r, rm, span) in enumerate(cols):
        base = c0 + (r[0 if scene.struck_wall == -1 else -1] - scene.radius) * n + places[k]
        ends.append(base)
        for pl in scene.geometry.planes:
            near = min(float((base - pl.point) @ pl.normal), float((base + span * n - pl.point) @ pl.normal))
            if near < rm * (1.0 - 1e-9):
                raise ParameterError(name.format(k=k), f"cavity {k + 1}'s balls would leave the fluid: a centre "
                                                       f"{near:.4g} m from the {pl.label}, less than the radius "
                                                       f"{rm:g} m")
    for j in range(len(cavs)):
        for k in range(j):
            d = _apart(ends[k], cols[k][2], ends[j], cols[j][2], n)
            if d < (cols[j][1] + cols[k][1]) * (1.0 - 1e-9):
                raise ParameterError(name.format(k=j), f"cavity {j + 1} overlaps cavity {k + 1}: their columns are "
                                                       f"{d:.4g} m apart, less than {cols[j][1] + cols[k][1]:g} m "
                                                       "(the sum of their balls' radii)")
    return places


def _roomiest(scene: CavityScene, n: np.ndarray, c0: np.ndarray) -> np.ndarray:
    """The unit vector among +x, +y, -x, -y perpendicular to ``n`` along which the planes leave most room."""
    best, room = None, -np.inf
    for h in np.array([[1.0, 0, 0], [0, 1.0, 0], [-1.0, 0, 0], [0, -1.0, 0]]):
        if abs(h @ n) > 1e-12:
            continue
        free = min([float((c0 - pl.point) @ pl.normal) / -float(h @ pl.normal)
                    for pl in scene.geometry.planes if h @ pl.normal < -1e-12], default=np.inf)
        if free > room:
            best, room = h, free
    return best


def _apart(p: np.ndarray, lp: float, q: np.ndarray, lq: float, n: np.ndarray) -> float:
    """Distance in m between the parallel segments ``[p, p + lp n]`` and ``[q, q + lq n]``."""
    d = q - p
    s = float(d @ n)
    across = float(np.linalg.norm(d - s * n))
    along = max(0.0, s - lp, -(s + lq))
    return math.hypot(across, along)


def _ball_index(name: str, n: int) -> int:
    """0-based ball of a body name ``ballK`` (-1 for ``wall-``, n for ``wall+``)."""
    if name == "wall-":
        return -1
    if name == "wall+":
        return n
    return int(name[4:]) - 1


def _sphere_sources(scene: CavityScene, position, axis, label: str) -> tuple:
    """The sphere at ``position`` (m) accelerated along ``axis`` and its images in the scene's planes.

    In a room the sphere alone: :func:`render_clicks` makes the room's images of it.
    """
    real = ImageSource(position, axis, 0, label)
    if scene.geometry.enclosed:
        return (real,)
    return tuple(scene.geometry.image_sources(real))


def _centres(result, cav, times: np.ndarray, index: int) -> np.ndarray:
    """Distance in m of ball ``index``'s centre from ball 1's centre at the wall- contact, at ``times``."""
    if np.size(result.t) < 2:
        raise ParameterError("result", "the sound of several balls needs their sampled motion (t_eval)")
    base = cav.offsets[0] - 0.5 * cav.gap
    return np.interp(times, result.t, result.y[:, index] - result.x) - base


def ball_clicks(result, scene: CavityScene, click: ClickModel, *, positions=None) -> BallClicks:
    """The radiating spheres of every collision of a multi-ball run.

    Parameters
    ----------
    result : acoustiviz.dynamics.MultiBallResult
        The run, with its motion sampled (``t_eval``) finely enough to place the balls.
    scene : CavityScene
        The damper's surroundings; its struck wall holds ball 1 (``struck_wall=-1``) or ball N (``+1``)
        at the geometry's centre (several balls: :func:`column_scene`), the others further along its axis.
        One ball radiates as a sphere of the scene's radius, several (in one cavity or in all) each as a
        sphere of its own radius
        (:func:`radiating_radius`). In a room each click holds its real sphere alone (:class:`BallClicks`).
    click : ClickModel
        The contact and pulse of a ball on a wall (its ``mass`` is replaced by each ball's mass).
    positions : sequence, optional
        Several cavities: per cavity the offset in m of its struck wall from the scene's, or None for its
        default (:func:`cavity_places`).

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
    ball's own mass (equal and opposite forces). Several cavities (body names ``c2:ball1``) radiate each
    from its own place, their clicks in one list in order of first touch.
    """
    model = result.model
    scene = column_scene(scene, model.cavities[0])
    places = cavity_places(model, scene, positions)
    several = len(model.cavities) > 1
    firsts = np.cumsum([0] + [c.n_balls for c in model.cavities])
    imp = result.impacts
    found = []
    for k in range(len(imp)):
        t, v = float(imp.time[k]), abs(float(imp.approach_velocity[k]))
        if not v > 0.0:  # a contact made at rest (a column settling) accelerates nothing audibly: silent
            continue
        ic, first, second = 0, str(imp.first[k]), str(imp.second[k])
        if several:
            ic = int(first.partition(":")[0][1:]) - 1
            first, second = first.partition(":")[2], second.partition(":")[2]
        where = _Placement(result, scene, model.cavities[ic], places[ic], int(firsts[ic]))
        found += [(t, v, srcs, pulse_for(v), r, w, k)
                  for srcs, pulse_for, r, w in where.clicks(first, second, t, click)]
    cols = list(zip(*found, strict=True)) if found else [()] * 7
    return BallClicks(np.asarray(cols[0], dtype=float), np.asarray(cols[1], dtype=float), tuple(cols[2]),
                      tuple(cols[3]), np.asarray(cols[6], dtype=np.int64), np.asarray(cols[5], dtype=np.int64),
                      np.asarray(cols[4], dtype=float), places if several else None)


class _Placement:
    """Where the balls of one cavity radiate from: its place in the scene and its sampled motion."""

    def __init__(self, result, scene: CavityScene, cav, offset: np.ndarray, first: int):
        self.result, self.scene, self.cav, self.first = result, scene, cav, first
        self.several = result.model.n_balls > 1
        r_struck = self.radius(0 if scene.struck_wall == -1 else cav.n_balls - 1)
        # the scene's own sources serve a cavity in the scene's place with the scene's sphere on its struck wall
        self.same = not scene.geometry.enclosed and not np.any(offset) and r_struck == scene.radius
        self.base = np.asarray(scene.geometry.centre, dtype=float) + (r_struck - scene.radius) * scene.axis + offset
        self.top = cav.gap + cav.offsets[-1] - cav.offsets[0]  # ball N's distance at the wall+ contact

    def radius(self, ball: int) -> float:
        """Radius in m of the sphere ball ``ball`` (0-based) radiates as (:func:`radiating_radius`)."""
        return radiating_radius(self.cav, ball, self.scene.radius, several=self.several)

    def where(self, u):
        """Centre in m of a ball ``u`` m along the axis from ball 1's centre at the wall- contact."""
        return self.base + (u if self.scene.struck_wall == -1 else self.top - u) * self.scene.axis

    def clicks(self, first: str, second: str, t: float, click: ClickModel) -> list:
        """``(sources, pulse, radius, wall)`` of each sphere of the contact of bodies ``first``, ``second``."""
        scene, cav, n = self.scene, self.cav, self.cav.n_balls
        i, j = _ball_index(first, n), _ball_index(second, n)
        axis = scene.axis
        up = -scene.struck_wall * axis  # direction from wall- to wall+ in the scene
        if i == -1 or j == n:  # a ball on a wall: as the one ball of render(), of this ball's mass
            ball, wall = (j, -1) if i == -1 else (i, 1)
            radius = self.radius(ball)
            pulse = replace(click, mass=cav.masses[ball]).pulse_for
            if self.same and (wall == scene.struck_wall or scene.walls == "one" or n == 1):
                return [(wall_sources(scene, wall), pulse, radius, wall)]
            if self.same:
                return [(_sphere_sources(scene, self.where(0.0 if wall == -1 else self.top), -axis, "far"), pulse,
                         radius, wall)]
            heard = scene.struck_wall if scene.walls == "one" else wall
            u = 0.0 if heard == -1 else self.top
            sign = 1.0 if heard == scene.struck_wall else -1.0
            label = "real" if heard == scene.struck_wall else "far"
            return [(_sphere_sources(scene, self.where(u), sign * axis, label), pulse, radius, wall)]
        # two balls touching: the lower one pushed towards wall-, the upper towards wall+
        half = 0.5 * (cav.radii[i] + cav.radii[j])
        mid = 0.5 * (self._centre(t, i) + self._centre(t, j))
        lower, upper = mid - half, mid + half
        if scene.geometry.enclosed:  # a room refuses a sphere in its surface: a ball pressed into a wall touches it
            o = cav.offsets - cav.offsets[0]
            lower = min(max(lower, o[i]), self.top - o[-1] + o[i])
            upper = min(max(upper, o[j]), self.top - o[-1] + o[j])
        pair = dict(k_hertz=cav.k_ball[i], mass_model="effective", pulse=click.pulse,
                    hertz_samples=click.hertz_samples)
        return [(_sphere_sources(scene, self.where(lower), -up, f"ball{i + 1}"),
                 ClickModel(mass=cav.masses[i], main_mass=cav.masses[j], **pair).pulse_for,
                 self.radius(i), 0),
                (_sphere_sources(scene, self.where(upper), up, f"ball{j + 1}"),
                 ClickModel(mass=cav.masses[j], main_mass=cav.masses[i], **pair).pulse_for,
                 self.radius(j), 0)]

    def _centre(self, t: float, ball: int) -> float:
        """Distance in m of ball ``ball``'s centre from ball 1's centre at the wall- contact, at ``t``."""
        return _centres(self.result, self.cav, t, self.first + ball)


def render_clicks(clicks: BallClicks, scene: CavityScene, click: ClickModel, listeners, *,
                  sample_rate: int = WAV_RATE, duration: float | None = None,
                  oversampling: int | None = None) -> Rendering:
    """Render radiating spheres into band-limited pressure signals at the listeners (Pa).

    The same synthesis as :func:`acoustiviz.sound.render` (each click in closed form on the internal
    grid, filtered and decimated, added in time order), with each click's own spheres and radius
    (``clicks.radii``; the clicks of one radius are added together, in time order). In a room
    (``scene.geometry.enclosed``) each click's real sphere gets the room's images of its position,
    shared by the spheres within ``POSITION_STEP`` of each other (:class:`~.balls_room.RoomGroups`).

    Parameters
    ----------
    clicks : BallClicks
        The spheres (:func:`ball_clicks` of the same scene).
    scene : CavityScene
        The scene (medium, listener checks, a room's images).
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
        Its ``sequence`` holds the ball-wall contacts; :meth:`Rendering.describe` adds the ball-ball ones,
        what the model leaves out, the cavities' places and, in a room, how the room was applied.
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
    room = RoomGroups(clicks, scene.geometry, pts, radii, medium) if scene.geometry.enclosed else None
    geom, end = {}, 0.0 if room is None else room.end(clicks.times, taus, tails)
    for k, srcs in enumerate(clicks.sources):
        delay, p0, c_shape, _ = image_geometry(pts, srcs if room is None else room.sources(k), float(radii[k]),
                                               medium=medium)
        geom[k] = (delay, p0 * c_shape)
        end = max(end, float(clicks.times[k] + taus[k]) + float(delay.max()) + float(tails[k]))
    n_out = max(math.ceil(end * fs) + half + 1, math.ceil((duration or 0.0) * fs))
    out = np.zeros((pts.shape[0], n_out))

    def grid(a: float) -> tuple:
        return fs, L, f_int, h, half, _TAIL_DECADES * math.log(10.0) * float(a) / medium.c

    for a in np.unique(radii):  # one ball, or equal balls: one radius, one pass
        sel = np.flatnonzero(radii == a)
        order = SimpleNamespace(times=clicks.times[sel], walls=sel)
        _add_exact_clicks(out, order, [clicks.pulses[k] for k in sel], geom, grid(a), float(a), medium)
    described = clicks.describe()
    if room is not None:
        room.add_trains(out, pts, radii, grid)
        described["room"] = room.describe()
    out.flags.writeable = False
    return Rendering(Signal(out, fs), f_int, pts, seq, scene, click, balls=described)


def render_balls(result, scene: CavityScene, click: ClickModel, listeners, *, positions=None,
                 **options) -> Rendering:
    """The sound of a multi-ball run at the listeners: :func:`render_clicks` of :func:`ball_clicks`.

    ``positions``: several cavities, the offset in m of each one's struck wall from the scene's, or None for
    the default (:func:`cavity_places`). ``options``: ``sample_rate``, ``duration``, ``oversampling`` of
    :func:`render_clicks`. A listener inside any cavity's column of balls is refused (``listeners``).
    """
    scene, places, _ = check_ball_scene(result.model, scene, listeners, positions)
    return render_clicks(ball_clicks(result, scene, click, positions=places), scene, click, listeners, **options)


def check_ball_scene(model, scene: CavityScene, listeners, positions=None, *, name: str = "listeners",
                     positions_name: str = "positions[{k}]") -> tuple:
    """Place the cavities of a multi-ball model and check the listeners: ``(scene, places, listeners)``.

    The scene rebuilt around the first cavity's column (:func:`column_scene`), the offset in m of every
    cavity (:func:`cavity_places`, errors naming ``positions_name``) and the listeners as an ``(n, 3)``
    array in m, none inside any column (:func:`check_ball_listeners`, errors naming ``name``): what
    :func:`render_balls` checks, for a front end to check before any work.
    """
    scene = column_scene(scene, model.cavities[0])
    places = cavity_places(model, scene, positions, name=positions_name)
    return scene, places, check_ball_listeners(listeners, scene, model, places, name=name)


def check_ball_listeners(listeners, scene: CavityScene, model, places, *, name: str = "listeners") -> np.ndarray:
    """:func:`~acoustiviz.sound.check_listeners` with every cavity's column of balls at its place (m)."""
    cavs = model.cavities
    pts = check_listeners(listeners, scene, name=name, column=cavs[0] if len(cavs) == 1 else None)
    if len(cavs) > 1:
        for cav, offset in zip(cavs, places, strict=True):
            r, rm, span = _column(cav, scene.radius, True)
            base = np.asarray(scene.geometry.centre, dtype=float) + (r[0 if scene.struck_wall == -1 else -1]
                                                                     - scene.radius) * scene.axis + offset
            for p in pts:
                s = float(np.clip((p - base) @ scene.axis, 0.0, span))
                if np.linalg.norm(p - (base + s * scene.axis)) < rm * (1.0 - 1e-12):
                    raise ParameterError(name, f"listener ({p[0]:g}, {p[1]:g}, {p[2]:g}) m is inside cavity "
                                               f"{cavs.index(cav) + 1} (within {rm:g} m of the path of its balls' "
                                               f"centres, {span:g} m long from its struck wall's ball)")
    return pts
