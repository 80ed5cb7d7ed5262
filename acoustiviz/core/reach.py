"""How far a circle or a balloon around the sphere may reach before it leaves the fluid.

A directivity's circle (:meth:`acoustiviz.core.geometry.Geometry.observer_points`) and a balloon's
sphere of directions (:meth:`~acoustiviz.core.geometry.Geometry.view_region`) must stay in the
fluid: unbounded for the paper's geometries (their planes bound the directions, not the radius),
bounded by the walls and the ceiling in a room. The limits follow from the geometry's planes
alone, so every geometry gets them. All lengths in m.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import ParameterError

__all__ = ["circle_limit", "view_limit", "check_view_radius"]


def circle_limit(geometry) -> float:
    """Largest radius in m of the observer circle of ``geometry`` that stays in the fluid.

    The circle around the sphere's centre in the plane of the axis ``u`` and the side direction
    ``v`` (:meth:`~acoustiviz.core.geometry.Geometry.observer_points`), from 0 to its
    ``polar_limit_deg``: for each plane (normal ``n`` into the fluid, the centre at height ``h``
    above it) the circle reaches the plane at the radius ``h / m``, with ``m`` the largest of
    ``-(cos θ u + sin θ v) . n = A cos θ + B sin θ`` over the polar range (``sqrt(A^2 + B^2)`` at
    ``θ = atan2(B, A)`` when that angle lies in the range, else at its ends). ``inf`` when no plane
    is in the way.

    Examples
    --------
    >>> from acoustiviz.core.geometry import geometry
    >>> circle_limit(geometry("plane", 0.01))
    inf
    >>> round(circle_limit(geometry("room", 0.01, dimensions=(3, 2, 2), source=(1, 1, 0.01), duration=0.01)), 6)
    1.99
    """
    c = np.asarray(geometry.centre, dtype=float)
    u = np.asarray(geometry.axis, dtype=float)
    v = geometry.observer_points(1.0, math.pi / 2)[0] - c
    top = math.radians(geometry.polar_limit_deg)
    best = math.inf
    for pl in geometry.planes:
        a_, b_ = -float(u @ pl.normal), -float(v @ pl.normal)
        ends = [a_, a_ * math.cos(top) + b_ * math.sin(top)]
        if -1e-12 <= math.atan2(b_, a_) <= top + 1e-12:
            ends.append(math.hypot(a_, b_))
        m = max(ends)
        if m > 1e-12:
            best = min(best, float((c - pl.point) @ pl.normal) / m)
    return best


def view_limit(geometry) -> float:
    """Largest radius in m of a balloon around the view region of ``geometry`` that stays in the fluid.

    For each plane (normal ``n``, the region's anchor at height ``h`` above it) the region's
    directions ``d`` reach at most ``m = max(-d . n)`` towards it: 1 over the whole sphere of
    directions; over the half space about ``up``, 1 when ``-n`` lies in it, else
    ``sqrt(1 - (n . up)^2)``; the radius is then at most ``h / m``. ``inf`` when no plane is in the
    way (a quarter space's two planes bound its directions and are not counted).
    """
    reg = geometry.view_region()
    if reg.kind == "quarter":
        return math.inf
    up = np.asarray(reg.up, dtype=float)
    best = math.inf
    for pl in geometry.planes:
        n = np.asarray(pl.normal, dtype=float)
        m = 1.0 if reg.kind == "sphere" or float(-n @ up) >= 0.0 else math.sqrt(max(0.0, 1.0 - float(n @ up) ** 2))
        if m > 1e-12:
            best = min(best, float((np.asarray(reg.origin) - pl.point) @ n) / m)
    return best


def check_view_radius(geometry, distance: float, lowest: float) -> float:
    """``distance`` (m) if a balloon of that radius fits in the fluid of ``geometry``, else an error naming it.

    ``lowest`` (m) is the exclusive lower bound (the balloon's clearance of the sphere); the upper
    bound is :func:`view_limit`. The message gives the range and where the balloon is anchored.
    """
    r, top = float(distance), view_limit(geometry)
    if not lowest < r <= top:
        span = f"({lowest:g}, {top:.6g}]" if math.isfinite(top) else f"({lowest:g}, inf)"
        origin = ", ".join(f"{float(x):.6g}" for x in geometry.view_region().origin)
        raise ParameterError("distance", f"must lie in {span} m for the measuring sphere around ({origin}) m "
                                         f"to stay in the fluid ({geometry.fluid_text()}), got {r:g} m")
    return r
