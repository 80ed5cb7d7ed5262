"""Lone contacts of the multi-ball solver, integrated by the single-ball contact kernel (numba).

When a flight of :mod:`._balls` ends with exactly one pair touching, that contact is a two-body
problem and is integrated as the single-ball solver integrates its contacts
(:func:`~._contact.contact`: Dormand-Prince 8(5,3) in the time σ with dt = sqrt(δ) dσ, in which
the Hertz force is a polynomial and the steps stay long to both ends of the contact):

- a ball on a wall is exactly the single-ball contact problem: the main mass on its spring and
  dashpot, and that ball; the other balls fly freely (``s += w t``);
- two balls are the same problem with the upper ball of the pair in the place of the main mass,
  without spring or dashpot (``K = C = 0``) and without forcing; the main mass flies in closed form
  (with forcing, its free part plus the particular solution, :mod:`._flight`). The pair's
  coordinates are shifted by half the cavity's free travel, so that the contact's absolute position
  tolerance (``rtol`` times the half-gap) is on the cavity's scale, as for a wall.

With forcing (``fc``, the vector of :mod:`._balls`) a wall contact is the single-ball forced
contact: the forcing and the contact's start time go to the kernel, which integrates the work of F
with the motion, as the single-ball forced driver (:mod:`._forced_driver`) calls it. The work of F
over the contact (of the kernel, or of the main mass's forced flight during a contact of two
balls) is added to the state's last entry, the energy dissipated by C to the entry before it.

The same compiled code as the single-ball solvers' runs, so one ball in one cavity gives their
impacts bit for bit (free and forced alike). The contact's row (separation speed, peak force,
impulse, energy lost) is filled from the contact's result as the single-ball solvers fill their own.

Afterwards the other pairs are checked: every body outside the contact flies in closed form, and
the speeds of the two in contact are bounded over the contact (their end values widened by a
generous allowance for the main spring, its dashpot, the forcing's amplitude and the contact
damping). When a pair might have touched
meanwhile, or the contact did not end before the stop time, the state is put back at the onset and
the caller integrates the contact in its general physical-time path instead.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import helper
from ._contact import N_STAGE_ROWS, N_WORK_ROWS, NY, contact
from ._flight import _osc, flight_coeffs, flight_energy, flight_minmax, flight_state
from ._records import ContactStart, Params
from ._status import STATUS_OK

__all__ = ["lone_buffers", "lone_contact"]


@helper
def lone_buffers(n_state, n_eval, fc):
    """Work arrays of :func:`lone_contact`: the contact's ``work`` and ``kst``, dense rows, the onset state.

    The contact's state has ``NY`` components, one more with forcing (``fc`` not None: the work of F).
    """
    ny = NY if fc is None else NY + 1
    return (np.zeros((N_WORK_ROWS, ny)), np.zeros((N_STAGE_ROWS, ny)), np.zeros((n_eval, 6)), np.zeros(n_state),
            np.zeros(5))


@helper
def _contact_forcing(fc, fz, mb):
    """The forcing vector the contact kernel gets: ``fc`` on a wall (``mb`` 0: the main mass in contact).

    Between two balls none acts, but the kernel runs with the forcing's state (``fz``, zero forcing:
    F = 0 and its work stays 0), so that one compiled contact serves both kinds. (Its error norm then
    averages over one more component, always zero: the steps grow by (9/8)^(1/16), under 1 %.)
    """
    if fc is None:
        return fc
    if mb == 0:
        return fc
    return fz


@helper
def _setup(p, y, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, loc):
    """The two-body problem of pair ``p``: ``(Params, main body, ball body, wall side ±1, shift m)``.

    The "main" body is the main mass for a wall pair and the upper ball of a pair of balls; the
    "ball" is the other. ``shift`` (m) is added to the ball's coordinate in the contact problem.
    """
    i, j = pa[p], pb[p]
    if i == 0:  # wall-: delta = x - s - hg
        return Params(mass[0], K, C, mass[j], hgp[p], kh[p], cc[p], clip), 0, j, -1.0, 0.0
    if j == 0:  # wall+: delta = s - x - hg
        return Params(mass[0], K, C, mass[i], hgp[p], kh[p], cc[p], clip), 0, i, 1.0, 0.0
    hw = hgp[p - np.int64(loc[p])]  # half the free travel of the cavity (its wall- pair)
    return Params(mass[j], 0.0, 0.0, mass[i], hw, kh[p], cc[p], clip), j, i, 1.0, hw


@helper
def _force_bound(fc):
    """Largest value in N of the forcing ``F(t) = P cos ωt + Q sin ωt`` (0 without forcing)."""
    if fc is None:
        return 0.0
    return math.sqrt(fc[1] * fc[1] + fc[2] * fc[2])


@helper
def _speed_bounds(k, y0, y, nb, mb, bb, dur, K, C, fmax, mass, slack_c):
    """Lowest and highest speed in m/s body ``k`` can have had during the contact (module docstring).

    ``fmax`` (N) bounds the forcing on the main mass.
    """
    u0, u1 = y0[nb + k], y[nb + k]
    if k != mb and k != bb and k != 0:
        return u0, u0  # a free ball: constant speed
    du = abs(u1 - u0)
    slack = du
    if k == mb or k == bb:
        slack += slack_c / mass[k]  # the contact damping's pull, at most c |dδ/dt| over the contact
    if k == 0:  # the main spring, dashpot and forcing over the contact, bounded generously
        vmax = max(abs(u0), abs(u1)) + du
        xmax = max(abs(y0[0]), abs(y[0])) + dur * vmax
        slack += dur * (K * xmax + C * vmax + fmax) / mass[0]
    return min(u0, u1) - slack, max(u0, u1) + slack


@helper
def _touched_meanwhile(p, y0, y, nb, mass, pa, pb, hgp, K, C, fmax, mb, bb, dur, slack_c):
    """True when a pair other than ``p`` may have touched during the contact of ``dur`` s from ``y0``."""
    for q in range(pa.shape[0]):
        if q == p:
            continue
        i, j = pa[q], pb[q]
        _, hi_i = _speed_bounds(i, y0, y, nb, mb, bb, dur, K, C, fmax, mass, slack_c)
        lo_j, _ = _speed_bounds(j, y0, y, nb, mb, bb, dur, K, C, fmax, mass, slack_c)
        d0 = y0[i] - y0[j] - hgp[q]
        if d0 + dur * max(hi_i - lo_j, 0.0) > 0.0 or y[i] - y[j] - hgp[q] > 0.0:
            return True
    return False


@helper
def _main_flight(tc, y0, nb, a, wd, fc):
    """Flight coefficients (:mod:`._flight`) of the main mass from its state ``y0`` at ``tc`` s (forced or free)."""
    return flight_coeffs(tc, y0[0], y0[nb], 0.0, 0.0, a, wd, fc, 0.0)


@helper
def _dense_rows(ie0, ie, y0, tc, nb, mb, bb, shift, a, wd, fc, t_eval, d6, dense):
    """Multi-ball dense rows ``ie0 .. ie - 1`` from the contact's rows ``d6`` (x, v, y, w) and the free flights."""
    c = _main_flight(tc, y0, nb, a, wd, fc)
    for r in range(ie0, ie):
        td = t_eval[r] - tc
        for k in range(1, nb):
            dense[r, k] = y0[k] + y0[nb + k] * td
            dense[r, nb + k] = y0[nb + k]
        if mb != 0:
            if fc is None:
                x, v = _osc(y0[0], y0[nb], td, a, wd)
            else:
                x, v, _ = flight_state(td, c)
            dense[r, 0] = x
            dense[r, nb] = v
        dense[r, mb] = d6[r, 0]
        dense[r, nb + mb] = d6[r, 1]
        dense[r, bb] = d6[r, 2] - shift
        dense[r, nb + bb] = d6[r, 3]


