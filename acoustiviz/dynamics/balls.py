"""Multi-unit and particle-column impact dampers: one or several cavities of balls on the main mass.

The main mass ``M`` on its spring ``K`` and dashpot ``C`` (as :class:`~acoustiviz.dynamics.DamperModel`)
carries one or several :class:`Cavity`; each holds a column of balls that move along the axis.
A cavity's *free travel* ``gap`` is its length less the sum of its balls' diameters: with the balls
packed against each other the column can travel ``gap`` between the two walls, as the one impact
mass of the single-ball damper travels its gap.

Coordinates
-----------
``x`` (m) is the displacement of the main mass; the cavity's centre moves with it. A ball's
*centre* ``y_i`` (m) is reported in the same frame. Inside, each ball is followed by its reduced
coordinate ``s_i = y_i - o_i`` with the offset ``o_i = 2 (r_1 + ... + r_{i-1}) + r_i - (r_1 + ... + r_N)``
(m): the walls stand at ``x ∓ gap/2`` and two neighbours touch when their ``s`` coincide. One ball
has ``o_1 = 0`` and ``y = s``, the single-ball damper's coordinate.

Contact
-------
Every pair of neighbours (``wall-`` and ball 1, ball i and ball i+1, ball N and ``wall+``) follows
the single-ball solver's law (paper eq 15): with the penetration ``δ > 0`` the force
``F = K δ^{3/2} + c dδ/dt`` (clipped at zero with ``clip_tensile``) pushes the pair apart. ``K`` and
``c`` are the cavity's wall values for a wall pair and its ball values for two balls; the ball-ball
stiffness follows from the two radii and materials (:func:`~acoustiviz.core.contact.sphere_pair_stiffness`).

Solver: :func:`simulate_balls` (the compiled kernel :mod:`acoustiviz.dynamics._balls`). All SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_finite, check_nonnegative, check_positive
from ..constants import BALL_STARTS, TABLE1_PARAMETERS

__all__ = ["Cavity", "MultiBallModel", "BallState", "equal_balls", "cavity_body_names"]


def _floats(name: str, values, unit: str, check=check_positive) -> tuple:
    try:
        seq = tuple(values)
    except TypeError:
        raise ParameterError(name, f"must be a sequence of values in {unit}, got {values!r}") from None
    return tuple(check(f"{name}[{i}]", v, unit) for i, v in enumerate(seq))


@dataclass(frozen=True)
class Cavity:
    """A cavity of the main mass and its column of balls, in axis order.

    Parameters
    ----------
    gap : float
        Free travel in m: the cavity's length less the sum of the balls' diameters.
    masses : sequence of float
        Ball masses in kg (at least one ball).
    radii : sequence of float
        Ball radii in m (one per ball).
    k_wall : float
        Hertz stiffness of a ball on a wall in N/m^1.5 (the single-ball damper's ``k_hertz``).
    c_wall : float
        Contact damping of a ball on a wall in N s/m (the single-ball damper's ``c1``).
    k_ball : sequence of float
        Hertz stiffness of each pair of neighbouring balls in N/m^1.5 (N - 1 values; empty for one
        ball); see :func:`equal_balls` for the value from the radii and materials.
    c_ball : float
        Contact damping between two balls in N s/m.

    Examples
    --------
    >>> Cavity(0.04, (0.0405,), (0.0107,), 5.6e8, 20.0).n_balls
    1
    """

    gap: float
    masses: tuple
    radii: tuple
    k_wall: float
    c_wall: float
    k_ball: tuple = ()
    c_ball: float = 0.0

    def __post_init__(self):
        check_positive("gap", self.gap, "m")
        object.__setattr__(self, "masses", _floats("masses", self.masses, "kg"))
        object.__setattr__(self, "radii", _floats("radii", self.radii, "m"))
        object.__setattr__(self, "k_ball", _floats("k_ball", self.k_ball, "N/m^1.5"))
        if not self.masses:
            raise ParameterError("masses", "a cavity holds at least one ball")
        n = len(self.masses)
        if len(self.radii) != n:
            raise ParameterError("radii", f"one radius per ball: {n} balls, got {len(self.radii)} radii")
        if len(self.k_ball) != n - 1:
            raise ParameterError("k_ball", f"one stiffness per pair of neighbours: {n - 1} pairs, "
                                           f"got {len(self.k_ball)}")
        check_positive("k_wall", self.k_wall, "N/m^1.5")
        check_nonnegative("c_wall", self.c_wall, "N s/m")
        check_nonnegative("c_ball", self.c_ball, "N s/m")

    @property
    def n_balls(self) -> int:
        """Number of balls."""
        return len(self.masses)

    @property
    def length(self) -> float:
        """Length of the cavity in m: the free travel plus the balls' diameters."""
        return self.gap + 2.0 * sum(self.radii)

    @property
    def span(self) -> float:
        """Distance in m from ball 1's centre against ``wall-`` to ball N's against ``wall+``.

        The segment the balls' centres sweep: the free travel plus the diameters between the first
        ball's centre and the last's (one ball: the free travel).
        """
        return float(self.gap + 2.0 * sum(self.radii) - self.radii[0] - self.radii[-1])

    @property
    def offsets(self) -> np.ndarray:
        """Offset ``o_i`` in m of each ball's centre from its reduced coordinate (module docstring)."""
        r = np.asarray(self.radii)
        return 2.0 * (np.cumsum(r) - r) + r - r.sum()


def equal_balls(n: int, mass: float, gap: float, k_wall: float, c_wall: float, *, k_ball: float | None = None,
                c_ball: float | None = None, material: str = "steel") -> Cavity:
    """A cavity of ``n`` equal spheres of ``mass`` kg of ``material`` with free travel ``gap`` m.

    The radius follows from the mass and the material's density
    (:func:`~acoustiviz.core.materials.sphere_radius`); the ball-ball stiffness, unless given, from
    the two radii and materials (:func:`~acoustiviz.core.contact.sphere_pair_stiffness`); the
    ball-ball damping defaults to ``c_wall`` (N s/m).
    """
    from ..core.contact import sphere_pair_stiffness
    from ..core.materials import material as find_material
    from ..core.materials import sphere_radius

    if int(n) != n or n < 1:
        raise ParameterError("balls", f"must be a whole number >= 1, got {n!r}")
    n = int(n)
    mat = find_material(material)
    radius = sphere_radius(mass, mat.density)
    kb = sphere_pair_stiffness(radius, radius, mat, mat) if k_ball is None else check_positive("k_ball", k_ball)
    cb = c_wall if c_ball is None else c_ball
    return Cavity(gap, (mass,) * n, (radius,) * n, k_wall, c_wall, (kb,) * (n - 1), cb)


@dataclass(frozen=True)
class MultiBallModel:
    """The main mass with one or several cavities of balls; defaults as the paper's Table 1.

    Parameters
    ----------
    cavities : sequence of Cavity
        The cavities, numbered from 1 in this order (``c2:ball1`` in the impact table).
    M, K, C : float
        Main mass in kg, spring in N/m and dashpot in N s/m (:class:`~acoustiviz.dynamics.DamperModel`).
    clip_tensile : bool
        Clip every contact force at zero.
    """

    cavities: tuple
    M: float = TABLE1_PARAMETERS["M"]
    K: float = TABLE1_PARAMETERS["K"]
    C: float = TABLE1_PARAMETERS["C"]
    clip_tensile: bool = False

    def __post_init__(self):
        cavs = (self.cavities,) if isinstance(self.cavities, Cavity) else tuple(self.cavities)
        if not cavs or not all(isinstance(c, Cavity) for c in cavs):
            raise ParameterError("cavities", "must be one or several Cavity")
        object.__setattr__(self, "cavities", cavs)
        check_positive("M", self.M, "kg")
        check_positive("K", self.K, "N/m")
        check_nonnegative("C", self.C, "N s/m")
        if not isinstance(self.clip_tensile, bool):
            raise ParameterError("clip_tensile", f"must be True or False, got {self.clip_tensile!r}")

    @classmethod
    def from_damper(cls, model, balls: int = 1, *, k_ball: float | None = None, c_ball: float | None = None,
                    material: str = "steel") -> MultiBallModel:
        """``balls`` equal spheres of the impact mass ``model.m`` in the gap of a :class:`DamperModel`."""
        cav = equal_balls(balls, model.m, model.gap, model.k_hertz, model.c1, k_ball=k_ball, c_ball=c_ball,
                          material=material)
        return cls((cav,), model.M, model.K, model.C, model.clip_tensile)

    @property
    def n_balls(self) -> int:
        """Number of balls in all cavities."""
        return sum(c.n_balls for c in self.cavities)

    @property
    def main_frequency(self) -> float:
        """Undamped angular frequency sqrt(K/M) of the main mass in rad/s."""
        return math.sqrt(self.K / self.M)

    @property
    def underdamped(self) -> bool:
        """True when the main oscillator is underdamped (needed by the closed-form flights)."""
        return self.C < 2.0 * math.sqrt(self.K * self.M)

    def pairs(self) -> dict:
        """The contact pairs as arrays: bodies ``pa``, ``pb`` (0 main, 1.. balls), half-gaps m, K, c, cavity, pair."""
        pa, pb, hg, kh, cc, cav, loc = [], [], [], [], [], [], []
        first = 1
        for ic, c in enumerate(self.cavities, start=1):
            n = c.n_balls
            for j in range(n + 1):
                wall = j in (0, n)
                pa.append(0 if j == 0 else first + j - 1)
                pb.append(0 if j == n else first + j)
                hg.append(0.5 * c.gap if wall else 0.0)
                kh.append(c.k_wall if wall else c.k_ball[j - 1])
                cc.append(c.c_wall if wall else c.c_ball)
                cav.append(ic)
                loc.append(j)
            first += n
        ints = {"pa": pa, "pb": pb}
        out = {k: np.asarray(v, dtype=np.int64) for k, v in ints.items()}
        out.update({k: np.asarray(v, dtype=float) for k, v in
                    {"hg": hg, "kh": kh, "cc": cc, "cav": cav, "loc": loc}.items()})
        return out

    def masses(self) -> np.ndarray:
        """Masses in kg of the bodies: the main mass, then every ball in cavity and axis order."""
        return np.array([self.M, *(m for c in self.cavities for m in c.masses)], dtype=float)

    def offsets(self) -> np.ndarray:
        """Offsets in m of every ball's centre from its reduced coordinate (cavity and axis order)."""
        return np.concatenate([c.offsets for c in self.cavities])

    def energy(self, q, u) -> float:
        """Mechanical energy in J of the bodies at reduced positions ``q`` (m) and velocities ``u`` (m/s).

        Kinetic + main spring + Hertz (``2/5 K δ^{5/2}`` of every pair in contact).
        """
        q, u = np.asarray(q, dtype=float), np.asarray(u, dtype=float)
        pr = self.pairs()
        d = np.maximum(q[pr["pa"]] - q[pr["pb"]] - pr["hg"], 0.0)
        return float(0.5 * np.sum(self.masses() * u**2) + 0.5 * self.K * q[0] ** 2 + np.sum(0.4 * pr["kh"] * d**2.5))


def cavity_body_names(model: MultiBallModel) -> list:
    """Names of the bodies of each pair, in pair order: ``(first, second)`` as ``wall-``, ``ball1`` ... ``wall+``.

    With several cavities each name carries its cavity's number, ``c2:ball1``.
    """
    names = []
    several = len(model.cavities) > 1
    for ic, c in enumerate(model.cavities, start=1):
        pre = f"c{ic}:" if several else ""
        bodies = ["wall-", *(f"ball{i}" for i in range(1, c.n_balls + 1)), "wall+"]
        names.extend((pre + bodies[j], pre + bodies[j + 1]) for j in range(c.n_balls + 1))
    return names


@dataclass(frozen=True)
class BallState:
    """Initial state: the main mass's displacement (m) and velocity (m/s) and the balls'.

    Parameters
    ----------
    x, v : float
        Main mass (the paper's Figure 5 start: 0 m, 2 m/s).
    y, w : sequence of float or None
        Ball centres in m and velocities in m/s, cavity and axis order. ``y`` None: the balls placed by
        ``start``; ``w`` None: at rest.
    start : str or sequence of str
        Where the balls start when ``y`` is None, one of :data:`acoustiviz.constants.BALL_STARTS` for
        every cavity or one per cavity: ``spaced`` (the free travel split into N + 1 equal spaces; one
        ball: centred), ``low`` (packed touching on ``wall-``, the free travel all above), ``high``
        (packed on ``wall+``), ``random`` (the free travel split at N uniform random points).
    seed : int, optional
        Seed of the ``random`` start (:func:`numpy.random.default_rng`); None: fresh entropy.
    """

    x: float = 0.0
    v: float = 2.0
    y: tuple | None = None
    w: tuple | None = None
    start: str | tuple = "spaced"
    seed: int | None = None

    def __post_init__(self):
        check_finite("x", self.x)
        check_finite("v", self.v)
        for name in ("y", "w"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _floats(name, getattr(self, name), "",
                                                       lambda n, v, _u: check_finite(n, v)))
        starts = (self.start,) if isinstance(self.start, str) else tuple(self.start)
        for i, name in enumerate(starts):
            if name not in BALL_STARTS:
                where = "start" if isinstance(self.start, str) else f"start[{i}]"
                raise ParameterError(where, f"must be one of {', '.join(BALL_STARTS)}, got {name!r}")

    def cuts(self, model: MultiBallModel) -> list:
        """Per cavity, how far in m each ball has travelled from ``wall-`` when ``y`` is None, as ``start`` says.

        Ball i's clearance to its lower neighbour (``wall-`` for ball 1) is ``cuts[i] - cuts[i-1]``.
        """
        starts = (self.start,) * len(model.cavities) if isinstance(self.start, str) else tuple(self.start)
        if len(starts) != len(model.cavities):
            raise ParameterError("start", f"one start per cavity: {len(model.cavities)} cavities, "
                                          f"got {len(starts)}")
        rng = np.random.default_rng(self.seed) if "random" in starts else None
        out = []
        for c, start in zip(model.cavities, starts, strict=True):
            n = c.n_balls
            if start == "spaced":
                out.append(c.gap * np.arange(1, n + 1) / (n + 1))
            elif start == "random":
                out.append(np.sort(rng.uniform(0.0, c.gap, n)))
            else:
                out.append(np.full(n, 0.0 if start == "low" else c.gap))
        return out

    def clearances(self, model: MultiBallModel) -> list:
        """Per cavity the N + 1 spaces in m of its column when ``y`` is None, summing to its free travel.

        From ``wall-`` to ball 1, between neighbours, from ball N to ``wall+``, as ``start`` places them.
        """
        return [np.diff(np.concatenate([[0.0], cut, [c.gap]]))
                for c, cut in zip(model.cavities, self.cuts(model), strict=True)]

    def reduced(self, model: MultiBallModel) -> tuple[np.ndarray, np.ndarray]:
        """Reduced positions (m) and velocities (m/s) of every body, checked to lie in their cavities."""
        nb = model.n_balls
        if self.y is None:
            cuts = zip(model.cavities, self.cuts(model), strict=True)
            s = np.concatenate([self.x - 0.5 * c.gap + cut for c, cut in cuts])
        else:
            if len(self.y) != nb:
                raise ParameterError("initial.y", f"one position per ball: {nb} balls, got {len(self.y)}")
            s = np.asarray(self.y) - model.offsets()
        w = np.zeros(nb) if self.w is None else np.asarray(self.w, dtype=float)
        if w.size != nb:
            raise ParameterError("initial.w", f"one velocity per ball: {nb} balls, got {w.size}")
        q = np.concatenate([[float(self.x)], s])
        pr = model.pairs()
        # packed balls touch: a rounding of the last bit is no overlap
        slack = 8.0 * np.finfo(float).eps * (abs(q[0]) + max(c.length for c in model.cavities))
        if np.any(q[pr["pa"]] - q[pr["pb"]] - pr["hg"] > slack):
            raise ParameterError("initial.y", "the balls must start in their cavities without overlap")
        return q, np.concatenate([[float(self.v)], w])

