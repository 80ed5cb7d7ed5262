"""Compiled Newmark-beta kernel of the forced impact damper (numba): the independent second method.

State, impact rows and accumulators as in :mod:`._forced_kernels`; the forcing vector ``fc`` is
``[ω rad/s, P N, Q N, A_c m, A_s m]`` with the external force ``P cos(ωt) + Q sin(ωt)`` on the
main mass.
"""

from __future__ import annotations

import math

from numba import njit

from ._forced_kernels import STATUS_DIVERGED, STATUS_MAX_IMPACTS, STATUS_OK


@njit(cache=True)
def _nm_force(x, y, v, w, hg, kh, c1, clip):
    """Contact (wall, δ m, rate m/s, force N, elastic force N, tangent stiffness N/m) for Newmark."""
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
    if clip and f < 0.0:
        return sw, d, u, 0.0, fe, -1.0
    return sw, d, u, f, fe, 1.5 * kh * sq


@njit(cache=True)
def newmark_advance(p, fc, st, t0, h, nsteps, impacts, n, max_impacts, acc, extrema):
    """Average-acceleration Newmark-beta (γ = 1/2, β = 1/4) with forcing, ``nsteps`` steps of ``h`` s.

    Newton iterations on the contact force, as the paper's scheme (Clough and Penzien); contact
    onset and end interpolated linearly between steps. State, impacts and accumulators as in
    :func:`advance` (work and dissipation by the trapezoidal rule). Returns ``(n, status)``.
    """
    M, K, C, m, hg, kh, c1 = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    clip = p[7] > 0.5
    om, pc, ps = fc[0], fc[1], fc[2]
    x, v, y, w = st[0], st[1], st[2], st[3]
    sw, d, u, f, fe, kt = _nm_force(x, y, v, w, hg, kh, c1, clip)
    fx = pc * math.cos(om * t0) + ps * math.sin(om * t0)
    ax = (sw * f - K * x - C * v + fx) / M
    ay = -sw * f / m
    in_contact = sw != 0.0 and st[4] > 0.5
    pw_prev = (f - fe) * u
    hh = 0.25 * h * h
    h2 = 0.5 * h
    escale = 1e-13 * (abs(v) + abs(w) + 1.0)
    t = t0
    for k in range(nsteps):
        t1 = t0 + (k + 1) * h
        fx1 = pc * math.cos(om * t1) + ps * math.sin(om * t1)
        bx = ax
        by = ay
        for _ in range(30):
            x1 = x + h * v + hh * (ax + bx)
            y1 = y + h * w + hh * (ay + by)
            v1 = v + h2 * (ax + bx)
            w1 = w + h2 * (ay + by)
            sw1, d1, u1, f1, fe1, kt1 = _nm_force(x1, y1, v1, w1, hg, kh, c1, clip)
            r1 = M * bx + K * x1 + C * v1 - sw1 * f1 - fx1
            r2 = m * by + sw1 * f1
            kc = 0.0 if kt1 < 0.0 else kt1
            cc = c1 if (sw1 != 0.0 and kt1 >= 0.0) else 0.0
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
            return n, STATUS_DIVERGED
        acc[0] += h2 * (fx * v + fx1 * v1)
        acc[1] += h2 * C * (v * v + v1 * v1)
        pw = (f1 - fe1) * u1
        acc[2] += h2 * (pw_prev + pw)
        if extrema:
            acc[3] = max(acc[3], x1)
            acc[4] = min(acc[4], x1)
        now = sw1 != 0.0
        if now and not in_contact:
            if n >= max_impacts:
                return n, STATUS_MAX_IMPACTS
            z0 = sw1 * (y - x) - hg
            fr = -z0 / (d1 - z0) if d1 != z0 else 1.0
            impacts[n, 0] = t + fr * h
            impacts[n, 1] = sw1
            impacts[n, 2] = sw1 * (w - v) + fr * h * sw1 * (ay - ax)
            impacts[n, 3] = math.nan
            for j in range(4, 8):
                impacts[n, j] = 0.0
            n += 1
        if now:
            r = n - 1
            impacts[r, 5] = max(impacts[r, 5], f1)
            impacts[r, 6] += h2 * (f + f1) if in_contact else h2 * f1
            impacts[r, 7] += h2 * (pw_prev + pw)
        if in_contact and not now:
            r = n - 1
            zp = d
            z1 = sw * (y1 - x1) - hg
            fr = zp / (zp - z1) if zp != z1 else 1.0
            impacts[r, 3] = -(sw * (w1 - v1) - (1.0 - fr) * h * sw * (by - bx))
            impacts[r, 4] = t + fr * h - impacts[r, 0]
            impacts[r, 6] += h2 * f
        x, v, y, w = x1, v1, y1, w1
        ax, ay = bx, by
        sw, d, f, fe, fx = sw1, d1, f1, fe1, fx1
        pw_prev = pw
        in_contact = now
        t = t1
    st[0] = x
    st[1] = v
    st[2] = y
    st[3] = w
    st[4] = 1.0 if in_contact else 0.0
    st[5] = sw
    return n, STATUS_OK
