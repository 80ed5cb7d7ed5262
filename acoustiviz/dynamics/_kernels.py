"""Compiled kernels of the impact-damper solvers (numba).

Why numba: the paper's Newmark scheme at 1e-7 s takes 2e8 steps over 20 s of motion, and the
event-driven solver does a few thousand small operations per impact (root finding, Runge-Kutta
stages, error control). A Python-level loop would take minutes for the first and tens of
milliseconds per impact for the second; compiled, they take seconds and microseconds. The kernels
are plain functions of float arrays, cached on disk (``cache=True``), and hold no global state
besides the constant Dormand-Prince coefficients.

Parameter vector ``p`` (floats): ``[M, K, C, m, half_gap, k_hertz, c1, clip]``.
Impact rows (``IMPACT_COLUMNS``): start time, wall, approach speed, separation speed, duration,
peak force, impulse, energy lost.
Dense rows: x, v, y, w, dissipated by C, dissipated in contacts.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as _dop

#: Columns of the impact array filled by the kernels.
IMPACT_COLUMNS = ("time", "wall", "approach", "separation", "duration", "peak_force", "impulse", "energy_lost")
#: Columns of the dense-output array filled by the kernels.
DENSE_COLUMNS = ("x", "v", "y", "w", "dissipated_C", "dissipated_contact")

# Dormand-Prince 8(5,3) coefficients (Hairer, Norsett, Wanner, Solving ODEs I, II.10), as in scipy.
_NS = _dop.N_STAGES
_A = np.ascontiguousarray(_dop.A[:_NS, :_NS])
_B = np.ascontiguousarray(_dop.B)
_E3 = np.ascontiguousarray(_dop.E3)
_E5 = np.ascontiguousarray(_dop.E5)
_NY = 8  # contact state: t, x, v, sqrt(delta), u, impulse, dissipated in contact, dissipated by C

STATUS_OK = 0
STATUS_MAX_IMPACTS = 1
STATUS_STEP_UNDERFLOW = 2
STATUS_DIVERGED = 3

_HERTZ_T = 2.943275  # contact duration in units of alpha_max / U0


# ============================================================ closed-form free motion
@njit(cache=True)
def _osc(x0, v0, tau, a, wd):
    """Displacement (m) and velocity (m/s) of the underdamped oscillator after ``tau`` s."""
    e = math.exp(-a * tau)
    c = math.cos(wd * tau)
    s = math.sin(wd * tau)
    b = (v0 + a * x0) / wd
    x = e * (x0 * c + b * s)
    v = e * ((b * wd - a * x0) * c - (x0 * wd + a * b) * s)
    return x, v


@njit(cache=True)
def _first_acc_zero(x0, v0, a, wd):
    """First time > 0 in s where the free oscillator's acceleration vanishes."""
    p0 = x0
    q0 = (v0 + a * x0) / wd
    p1 = -a * p0 + wd * q0
    q1 = -a * q0 - wd * p0
    p2 = -a * p1 + wd * q1
    q2 = -a * q1 - wd * p1
    phi = math.atan2(q2, p2)
    th = phi + 0.5 * math.pi
    k = math.ceil(-th / math.pi)
    th = th + k * math.pi
    if th <= 0.0:
        th += math.pi
    return th / wd


@njit(cache=True)
def _ffval(kind, tau, x0, v0, y0, w0, a, wd, hg):
    """Free-flight gap functions: 0 -> dz/dt, 1 -> d/2 - z, 2 -> z + d/2 (m/s or m)."""
    x, v = _osc(x0, v0, tau, a, wd)
    if kind == 0:
        return w0 - v
    z = y0 + w0 * tau - x
    if kind == 1:
        return hg - z
    return z + hg


@njit(cache=True)
def _brent(kind, xa, xb, fa, fb, x0, v0, y0, w0, a, wd, hg):
    """Brent's root of a free-flight function bracketed by ``[xa, xb]`` (times in s)."""
    xpre, xcur, fpre, fcur = xa, xb, fa, fb
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    xblk = 0.0
    fblk = 0.0
    spre = 0.0
    scur = 0.0
    xtol = 1e-18
    rtol = 4.0 * 2.220446049250313e-16
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
        delta = 0.5 * (xtol + rtol * abs(xcur))
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
        fcur = _ffval(kind, xcur, x0, v0, y0, w0, a, wd, hg)
    return xcur


