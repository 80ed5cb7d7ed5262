"""Compiled kernels of the impact-damper solvers (numba).

Why numba: the paper's Newmark scheme at 1e-7 s takes 2e8 steps over 20 s of motion, and the
event-driven solver does a few thousand small operations per impact (root finding, Runge-Kutta
stages, error control). A Python-level loop would take minutes for the first and tens of
milliseconds per impact for the second; compiled, they take seconds and microseconds. The kernels
are plain functions of float arrays, cached on disk (``cache=True``), and hold no global state
besides the constant Dormand-Prince coefficients.

Modules, shared by free decay and forced operation: ``_flight`` (closed-form flight and exact
contact detection), ``_contact`` (one contact by DOP853, whose tableau is vendored in
``_dop853``), ``_newmark`` (fixed-step schemes), ``_status`` (status codes, column layouts and
messages); this one holds the free-decay drivers (event-driven and impact map), ``_forced_driver``
the forced one.

Parameter vector ``p`` (floats): ``[M, K, C, m, half_gap, k_hertz, c1, clip]``.
Impact rows (``IMPACT_COLUMNS``): start time, wall, approach speed, separation speed, duration,
peak force, impulse, energy lost.
Dense rows: x, v, y, w, dissipated by C, dissipated in contacts.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import helper, kernel
from ._contact import N_STAGE_ROWS, N_WORK_ROWS, NY, contact, free_contact, instant_impact
from ._flight import _osc, flight_coeffs, free_extrema, record_extremum, scan_unforced
from ._newmark import central_difference, compile_newmark, newmark
from ._records import ContactStart, as_params, without_main
from ._status import (
    DENSE_COLUMNS,
    IMPACT_COLUMNS,
    STATUS_DIVERGED,
    STATUS_MAX_IMPACTS,
    STATUS_OK,
    STATUS_STEP_UNDERFLOW,
)

__all__ = [
    "IMPACT_COLUMNS",
    "DENSE_COLUMNS",
    "STATUS_OK",
    "STATUS_MAX_IMPACTS",
    "STATUS_STEP_UNDERFLOW",
    "STATUS_DIVERGED",
    "restitution_table",
    "event_solver",
    "newmark",
    "compile_newmark",
    "central_difference",
]


@kernel
def restitution_table(p, lnu, rtol, table):
    """Fill ``table`` (n, 3) with restitution, ln(duration/s), ln(peak force/N) at speeds exp(lnu).

    The compliant contact of the two masses alone (no main spring or dashpot), as used by the
    impact map; ``lnu`` must be uniformly spaced. Returns the worst status.
    """
    pfree = without_main(as_params(p))
    work = np.zeros((N_WORK_ROWS, NY))
    kst = np.zeros((N_STAGE_ROWS, NY))
    status = STATUS_OK
    for i in range(lnu.shape[0]):
        st, e, dur, peak = free_contact(pfree, math.exp(lnu[i]), rtol, work, kst)
        table[i, 0] = e
        table[i, 1] = math.log(dur)
        table[i, 2] = math.log(peak)
        status = max(status, st)
    return status


@helper
def _table_lookup(lnu, table, x, col):
    """Cubic (Catmull-Rom) interpolation of ``table[:, col]`` on the uniform grid ``lnu``."""
    n = lnu.shape[0]
    d = lnu[1] - lnu[0]
    s = (x - lnu[0]) / d
    i = min(max(int(math.floor(s)), 1), n - 3)
    t = s - i
    p0, p1, p2, p3 = table[i - 1, col], table[i, col], table[i + 1, col], table[i + 2, col]
    return p1 + 0.5 * t * (p2 - p0 + t * (2 * p0 - 5 * p1 + 4 * p2 - p3 + t * (3 * (p1 - p2) + p3 - p0)))


@kernel
def event_solver(p, state0, t_end, rtol, t_eval, max_impacts, impacts, dense, final, lnu, table, ext, n_ext):
    """Event-driven (``lnu`` and ``table`` None) or impact-map (both arrays) integration from t = 0.

    The impact map takes the restitution, duration and peak force at each approach speed from
    ``table`` (see :func:`restitution_table`) by cubic interpolation in ln(speed) inside the
    table's inner range, and integrates the compliant contact directly outside it.

    Fills ``impacts`` (rows as ``IMPACT_COLUMNS``), ``dense`` (rows as ``DENSE_COLUMNS`` at
    ``t_eval``) and ``final`` (x, v, y, w, dissipated by C, dissipated in contacts, delta at the
    end). Records every extremum of the main-mass displacement (a zero of its velocity, or for
    the impact map a jump of the velocity through zero) in ``ext`` (rows: time s, x m, +1 for a
    maximum or -1 for a minimum; ``n_ext[0]`` counts them): in free flight from the closed form
    (:func:`~acoustiviz.dynamics._flight.free_extrema`), inside contacts by root finding on the
    contact integration. Returns ``(n_impacts, status, t_reached)``.
    """
    prm = as_params(p)
    M, K, C, hg = prm.M, prm.K, prm.C, prm.half_gap
    a = C / (2.0 * M)
    wd = math.sqrt(K / M - a * a)
    work = np.zeros((N_WORK_ROWS, NY))
    kst = np.zeros((N_STAGE_ROWS, NY))
    pfree = without_main(prm)
    x0, v0, y0, w0 = state0[0], state0[1], state0[2], state0[3]
    t0 = 0.0
    ec = 0.0
    en = 0.0
    ie = 0
    n = 0
    status = STATUS_OK
    dfinal = 0.0
    while True:
        c = flight_coeffs(t0, x0, v0, y0, w0, a, wd, None, hg)
        found, tau, sw = scan_unforced(c, t_end - t0)
        tstop = t0 + tau if found else t_end
        free_extrema(c, tau, ext, n_ext)
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
        if table is not None:  # the impact map; numba compiles this branch only for an array table
            lu = math.log(u0) if u0 > 0.0 else -math.inf
            if lnu.shape[0] >= 4 and lnu[1] <= lu <= lnu[lnu.shape[0] - 2]:
                st = STATUS_OK
                e = _table_lookup(lnu, table, lu, np.int64(0))
                dur = math.exp(_table_lookup(lnu, table, lu, np.int64(1)))
                peak = math.exp(_table_lookup(lnu, table, lu, np.int64(2)))
            else:
                st, e, dur, peak = free_contact(pfree, u0, rtol, work, kst)
            x0 = xx
            v0, w0, lost = instant_impact(prm, sw, u0, e, vv, w0, dur, peak, impacts[n])
            if (vv > 0.0) != (v0 > 0.0):  # the impulse turns the main mass: a kink extremum
                record_extremum(ext, n_ext, tc, xx, 1.0 if vv > 0.0 else -1.0)
            y0 = x0 + sw * hg
            en += lost
            n += 1
            t0 = tc
            if st != STATUS_OK:
                status = st
                break
            continue
        r = contact(prm, None, ContactStart(tc, sw, xx, vv, math.sqrt(d0), u0), t_end, rtol, t_eval, ie, dense, ec, en,
                    work, kst, ext, n_ext)
        yc, dur, ie = r.y, r.duration, r.ie
        ec += yc[7]
        en += yc[6]
        impacts[n, 3] = -yc[4]
        impacts[n, 4] = dur
        impacts[n, 5] = r.peak
        impacts[n, 6] = yc[5]
        impacts[n, 7] = yc[6]
        n += 1
        x0, v0 = yc[1], yc[2]
        dlt = yc[3] * abs(yc[3])
        y0 = x0 + sw * (hg + dlt)
        w0 = v0 + sw * yc[4]
        t0 = tc + dur
        if r.status != STATUS_OK:
            status = r.status
            t_end = t0
            break
        if not r.ended:
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
