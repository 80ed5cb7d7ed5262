"""Observer grids: spherical grids with quadrature weights, and planar grids of any orientation.

Spherical grids sample a sphere of directions around a centre -- the whole sphere, the half
space above a plane or the quarter space of a wall-floor corner -- with weights ``w_i`` in
steradians such that ``Σ w_i f(x_i) ≈ ∫ f dΩ``: Gauss-Legendre nodes in ``cos θ`` and, in
azimuth, the trapezoidal rule (whole turn) or Gauss-Legendre (half turn). The weights sum to
the solid angle (4π, 2π, π) and integrate polynomials in the direction cosines exactly up to a
degree set by the resolution, so spherical averages and radiated energies come out right.

Planar grids are regular ``n_u × n_v`` lattices on a rectangle of any position and
orientation; :func:`section_grid` lays one through the sphere along two axes of the scene, cut
at the floor and the walls so that no point lies behind a reflecting plane. Both kinds convert
to a :class:`pyvista.StructuredGrid` (pyvista is imported only then). Points are ``(n, 3)`` arrays in m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice, check_positive
from ..constants import SECTION_PLANES

__all__ = [
    "REGIONS",
    "SOLID_ANGLE",
    "SphericalGrid",
    "PlanarGrid",
    "spherical_grid",
    "spherical_grid_for",
    "planar_grid",
    "SECTIONS",
    "fluid_box",
    "section_rectangle",
    "section_grid",
]

#: Regions of a spherical grid.
REGIONS = ("sphere", "half", "quarter")
#: Solid angle in sr of each region.
SOLID_ANGLE = {"sphere": 4 * math.pi, "half": 2 * math.pi, "quarter": math.pi}
#: Sections through the sphere, named by the two axes they hold -> the indices of those axes:
#: ``"xz"`` the vertical plane normal to the wall (holding the acceleration axis), ``"yz"`` the
#: vertical plane parallel to the wall, ``"xy"`` a horizontal plane.
SECTIONS = {name: ("xyz".index(name[0]), "xyz".index(name[1])) for name in SECTION_PLANES}


def _unit(name, v):
    a = np.asarray(v, dtype=float).reshape(-1)
    n = float(np.linalg.norm(a)) if a.shape == (3,) else 0.0
    if not (n > 0 and math.isfinite(n)):
        raise ParameterError(name, f"expected a non-zero finite 3-vector, got {v!r}")
    return a / n


def _count(name, n, low):
    if int(n) != n or n < low:
        raise ParameterError(name, f"must be an integer >= {low}, got {n!r}")
    return int(n)


def _structured(points: np.ndarray, n_fast: int, n_slow: int):
    import pyvista as pv

    x, y, z = (points[:, k].reshape(n_slow, n_fast).T[..., None] for k in range(3))
    return pv.StructuredGrid(x, y, z)


@dataclass(frozen=True)
class SphericalGrid:
    """Points on (part of) a sphere with quadrature weights in steradians.

    Attributes
    ----------
    points : (n, 3) ndarray
        Positions in m, azimuth varying fastest.
    weights : (n,) ndarray
        Solid-angle weights in sr; they sum to :attr:`solid_angle`.
    directions : (n, 3) ndarray
        Unit vectors from the centre to the points.
    centre : (3,) ndarray
        Centre in m.
    radius : float
        Radius in m.
    region : str
        ``"sphere"``, ``"half"`` or ``"quarter"``.
    n_theta, n_phi : int
        Nodes in polar angle and azimuth.
    """

    points: np.ndarray
    weights: np.ndarray
    directions: np.ndarray
    centre: np.ndarray
    radius: float
    region: str
    n_theta: int
    n_phi: int

    @property
    def solid_angle(self) -> float:
        """Solid angle covered, in sr."""
        return SOLID_ANGLE[self.region]

    @property
    def area_weights(self) -> np.ndarray:
        """Area weights in m² (``radius² × weights``)."""
        return self.radius**2 * self.weights

    def integrate(self, values) -> np.ndarray:
        """``∫ f dΩ`` in (unit of f)·sr from values at the points (first axis)."""
        v = np.asarray(values, dtype=float)
        if v.shape[0] != self.weights.size:
            raise ParameterError("values", f"first axis must have {self.weights.size} entries, got {v.shape[0]}")
        return np.tensordot(self.weights, v, axes=(0, 0))

    def average(self, values) -> np.ndarray:
        """Spherical average of ``values`` over the region (same unit as the values)."""
        return self.integrate(values) / self.solid_angle

    def to_pyvista(self):
        """The grid as a :class:`pyvista.StructuredGrid` (n_phi × n_theta × 1), points in order."""
        return _structured(self.points, self.n_phi, self.n_theta)


def spherical_grid(
    radius: float,
    *,
    region: str = "sphere",
    centre=(0.0, 0.0, 0.0),
    up=(0.0, 0.0, 1.0),
    side=(1.0, 0.0, 0.0),
    n_theta: int = 32,
    n_phi=None,
) -> SphericalGrid:
    """A spherical grid of directions with quadrature weights.

    Parameters
    ----------
    radius : float
        Radius of the sphere in m.
    region : {"sphere", "half", "quarter"}
        All directions (4π sr); those with ``d·up >= 0`` (2π sr, the half space above a
        plane of normal ``up``); or those with ``d·up >= 0`` and ``d·side >= 0`` (π sr, the
        quarter space of a corner whose planes have normals ``up`` and ``side``).
    centre : (3,) array_like
        Centre in m (on the plane, or on the corner's edge, for the half and quarter regions).
    up, side : (3,) array_like
        Polar axis and azimuth origin; ``side`` is made orthogonal to ``up``.
    n_theta : int
        Gauss-Legendre nodes in ``cos θ`` (>= 2).
    n_phi : int, optional
        Azimuth nodes (default ``2 n_theta``).

    Returns
    -------
    SphericalGrid

    Notes
    -----
    With ``μ = cos θ`` the rule is exact for polynomials in the direction cosines of degree
    up to ``2 n_theta - 1`` in ``μ`` and, in azimuth, up to ``n_phi - 1`` (trapezoid over a full
    turn). Over the half turn of the quarter region Gauss-Legendre in φ converges exponentially
    (trigonometric polynomials are not polynomials in φ): with the default ``n_phi`` the
    error for polynomials of degree <= 6 in the direction cosines is below 1e-13 at
    ``n_theta = 10``.

    Examples
    --------
    >>> g = spherical_grid(1.0, region="half", n_theta=4)
    >>> round(float(g.weights.sum() / np.pi), 12)
    2.0
    """
    r = check_positive("radius", radius, "m")
    check_choice("region", region, REGIONS)
    nt = _count("n_theta", n_theta, 2)
    npf = _count("n_phi", 2 * nt if n_phi is None else n_phi, 3 if region != "quarter" else 2)
    c = np.asarray(centre, dtype=float).reshape(3)
    e3 = _unit("up", up)
    s = np.asarray(side, dtype=float).reshape(3) - np.dot(side, e3) * e3
    e1 = _unit("side", s)
    e2 = np.cross(e3, e1)
    x, w = np.polynomial.legendre.leggauss(nt)
    if region == "sphere":
        mu, wmu = x, w
    else:  # μ in [0, 1]
        mu, wmu = 0.5 * (x + 1.0), 0.5 * w
    if region == "quarter":  # φ in [-π/2, π/2]
        xp, wp = np.polynomial.legendre.leggauss(npf)
        phi, wphi = 0.5 * math.pi * xp, 0.5 * math.pi * wp
    else:
        phi = 2.0 * math.pi * np.arange(npf) / npf
        wphi = np.full(npf, 2.0 * math.pi / npf)
    sin_t = np.sqrt(np.clip(1.0 - mu * mu, 0.0, None))
    d = (
        (sin_t[:, None, None] * np.cos(phi)[None, :, None]) * e1
        + (sin_t[:, None, None] * np.sin(phi)[None, :, None]) * e2
        + mu[:, None, None] * e3
    ).reshape(-1, 3)
    weights = (wmu[:, None] * wphi[None, :]).reshape(-1)
    return SphericalGrid(c + r * d, weights, d, c, r, region, nt, npf)


def spherical_grid_for(geometry, radius: float, *, n_theta: int = 32, n_phi=None) -> SphericalGrid:
    """The spherical grid that closes the fluid region of a geometry.

    The region is the geometry's :meth:`~acoustiviz.core.geometry.Geometry.enclosure`: for the
    free field the whole sphere around the sphere's centre, for the plane the half space around
    the contact point on the plane, for the wall-floor corner the quarter space around the point
    of the corner's edge nearest the sphere. With rigid planes (zero normal velocity) such a
    surface encloses all the radiated energy.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The scene.
    radius : float
        Radius in m; for the half and quarter regions it must keep the grid clear of the
        sphere (checked).
    n_theta, n_phi : int
        Resolution (see :func:`spherical_grid`).

    Returns
    -------
    SphericalGrid
    """
    reg = geometry.enclosure()
    g = spherical_grid(radius, region=reg.kind, centre=reg.origin, up=reg.up, side=reg.side, n_theta=n_theta,
                       n_phi=n_phi)
    dist = np.linalg.norm(g.points - geometry.centre, axis=1)
    if np.any(dist < geometry.radius) or not np.all(geometry.in_fluid(g.points)):
        raise ParameterError("radius", f"{radius:g} m puts grid points inside the sphere or a wall; make it larger")
    return g


@dataclass(frozen=True)
class PlanarGrid:
    """A regular lattice on a rectangle ``origin + i du + j dv``.

    Attributes
    ----------
    points : (n_u n_v, 3) ndarray
        Positions in m, ``u`` varying fastest.
    origin : (3,) ndarray
        First corner in m.
    u, v : (3,) ndarray
        Edge vectors in m (the whole extent along each side).
    n_u, n_v : int
        Number of points along ``u`` and ``v``.
    """

    points: np.ndarray
    origin: np.ndarray
    u: np.ndarray
    v: np.ndarray
    n_u: int
    n_v: int

    @property
    def shape(self) -> tuple:
        """``(n_v, n_u)``: the shape of :meth:`image` arrays."""
        return (self.n_v, self.n_u)

    @property
    def normal(self) -> np.ndarray:
        """Unit normal ``u × v / |u × v|``."""
        n = np.cross(self.u, self.v)
        return n / np.linalg.norm(n)

    @property
    def extent(self) -> tuple:
        """``(0, |u|, 0, |v|)`` in m: in-plane coordinates for ``imshow(..., origin="lower")``."""
        return (0.0, float(np.linalg.norm(self.u)), 0.0, float(np.linalg.norm(self.v)))

    def local(self, points) -> np.ndarray:
        """In-plane coordinates ``(s, t)`` in m of points along ``u`` and ``v`` from the origin."""
        p = np.asarray(points, dtype=float) - self.origin
        return np.stack([p @ self.u / np.linalg.norm(self.u), p @ self.v / np.linalg.norm(self.v)], axis=-1)

    def image(self, values) -> np.ndarray:
        """Values at the points (last axis) reshaped to ``(..., n_v, n_u)`` for plotting."""
        v = np.asarray(values)
        return v.reshape(*v.shape[:-1], self.n_v, self.n_u)

    def to_pyvista(self):
        """The grid as a :class:`pyvista.StructuredGrid` (n_u × n_v × 1), points in order."""
        return _structured(self.points, self.n_u, self.n_v)


def planar_grid(centre, u, v, n_u: int = 101, n_v=None) -> PlanarGrid:
    """A rectangular grid of points centred at ``centre`` spanning edge vectors ``u`` and ``v``.

    Parameters
    ----------
    centre : (3,) array_like
        Centre of the rectangle in m.
    u, v : (3,) array_like
        Edge vectors in m: the rectangle is ``centre + α u + β v`` with α, β in [-1/2, 1/2].
        Any orientation; they need not be orthogonal, only independent.
    n_u, n_v : int
        Points along ``u`` and ``v`` (>= 2; ``n_v`` defaults to keep the spacing square).

    Returns
    -------
    PlanarGrid

    Examples
    --------
    >>> g = planar_grid((0, 0, 0.1), (0.2, 0, 0), (0, 0, 0.2), n_u=3)
    >>> g.points.shape, g.shape
    ((9, 3), (3, 3))
    """
    c = np.asarray(centre, dtype=float).reshape(3)
    uu = np.asarray(u, dtype=float).reshape(3)
    vv = np.asarray(v, dtype=float).reshape(3)
    if not np.all(np.isfinite(np.r_[c, uu, vv])):
        raise ParameterError("centre", "centre, u and v must be finite")
    lu, lv = float(np.linalg.norm(uu)), float(np.linalg.norm(vv))
    if not (lu > 0 and lv > 0) or np.linalg.norm(np.cross(uu, vv)) < 1e-12 * lu * lv:
        raise ParameterError("u", "u and v must be non-zero and not parallel")
    nu = _count("n_u", n_u, 2)
    nv = _count("n_v", max(2, round((nu - 1) * lv / lu) + 1) if n_v is None else n_v, 2)
    origin = c - 0.5 * uu - 0.5 * vv
    a = np.linspace(0.0, 1.0, nu)
    b = np.linspace(0.0, 1.0, nv)
    pts = origin + (b[:, None, None] * vv + a[None, :, None] * uu).reshape(-1, 3)
    return PlanarGrid(pts, origin, uu, vv, nu, nv)


def fluid_box(geometry, lo, hi) -> tuple:
    """The box ``[lo, hi]`` cut at each plane of ``geometry`` on the side away from the fluid.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The scene; each of its planes is normal to an axis (the floor's z, a wall's x or y).
    lo, hi : (3,) array_like
        Lower and upper corners in m.

    Returns
    -------
    (lo, hi) : two (3,) ndarray
        The corners in m, raised to a plane facing up its axis and lowered to one facing down it.
    """
    lo = np.array(lo, dtype=float)
    hi = np.array(hi, dtype=float)
    for p in geometry.planes:
        k = int(np.argmax(np.abs(p.normal)))
        if p.normal[k] > 0:
            lo[k] = max(lo[k], float(p.point[k]))
        else:
            hi[k] = min(hi[k], float(p.point[k]))
    return lo, hi


def section_rectangle(geometry, section: str, extent: float, n_long: int, *, level=None) -> tuple:
    """The rectangle and point counts of :func:`section_grid`, without building its points.

    Parameters and notes as for :func:`section_grid` (a caller checks the size of a grid from
    the counts before it builds it).

    Returns
    -------
    (centre, u, v, n_u, n_v)
        Centre and edge vectors in m (the arguments of :func:`planar_grid`) and the counts.
    """
    check_choice("section", section, tuple(SECTIONS))
    c = np.asarray(geometry.centre, dtype=float)
    lo, hi = fluid_box(geometry, c - extent, c + extent)
    i, j = SECTIONS[section]
    centre = c.copy()
    centre[i] = 0.5 * (lo[i] + hi[i])
    centre[j] = 0.5 * (lo[j] + hi[j])
    if level is not None:
        centre[3 - i - j] = float(level)
    u, v = np.zeros(3), np.zeros(3)
    u[i], v[j] = hi[i] - lo[i], hi[j] - lo[j]
    long = max(u[i], v[j])
    nu = max(2, int(round((n_long - 1) * u[i] / long)) + 1)
    nv = max(2, int(round((n_long - 1) * v[j] / long)) + 1)
    return centre, u, v, nu, nv


def section_grid(geometry, section: str, extent: float, n_long: int, *, level=None) -> PlanarGrid:
    """A planar grid through the sphere along two axes, reaching ``extent`` from its centre, cut at the planes.

    The square of half-side ``extent`` around the sphere's centre in the plane of ``section`` is
    cut by :func:`fluid_box`, so every point lies on the fluid's side of every plane (points
    inside the sphere are kept: the field there is NaN).

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its planes.
    section : {"xz", "yz", "xy"}
        The two axes the grid spans (see :data:`SECTIONS`).
    extent : float
        Distance in m from the sphere's centre to the far edges (checked by the caller).
    n_long : int
        Points along the longer side (>= 2, checked by the caller); the other side keeps the
        spacing as near square as whole counts allow.
    level : float, optional
        Coordinate in m of the plane along its normal axis (default: the sphere centre's).

    Returns
    -------
    PlanarGrid
        Edge ``u`` along the first axis of ``section``, ``v`` along the second.

    Examples
    --------
    >>> from acoustiviz.core.geometry import geometry
    >>> g = section_grid(geometry("plane", 0.01905), "xz", 0.2, 21)
    >>> g.shape, round(float(g.points[:, 2].min()), 6)  # cut at the floor z = 0
    ((12, 21), 0.0)
    """
    centre, u, v, nu, nv = section_rectangle(geometry, section, extent, n_long, level=level)
    return planar_grid(centre, u, v, n_u=nu, n_v=nv)
