"""A start's direct run (numba): many forcing cycles per call, stopping where the search has work to do.

The search of :mod:`._attractors` runs each start cycle by cycle on the Poincaré section and, after
each cycle, looks at its section point: is it on a known stable orbit, does it return close to
itself (a period to refine by shooting), is it a checkpoint, is a non-periodic start due for a
comparison with the known non-periodic motions. Most cycles call for none of this. :func:`run_cycles`
advances the forced driver (:func:`._forced_driver.advance`) cycle after cycle exactly as one call per
cycle does (the same times ``kT``, impact rows, accumulators and section points, so the same bits),
records what the search keeps of each cycle, and returns at the first cycle where one of those
conditions may hold; the search then decides there as before. The tests are the search's own, so
they can only stop the run early (a superset), never skip a cycle the search would act on.

The same kernel runs the plain stretches of cycles of :meth:`._forced_steady._Runner.cycles`: the
``n`` cycles of one Poincaré map ``P^n`` (:data:`MODE_PLAIN`) and the cycles of a measurement, the state of
each kept (:data:`MODE_CARRY`), in one call instead of one per cycle, with the same bits.
"""

from __future__ import annotations

import numpy as np

from .._jit import compile_for, helper, kernel
from . import _forced_driver as fd
from ._status import STATUS_OK

__all__ = ["MODE_PLAIN", "MODE_CARRY", "MODE_SEARCH", "FORCED_COMPILE_S", "run_cycles", "run_plain", "compile_once"]

#: CPU time in s of the forced driver's first compilation with its callees, by solver (the impact
#: map's compiles more: instantaneous impacts, sticking, and the compliant contact for a run resumed
#: inside one), quoted to the user when it happens; measured by ``benchmarks/bench_startup.py``
#: (figures: ``benchmarks/results/design_timings.md``).
FORCED_COMPILE_S = {"event": 7.0, "impact-map": 10.0}

# the search's arguments of the kernel when it runs plain cycles (:func:`run_plain`)
_UNUSED_SCALE = np.ones(4)
_UNUSED_POINTS = np.zeros((1, 4))
_UNUSED_ROW = np.zeros(1)
_UNUSED_COLS = np.zeros(0, dtype=np.int64)
_COMPILED = set()  # solvers whose kernel is compiled (or loaded) in this process


def compile_once(solver, args):
    """Compile :func:`run_cycles` for ``solver`` with the types of ``args`` once per process, saying so if long.

    Every call of the kernel has the same argument types for one solver.
    """
    if solver not in _COMPILED:
        compile_for(run_cycles, args, "forced-response", FORCED_COMPILE_S[solver])
        _COMPILED.add(solver)


def run_plain(solver, prm, fc, fcs, st, j0, T, restitution, rtol, impacts, n0, cap, acc, extrema, mode, count,
              states):
    """Cycles ``1..count`` of :func:`run_cycles` in mode :data:`MODE_PLAIN` or :data:`MODE_CARRY` (with ``states``).

    Returns its ``(k, status, n)``.
    """
    args = (prm, fc, fcs, st, j0, T, restitution, rtol, impacts, n0, cap, acc, bool(extrema), mode, 1, count,
            _UNUSED_SCALE, _UNUSED_POINTS if states is None else states, _UNUSED_ROW, _UNUSED_ROW, _UNUSED_ROW,
            _UNUSED_POINTS, _UNUSED_COLS, 0.0, 0.0, _UNUSED_COLS, 0.0, 0, 0)
    compile_once(solver, args)
    return run_cycles(*args)


@helper
def _returns(pts, k, max_period, d):
    """Scaled distances ``d[n]`` of section point ``k`` to point ``k - n``, n = 1..max_period (inf where k < n)."""
    for n in range(max_period + 1):  # elementwise: a slice assignment compiles a shape check and its message
        d[n] = np.inf
    for n in range(1, min(max_period, k) + 1):
        m = 0.0
        for c in range(4):
            v = abs(pts[k, c] - pts[k - n, c])
            if v > m or v != v:
                m = v
        d[n] = m


@helper
def _on_orbit(orbits, orbit_cols, pts, k, capture):
    """True when section point ``k`` lies within ``capture`` (scaled, largest component) of a row of ``orbits``."""
    for r in range(orbits.shape[0]):
        m = 0.0
        for c in range(orbit_cols[r]):
            v = abs(orbits[r, c] - pts[k, c])
            if v > m or v != v:
                m = v
        if m < capture:
            return True
    return False


@helper
def _period_due(d, prev, trigger, k, checkpoints, checkpoint_return):
    """True when a return is close twice in a row, or ``k`` is a checkpoint with a return under ``checkpoint_return``.

    ``d``, ``prev``: the scaled returns of this cycle and the one before (index = period, 0 unused).
    """
    best = np.inf
    for n in range(1, d.size):
        if d[n] < trigger and prev[n] < trigger:
            return True
        best = min(best, d[n])
    for c in checkpoints:
        if k == c and best < checkpoint_return:
            return True
    return False


@helper
def _search_stops(pts, k, orbits, orbit_cols, capture, probe, d, prev, trigger, checkpoints, checkpoint_return,
                  next_try):
    """True when the search looks at section point ``k`` (:func:`run_cycles`); else ``prev`` takes its returns."""
    if _on_orbit(orbits, orbit_cols, pts, k, capture):  # on a known stable orbit
        return True
    if probe > 0 and k >= probe and k % probe == 0:  # a comparison with the known non-periodic motions
        return True
    max_period = d.size - 1
    _returns(pts, k, max_period, d)
    if k >= next_try and _period_due(d, prev, trigger, k, checkpoints, checkpoint_return):
        return True
    for n in range(max_period + 1):
        prev[n] = d[n]
    return False


