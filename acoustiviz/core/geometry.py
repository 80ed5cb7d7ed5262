"""Geometry as a value: the sphere, the rigid surfaces around it, its image sources and its fluid.

A geometry is a frozen value built from a registry name and its settings. It knows its
reflecting surfaces and yields everything the rest of the package used to derive from a
configuration's name:

* its **image sources** (:meth:`Geometry.images`: positions, mirrored acceleration axes,
  reflection weights and orders, as arrays the field evaluator sums), also of a sphere moved
  elsewhere in it (:meth:`Geometry.image_sources`, the damper cavity's far wall);
* the **region a listener may occupy** (:meth:`Geometry.in_fluid`, :meth:`Geometry.sphere_distance`),
  the directions a polar pattern may cover (:attr:`Geometry.polar_limit_deg`) and the floor
  that bounds a horizontal map (:attr:`Geometry.floor_height`);
* the **solid-angle regions** of its closing grid (:meth:`Geometry.enclosure`) and of its
  directivity balloon (:meth:`Geometry.view_region`), and the size views should frame
  (:attr:`Geometry.feature_distance`);
* its **labels** (:meth:`Geometry.caption`) and the settings a sidecar records (:meth:`Geometry.settings`);
* what it is, for the layers above: :attr:`Geometry.enclosed` (a room), :attr:`Geometry.reflecting`.

:data:`GEOMETRIES` maps the names of scenes and of the command line (``--config``, ``[configuration]
kind``) to the classes; :func:`geometry` builds one from a name and its settings with the front-ends'
rules. A new geometry is one class here and one registry entry: nothing outside this module
compares a geometry's name (``tests/test_architecture.py`` checks it).

Frame (all lengths in m): the struck surface is the plane ``z = 0`` and the fluid is ``z > 0``;
the sphere's centre is at ``(0, 0, a)`` and its acceleration (the rebound from the surface) points
along ``+z``, except for a wall strike in the corner (:class:`WallFloorCorner`). This module knows
nothing of acoustics, grids or files.

Examples
--------
>>> g = geometry("wall-floor", 0.01905, wall_distance=0.05)
>>> type(g).__name__, len(g.images()), g.images().orders.tolist()
('WallFloorCorner', 4, [0, 1, 1, 2])
>>> g.enclosure().kind, [round(float(x), 3) for x in g.enclosure().origin]
('quarter', [-0.05, 0.0, 0.0])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

import numpy as np

from .._validate import ParameterError, check_choice, check_positive, check_range
from ..constants import CONFIGURATIONS, DEFAULT_WALL_DISTANCE, STRIKES
from .geometry_base import Configuration, Geometry
from .images import ImageSource, Plane, Region
from .room_geometry import Room

__all__ = [
    "CONFIGURATIONS",
    "GEOMETRIES",
    "Configuration",
    "FreeField",
    "Geometry",
    "ReflectingPlane",
    "Region",
    "WallFloorCorner",
    "geometry",
    "geometry_class",
    "relevant_settings",
    "images_free",
    "images_plane",
    "images_wall_floor",
    "observer_points",
]

@dataclass(frozen=True)
class FreeField(Geometry):
    """The sphere alone in free field: centre ``(0, 0, a)``, acceleration ``+z``.

    Examples
    --------
    >>> len(FreeField(0.01).images()), FreeField(0.01).polar_limit_deg
    (1, 180.0)
    """

    radius: float

    name: ClassVar[str] = "free"
    polar_limit_deg: ClassVar[float] = 180.0
    reflecting: ClassVar[bool] = False

    @cached_property
    def planes(self) -> tuple:
        """No reflecting planes."""
        return ()

    @cached_property
    def real(self) -> ImageSource:
        """The sphere: centre ``(0, 0, a)``, axis ``+z``."""
        return ImageSource(np.array([0.0, 0.0, self.radius]), np.array([0.0, 0.0, 1.0]), 0, "real")


@dataclass(frozen=True)
class ReflectingPlane(Geometry):
    """The sphere touching the rigid plane ``z = 0`` and its image (paper eq 14, Figure 1).

    Sources: the real sphere at ``(0, 0, a)`` with axis ``+z`` and its image at ``(0, 0, -a)``
    with the mirrored axis ``-z``. One plane, ``z = 0``, normal ``+z``. With the mirrored axis
    the image adds with a plus sign; taking its polar angle from the real axis instead flips the
    sign of ``cos θ2`` and gives the paper's eq 14, ``p(r1, θ1, t1) - p(r2, θ2, t2)``.
    """

    radius: float

    name: ClassVar[str] = "plane"

    @cached_property
    def planes(self) -> tuple:
        """The floor ``z = 0``, normal ``+z``."""
        return (Plane(np.zeros(3), np.array([0.0, 0.0, 1.0]), "floor"),)

    @cached_property
    def real(self) -> ImageSource:
        """The sphere: centre ``(0, 0, a)``, axis ``+z``."""
        return ImageSource(np.array([0.0, 0.0, self.radius]), np.array([0.0, 0.0, 1.0]), 0, "real")


@dataclass(frozen=True)
class WallFloorCorner(Geometry):
    """The sphere in a wall-floor corner (two perpendicular rigid planes) and its 3 images.

    Parameters
    ----------
    radius : float
        Sphere radius a in m.
    wall_distance : float
        Horizontal distance in m from the sphere's centre to the wall ``x = -wall_distance``;
        ``>= radius``. With ``strike="wall"`` the sphere touches the wall, so it must equal
        the radius (``None`` means the radius).
    strike : {"floor", "wall"}
        Which surface the sphere strikes. ``"floor"``: centre ``(0, 0, a)``, acceleration
        ``+z``. ``"wall"``: centre ``(0, 0, height)``, acceleration ``+x`` (away from the wall).
    height : float, optional
        With ``strike="wall"`` only: height in m of the sphere's centre above the floor,
        ``>= radius`` (default the radius: the ball touches the wall and the floor).

    Notes
    -----
    Four sources: the real sphere, its images in the floor and in the wall (order 1) and the
    image in both (order 2). Planes: floor ``z = 0`` (normal ``+z``) and wall
    ``x = -wall_distance`` (normal ``+x``). Two perpendicular planes make a closed group of
    three images, so the method of images is exact here (Allen and Berkley's construction for a
    rectangular room, restricted to one corner).
    """

    radius: float
    wall_distance: float | None = None
    strike: str = "floor"
    height: float | None = None

    name: ClassVar[str] = "wall-floor"
    SETTINGS: ClassVar[tuple] = ("wall_distance", "strike", "height")

    def __post_init__(self):
        super().__post_init__()
        a = self.radius
        check_choice("strike", self.strike, STRIKES)
        if self.strike == "floor":
            if self.wall_distance is None:
                raise ParameterError(
                    "wall_distance", "required for the wall-floor corner (distance in m >= radius)")
            w = check_positive("wall_distance", self.wall_distance, "m")
            if w < a * (1 - 1e-12):
                raise ParameterError(
                    "wall_distance", f"must be >= radius = {a:g} m (sphere inside the wall), got {w:g} m")
            if self.height is not None and abs(float(self.height) - a) > 1e-12 * a:
                raise ParameterError(
                    "height", "only used with strike='wall'; a floor strike has its centre at z = radius")
            h = None
        else:
            w = a if self.wall_distance is None else check_positive("wall_distance", self.wall_distance, "m")
            if abs(w - a) > 1e-9 * a:
                raise ParameterError(
                    "wall_distance", f"a sphere striking the wall touches it: must equal radius = {a:g} m")
            h = a if self.height is None else check_positive("height", self.height, "m")
            if h < a * (1 - 1e-12):
                raise ParameterError("height", f"must be >= radius = {a:g} m (sphere inside the floor), got {h:g} m")
        object.__setattr__(self, "wall_distance", w)
        object.__setattr__(self, "height", h)

    @cached_property
    def planes(self) -> tuple:
        """The floor ``z = 0`` (normal ``+z``) and the wall ``x = -wall_distance`` (normal ``+x``)."""
        return (Plane(np.zeros(3), np.array([0.0, 0.0, 1.0]), "floor"),
                Plane(np.array([-self.wall_distance, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), "wall"))

    @cached_property
    def real(self) -> ImageSource:
        """The sphere: on the floor with axis ``+z``, or against the wall with axis ``+x``."""
        if self.strike == "floor":
            return ImageSource(np.array([0.0, 0.0, self.radius]), np.array([0.0, 0.0, 1.0]), 0, "real")
        return ImageSource(np.array([0.0, 0.0, self.height]), np.array([1.0, 0.0, 0.0]), 0, "real")

    @property
    def feature_distance(self) -> float:
        """Distance in m from the sphere's centre to the wall."""
        return float(self.wall_distance)

    def caption(self, *, long: bool = False) -> str:  # noqa: D102 - see Geometry.caption
        mm = f"{self.wall_distance * 1e3:.3g} mm"
        return f"{self.name} (wall {mm} from the centre)" if long else f"{self.name}, wall at {mm}"

    def settings(self) -> dict:
        """``wall_distance_m``, ``strike`` and ``height_m`` (None for a floor strike)."""
        return {"wall_distance_m": self.wall_distance, "strike": self.strike, "height_m": self.height}

    @classmethod
    def from_settings(cls, radius: float, *, wall_distance=None, strike: str = "floor", height=None,
                      **others) -> WallFloorCorner:
        """The front-ends' rule: a floor strike puts the wall ``wall_distance`` m from the centre.

        The default is :data:`~acoustiviz.constants.DEFAULT_WALL_DISTANCE`, at least the radius;
        a wall strike puts the sphere against the wall (no ``wall_distance``) at ``height`` m
        above the floor (default: the radius).
        """
        cls._refuse(others)
        a = check_positive("radius", radius, "m")
        check_choice("strike", strike, STRIKES)
        if height is not None and strike != "wall":
            raise ParameterError("height", "only applies to a wall strike")
        if strike == "wall":
            if wall_distance is not None:
                raise ParameterError("wall_distance", "a wall strike puts the sphere against the wall; omit it")
            h = a if height is None else check_range("height", height, a, math.inf, unit="m")
            return cls(a, a, "wall", h)
        wall = DEFAULT_WALL_DISTANCE if wall_distance is None else wall_distance
        if math.isfinite(float(wall)) and wall < a:
            raise ParameterError("wall_distance", f"the sphere would cut the wall: must be >= radius = {a:g} m, "
                                                  f"got {wall:g} m")
        return cls(a, check_range("wall_distance", wall, a, math.inf, unit="m"), "floor")

    @classmethod
    def relevant(cls, settings) -> dict:
        """The strike, and the wall distance (floor strike) or the height (wall strike)."""
        strike = settings.get("strike", "floor")
        out = {"strike": strike}
        key = "wall_distance" if strike == "floor" else "height"
        if settings.get(key) is not None:
            out[key] = settings[key]
        return out


