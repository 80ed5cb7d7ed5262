"""Image sources for a sphere striking a rigid plane or a wall-floor corner (geometry only).

A rigid plane is accounted for by the method of images (paper eq 14, Figure 1): the sphere
and its mirror image radiate together, and the normal particle velocity vanishes on the plane.
Each image is a sphere of the same radius with its own centre and its own acceleration axis --
the real axis mirrored by every plane that made the image. With these mirrored axes every
image contributes with a **plus** sign and its own polar angle; this is the same sum as the
paper's ``p(r1, θ1, t1) - p(r2, θ2, t2)`` in which both angles are taken from the real axis.

Frame (all lengths in m)
------------------------
* The struck surface is the plane ``z = 0`` and the fluid is ``z > 0``.
* ``"free"`` and ``"plane"``: the sphere's centre is at ``(0, 0, a)`` and its acceleration
  (the rebound from the surface) points along ``+z``.
* ``"wall-floor"``: floor ``z = 0``, wall ``x = -wall_distance``; the fluid is
  ``z > 0, x > -wall_distance``.

  - ``strike="floor"`` (default): the sphere rests on the floor, centre ``(0, 0, a)`` at
    horizontal distance ``wall_distance >= a`` from the wall, acceleration ``+z``.
  - ``strike="wall"``: the sphere touches the wall (so ``wall_distance = a``), its centre at
    ``(0, 0, height)`` with ``height >= a`` (default ``a``: a ball in the corner, touching
    both the wall and the floor), acceleration ``+x``, away from the wall.

This module knows nothing of acoustics: the field evaluator loops over ``sources`` and calls
the free-field radiation model for each.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validate import ParameterError, check_choice, check_points, check_positive

__all__ = [
    "CONFIGURATIONS",
    "ImageSource",
    "Plane",
    "Configuration",
    "images_free",
    "images_plane",
    "images_wall_floor",
    "configuration",
    "mirror_point",
    "mirror_vector",
    "images_of",
    "observer_points",
]

#: Configuration names understood by :func:`configuration`.
CONFIGURATIONS = ("free", "plane", "wall-floor")


def _vec3(name, v) -> np.ndarray:
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ParameterError(name, f"expected 3 finite coordinates, got {v!r}")
    a = a.copy()
    a.setflags(write=False)
    return a


def _unit(name, v) -> np.ndarray:
    a = np.asarray(v, dtype=float).reshape(-1)
    n = float(np.linalg.norm(a)) if a.shape == (3,) else 0.0
    if not n > 0 or not np.isfinite(n):
        raise ParameterError(name, f"expected a non-zero finite 3-vector, got {v!r}")
    return _vec3(name, a / n)


@dataclass(frozen=True)
class ImageSource:
    """One radiating sphere, real (order 0) or an image (order 1 or 2).

    Parameters
    ----------
    position : (3,) array_like
        Centre of the sphere in m.
    axis : (3,) array_like
        Unit direction of its acceleration (normalised here).
    order : int
        Number of reflections that made it: 0 for the real sphere.
    label : str
        A short name, e.g. ``"real"``, ``"floor"``, ``"wall"``, ``"floor+wall"``.
    """

    position: np.ndarray
    axis: np.ndarray
    order: int = 0
    label: str = "real"

    def __post_init__(self):
        object.__setattr__(self, "position", _vec3("position", self.position))
        object.__setattr__(self, "axis", _unit("axis", self.axis))
        if int(self.order) != self.order or self.order < 0:
            raise ParameterError("order", f"must be a non-negative integer, got {self.order!r}")


@dataclass(frozen=True)
class Plane:
    """A rigid plane through ``point`` with unit ``normal`` pointing into the fluid.

    Parameters
    ----------
    point : (3,) array_like
        Any point of the plane, in m.
    normal : (3,) array_like
        Normal pointing into the fluid (normalised here).
    label : str
        A short name (``"floor"``, ``"wall"``).
    """

    point: np.ndarray
    normal: np.ndarray
    label: str = "plane"

    def __post_init__(self):
        object.__setattr__(self, "point", _vec3("point", self.point))
        object.__setattr__(self, "normal", _unit("normal", self.normal))

    def signed_distance(self, points) -> np.ndarray:
        """Signed distance in m of ``(n, 3)`` points from the plane, positive in the fluid."""
        pts = check_points("points", points)
        return (pts - self.point) @ self.normal


def mirror_point(point, plane: Plane) -> np.ndarray:
    """Mirror image in m of a point (or ``(n, 3)`` points) across ``plane``."""
    p = np.asarray(point, dtype=float)
    d = (p - plane.point) @ plane.normal
    return p - 2.0 * np.multiply.outer(d, plane.normal)


def mirror_vector(vector, plane: Plane) -> np.ndarray:
    """Mirror image of a direction (or ``(n, 3)`` directions) across ``plane``."""
    v = np.asarray(vector, dtype=float)
    return v - 2.0 * np.multiply.outer(v @ plane.normal, plane.normal)


@dataclass(frozen=True)
class Configuration:
    """A sphere and its images in front of zero, one or two rigid planes.

    Parameters
    ----------
    name : str
        ``"free"``, ``"plane"`` or ``"wall-floor"``.
    radius : float
        Sphere radius a in m (the same for every image).
    sources : tuple of ImageSource
        The real sphere first, then its images.
    planes : tuple of Plane
        The rigid planes bounding the fluid.
    strike : str
        Which surface the sphere strikes (``"floor"`` or ``"wall"``).
    """

    name: str
    radius: float
    sources: tuple = field(default_factory=tuple)
    planes: tuple = field(default_factory=tuple)
    strike: str = "floor"

    def __post_init__(self):
        check_positive("radius", self.radius, "m")
        if not self.sources or self.sources[0].order != 0:
            raise ParameterError("sources", "the real sphere (order 0) must come first")

    @property
    def real(self) -> ImageSource:
        """The real sphere."""
        return self.sources[0]

    @property
    def centre(self) -> np.ndarray:
        """Centre of the real sphere in m."""
        return self.sources[0].position

    @property
    def axis(self) -> np.ndarray:
        """Acceleration axis of the real sphere (unit vector)."""
        return self.sources[0].axis

    @property
    def contact_point(self) -> np.ndarray:
        """Point in m where the sphere touches the struck surface."""
        return self.centre - self.radius * self.axis

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


def images_free(radius: float) -> Configuration:
    """Build the sphere alone in free field: centre ``(0, 0, a)``, acceleration ``+z``.

    Parameters
    ----------
    radius : float
        Sphere radius a in m.

    Returns
    -------
    Configuration
        One source, no planes.
    """
    a = check_positive("radius", radius, "m")
    real = ImageSource(np.array([0.0, 0.0, a]), np.array([0.0, 0.0, 1.0]), 0, "real")
    return Configuration("free", a, (real,), ())


def images_plane(radius: float) -> Configuration:
    """Build the sphere touching the rigid plane ``z = 0`` and its image (paper eq 14, Figure 1).

    Parameters
    ----------
    radius : float
        Sphere radius a in m.

    Returns
    -------
    Configuration
        Sources: the real sphere at ``(0, 0, a)`` with axis ``+z`` and its image at
        ``(0, 0, -a)`` with the mirrored axis ``-z``. One plane, ``z = 0``, normal ``+z``.

    Notes
    -----
    With the mirrored axis the image adds with a plus sign; taking its polar angle from the
    real axis instead flips the sign of ``cos θ2`` and gives the paper's eq 14,
    ``p(r1, θ1, t1) - p(r2, θ2, t2)``.

    Examples
    --------
    >>> cfg = images_plane(0.01)
    >>> [float(s.position[2]) for s in cfg.sources], [float(s.axis[2]) for s in cfg.sources]
    ([0.01, -0.01], [1.0, -1.0])
    """
    a = check_positive("radius", radius, "m")
    floor = Plane(np.zeros(3), np.array([0.0, 0.0, 1.0]), "floor")
    real = ImageSource(np.array([0.0, 0.0, a]), np.array([0.0, 0.0, 1.0]), 0, "real")
    return Configuration("plane", a, images_of(real, (floor,)), (floor,))


def observer_points(config: Configuration, distance, angles) -> np.ndarray:
    """Observers at ``distance`` (m) from the sphere's centre and ``angles`` (rad) from its axis.

    The observers lie in the plane spanned by the acceleration axis and the horizontal
    direction ``+x`` (for a wall strike, whose axis is ``+x``, the vertical ``+z``): for the
    wall-floor corner that is the plane through the centre normal to the wall, on the side away
    from it. This is the one convention of every command, scene and sweep.

    Parameters
    ----------
    config : Configuration
        The sphere and its images.
    distance : float or (k,) array_like
        Distance(s) in m from the sphere's centre.
    angles : float or (k,) array_like
        Polar angle(s) in rad from the acceleration axis.

    Returns
    -------
    (k, 3) ndarray
        Positions in m (not checked against the fluid: see :meth:`Configuration.in_fluid`).
    """
    th = np.atleast_1d(np.asarray(angles, dtype=float))
    r = np.atleast_1d(np.asarray(distance, dtype=float))
    axis = np.asarray(config.axis, dtype=float)
    perp = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.5 else np.array([0.0, 0.0, 1.0])
    return np.asarray(config.centre, dtype=float) + r[:, None] * (
        np.cos(th)[:, None] * axis + np.sin(th)[:, None] * perp)


def images_of(real: ImageSource, planes) -> tuple:
    """Return a source and its images in one plane or two perpendicular planes (orders 1 and 2).

    Parameters
    ----------
    real : ImageSource
        The sphere that radiates (order 0).
    planes : sequence of Plane
        One plane, or two perpendicular planes (for which four sources are exact).

    Returns
    -------
    tuple of ImageSource
        ``real`` first, then one image per plane, then (two planes) the image in both.
    """
    out = [real]
    for pl in planes:
        out.append(
            ImageSource(mirror_point(real.position, pl), mirror_vector(real.axis, pl), 1, pl.label)
        )
    if len(planes) == 2:
        p1, p2 = planes
        pos = mirror_point(mirror_point(real.position, p1), p2)
        ax = mirror_vector(mirror_vector(real.axis, p1), p2)
        out.append(ImageSource(pos, ax, 2, f"{p1.label}+{p2.label}"))
    return tuple(out)


def images_wall_floor(
    radius: float, wall_distance=None, *, strike: str = "floor", height=None
) -> Configuration:
    """Build the sphere in a wall-floor corner (two perpendicular rigid planes) and 3 images.

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

    Returns
    -------
    Configuration
        Four sources: the real sphere, its images in the floor and in the wall (order 1) and
        the image in both (order 2). Planes: floor ``z = 0`` (normal ``+z``) and wall
        ``x = -wall_distance`` (normal ``+x``).

    Notes
    -----
    Two perpendicular planes make a closed group of three images, so the method of images is
    exact here (Allen and Berkley's construction for a rectangular room, restricted to one
    corner).
    """
    a = check_positive("radius", radius, "m")
    check_choice("strike", strike, ("floor", "wall"))
    if strike == "floor":
        if wall_distance is None:
            raise ParameterError(
                "wall_distance", "required for the wall-floor corner (distance in m >= radius)"
            )
        w = check_positive("wall_distance", wall_distance, "m")
        if w < a * (1 - 1e-12):
            raise ParameterError(
                "wall_distance",
                f"must be >= radius = {a:g} m (sphere inside the wall), got {w:g} m",
            )
        if height is not None and abs(float(height) - a) > 1e-12 * a:
            raise ParameterError(
                "height",
                "only used with strike='wall'; a floor strike has its centre at z = radius",
            )
        centre, axis = np.array([0.0, 0.0, a]), np.array([0.0, 0.0, 1.0])
    else:
        w = a if wall_distance is None else check_positive("wall_distance", wall_distance, "m")
        if abs(w - a) > 1e-9 * a:
            raise ParameterError(
                "wall_distance",
                f"a sphere striking the wall touches it: must equal radius = {a:g} m",
            )
        h = a if height is None else check_positive("height", height, "m")
        if h < a * (1 - 1e-12):
            raise ParameterError(
                "height", f"must be >= radius = {a:g} m (sphere inside the floor), got {h:g} m"
            )
        centre, axis = np.array([0.0, 0.0, h]), np.array([1.0, 0.0, 0.0])
    floor = Plane(np.zeros(3), np.array([0.0, 0.0, 1.0]), "floor")
    wall = Plane(np.array([-w, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), "wall")
    real = ImageSource(centre, axis, 0, "real")
    return Configuration("wall-floor", a, images_of(real, (floor, wall)), (floor, wall), strike)


def configuration(
    name: str, radius: float, *, wall_distance=None, strike: str = "floor", height=None
) -> Configuration:
    """Build a configuration by name.

    Parameters
    ----------
    name : {"free", "plane", "wall-floor"}
        The scene.
    radius : float
        Sphere radius in m.
    wall_distance : float, optional
        Distance in m from the sphere's centre to the wall (``"wall-floor"`` only, >= radius).
    strike : {"floor", "wall"}
        Struck surface for ``"wall-floor"``.
    height : float, optional
        Height of the centre for a wall strike (see :func:`images_wall_floor`).

    Returns
    -------
    Configuration
    """
    check_choice("config", name, CONFIGURATIONS)
    if name == "free":
        return images_free(radius)
    if name == "plane":
        return images_plane(radius)
    return images_wall_floor(radius, wall_distance, strike=strike, height=height)
