"""Compiled kernels of the forced impact damper (numba): free flight, contact, impact map.

The main mass carries an external force ``F(t) = P cos(ωt) + Q sin(ωt)`` (a harmonic force,
or the spring and dashpot forces of a harmonic base motion, see :mod:`.forced`). Between contacts
the main mass is a forced damped oscillator in closed form: the particular (steady) solution
``x_p(t) = A_c cos(ωt) + A_s sin(ωt)`` plus the free damped oscillation; the impact mass flies
at constant velocity. Contact onset is found by exact bracketing (see :func:`_scan`); contacts
are integrated by an adaptive Dormand-Prince 8(5,3) scheme in the transformed time σ of
:mod:`._kernels` (dt = sqrt(δ) dσ), with the forcing evaluated at the physical time.

Parameter vector ``p``: ``[M, K, C, m, half_gap, k_hertz, c1, clip]`` (SI).
Forcing vector ``fc``: ``[ω rad/s, P N, Q N, A_c m, A_s m]``.
State vector ``st`` (in/out, 8 floats): ``x, v, y, w`` (m, m/s), in-contact flag, wall ±1,
``ξ = sqrt(δ)`` (m^0.5) and ``u = dδ/dt`` (m/s) of an unfinished contact. While the flag is set the
impact row ``n - 1`` is still open (its separation speed is NaN).
Impact rows (``IMPACT_COLUMNS`` of :mod:`._kernels`): start time, wall, approach speed, separation
speed, duration, peak force, impulse, energy lost.
Accumulators ``acc`` (added to): work of F on the main mass, dissipated by C, dissipated in
contacts (J), and the largest and smallest x reached (m).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..constants import HERTZ_DURATION_CONSTANT
from . import _dop853 as _dop
from ._dop853 import error_norm as _dop_error
from ._status import STATUS_DIVERGED, STATUS_MAX_IMPACTS, STATUS_OK, STATUS_STEP_UNDERFLOW

# the vendored Dormand-Prince 8(5,3) tableau, shared with the free-decay contact solver
_NS = _dop.N_STAGES
_A = _dop.A
_B = _dop.B
_NY = 9  # contact state: t, x, v, ξ, u, impulse, dissipated in contact, dissipated by C, work of F
_GX, _GW = (np.ascontiguousarray(a) for a in np.polynomial.legendre.leggauss(12))

__all__ = ["STATUS_OK", "STATUS_MAX_IMPACTS", "STATUS_STEP_UNDERFLOW", "STATUS_DIVERGED", "free_restitution"]

_HERTZ_T = HERTZ_DURATION_CONSTANT  # contact duration in units of alpha_max / U0
_EPS = 2.220446049250313e-16


# ============================================================ closed-form free flight
# Flight coefficients ``c``: t0, xh0, vh0 (free part at t0), y0, w0, a, wd, ω, A_c, A_s, half gap.
@njit(cache=True)
def _flight_coeffs(c, t0, x, v, y, w, a, wd, fc):
    om, ac, as_ = fc[0], fc[3], fc[4]
    cs = math.cos(om * t0)
    sn = math.sin(om * t0)
    c[0] = t0
    c[1] = x - (ac * cs + as_ * sn)
    c[2] = v - om * (as_ * cs - ac * sn)
    c[3] = y
    c[4] = w
    c[5] = a
    c[6] = wd
    c[7] = om
    c[8] = ac
    c[9] = as_


@njit(cache=True)
def _main(tau, c):
    """Main-mass displacement (m), velocity (m/s) and acceleration (m/s²) at t0 + tau."""
    a, wd, om, ac, as_ = c[5], c[6], c[7], c[8], c[9]
    x0, v0 = c[1], c[2]
    e = math.exp(-a * tau)
    cw = math.cos(wd * tau)
    sw = math.sin(wd * tau)
    b = (v0 + a * x0) / wd
    xh = e * (x0 * cw + b * sw)
    vh = e * ((b * wd - a * x0) * cw - (x0 * wd + a * b) * sw)
    ah = -2.0 * a * vh - (a * a + wd * wd) * xh
    t = c[0] + tau
    cs = math.cos(om * t)
    sn = math.sin(om * t)
    xp = ac * cs + as_ * sn
    vp = om * (as_ * cs - ac * sn)
    return xh + xp, vh + vp, ah - om * om * xp


@njit(cache=True)
def _fval(kind, tau, c):
    """0 -> main-mass velocity (m/s), 1 -> d/2 - z (m), 2 -> z + d/2 (m), 3 -> acceleration (m/s²)."""
    x, v, acc = _main(tau, c)
    if kind == 0:
        return v
    if kind == 3:
        return acc
    z = c[3] + c[4] * tau - x
    if kind == 1:
        return c[10] - z
    return z + c[10]


@njit(cache=True)
def _brent(kind, xa, xb, fa, fb, c):
    """Brent's root in s of a flight function bracketed by ``[xa, xb]``."""
    xpre, xcur, fpre, fcur = xa, xb, fa, fb
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    xblk = 0.0
    fblk = 0.0
    spre = 0.0
    scur = 0.0
    for _ in range(200):
        if fpre != 0.0 and fcur != 0.0 and ((fpre < 0.0) != (fcur < 0.0)):
            xblk = xpre
            fblk = fpre
            spre = xcur - xpre
            scur = spre
        if abs(fblk) < abs(fcur):
            xpre = xcur
            xcur = xblk
            xblk = xpre
            fpre = fcur
            fcur = fblk
            fblk = fpre
        delta = 0.5 * (1e-18 + 4.0 * _EPS * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre = scur
                scur = stry
            else:
                spre = sbis
                scur = sbis
        else:
            spre = sbis
            scur = sbis
        xpre = xcur
        fpre = fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = _fval(kind, xcur, c)
    return xcur


@njit(cache=True)
def _scan(c, tau_end):
    """First contact of a forced free flight within ``[0, tau_end]``: (found, tau in s, wall ±1).

    Exact bracketing with a bound ``L`` on ``|d²z/dt²| = |d²x/dt²|`` (free part
    ``R e^{-a t} ω_n²`` plus particular part ``ω² |A|``). A step ``[t_a, t_a + h]`` is accepted when
    either ``|dz/dt(t_a)| > L h`` (``z`` monotone: at most one wall crossing, bracketed by the
    signs at both ends and found by Brent's method) or the Taylor bound
    ``g(t_a) + g'(t_a) s - L s²/2`` keeps both gap functions ``g`` positive; otherwise the step is
    halved. Only a grazing shorter than ``1e-10`` of the step cap (a penetration below
    ``L h²/2``, ~1e-20 m) can go unnoticed.
    """
    a, wd, om, hg = c[5], c[6], c[7], c[10]
    x0, v0 = c[1], c[2]
    r = math.sqrt(x0 * x0 + ((v0 + a * x0) / wd) ** 2)
    wn2 = a * a + wd * wd
    lp = om * om * math.sqrt(c[8] * c[8] + c[9] * c[9])
    hmax = 0.25 * 2.0 * math.pi / max(wd, om)
    hmin = 1e-10 * hmax
    ta = 0.0
    x, v, _ = _main(0.0, c)
    z = c[3] - x
    gpa = hg - z
    gma = z + hg
    dza = c[4] - v
    if gpa <= 0.0 and dza > 0.0:
        return True, 0.0, 1.0
    if gma <= 0.0 and dza < 0.0:
        return True, 0.0, -1.0
    while ta < tau_end:
        h = min(hmax, tau_end - ta)
        lb = r * math.exp(-a * ta) * wn2 + lp
        while True:
            tb = ta + h
            x, v, _ = _main(tb, c)
            z = c[3] + c[4] * tb - x
            gpb = hg - z
            gmb = z + hg
            dzb = c[4] - v
            if abs(dza) > lb * h:  # monotone z
                if dza > 0.0 and gpb <= 0.0:
                    return True, _brent(1, ta, tb, gpa, gpb, c), 1.0
                if dza < 0.0 and gmb <= 0.0:
                    return True, _brent(2, ta, tb, gma, gmb, c), -1.0
                break
            q = 0.5 * lb * h * h
            okp = (gpa > 0.0 and gpa - dza * h - q > 0.0) or (gpb > 0.0 and gpb + dzb * h - q > 0.0)
            okm = (gma > 0.0 and gma + dza * h - q > 0.0) or (gmb > 0.0 and gmb - dzb * h - q > 0.0)
            if okp and okm:
                break
            if h <= hmin:
                if gpb <= 0.0:
                    return True, _brent(1, ta, tb, gpa, gpb, c) if gpa > 0.0 else ta, 1.0
                if gmb <= 0.0:
                    return True, _brent(2, ta, tb, gma, gmb, c) if gma > 0.0 else ta, -1.0
                break
            h *= 0.5
        ta = tb
        gpa, gma, dza = gpb, gmb, dzb
    return False, tau_end, 0.0


@njit(cache=True)
def _flight_energy(c, tau, fc, cdamp):
    """Work of F on the main mass and energy dissipated by C (J) over ``[0, tau]`` of a flight.

    Gauss-Legendre quadrature (12 nodes) on pieces no longer than a quarter period: the
    integrands are smooth sums of exponentials and sinusoids, integrated to round-off.
    """
    om, pc, ps = fc[0], fc[1], fc[2]
    hq = 0.25 * 2.0 * math.pi / max(c[6], om)
    npc = max(int(math.ceil(tau / hq)), 1)
    h = tau / npc
    work = 0.0
    diss = 0.0
    for k in range(npc):
        mid = (k + 0.5) * h
        for j in range(_GX.shape[0]):
            s = mid + 0.5 * h * _GX[j]
            _, v, _ = _main(s, c)
            t = c[0] + s
            f = pc * math.cos(om * t) + ps * math.sin(om * t)
            work += 0.5 * h * _GW[j] * f * v
            diss += 0.5 * h * _GW[j] * cdamp * v * v
    return work, diss


@njit(cache=True)
def _flight_extrema(c, tau, acc):
    """Update ``acc[3]``/``acc[4]`` with the largest/smallest x (m) of a flight over ``[0, tau]``.

    Zeros of the main-mass velocity are bracketed on 64 samples per period and located by Brent's
    method; the flight ends are included.
    """
    om = c[7]
    hs = 2.0 * math.pi / max(c[6], om) / 64.0
    ns = max(int(math.ceil(tau / hs)), 1)
    h = tau / ns
    x, va, _ = _main(0.0, c)
    acc[3] = max(acc[3], x)
    acc[4] = min(acc[4], x)
    ta = 0.0
    for k in range(1, ns + 1):
        tb = k * h
        x, vb, _ = _main(tb, c)
        acc[3] = max(acc[3], x)
        acc[4] = min(acc[4], x)
        if (va > 0.0) != (vb > 0.0) and va != 0.0 and vb != 0.0:
            tr = _brent(0, ta, tb, va, vb, c)
            x, _, _ = _main(tr, c)
            acc[3] = max(acc[3], x)
            acc[4] = min(acc[4], x)
        ta = tb
        va = vb


# ============================================================ contact phase (DOP853 in σ)
# As in ._kernels: dt = ξ dσ with ξ = sqrt(δ) a state variable, so the Hertz force K_HZ ξ³ is a
# polynomial and the solution is analytic in σ up to both ends of the contact. The external force
# is evaluated at the physical time tc + t.
@njit(cache=True, inline="always")
def _rhs_into(y, p, fc, tc, sw, out, row):
    M, K, C, m, kh, c1 = p[0], p[1], p[2], p[3], p[5], p[6]
    x, v, xi, u = y[1], y[2], y[3], y[4]
    fe = kh * xi * xi * xi
    f = fe + c1 * u
    if p[7] > 0.5 and f < 0.0:
        f = 0.0
    t = tc + y[0]
    fx = fc[1] * math.cos(fc[0] * t) + fc[2] * math.sin(fc[0] * t)
    spring = K * x + C * v - fx
    out[row, 0] = xi
    out[row, 1] = xi * v
    out[row, 2] = xi * (sw * f - spring) / M
    out[row, 3] = 0.5 * u
    out[row, 4] = xi * (-f / m - f / M + sw * spring / M)
    out[row, 5] = xi * f
    out[row, 6] = xi * (f - fe) * u
    out[row, 7] = xi * C * v * v
    out[row, 8] = xi * fx * v


@njit(cache=True)
def _dop_step(y, f0, h, p, fc, tc, sw, kst, ytmp, ynew, fnew):
    """One Dormand-Prince 8 step of size ``h``; fills ``ynew``, ``fnew`` and the stages."""
    for i in range(_NY):
        kst[0, i] = f0[i]
    for st in range(1, _NS):
        for i in range(_NY):
            acc = 0.0
            for j in range(st):
                acc += _A[st, j] * kst[j, i]
            ytmp[i] = y[i] + h * acc
        _rhs_into(ytmp, p, fc, tc, sw, kst, st)
    for i in range(_NY):
        acc = 0.0
        for j in range(_NS):
            acc += _B[j] * kst[j, i]
        ynew[i] = y[i] + h * acc
    _rhs_into(ynew, p, fc, tc, sw, kst, _NS)
    for i in range(_NY):
        fnew[i] = kst[_NS, i]


@njit(cache=True)
def _newton_in_step(kind, target, y, f0, h, glo, p, fc, tc, sw, kst, ytmp, ynew, fnew):
    """Step length in [0, h] where ξ (kind 0) or t - target (kind 2) vanishes (Newton, bracketed)."""
    lo, hi = 0.0, h
    hm = h
    g = ynew[3] if kind == 0 else ynew[0] - target
    dg = fnew[3] if kind == 0 else fnew[0]
    for _ in range(40):
        hn = hm - g / dg if dg != 0.0 else 0.5 * (lo + hi)
        if not (lo < hn < hi):
            hn = 0.5 * (lo + hi)
        _dop_step(y, f0, hn, p, fc, tc, sw, kst, ytmp, ynew, fnew)
        g = ynew[3] if kind == 0 else ynew[0] - target
        dg = fnew[3] if kind == 0 else fnew[0]
        if (g > 0.0) == (glo > 0.0):
            lo = hn
        else:
            hi = hn
        done = abs(hn - hm) <= 8.0 * _EPS * hn or g == 0.0
        hm = hn
        if done or hi - lo <= 4.0 * _EPS * hi:
            break
    return hm


@njit(cache=True)
def _contact(p, fc, sw, x, v, xi0, u0, tc, t_stop, rtol, work, kst):
    """Integrate a contact from ``tc`` s until the bodies part or the time ``t_stop`` s.

    Returns ``(ended, status, peak_force, y)`` with ``y`` the 9-component state at the end (t from
    ``tc``, x, v, ξ, u, impulse, dissipated in contact, dissipated by C, work of F).
    """
    M, m, kh, hg, c1 = p[0], p[3], p[5], p[4], p[6]
    meff = m * M / (m + M)
    y = work[0]
    f0 = work[1]
    ytmp = work[2]
    ynew = work[3]
    fnew = work[4]
    atol = work[5]
    y[0] = 0.0
    y[1] = x
    y[2] = v
    y[3] = xi0
    y[4] = u0
    for i in range(5, _NY):
        y[i] = 0.0
    # the approach speed with the same energy (a contact resumed mid-way has u0 < U)
    uref = max(math.sqrt(u0 * u0 + 0.8 * kh * xi0 ** 5 / meff), 1e-9)
    amax = (1.25 * meff * uref * uref / kh) ** 0.4
    tau_h = _HERTZ_T * amax / uref
    atol[0] = rtol * tau_h
    atol[1] = rtol * hg
    atol[2] = rtol * max(abs(v), uref)
    atol[3] = rtol * math.sqrt(amax)
    atol[4] = rtol * uref
    atol[5] = rtol * meff * uref
    atol[6] = rtol * 0.5 * meff * uref * uref
    atol[7] = atol[6]
    atol[8] = atol[6]
    _rhs_into(y, p, fc, tc, sw, f0.reshape((1, _NY)), 0)
    fpk = kh * xi0 ** 3 + c1 * u0
    peak = max(fpk, 0.0)
    h = 0.02 * tau_h / math.sqrt(amax)
    nrej = 0
    rejected = False
    ended = False
    status = STATUS_OK
    t_rel = t_stop - tc
    if t_rel <= 0.0:
        return False, status, peak, y
    while True:
        _dop_step(y, f0, h, p, fc, tc, sw, kst, ytmp, ynew, fnew)
        err = _dop_error(y, ynew, h, kst, rtol, atol)
        if not (err <= 1.0):
            if not math.isfinite(err):
                err = 1e10
            h = h * max(0.2, 0.9 * err ** (-1.0 / 8.0))
            nrej += 1
            rejected = True
            if nrej > 100000:
                status = STATUS_STEP_UNDERFLOW
                break
            continue
        exiting = ynew[3] <= 0.0
        hstep = h
        if exiting:
            hstep = _newton_in_step(0, 0.0, y, f0, h, y[3], p, fc, tc, sw, kst, ytmp, ynew, fnew)
        if ynew[0] >= t_rel:
            exiting = False
            _newton_in_step(2, t_rel, y, f0, hstep, -1.0, p, fc, tc, sw, kst, ytmp, ynew, fnew)
            for i in range(_NY):
                y[i] = ynew[i]
            break
        xi = max(ynew[3], 0.0)
        fpk = kh * xi * xi * xi + c1 * ynew[4]
        peak = max(peak, fpk)
        for i in range(_NY):
            y[i] = ynew[i]
            f0[i] = fnew[i]
        if exiting:
            ended = True
            break
        grow = 1.0 if rejected else 10.0
        rejected = False
        h = h * grow if err == 0.0 else h * min(grow, 0.8 * err ** (-1.0 / 8.0))
    return ended, status, peak, y


@njit(cache=True)
def free_restitution(p, u0, rtol):
    """Restitution of the compliant contact of the two masses alone at approach speed ``u0`` m/s.

    Returns ``(restitution, duration in s, peak force in N)``.
    """
    pfree = p.copy()
    pfree[1] = 0.0
    pfree[2] = 0.0
    work = np.zeros((6, _NY))
    kst = np.zeros((_NS + 1, _NY))
    ended, _, peak, yc = _contact(pfree, np.zeros(5), 1.0, 0.0, 0.0, 0.0, u0, 0.0, math.inf, rtol,
                                  work, kst)
    return max(-yc[4], 0.0) / u0, yc[0], peak