#: The registry: scene and command-line names -> geometry classes. The ``--config`` choices,
#: :data:`~acoustiviz.constants.CONFIGURATIONS`, are those built from a radius alone; the room
#: (:mod:`acoustiviz.core.room_geometry`, ``--room``, a scene's ``kind = "room"``) needs its dimensions.
GEOMETRIES = {cls.name: cls for cls in (FreeField, ReflectingPlane, WallFloorCorner, Room)}


def geometry_class(name: str) -> type:
    """The geometry class registered as ``name`` (a ParameterError naming ``config`` otherwise)."""
    return GEOMETRIES[check_choice("config", name, tuple(GEOMETRIES))]


def relevant_settings(name: str, **settings) -> dict:
    """The subset of ``settings`` (e.g. a scene's whole table) that applies to geometry ``name``."""
    return geometry_class(name).relevant(settings)


def geometry(name: str, radius: float, *, lenient: bool = False, **settings) -> Geometry:
    """Build a geometry from its registry name and the settings of a front-end.

    Parameters
    ----------
    name : {"free", "plane", "wall-floor"}
        Registry name (:data:`GEOMETRIES`).
    radius : float
        Sphere radius a in m.
    lenient : bool
        Drop the settings that do not apply to ``name`` (a scene's table, a sweep's settings)
        instead of refusing them.
    **settings
        ``wall_distance`` (m, ``"wall-floor"`` floor strike; default
        :data:`~acoustiviz.constants.DEFAULT_WALL_DISTANCE`), ``strike`` (``"floor"`` or
        ``"wall"``, ``"wall-floor"`` only), ``height`` (m, wall strike only; default the radius).

    Returns
    -------
    Geometry

    Examples
    --------
    >>> geometry("plane", 0.01).sources[1].position.tolist()
    [0.0, 0.0, -0.01]
    >>> geometry("plane", 0.01, lenient=True, wall_distance=0.2).name
    'plane'
    """
    cls = geometry_class(name)
    if lenient:
        settings = cls.relevant(settings)
    return cls.from_settings(radius, **settings)