@helper
def _fly_others(y, y0, tc, nb, npair, mb, bb, dur, a, wd, M, K, C, fc):
    """Advance the bodies outside the contact (begun at ``tc`` s) ``dur`` s in closed form.

    A main mass outside the contact flies as in :mod:`._balls`: the dashpot's loss (J) is added to
    ``y[2 nb + 2 npair]`` and, with forcing, the work of F (J) to ``y[-1]``.
    """
    for k in range(1, nb):
        if k != mb and k != bb:
            y[k] = y0[k] + y0[nb + k] * dur
    if mb == 0:
        return
    if fc is None:
        x, v = _osc(y0[0], y0[nb], dur, a, wd)
        y[2 * nb + 2 * npair] += 0.5 * M * y0[nb] ** 2 + 0.5 * K * y0[0] ** 2 - (0.5 * M * v * v + 0.5 * K * x * x)
    else:
        c = _main_flight(tc, y0, nb, a, wd, fc)
        if dur > 0.0:
            work, diss = flight_energy(c, dur, fc, C)
            y[2 * nb + 2 * npair] += diss
            y[y.shape[0] - 1] += work
        x, v, _ = flight_state(dur, c)
    y[0] = x
    y[nb] = v


@helper
def _close(p, t, dur, yc, peak, y, nb, npair, open_row, rows, active, peaks):
    """Close pair ``p``'s row at the parting ``t + dur`` s from the contact's end state ``yc``; clear its flag."""
    y[2 * nb + p] = yc[5]
    y[2 * nb + npair + p] = yc[6]
    n = open_row[p]
    rows[n, 1] = t + dur
    rows[n, 5] = -yc[4]
    rows[n, 6] = peak
    rows[n, 7] = yc[5]
    rows[n, 8] = yc[6]
    open_row[p] = -1
    active[p] = False
    peaks[p] = 0.0


