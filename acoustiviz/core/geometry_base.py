"""The base of every geometry value: a rigid sphere, the rigid surfaces around it and its images.

:class:`Geometry` holds what every geometry knows (its image sources, the region a listener may
occupy, the regions of its closing grid and balloon, its labels and settings);
:class:`Configuration` is a geometry given by explicit sources and planes. The named geometries
and their registry are in :mod:`acoustiviz.core.geometry` (the paper's three) and
:mod:`acoustiviz.core.room_geometry` (the shoebox room). All lengths in m.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np

from .._validate import ParameterError, check_choice, check_points, check_positive
from ..constants import STRIKES
from .images import ImageSet, ImageSource, Region, images_of

__all__ = ["Configuration", "Geometry"]

_X = np.array([1.0, 0.0, 0.0])
_Z = np.array([0.0, 0.0, 1.0])
#: Settings of the registry's geometries and the value each takes when it does not apply.
_NEUTRAL = {"wall_distance": None, "strike": "floor", "height": None, "dimensions": None, "absorption": None,
            "source": None, "order": None, "tolerance_db": None, "duration": None, "sound_speed": None}


class Geometry:
    """A rigid sphere of radius a and the rigid surfaces around it (base of every geometry).

    Subclasses are frozen dataclasses with a ``radius`` field (m, the same for every image); they
    provide ``planes`` (the reflecting planes, normals into the fluid) and ``real`` (the real
    sphere, an :class:`ImageSource` of order 0), and may override :meth:`image_sources` (default:
    the images in at most two perpendicular planes), :meth:`enclosure`, :meth:`view_region`,
    :attr:`feature_distance`, :meth:`caption` and :meth:`settings`.
    """

    #: Registry name (the scene's ``kind`` and the command line's ``--config``).
    name: ClassVar[str] = "custom"
    #: Settings :func:`geometry` accepts for this class (beyond the radius).
    SETTINGS: ClassVar[tuple] = ()
    #: Settings without a default (a room's dimensions): such a geometry is not a plain ``--config`` choice.
    REQUIRED: ClassVar[tuple] = ()
    #: Largest polar angle in degrees from the acceleration axis a listener may take in the
    #: paper's observer plane (the fluid above the struck surface: 90; all around: 180).
    polar_limit_deg: ClassVar[float] = 90.0
    #: True when the surfaces close the fluid (a room): no radiated energy or sound power (:meth:`enclosure`).
    enclosed: ClassVar[bool] = False
    #: False for the free field alone: no surface of its own, so it may stand for "no surroundings".
    reflecting: ClassVar[bool] = True

    def __post_init__(self):
        object.__setattr__(self, "radius", check_positive("radius", self.radius, "m"))

    # -- images --------------------------------------------------------------------------
    def image_sources(self, real: ImageSource) -> tuple:
        """``real`` (an :class:`ImageSource` of order 0 in the fluid) and its images (tuple of :class:`ImageSource`).

        ``real`` first, then its images in this geometry's surfaces with their mirrored axes,
        reflection weights and orders.
        """
        return images_of(real, self.planes)

    @cached_property
    def sources(self) -> tuple:
        """The real sphere first, then its images (tuple of :class:`ImageSource`)."""
        return self.image_sources(self.real)

    def images(self) -> ImageSet:
        """The real sphere and its images as arrays (:class:`ImageSet`): what the field evaluator sums."""
        return self._image_set

    @cached_property
    def _image_set(self) -> ImageSet:
        return ImageSet.of(self.sources)

    @property
    def centre(self) -> np.ndarray:
        """Centre of the real sphere in m."""
        return self.real.position

    @property
    def axis(self) -> np.ndarray:
        """Acceleration axis of the real sphere (unit vector)."""
        return self.real.axis

    @property
    def contact_point(self) -> np.ndarray:
        """Point in m where the sphere touches the struck surface."""
        return self.centre - self.radius * self.axis

    # -- the fluid -----------------------------------------------------------------------
    def in_fluid(self, points) -> np.ndarray:
        """Boolean mask of the ``(n, 3)`` points (m) outside the sphere and on the fluid side.

        Points on a plane or on the sphere's surface count as in the fluid (a relative
        tolerance of 1e-12 of the radius absorbs round-off).
        """
        pts = check_points("points", points)
        tol = 1e-12 * self.radius
        ok = np.linalg.norm(pts - self.centre, axis=1) >= self.radius - tol
        for pl in self.planes:
            ok &= (pts - pl.point) @ pl.normal >= -tol
        return ok

    def sphere_distance(self, points) -> np.ndarray:
        """Distance in m of ``(n, 3)`` points from the sphere's surface (negative inside it)."""
        pts = check_points("points", points)
        return np.linalg.norm(pts - self.centre, axis=1) - self.radius

    def fluid_text(self) -> str:
        """Where the fluid is, in words (for error messages): e.g. ``"z > 0 m, x > -0.05 m"``."""
        parts = []
        for p in self.planes:
            i = int(np.argmax(np.abs(p.normal)))
            if abs(p.normal[i]) == 1.0:
                parts.append(f"{'xyz'[i]} {'>' if p.normal[i] > 0 else '<'} {p.point[i]:g} m")
            else:
                parts.append(f"(x - {p.point.tolist()}) . {p.normal.tolist()} > 0")
        return ", ".join(parts) or "everywhere outside the sphere"

    @property
    def floor_height(self):
        """Height z in m of a floor bounding the fluid from below, or None without one."""
        for pl in self.planes:
            if pl.normal[2] == 1.0:
                return float(pl.point[2])
        return None

    def observer_points(self, distance, angles) -> np.ndarray:
        """Observers at ``distance`` (m) from the sphere's centre and ``angles`` (rad) from its axis.

        The observers (a ``(k, 3)`` array in m, not checked against the fluid) lie in the plane
        spanned by the acceleration axis and the horizontal direction ``+x`` (for an axis along
        ``x``, the vertical ``+z``): for the wall-floor corner the plane through the centre normal
        to the wall, on the side away from it. The one convention of every command, scene and sweep.
        """
        th = np.atleast_1d(np.asarray(angles, dtype=float))
        r = np.atleast_1d(np.asarray(distance, dtype=float))
        axis = np.asarray(self.axis, dtype=float)
        perp = _X if abs(axis[0]) < 0.5 else _Z
        return np.asarray(self.centre, dtype=float) + r[:, None] * (
            np.cos(th)[:, None] * axis + np.sin(th)[:, None] * perp)

    # -- regions and views ---------------------------------------------------------------
    def enclosure(self) -> Region:
        """The region of directions of a spherical surface that closes the fluid.

        The whole sphere around the sphere's centre without planes; the half space around the
        foot of the centre on one plane; the quarter space around the point of the corner's edge
        nearest the centre for two perpendicular planes. With rigid planes (zero normal velocity)
        such a surface encloses all the radiated energy.
        """
        c, planes = self.centre, self.planes
        if not planes:
            return Region("sphere", c, self.axis, _X)
        if len(planes) == 1:
            (p,) = planes
            return Region("half", c - ((c - p.point) @ p.normal) * p.normal, p.normal, _X)
        if len(planes) == 2:
            p, q = planes
            foot = c - ((c - p.point) @ p.normal) * p.normal - ((c - q.point) @ q.normal) * q.normal
            return Region("quarter", foot, p.normal, q.normal)
        raise ParameterError("config", f"{type(self).__name__} has no enclosing region of directions")

    def view_region(self) -> Region:
        """The region of directions of a directivity balloon: anchored at the contact point."""
        planes = self.planes
        if not planes:
            return Region("sphere", self.centre, self.axis, _X)
        if len(planes) == 1:
            return Region("half", self.contact_point, planes[0].normal, _X)
        if len(planes) == 2:
            return Region("quarter", self.contact_point, planes[0].normal, planes[1].normal)
        raise ParameterError("config", f"{type(self).__name__} has no balloon region")

    @property
    def feature_distance(self) -> float:
        """Distance in m from the sphere's centre to a side surface a view should frame (0: none)."""
        return 0.0

    def caption(self, *, long: bool = False) -> str:
        """A label for titles: the registry name and what sets the geometry apart.

        Parameters
        ----------
        long : bool
            The wording of a figure's annotation instead of a plot's short label.
        """
        return self.name

    def settings(self) -> dict:
        """The geometry's own settings as JSON-ready values (SI, keys ending in the unit)."""
        return {}

    # -- construction --------------------------------------------------------------------
    @classmethod
    def from_settings(cls, radius: float, **settings) -> Geometry:
        """Build from a front-end's settings (as :func:`geometry`; ``radius`` in m), refusing any that do not apply."""
        cls._refuse(settings)
        return cls(radius)

    @classmethod
    def relevant(cls, settings) -> dict:
        """The subset of ``settings`` (a mapping) that applies to this class (the rest is dropped)."""
        return {}

    @classmethod
    def _refuse(cls, settings, keep=()):
        for k, v in settings.items():
            if k not in _NEUTRAL:
                raise ParameterError(k, f"not a setting of any geometry (known: {', '.join(_NEUTRAL)})")
            if k == "strike" and "strike" not in keep:
                check_choice("strike", v, STRIKES)
            if k not in keep and v != _NEUTRAL[k]:
                owners = [c.name for c in _subclasses(Geometry) if k in c.SETTINGS]
                raise ParameterError(k, f"only applies to the {' and '.join(owners)} configuration")

    def with_sources(self, sources) -> Configuration:
        """The same surfaces radiated by other sources (e.g. the sphere at a cavity's far wall)."""
        return Configuration(self.name, self.radius, tuple(sources), tuple(self.planes),
                             self.settings().get("strike", "floor"))