@njit(cache=True)
def _scan(x0, v0, y0, w0, tau_end, a, wd, hg):
    """First contact of free flight within ``(0, tau_end]``: (found, tau in s, wall ±1).

    Between consecutive zeros of the main-mass acceleration ``dz/dt`` is monotone, so ``z`` has at
    most one extremum there, found by Brent's method on ``dz/dt``; on each monotone piece a wall
    crossing is bracketed exactly. No contact can be missed, however short the excursion.
    """
    half = math.pi / wd
    tz = _first_acc_zero(x0, v0, a, wd)
    ta = 0.0
    pieces = np.empty(3)
    while ta < tau_end:
        tb = min(tz, tau_end)
        if tb > ta:
            da = _ffval(0, ta, x0, v0, y0, w0, a, wd, hg)
            db = _ffval(0, tb, x0, v0, y0, w0, a, wd, hg)
            npc = 2
            pieces[0] = ta
            if (da < 0.0) != (db < 0.0) and da != 0.0 and db != 0.0:
                pieces[1] = _brent(0, ta, tb, da, db, x0, v0, y0, w0, a, wd, hg)
                pieces[2] = tb
                npc = 3
            else:
                pieces[1] = tb
            for i in range(npc - 1):
                p = pieces[i]
                q = pieces[i + 1]
                hup = _ffval(1, p, x0, v0, y0, w0, a, wd, hg)
                huq = _ffval(1, q, x0, v0, y0, w0, a, wd, hg)
                if huq < hup:  # z increasing: only wall +1 can be reached
                    if hup <= 0.0:
                        return True, p, 1.0
                    if huq <= 0.0:
                        return True, _brent(1, p, q, hup, huq, x0, v0, y0, w0, a, wd, hg), 1.0
                else:
                    hlp = _ffval(2, p, x0, v0, y0, w0, a, wd, hg)
                    hlq = _ffval(2, q, x0, v0, y0, w0, a, wd, hg)
                    if hlq < hlp:
                        if hlp <= 0.0:
                            return True, p, -1.0
                        if hlq <= 0.0:
                            return True, _brent(2, p, q, hlp, hlq, x0, v0, y0, w0, a, wd, hg), -1.0
        ta = tb
        tz += half
    return False, tau_end, 0.0


# ============================================================ contact phase (DOP853)
# The contact is integrated in a transformed time σ with dt = ξ dσ, where ξ = sqrt(δ) is a state
# variable (dξ/dσ = u/2). The Hertz force becomes K_HZ ξ³, a polynomial, so the δ^{3/2}
# singularities at contact onset and end (solution terms in t^{3.5}) disappear: the solution is
# analytic in σ and the 8th-order steps stay long up to both ends. The contact ends at the simple
# root ξ = 0 (dξ/dσ = u/2 < 0 there), located by Newton's method on full Runge-Kutta steps.
# State: t (from onset), x, v, ξ, u = dδ/dt, impulse, dissipated in contact, dissipated by C.
@njit(cache=True)
def _force(d, u, kh, c1, clip):
    """Contact force in N and its elastic part in N at penetration d (m), rate u (m/s)."""
    if d <= 0.0:
        return 0.0, 0.0
    fe = kh * d * math.sqrt(d)
    f = fe + c1 * u
    if clip and f < 0.0:
        f = 0.0
    return f, fe


@njit(cache=True, inline="always")
def _rhs_into(y, p, sw, out, row):
    """Derivatives with respect to σ of the contact state into ``out[row]`` (section comment)."""
    M, K, C, m, kh, c1 = p[0], p[1], p[2], p[3], p[5], p[6]
    clip = p[7] > 0.5
    x, v, xi, u = y[1], y[2], y[3], y[4]
    fe = kh * xi * xi * xi
    f = fe + c1 * u
    if clip and f < 0.0:
        f = 0.0
    spring = K * x + C * v
    out[row, 0] = xi
    out[row, 1] = xi * v
    out[row, 2] = xi * (sw * f - spring) / M
    out[row, 3] = 0.5 * u
    out[row, 4] = xi * (-f / m - f / M + sw * spring / M)
    out[row, 5] = xi * f
    out[row, 6] = xi * (f - fe) * u
    out[row, 7] = xi * C * v * v


