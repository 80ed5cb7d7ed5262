"""Compiled solver of the multi-ball impact damper (numba): balls in columns inside cavities of a main mass.

Bodies: 0 is the main mass (spring ``K``, dashpot ``C``), 1..B the balls. A ball's coordinate ``s``
is its centre less its offset in the column (:mod:`acoustiviz.dynamics.balls`), so that in every
cavity the walls stand at ``x ∓ d/2`` and neighbouring balls touch when their ``s`` coincide. A
contact pair ``p`` joins its lower body ``pa[p]`` and its upper body ``pb[p]`` with the penetration
``δ = q[pa] - q[pb] - hgp[p]`` (``hgp`` = d/2 for a wall pair, 0 for two balls) and, when ``δ > 0``,
the force ``F = K_p δ^{3/2} + c_p dδ/dt`` (clipped at zero if asked), pushing ``pa`` down and ``pb``
up: the law of the single-ball solver (paper eq 15).

The run alternates two phases.

Flight (no pair in contact): the main mass is a free damped oscillator and the balls move
uniformly, all in closed form. The next contact of two balls is a linear root; that of a ball with
a wall is found by the single-ball solver's exact bracketing (:func:`~._flight.scan_unforced`), so no
grazing contact is missed. The run jumps to the earliest.

Contact (some pair in contact): every body is integrated together by Dormand-Prince 8(5,3) in
physical time with error control on the positions and velocities. After each step the sign of
every pair's penetration is compared with its contact flag; the earliest change is located by the
Illinois method on full steps from the step start (as accurate as the integration) and the step
is cut there, on the far side of the change. Each contact's impulse and dissipated work
(``∫ (F - K_p δ^{3/2}) dδ/dt dt``) are integrated with the motion. Positions and velocities at
output times inside a step, and the peak force, come from the quintic Hermite interpolant of the
step (positions, velocities, accelerations at both ends; error of order h^6).

Lone contact (a flight ends with exactly one pair touching): a two-body problem, integrated by the
single-ball solver's contact kernel in its sqrt(δ) time (:mod:`._balls_lone`), with forcing too, so
one ball in one cavity reproduces the single-ball solver (free) and the single-ball forced driver bit
for bit. Should another pair have touched meanwhile, or the contact outlast the batch's stop time,
the contact is taken again from its onset by the general path above.

Impact rows (``IMPACT_ROW_COLUMNS``): start s, end s, cavity, pair (0: wall- and ball 1, j: ball j
and ball j+1, N: ball N and wall+), approach speed m/s, separation speed m/s, peak force N,
impulse N s, dissipated work J.
State ``y``: positions (B+1), velocities (B+1), impulse of each pair, work of each pair, energy
dissipated by C and, with forcing, the work of the external force.

Forcing ``fc``: None (free vibration; numba compiles that case without the forcing terms, as
:mod:`._flight` does) or the single-ball kernels' vector ``[ω rad/s, P N, Q N, A_c m, A_s m]``: the
main mass carries ``F(t) = P cos ωt + Q sin ωt``. Its flights then use the particular solution and
:func:`~._flight.scan_forced`, the contact right-hand side adds ``F(t)``, and ``∫ F dx`` is integrated
with the motion (by quadrature in the flights) so that the energy balance closes.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import helper, kernel
from ..constants import HERTZ_DURATION_CONSTANT as _HERTZ_T
from . import _dop853 as _dop
from ._balls_lone import lone_buffers, lone_contact
from ._contact import forcing_at, phase_cos_sin
from ._dop853 import N_STAGES as _NS
from ._dop853 import C as _CN
from ._flight import _osc, flight_coeffs, flight_energy, flight_minmax, flight_state, scan_forced, scan_unforced

__all__ = ["IMPACT_ROW_COLUMNS", "STATUS_REACHED", "STATUS_MAX_IMPACTS", "STATUS_STEP_UNDERFLOW", "run_balls"]

#: Columns of an impact row.
IMPACT_ROW_COLUMNS = ("start", "end", "cavity", "pair", "approach", "separation", "peak", "impulse", "work")
#: The batch reached its stop time.
STATUS_REACHED = 0
#: The impact table is full.
STATUS_MAX_IMPACTS = 1
#: The step size vanished (a contact the tolerance cannot follow).
STATUS_STEP_UNDERFLOW = 2
_EPS = 2.220446049250313e-16
#: Cuts of one step at most: changes of several pairs at one instant (to rounding) could otherwise cut in turn
#: forever; every pair whose flag then disagrees with its penetration changes at the step's end.
_MAX_CUTS = 4


@helper
def _rhs(y, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, out, row, fc, fab, dt):
    """Derivatives of the state ``y`` (module docstring) ``dt`` s after a time ``t`` into ``out[row]``.

    ``fab = (ω, A, B)``, the forcing at ``t`` (:func:`~._contact.forcing_at`): ``F(t + dt) = A cos ωdt + B sin ωdt``.
    """
    npair = pa.shape[0]
    for k in range(nb):
        out[row, k] = y[nb + k]
        out[row, nb + k] = 0.0
    out[row, nb] = -K * y[0] - C * y[nb]
    if fc is not None:
        c, s = phase_cos_sin(fab[0] * dt)
        force = fab[1] * c + fab[2] * s
        out[row, nb] += force
        out[row, 2 * nb + 2 * npair + 1] = force * y[nb]
    for p in range(npair):
        i, j = pa[p], pb[p]
        d = y[i] - y[j] - hgp[p]
        f = 0.0
        fd = 0.0
        if d > 0.0:
            r = y[nb + i] - y[nb + j]
            fe = kh[p] * d * math.sqrt(d)
            f = fe + cc[p] * r
            if clip and f < 0.0:
                f = 0.0
            fd = (f - fe) * r
            out[row, nb + i] -= f
            out[row, nb + j] += f
        out[row, 2 * nb + p] = f
        out[row, 2 * nb + npair + p] = fd
    for k in range(nb):
        out[row, nb + k] /= mass[k]
    out[row, 2 * nb + 2 * npair] = C * y[nb] * y[nb]


@helper
def _step(y, h, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, fc, t):
    """One Dormand-Prince 8 step of ``h`` s from ``y`` at ``t`` s (``kst[0]`` its derivative).

    Fills ``ynew`` and ``kst``. The stages' intermediate states ``ytmp`` hold only the positions and
    velocities, the ``2 nb`` components :func:`_rhs` reads (the others are quadratures). The forcing
    at ``t`` is evaluated once, the stages' by angle addition (:func:`~._contact.forcing_at`).
    """
    nread = 2 * nb
    fab = forcing_at(fc, t)
    for st in range(1, _NS):
        _dop.stage_state(st, y, h, kst, ytmp, nread)
        _rhs(ytmp, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, np.int64(st), fc, fab, _CN[st] * h)
    _dop.solution(y, h, kst, ynew, y.shape[0])
    _rhs(ynew, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, np.int64(_NS), fc, fab, h)


@helper
def _error(y, ynew, h, kst, rtol, atol):
    """Hairer's DOP853 error norm over the positions and velocities (``atol`` rows), 1 = at tolerance.

    Infinite (the step rejected) when a scale is not finite, as :func:`~._dop853.error_norm`.
    """
    n = atol.shape[0]
    e5 = 0.0
    e3 = 0.0
    for i in range(n):
        sc = atol[i] + rtol * max(abs(y[i]), abs(ynew[i]))
        if not sc < math.inf:
            return math.inf
        a5, a3 = _dop.estimates(kst, i)
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@helper
def _next_step(err, h, rejected):
    """The next step after one of ``h`` s with error norm ``err`` (the single-ball contact's rule)."""
    if not (err <= 1.0):
        if not math.isfinite(err):
            err = 1e10
        return h * max(0.2, 0.9 * err ** (-1.0 / 8.0))
    grow = 1.0 if rejected else 10.0
    if err == 0.0:
        return h * grow
    return h * min(grow, 0.8 * err ** (-1.0 / 8.0))


@helper
def _hermite(y0, v0, a0, y1, v1, a1, h, th):
    """Quintic Hermite interpolant at ``th`` in [0, 1] of a step of ``h`` s: value and rate."""
    t2 = th * th
    t3 = t2 * th
    t4 = t3 * th
    t5 = t4 * th
    p = (y0 * (1 - 10 * t3 + 15 * t4 - 6 * t5) + h * v0 * (th - 6 * t3 + 8 * t4 - 3 * t5)
         + h * h * a0 * (0.5 * t2 - 1.5 * t3 + 1.5 * t4 - 0.5 * t5) + y1 * (10 * t3 - 15 * t4 + 6 * t5)
         + h * v1 * (-4 * t3 + 7 * t4 - 3 * t5) + h * h * a1 * (0.5 * t3 - t4 + 0.5 * t5))
    dp = (y0 * (-30 * t2 + 60 * t3 - 30 * t4) + h * v0 * (1 - 18 * t2 + 32 * t3 - 15 * t4)
          + h * h * a0 * (th - 4.5 * t2 + 6 * t3 - 2.5 * t4) + y1 * (30 * t2 - 60 * t3 + 30 * t4)
          + h * v1 * (-12 * t2 + 28 * t3 - 15 * t4) + h * h * a1 * (1.5 * t2 - 4 * t3 + 2.5 * t4))
    return p, dp / h


@helper
def _pair_at(y, f, nb, i, j, hg):
    """Penetration (m), its rate (m/s) and its second derivative (m/s²) of the bodies ``i < j`` at ``y``."""
    return y[i] - y[j] - hg, y[nb + i] - y[nb + j], f[nb + i] - f[nb + j]


@helper
def _force_of(d, r, k, c, clip):
    if d <= 0.0:
        return 0.0
    f = k * d * math.sqrt(d) + c * r
    return 0.0 if clip and f < 0.0 else f


@helper
def _peak_in_step(y, ynew, kst, h, nb, i, j, hg, k, c, clip):
    """Largest force in N of a pair inside a step, golden-section search on the Hermite interpolant."""
    d0, r0, a0 = _pair_at(y, kst[0], nb, i, j, hg)
    d1, r1, a1 = _pair_at(ynew, kst[_NS], nb, i, j, hg)
    lo, hi = 0.0, 1.0
    g = 0.6180339887498949
    best = 0.0
    for _ in range(40):
        m1 = hi - g * (hi - lo)
        m2 = lo + g * (hi - lo)
        p1, q1 = _hermite(d0, r0, a0, d1, r1, a1, h, m1)
        p2, q2 = _hermite(d0, r0, a0, d1, r1, a1, h, m2)
        f1 = _force_of(p1, q1, k, c, clip)
        f2 = _force_of(p2, q2, k, c, clip)
        best = max(best, f1, f2)
        if f1 < f2:
            lo = m1
        else:
            hi = m2
    return best


@helper
def _dense(y, ynew, kst, h, t0, nb, t_eval, ie, dense):
    """Positions and velocities at the output times in ``(t0, t0 + h]`` from the step's Hermite interpolant."""
    while ie < t_eval.shape[0] and t_eval[ie] <= t0 + h:
        th = (t_eval[ie] - t0) / h
        for k in range(nb):
            p, dp = _hermite(y[k], y[nb + k], kst[0, nb + k], ynew[k], ynew[nb + k], kst[_NS, nb + k], h, th)
            dense[ie, k] = p
            dense[ie, nb + k] = dp
        ie += 1
    return ie


@helper
def _flips(ynew, nb, pa, pb, hgp, active, skip):
    """The first pair (index) whose contact flag disagrees with the sign of its penetration, else -1."""
    for p in range(pa.shape[0]):
        if p != skip and (ynew[pa[p]] - ynew[pb[p]] - hgp[p] > 0.0) != active[p]:
            return p
    return -1


@helper
def _locate(p, t, y, h, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, active, fc):
    """Step length in (0, h] just past the change of pair ``p`` (Illinois on full steps); fills ``ynew``.

    Located to a few units of the rounding of the time ``t + h`` s (finer cannot be represented).
    """
    flag = active[p]
    glo = y[pa[p]] - y[pb[p]] - hgp[p]
    _step(y, h, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, fc, t)
    ghi = ynew[pa[p]] - ynew[pb[p]] - hgp[p]
    lo, hi = 0.0, h
    side = 0
    for _ in range(200):
        if hi - lo <= 4.0 * _EPS * (t + hi):
            break
        hm = (lo * ghi - hi * glo) / (ghi - glo) if ghi != glo else 0.5 * (lo + hi)
        if not (lo < hm < hi):
            hm = 0.5 * (lo + hi)
        _step(y, hm, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, fc, t)
        gm = ynew[pa[p]] - ynew[pb[p]] - hgp[p]
        if (gm > 0.0) == flag:
            lo, glo = hm, gm
            ghi *= 0.5 if side == -1 else 1.0
            side = -1
        else:
            hi, ghi = hm, gm
            glo *= 0.5 if side == 1 else 1.0
            side = 1
    _step(y, hi, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, fc, t)
    return hi


@helper
def _toggle(p, t, y, nb, npair, pa, pb, cav, loc, active, open_row, rows, n_rows, peaks):
    """Open (at first touch) or close (as the bodies part) the impact row of pair ``p`` at ``t`` s."""
    r = y[nb + pa[p]] - y[nb + pb[p]]
    if not active[p]:
        active[p] = True
        n = n_rows[0]
        open_row[p] = n
        n_rows[0] = n + 1
        rows[n, 0] = t
        rows[n, 1] = math.nan
        rows[n, 2] = cav[p]
        rows[n, 3] = loc[p]
        rows[n, 4] = r
        rows[n, 5] = math.nan
        y[2 * nb + p] = 0.0
        y[2 * nb + npair + p] = 0.0
        peaks[p] = 0.0
    else:
        active[p] = False
        close_row(p, t, y, nb, npair, r, open_row, rows, peaks)


@helper
def close_row(p, t, y, nb, npair, r, open_row, rows, peaks):
    """Fill the end, separation speed, peak, impulse and work of pair ``p``'s open row."""
    n = open_row[p]
    rows[n, 1] = t
    rows[n, 5] = -r
    rows[n, 6] = peaks[p]
    rows[n, 7] = y[2 * nb + p]
    rows[n, 8] = y[2 * nb + npair + p]
    open_row[p] = -1


@helper
def _first_flight_event(t0, y, nb, pa, pb, hgp, a, wd, horizon, fc):
    """Earliest contact of a flight from ``t0``: (tau s, pair, or -1 for a re-scan only, or -2 for none).

    The pairs of two balls first (linear roots); the walls are then scanned up to the earliest of
    those, each with the same horizon (one ball alone scans both walls alike). A wall scan that meets
    the other wall first (impossible past a neighbour, so only as a rounding) asks for a re-scan.
    """
    best, which = horizon, -2
    for p in range(pa.shape[0]):
        i, j = pa[p], pb[p]
        if i != 0 and j != 0:
            r = y[nb + i] - y[nb + j]
            if r > 0.0:
                tau = max(-(y[i] - y[j]) / r, 0.0)
                if tau < best:
                    best, which = tau, p
    lin = best
    noop = math.inf
    for p in range(pa.shape[0]):
        i, j = pa[p], pb[p]
        if i == 0 or j == 0:  # a wall: the single-ball solver's exact bracketing
            b = j if i == 0 else i
            want = -1.0 if i == 0 else 1.0
            c = flight_coeffs(t0, y[0], y[nb], y[b], y[nb + b], a, wd, fc, hgp[p])
            if fc is None:
                found, tau, sw = scan_unforced(c, lin)
            else:
                found, tau, sw = scan_forced(c, lin)
            if found and sw == want and tau < best:
                best, which = tau, p
            elif found and sw != want and tau > 0.0:
                noop = min(noop, tau)
    if noop < best:
        return noop, -1
    return best, which


@helper
def _fly(t0, tau, y, nb, a, wd, M, K):
    """Advance every body ``tau`` s in free flight; the energy dissipated by C is added to ``y[-1]``."""
    e0 = 0.5 * M * y[nb] ** 2 + 0.5 * K * y[0] ** 2
    x, v = _osc(y[0], y[nb], tau, a, wd)
    y[0] = x
    y[nb] = v
    for k in range(1, nb):
        y[k] += y[nb + k] * tau
    y[y.shape[0] - 1] += e0 - (0.5 * M * v * v + 0.5 * K * x * x)


@helper
def _fly_forced(t0, tau, y, nb, npair, a, wd, C, fc, ext):
    """Advance every body ``tau`` s in a forced flight; adds C's dissipation and F's work to ``y``.

    With ``ext`` (an array of 5), ``ext[3]``/``ext[4]`` gather the largest/smallest main-mass
    displacement (m) of the flight (:func:`~._flight.flight_minmax`).
    """
    c = flight_coeffs(t0, y[0], y[nb], 0.0, 0.0, a, wd, fc, 0.0)
    if ext is not None:
        flight_minmax(c, tau, ext)
    if tau > 0.0:
        work, diss = flight_energy(c, tau, fc, C)
        y[2 * nb + 2 * npair] += diss
        y[2 * nb + 2 * npair + 1] += work
    x, v, _ = flight_state(tau, c)
    y[0] = x
    y[nb] = v
    for k in range(1, nb):
        y[k] += y[nb + k] * tau


@helper
def _flight(t0, tau, y, nb, npair, a, wd, M, K, C, fc, ext, t_eval, ie, dense):
    """A flight of ``tau`` s from ``t0`` s: the output times inside it, then every body moved to its end."""
    ie = _flight_dense(t0, tau, y, nb, a, wd, fc, t_eval, ie, dense)
    if fc is None:
        _fly(t0, tau, y, nb, a, wd, M, K)
    else:
        _fly_forced(t0, tau, y, nb, npair, a, wd, C, fc, ext)
    return ie


@helper
def _flight_dense(t0, tau, y, nb, a, wd, fc, t_eval, ie, dense):
    """Fill the output times of a flight of ``tau`` s from ``t0`` s; returns the next one due.

    The main mass in closed form (with the particular solution of the forcing ``fc``; None: free, the
    damped oscillation alone), the balls at constant velocity.
    """
    c = flight_coeffs(t0, y[0], y[nb], 0.0, 0.0, a, wd, fc, 0.0)
    while ie < t_eval.shape[0] and t_eval[ie] <= t0 + tau:
        dt = t_eval[ie] - t0
        if fc is None:
            x, v = _osc(y[0], y[nb], dt, a, wd)
        else:
            x, v, _ = flight_state(dt, c)
        dense[ie, 0] = x
        dense[ie, nb] = v
        for k in range(1, nb):
            dense[ie, k] = y[k] + y[nb + k] * dt
            dense[ie, nb + k] = y[nb + k]
        ie += 1
    return ie


@helper
def _first_step(p, y, nb, mass, pa, pb, kh):
    """A first step in s for a contact of pair ``p`` just begun: 1e-3 of its undamped Hertz duration.

    Small because the force grows as t^1.5 from first touch; the error control lengthens it at once.
    """
    i, j = pa[p], pb[p]
    meff = mass[i] * mass[j] / (mass[i] + mass[j])
    u = max(y[nb + i] - y[nb + j], 1e-9)
    amax = (1.25 * meff * u * u / kh[p]) ** 0.4
    return 1e-3 * _HERTZ_T * amax / u


@helper
def _update_peaks(y, ynew, kst, h, nb, pa, pb, hgp, kh, cc, clip, active, peaks):
    """Raise the peak force of each contact under way with the step's end and, at a maximum, its inside."""
    for q in range(pa.shape[0]):
        if active[q]:
            i, j = pa[q], pb[q]
            d1, r1, s1 = _pair_at(ynew, kst[_NS], nb, i, j, hgp[q])
            d0, r0, s0 = _pair_at(y, kst[0], nb, i, j, hgp[q])
            f1 = _force_of(d1, r1, kh[q], cc[q], clip)
            slope0 = 1.5 * kh[q] * math.sqrt(max(d0, 0.0)) * r0 + cc[q] * s0
            slope1 = 1.5 * kh[q] * math.sqrt(max(d1, 0.0)) * r1 + cc[q] * s1
            if slope0 > 0.0 and slope1 <= 0.0:
                f1 = max(f1, _peak_in_step(y, ynew, kst, h, nb, i, j, hgp[q], kh[q], cc[q], clip))
            peaks[q] = max(peaks[q], f1)


@helper
def _contact_step(t, h, y, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, rtol, atol, active, peaks,
                  t_eval, ie, dense, fc):
    """One accepted or rejected step while some pair touches: ``(accepted, t, h, changed pair or -1, ie)``.

    ``kst[0]`` holds the derivative at ``y`` on entry, and at the new ``y`` on return.
    An accepted step is cut at the earliest change of a contact flag (located on full steps); the
    state moves to its end.
    """
    _step(y, h, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, fc, t)
    err = _error(y, ynew, h, kst, rtol, atol)
    if not (err <= 1.0):
        return False, t, _next_step(err, h, False), -1, ie
    hstep = h
    p = _flips(ynew, nb, pa, pb, hgp, active, np.int64(-1))
    changed = -1
    cuts = 0
    while p >= 0 and cuts < _MAX_CUTS:  # cut the step at the earliest change of a contact
        hstep = _locate(p, t, y, hstep, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, ytmp, ynew, active, fc)
        changed = p
        cuts += 1
        p = _flips(ynew, nb, pa, pb, hgp, active, changed)
    _update_peaks(y, ynew, kst, hstep, nb, pa, pb, hgp, kh, cc, clip, active, peaks)
    ie = _dense(y, ynew, kst, hstep, t, nb, t_eval, ie, dense)
    for i in range(y.shape[0]):  # the step's end, and its derivative (the last stage), start the next
        y[i] = ynew[i]
        kst[0, i] = kst[_NS, i]
    return True, t + hstep, (h if changed >= 0 else _next_step(err, h, False)), changed, ie


@helper
def _rows_left(changed, y, pa, pb, hgp, active, n_rows, rows):
    """True when the impact table has a row for every contact opening now (``changed`` and any other touching)."""
    opening = 0
    for q in range(pa.shape[0]):
        if not active[q] and (q == changed or y[pa[q]] - y[pb[q]] - hgp[q] > 0.0):
            opening += 1
    return n_rows[0] + opening <= rows.shape[0]


@helper
def _toggle_changed(changed, t, h, y, nb, mass, pa, pb, hgp, kh, cav, loc, active, open_row, rows, n_rows, peaks):
    """Toggle the pair located, and any other whose change fell on the same instant (to the time's rounding).

    Returns the next step in s: no longer than the first step of a contact begun now.
    """
    npair = pa.shape[0]
    before = np.sum(active)
    for q in range(npair):
        if q == changed or (y[pa[q]] - y[pb[q]] - hgp[q] > 0.0) != active[q]:
            _toggle(q, t, y, nb, npair, pa, pb, cav, loc, active, open_row, rows, n_rows, peaks)
            if active[q]:
                h = min(h, _first_step(q, y, nb, mass, pa, pb, kh)) if before > 0 else \
                    _first_step(q, y, nb, mass, pa, pb, kh)
                before = 1
    return h


@kernel
def run_balls(mass, pa, pb, hgp, kh, cc, cav, loc, K, C, clip, y, active, open_row, peaks, clock, t_stop, rtol,
              atol, t_eval, ie_arr, dense, rows, n_rows, max_steps, fc, ext):
    """Advance the run from ``clock[0]`` s to ``t_stop`` s (module docstring); resumable batch by batch.

    ``y``, ``active``, ``open_row``, ``peaks`` (largest force of each open contact, N), ``clock``
    (time s, next step s), ``ie_arr`` (next output time due) and ``n_rows`` carry the run from one
    batch to the next. A batch also ends after ``max_steps`` steps (``clock[0] < t_stop``), so a
    caller can report progress and be interrupted. Returns a status (``STATUS_*``).
    ``fc``: the forcing (module docstring; None: free vibration). ``ext`` (None, or an array of 5
    with the forcing): ``ext[3]``/``ext[4]`` gather the largest/smallest main-mass displacement in m.
    """
    nb = mass.shape[0]
    npair = pa.shape[0]
    a = C / (2.0 * mass[0])
    wd = math.sqrt(K / mass[0] - a * a)
    n = y.shape[0]
    kst = np.zeros((_NS + 1, n))
    ytmp = np.zeros(n)
    ynew = np.zeros(n)
    lone = lone_buffers(n, t_eval.shape[0], fc)
    t, h, ie = clock[0], clock[1], ie_arr[0]
    status = STATUS_REACHED
    steps = 0
    _rhs(y, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, np.int64(0), fc, forcing_at(fc, t), 0.0)
    while t < t_stop and steps <= max_steps:
        steps += 1
        flight = not np.any(active)  # a contact found by this flight may be integrated alone (below)
        changed = -1
        if not np.any(active):  # flight in closed form up to the next contact
            tau, changed = _first_flight_event(t, y, nb, pa, pb, hgp, a, wd, t_stop - t, fc)
            ie = _flight(t, tau, y, nb, npair, a, wd, mass[0], K, C, fc, ext, t_eval, ie, dense)
            t = t_stop if changed == -2 else t + tau
        else:
            accepted, t, h, changed, ie = _contact_step(t, min(h, t_stop - t), y, nb, mass, pa, pb, hgp, kh, cc, K,
                                                        C, clip, kst, ytmp, ynew, rtol, atol, active, peaks, t_eval,
                                                        ie, dense, fc)
            if not accepted and h < 1e-6 * _EPS * max(t, 1e-3):
                status = STATUS_STEP_UNDERFLOW
                break
        if changed >= 0:
            if not _rows_left(changed, y, pa, pb, hgp, active, n_rows, rows):
                status = STATUS_MAX_IMPACTS
                break
            h = _toggle_changed(changed, t, h, y, nb, mass, pa, pb, hgp, kh, cav, loc, active, open_row, rows, n_rows,
                                peaks)
            _rhs(y, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, kst, np.int64(0), fc, forcing_at(fc, t), 0.0)
            if flight and np.sum(active) == 1:  # one pair alone: the single-ball contact
                _, t, ie = lone_contact(np.argmax(active), t, y, nb, mass, pa, pb, hgp, kh, cc, loc, K, C, clip, a,
                                        wd, fc, t_stop, rtol, t_eval, ie, dense, open_row, rows, active, peaks, ext,
                                        lone)
        if ext is not None and fc is not None:
            ext[3] = max(ext[3], y[0])
            ext[4] = min(ext[4], y[0])
    clock[0] = t
    clock[1] = h
    ie_arr[0] = ie
    return status
