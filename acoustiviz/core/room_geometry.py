"""The shoebox room as a geometry value: the sphere in a rectangular room with absorbing walls.

:class:`Room` is one more :class:`~acoustiviz.core.geometry_base.Geometry`, registered in
:data:`~acoustiviz.core.geometry.GEOMETRIES` as ``"room"``. Its images are the closed-form lattice of
:mod:`acoustiviz.core.room` to the order the outputs need
(:func:`acoustiviz.core.reverberation.energy_order`, :func:`~acoustiviz.core.reverberation.order_for_time`),
so the field evaluator, the renders and the auralisation sum them like any geometry's images.
All lengths in m, times in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

import numpy as np

from .._validate import ParameterError, check_choice, check_points, check_positive, check_range
from ..constants import ROOM_STRIKES
from .geometry_base import Geometry
from .images import ImageSet, ImageSource, Plane, Region
from .room import SURFACES, Shoebox, image_sources, max_order_for_memory

__all__ = ["ROOM_STRIKES", "ROOM_TOLERANCE_DB", "Room"]

_ROOM_ALIASES = {"floor": "z0", "ceiling": "z1"}
#: Default neglected-energy tolerance in dB of the room's image order.
ROOM_TOLERANCE_DB = -60.0


def _triple(name: str, value, what: str) -> tuple:
    """``value`` as 3 finite floats (a sequence or an ``"x,y,z"`` string), naming ``name``."""
    given = value
    if isinstance(value, str):
        value = value.split(",")
    try:
        v = tuple(float(x) for x in value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"expected {what}, got {given!r}") from None
    if len(v) != 3 or not all(math.isfinite(x) for x in v):
        raise ParameterError(name, f"expected {what}, got {given!r}")
    return v


def _absorption(value) -> tuple:
    """One value or six (x0, x1, y0, y1, z0, z1), as a tuple of 1 or 6 floats.

    Their range, [0, 1), is checked once, by :class:`acoustiviz.core.room.Shoebox`.
    """
    if isinstance(value, str):
        value = value.split(",")
    vals = (value,) if isinstance(value, (int, float, np.floating, np.integer)) else tuple(value)
    try:
        vals = tuple(float(x) for x in vals)
    except (TypeError, ValueError):
        raise ParameterError("absorption", f"expected one value or six (x0, x1, y0, y1, z0, z1) in [0, 1), "
                                           f"got {value!r}") from None
    if len(vals) not in (1, 6):
        raise ParameterError("absorption", f"expected one value or six (x0, x1, y0, y1, z0, z1) in [0, 1), "
                                           f"got {len(vals)}")
    return vals


@dataclass(frozen=True)
class Room(Geometry):
    """The sphere in a rectangular (shoebox) room with absorbing walls, and its image sources.

    Parameters
    ----------
    radius : float
        Sphere radius a in m.
    dimensions : (3,) tuple of float
        ``(Lx, Ly, Lz)`` in m; the room is ``[0, Lx] x [0, Ly] x [0, Lz]``, the floor ``z = 0``.
    absorption : float or (6,) tuple of float
        Energy absorption coefficient alpha in ``[0, 1)`` of every surface, or of each in the
        order x0, x1, y0, y1, z0 (floor), z1 (ceiling); the pressure reflection coefficient is
        ``sqrt(1 - alpha)`` (:class:`acoustiviz.core.room.Shoebox`).
    source : (3,) tuple of float, optional
        Centre of the sphere in m, at least ``radius`` from every surface (default: the middle
        of the floor, ``(Lx/2, Ly/2, a)``).
    strike : str
        The struck surface: ``"floor"`` (default, acceleration ``+z``), ``"ceiling"`` or any of
        x0, x1, y0, y1, z0, z1; the acceleration is that surface's inward normal (the rebound).
    order : int, optional
        Image order N; by default chosen from ``tolerance_db`` and ``duration``.
    tolerance_db : float
        Largest energy of the images left out relative to the total, in dB, in ``[-200, 0)``
        (default -60; :func:`acoustiviz.core.reverberation.energy_order`).
    duration : float, optional
        Length in s of the window the outputs cover from the start of contact: images that cannot
        arrive within it are left out (:func:`acoustiviz.core.reverberation.order_for_time`).
        Required when a surface is rigid and ``order`` is not given.
    sound_speed : float, optional
        Speed of sound in m/s that sets the arrival times (default the air's, 343.2 m/s).
    max_memory_mb : float, optional
        Memory budget in MB that caps the image order (default
        :data:`acoustiviz.constants.MAX_MEMORY_MB`; :func:`acoustiviz.core.room.max_order_for_memory`).

    Notes
    -----
    Images in closed form (Allen and Berkley 1979, :func:`acoustiviz.core.room.image_sources`):
    every image of order <= N with its position, mirrored acceleration axis, reflection weight
    (the product of ``sqrt(1 - alpha)`` of the surfaces it was reflected in) and order. The order
    is the smallest that leaves out at most ``tolerance_db`` of the energy within ``duration``,
    capped by the memory budget (:func:`acoustiviz.core.room.max_order_for_memory`; the settings
    then record ``capped``). The listener region is the inside of the room outside the sphere.

    Examples
    --------
    >>> g = Room(0.01905, (6.0, 4.0, 3.0), 0.1, (2.0, 1.5, 0.01905), duration=0.01)
    >>> g.image_order, g.image_count, g.neglected_energy_db
    (4, 129, -inf)
    """

    radius: float
    dimensions: tuple = (6.0, 4.0, 3.0)
    absorption: float | tuple = 0.0
    source: tuple | None = None
    strike: str = "floor"
    order: int | None = None
    tolerance_db: float = ROOM_TOLERANCE_DB
    duration: float | None = None
    sound_speed: float | None = None
    max_memory_mb: float | None = None

    name: ClassVar[str] = "room"
    SETTINGS: ClassVar[tuple] = ("dimensions", "absorption", "source", "strike", "order", "tolerance_db",
                                 "duration", "sound_speed")
    REQUIRED: ClassVar[tuple] = ("dimensions",)
    enclosed: ClassVar[bool] = True

    def __post_init__(self):
        super().__post_init__()
        a = self.radius
        dims = _triple("dimensions", self.dimensions, "three lengths Lx,Ly,Lz in m")
        for ax, v in zip("xyz", dims, strict=True):
            if not v > 0:
                raise ParameterError("dimensions", f"L{ax} must be > 0 m, got {v:g} m")
            if v < 2 * a:
                raise ParameterError("dimensions", f"L{ax} = {v:g} m is smaller than the sphere's diameter "
                                                   f"{2 * a:g} m")
        object.__setattr__(self, "dimensions", dims)
        object.__setattr__(self, "absorption", _absorption(self.absorption))
        self.shoebox  # noqa: B018 - the coefficients in [0, 1), checked by the room itself
        strike = check_choice("strike", self.strike, ROOM_STRIKES)
        object.__setattr__(self, "strike", strike)
        src = (dims[0] / 2, dims[1] / 2, a) if self.source is None else _triple(
            "source", self.source, "the sphere's centre x,y,z in m")
        tol = 1e-12 * max(dims)
        for i, ax in enumerate("xyz"):
            lo, hi = a, dims[i] - a
            if not (lo - tol <= src[i] <= hi + tol):
                raise ParameterError("source", f"{ax} must lie in [{lo:g}, {hi:g}] m (the sphere of radius {a:g} m "
                                               f"inside the room), got {src[i]:g} m")
        object.__setattr__(self, "source", src)
        if self.order is not None:
            if isinstance(self.order, bool) or int(self.order) != self.order or self.order < 0:
                raise ParameterError("order", f"must be an integer >= 0, got {self.order!r}")
            object.__setattr__(self, "order", int(self.order))
        object.__setattr__(self, "tolerance_db", check_range("tolerance_db", self.tolerance_db, -200.0, 0.0,
                                                             unit="dB", high_open=True))
        if self.duration is not None:
            object.__setattr__(self, "duration", check_positive("duration", self.duration, "s"))
        if self.sound_speed is not None:
            object.__setattr__(self, "sound_speed", check_positive("sound_speed", self.sound_speed, "m/s"))
        if self.order is None and self.duration is None and min(self.absorption) == 0.0:
            i = self.absorption.index(0.0) if len(self.absorption) == 6 else 0
            raise ParameterError("duration", f"required: surface {SURFACES[i]} is rigid (alpha = 0), so the whole "
                                             "image sum has no finite energy; give the window's length in s "
                                             "or an image order")
        self._chosen  # noqa: B018 - the order fits the memory budget or is capped, before any work

    # -- the room ------------------------------------------------------------------------
    @cached_property
    def shoebox(self) -> Shoebox:
        """The room and its absorption (:class:`acoustiviz.core.room.Shoebox`)."""
        return Shoebox(self.dimensions, self.absorption[0] if len(self.absorption) == 1 else self.absorption)

    @property
    def c(self) -> float:
        """Speed of sound in m/s of the arrival times."""
        return 343.2 if self.sound_speed is None else float(self.sound_speed)

    @property
    def direction(self) -> np.ndarray:
        """Unit acceleration of the real sphere: the struck surface's inward normal."""
        i = SURFACES.index(_ROOM_ALIASES.get(self.strike, self.strike))
        d = np.zeros(3)
        d[i // 2] = 1.0 if i % 2 == 0 else -1.0
        return d

    @cached_property
    def planes(self) -> tuple:
        """The six surfaces x0, x1, y0, y1, z0 (floor), z1, normals into the room, reflection ``sqrt(1 - alpha)``."""
        beta = self.shoebox.reflection
        out = []
        for i, label in enumerate(SURFACES):
            ax, far = i // 2, i % 2
            point = np.zeros(3)
            normal = np.zeros(3)
            point[ax] = self.dimensions[ax] if far else 0.0
            normal[ax] = -1.0 if far else 1.0
            out.append(Plane(point, normal, "floor" if label == "z0" else label, float(beta[i])))
        return tuple(out)

    @cached_property
    def real(self) -> ImageSource:
        """The sphere at ``source`` accelerating along the struck surface's inward normal."""
        return ImageSource(np.array(self.source), self.direction, 0, "real")

    # -- the order -----------------------------------------------------------------------
    @cached_property
    def _chosen(self):
        from .medium import Medium
        from .reverberation import ImageOrder, energy_order, order_for_time
        from .room import image_count

        room, a = self.shoebox, self.radius
        medium = Medium(c=self.c, rho=1.204)
        cap = max_order_for_memory() if self.max_memory_mb is None else max_order_for_memory(self.max_memory_mb)
        if self.order is not None:
            if self.order > cap:
                raise ParameterError("order", f"must lie in [0, {cap}] (the memory budget), got {self.order}")
            reach = None if self.duration is None else order_for_time(room, self.duration, radius=a, medium=medium)
            neglected = -math.inf if reach is not None and self.order >= reach else math.nan
            if math.isnan(neglected) and (self.duration is not None or min(self.absorption) > 0):
                probe = energy_order(room, -200.0, radius=a, medium=medium, duration=self.duration,
                                     max_order=self.order)
                neglected = probe.neglected_db
            return ImageOrder(self.order, image_count(self.order), neglected, self.tolerance_db, False)
        return energy_order(room, self.tolerance_db, radius=a, medium=medium, duration=self.duration,
                            max_order=cap)

    @property
    def image_order(self) -> int:
        """Largest image order kept."""
        return int(self._chosen.order)

    @property
    def image_count(self) -> int:
        """Number of image sources, the real sphere included: ``(4 N^3 + 6 N^2 + 8 N + 3) / 3``."""
        return int(self._chosen.images)

    @property
    def neglected_energy_db(self) -> float:
        """Bound in dB of the energy of the images left out relative to the total (``-inf``: none can arrive)."""
        return float(self._chosen.neglected_db)

    @property
    def order_capped(self) -> bool:
        """True when the memory budget cut the order before the tolerance was met."""
        return bool(self._chosen.capped)

    # -- images --------------------------------------------------------------------------
    def room_images(self, real: ImageSource | None = None):
        """Images of ``real`` (default: the sphere) to :attr:`image_order` (a :class:`~.room.RoomImages`)."""
        real = self.real if real is None else real
        return image_sources(self.shoebox, real.position, self.image_order, radius=self.radius,
                             direction=real.axis)

    def image_sources(self, real: ImageSource) -> ImageSet:
        """``real`` and its images in the room's six surfaces, as an :class:`ImageSet` (sorted by order).

        The sets of the last two spheres asked for are kept (the struck and the far wall of a
        damper's cavity are asked for again by each stage of a WAV).
        """
        key = (real.position.tobytes(), real.axis.tobytes(), real.weight)
        cache = self.__dict__.setdefault("_image_cache", {})
        if key not in cache:
            made = self._moved(real, cache.values())
            if made is None:
                im = self.room_images(real)
                w = im.weights if real.weight == 1.0 else im.weights * real.weight
                made = ImageSet(im.positions, im.directions, w, im.orders, ("",) * len(im))
            if len(cache) >= 2:
                cache.pop(next(iter(cache)))
            cache[key] = made
        return cache[key]

    @staticmethod
    def _moved(real: ImageSource, known) -> ImageSet | None:
        """The images of ``real`` from those of a sphere moved along its own axis (a cavity's far wall), or None.

        Every image is the real sphere under a fixed mirror map M (a product of reflections), so
        moving the sphere by ``g u`` along its axis ``u`` moves image j by ``g M u = g d_j``, its own
        acceleration direction; reversing the axis reverses every ``d_j``; the weights do not change.
        """
        for s in known:
            u, shift = s.axes[0], real.position - s.positions[0]
            g = float(shift @ u)
            sign = float(real.axis @ u)
            if abs(abs(sign) - 1.0) > 1e-12 or np.linalg.norm(shift - g * u) > 1e-12 * max(1.0, abs(g)) \
                    or real.weight != s.weights[0]:
                continue
            return ImageSet(s.positions + g * s.axes, sign * s.axes, s.weights, s.orders, s.labels)
        return None

    @cached_property
    def sources(self) -> ImageSet:
        """The real sphere first, then its images (an :class:`ImageSet`; iterate with ``.sources()``)."""
        return self.image_sources(self.real)

    @cached_property
    def _image_set(self) -> ImageSet:
        return self.sources

    # -- regions and labels --------------------------------------------------------------
    @property
    def contact_coordinate(self) -> tuple:
        """``(axis, value)``: the coordinate (0, 1, 2 for x, y, z) and its value in m touching the struck surface.

        The sphere's centre is then one radius from that surface (``(2, a)`` for the floor).
        """
        i = SURFACES.index(_ROOM_ALIASES.get(self.strike, self.strike))
        ax = i // 2
        return ax, (self.radius if i % 2 == 0 else self.dimensions[ax] - self.radius)

    @property
    def touches_struck_surface(self) -> bool:
        """True when the sphere touches the surface it strikes (its centre one radius from it)."""
        ax, value = self.contact_coordinate
        return abs(self.source[ax] - value) <= 1e-9 * max(self.radius, 1.0)

    @property
    def polar_limit_deg(self) -> float:
        """90 degrees for a sphere on the struck surface (the fluid in front of it), else 180."""
        return 90.0 if self.touches_struck_surface else 180.0

    def view_region(self):
        """The balloon's directions: the half space in front of the struck surface, or the whole sphere.

        The half space around the contact point for a sphere on the struck surface; the whole sphere
        around its centre for a sphere away from it.
        """
        side = np.array([1.0, 0.0, 0.0]) if abs(self.axis[0]) < 0.5 else np.array([0.0, 0.0, 1.0])
        if not self.touches_struck_surface:
            return Region("sphere", self.centre, self.axis, side)
        return Region("half", self.contact_point, self.axis, side)

    def enclosure(self):
        """Refused: the room's surfaces close the fluid, so no surface in it encloses a radiated energy."""
        raise ParameterError("config", "the radiated energy is not defined in a room: its walls close the fluid "
                                       "and return the sound, so no surface around the sphere encloses the "
                                       "energy radiated away (defined in free field, above a plane and in a "
                                       "wall-floor corner)")

    @property
    def feature_distance(self) -> float:
        """Distance in m from the sphere's centre to the farthest corner of the room (views frame the room)."""
        c = np.asarray(self.source)
        far = np.maximum(c, np.asarray(self.dimensions) - c)
        return float(np.linalg.norm(far))

    def caption(self, *, long: bool = False) -> str:  # noqa: D102 - see Geometry.caption
        lx, ly, lz = self.dimensions
        ab = self.absorption
        alpha = f"alpha {ab[0]:g}" if len(ab) == 1 else "alpha " + "/".join(f"{x:g}" for x in ab)
        room = f"{lx:g} x {ly:g} x {lz:g} m"
        if long:
            return f"{self.name} ({room}, {alpha}, image order {self.image_order}, {self.image_count} images)"
        return f"{self.name} {room}, {alpha}"

    def settings(self) -> dict:
        """Room, absorption, sphere, strike and the chosen image order with its neglected-energy bound."""
        neg = self.neglected_energy_db
        return {"dimensions_m": list(self.dimensions), "absorption": list(self.absorption),
                "source_m": list(self.source), "strike": self.strike, "image_order": self.image_order,
                "images": self.image_count,
                "neglected_energy_db": None if math.isnan(neg) else (neg if math.isfinite(neg) else "-inf"),
                "order_capped": self.order_capped, "tolerance_db": self.tolerance_db,
                "window_s": self.duration}

    @classmethod
    def from_settings(cls, radius: float, *, dimensions=None, absorption=None, source=None, strike="floor",
                      order=None, tolerance_db=None, duration=None, sound_speed=None, max_memory_mb=None,
                      **others) -> Room:
        """Build from a front-end's settings (the one validation of the command line and the scenes).

        ``dimensions`` is required; ``absorption`` defaults to 0 (rigid), ``tolerance_db`` to -60.
        """
        cls._refuse(others)
        a = check_positive("radius", radius, "m")
        if dimensions is None:
            raise ParameterError("dimensions", "required for a room: three lengths Lx,Ly,Lz in m")
        return cls(a, dimensions, 0.0 if absorption is None else absorption, source,
                   "floor" if strike is None else strike, order,
                   ROOM_TOLERANCE_DB if tolerance_db is None else tolerance_db, duration, sound_speed, max_memory_mb)

    @classmethod
    def relevant(cls, settings) -> dict:
        """The room's own settings among ``settings`` (those given)."""
        return {k: settings[k] for k in cls.SETTINGS if settings.get(k) is not None}

    def in_room(self, name: str, points) -> np.ndarray:
        """The ``(n, 3)`` points (m) if they lie in the room outside the sphere, else an error naming ``name``."""
        pts = check_points(name, points)
        ok = self.in_fluid(pts)
        if not np.all(ok):
            p = pts[int(np.flatnonzero(~ok)[0])]
            where = f"({p[0]:g}, {p[1]:g}, {p[2]:g}) m"
            lx, ly, lz = self.dimensions
            if np.linalg.norm(p - self.centre) < self.radius:
                raise ParameterError(name, f"{where} is inside the sphere (radius {self.radius:g} m at "
                                           f"{tuple(round(x, 6) for x in self.source)} m)")
            raise ParameterError(name, f"{where} is outside the room [0, {lx:g}] x [0, {ly:g}] x [0, {lz:g}] m")
        return pts