@njit(cache=True)
def _rhs(y, p, sw, out):
    """Derivatives with respect to σ of the contact state into the 1-D array ``out``."""
    _rhs_into(y, p, sw, out.reshape((1, _NY)), 0)


@njit(cache=True)
def _dop_step(y, f0, h, p, sw, kst, ytmp, ynew, fnew):
    """One Dormand-Prince 8 step of size ``h``; fills ``ynew``, ``fnew`` and the stages."""
    for i in range(_NY):
        kst[0, i] = f0[i]
    for st in range(1, _NS):
        for i in range(_NY):
            acc = 0.0
            for j in range(st):
                acc += _A[st, j] * kst[j, i]
            ytmp[i] = y[i] + h * acc
        _rhs_into(ytmp, p, sw, kst, st)
    for i in range(_NY):
        acc = 0.0
        for j in range(_NS):
            acc += _B[j] * kst[j, i]
        ynew[i] = y[i] + h * acc
    _rhs_into(ynew, p, sw, kst, _NS)
    for i in range(_NY):
        fnew[i] = kst[_NS, i]


@njit(cache=True)
def _dop_error(y, ynew, h, kst, rtol, atol):
    """Hairer's DOP853 error norm over all components (1 = at tolerance)."""
    e5 = 0.0
    e3 = 0.0
    for i in range(_NY):
        sc = atol[i] + rtol * max(abs(y[i]), abs(ynew[i]))
        a5 = 0.0
        a3 = 0.0
        for j in range(_NS + 1):
            a5 += _E5[j] * kst[j, i]
            a3 += _E3[j] * kst[j, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * _NY)


@njit(cache=True)
def _dfds(y, f, p):
    """Rate of change of the contact force with σ (same sign as dF/dt while ξ > 0)."""
    xi = y[3]
    return 3.0 * p[5] * xi * xi * f[3] + p[6] * f[4]


@njit(cache=True)
def _newton_in_step(kind, target, y, f0, h, glo, p, sw, kst, ytmp, ynew, fnew):
    """Step length in [0, h] where ξ (kind 0) or t - target (kind 2) vanishes.

    Newton's method on the step length (the derivative, u/2 or ξ, is part of the state) kept
    inside the bracket; every trial is a full Dormand-Prince step from the step start, so the
    root is as accurate as the integration. ``ynew``/``fnew`` hold the state at the root and
    ``glo`` is the sign-carrying value at the step start. The first trial reuses ``ynew``.
    """
    lo, hi = 0.0, h
    hm = h
    g = ynew[3] if kind == 0 else ynew[0] - target
    dg = fnew[3] if kind == 0 else fnew[0]
    for _ in range(40):
        hn = hm - g / dg if dg != 0.0 else 0.5 * (lo + hi)
        if not (lo < hn < hi):
            hn = 0.5 * (lo + hi)
        _dop_step(y, f0, hn, p, sw, kst, ytmp, ynew, fnew)
        g = ynew[3] if kind == 0 else ynew[0] - target
        dg = fnew[3] if kind == 0 else fnew[0]
        if (g > 0.0) == (glo > 0.0):
            lo = hn
        else:
            hi = hn
        done = abs(hn - hm) <= 8.0 * 2.220446049250313e-16 * hn or g == 0.0
        hm = hn
        if done or hi - lo <= 4.0 * 2.220446049250313e-16 * hi:
            break
    return hm