def images_free(radius: float) -> FreeField:
    """The sphere alone in free field (:class:`FreeField`).

    Examples
    --------
    >>> len(images_free(0.01905).images()), images_free(0.01905).polar_limit_deg  # one source, all around
    (1, 180.0)
    """
    return FreeField(radius)


def images_plane(radius: float) -> ReflectingPlane:
    """The sphere touching the rigid plane ``z = 0`` and its image (:class:`ReflectingPlane`).

    Examples
    --------
    The image sits below the plane and accelerates the other way (paper eq 14, Figure 1):

    >>> [(float(s.position[2]), float(s.axis[2])) for s in images_plane(0.01).sources]
    [(0.01, 1.0), (-0.01, -1.0)]
    """
    return ReflectingPlane(radius)


def images_wall_floor(radius: float, wall_distance=None, *, strike: str = "floor", height=None) -> WallFloorCorner:
    """The sphere in a wall-floor corner and its 3 images (:class:`WallFloorCorner`).

    Examples
    --------
    Floor strike 5 cm from the wall: the sphere, its images in floor and wall, and in both:

    >>> s = images_wall_floor(0.01905, 0.05).images()
    >>> len(s), s.orders.tolist(), np.round(s.positions[:, 0], 3).tolist()  # x in m
    (4, [0, 1, 1, 2], [0.0, 0.0, -0.1, -0.1])
    """
    return WallFloorCorner(radius, wall_distance, strike, height)


def observer_points(geometry: Geometry, distance, angles) -> np.ndarray:
    """Observers at ``distance`` (m) and ``angles`` (rad) from the axis (:meth:`Geometry.observer_points`)."""
    return geometry.observer_points(distance, angles)