#: :func:`run_cycles` modes: plain cycles each writing its impact rows from row ``n0`` (a Poincaré map),
MODE_PLAIN = 0
#: plain cycles carrying the impact rows on and recording the state after each cycle (a measurement),
MODE_CARRY = 1
#: the search's cycles (a start's direct run).
MODE_SEARCH = 2


@kernel
def run_cycles(prm, fc, fcs, st, j0, T, restitution, rtol, impacts, n0, cap, acc, extrema, mode, k0, k1, scale,
               pts, xhi, xlo, ipc, orbits, orbit_cols, capture, trigger, checkpoints, checkpoint_return, next_try,
               probe):
    """Run cycles ``k0``..``k1`` of a start (``j0`` cycles run before ``k0``) until one may need the search.

    The one compiled entry of the forced driver for the event solver and the impact map, in three modes.
    :data:`MODE_PLAIN` runs the cycles ``k0``..``k1``, each writing its impact rows from row ``n0`` and adding
    to ``acc`` (extrema when ``extrema``), as as many calls of :meth:`._forced_steady._Runner.cycle` with
    that start row do (a Poincaré map). :data:`MODE_CARRY` runs them with each cycle's rows following those
    of the cycle before, from ``n0``, and writes the state ``(x, v, y, w)`` after cycle ``k`` into row
    ``k - k0`` of ``pts`` (a measurement). Both stop at the first cycle the driver stops, and use none
    of the arguments after ``k1`` but ``pts``. :data:`MODE_SEARCH` runs the search's cycles described below.

    Parameters
    ----------
    prm, fc, fcs, st, restitution, rtol, impacts, acc, extrema
        As :func:`._forced_driver.advance` (``st`` updated in place; in :data:`MODE_SEARCH` mode each cycle
        writes its impact rows from row 0 and its accumulators into ``acc``, reset each cycle).
    n0 : int
        First impact row (:data:`MODE_PLAIN`, :data:`MODE_CARRY`; 0 in :data:`MODE_SEARCH` mode).
    cap : int
        Impact rows a cycle may write: its row limit is ``min(first row + cap, impacts.shape[0] - 1)``.
    mode : int
        :data:`MODE_PLAIN`, :data:`MODE_CARRY` or :data:`MODE_SEARCH`.
    j0 : int
        Cycles the run has done since its start: cycle ``k`` spans ``[(j0 + k - k0) T, (j0 + k - k0 + 1) T]``.
    T : float
        Forcing period in s.
    k0, k1 : int
        First and last cycle numbers to run.
    scale : (4,) ndarray
        Scale of the section variables (m, m/s).
    pts : (n, 4) ndarray
        :data:`MODE_SEARCH`: scaled section points by cycle number; row ``k`` written after cycle ``k`` (rows
        before ``k0`` read). :data:`MODE_CARRY`: ``(k1 - k0 + 1, 4)`` states written.
    xhi, xlo, ipc : (n,) ndarray
        Largest and smallest main-mass displacement (m) and impact count of each cycle, written.
    orbits : (r, 4) ndarray
        Scaled points of the known stable periodic orbits; ``orbit_cols`` (r,) the columns compared (2 or 4).
    capture : float
        Scaled distance to a known orbit point that stops the run.
    trigger : float
        Return distance under which (twice in a row) a period is tried.
    checkpoints : ndarray of int
        Cycles at which the best return below ``checkpoint_return`` is tried.
    next_try : int
        No period is tried before this cycle.
    probe : int
        Stop at the multiples of ``probe`` cycles (0: never), the comparisons with known non-periodic motions.

    Returns
    -------
    tuple of int
        ``(k, status, n)``: the last cycle run, at which the search looks (``k1`` when none stopped the
        run earlier), the driver's status of that cycle and its next free impact row.
    """
    max_period = 8
    record = mode == MODE_SEARCH
    d = np.empty(max_period + 1)
    prev = np.empty(max_period + 1)
    if record:
        _returns(pts, k0 - 1, max_period, prev)
    row0 = 0 if record else n0
    last = impacts.shape[0] - 1
    for k in range(k0, k1 + 1):
        t0 = (j0 + k - k0) * T
        if record:
            acc[0] = 0.0
            acc[1] = 0.0
            acc[2] = 0.0
            acc[3] = -np.inf
            acc[4] = np.inf
        # the driver's one call site here: each call site inlines a copy of it
        n, status = fd.advance_inline(prm, fc, fcs, st, t0, t0 + T, restitution, rtol, impacts, row0,
                                      min(row0 + cap, last), acc, extrema)
        if not record:
            if mode == MODE_CARRY:
                row0 = n
                for c in range(4):
                    pts[k - k0, c] = st[c]
            if status != STATUS_OK or k == k1:
                return k, status, n
            continue
        if status != STATUS_OK:
            return k, status, n
        xhi[k] = acc[3]
        xlo[k] = acc[4]
        ipc[k] = n
        pts[k, 0] = st[0] / scale[0]
        pts[k, 1] = st[1] / scale[1]
        pts[k, 2] = (st[2] - st[0]) / scale[2]
        pts[k, 3] = (st[3] - st[1]) / scale[3]
        if k == k1 or _search_stops(pts, k, orbits, orbit_cols, capture, probe, d, prev, trigger, checkpoints,
                                    checkpoint_return, next_try):
            return k, status, n
    return k1, STATUS_OK, 0