@njit(cache=True)
def _peak_in_step(y, f0, h, g0, g1, p, sw, kst, ytmp, ynew, fnew):
    """Step length in (0, h] where dF/dσ vanishes (Illinois; loose, the peak value is flat)."""
    lo, hi = 0.0, h
    glo, ghi = g0, g1
    side = 0
    hm = hi
    for _ in range(60):
        hm = (lo * ghi - hi * glo) / (ghi - glo) if ghi != glo else 0.5 * (lo + hi)
        if not (lo < hm < hi):
            hm = 0.5 * (lo + hi)
        _dop_step(y, f0, hm, p, sw, kst, ytmp, ynew, fnew)
        gm = _dfds(ynew, fnew, p)
        if gm == 0.0:
            break
        if (gm > 0.0) == (glo > 0.0):
            lo, glo = hm, gm
            if side == -1:
                ghi *= 0.5
            side = -1
        else:
            hi, ghi = hm, gm
            if side == 1:
                glo *= 0.5
            side = 1
        if hi - lo <= 1e-6 * h:  # relative force error ~ (time error / contact time)^2 < 1e-12
            break
    return hm


@njit(cache=True)
def _copy(src, dst):
    for i in range(src.shape[0]):
        dst[i] = src[i]


@njit(cache=True)
def _contact(p, sw, x, v, d0, u0, tc, t_end, rtol, t_eval, ie, dense, ec0, en0, work, kst):
    """Integrate one contact from its onset at ``tc`` s until the bodies part or ``t_end``.

    Returns ``(ended, status, ie, duration, peak_force, yout)`` where ``yout`` is the 8-component
    state at the end (t from onset, x, v, ξ = sqrt(δ), u, impulse, dissipated in contact,
    dissipated by C).
    """
    M, m, kh, hg, c1 = p[0], p[3], p[5], p[4], p[6]
    meff = m * M / (m + M)
    clip = p[7] > 0.5
    y = work[0]
    f0 = work[1]
    ytmp = work[2]
    ynew = work[3]
    fnew = work[4]
    yd = work[5]
    fd = work[6]
    atol = work[7]
    ys = work[8]
    fs = work[9]
    y[0] = 0.0
    y[1] = x
    y[2] = v
    y[3] = math.sqrt(max(d0, 0.0))
    y[4] = u0
    y[5] = 0.0
    y[6] = 0.0
    y[7] = 0.0
    uref = max(abs(u0), 1e-9)
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
    _rhs(y, p, sw, f0)
    peak, _ = _force(d0, u0, kh, c1, clip)
    h = 0.02 * tau_h / math.sqrt(amax)  # σ has units of s / sqrt(m)
    status = 0
    ended = False
    nrej = 0
    rejected = False
    t_stop = t_end - tc
    while True:
        _dop_step(y, f0, h, p, sw, kst, ytmp, ynew, fnew)
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
        hstep = h
        exiting = ynew[3] <= 0.0
        if exiting:
            _copy(ynew, ys)
            _copy(fnew, fs)
            hstep = _newton_in_step(0, 0.0, y, f0, h, y[3], p, sw, kst, ytmp, ynew, fnew)
        stopping = ynew[0] >= t_stop
        if stopping:
            exiting = False
            hstep = _newton_in_step(2, t_stop, y, f0, hstep, -1.0, p, sw, kst, ytmp, ynew, fnew)
        g0 = _dfds(y, f0, p)
        g1 = _dfds(ynew, fnew, p)
        if g0 > 0.0 and g1 <= 0.0:
            _copy(ynew, yd)
            _copy(fnew, fd)
            _peak_in_step(y, f0, hstep, g0, g1, p, sw, kst, ytmp, ynew, fnew)
            fpk, _ = _force(ynew[3] * ynew[3], ynew[4], kh, c1, clip)
            peak = max(peak, fpk)
            _copy(yd, ynew)
            _copy(fd, fnew)
        fend, _ = _force(max(ynew[3], 0.0) ** 2, ynew[4], kh, c1, clip)
        peak = max(peak, fend)
        # dense output inside the step: Newton on t(σ) with full steps from the step start
        while ie < t_eval.shape[0] and t_eval[ie] - tc <= ynew[0]:
            _copy(ynew, yd)
            _copy(fnew, fd)
            target = t_eval[ie] - tc
            if target > y[0]:
                _newton_in_step(2, target, y, f0, hstep, -1.0, p, sw, kst, ytmp, ynew, fnew)
            else:
                _copy(y, ynew)
            xi = max(ynew[3], 0.0)
            dense[ie, 0] = ynew[1]
            dense[ie, 1] = ynew[2]
            dense[ie, 2] = ynew[1] + sw * (hg + xi * xi)
            dense[ie, 3] = ynew[2] + sw * ynew[4]
            dense[ie, 4] = ec0 + ynew[7]
            dense[ie, 5] = en0 + ynew[6]
            _copy(yd, ynew)
            _copy(fd, fnew)
            ie += 1
        _copy(ynew, y)
        _copy(fnew, f0)
        if exiting:
            ended = True
            break
        if stopping:
            break
        # no growth right after a rejection (Hairer, Norsett, Wanner, II.4); a safety factor of
        # 0.8 on growth cuts rejections from ~20 % to ~5 % of the steps and the total by ~7 %
        grow = 1.0 if rejected else 10.0
        rejected = False
        if err == 0.0:
            h = h * grow
        else:
            h = h * min(grow, 0.8 * err ** (-1.0 / 8.0))
    return ended, status, ie, y[0], peak, y


