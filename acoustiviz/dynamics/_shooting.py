r"""Periodic orbits of the forced damper by shooting, and their Floquet multipliers.

The Poincaré section is the forcing phase 0 (``t = kT``, ``T = 2π/ω``); its points are
``s = (x, v, z, u)`` with ``z = y - x`` and ``u = w - v`` (m, m/s). A period-n orbit solves
``P^n(s) = s``, ``P`` the map over one forcing period integrated by the solver itself (a point
with ``|z| > d/2`` lies inside a contact and is resumed there, see :class:`._forced_steady._Runner`).
:func:`shoot` solves it by Newton's method from a candidate point, in the scaled variables
``s / (X_s, ω X_s, d/2, ω d/2)``, ``X_s = max(|X_lin|, d/2)``.

Jacobian: finite differences of the solver's own map
----------------------------------------------------
The monodromy matrix ``dP^n/ds`` of the Floquet multipliers is taken by central differences of the
event solver (or the impact map, or Newmark) with a step ``h = rtol^{1/3}`` in the scaled variables
(clipped to [1e-6, 1e-3]); the Newton steps take forward differences (:func:`newton_step`). Why
not variational equations with saltation matrices: the contact is compliant (a Hertz spring with
damping c1 integrated by adaptive DOP853), so the event solver has no impact instants at which a
saltation matrix applies; the variational equations would have to be
integrated through every contact inside the compiled kernels, and the Jacobian would be that of
another discretisation than the map whose fixed point is sought. Finite differences of the map
itself cost 4 n cycles (forward) or 8 n (central) per Jacobian (a handful of Newton steps, tens
of cycles against the thousands of a direct run), need no change to the kernels, and apply unchanged to the three
solvers. Their accuracy: truncation ``O(h²)`` plus the map's integration noise ``ε ≈ rtol``
divided by ``h``; ``h = ε^{1/3}`` balances both at ``ε^{2/3}`` (2e-7 at rtol 1e-10, 1e-8 at
1e-12), which is the accuracy of the Floquet multipliers. The Newton residual, which decides
``converged``, is evaluated with the map itself, so the Jacobian's error slows Newton down (a
linear rate of about that error per step, ``rtol^{1/2}`` for the forward differences) but does not
enter the orbit found. A step that crosses a
grazing (an impact appearing or vanishing) makes the difference meaningless; Newton then fails
to reduce the residual and the caller goes on with the direct run.

``J - I`` is solved by a pseudo-inverse: a motion without impacts is a family of orbits (the
impact mass floats anywhere in the cavity), ``J`` has the double multiplier 1 of the free
impact mass, and the minimum-norm step lands on the nearest member.

Why every Newton step takes a fresh Jacobian
--------------------------------------------
In a search in operation the shootings integrate about a fifth of the forcing cycles, and a solve
that converges spends about three quarters of its cycles in its forward-difference Jacobians
(``benchmarks/bench_shooting.py`` counts them by phase). A quasi-Newton method would save part of
those: Broyden's rank-one update of ``J`` after each step, a fresh Jacobian only when a step with
the updated one fails to reduce the residual, costs n cycles a step where Newton costs 5 n. It
converges to the same fixed point within the tolerance, but not to the same bits, and the search
depends on those bits: the point of a periodic orbit seeds the neighbouring frequencies
(:mod:`._forced_response`), and a seeded start that turns chaotic amplifies a change in its last
bit into another transient, other shootings and at times another attractor (``bench_shooting.py
--ulp`` moves every converged point by one unit in the last place: the search's path changes in
every design of the benchmark, and one design's worst case with it). So the iterates of a
converging solve stay those of Newton's method with a fresh Jacobian at every step, computed in a
fixed order of operations (:func:`pinv_solve`), and so do the orbit points. Nor is a failing solve
cut short: no test on its first steps tells it from a converging one (on the benchmark, solves
that converged took up to ten steps, some after a first step that reduced the residual by a few
per cent or a line search down to a sixteenth of the step), and a solve stopped that would have
converged changes the search's path the same way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ._forced_steady import MAX_PERIOD, _Runner, linear_start
from ._status import STATUS_OK

__all__ = ["PoincareMap", "ShootResult", "shoot", "with_multipliers", "section_scale", "STABILITY_MARGIN"]

#: Newton steps tried before giving up.
SHOOT_MAX_ITERATIONS = 10
#: A multiplier is outside the unit circle when its modulus exceeds 1 + this (the resolution of
#: the finite-difference Jacobian; a neutral multiplier 1 is the free impact mass of a motion
#: without impacts).
STABILITY_MARGIN = 1e-5
#: Singular values of ``J - I`` below this fraction of the largest are dropped (pseudo-inverse).
PINV_RCOND = 1e-9


def section_scale(model, excitation) -> np.ndarray:
    """Scale of the section variables ``(x, v, z, u)``: ``(X_s, ω X_s, d/2, ω d/2)`` in m and m/s."""
    hg = 0.5 * model.gap
    xs = max(abs(excitation.linear_response(model)), hg)
    om = excitation.omega
    return np.array([xs, om * xs, hg, om * hg])


def fd_step(rtol: float) -> float:
    """Central-difference step in the scaled variables: ``rtol^{1/3}`` within [1e-6, 1e-3] (module docstring)."""
    return min(max(rtol ** (1.0 / 3.0), 1e-6), 1e-3)


def newton_step(rtol: float) -> float:
    """Forward-difference step of the Newton iterations: ``rtol^{1/2}`` within [1e-7, 1e-4]."""
    return min(max(math.sqrt(rtol), 1e-7), 1e-4)


class PoincareMap:
    """``s -> P^n(s)`` of one solver, counting the cycles it integrates.

    Parameters
    ----------
    model, excitation, settings
        The damper, its excitation and :class:`._forced_steady.SteadyStateOptions`.
    """

    def __init__(self, model, excitation, settings):
        self.run = _Runner(model, excitation, settings, linear_start(model, excitation),
                           rows=settings.max_impacts_per_cycle * MAX_PERIOD)
        self.hg = 0.5 * model.gap
        self.gap = model.gap
        self.acc = np.zeros(5)

    @property
    def cycles(self) -> int:
        """Forcing cycles integrated so far."""
        return self.run.total

    def __call__(self, s, n: int):
        """``P^n(s)`` (m, m/s), or None when ``s`` lies outside the cavity or the solver stops."""
        x, v, z, u = (float(q) for q in s)
        if not all(math.isfinite(q) for q in (x, v, z, u)) or abs(z) > self.hg + 0.01 * self.gap:
            return None
        self.run.set_state((x, v, x + z, v + u))
        _, status, _ = self.run.cycles(n, 0, self.acc, False)  # the n cycles in one compiled call
        return self.run.section() if status == STATUS_OK else None


@dataclass(frozen=True)
class ShootResult:
    """A Newton solve of ``P^n(s) = s``.

    Attributes
    ----------
    converged : bool
        ``residual < tolerance``.
    point : ndarray
        The last iterate ``(x, v, z, u)`` in m and m/s.
    residual : float
        Largest component of ``|P^n(s) - s|`` there (m and m/s); inf when the map failed.
    iterations : int
        Newton steps taken.
    multipliers : ndarray
        Eigenvalues of the monodromy matrix at ``point`` (complex; empty unless converged).
    jacobian : ndarray or None
        ``dP^n/ds`` at ``point`` in the scaled variables (None unless converged).
    """

    converged: bool
    point: np.ndarray
    residual: float
    iterations: int
    multipliers: np.ndarray
    jacobian: np.ndarray | None

    @property
    def stable(self) -> bool:
        """No multiplier beyond ``1 + STABILITY_MARGIN`` in modulus."""
        return bool(self.multipliers.size) and float(np.max(np.abs(self.multipliers))) <= 1.0 + STABILITY_MARGIN


def _jacobian(fun, q, h, f0=None):
    """Finite differences of ``fun`` (scaled variables) at ``q``; None when the map fails.

    Central differences, or forward ones from ``f0 = fun(q)`` when given.

    The step is kept below a quarter of the impact mass's distance to the wall (``1 - |q_z|`` in
    the scaled variables, down to 1e-8) so that no perturbed start crosses a wall: an impact just
    after the section would otherwise move to before it.
    """
    room = 1.0 - abs(q[2])
    if room > 0.0:
        h = min(h, max(0.25 * room, 1e-8))
    jac = np.empty((4, 4))
    for j in range(4):
        e = np.zeros(4)
        e[j] = h
        fp = fun(q + e)
        fm = f0 if f0 is not None else fun(q - e)
        if fp is None or fm is None:
            return None
        jac[:, j] = (fp - fm) / (h if f0 is not None else 2.0 * h)
    return jac


def pinv_solve(a, b, rcond: float) -> np.ndarray:
    """Least-norm solution ``pinv(a) b`` of a small square system, the same on every machine.

    One-sided Jacobi SVD (Hestenes) in plain floating point, in a fixed order of operations:
    the multiple of a step that LAPACK gives through OpenBLAS depends on the processor's kernels
    in its last bits, and a Newton step that lands near a grazing or a basin boundary then sends
    the run to another attractor on another machine. Singular values below ``rcond`` times the
    largest are dropped, as :func:`numpy.linalg.pinv` does.

    Parameters
    ----------
    a : (n, n) array_like
        The matrix (dimensionless, scaled section variables).
    b : (n,) array_like
        Right-hand side.
    rcond : float
        Relative cut-off of the singular values.

    Returns
    -------
    (n,) ndarray
    """
    n = len(b)
    u = [[float(a[i][j]) for i in range(n)] for j in range(n)]  # the columns of a, rotated into U Σ
    v = [[1.0 if i == j else 0.0 for i in range(n)] for j in range(n)]  # the columns of V
    for _ in range(60):
        rotated = False
        for i in range(n - 1):
            for j in range(i + 1, n):
                ci, cj = u[i], u[j]
                alpha = math.fsum(x * x for x in ci)
                beta = math.fsum(x * x for x in cj)
                gamma = math.fsum(x * y for x, y in zip(ci, cj, strict=True))
                if gamma == 0.0 or abs(gamma) <= 1e-15 * math.sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = math.copysign(1.0, zeta) / (abs(zeta) + math.hypot(1.0, zeta))
                c = 1.0 / math.hypot(1.0, t)
                sn = c * t
                for w in (u, v):
                    wi, wj = w[i], w[j]
                    w[i] = [c * x - sn * y for x, y in zip(wi, wj, strict=True)]
                    w[j] = [sn * x + c * y for x, y in zip(wi, wj, strict=True)]
        if not rotated:
            break
    sigma = [math.sqrt(math.fsum(x * x for x in col)) for col in u]
    cut = rcond * max(sigma)
    bb = [float(x) for x in b]
    out = [0.0] * n
    for k in range(n):
        if sigma[k] <= cut or sigma[k] == 0.0:
            continue
        coef = math.fsum(x * y for x, y in zip(u[k], bb, strict=True)) / (sigma[k] * sigma[k])
        out = [o + coef * vk for o, vk in zip(out, v[k], strict=True)]
    return np.array(out)


def shoot(pmap: PoincareMap, s0, n: int, tolerance: float, scale, *, rtol: float = 1e-10,
          max_iterations: int = SHOOT_MAX_ITERATIONS, multipliers: bool = True) -> ShootResult:
    """Newton's method on ``P^n(s) = s`` from ``s0`` (m, m/s); see the module docstring.

    Each step solves ``(J - I) Δ = -(P^n(q) - q)`` in the scaled variables, ``J`` by forward
    differences afresh at every step (4 n cycles; step ``rtol^{1/2}``: its error only slows the
    convergence; no quasi-Newton update, whose orbit points would differ in their last bits, which
    the search depends on: module docstring), and
    halves the step (four times at most) until the residual falls by ``1 - λ/10`` (λ the step
    fraction); a step that cannot ends the solve (``converged=False``): far from an orbit, or
    across a grazing, shooting gives up early and the direct run goes on. At convergence the
    Jacobian is taken by central differences at the orbit point for the Floquet multipliers
    (``multipliers=False`` skips it).
    """
    scale = np.asarray(scale, dtype=float)
    hn = newton_step(rtol)

    def fmap(q):
        p = pmap(q * scale, n)
        return None if p is None else p / scale

    def resid(q, p):
        return float(np.max(np.abs((p - q) * scale)))

    q = np.asarray(s0, dtype=float) / scale
    p = fmap(q)
    if p is None:
        return ShootResult(False, q * scale, math.inf, 0, np.empty(0, dtype=complex), None)
    res = resid(q, p)
    it = 0
    while res >= tolerance and it < max_iterations:
        jac = _jacobian(fmap, q, hn, p)
        if jac is None:
            break
        a = jac - np.eye(4)
        dq = -pinv_solve(a, p - q, PINV_RCOND)
        lam, accepted = 1.0, False
        for _ in range(5):
            qn = q + lam * dq
            pn = fmap(qn)
            if pn is not None:
                rn = resid(qn, pn)
                if rn < (1.0 - 0.1 * lam) * res:
                    accepted = True
                    break
            lam *= 0.5
        it += 1
        if not accepted:
            break
        q, p, res = qn, pn, rn
    out = ShootResult(bool(res < tolerance), q * scale, res, it, np.empty(0, dtype=complex), None)
    return with_multipliers(pmap, out, n, scale, rtol=rtol) if multipliers else out


def with_multipliers(pmap: PoincareMap, shot: ShootResult, n: int, scale, *, rtol: float = 1e-10) -> ShootResult:
    """``shot`` with its Floquet multipliers and Jacobian (central differences at its point) when converged.

    What :func:`shoot` does at convergence; apart, so that a caller may first tell a known orbit.
    """
    if not shot.converged:
        return shot
    scale = np.asarray(scale, dtype=float)

    def fmap(q):
        p = pmap(q * scale, n)
        return None if p is None else p / scale

    mult = np.empty(0, dtype=complex)
    jac = _jacobian(fmap, shot.point / scale, fd_step(rtol))
    if jac is not None:
        mult = np.linalg.eigvals(jac).astype(complex)
        mult = mult[np.argsort(-np.abs(mult), kind="stable")]
    return replace(shot, multipliers=mult, jacobian=jac)