@dataclass(frozen=True)
class Configuration(Geometry):
    """A geometry given by its sources: a sphere and explicit images in front of rigid planes.

    Parameters
    ----------
    name : str
        A label.
    radius : float
        Sphere radius a in m (the same for every image).
    sources : tuple of ImageSource
        The real sphere first, then its images.
    planes : tuple of Plane
        The rigid planes bounding the fluid.
    strike : str
        Which surface the sphere strikes (``"floor"`` or ``"wall"``).
    """

    name: str = field()
    radius: float
    sources: tuple = field(default_factory=tuple)
    planes: tuple = field(default_factory=tuple)
    strike: str = "floor"

    def __post_init__(self):
        super().__post_init__()
        if not self.sources or self.sources[0].order != 0:
            raise ParameterError("sources", "the real sphere (order 0) must come first")

    @property
    def real(self) -> ImageSource:
        """The real sphere."""
        return self.sources[0]

    @property
    def polar_limit_deg(self) -> float:
        """180 degrees without planes, else 90."""
        return 90.0 if self.planes else 180.0


def _subclasses(cls) -> list:
    """Every subclass of ``cls``, depth first in the order they were defined."""
    out = []
    for sub in cls.__subclasses__():
        out += [sub, *_subclasses(sub)]
    return out