# ============================================================ drivers
@njit(cache=True)
def _free_contact(pfree, u0, rtol, work, kst):
    """Compliant contact of the two masses alone at approach speed ``u0`` m/s.

    Returns ``(status, restitution, duration in s, peak force in N)``.
    """
    ended, st, _, dur, peak, yc = _contact(
        pfree, 1.0, 0.0, 0.0, 0.0, u0, 0.0, math.inf, rtol, np.empty(0), 0, np.empty((0, 6)),
        0.0, 0.0, work, kst
    )
    e = max(-yc[4], 0.0) / u0 if u0 > 0.0 else 0.0
    return st, e, dur, peak


@njit(cache=True)
def restitution_table(p, lnu, rtol, table):
    """Fill ``table`` (n, 3) with restitution, ln(duration/s), ln(peak force/N) at speeds exp(lnu).

    The compliant contact of the two masses alone (no main spring or dashpot), as used by the
    impact map; ``lnu`` must be uniformly spaced. Returns the worst status.
    """
    pfree = p.copy()
    pfree[1] = 0.0
    pfree[2] = 0.0
    work = np.zeros((10, _NY))
    kst = np.zeros((_NS + 1, _NY))
    status = STATUS_OK
    for i in range(lnu.shape[0]):
        st, e, dur, peak = _free_contact(pfree, math.exp(lnu[i]), rtol, work, kst)
        table[i, 0] = e
        table[i, 1] = math.log(dur)
        table[i, 2] = math.log(peak)
        status = max(status, st)
    return status


@njit(cache=True)
def _table_lookup(lnu, table, x, col):
    """Cubic (Catmull-Rom) interpolation of ``table[:, col]`` on the uniform grid ``lnu``."""
    n = lnu.shape[0]
    d = lnu[1] - lnu[0]
    s = (x - lnu[0]) / d
    i = min(max(int(math.floor(s)), 1), n - 3)
    t = s - i
    p0, p1, p2, p3 = table[i - 1, col], table[i, col], table[i + 1, col], table[i + 2, col]
    return p1 + 0.5 * t * (p2 - p0 + t * (2 * p0 - 5 * p1 + 4 * p2 - p3 + t * (3 * (p1 - p2) + p3 - p0)))