@helper
def lone_contact(p, t, y, nb, mass, pa, pb, hgp, kh, cc, loc, K, C, clip, a, wd, fc, t_stop, rtol, t_eval, ie, dense,
                 open_row, rows, active, peaks, ext, bufs):
    """Integrate the lone contact of pair ``p``, begun at ``t`` s (module docstring): ``(done, t, ie)``.

    On success (``done``) the state ``y`` is at the parting, the pair's row is closed and its flag
    cleared; otherwise ``y`` and the output are as on entry, and the contact is the caller's.
    ``fc``: the forcing (None: free vibration); ``ext`` (None, or an array of 5 with the forcing):
    ``ext[3]``/``ext[4]`` gather the largest/smallest main-mass displacement (m) of a main mass
    flying during a contact of two balls (:func:`~._flight.flight_minmax`, as the flights do).
    """
    work, kst, d6, y0, fz = bufs
    npair = pa.shape[0]
    for k in range(y.shape[0]):
        y0[k] = y[k]
    prm, mb, bb, sw, shift = _setup(p, y, nb, mass, pa, pb, hgp, kh, cc, K, C, clip, loc)
    i, j = pa[p], pb[p]
    d0 = max(y[i] - y[j] - hgp[p], 0.0)
    u0 = y[nb + i] - y[nb + j]
    start = ContactStart(t, sw, y[mb], y[nb + mb], math.sqrt(d0), u0)
    # the main mass carries the forcing: into the contact on a wall, in its flight beside two balls
    r = contact(prm, _contact_forcing(fc, fz, mb), start, t_stop, rtol, t_eval, ie, d6, 0.0, 0.0, work, kst, None, None)
    if not r.ended or r.status != STATUS_OK:
        return False, t, ie
    yc, dur = r.y, r.duration
    dlt = yc[3] * abs(yc[3])
    y[mb] = yc[1]
    y[nb + mb] = yc[2]
    y[bb] = yc[1] + sw * (hgp[p] + dlt)
    y[nb + bb] = yc[2] + sw * yc[4]
    y[2 * nb + 2 * npair] += yc[7]
    if fc is not None and mb == 0:
        y[y.shape[0] - 1] += yc[8]
    _fly_others(y, y0, t, nb, npair, mb, bb, dur, a, wd, mass[0], K, C, fc)
    slack_c = dur * cc[p] * max(abs(u0), abs(yc[4]))
    if _touched_meanwhile(p, y0, y, nb, mass, pa, pb, hgp, K, C, _force_bound(fc), mb, bb, dur, slack_c):
        for k in range(y.shape[0]):
            y[k] = y0[k]
        return False, t, ie
    if ext is not None:
        if fc is not None and mb != 0:
            flight_minmax(_main_flight(t, y0, nb, a, wd, fc), dur, ext)
    _dense_rows(ie, r.ie, y0, t, nb, mb, bb, shift, a, wd, fc, t_eval, d6, dense)
    _close(p, t, dur, yc, r.peak, y, nb, npair, open_row, rows, active, peaks)
    return True, t + dur, r.ie
