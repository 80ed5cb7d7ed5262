"""Fixed-step solvers of the impact damper (numba).

The paper's Newmark-beta scheme, and explicit central differences (only to show where an
explicit scheme fails).

Parameter vector ``p`` (floats): ``[M, K, C, m, half_gap, k_hertz, c1, clip]``; arrays as in
:func:`acoustiviz.dynamics._kernels.event_solver`.
"""

from __future__ import annotations

import math

from numba import njit

from ._free import record_extremum
from ._status import STATUS_DIVERGED, STATUS_MAX_IMPACTS, STATUS_OK


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
def _hermite_turn(x, v, x1, v1, h):
    """Where the cubic Hermite interpolant of a step turns: (fraction s in [0, 1], x in m).

    Its slope ``h00' x + h10' h v + h01' x1 + h11' h v1`` is a quadratic in ``s`` with opposite
    signs at the ends (the caller checks ``v`` and ``v1``), so it has one root there; found by
    bisection to round-off.
    """
    c2 = 6.0 * (x - x1) + 3.0 * h * (v + v1)
    c1 = 6.0 * (x1 - x) - h * (4.0 * v + 2.0 * v1)
    c0 = h * v
    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if ((c2 * mid + c1) * mid + c0 > 0.0) == (c0 > 0.0):
            lo = mid
        else:
            hi = mid
    s = 0.5 * (lo + hi)
    h00 = 2 * s**3 - 3 * s**2 + 1
    h10 = s**3 - 2 * s**2 + s
    h01 = -2 * s**3 + 3 * s**2
    h11 = s**3 - s**2
    return s, h00 * x + h10 * h * v + h01 * x1 + h11 * h * v1


@njit(cache=True)
def newmark(p, state0, h, nsteps, t_eval, max_impacts, impacts, dense, final, ext, n_ext):
    """Average-acceleration Newmark-beta (γ = 1/2, β = 1/4) with Newton iterations, fixed step h s.

    Contact onset and end are located by linear interpolation of the penetration between steps;
    the approach (separation) speed is extrapolated from the free side of the step, because the
    paper's damping force jumps at first touch.
    Extrema of x (into ``ext``) are the turning points of the cubic Hermite interpolant of each
    step whose end velocities differ in sign (:func:`_hermite_turn`), the interpolant of the
    dense output. Returns ``(n_impacts, status, t_reached)``; arrays as in :func:`event_solver`.
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
        if (v > 0.0) != (v1 > 0.0):
            s_turn, x_turn = _hermite_turn(x, v, x1, v1, h)
            record_extremum(ext, n_ext, t + s_turn * h, x_turn, 1.0 if v > 0.0 else -1.0)
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