@njit(cache=True)
def event_solver(p, state0, t_end, rtol, t_eval, max_impacts, impacts, dense, final, impact_map,
                 lnu, table):
    """Event-driven (``impact_map=False``) or impact-map (``True``) integration from t = 0.

    The impact map takes the restitution, duration and peak force at each approach speed from
    ``table`` (see :func:`restitution_table`) by cubic interpolation in ln(speed) inside the
    table's inner range, and integrates the compliant contact directly outside it.

    Fills ``impacts`` (rows as ``IMPACT_COLUMNS``), ``dense`` (rows as ``DENSE_COLUMNS`` at
    ``t_eval``) and ``final`` (x, v, y, w, dissipated by C, dissipated in contacts, delta at the
    end). Returns ``(n_impacts, status, t_reached)``.
    """
    M, K, C, m, hg = p[0], p[1], p[2], p[3], p[4]
    meff = m * M / (m + M)
    a = C / (2.0 * M)
    wd = math.sqrt(K / M - a * a)
    work = np.zeros((10, _NY))
    kst = np.zeros((_NS + 1, _NY))
    pfree = p.copy()
    pfree[1] = 0.0
    pfree[2] = 0.0
    x0, v0, y0, w0 = state0[0], state0[1], state0[2], state0[3]
    t0 = 0.0
    ec = 0.0
    en = 0.0
    ie = 0
    n = 0
    status = STATUS_OK
    dfinal = 0.0
    while True:
        found, tau, sw = _scan(x0, v0, y0, w0, t_end - t0, a, wd, hg)
        tstop = t0 + tau if found else t_end
        eosc0 = 0.5 * M * v0 * v0 + 0.5 * K * x0 * x0
        while ie < t_eval.shape[0] and t_eval[ie] <= tstop:
            tt = t_eval[ie] - t0
            xx, vv = _osc(x0, v0, tt, a, wd)
            dense[ie, 0] = xx
            dense[ie, 1] = vv
            dense[ie, 2] = y0 + w0 * tt
            dense[ie, 3] = w0
            dense[ie, 4] = ec + eosc0 - (0.5 * M * vv * vv + 0.5 * K * xx * xx)
            dense[ie, 5] = en
            ie += 1
        xx, vv = _osc(x0, v0, tau, a, wd)
        yy = y0 + w0 * tau
        ec += eosc0 - (0.5 * M * vv * vv + 0.5 * K * xx * xx)
        if not found:
            x0, v0, y0 = xx, vv, yy
            break
        if n >= max_impacts:
            status = STATUS_MAX_IMPACTS
            x0, v0, y0 = xx, vv, yy
            t_end = tstop
            break
        tc = tstop
        d0 = max(sw * (yy - xx) - hg, 0.0)
        u0 = sw * (w0 - vv)
        impacts[n, 0] = tc
        impacts[n, 1] = sw
        impacts[n, 2] = u0
        if impact_map:
            lu = math.log(u0) if u0 > 0.0 else -math.inf
            if lnu.shape[0] >= 4 and lnu[1] <= lu <= lnu[lnu.shape[0] - 2]:
                st = STATUS_OK
                e = _table_lookup(lnu, table, lu, 0)
                dur = math.exp(_table_lookup(lnu, table, lu, 1))
                peak = math.exp(_table_lookup(lnu, table, lu, 2))
            else:
                st, e, dur, peak = _free_contact(pfree, u0, rtol, work, kst)
            jimp = (1.0 + e) * meff * u0
            x0 = xx
            v0 = vv + sw * jimp / M
            w0 = w0 - sw * jimp / m
            y0 = x0 + sw * hg
            lost = 0.5 * meff * u0 * u0 * (1.0 - e * e)
            en += lost
            impacts[n, 3] = e * u0
            impacts[n, 4] = dur
            impacts[n, 5] = peak
            impacts[n, 6] = jimp
            impacts[n, 7] = lost
            n += 1
            t0 = tc
            if st != STATUS_OK:
                status = st
                break
            continue
        ended, st, ie, dur, peak, yc = _contact(
            p, sw, xx, vv, d0, u0, tc, t_end, rtol, t_eval, ie, dense, ec, en, work, kst
        )
        ec += yc[7]
        en += yc[6]
        impacts[n, 3] = -yc[4]
        impacts[n, 4] = dur
        impacts[n, 5] = peak
        impacts[n, 6] = yc[5]
        impacts[n, 7] = yc[6]
        n += 1
        x0, v0 = yc[1], yc[2]
        dlt = yc[3] * abs(yc[3])
        y0 = x0 + sw * (hg + dlt)
        w0 = v0 + sw * yc[4]
        t0 = tc + dur
        if st != STATUS_OK:
            status = st
            t_end = t0
            break
        if not ended:
            dfinal = dlt
            impacts[n - 1, 3] = math.nan
            break
    final[0] = x0
    final[1] = v0
    final[2] = y0
    final[3] = w0
    final[4] = ec
    final[5] = en
    final[6] = dfinal
    return n, status, t_end


