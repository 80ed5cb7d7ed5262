"""A rectangular (shoebox) room and its image sources in closed form (Allen and Berkley 1979).

The room occupies ``[0, Lx] x [0, Ly] x [0, Lz]`` (m). Its six surfaces, in the order used for
every per-surface array (the order of pyroomacoustics' west, east, south, north, floor, ceiling)::

    x0: x = 0    x1: x = Lx    y0: y = 0    y1: y = Ly    z0: z = 0 (floor)    z1: z = Lz (ceiling)

Image lattice (Allen and Berkley 1979)
--------------------------------------
Along one axis of length ``L`` a source at ``x`` has one image per integer index ``k``::

    x_k = k L + x          (k even)        x_k = k L + L - x      (k odd)

``|k|`` reflections made it: for ``k >= 0`` ``ceil(k/2)`` at the far wall ``x = L`` and
``floor(k/2)`` at ``x = 0``; for ``k < 0`` the other way round. Odd ``k`` mirrors the axis, so
the image's acceleration direction has that component flipped. An image of the room is one
triple ``(kx, ky, kz)``; its order is ``|kx| + |ky| + |kz|`` and its pressure weight the product
of the reflection coefficients ``beta = sqrt(1 - alpha)`` of the surfaces it was reflected in.
Every triple is one distinct image, so the images of order ``<= N`` are listed in closed form,
without a search over duplicates: there are ``4 n^2 + 2`` of order ``n >= 1`` and::

    (4 N^3 + 6 N^2 + 8 N + 3) / 3

of order ``<= N`` (1, 7, 25, 63, 129, ...).

The order each output needs, the reverberation times and the statistical decay of the image
sum are in :mod:`acoustiviz.core.reverberation`.

This module knows nothing of grids, pulses or files; the field evaluator sums the free-field
radiation of :mod:`acoustiviz.core.radiation` over the images it returns.

References
----------
J. B. Allen and D. A. Berkley, "Image method for efficiently simulating small-room acoustics",
J. Acoust. Soc. Am. 65(4), 943-950 (1979).
H. Kuttruff, *Room Acoustics*, 6th ed., CRC Press (2017), ch. 4 (image sources of a rectangular room).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_positive
from ..constants import MAX_MEMORY_MB
from ..constants import ROOM_SURFACES as SURFACES  # the order of every per-surface array

__all__ = [
    "SURFACES",
    "Shoebox",
    "RoomImages",
    "image_count",
    "image_sources",
    "max_order_for_memory",
]

#: Bytes held per image at the peak of :func:`image_sources` with broadband weights: positions
#: and directions (3 x 8 B each), lattice indices (3 x 4 B), order and weight (8 B each), and the
#: gathered temporaries of one axis (2 x 8 B), with 25 % to spare; each band adds 2 x 8 B.
_BYTES_PER_IMAGE = 120
_BYTES_PER_BAND = 16


def _as_array(name: str, value, shape_hint: str) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, f"expected {shape_hint}, got {value!r}") from None
    return a


@dataclass(frozen=True, eq=False)
class Shoebox:
    """A rectangular room ``[0, Lx] x [0, Ly] x [0, Lz]`` with absorbing surfaces.

    Parameters
    ----------
    dimensions : (3,) array_like
        ``(Lx, Ly, Lz)`` in m, each > 0.
    absorption : float, (6,) or (6, n_bands) array_like
        Energy absorption coefficient alpha of the surfaces, each in ``[0, 1)``: one value for
        every surface, one per surface in the order of :data:`SURFACES` (x0, x1, y0, y1, z0, z1),
        or one per surface and octave band. Stored as a read-only ``(6,)`` or ``(6, n_bands)``
        array.

    Examples
    --------
    >>> room = Shoebox((6.0, 4.0, 3.0), 0.1)
    >>> room.volume, room.surface_area
    (72.0, 108.0)
    >>> room.reflection[:2]
    array([0.9486833, 0.9486833])
    """

    dimensions: np.ndarray
    absorption: np.ndarray = 0.0

    def __post_init__(self):
        d = _as_array("dimensions", self.dimensions, "3 lengths in m").reshape(-1)
        if d.shape != (3,):
            raise ParameterError("dimensions", f"expected 3 lengths (Lx, Ly, Lz) in m, got {self.dimensions!r}")
        for name, v in zip(("Lx", "Ly", "Lz"), d, strict=True):
            check_positive(f"dimensions ({name})", v, "m")
        d = d.copy()
        d.setflags(write=False)
        object.__setattr__(self, "dimensions", d)
        hint = "one value, six (x0, x1, y0, y1, z0, z1) or a (6, n_bands) array"
        a = _as_array("absorption", self.absorption, hint)
        one = a.ndim == 0
        if one:
            a = np.full(6, float(a))
        elif a.shape == (6,) or (a.ndim == 2 and a.shape[0] == 6 and a.shape[1] >= 1):
            a = a.copy()
        else:
            raise ParameterError("absorption", f"expected {hint}, got shape {a.shape}")
        bad = ~(np.isfinite(a) & (a >= 0.0) & (a < 1.0))
        if np.any(bad):
            first = np.unravel_index(int(np.flatnonzero(bad)[0]), a.shape)
            where = "" if one else f" on surface {SURFACES[first[0]]}"
            raise ParameterError("absorption", f"energy absorption coefficient alpha must lie in [0, 1), got "
                                               f"{float(a[first]):g}{where}")
        a.setflags(write=False)
        object.__setattr__(self, "absorption", a)

    def _key(self):
        return (self.dimensions.tobytes(), self.absorption.shape, self.absorption.tobytes())

    def __eq__(self, other) -> bool:
        return isinstance(other, Shoebox) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    @property
    def bands(self) -> int | None:
        """Number of frequency bands of the absorption, or ``None`` for one broadband value per surface."""
        return None if self.absorption.ndim == 1 else int(self.absorption.shape[1])

    @property
    def volume(self) -> float:
        """Volume V in m³."""
        return float(np.prod(self.dimensions))

    @property
    def areas(self) -> np.ndarray:
        """Area in m² of each surface, in the order of :data:`SURFACES`."""
        lx, ly, lz = self.dimensions
        return np.repeat([ly * lz, lx * lz, lx * ly], 2)

    @property
    def surface_area(self) -> float:
        """Total surface S in m²."""
        return float(self.areas.sum())

    @property
    def reflection(self) -> np.ndarray:
        """Pressure reflection coefficient ``beta = sqrt(1 - alpha)`` of each surface, shaped like ``absorption``."""
        return np.sqrt(1.0 - self.absorption)

    @property
    def absorption_area(self) -> np.ndarray | float:
        """Equivalent absorption area ``A = sum_i S_i alpha_i`` in m² (per band if banded)."""
        a = np.tensordot(self.areas, self.absorption, axes=(0, 0))
        return float(a) if a.ndim == 0 else a

    @property
    def mean_absorption(self) -> np.ndarray | float:
        """Area-weighted mean absorption coefficient ``A / S`` (per band if banded)."""
        return self.absorption_area / self.surface_area

    @property
    def mean_free_path(self) -> float:
        """Mean free path ``4 V / S`` in m of a diffuse field (Kuttruff, ch. 5)."""
        return 4.0 * self.volume / self.surface_area

    @property
    def lattice_spacing(self) -> float:
        """``H = (Lx^-2 + Ly^-2 + Lz^-2)^(-1/2)`` in m: every image of order n is at least ``(n - 3) H`` away."""
        return float(1.0 / math.sqrt(float(np.sum(self.dimensions ** -2.0))))


@dataclass(frozen=True, eq=False)
class RoomImages:
    """The images of a sphere in a shoebox room, sorted by order (the real sphere first).

    Parameters
    ----------
    positions : (n, 3) ndarray
        Centres of the image spheres in m.
    directions : (n, 3) ndarray
        Unit directions of their accelerations (the real direction mirrored by each reflection).
    weights : (n,) or (n, n_bands) ndarray
        Pressure weight of each image: the product of the reflection coefficients of the
        surfaces it was reflected in (per band when the absorption is banded).
    orders : (n,) ndarray of int
        Number of reflections of each image (0 for the real sphere).
    lattice : (n, 3) ndarray of int32
        The image's lattice indices ``(kx, ky, kz)``; ``|k_i|`` reflections across the walls
        normal to axis i.

    Notes
    -----
    The images come shell by shell in order, so those of order ``<= m`` are the first
    ``image_count(m)``.
    """

    positions: np.ndarray
    directions: np.ndarray
    weights: np.ndarray
    orders: np.ndarray
    lattice: np.ndarray

    def __len__(self) -> int:
        return int(self.orders.size)

    @property
    def max_order(self) -> int:
        """Largest order held."""
        return int(self.orders.max())

    def up_to(self, order: int) -> RoomImages:
        """The images of order ``<= order`` (a prefix of these: views, no copy)."""
        n = image_count(min(check_order("order", order), self.max_order))
        return RoomImages(self.positions[:n], self.directions[:n], self.weights[:n], self.orders[:n],
                          self.lattice[:n])

    @property
    def axis_reflections(self) -> np.ndarray:
        """``(n, 3)`` number of reflections of each image across the walls normal to x, y and z."""
        return np.abs(self.lattice)

    @property
    def reflections(self) -> np.ndarray:
        """``(n, 6)`` number of reflections of each image in each surface, in the order of :data:`SURFACES`."""
        k = self.lattice
        near = np.where(k >= 0, k // 2, (1 - k) // 2)  # at x = 0
        far = np.where(k >= 0, (k + 1) // 2, (-k) // 2)  # at x = L
        return np.stack([near[:, 0], far[:, 0], near[:, 1], far[:, 1], near[:, 2], far[:, 2]], axis=1)


def image_count(order: int) -> int:
    """Number of images of order ``<= order`` in a shoebox room, real source included.

    Parameters
    ----------
    order : int
        Largest reflection order N >= 0.

    Returns
    -------
    int
        ``(4 N^3 + 6 N^2 + 8 N + 3) / 3``: ``1 + sum_{n=1}^{N} (4 n^2 + 2)``.

    Examples
    --------
    >>> [image_count(n) for n in range(5)]
    [1, 7, 25, 63, 129]
    """
    n = check_order("order", order)
    return (4 * n**3 + 6 * n**2 + 8 * n + 3) // 3


def check_order(name: str, order) -> int:
    """Return ``order`` as an int, raising unless it is an integer >= 0."""
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order < 0:
        raise ParameterError(name, f"must be an integer >= 0, got {order!r}")
    return int(order)


def _image_bytes(order: int, bands: int | None) -> int:
    per = _BYTES_PER_IMAGE + (_BYTES_PER_BAND * (bands - 1) if bands else 0)
    return image_count(order) * per


def max_order_for_memory(max_memory_mb: float = MAX_MEMORY_MB, bands: int | None = None) -> int:
    """Largest image order whose construction fits ``max_memory_mb``.

    Parameters
    ----------
    max_memory_mb : float
        Memory budget in MB (10^6 B), > 0.
    bands : int, optional
        Number of frequency bands of the weights (``None``: broadband).

    Returns
    -------
    int
        The largest N with ``image_count(N)`` images times the bytes per image within budget.
    """
    budget = check_positive("max_memory_mb", max_memory_mb, "MB") * 1e6
    per = _BYTES_PER_IMAGE + (_BYTES_PER_BAND * (bands - 1) if bands else 0)
    n = max(0, int((3.0 * budget / per / 4.0) ** (1.0 / 3.0)) + 2)
    while n > 0 and image_count(n) * per > budget:
        n -= 1
    return n


def _direction(direction) -> np.ndarray:
    if isinstance(direction, str):
        if direction not in SURFACES:
            allowed = ", ".join(repr(s) for s in SURFACES)
            raise ParameterError("direction", f"a surface name must be one of {allowed}, got {direction!r}")
        i = SURFACES.index(direction)
        d = np.zeros(3)
        d[i // 2] = 1.0 if i % 2 == 0 else -1.0  # the inward normal: the rebound from that surface
        return d
    d = _as_array("direction", direction, "a surface name or a 3-vector").reshape(-1)
    norm = float(np.linalg.norm(d)) if d.shape == (3,) else 0.0
    if not (norm > 0 and math.isfinite(norm)):
        raise ParameterError("direction", f"expected a surface name or a non-zero finite 3-vector, got {direction!r}")
    return d / norm


def _check_centre(room: Shoebox, centre, radius: float) -> np.ndarray:
    c = _as_array("centre", centre, "3 coordinates in m").reshape(-1)
    if c.shape != (3,) or not np.all(np.isfinite(c)):
        raise ParameterError("centre", f"expected 3 finite coordinates in m, got {centre!r}")
    tol = 1e-12 * max(radius, float(room.dimensions.max()))
    for i, ax in enumerate("xyz"):
        lo, hi = radius, room.dimensions[i] - radius
        if hi < lo - tol:
            raise ParameterError(
                "radius", f"the sphere (diameter {2 * radius:g} m) does not fit in L{ax} = {room.dimensions[i]:g} m")
        if not (lo - tol <= c[i] <= hi + tol):
            raise ParameterError(
                "centre", f"{ax} must lie in [{lo:g}, {hi:g}] m (the sphere of radius {radius:g} m inside the "
                          f"room), got {c[i]:g} m")
    return c


def _shell(n: int) -> np.ndarray:
    """The ``4 n^2 + 2`` integer triples with ``|kx| + |ky| + |kz| = n`` (one for n = 0), ``(m, 3)`` int32."""
    if n == 0:
        return np.zeros((1, 3), dtype=np.int32)
    kx = np.arange(-n, n + 1)
    rem = n - np.abs(kx)
    count = 2 * rem + 1  # ky = -rem..rem
    starts = np.cumsum(count) - count
    ky = np.arange(count.sum()) - np.repeat(starts + rem, count)
    kx = np.repeat(kx, count)
    rem = np.repeat(rem, count) - np.abs(ky)
    count = np.where(rem > 0, 2, 1)  # kz = +rem, -rem
    starts = np.cumsum(count) - count
    sign = 1 - 2 * (np.arange(count.sum()) - np.repeat(starts, count))
    out = np.empty((int(count.sum()), 3), dtype=np.int32)
    out[:, 0] = np.repeat(kx, count)
    out[:, 1] = np.repeat(ky, count)
    out[:, 2] = np.repeat(rem, count) * sign
    return out


def _lattice(order: int):
    """All integer triples with ``|kx| + |ky| + |kz| <= order``, shell by shell, and their orders."""
    total = image_count(order)
    k = np.empty((total, 3), dtype=np.int32)
    orders = np.empty(total, dtype=np.int64)
    at = 0
    for n in range(order + 1):  # one vectorised step per shell, no search and no sort
        shell = _shell(n)
        k[at:at + shell.shape[0]] = shell
        orders[at:at + shell.shape[0]] = n
        at += shell.shape[0]
    return k, orders


def image_sources(room: Shoebox, centre, order: int, *, radius: float, direction="z0",
                  max_memory_mb: float = MAX_MEMORY_MB) -> RoomImages:
    """Image sources of a sphere in a shoebox room to order N (Allen and Berkley's lattice).

    Parameters
    ----------
    room : Shoebox
        The room and its absorption.
    centre : (3,) array_like
        Centre of the real sphere in m; at least ``radius`` from every surface.
    order : int
        Largest reflection order N, from 0 (the real sphere alone) to the largest order whose
        ``(4 N^3 + 6 N^2 + 8 N + 3) / 3`` images fit ``max_memory_mb`` (:func:`max_order_for_memory`).
    radius : float
        Sphere radius a in m.
    direction : str or (3,) array_like
        The sphere's acceleration: the name of the struck surface (:data:`SURFACES`; the
        acceleration is that surface's inward normal, the rebound: ``"z0"``, the floor, gives
        ``+z``), or any direction vector (normalised here).
    max_memory_mb : float
        Memory budget in MB for the construction (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).

    Returns
    -------
    RoomImages
        ``(4 N^3 + 6 N^2 + 8 N + 3) / 3`` images sorted by order, the real sphere first.

    Notes
    -----
    Closed form along each axis (module docstring): the lattice indices of each shell are
    listed directly (one vectorised step per order), and coordinates, direction signs and
    weights are tabulated once per axis for ``k = -N..N`` and gathered; nothing loops over
    images, searches for duplicates or sorts.

    Examples
    --------
    >>> room = Shoebox((6.0, 4.0, 3.0), 0.1)
    >>> im = image_sources(room, (2.0, 1.5, 0.02), 1, radius=0.02)
    >>> len(im), im.orders.tolist()
    (7, [0, 1, 1, 1, 1, 1, 1])
    >>> im.positions[im.lattice[:, 2] == -1], im.directions[im.lattice[:, 2] == -1]
    (array([[ 2.  ,  1.5 , -0.02]]), array([[ 0.,  0., -1.]]))
    """
    if not isinstance(room, Shoebox):
        raise ParameterError("room", f"expected a Shoebox, got {type(room).__name__}")
    a = check_positive("radius", radius, "m")
    c = _check_centre(room, centre, a)
    u = _direction(direction)
    n = check_order("order", order)
    nmax = max_order_for_memory(max_memory_mb, room.bands)
    if n > nmax:
        raise ParameterError(
            "order", f"must lie in [0, {nmax}]: the (4N^3 + 6N^2 + 8N + 3)/3 = {image_count(n):,} images of "
                     f"order <= {n} need about {_image_bytes(n, room.bands) / 1e6:,.0f} MB, over the "
                     f"max_memory_mb = {max_memory_mb:g} MB budget")
    k, orders = _lattice(n)
    ks = np.arange(-n, n + 1)
    odd = (ks % 2).astype(bool)
    beta = room.reflection.reshape(6, -1)
    near = np.where(ks >= 0, ks // 2, (1 - ks) // 2)  # reflections at the wall through the origin
    far = np.where(ks >= 0, (ks + 1) // 2, (-ks) // 2)  # at the opposite wall
    pos = np.empty(k.shape)
    dirs = np.empty(k.shape)
    w = None
    for i in range(3):
        length = room.dimensions[i]
        idx = k[:, i] + n
        pos[:, i] = np.take(ks * length + np.where(odd, length - c[i], c[i]), idx)
        dirs[:, i] = np.take(np.where(odd, -u[i], u[i]), idx)
        table = beta[2 * i][None, :] ** near[:, None] * beta[2 * i + 1][None, :] ** far[:, None]
        factor = np.take(table[:, 0], idx) if room.bands is None else np.take(table, idx, axis=0)
        w = factor if w is None else np.multiply(w, factor, out=w)
        del idx, factor
    out = RoomImages(pos, dirs, w, orders, k)
    for arr in (out.positions, out.directions, out.weights, out.orders, out.lattice):
        arr.setflags(write=False)
    return out
