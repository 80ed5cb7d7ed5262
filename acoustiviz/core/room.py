"""A rectangular (shoebox) room: image sources in closed form and the image order each output needs.

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
without a search over duplicates: there are ``4 n^2 + 2`` of order ``n >= 1`` and

    (4 N^3 + 6 N^2 + 8 N + 3) / 3

of order ``<= N`` (the octahedral numbers: 1, 7, 25, 63, ...).

Bounds on where images lie (used to choose an order)
----------------------------------------------------
For a receiver anywhere in the room and an image with indices ``k``, the image lies in the cell
``[k L, (k + 1) L]`` of each axis, so ``|x_k - x_r| >= (|k| - 1)^+ L`` and ``<= (|k| + 1) L``. By
Cauchy-Schwarz, ``sum_i (|k_i| - 1)^+ >= n - 3`` gives the distance of every image of order ``n``::

    r >= (n - 3) H,      H = (Lx^-2 + Ly^-2 + Lz^-2)^(-1/2),

and ``r <= sqrt(((n + 1) L_max)^2 + L_mid^2 + L_min^2)`` (the convex bound is largest at a vertex).

This module knows nothing of grids, pulses or files; the field evaluator sums the free-field
radiation of :mod:`acoustiviz.core.radiation` over the images it returns.

References
----------
J. B. Allen and D. A. Berkley, "Image method for efficiently simulating small-room acoustics",
J. Acoust. Soc. Am. 65(4), 943-950 (1979).
W. C. Sabine, *Collected Papers on Acoustics*, Harvard University Press (1922).
C. F. Eyring, "Reverberation time in 'dead' rooms", J. Acoust. Soc. Am. 1(2A), 217-241 (1930).
H. Kuttruff, *Room Acoustics*, 6th ed., CRC Press (2017), ch. 4 (image sources of a rectangular
room, their density 4 pi c^3 t^2 / V) and ch. 5 (reverberation, mean free path 4V/S).
M. R. Schroeder, "The 'Schroeder frequency' revisited", J. Acoust. Soc. Am. 99(5), 3240-3241 (1996).
A. Lindau, L. Kosanke and S. Weinzierl, "Perceptual evaluation of model- and signal-based
predictors of the mixing time in binaural room impulse responses", J. Audio Eng. Soc. 60(11),
887-898 (2012) (the sqrt(V) ms rule of J.-D. Polack).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_positive, check_range
from ..constants import MAX_MEMORY_MB
from .medium import AIR, Medium

__all__ = [
    "SURFACES",
    "Shoebox",
    "RoomImages",
    "ImageOrder",
    "image_count",
    "image_sources",
    "max_order_for_memory",
    "order_for_time",
    "energy_order",
    "reverberation_time",
    "mixing_time",
    "echo_density_time",
    "image_energy_decay",
]

#: The six surfaces of a shoebox room, in the order of every per-surface array.
SURFACES = ("x0", "x1", "y0", "y1", "z0", "z1")

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


@dataclass(frozen=True)
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
        if a.ndim == 0:
            a = np.full(6, float(a))
        elif a.shape == (6,) or (a.ndim == 2 and a.shape[0] == 6 and a.shape[1] >= 1):
            a = a.copy()
        else:
            raise ParameterError("absorption", f"expected {hint}, got shape {a.shape}")
        bad = ~(np.isfinite(a) & (a >= 0.0) & (a < 1.0))
        if np.any(bad):
            i = int(np.argwhere(bad)[0][0])
            v = a[np.unravel_index(int(np.flatnonzero(bad)[0]), a.shape)]
            raise ParameterError(
                "absorption", f"each coefficient alpha must lie in [0, 1), got {v!r} on surface {SURFACES[i]}")
        a.setflags(write=False)
        object.__setattr__(self, "absorption", a)

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


@dataclass(frozen=True)
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


@dataclass(frozen=True)
class ImageOrder:
    """The image order an output needs, and what it leaves out.

    Parameters
    ----------
    order : int
        Largest image order kept.
    images : int
        Number of images of order ``<= order``, real sphere included.
    neglected_db : float
        Upper bound in dB of the energy of the images left out relative to (a lower bound of)
        the total energy, the worst band; ``-inf`` when nothing that can arrive is left out.
    tolerance_db : float
        The tolerance asked for, in dB.
    capped : bool
        True when ``order`` was cut by ``max_order`` before ``neglected_db <= tolerance_db``.
    """

    order: int
    images: int
    neglected_db: float
    tolerance_db: float
    capped: bool = False


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
    n = _check_order_value("order", order)
    return (4 * n**3 + 6 * n**2 + 8 * n + 3) // 3


def _check_order_value(name: str, order) -> int:
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
    n = _check_order_value("order", order)
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
    w = np.ones((k.shape[0], beta.shape[1]))
    for i in range(3):
        length = room.dimensions[i]
        idx = k[:, i] + n
        pos[:, i] = (ks * length + np.where(odd, length - c[i], c[i]))[idx]
        dirs[:, i] = np.where(odd, -u[i], u[i])[idx]
        w *= (beta[2 * i][None, :] ** near[:, None] * beta[2 * i + 1][None, :] ** far[:, None])[idx]
        del idx
    out = RoomImages(pos, dirs, w if room.bands else w[:, 0], orders, k)
    for arr in (out.positions, out.directions, out.weights, out.orders, out.lattice):
        arr.setflags(write=False)
    return out


# ------------------------------------------------------------------------------- choosing the order
def _shell_upper_distance(room: Shoebox, n: np.ndarray) -> np.ndarray:
    """Largest distance in m from any room point to any image of order n (vertex of a convex bound)."""
    d = np.sort(room.dimensions)[::-1]
    return np.sqrt(((n + 1.0) * d[0]) ** 2 + d[1] ** 2 + d[2] ** 2)


def _shell_lower_distance(room: Shoebox, n: np.ndarray) -> np.ndarray:
    """Smallest distance in m from any room point to any image of order n: ``(n - 3)^+ H``."""
    return np.maximum(n - 3.0, 0.0) * room.lattice_spacing


def order_for_time(room: Shoebox, time: float, *, radius: float, medium: Medium = AIR) -> int:
    """Smallest order that holds every image whose sound can reach the room by ``time``.

    Parameters
    ----------
    room : Shoebox
        The room.
    time : float
        Time in s after the start of contact (e.g. the direct arrival plus the pulse duration and
        a margin, for a peak level), >= 0.
    radius : float
        Sphere radius a in m: sound leaves the sphere's surface, so an image at distance r
        arrives at ``(r - a) / c``.
    medium : Medium
        The fluid (its sound speed c).

    Returns
    -------
    int
        ``N = 3 + floor((c t + a) / H)`` with ``H`` of :attr:`Shoebox.lattice_spacing`: every image
        of order ``n > N`` is farther than ``c t + a`` from every point of the room, so it has
        not arrived anywhere in the room by ``time``.

    Notes
    -----
    An image of order n with lattice indices k lies at least ``(|k_i| - 1)^+ L_i`` from any room
    point along axis i, and ``sum_i (|k_i| - 1)^+ >= n - 3``; by Cauchy-Schwarz
    ``n - 3 <= sum_i m_i <= sqrt(sum_i m_i^2 L_i^2) sqrt(sum_i L_i^-2)``, so ``r >= (n - 3) H``.
    The bound holds for every receiver and source position in the room; it is tight to about
    3 orders for large ``c t`` (a receiver in a corner and an image along the direction that
    minimises ``sum_i m_i^2 L_i^2``).

    Examples
    --------
    >>> order_for_time(Shoebox((6.0, 4.0, 3.0)), 0.02, radius=0.02)
    6
    """
    t = check_range("time", time, 0.0, unit="s")
    a = check_positive("radius", radius, "m")
    return 3 + int(math.floor((medium.c * t + a) / room.lattice_spacing))


def _shell_weights(room: Shoebox, m: int) -> np.ndarray:
    """``W(n) = sum over the images of order n of w^2`` for n = 0..m, per band: ``(m + 1, n_bands)``.

    Per axis the squared weights summed over ``|k| = j`` form a sequence; the shells are their
    three-fold convolution (exact, no enumeration of images).
    """
    b2 = room.reflection.reshape(6, -1) ** 2
    j = np.arange(m + 1)
    out = None
    for i in range(3):
        lo, hi = b2[2 * i], b2[2 * i + 1]
        # k = +j: ceil(j/2) at the far wall, floor(j/2) at the near one; k = -j the other way round
        plus = lo[None, :] ** (j // 2)[:, None] * hi[None, :] ** ((j + 1) // 2)[:, None]
        minus = lo[None, :] ** ((j + 1) // 2)[:, None] * hi[None, :] ** (j // 2)[:, None]
        seq = plus + minus
        seq[0] = 1.0
        if out is None:
            out = seq
        else:
            out = np.stack([np.convolve(out[:, b], seq[:, b])[: m + 1] for b in range(seq.shape[1])], axis=1)
    return out


def energy_order(room: Shoebox, tolerance_db: float = -60.0, *, radius: float, medium: Medium = AIR,
                 duration: float | None = None, max_order: int | None = None) -> ImageOrder:
    """Smallest image order whose neglected energy is below ``tolerance_db`` of the total.

    For energy metrics (LAeq, SEL) and a WAV: the images left out carry at most
    ``10^(tolerance_db/10)`` of the energy, at every receiver in the room.

    Parameters
    ----------
    room : Shoebox
        The room and its absorption.
    tolerance_db : float
        Largest neglected energy relative to the total, in dB, in ``[-200, 0)``.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.
    duration : float, optional
        Length in s of the signal the energy is taken over, from the start of contact; images
        that cannot arrive within it carry none. Required when a surface is rigid
        (alpha = 0), whose infinite image sum has no finite energy.
    max_order : int, optional
        Cap on the order (e.g. :func:`max_order_for_memory`); when it binds, the result says so
        (``capped``) and gives the bound actually reached.

    Returns
    -------
    ImageOrder
        The order, the number of images and the neglected-energy bound in dB (the worst band).

    Notes
    -----
    Energy model: each image adds ``w^2 / r^2`` (an omnidirectional source of unit power; its
    weight w per band). Summing over the images of order n gives the exact shell weight
    ``W(n) = sum w^2`` (:func:`_shell_weights`, a convolution of three per-axis sequences) and
    the distance bounds of the module docstring give, at every receiver in the room,

        neglected <= sum_{n > N} W(n) / ((n - 3) H)^2,
        total >= sum_{n <= N} W(n) / r_max(n)^2,

    both rigorous. Beyond the orders summed explicitly, ``W(n) <= (4 n^2 + 2) beta_max^(2 n)``
    with the largest reflection coefficient ``beta_max`` bounds the rest by a geometric series
    (``(4 n^2 + 2)/(n - 3)^2`` decreases for n > 3). This is a bound, not an estimate, for the
    omnidirectional model; the sphere's far field carries ``cos^2 theta <= 1`` of it, so the
    neglected part stays bounded, while its total at a receiver near the nodal plane of the
    direct sound may fall below the omnidirectional one: for the sphere the figure is an
    estimate, averaged over the images' many directions (mean ``cos^2 theta = 1/3`` for both
    sides).

    Examples
    --------
    >>> room = Shoebox((6.0, 4.0, 3.0), 0.3)
    >>> res = energy_order(room, -30.0, radius=0.02)
    >>> res.order, res.images, res.neglected_db <= -30.0
    (27, 27775, True)
    """
    tol = check_range("tolerance_db", tolerance_db, -200.0, 0.0, unit="dB", high_open=True)
    a = check_positive("radius", radius, "m")
    cap_time = None if duration is None else order_for_time(room, check_positive("duration", duration, "s"),
                                                           radius=a, medium=medium)
    if max_order is not None:
        max_order = _check_order_value("max_order", max_order)
    beta_max = float(room.reflection.max())
    if cap_time is None and beta_max >= 1.0:
        i = int(np.flatnonzero(room.absorption.reshape(6, -1).min(axis=1) == 0.0)[0])
        raise ParameterError(
            "duration", f"required: surface {SURFACES[i]} is rigid (alpha = 0), so the energy of the whole "
                        "image sum is infinite; give the signal's length in s")
    h = room.lattice_spacing
    target = 10.0 ** (tol / 10.0)
    # orders summed explicitly: up to the time cap, or until the geometric remainder is negligible
    m = cap_time if cap_time is not None else 64
    while True:
        n = np.arange(m + 1, dtype=float)
        shells = _shell_weights(room, m)
        included = np.cumsum(shells / _shell_upper_distance(room, n)[:, None] ** 2, axis=0)
        with np.errstate(divide="ignore"):
            lower = _shell_lower_distance(room, n)
            per = np.where(lower[:, None] > 0, shells / np.maximum(lower, 1e-300)[:, None] ** 2, np.inf)
        tail_from = np.cumsum(per[::-1], axis=0)[::-1]  # sum over orders >= n
        rest = 0.0
        if cap_time is None:
            q = beta_max**2
            nn = m + 1.0
            rest = (4 * nn**2 + 2) / ((nn - 3) ** 2 * h**2) * q**nn / (1.0 - q)
        neglected = np.vstack([tail_from[1:], np.zeros((1, shells.shape[1]))]) + rest  # orders > N
        ratio = (neglected / included).max(axis=1)
        ok = np.flatnonzero(ratio <= target)
        if cap_time is not None or (ok.size and rest <= 1e-3 * target * included[-1].min()):
            break
        m *= 2
    order = int(ok[0]) if ok.size else m
    capped = False
    if max_order is not None and order > max_order:
        order, capped = max_order, True
    r = float(ratio[order]) if order <= m else 0.0
    neglected_db = 10.0 * math.log10(r) if r > 0 else -math.inf
    return ImageOrder(order, image_count(order), neglected_db, tol, capped)


# ------------------------------------------------------------------------------- statistical room acoustics
def reverberation_time(room: Shoebox, formula: str = "eyring", *, medium: Medium = AIR):
    """Reverberation time T60 in s by Sabine's or Eyring's formula (per band if banded).

    Parameters
    ----------
    room : Shoebox
        The room and its absorption.
    formula : {"eyring", "sabine"}
        ``"sabine"``: ``T = 24 ln(10) V / (c A)``, ``A = sum_i S_i alpha_i``.
        ``"eyring"``: ``T = 24 ln(10) V / (c S (-ln(1 - alpha_mean)))``, ``alpha_mean = A / S``.
    medium : Medium
        The fluid: its sound speed c in m/s.

    Returns
    -------
    float or (n_bands,) ndarray
        T60 in s (``inf`` with no absorption).

    Notes
    -----
    The energy density of a diffuse field decays as ``exp(-c A' t / (4 V))`` with ``A' = A``
    (Sabine) or ``-S ln(1 - alpha_mean)`` (Eyring, 1930: each of the ``c t S / (4 V)``
    reflections in time t keeps ``1 - alpha_mean`` of the energy). It falls by 60 dB, a factor
    10^6, after ``4 V ln(10^6) / (c A') = 24 ln(10) V / (c A')``; in air at 20 °C
    ``24 ln(10) / c = 0.161`` s/m, Sabine's constant.

    Examples
    --------
    >>> room = Shoebox((6.0, 4.0, 3.0), 0.1)
    >>> round(reverberation_time(room, "sabine"), 3), round(reverberation_time(room, "eyring"), 3)
    (1.073, 1.018)
    """
    if formula not in ("eyring", "sabine"):
        raise ParameterError("formula", f"must be one of 'eyring', 'sabine', got {formula!r}")
    s = room.surface_area
    if formula == "sabine":
        area = np.asarray(room.absorption_area, dtype=float)
    else:
        area = -s * np.log1p(-np.asarray(room.mean_absorption, dtype=float))
    with np.errstate(divide="ignore"):
        t = np.where(area > 0, 24.0 * math.log(10.0) * room.volume / (medium.c * np.maximum(area, 1e-300)),
                     np.inf)
    return float(t) if t.ndim == 0 else t


def mixing_time(room: Shoebox) -> float:
    """Mixing (transition) time in s after which the reflections form a diffuse tail: ``sqrt(V)`` ms.

    Parameters
    ----------
    room : Shoebox
        The room.

    Returns
    -------
    float
        ``1e-3 sqrt(V / 1 m³)`` s (Polack's rule, as evaluated by Lindau, Kosanke and Weinzierl 2012).

    Examples
    --------
    >>> round(mixing_time(Shoebox((6.0, 4.0, 3.0))), 5)
    0.00849
    """
    return 1e-3 * math.sqrt(room.volume)


def echo_density_time(room: Shoebox, spacing: float, *, medium: Medium = AIR) -> float:
    """Time in s at which the mean spacing of the reflections falls to ``spacing``.

    Parameters
    ----------
    room : Shoebox
        The room.
    spacing : float
        Mean time in s between successive reflections, > 0 (e.g. the length of the click, after
        which successive reflections overlap).
    medium : Medium
        The fluid.

    Returns
    -------
    float
        ``t = sqrt(V / (4 pi c^3 spacing))``: the reflection density is ``4 pi c^3 t^2 / V`` per
        second (Kuttruff, ch. 4; Schroeder 1996).

    Examples
    --------
    >>> round(echo_density_time(Shoebox((6.0, 4.0, 3.0)), 1e-4), 4)
    0.0376
    """
    dt = check_positive("spacing", spacing, "s")
    return math.sqrt(room.volume / (4.0 * math.pi * medium.c**3 * dt))


def image_energy_decay(room: Shoebox, times, *, medium: Medium = AIR, nodes: int = 48) -> np.ndarray:
    """Expected rate at which the images' energy arrives, ``dE/dt`` in 1/(m² s), per band.

    Each image contributes ``w^2 / r^2`` (the energy model of :func:`energy_order`); the images
    arriving between t and t + dt number ``4 pi c^3 t^2 dt / V`` (Kuttruff, ch. 4), so
    ``dE/dt = (4 pi c / V) <w^2>``, with ``<w^2>`` averaged over the directions u of the images.
    An image at distance ``r = c t`` in direction u was reflected about ``r |u_i| / (2 L_i)``
    times in each of the two walls normal to axis i, so

        dE/dt = (4 pi c / V) < exp(c t sum_i |u_i| (ln(1 - alpha_i0) + ln(1 - alpha_i1)) / (2 L_i)) >_u.

    Parameters
    ----------
    room : Shoebox
        The room and its absorption.
    times : array_like
        Times in s after the emission (>= 0).
    medium : Medium
        The fluid.
    nodes : int
        Gauss-Legendre nodes per angle of the direction average over one octant (the integrand is
        smooth there).

    Returns
    -------
    ndarray
        Shaped like ``times``, with a trailing band axis when the absorption is banded; in
        1/(m² s).

    Notes
    -----
    Eyring's formula replaces the average of the exponentials by the exponential of the average
    (the mean of ``|u_i|`` over directions is 1/2, so the mean number of reflections per metre is
    ``sum_i 1/(2 L_i) = S / (4 V)``, the inverse of the mean free path). By Jensen's inequality
    the average decays more slowly: a shoebox's image sum reverberates longer than Eyring's time,
    the more so the more elongated the room, since the directions with the fewest reflections
    per metre (along its longest side) dominate late. In a cube the T30 is about 4 % above
    Eyring's; in a 6 x 4 x 3 m room about 14 % (:mod:`tests.test_room`).
    """
    t = np.asarray(times, dtype=float)
    if np.any(~np.isfinite(t)) or np.any(t < 0):
        raise ParameterError("times", "must be finite and >= 0 s")
    x, wq = np.polynomial.legendre.leggauss(int(nodes))
    mu = 0.5 * (x + 1.0)  # cos(theta) in [0, 1]
    phi = 0.25 * np.pi * (x + 1.0)  # [0, pi/2]
    wmu, wphi = 0.5 * wq, 0.25 * np.pi * wq
    st = np.sqrt(1.0 - mu**2)
    ux = np.outer(st, np.cos(phi)).ravel()
    uy = np.outer(st, np.sin(phi)).ravel()
    uz = np.repeat(mu, phi.size)
    wt = np.outer(wmu, wphi).ravel() / (0.5 * np.pi)  # the octant's solid angle is pi/2
    lg = np.log1p(-room.absorption.reshape(6, -1))  # ln(1 - alpha) <= 0
    rate = sum(np.outer(u, (lg[2 * i] + lg[2 * i + 1]) / (2.0 * room.dimensions[i]))
               for i, u in enumerate((ux, uy, uz)))  # (directions, bands), per m of path
    ct = medium.c * t.reshape(-1)
    out = np.einsum("d,tdb->tb", wt, np.exp(ct[:, None, None] * rate[None, :, :]))
    out *= 4.0 * math.pi * medium.c / room.volume
    return out.reshape(t.shape) if room.bands is None else out.reshape(*t.shape, -1)