@njit(cache=True)
def _nm_force(x, y, v, w, hg, kh, c1, clip):
    """Contact state for Newmark: (wall, delta m, rate m/s, force N, elastic force N, stiffness N/m)."""
    z = y - x
    if z > hg:
        sw = 1.0
    elif z < -hg:
        sw = -1.0
    else:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    d = sw * z - hg
    u = sw * (w - v)
    sq = math.sqrt(d)
    fe = kh * d * sq
    f = fe + c1 * u
    kt = 1.5 * kh * sq
    if clip and f < 0.0:
        return sw, d, u, 0.0, fe, -1.0
    return sw, d, u, f, fe, kt


@njit(cache=True)
def newmark(p, state0, h, nsteps, t_eval, max_impacts, impacts, dense, final):
    """Average-acceleration Newmark-beta (γ = 1/2, β = 1/4) with Newton iterations, fixed step h s.

    Contact onset and end are located by linear interpolation of the penetration between steps;
    the approach (separation) speed is extrapolated from the free side of the step, because the
    paper's damping force jumps at first touch.
    Returns ``(n_impacts, status, t_reached)``; arrays as in :func:`event_solver`.
    """
    M, K, C, m, hg, kh, c1 = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    clip = p[7] > 0.5
    x, v, y, w = state0[0], state0[1], state0[2], state0[3]
    sw, d, u, f, fe, kt = _nm_force(x, y, v, w, hg, kh, c1, clip)
    ax = (sw * f - K * x - C * v) / M
    ay = -sw * f / m
    ec = 0.0
    en = 0.0
    n = 0
    ie = 0
    status = STATUS_OK
    in_contact = sw != 0.0
    peak = 0.0
    jimp = 0.0
    lost = 0.0
    pw_prev = (f - fe) * u
    t = 0.0
    hh = 0.25 * h * h
    h2 = 0.5 * h
    escale = 1e-13 * (abs(v) + abs(w) + 1.0)
    for k in range(nsteps):
        t1 = (k + 1) * h
        # predictor: unchanged acceleration
        bx = ax
        by = ay
        for _ in range(30):
            x1 = x + h * v + hh * (ax + bx)
            y1 = y + h * w + hh * (ay + by)
            v1 = v + h2 * (ax + bx)
            w1 = w + h2 * (ay + by)
            sw1, d1, u1, f1, fe1, kt1 = _nm_force(x1, y1, v1, w1, hg, kh, c1, clip)
            r1 = M * bx + K * x1 + C * v1 - sw1 * f1
            r2 = m * by + sw1 * f1
            if kt1 < 0.0:  # clipped: no contact stiffness or damping
                kc = 0.0
                cc = 0.0
            else:
                kc = kt1
                cc = c1 if sw1 != 0.0 else 0.0
            j11 = M + h2 * (C + cc) + hh * (K + kc)
            j12 = -h2 * cc - hh * kc
            j22 = m + h2 * cc + hh * kc
            det = j11 * j22 - j12 * j12
            dbx = (j22 * r1 - j12 * r2) / det
            dby = (j11 * r2 - j12 * r1) / det
            bx -= dbx
            by -= dby
            if abs(dbx) * h + abs(dby) * h <= escale:
                break
        x1 = x + h * v + hh * (ax + bx)
        y1 = y + h * w + hh * (ay + by)
        v1 = v + h2 * (ax + bx)
        w1 = w + h2 * (ay + by)
        sw1, d1, u1, f1, fe1, kt1 = _nm_force(x1, y1, v1, w1, hg, kh, c1, clip)
        if not (math.isfinite(x1) and math.isfinite(y1)):
            status = STATUS_DIVERGED
            break
        ec += h2 * C * (v * v + v1 * v1)
        pw = (f1 - fe1) * u1
        en += h2 * (pw_prev + pw)
        # impacts
        now = sw1 != 0.0
        if now and not in_contact:
            if n >= max_impacts:
                status = STATUS_MAX_IMPACTS
                t = t1
                x, v, y, w = x1, v1, y1, w1
                break
            z0 = sw1 * (y - x) - hg
            fr = -z0 / (d1 - z0) if d1 != z0 else 1.0
            impacts[n, 0] = t + fr * h
            impacts[n, 1] = sw1
            # extrapolate from the free side: the damping force jumps at first touch
            impacts[n, 2] = sw1 * (w - v) + fr * h * sw1 * (ay - ax)
            peak = 0.0
            jimp = 0.0
            lost = 0.0
        if now:
            peak = max(peak, f1)
            jimp += h2 * (f + f1) if in_contact else h2 * f1
            lost += h2 * (pw_prev + pw)
        if in_contact and not now:
            swp = sw
            zp = d
            z1 = swp * (y1 - x1) - hg
            fr = zp / (zp - z1) if zp != z1 else 1.0
            impacts[n, 3] = -(swp * (w1 - v1) - (1.0 - fr) * h * swp * (by - bx))
            impacts[n, 4] = t + fr * h - impacts[n, 0]
            impacts[n, 5] = peak
            impacts[n, 6] = jimp + h2 * f
            impacts[n, 7] = lost
            n += 1
        # dense output: cubic Hermite in displacement, linear acceleration in velocity
        while ie < t_eval.shape[0] and t_eval[ie] <= t1 + 1e-9 * h:
            s = min((t_eval[ie] - t) / h, 1.0)
            h00 = 2 * s**3 - 3 * s**2 + 1
            h10 = s**3 - 2 * s**2 + s
            h01 = -2 * s**3 + 3 * s**2
            h11 = s**3 - s**2
            dense[ie, 0] = h00 * x + h10 * h * v + h01 * x1 + h11 * h * v1
            dense[ie, 1] = h00 * v + h10 * h * ax + h01 * v1 + h11 * h * bx
            dense[ie, 2] = h00 * y + h10 * h * w + h01 * y1 + h11 * h * w1
            dense[ie, 3] = h00 * w + h10 * h * ay + h01 * w1 + h11 * h * by
            dense[ie, 4] = ec - (1.0 - s) * h2 * C * (v * v + v1 * v1)
            dense[ie, 5] = en - (1.0 - s) * h2 * (pw_prev + pw)
            ie += 1
        x, v, y, w = x1, v1, y1, w1
        ax, ay = bx, by
        sw, d, u, f, fe = sw1, d1, u1, f1, fe1
        pw_prev = pw
        in_contact = now
        t = t1
    if in_contact and n < max_impacts:
        impacts[n, 3] = math.nan
        impacts[n, 4] = t - impacts[n, 0]
        impacts[n, 5] = peak
        impacts[n, 6] = jimp
        impacts[n, 7] = lost
        n += 1
    final[0] = x
    final[1] = v
    final[2] = y
    final[3] = w
    final[4] = ec
    final[5] = en
    final[6] = d if in_contact else 0.0
    return n, status, t


@njit(cache=True)
def central_difference(p, state0, h, nsteps):
    """Explicit central-difference integration; returns the largest |y - x| in m reached.

    Used only to show where an explicit scheme fails: it is stable for ``h < 2 / ω_contact``.
    Damping forces use the previous half-step velocity (explicit).
    """
    M, K, C, m, hg, kh, c1 = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    clip = p[7] > 0.5
    x, v, y, w = state0[0], state0[1], state0[2], state0[3]
    vh = v
    wh = w
    zmax = abs(y - x)
    for _ in range(nsteps):
        sw, d, u, f, fe, _ = _nm_force(x, y, vh, wh, hg, kh, c1, clip)
        ax = (sw * f - K * x - C * vh) / M
        ay = -sw * f / m
        vh += h * ax
        wh += h * ay
        x += h * vh
        y += h * wh
        zmax = max(zmax, abs(y - x))
        if not math.isfinite(zmax) or zmax > 1e3:
            return math.inf
    return zmax
