"""The cavity of a damper and the sources it makes: impact sequences, walls, listeners."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice, check_points, check_positive
from ..constants import PAPER_RADIUS
from ..core.geometry import Geometry, geometry
from ..core.images import ImageSet, ImageSource
from ..core.medium import AIR, Medium
from ..dynamics.sequence import ImpactSequence
from ..field.metrics import spl_db

__all__ = [
    "MASS_MODELS",
    "WALL_MODELS",
    "ImpactSequence",
    "periodic_train",
    "CavityScene",
    "spl",
    "wall_sources",
    "check_listeners",
    "ear_positions",
    "cavity",
]


#: Which mass decelerates in the Hertz contact: the impact mass alone against a fixed wall
#: (the paper, eq 3) or the effective mass m M / (m + M) of the two free bodies.
MASS_MODELS = ("impact", "effective")

#: ``"both"``: impacts on the far wall radiate from the far wall; ``"one"``: all from the struck wall.
WALL_MODELS = ("both", "one")


# --------------------------------------------------------------------------- small helpers
def spl(pressure) -> float:
    """Peak sound pressure level ``20 log10(max|p| / 20 µPa)`` in dB of a signal in Pa (-inf if silent)."""
    return spl_db(float(np.max(np.abs(np.asarray(pressure, dtype=float)), initial=0.0)))


# --------------------------------------------------------------------------- inputs
def periodic_train(times, walls, velocities, period: float, repeats: int) -> ImpactSequence:
    """The impacts of one period repeated ``repeats`` times, each copy ``period`` s after the last.

    Parameters
    ----------
    times : (n,) array_like
        Contact start times in s of the impacts of one period (>= 0).
    walls : (n,) array_like of int
        The wall each strikes, -1 or +1.
    velocities : (n,) array_like
        Their approach speeds in m/s (> 0).
    period : float
        Period of the train in s (a forcing period, or a whole number of them).
    repeats : int
        Number of copies.

    Returns
    -------
    ImpactSequence
        ``repeats * n`` impacts: the ``k``-th copy at ``times + k period``.

    Examples
    --------
    >>> seq = periodic_train([0.01], [-1], [1.2], 0.1, 3)
    >>> [round(float(t), 2) for t in seq.times]
    [0.01, 0.11, 0.21]
    """
    base = np.asarray(times, dtype=float)
    t = np.concatenate([base + k * period for k in range(repeats)]) if base.size else np.empty(0)
    return ImpactSequence(t, np.tile(walls, repeats), np.tile(velocities, repeats))


@dataclass(frozen=True)
class CavityScene:
    """Where the cavity sits and which surfaces reflect.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry or str
        The geometry of the struck wall's surroundings (:mod:`acoustiviz.core.geometry`), or a
        registry name (``"free"``, ``"plane"``, ...) built with its default settings and
        ``radius``. Stored as the geometry value.
    radius : float, optional
        Sphere (impact mass) radius a in m: the geometry's own, or with a name the sphere to
        build it with (default 0.01905).
    gap : float
        Total free travel d of the impact mass in the cavity in m; the far wall lies ``gap + 2a``
        from the struck one.
    struck_wall : {-1, +1}
        The damper wall lying on the geometry's struck surface.
    walls : {"both", "one"}
        ``"both"``: far-wall impacts radiate from the far wall with the reversed axis;
        ``"one"``: every impact is heard as a strike on the struck wall.
    medium : Medium
        The fluid.
    """

    geometry: Geometry | str = "plane"
    radius: float | None = None
    gap: float = 0.04
    struck_wall: int = -1
    walls: str = "both"
    medium: Medium = AIR

    def __post_init__(self):
        if isinstance(self.geometry, Geometry):
            built = self.geometry
            if self.radius is not None and check_positive("radius", self.radius, "m") != built.radius:
                raise ParameterError("radius", f"the geometry's sphere has radius {built.radius:g} m, got "
                                               f"{self.radius:g} m")
        else:  # a registry name: the geometry it names, around the given sphere
            built = geometry(self.geometry, PAPER_RADIUS if self.radius is None else self.radius)
        object.__setattr__(self, "geometry", built)
        object.__setattr__(self, "radius", built.radius)
        check_positive("gap", self.gap, "m")
        if self.struck_wall not in (-1, 1):
            raise ParameterError("struck_wall", f"must be -1 or +1, got {self.struck_wall!r}")
        check_choice("walls", self.walls, WALL_MODELS)
        if not isinstance(self.medium, Medium):
            raise ParameterError("medium", f"expected a Medium, got {type(self.medium).__name__}")

    @property
    def axis(self) -> np.ndarray:
        """Unit normal n of the struck surface (the damper's axis of motion), into the fluid."""
        return np.asarray(self.geometry.axis, dtype=float)

    @property
    def far_centre(self) -> np.ndarray:
        """Centre in m of the sphere when it touches the far wall: ``c0 + gap n``."""
        return np.asarray(self.geometry.centre, dtype=float) + self.gap * self.axis

    def sources(self, wall: int) -> tuple:
        """Image sources radiating an impact on damper wall ``wall`` (-1 or +1); see :func:`wall_sources`."""
        return wall_sources(self, wall)

    def describe(self) -> dict:
        """A JSON-ready description of the scene and of how impacts map to sources."""
        geometry = self.geometry
        far = -self.struck_wall
        out = {
            "config": geometry.name,
            "radius_m": self.radius,
            "gap_m": self.gap,
            "struck_wall": self.struck_wall,
            "walls": self.walls,
            "planes": [{"label": p.label, "point_m": p.point.tolist(), "normal": p.normal.tolist()}
                       for p in geometry.planes],
            "medium": {"c_m_s": self.medium.c, "rho_kg_m3": self.medium.rho},
            "sources": {},
        }
        out.update(geometry.settings())
        for w in (self.struck_wall, far):
            srcs = self.sources(w)
            if isinstance(srcs, ImageSet):  # a room's images: their count and the real sphere, not each one
                out["sources"][f"{w:+d}"] = {"images": len(srcs), "max_order": int(srcs.orders.max()),
                                             "real_position_m": srcs.positions[0].tolist(),
                                             "real_axis": srcs.axes[0].tolist()}
                continue
            out["sources"][f"{w:+d}"] = [
                {"label": s.label, "order": s.order, "position_m": s.position.tolist(), "axis": s.axis.tolist()}
                for s in self.sources(w)
            ]
        return out


def wall_sources(scene: CavityScene, wall: int) -> tuple:
    """Image sources radiating an impact on damper wall ``wall``.

    Parameters
    ----------
    scene : CavityScene
        The scene.
    wall : {-1, +1}
        The damper wall struck.

    Returns
    -------
    tuple of ImageSource, or ImageSet
        For the struck wall (or any wall with ``walls="one"``): the geometry's sources.
        For the far wall: the sphere at ``c0 + gap n`` with axis ``-n``, then its images in the
        geometry's planes (labels prefixed ``"far "``). A geometry whose images come as an
        :class:`~acoustiviz.core.images.ImageSet` (a room's thousands) gives them as one.

    Examples
    --------
    >>> sc = CavityScene("plane", radius=0.01, gap=0.04)
    >>> [(float(s.position[2]), float(s.axis[2])) for s in wall_sources(sc, +1)]
    [(0.05, -1.0), (-0.05, 1.0)]
    """
    if wall not in (-1, 1):
        raise ParameterError("wall", f"must be -1 or +1, got {wall!r}")
    geometry = scene.geometry
    if wall == scene.struck_wall or scene.walls == "one":
        return geometry.sources if isinstance(geometry.sources, ImageSet) else tuple(geometry.sources)
    real = ImageSource(scene.far_centre, -scene.axis, 0, "far")
    imgs = geometry.image_sources(real)
    if isinstance(imgs, ImageSet):
        return imgs
    return tuple(ImageSource(s.position, s.axis, s.order, "far" if s.order == 0 else f"far {s.label}", s.weight)
                 for s in imgs)


def check_listeners(points, scene: CavityScene, *, name: str = "listeners", column=None) -> np.ndarray:
    """Validate listener positions; return them as an ``(n, 3)`` array in m.

    A listener must be in the fluid of the geometry (not below the floor, not behind a
    wall, not inside the sphere) and, with ``walls="both"``, not inside the cavity (within a
    radius of the segment the sphere's centre travels between the two walls). With a column of
    several balls, whatever ``walls``, not inside the column (within the largest ball's radius of the
    segment its balls' centres sweep, :attr:`acoustiviz.dynamics.Cavity.span`).

    Parameters
    ----------
    points : (n, 3) or (3,) array_like
        Positions in m in the geometry's frame.
    scene : CavityScene
        The scene.
    name : str
        Parameter name used in error messages (e.g. ``"--listener"``).
    column : acoustiviz.dynamics.Cavity, optional
        The cavity's balls; with several, the column's extent replaces the one sphere's path.

    Raises
    ------
    ParameterError
        Naming ``name``, the offending position and why it is not allowed.
    """
    pts = check_points(name, points)
    geometry = scene.geometry
    a = scene.radius
    tol = 1e-12 * a
    c0 = np.asarray(geometry.centre, dtype=float)
    if column is not None and column.n_balls > 1:
        _outside_column(pts, scene, column, name)
    for p in pts:
        where = f"({p[0]:g}, {p[1]:g}, {p[2]:g}) m"
        if np.linalg.norm(p - c0) < a - tol:
            raise ParameterError(name, f"listener {where} is inside the sphere (radius {a:g} m)")
        for pl in geometry.planes:
            if (p - pl.point) @ pl.normal < -tol:
                side = "below the floor" if pl.label == "floor" else f"behind the {pl.label}"
                raise ParameterError(name, f"listener {where} is {side} (the fluid is where "
                                           f"(x - {pl.point.tolist()}) . {pl.normal.tolist()} >= 0)")
        if scene.walls == "both":
            n = scene.axis
            s = float(np.clip((p - c0) @ n, 0.0, scene.gap))
            if np.linalg.norm(p - (c0 + s * n)) < a - tol:
                raise ParameterError(name, f"listener {where} is inside the cavity (within {a:g} m of the "
                                           f"sphere's path between the walls)")
    return pts


def _outside_column(pts: np.ndarray, scene: CavityScene, column, name: str) -> None:
    """Refuse a listener within the largest ball's radius of the segment a column's centres sweep."""
    a = float(max(column.radii))
    c0, n = np.asarray(scene.geometry.centre, dtype=float), scene.axis
    for p in pts:
        s = float(np.clip((p - c0) @ n, 0.0, column.span))
        if np.linalg.norm(p - (c0 + s * n)) < a * (1.0 - 1e-12):
            raise ParameterError(name, f"listener ({p[0]:g}, {p[1]:g}, {p[2]:g}) m is inside the column of "
                                       f"{column.n_balls} balls (within {a:g} m of the path of their centres, "
                                       f"{column.span:g} m long from the struck wall's ball)")


def ear_positions(centre, scene: CavityScene, *, spacing: float = 0.18) -> np.ndarray:
    """Two ear (or microphone) positions ``spacing`` m apart, centred on ``centre``, facing the damper.

    The ears lie on the horizontal line (perpendicular to ``+z``) perpendicular to the direction
    from ``centre`` to the struck wall's contact point; the first row is the left ear of a listener
    facing the damper, the second the right ear. No head is modelled (two free-field microphones).

    Parameters
    ----------
    centre : (3,) array_like
        Centre of the head in m.
    scene : CavityScene
        The scene (gives the contact point).
    spacing : float
        Distance between the ears in m (default 0.18).

    Returns
    -------
    (2, 3) ndarray
        Left and right ear positions in m.
    """
    c = check_points("centre", centre)[0]
    d = check_positive("spacing", spacing, "m")
    look = np.asarray(scene.geometry.contact_point, dtype=float) - c
    up = np.array([0.0, 0.0, 1.0])
    side = np.cross(up, look)  # points to the listener's left when facing the damper
    if np.linalg.norm(side) < 1e-12:  # listener straight above: use +y as the left
        side = np.array([0.0, 1.0, 0.0])
    side = side / np.linalg.norm(side)
    return np.stack([c + 0.5 * d * side, c - 0.5 * d * side])


def cavity(kind: str, radius: float, gap: float, *, struck_wall: int = -1, walls: str = "both",
           wall_distance=None, strike: str = "floor", height=None, medium=None, room=None) -> CavityScene:
    """The damper's cavity in its surroundings (:func:`acoustiviz.core.geometry.geometry` builds them).

    ``room``: the settings of a shoebox room (:class:`acoustiviz.core.geometry.Room`), which then
    replaces ``kind`` (the configuration kind) and its settings.
    """
    if room is not None:
        c = {} if medium is None else {"sound_speed": medium.c}
        geom = geometry("room", radius, **{**c, **room})
    else:
        geom = geometry(kind, radius, wall_distance=wall_distance, strike=strike, height=height)
    extra = {} if medium is None else {"medium": medium}
    return CavityScene(geom, gap=gap, struck_wall=struck_wall, walls=walls, **extra)
