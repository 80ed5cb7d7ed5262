"""One contact of the impact damper, integrated by Dormand-Prince 8(5,3) in a regularising time (numba).

Free decay and forced operation share this solver; the external force
``F(t) = P cos(ωt) + Q sin(ωt)`` on the main mass is a parameter (the forcing vector ``fc``,
None for none). During a contact on wall ``s = ±1`` with penetration ``δ = s z - d/2`` (paper eq 15)::

    M x'' = s F_c - K x - C x' + F(t),    m y'' = -s F_c,    F_c = K_HZ δ^{3/2} + c1 dδ/dt.

The contact is integrated in a transformed time σ with dt = ξ dσ, where ξ = sqrt(δ) is a state
variable (dξ/dσ = u/2). The Hertz force becomes K_HZ ξ³, a polynomial, so the δ^{3/2}
singularities at contact onset and end (solution terms in t^{3.5}) disappear: the solution is
analytic in σ and the 8th-order steps stay long up to both ends. The contact ends at the simple
root ξ = 0 (dξ/dσ = u/2 < 0 there), located by Newton's method on full Runge-Kutta steps.
State (``NY`` components, ``NY + 1`` with forcing): t (s, from onset), x (m), v (m/s), ξ (m^0.5), u = dδ/dt
(m/s), impulse (N s), dissipated in contact (J), dissipated by C (J) and, with forcing, the work
of F on the main mass (J). Without forcing (``fc`` None) numba compiles a specialisation in which
the ninth component and the evaluation of F do not exist: zero forcing costs nothing.

Model: :class:`~acoustiviz.dynamics._records.Params` (``free_restitution``, called from Python,
takes the parameter vector ``p``).
Forcing vector ``fc``: None, or ``[ω rad/s, P N, Q N, ...]``. Inside a contact begun at ``tc`` the force is
``A cos θ + B sin θ`` with ``θ = ω (t - tc)`` (:func:`forcing_at`, one cosine and sine per contact), and
cos θ, sin θ are short polynomials while θ is small (:func:`phase_cos_sin`), rather than a cosine and a sine
at each of the thirteen stages of every step.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import helper, kernel, njit
from ..constants import HERTZ_DURATION_CONSTANT
from . import _dop853 as _dop
from ._dop853 import error_norm as _dop_error
from ._flight import record_extremum
from ._records import ContactEnd, ContactStart, as_params, without_main
from ._status import STATUS_OK, STATUS_STEP_UNDERFLOW

# Dormand-Prince 8(5,3) coefficients (Hairer, Norsett, Wanner, Solving ODEs I, II.10), vendored.
_NS = _dop.N_STAGES
#: Contact state components without forcing (t, x, v, sqrt(delta), u, impulse, dissipated in
#: contact, dissipated by C); forcing adds the work of F.
NY = 8
#: Leading contact state components a derivative reads (t, x, v, ξ, u; t only with forcing): the others are
#: quadratures that feed no derivative, so a stage's intermediate state needs only these.
NY_READ = 5
#: Rows of the stage array ``kst`` a caller allocates: the stages and the derivative at the new point.
N_STAGE_ROWS = _NS + 1
#: Rows of the work array ``work`` a caller allocates.
N_WORK_ROWS = 8
_EPS = 2.220446049250313e-16
#: The peak force's search stops at a trial where the force falls short of the top of its local parabola
#: (value, σ-rate and second σ-derivative there) by at most this much relative, and reports that top: its
#: error is then of the order of the cubic term, this shortfall to the power 3/2 (~3e-11), far below the
#: integration's own (the peak is an output only, it feeds no motion).
_PEAK_RTOL = 1e-7

_HERTZ_T = HERTZ_DURATION_CONSTANT  # contact duration in units of alpha_max / U0

#: Largest forcing phase θ = ω t (rad) since a contact's onset at which cos θ and sin θ come from
#: their Taylor polynomials (:func:`phase_cos_sin`); beyond, from ``math.cos`` and ``math.sin``. A contact
#: of the paper's damper spans θ of about 0.01-0.03 rad at 5 Hz.
THETA_MAX = 0.1
#: Taylor coefficients of cos θ in z = θ² (1, -1/2!, ..., -1/10!); for |θ| <= ``THETA_MAX`` the first
#: omitted term, θ^12/12!, is below 2.1e-21.
COS_TAYLOR = (1.0, -1.0 / 2.0, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0)
#: Taylor coefficients of sin θ / θ in z = θ² (1, -1/3!, ..., 1/9!); for |θ| <= ``THETA_MAX`` the first
#: omitted term relative to sin θ, θ^10/11!, is below 2.6e-18.
SIN_TAYLOR = (1.0, -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0)


@helper
def _force(d, u, kh, c1, clip):
    """Contact force in N and its elastic part in N at penetration d (m), rate u (m/s)."""
    if d <= 0.0:
        return 0.0, 0.0
    fe = kh * d * math.sqrt(d)
    f = fe + c1 * u
    if clip and f < 0.0:
        f = 0.0
    return f, fe


@helper
def phase_cos_sin(theta):
    """``(cos θ, sin θ)`` of a phase ``θ`` (rad): Horner sums of the Taylor polynomials within ``THETA_MAX``.

    Within ``|θ| <= THETA_MAX`` the truncation is below 3e-18 relative (``COS_TAYLOR``, ``SIN_TAYLOR``),
    so both agree with ``math.cos`` and ``math.sin`` to about an ulp, without a call to either;
    beyond, they are ``math.cos(θ)`` and ``math.sin(θ)``.
    """
    if abs(theta) <= THETA_MAX:
        c, s = COS_TAYLOR, SIN_TAYLOR
        z = theta * theta
        cz = c[0] + z * (c[1] + z * (c[2] + z * (c[3] + z * (c[4] + z * c[5]))))
        sz = theta + theta * (z * (s[1] + z * (s[2] + z * (s[3] + z * s[4]))))
        return cz, sz
    return math.cos(theta), math.sin(theta)


@helper
def forcing_at(fc, tc):
    """The forcing of a contact begun at ``tc`` s, ``(ω rad/s, A N, B N)``: ``F(tc + t) = A cos ωt + B sin ωt``.

    With ``F(t) = P cos ωt + Q sin ωt`` (``fc = [ω, P, Q, ...]``), angle addition gives ``A = P cos ωtc +
    Q sin ωtc`` and ``B = Q cos ωtc - P sin ωtc``: one cosine and sine per contact, the phase ``ωt``
    since the onset then stays small (:func:`phase_cos_sin`). ``fc`` None (free decay): zeros, unused.
    """
    if fc is None:
        return 0.0, 0.0, 0.0
    w, p, q = fc[0], fc[1], fc[2]
    c, s = math.cos(w * tc), math.sin(w * tc)
    return w, p * c + q * s, q * c - p * s


@helper
def _rhs_into(y, prm, fc, fab, sw, out, row):
    """Derivatives with respect to σ of the contact state into ``out[row]`` (module docstring).

    ``dt/dσ = ξ``, ``dx/dσ = ξ v``, ``dv/dσ = ξ (s F_c - K x - C v + F) / M``, ``dξ/dσ = u / 2``,
    ``du/dσ = ξ (-F_c/m - F_c/M + s (K x + C v - F) / M)``, then the integrands ξ F_c, ξ (F_c -
    K_HZ δ^{3/2}) u, ξ C v² and (forced) ξ F v. ``F = A cos ωt + B sin ωt`` at the time ``t`` since
    the onset, ``fab = (ω, A, B)`` (:func:`forcing_at`), is evaluated only when ``fc`` is not None (a
    branch numba removes at compile time). Reads only ``y[:NY_READ]``.
    """
    M, K, C, m, kh, c1, clip = prm.M, prm.K, prm.C, prm.m, prm.k_hertz, prm.c1, prm.clip
    x, v, xi, u = y[1], y[2], y[3], y[4]
    fe = kh * xi * xi * xi
    f = fe + c1 * u
    if clip and f < 0.0:
        f = 0.0
    spring = K * x + C * v
    if fc is not None:
        c, s = phase_cos_sin(fab[0] * y[0])
        fx = fab[1] * c + fab[2] * s
        spring = spring - fx
        out[row, 8] = xi * fx * v
    out[row, 0] = xi
    out[row, 1] = xi * v
    out[row, 2] = xi * (sw * f - spring) / M
    out[row, 3] = 0.5 * u
    out[row, 4] = xi * (-f / m - f / M + sw * spring / M)
    out[row, 5] = xi * f
    out[row, 6] = xi * (f - fe) * u
    out[row, 7] = xi * C * v * v


@helper
def _dop_step(y, f0, h, prm, fc, fab, sw, kst, ytmp, ynew, fnew):
    """One Dormand-Prince 8 step of size ``h``; fills ``ynew``, ``fnew`` and the stages.

    The intermediate states ``ytmp`` of the stages hold only the ``NY_READ`` components a derivative
    reads (the quadratures' sums would be computed for nothing); ``ynew`` has them all.
    """
    ny = NY if fc is None else NY + 1  # a compile-time constant
    for i in range(ny):
        kst[0, i] = f0[i]
    for st in range(1, _NS):
        _dop.stage_state(st, y, h, kst, ytmp, NY_READ)
        _rhs_into(ytmp, prm, fc, fab, sw, kst, st)
    _dop.solution(y, h, kst, ynew, ny)
    _rhs_into(ynew, prm, fc, fab, sw, kst, np.int64(_NS))
    for i in range(ny):
        fnew[i] = kst[_NS, i]


@helper
def _dfds(y, f, prm):
    """Rate of change of the contact force with σ (same sign as dF/dt while ξ > 0)."""
    xi = y[3]
    return 3.0 * prm.k_hertz * xi * xi * f[3] + prm.c1 * f[4]


@helper
def _d2fds2(y, f, prm, fc, fab, sw):
    """Second derivative of the (unclipped) contact force with σ, in N (s m^-0.5)^-2, from the state and its rates.

    With ``F = K_HZ ξ³ + c1 u``, ``ξ' = u/2`` and ``u' = ξ a``, ``a = -F/m - F/M + s S/M``, ``S = K x + C v -
    F_ext`` (module docstring; ``fab`` as in :func:`_rhs_into`):
    ``F'' = 6 K_HZ ξ ξ'² + 3 K_HZ ξ² u'/2 + c1 (ξ' a + ξ (-F'/m - F'/M + s S'/M))`` with
    ``F' = dF/dσ`` (:func:`_dfds`) and ``S' = K x' + C v' - t' dF_ext/dt``.
    """
    M, K, C, m, kh, c1 = prm.M, prm.K, prm.C, prm.m, prm.k_hertz, prm.c1
    xi, u, dxi, du = y[3], y[4], f[3], f[4]
    force = kh * xi * xi * xi + c1 * u
    dforce = 3.0 * kh * xi * xi * dxi + c1 * du
    spring = K * y[1] + C * y[2]
    dspring = K * f[1] + C * f[2]
    if fc is not None:
        w, fa, fb = fab
        c, s = phase_cos_sin(w * y[0])
        spring = spring - (fa * c + fb * s)
        dspring = dspring - f[0] * w * (fb * c - fa * s)
    a = -force / m - force / M + sw * spring / M
    ddu = dxi * a + xi * (-dforce / m - dforce / M + sw * dspring / M)
    return 6.0 * kh * xi * dxi * dxi + 1.5 * kh * xi * xi * du + c1 * ddu


@helper
def _peak_guess(y, ynew, h, g0, g1, prm):
    """First estimate in (0, h) of the σ step to the force maximum: the cubic Hermite interpolant's.

    The force's values ``F = K_HZ ξ³ + c1 u`` and σ-rates ``g0 > 0``, ``g1 <= 0`` at both ends of the
    step of ``h`` define a cubic whose derivative, a quadratic, has one root in (0, h]; the secant
    of the rates when that root is not found.
    """
    kh, c1 = prm.k_hertz, prm.c1
    fa = kh * y[3] * y[3] * y[3] + c1 * y[4]
    fb = kh * ynew[3] * ynew[3] * ynew[3] + c1 * ynew[4]
    # p'(s) = a s² + b s + c on s = σ/h in [0, 1], c = h g0 > 0 >= a + b + c = h g1
    a = 6.0 * (fa - fb) + 3.0 * h * (g0 + g1)
    b = 6.0 * (fb - fa) - h * (4.0 * g0 + 2.0 * g1)
    c = h * g0
    s = -1.0
    disc = b * b - 4.0 * a * c
    if a == 0.0:
        s = -c / b if b != 0.0 else -1.0
    elif disc >= 0.0:
        q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
        s = q / a if 0.0 < q / a < 1.0 else (c / q if q != 0.0 else -1.0)
    if not (0.0 < s < 1.0):
        s = g0 / (g0 - g1)
    return s * h


@helper
def _root_in_step(kind, target, y, f0, h, glo, g1, dg1, prm, fc, fab, sw, kst, ytmp, ynew, fnew):
    """Step length in [0, h] where ξ (kind 0), v (kind 1), t - target (kind 2) or dF/dσ (kind 3) vanishes.

    ``glo`` is the sign-carrying value at the step start, ``g1`` the value at the full step's end.
    Kinds 0-2: Newton's method on the step length (the derivative, u/2 or ξ, is part of the
    state) kept inside the bracket, the first trial from the step end (value ``g1``, σ-derivative
    ``dg1``). Kind 3, the peak force, between ``glo`` (> 0) at the step start and ``g1`` (<= 0) at
    its end: Newton on dF/dσ with its derivative :func:`_d2fds2`, kept inside the bracket, from the
    first trial ``target`` (:func:`_peak_guess`; ``dg1`` unused), until the force at the trial is
    within ``_PEAK_RTOL`` of the top of its local parabola (or the bracket within 1e-6 h); the
    caller takes that top. The maximum is flat: the step length needs only about half the digits
    of the force, and the first trial usually suffices. Every trial is a full
    Dormand-Prince step from the step start, so the root is as accurate as the integration;
    ``ynew``/``fnew`` receive the state at the root (the step end's own buffers, or others that
    keep it). One compiled function for both searches: each compiled function that calls
    :func:`_dop_step` carries its own copy of the step's code.
    """
    lo, hi = 0.0, h
    if kind == 3:  # Newton on dF/dσ from the first trial ``target``
        hm = target
        for _ in range(60):
            if not (lo < hm < hi):
                hm = 0.5 * (lo + hi)
            _dop_step(y, f0, hm, prm, fc, fab, sw, kst, ytmp, ynew, fnew)
            gm = _dfds(ynew, fnew, prm)
            if gm == 0.0:
                break
            if gm > 0.0:
                lo = hm
            else:
                hi = hm
            dgm = _d2fds2(ynew, fnew, prm, fc, fab, sw)
            fm = prm.k_hertz * ynew[3] * ynew[3] * ynew[3] + prm.c1 * ynew[4]
            # F here falls short of the maximum of its parabola by gm² / (2 |F''|)
            if gm * gm <= 2.0 * _PEAK_RTOL * fm * abs(dgm) or hi - lo <= 1e-6 * h:
                break
            hm = hm - gm / dgm if dgm < 0.0 else 0.5 * (lo + hi)
        return hm
    # Newton on state component ci less target: ξ (kind 0), v (kind 1) or t (kind 2, the only
    # one with a target; x - 0.0 is x exactly)
    ci = 3 if kind == 0 else (2 if kind == 1 else 0)
    hm = h
    g, dg = g1, dg1
    for _ in range(40):
        hn = hm - g / dg if dg != 0.0 else 0.5 * (lo + hi)
        if not (lo < hn < hi):
            hn = 0.5 * (lo + hi)
        _dop_step(y, f0, hn, prm, fc, fab, sw, kst, ytmp, ynew, fnew)
        g, dg = ynew[ci] - target, fnew[ci]
        if (g > 0.0) == (glo > 0.0):
            lo = hn
        else:
            hi = hn
        done = abs(hn - hm) <= 8.0 * _EPS * hn or g == 0.0
        hm = hn
        if done or hi - lo <= 4.0 * _EPS * hi:
            break
    return hm


@helper
def _contact_begin(prm, start, rtol, y, atol):
    """Fill the contact state ``y`` at the start and the absolute tolerances ``atol``; return the first σ step.

    Tolerances scale with the Hertz contact (Johnson, *Contact Mechanics*, 1985, §11.4) at the
    approach speed of the same energy, ``U = sqrt(u0² + 4 K_HZ ξ0⁵ / (5 m_eff))`` (m/s):
    ``α_max = (5 m_eff U² / 4 K_HZ)^{2/5}`` (m) and duration ``τ = 2.943 α_max / U`` (s,
    ``HERTZ_DURATION_CONSTANT``); the first step is ``0.02 τ / sqrt(α_max)`` (σ in s m^-0.5).
    """
    M, m, kh, hg = prm.M, prm.m, prm.k_hertz, prm.half_gap
    meff = m * M / (m + M)
    xi0, u0 = start.xi, start.u
    y[0] = 0.0
    y[1] = start.x
    y[2] = start.v
    y[3] = xi0
    y[4] = u0
    for i in range(5, y.shape[0]):
        y[i] = 0.0
    # the approach speed with the same energy (a contact resumed mid-way has u0 < U)
    xi2 = xi0 * xi0
    uref = max(math.sqrt(u0 * u0 + 0.8 * kh * (xi0 * (xi2 * xi2)) / meff), 1e-9)
    amax = (1.25 * meff * uref * uref / kh) ** 0.4
    tau_h = _HERTZ_T * amax / uref
    atol[0] = rtol * tau_h
    atol[1] = rtol * hg
    atol[2] = rtol * max(abs(start.v), uref)
    atol[3] = rtol * math.sqrt(amax)
    atol[4] = rtol * uref
    atol[5] = rtol * meff * uref
    atol[6] = rtol * 0.5 * meff * uref * uref
    for i in range(7, y.shape[0]):
        atol[i] = atol[6]
    return 0.02 * tau_h / math.sqrt(amax)


@helper
def _step_size(err, h, rejected):
    """The next σ step after a step of ``h`` with error norm ``err``.

    A rejected step (``err > 1`` or not finite) shrinks by ``max(0.2, 0.9 err^(-1/8))``. An
    accepted one grows by at most 10, with no growth right after a rejection (Hairer, Norsett,
    Wanner, II.4), and a safety factor of 0.8 on growth (it cuts rejections from ~20 % to ~5 %
    of the steps and the total by ~7 %).
    """
    if not (err <= 1.0):
        if not math.isfinite(err):
            err = 1e10
        return h * max(0.2, 0.9 * err ** (-1.0 / 8.0))
    grow = 1.0 if rejected else 10.0
    if err == 0.0:
        return h * grow
    return h * min(grow, 0.8 * err ** (-1.0 / 8.0))


@njit(inline="always")
def _peak_of_step(prm, fc, fab, start, work, kst, hstep, g0, g1, peak):
    """The largest contact force (N) so far, with a maximum inside the step of ``hstep`` from ``work[0]``.

    dF/dσ is ``g0`` at the step start and ``g1`` at its end; when it turns from > 0 to <= 0 the
    maximum is located by :func:`_root_in_step` into ``work[5:7]``, the buffers taken only then (no
    reference counting in the other steps), and taken as the top of the force's parabola there
    (its value, σ-rate and second σ-derivative); the step end stays in ``work[3:5]``.
    """
    if g0 > 0.0 and g1 <= 0.0:
        y, f0, ytmp, yd, fd = work[0], work[1], work[2], work[5], work[6]
        first = _peak_guess(y, work[3], hstep, g0, g1, prm)
        _root_in_step(np.int64(3), first, y, f0, hstep, g0, g1, 0.0, prm, fc, fab, start.sw, kst, ytmp, yd, fd)
        fpk, _ = _force(yd[3] * yd[3], yd[4], prm.k_hertz, prm.c1, prm.clip)
        gm, dgm = _dfds(yd, fd, prm), _d2fds2(yd, fd, prm, fc, fab, start.sw)
        rise = gm * gm / (-2.0 * dgm) if dgm < 0.0 else math.inf
        if rise <= _PEAK_RTOL * fpk:  # the top of the force's parabola there, where the search trusts it
            fpk += rise
        peak = max(peak, fpk)
    return peak


@njit(inline="always")
def _turn_in_step(prm, fc, fab, start, work, kst, hstep, ext, n_ext):
    """Record a zero of the main-mass velocity inside the step (Newton, full steps) in ``ext``.

    Rows: time (s), x (m), +1 for a maximum or -1 for a minimum; the caller has seen the velocity
    change sign between ``work[0]`` and ``work[3]``. The root goes to ``work[5:7]``; the step end
    stays in ``work[3:5]``.
    """
    y, f0, ytmp, ynew, fnew, yd, fd = work[0], work[1], work[2], work[3], work[4], work[5], work[6]
    _root_in_step(np.int64(1), 0.0, y, f0, hstep, y[2], ynew[2], fnew[2], prm, fc, fab, start.sw, kst, ytmp, yd, fd)
    record_extremum(ext, n_ext, start.tc + yd[0], yd[1], 1.0 if y[2] > 0.0 else -1.0)


@njit(inline="always")
def _dense_in_step(prm, fc, fab, start, work, kst, hstep, t_eval, ie, dense, ec0, en0):
    """Dense rows (``DENSE_COLUMNS``) at the output times ``t_eval`` (s) inside the step; return the next due.

    Newton on t(σ) with full steps from the step start; ``ec0``, ``en0`` (J) are the energies
    dissipated by C and in contacts before the contact. The states at those times go to
    ``work[5:7]``; the step end stays in ``work[3:5]``.
    """
    y, f0, ytmp, ynew, fnew, yd, fd = work[0], work[1], work[2], work[3], work[4], work[5], work[6]
    tc, sw, hg = start.tc, start.sw, prm.half_gap
    while ie < t_eval.shape[0] and t_eval[ie] - tc <= ynew[0]:
        target = t_eval[ie] - tc
        yt = y
        if target > y[0]:
            _root_in_step(np.int64(2), target, y, f0, hstep, -1.0, ynew[0] - target, fnew[0], prm, fc, fab, sw, kst,
                          ytmp, yd, fd)
            yt = yd
        xi = max(yt[3], 0.0)
        dense[ie, 0] = yt[1]
        dense[ie, 1] = yt[2]
        dense[ie, 2] = yt[1] + sw * (hg + xi * xi)
        dense[ie, 3] = yt[2] + sw * yt[4]
        dense[ie, 4] = ec0 + yt[7]
        dense[ie, 5] = en0 + yt[6]
        ie += 1
    return ie


@njit(inline="always")
def contact(prm, fc, start, t_end, rtol, t_eval, ie, dense, ec0, en0, work, kst, ext, n_ext):
    """Integrate one contact from ``start.tc`` s until the bodies part or ``t_end`` s (module docstring).

    The contact starts (or resumes, for a run continued mid-contact) as ``start`` says. Step
    sizes and tolerances: :func:`_contact_begin`, :func:`_step_size`. The peak force is located
    as the zero of dF_c/dσ inside a step (:func:`_peak_of_step`); every zero of the main-mass
    velocity inside the contact is located by Newton's method on full Runge-Kutta steps from the
    step start (as accurate as the integration) and recorded in ``ext`` (:func:`_turn_in_step`;
    ``ext=None`` compiles it out); x, v, y, w and the dissipated energies (plus ``ec0``, ``en0``
    J) are written to ``dense[ie:]`` at the times ``t_eval`` (:func:`_dense_in_step`;
    ``t_eval=None``: no dense output, compiled out).

    Parameters
    ----------
    prm : Params
        The model (:class:`~acoustiviz.dynamics._records.Params`, SI).
    fc : ndarray or None
        Forcing ``[ω rad/s, P N, Q N, ...]``; None for free decay (8 state components).
    start : ContactStart
        Time (s), wall (±1), main-mass displacement (m) and velocity (m/s), sqrt of the
        penetration (m^0.5) and penetration rate (m/s) at the start
        (:class:`~acoustiviz.dynamics._records.ContactStart`).
    t_end, rtol : float
        Latest end of the integration (s); relative tolerance.
    t_eval, ie, dense : ndarray, int, ndarray, or None, 0, None
        Output times (s), the next one due, and the (n, 6) dense rows.
    ec0, en0 : float
        Energy dissipated by C and in contacts before ``start.tc`` (J), added to the dense rows.
    work, kst : ndarray
        Buffers ``(N_WORK_ROWS, n)`` and ``(N_STAGE_ROWS, n)``, ``n = NY`` or ``NY + 1`` with
        forcing.
    ext, n_ext : ndarray or None
        Turning points of x (rows: time s, x m, ±1) and their count.

    Returns
    -------
    ContactEnd
        ``ended`` (True when the bodies parted before ``t_end``), ``status`` (``STATUS_OK`` or
        ``STATUS_STEP_UNDERFLOW``), ``ie`` (the next output time due), ``duration`` (time
        integrated, s), ``peak`` (largest contact force, N) and ``y`` (the state at the end,
        module docstring, t counted from ``start.tc``; a view of ``work[0]``).

    Notes
    -----
    Inlined into each driver (one call site each): compiled apart, its code would be optimised and
    compiled twice, in its own module and again in the driver's that links it.
    """
    tc, sw = start.tc, start.sw
    y, f0, ytmp, ynew, fnew = work[0], work[1], work[2], work[3], work[4]
    h = _contact_begin(prm, start, rtol, y, work[7])
    fab = forcing_at(fc, tc)
    _rhs_into(y, prm, fc, fab, sw, work, np.int64(1))  # f0 is work[1]
    peak, _ = _force(start.xi * start.xi, start.u, prm.k_hertz, prm.c1, prm.clip)
    status = STATUS_OK
    ended = False
    nrej = 0
    rejected = False
    t_stop = t_end - tc
    if t_stop <= 0.0:
        return ContactEnd(False, status, ie, 0.0, peak, y)
    while True:
        _dop_step(y, f0, h, prm, fc, fab, sw, kst, ytmp, ynew, fnew)
        err = _dop_error(y, ynew, h, kst, rtol, work[7])
        if not (err <= 1.0):
            h = _step_size(err, h, rejected)
            nrej += 1
            rejected = True
            if nrej > 100000:
                status = STATUS_STEP_UNDERFLOW
                break
            continue
        hstep = h
        exiting = ynew[3] <= 0.0
        if exiting:
            hstep = _root_in_step(np.int64(0), 0.0, y, f0, h, y[3], ynew[3], fnew[3], prm, fc, fab, sw, kst, ytmp,
                                  ynew, fnew)
        stopping = ynew[0] >= t_stop
        if stopping:
            exiting = False
            hstep = _root_in_step(np.int64(2), t_stop, y, f0, hstep, -1.0, ynew[0] - t_stop, fnew[0], prm, fc, fab, sw,
                                  kst, ytmp, ynew, fnew)
        # the pieces take the other buffers only in the steps that need them (no reference counting
        # in the others); ext=None, t_eval=None: compiled out
        peak = _peak_of_step(prm, fc, fab, start, work, kst, hstep, _dfds(y, f0, prm), _dfds(ynew, fnew, prm), peak)
        xi1 = max(ynew[3], 0.0)
        fend, _ = _force(xi1 * xi1, ynew[4], prm.k_hertz, prm.c1, prm.clip)
        peak = max(peak, fend)
        if ext is not None and ext.shape[0] > 0 and (y[2] > 0.0) != (ynew[2] > 0.0):  # the main mass turns
            _turn_in_step(prm, fc, fab, start, work, kst, hstep, ext, n_ext)
        if t_eval is not None and ie < t_eval.shape[0] and t_eval[ie] - tc <= ynew[0]:
            ie = _dense_in_step(prm, fc, fab, start, work, kst, hstep, t_eval, ie, dense, ec0, en0)
        for i in range(y.shape[0]):  # the step end becomes the step start
            y[i] = ynew[i]
            f0[i] = fnew[i]
        if exiting:
            ended = True
            break
        if stopping:
            break
        h = _step_size(err, h, rejected)
        rejected = False
    return ContactEnd(ended, status, ie, y[0], peak, y)


@helper
def instant_impact(prm, sw, u0, e, v, w, dur, peak, row):
    """Instantaneous impact on wall ``sw`` at approach speed ``u0`` m/s with restitution ``e``.

    The rigid-body limit of the contact (impact map): momentum is conserved and the relative
    speed reverses with factor ``e``, so the impulse is ``J = (1 + e) m_eff u0`` (N s, with
    ``m_eff = m M / (m + M)``), ``v⁺ = v + s J / M``, ``w⁺ = w - s J / m`` (m/s) and the energy
    lost ``m_eff u0² (1 - e²) / 2`` (J). Fills ``row[3:8]`` of an impact row (separation speed,
    duration ``dur`` s, peak force ``peak`` N, impulse, energy lost).

    Returns ``(v⁺, w⁺, energy lost)``.
    """
    M, m = prm.M, prm.m
    meff = m * M / (m + M)
    jimp = (1.0 + e) * meff * u0
    lost = 0.5 * meff * u0 * u0 * (1.0 - e * e)
    row[3] = e * u0
    row[4] = dur
    row[5] = peak
    row[6] = jimp
    row[7] = lost
    return v + sw * jimp / M, w - sw * jimp / m, lost


@helper
def free_contact(pfree, u0, rtol, work, kst):
    """Compliant contact of the two masses alone (``pfree``: Params with K = C = 0) at approach speed ``u0`` m/s.

    No forcing, 8-component buffers ``work`` and ``kst``; no dense output and no turning points
    (compiled out). Returns ``(status, restitution, duration in s, peak force in N)``.
    """
    r = contact(pfree, None, ContactStart(0.0, 1.0, 0.0, 0.0, 0.0, u0), math.inf, rtol, None, np.int64(0), None,
                0.0, 0.0, work, kst, None, None)
    e = max(-r.y[4], 0.0) / u0 if u0 > 0.0 else 0.0
    return r.status, e, r.duration, r.peak


@kernel
def free_restitution(p, u0, rtol):
    """Restitution of the compliant contact of the two masses alone at approach speed ``u0`` m/s.

    :func:`free_restitution_of` of the parameter vector ``p``.
    Returns ``(restitution, duration in s, peak force in N)``.
    """
    return free_restitution_of(as_params(p), u0, rtol)


@njit(inline="always")
def free_restitution_of(prm, u0, rtol):
    """Restitution of the compliant contact of the two masses alone at approach speed ``u0`` m/s.

    The main spring and dashpot of ``prm`` are left out (the impact map's contact, see
    :func:`free_contact`). Returns ``(restitution, duration in s, peak force in N)``.
    """
    pfree = without_main(prm)
    work = np.zeros((N_WORK_ROWS, NY))
    kst = np.zeros((N_STAGE_ROWS, NY))
    _, e, dur, peak = free_contact(pfree, u0, rtol, work, kst)
    return e, dur, peak
