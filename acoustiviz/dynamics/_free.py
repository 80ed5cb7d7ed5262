"""Closed-form free flight of the impact damper (numba), with exact detection of contact onset.

The main mass is a damped linear oscillator and the impact mass flies at constant velocity;
contact onsets are bracketed exactly.

Times ``tau`` are measured from the start of the flight, in s; ``a = C / (2M)`` in 1/s and
``wd`` the damped angular frequency in rad/s; ``hg`` is half the gap in m.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


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
def record_extremum(ext, n_ext, t, x, kind):
    """Append an extremum of the main-mass displacement (time s, x m, +1 max / -1 min) to ``ext``.

    ``n_ext[0]`` counts every extremum found, also those beyond the capacity of ``ext`` (the
    caller compares the count with the capacity).
    """
    k = n_ext[0]
    if k < ext.shape[0]:
        ext[k, 0] = t
        ext[k, 1] = x
        ext[k, 2] = kind
    n_ext[0] = k + 1


@njit(cache=True)
def free_extrema(x0, v0, tau_end, a, wd, t0, ext, n_ext):
    """Record the extrema of the free main mass in ``(0, tau_end]`` (times from ``t0`` s).

    The velocity of the damped oscillator is ``e^{-a τ} (p cos ωd τ + q sin ωd τ)``, so its zeros
    are ``ωd τ = atan2(q, p) + π/2 + kπ`` exactly; one Newton step on the closed-form velocity
    polishes each. At a zero the acceleration is ``-K x / M``: a maximum where ``x > 0``.
    """
    if wd <= 0.0 or tau_end <= 0.0:
        return
    q0 = (v0 + a * x0) / wd
    p1 = -a * x0 + wd * q0
    q1 = -a * q0 - wd * x0
    if p1 == 0.0 and q1 == 0.0:
        return  # at rest
    th = math.atan2(q1, p1) + 0.5 * math.pi
    th = th + math.ceil(-th / math.pi) * math.pi
    if th <= 0.0:
        th += math.pi
    w2 = a * a + wd * wd
    while th / wd <= tau_end:
        tau = th / wd
        x, v = _osc(x0, v0, tau, a, wd)
        acc = -w2 * x - 2.0 * a * v
        if acc != 0.0:
            tn = tau - v / acc
            if 0.0 < tn <= tau_end and abs(tn - tau) < 1e-6 / wd:
                tau = tn
                x, v = _osc(x0, v0, tau, a, wd)
        if x != 0.0:
            record_extremum(ext, n_ext, t0 + tau, x, 1.0 if x > 0.0 else -1.0)
        th += math.pi


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
