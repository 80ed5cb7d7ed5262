"""How far a shoebox room's image sum must go, and how it decays: order rules and reverberation.

Bounds on where images lie
--------------------------
For a receiver anywhere in the room and an image with indices ``k``, the image lies in the cell
``[k L, (k + 1) L]`` of each axis, so ``|x_k - x_r| >= (|k| - 1)^+ L`` and ``<= (|k| + 1) L``. By
Cauchy-Schwarz, ``sum_i (|k_i| - 1)^+ >= n - 3`` gives the distance of every image of order ``n``::

    r >= (n - 3) H,      H = (Lx^-2 + Ly^-2 + Lz^-2)^(-1/2),

and ``r <= sqrt(((n + 1) L_max)^2 + L_mid^2 + L_min^2)`` (the convex bound is largest at a vertex).

The order rules here follow from them: an output that needs the sound until a time t needs
every image that can arrive by then (:func:`order_for_time`); an energy metric needs the images
until the energy of the rest is below a tolerance of the total (:func:`energy_order`).

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
from .medium import AIR, Medium
from .room import SURFACES, Shoebox, check_order, image_count

__all__ = [
    "ImageOrder",
    "order_for_time",
    "energy_order",
    "reverberation_time",
    "mixing_time",
    "echo_density_time",
    "image_energy_decay",
    "complete_until",
]

#: Largest order :func:`energy_order` sums shell by shell before it reports the order as capped
#: (about 3e13 images: far beyond any memory budget).
_ORDER_SEARCH_LIMIT = 32768
#: Shell-weight convolutions of more products than this use an FFT beyond :data:`_EXACT_ORDERS`.
_DIRECT_PRODUCTS = 10**8
#: Orders whose shell weights are always convolved exactly (above any order the memory allows).
_EXACT_ORDERS = 8192


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
    The bound holds for every receiver and source position in the room, and it is tight: in
    the tests' random rooms an image of order N - 1 does arrive by ``time`` at some receiver
    (a corner, the images near the direction that minimises ``sum_i m_i^2 L_i^2``).

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
            out = np.stack([_convolve_head(out[:, b], seq[:, b], m + 1) for b in range(seq.shape[1])], axis=1)
    return out


def _convolve_head(a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    """``np.convolve(a, b)[:n]`` of non-negative sequences, fast for the long ones of a long signal.

    Up to :data:`_DIRECT_PRODUCTS` products, ``np.convolve`` itself. A long signal in a room asks
    for orders in the millions, whose direct convolution would take hours. Their trailing zeros
    are then left out (with absorbing walls the weights, powers of reflection coefficients,
    underflow to exact zeros after a few thousand orders); if what is left is still too long (a
    rigid or nearly rigid room) the orders from :data:`_EXACT_ORDERS` on are convolved by FFT, to
    round-off (clipped at zero, the weights being large there), and those below, among which an
    order is chosen, directly.
    """
    if a.size * b.size <= _DIRECT_PRODUCTS:
        return np.convolve(a, b)[:n]
    la, lb = (int(np.flatnonzero(x)[-1]) + 1 if np.any(x) else 0 for x in (a, b))
    out = np.zeros(n)
    if la * lb <= _DIRECT_PRODUCTS:
        head = np.convolve(a[:la], b[:lb])[:n] if la and lb else out[:0]
        out[: head.size] = head
        return out
    from scipy.signal import fftconvolve

    full = fftconvolve(a[:la], b[:lb])[:n]
    out[: full.size] = np.maximum(full, 0.0)
    k = min(n, _EXACT_ORDERS)
    out[:k] = np.convolve(a[:k], b[:k])[:k]
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
        Cap on the order (e.g. :func:`acoustiviz.core.room.max_order_for_memory`); when it binds,
        the result says so (``capped``) and gives the bound actually reached.

    Returns
    -------
    ImageOrder
        The order, the number of images and the neglected-energy bound in dB (the worst band).

    Notes
    -----
    Energy model: each image adds ``w^2 / r^2`` (an omnidirectional source of unit power; its
    weight w per band). Summing over the images of order n gives the exact shell weight
    ``W(n) = sum w^2`` (:func:`_shell_weights`, a convolution of three per-axis sequences) and
    the distance bounds of the module docstring give, at every receiver in the room::

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
        max_order = check_order("max_order", max_order)
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
        if (max_order is not None and m > max_order) or m >= _ORDER_SEARCH_LIMIT:
            break  # ratio[:m + 1] are bounds already (the remainder is in them); the order is capped below
        m *= 2
    order = int(ok[0]) if ok.size else m
    capped = not ok.size and cap_time is None
    if max_order is not None and order > max_order:
        order, capped = max_order, True
    r = float(ratio[order])
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
    times in each of the two walls normal to axis i, so::

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
    Eyring's; in a 6 x 4 x 3 m room about 14 % (``tests/test_reverberation.py``).
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


# ------------------------------------------------------------------------------- statistical late tail
def complete_until(room: Shoebox, order: int, *, radius: float, medium: Medium = AIR) -> float:
    """Time in s before which the images of order ``<= order`` are every image that arrives.

    Parameters
    ----------
    room : Shoebox
        The room.
    order : int
        Largest image order N kept (>= 0).
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    float
        ``max(0, ((N - 2) H - a) / c)``: every image of order > N is at least ``(N - 2) H`` from
        every point of the room (module docstring), so nothing it radiates arrives earlier. The
        inverse of :func:`order_for_time`; a statistical tail
        (:func:`acoustiviz.core.tail.late_tail`) takes over here.

    Examples
    --------
    >>> round(complete_until(Shoebox((6.0, 4.0, 3.0)), 10, radius=0.02), 5)
    0.05188
    """
    n = check_order("order", order)
    a = check_positive("radius", radius, "m")
    return max(0.0, ((n - 2) * room.lattice_spacing - a) / medium.c)
