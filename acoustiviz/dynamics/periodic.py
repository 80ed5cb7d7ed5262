r"""Closed-form periodic references of the forced damper: the linear limit and Masri-Caughey.

Linear limit
------------
Without impacts the main mass alone obeys ``M x'' + C x' + K x = P cos ωt + Q sin ωt`` and its
steady state is ``x = Re(X e^{iωt})`` with ``X = (P - iQ)/(K - Mω² + iCω)``
(:func:`linear_amplitude`).

Symmetric two impacts per cycle (Masri and Caughey, 1966)
---------------------------------------------------------
With instantaneous impacts of restitution ``e`` (momentum conserved,
``w⁺ - v⁺ = -e (w⁻ - v⁻)``) look for a motion with one impact on each wall per period
``T = 2π/ω``, half a period apart, the second the mirror image of the first. Put the impact on
wall +1 (``z = y - x = +d/2``) at ``t = 0`` with the force ``F(t) = Re(F̂ e^{i(ωt + φ)})``,
``F̂ = P - iQ``, and let ``x₀`` be the main-mass displacement there. Symmetry gives the
state at ``T/2``: ``x = -x₀``, pre-impact velocities ``-v⁻`` and ``-W`` (``W = w⁻`` the impact
mass's approach velocity at ``t = 0``), so the impact mass flies at ``w⁺ = -W``. Then

* the flight of the impact mass across the gap, ``z(T/2) - z(0) = -d``, gives
  ``W = 2ω (x₀ + d/2) / π``;
* momentum and restitution give ``v⁻ = κ⁻ W`` and ``v⁺ = κ⁺ W`` with
  ``κ⁻ = -(1 + 2μ - e)/(1 + e)``, ``κ⁺ = (e - 1 + 2μe)/(1 + e)``, ``μ = m/M``;
* the main mass flies as a forced damped oscillator: with ``x_p`` the particular solution and
  ``Φ`` the free oscillator's transition matrix over ``T/2``, ``x_p(t + T/2) = -x_p(t)`` turns the
  mirror condition into ``(Φ + I) [p, q]ᵀ = Φ [x₀, v⁺]ᵀ + [x₀, v⁻]ᵀ`` with
  ``p = x_p(0) = |X| cos ψ``, ``q = x_p'(0) = -ω |X| sin ψ``, ``ψ = φ + arg X``.

The last line is affine in ``x₀``: ``[p, q] = a x₀ + b``; ``p² + (q/ω)² = |X|²`` is then a
quadratic in ``x₀`` with up to two roots (the two branches of Masri and Caughey), each giving
the phase ``ψ``. A root is kept when ``W > 0`` and the impact mass stays inside the cavity
between the impacts. The undamped case ``C = 0`` is the original paper's; the derivation holds
for any underdamped ``C`` and for base excitation through ``F̂``.

References: S. F. Masri and T. K. Caughey, "On the stability of the impact damper", J. Appl.
Mech. 33 (1966) 586-592.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_range
from ._forced_steady import Excitation
from .model import DamperModel

__all__ = ["MasriCaughey", "linear_amplitude", "masri_caughey", "transition_matrix"]


def linear_amplitude(model: DamperModel, excitation: Excitation) -> float:
    """Steady amplitude |X| in m of the main mass without impacts (module docstring)."""
    return abs(excitation.linear_response(model))


def transition_matrix(model: DamperModel, tau: float) -> np.ndarray:
    """2x2 matrix taking ``(x, v)`` of the free damped main oscillator over ``tau`` s (SI)."""
    a = model.C / (2.0 * model.M)
    wd = math.sqrt(model.K / model.M - a * a)
    e = math.exp(-a * tau)
    c, s = math.cos(wd * tau), math.sin(wd * tau)
    return e * np.array([[c + a * s / wd, s / wd],
                         [-(a * a + wd * wd) * s / wd, c - a * s / wd]])


@dataclass(frozen=True)
class MasriCaughey:
    """One symmetric two-impacts-per-cycle periodic motion (module docstring).

    Attributes
    ----------
    x0 : float
        Main-mass displacement at the impact on wall +1, in m.
    phase : float
        Forcing phase ``ωt mod 2π`` of that impact in rad (the wall -1 impact is at phase + π).
    approach_speed : float
        Relative approach speed ``W - v⁻`` at each impact, in m/s.
    v_before, v_after, w_before : float
        Main-mass velocity before/after and impact-mass velocity before the wall +1 impact, m/s.
    amplitude : float
        Largest |x| over the cycle, in m.
    valid : bool
        True when ``W > 0`` and the impact mass stays in the cavity between impacts.
    """

    x0: float
    phase: float
    approach_speed: float
    v_before: float
    v_after: float
    w_before: float
    amplitude: float
    valid: bool

    def motion(self, model: DamperModel, excitation: Excitation, t):
        """Main-mass displacement x (m), velocity v (m/s) and relative displacement z (m).

        ``t`` in s lies in [0, T/2] after the wall +1 impact.
        """
        t = np.asarray(t, dtype=float)
        X = excitation.linear_response(model)
        om = excitation.omega
        rot = X * np.exp(1j * (om * t + self.phase))
        xp, vp = rot.real, (1j * om * rot).real
        p0 = (X * np.exp(1j * self.phase)).real
        q0 = (1j * om * X * np.exp(1j * self.phase)).real
        a = model.C / (2.0 * model.M)
        wd = math.sqrt(model.K / model.M - a * a)
        xh0, vh0 = self.x0 - p0, self.v_after - q0
        b = (vh0 + a * xh0) / wd
        ex, c, s = np.exp(-a * t), np.cos(wd * t), np.sin(wd * t)
        xh = ex * (xh0 * c + b * s)
        vh = ex * ((b * wd - a * xh0) * c - (xh0 * wd + a * b) * s)
        x = xh + xp
        y = self.x0 + 0.5 * model.gap - self.w_before * t
        return x, vh + vp, y - x

    def state(self, model: DamperModel, excitation: Excitation, t: float) -> tuple:
        """``(x, v, y, w)`` in m and m/s at time ``t`` s, the impacts being at ``ωt = phase (+π)``."""
        om = excitation.omega
        period = 2.0 * math.pi / om
        s = (t - self.phase / om) % period  # time since the wall +1 impact
        sign = 1.0
        if s > 0.5 * period:  # after the mirrored wall -1 impact
            s -= 0.5 * period
            sign = -1.0
        x, v, z = (float(q) for q in self.motion(model, excitation, s))
        return sign * x, sign * v, sign * (x + z), -sign * self.w_before


def _largest(sol, model, excitation, t, ax) -> float:
    """Largest |x| in m over [0, T/2]: the best sample refined by a bounded scalar search (to ~1e-15 s)."""
    from scipy.optimize import minimize_scalar

    k = int(np.argmax(ax))
    lo, hi = t[max(k - 1, 0)], t[min(k + 1, t.size - 1)]
    best = float(ax[k])
    if hi > lo:
        res = minimize_scalar(lambda s: -abs(float(sol.motion(model, excitation, s)[0])), bounds=(lo, hi),
                              method="bounded", options={"xatol": 1e-15})
        best = max(best, -float(res.fun))
    return best


def masri_caughey(model: DamperModel, excitation: Excitation, restitution: float) -> list[MasriCaughey]:
    """The symmetric two-impacts-per-cycle periodic motions (Masri and Caughey, 1966).

    Parameters
    ----------
    model : DamperModel
        The damper; its contact parameters are not used (impacts are instantaneous).
    excitation : Excitation
        Harmonic force or base motion.
    restitution : float
        Coefficient of restitution e in (0, 1].

    Returns
    -------
    list of MasriCaughey
        Zero, one or two solutions (both roots of the quadratic, with their ``valid`` flag),
        largest amplitude first. Their stability is not assessed here.
    """
    e = check_range("restitution", restitution, 0.0, 1.0, low_open=True)
    if not model.underdamped:
        raise ParameterError("C", "the closed form needs an underdamped main oscillator")
    om = excitation.omega
    hg = 0.5 * model.gap
    mu = model.m / model.M
    X = excitation.linear_response(model)
    kp = (e - 1.0 + 2.0 * mu * e) / (1.0 + e)
    km = -(1.0 + 2.0 * mu - e) / (1.0 + e)
    cw = 2.0 * om / math.pi  # W = cw (x0 + hg)
    phi = transition_matrix(model, math.pi / om)
    g_inv = np.linalg.inv(phi + np.eye(2))
    # [p, q] = a x0 + b
    a = g_inv @ (phi @ np.array([1.0, kp * cw]) + np.array([1.0, km * cw]))
    b = g_inv @ (phi @ np.array([0.0, kp * cw * hg]) + np.array([0.0, km * cw * hg]))
    s = np.array([1.0, 1.0 / om])
    qa = np.sum((a * s) ** 2)
    qb = 2.0 * np.sum(a * b * s * s)
    qc = np.sum((b * s) ** 2) - abs(X) ** 2
    disc = qb * qb - 4.0 * qa * qc
    if disc < 0.0:
        return []
    roots = {(-qb + math.sqrt(disc)) / (2.0 * qa), (-qb - math.sqrt(disc)) / (2.0 * qa)}
    out = []
    for x0 in roots:
        p, q = a * x0 + b
        psi = math.atan2(-q / om, p)
        ph = math.remainder(psi - math.atan2(X.imag, X.real), 2.0 * math.pi) % (2.0 * math.pi)
        w_before = cw * (x0 + hg)
        sol = MasriCaughey(x0=float(x0), phase=float(ph), approach_speed=float(w_before * (1.0 - km)),
                           v_before=float(km * w_before), v_after=float(kp * w_before),
                           w_before=float(w_before), amplitude=math.nan, valid=False)
        t = np.linspace(0.0, math.pi / om, 4001)
        x, _, z = sol.motion(model, excitation, t)
        inside = bool(np.all(np.abs(z[1:-1]) <= hg * (1.0 + 1e-9)))
        amp = _largest(sol, model, excitation, t, np.abs(x))
        out.append(MasriCaughey(sol.x0, sol.phase, sol.approach_speed, sol.v_before, sol.v_after,
                                sol.w_before, amp, bool(w_before > 0.0 and inside)))
    return sorted(out, key=lambda r: -r.amplitude)
