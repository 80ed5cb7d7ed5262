"""Fixed-step solvers of the impact damper (numba), free decay and forced.

The paper's average-acceleration Newmark-beta scheme (one kernel, :func:`newmark_advance`, with
the external force ``F(t) = P cos(ωt) + Q sin(ωt)`` on the main mass as a parameter; free decay
is ``F = 0``), and explicit central differences (only to show where an explicit scheme fails).

Equations (paper eq 15 with forcing), wall ``s = ±1``, penetration ``δ = s (y - x) - d/2``::

    M x'' + C x' + K x = s F_c + F(t),   m y'' = -s F_c,   F_c = K_HZ δ^{3/2} + c1 dδ/dt (δ > 0).

Parameter vector ``p`` (floats): ``[M, K, C, m, half_gap, k_hertz, c1, clip]``; forcing vector
``fc``: None (free decay, compiled without the forcing terms) or ``[ω rad/s, P N, Q N, ...]``.
State ``st`` (in/out, 8 floats): ``x, v, y, w`` (m, m/s), in-contact flag, wall; impact rows as ``IMPACT_COLUMNS`` of
:mod:`._status` (a row is opened at contact onset with a NaN separation speed and closed at the
end of the contact). Accumulators ``acc`` (added to): work of F, dissipated by C, dissipated in
contacts (J), largest and smallest x (m).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._flight import record_extremum
from ._status import STATUS_DIVERGED, STATUS_MAX_IMPACTS, STATUS_OK


@njit(cache=True)
def _nm_force(x, y, v, w, hg, kh, c1, clip):
    """Contact state for Newmark: (wall, δ m, rate m/s, force N, elastic force N, stiffness N/m).

    ``F_c = K_HZ δ^{3/2} + c1 dδ/dt`` and its tangent stiffness ``1.5 K_HZ δ^{1/2}`` (-1 when the
    force is clipped at zero).
    """
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
def newmark_advance(p, fc, st, t0, h, nsteps, impacts, n, max_impacts, acc, minmax, t_eval, ie, dense,  # noqa: C901 - one compiled kernel
                    ext, n_ext):
    """Average-acceleration Newmark-beta (γ = 1/2, β = 1/4), ``nsteps`` steps of ``h`` s from ``t0`` s.

    Each step solves ``M a_x + C v + K x - s F_c - F = 0``, ``m a_y + s F_c = 0`` at the new
    time with ``x1 = x + h v + h²/4 (a + a1)``, ``v1 = v + h/2 (a + a1)`` by Newton iterations on
    the accelerations (the paper's scheme; Clough and Penzien). Contact onset and end are located
    by linear interpolation of the penetration between steps; the approach (separation) speed is
    extrapolated from the free side of the step, because the paper's damping force jumps at first
    touch. Work and dissipation by the trapezoidal rule into ``acc[0:3]``; with ``minmax`` the
    step-end extremes of x into ``acc[3:5]``.

    Extrema of x (into ``ext``, ``n_ext`` counting) are the turning points of the cubic Hermite
    interpolant of each step whose end velocities differ in sign (:func:`_hermite_turn`), the
    interpolant of the dense output (x, v, y, w, dissipated by C and in contacts at ``t_eval``
    into ``dense`` from row ``ie``); ``ext=None`` and ``t_eval=None`` compile them out.

    Parameters
    ----------
    p : ndarray
        ``[M kg, K N/m, C N s/m, m kg, d/2 m, K_HZ N/m^1.5, c1 N s/m, clip]``.
    fc : ndarray or None
        Forcing ``[ω rad/s, P N, Q N, ...]``; None for free decay (compiled without it).
    st : ndarray
        State (module docstring), updated in place.
    t0, h : float
        Start time and step (s).
    nsteps : int
        Steps to take.
    impacts, n, max_impacts : ndarray, int, int
        Impact rows, the first free row and the row limit.
    acc : ndarray
        Accumulators (module docstring), added to.
    minmax : bool
        Track the step-end extremes of x in ``acc[3:5]``.
    t_eval, ie, dense : ndarray, int, ndarray, or None, 0, None
        Output times (s), the next one due, and the (n, 6) dense rows.
    ext, n_ext : ndarray or None
        Turning points of x (rows: time s, x m, ±1) and their count.

    Returns
    -------
    n : int
        The next free impact row.
    status : int
        ``STATUS_OK``, ``STATUS_MAX_IMPACTS`` or ``STATUS_DIVERGED``.
    t : float
        Time reached (s); ``st`` holds the state there.
    ie : int
        The next output time due.
    """
    M, K, C, m, hg, kh, c1 = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    clip = p[7] > 0.5
    om = 0.0
    pc = 0.0
    ps = 0.0
    forced = False
    if fc is not None:  # removed at compile time for free decay
        om, pc, ps = fc[0], fc[1], fc[2]
        forced = True
    x, v, y, w = st[0], st[1], st[2], st[3]
    sw, d, u, f, fe, kt = _nm_force(x, y, v, w, hg, kh, c1, clip)
    fx = pc * math.cos(om * t0) + ps * math.sin(om * t0) if forced else 0.0
    ax = (sw * f - K * x - C * v + fx) / M
    ay = -sw * f / m
    in_contact = sw != 0.0 and st[4] > 0.5
    wk, ec, en, xmax, xmin = acc[0], acc[1], acc[2], acc[3], acc[4]
    status = STATUS_OK
    pw_prev = (f - fe) * u
    hh = 0.25 * h * h
    h2 = 0.5 * h
    escale = 1e-13 * (abs(v) + abs(w) + 1.0)
    t = t0
    for k in range(nsteps):
        t1 = t0 + (k + 1) * h
        fx1 = pc * math.cos(om * t1) + ps * math.sin(om * t1) if forced else 0.0
        # predictor: unchanged acceleration
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
        if forced:
            wk += h2 * (fx * v + fx1 * v1)
        ec += h2 * C * (v * v + v1 * v1)
        pw = (f1 - fe1) * u1
        en += h2 * (pw_prev + pw)
        if minmax:
            xmax = max(xmax, x1)
            xmin = min(xmin, x1)
        # impacts: a row opens at onset and closes when the contact ends
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
            z1 = sw * (y1 - x1) - hg
            fr = d / (d - z1) if d != z1 else 1.0
            impacts[r, 3] = -(sw * (w1 - v1) - (1.0 - fr) * h * sw * (by - bx))
            impacts[r, 4] = t + fr * h - impacts[r, 0]
            impacts[r, 6] += h2 * f
        if ext is not None and (v > 0.0) != (v1 > 0.0):  # ext=None: compiled out
            s_turn, x_turn = _hermite_turn(x, v, x1, v1, h)
            record_extremum(ext, n_ext, t + s_turn * h, x_turn, 1.0 if v > 0.0 else -1.0)
        # dense output: cubic Hermite in displacement, linear acceleration in velocity
        if t_eval is not None:  # t_eval=None: compiled out
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
    acc[0] = wk
    acc[1] = ec
    acc[2] = en
    acc[3] = xmax
    acc[4] = xmin
    return n, status, t, ie


@njit(cache=True)
def newmark(p, state0, h, nsteps, t_eval, max_impacts, impacts, dense, final, ext, n_ext):
    """Free decay by :func:`newmark_advance` from t = 0 (no forcing), ``nsteps`` steps of ``h`` s.

    A start inside a contact opens an impact row at t = 0. A contact still open at the end
    keeps a NaN separation speed and its duration so far. Fills ``final`` (x, v, y, w,
    dissipated by C, dissipated in contacts, δ at the end; SI). Returns
    ``(n_impacts, status, t_reached)``; arrays as in
    :func:`~acoustiviz.dynamics._kernels.event_solver`.
    """
    hg = p[4]
    st = np.zeros(8)
    for i in range(4):
        st[i] = state0[i]
    z = state0[2] - state0[0]
    n = 0
    if abs(z) > hg:  # a start inside a contact
        sw = 1.0 if z > 0.0 else -1.0
        st[4] = 1.0
        st[5] = sw
        impacts[0, 0] = 0.0
        impacts[0, 1] = sw
        impacts[0, 2] = sw * (state0[3] - state0[1])
        impacts[0, 3] = math.nan
        for j in range(4, 8):
            impacts[0, j] = 0.0
        n = 1
    acc = np.zeros(5)
    n, status, t, _ = newmark_advance(p, None, st, 0.0, h, nsteps, impacts, n, max_impacts, acc, False,
                                      t_eval, 0, dense, ext, n_ext)
    delta = 0.0
    if st[4] > 0.5:
        impacts[n - 1, 4] = t - impacts[n - 1, 0]
        delta = st[5] * (st[2] - st[0]) - hg
    for i in range(4):
        final[i] = st[i]
    final[4] = acc[1]
    final[5] = acc[2]
    final[6] = delta
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
