"""Image sources: reflecting planes, mirrored spheres and the vectorised set a field evaluator sums.

A rigid plane is accounted for by the method of images (paper eq 14, Figure 1): the sphere
and its mirror image radiate together, and the normal particle velocity vanishes on the plane.
Each image is a sphere of the same radius with its own centre and its own acceleration axis --
the real axis mirrored by every plane that made the image -- and a reflection weight, the
product of the pressure reflection coefficients of those planes (1 for rigid planes). With
these mirrored axes every image contributes with a **plus** sign and its own polar angle; this
is the same sum as the paper's ``p(r1, θ1, t1) - p(r2, θ2, t2)`` in which both angles are taken
from the real axis.

This module knows nothing of acoustics nor of any particular geometry: the geometries
(:mod:`acoustiviz.core.geometry`) build their images from it, and the field evaluator sums the
free-field radiation of every image of an :class:`ImageSet`. :class:`Region` describes the
directions a geometry's closing grid or directivity balloon covers. All lengths in m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_points

__all__ = [
    "ImageSource",
    "ImageSet",
    "Plane",
    "Region",
    "mirror_point",
    "mirror_vector",
    "images_of",
]


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


def _weight(name, w) -> float:
    w = float(w)
    if not (np.isfinite(w) and -1.0 <= w <= 1.0):
        raise ParameterError(name, f"must be a reflection weight in [-1, 1], got {w!r}")
    return w


@dataclass(frozen=True)
class ImageSource:
    """One radiating sphere, real (order 0) or an image.

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
    weight : float
        Reflection weight in [-1, 1]: the product of the pressure reflection coefficients of the
        planes that made the image (1 for the real sphere and for rigid planes).
    """

    position: np.ndarray
    axis: np.ndarray
    order: int = 0
    label: str = "real"
    weight: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "position", _vec3("position", self.position))
        object.__setattr__(self, "axis", _unit("axis", self.axis))
        object.__setattr__(self, "weight", _weight("weight", self.weight))
        if int(self.order) != self.order or self.order < 0:
            raise ParameterError("order", f"must be a non-negative integer, got {self.order!r}")


@dataclass(frozen=True, eq=False)
class ImageSet:
    """The sphere and its images as arrays: what a field evaluator sums.

    Parameters
    ----------
    positions : (k, 3) ndarray
        Centres in m, the real sphere first.
    axes : (k, 3) ndarray
        Unit directions of the mirrored accelerations.
    weights : (k,) ndarray
        Reflection weights (dimensionless, 1 for rigid planes).
    orders : (k,) ndarray of int
        Reflections that made each image (0: the real sphere).
    labels : tuple of str
        A short name per image.

    Notes
    -----
    An image's pressure is the free-field pressure of a sphere at ``positions[j]`` accelerating
    along ``axes[j]``, times ``weights[j]``. The pressure of a sphere is linear in ``cos θ`` to its
    axis, so the weight may be folded into the axis: :attr:`weighted_axes` is what the compiled
    kernels take as each source's axis.

    Examples
    --------
    >>> s = ImageSet.of([ImageSource([0, 0, 0.01], [0, 0, 1]), ImageSource([0, 0, -0.01], [0, 0, -1], 1, "floor")])
    >>> len(s), s.orders.tolist(), s.weighted_axes[:, 2].tolist()
    (2, [0, 1], [1.0, -1.0])
    """

    positions: np.ndarray
    axes: np.ndarray
    weights: np.ndarray
    orders: np.ndarray
    labels: tuple

    def __post_init__(self):
        pos = np.ascontiguousarray(self.positions, dtype=float)
        k = pos.shape[0] if pos.ndim == 2 else -1
        if pos.shape != (k, 3) or k < 1:
            raise ParameterError("positions", f"expected a (k, 3) array with k >= 1, got shape {pos.shape}")
        ax = np.ascontiguousarray(self.axes, dtype=float)
        w = np.ascontiguousarray(self.weights, dtype=float)
        o = np.ascontiguousarray(self.orders, dtype=np.int64)
        if ax.shape != (k, 3) or w.shape != (k,) or o.shape != (k,) or len(self.labels) != k:
            raise ParameterError("images", "positions, axes, weights, orders and labels must have one row per image")
        for a in (pos, ax, w, o):
            a.setflags(write=False)
        object.__setattr__(self, "positions", pos)
        object.__setattr__(self, "axes", ax)
        object.__setattr__(self, "weights", w)
        object.__setattr__(self, "orders", o)
        object.__setattr__(self, "labels", tuple(self.labels))

    @classmethod
    def of(cls, sources) -> ImageSet:
        """The set of a sequence of :class:`ImageSource` (an :class:`ImageSet` is returned as it is)."""
        if isinstance(sources, ImageSet):
            return sources
        sources = tuple(sources)
        if not sources:
            raise ParameterError("sources", "expected at least one source")
        return cls(np.array([s.position for s in sources], dtype=float), np.array([s.axis for s in sources]),
                   np.array([s.weight for s in sources], dtype=float), np.array([s.order for s in sources]),
                   tuple(s.label for s in sources))

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    @property
    def weighted_axes(self) -> np.ndarray:
        """``(k, 3)`` axes times weights: the pressure of image ``j`` is linear in ``d · axis_j w_j``."""
        return np.ascontiguousarray(self.axes * self.weights[:, None])

    def sources(self) -> tuple:
        """The images as :class:`ImageSource` values."""
        return tuple(ImageSource(p, a, int(o), lab, float(w)) for p, a, o, lab, w in
                     zip(self.positions, self.axes, self.orders, self.labels, self.weights, strict=True))


@dataclass(frozen=True)
class Plane:
    """A reflecting plane through ``point`` with unit ``normal`` pointing into the fluid.

    Parameters
    ----------
    point : (3,) array_like
        Any point of the plane, in m.
    normal : (3,) array_like
        Normal pointing into the fluid (normalised here).
    label : str
        A short name (``"floor"``, ``"wall"``).
    reflection : float
        Pressure reflection coefficient in [-1, 1] (1: rigid).
    """

    point: np.ndarray
    normal: np.ndarray
    label: str = "plane"
    reflection: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "point", _vec3("point", self.point))
        object.__setattr__(self, "normal", _unit("normal", self.normal))
        object.__setattr__(self, "reflection", _weight("reflection", self.reflection))

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


def images_of(real: ImageSource, planes) -> tuple:
    """Return a source and its images in one plane or two perpendicular planes (orders 1 and 2).

    Parameters
    ----------
    real : ImageSource
        The sphere that radiates (order 0).
    planes : sequence of Plane
        None, one plane, or two perpendicular planes (for which four sources are exact).

    Returns
    -------
    tuple of ImageSource
        ``real`` first, then one image per plane, then (two planes) the image in both; each
        image's weight is ``real.weight`` times the reflection coefficients of its planes.
    """
    planes = tuple(planes)
    if len(planes) > 2:
        raise ParameterError("planes", f"images_of closes the images of at most two perpendicular planes, "
                                       f"got {len(planes)}")
    out = [real]
    for pl in planes:
        out.append(ImageSource(mirror_point(real.position, pl), mirror_vector(real.axis, pl), 1, pl.label,
                               real.weight * pl.reflection))
    if len(planes) == 2:
        p1, p2 = planes
        pos = mirror_point(mirror_point(real.position, p1), p2)
        ax = mirror_vector(mirror_vector(real.axis, p1), p2)
        out.append(ImageSource(pos, ax, 2, f"{p1.label}+{p2.label}", real.weight * p1.reflection * p2.reflection))
    return tuple(out)


@dataclass(frozen=True, eq=False)
class Region:
    """A region of directions around an anchor: a closing grid's or a balloon's.

    Parameters
    ----------
    kind : {"sphere", "half", "quarter"}
        All directions; those above a plane of normal ``up``; those above two perpendicular
        planes of normals ``up`` and ``side``.
    origin : (3,) ndarray
        Anchor in m (on the plane, or on the corner's edge, for the half and quarter regions).
    up, side : (3,) ndarray
        Polar axis and azimuth origin (unit vectors).
    """

    kind: str
    origin: np.ndarray
    up: np.ndarray
    side: np.ndarray
