"""Fixed-step solvers of the impact damper (numba), free decay and forced.

The paper's average-acceleration Newmark-beta scheme (one kernel, :func:`newmark_advance`, with
the external force ``F(t) = P cos(ωt) + Q sin(ωt)`` on the main mass as a parameter; free decay
is ``F = 0``), and explicit central differences (only to show where an explicit scheme fails).

Equations (paper eq 15 with forcing), wall ``s = ±1``, penetration ``δ = s (y - x) - d/2``::

    M x'' + C x' + K x = s F_c + F(t),   m y'' = -s F_c,   F_c = K_HZ δ^{3/2} + c1 dδ/dt (δ > 0).

Model: :class:`~acoustiviz.dynamics._records.Params` (the drivers called from Python take the
parameter vector ``p`` and turn it into one); forcing vector ``fc``: None (free decay, compiled
without the forcing terms) or ``[ω rad/s, P N, Q N, ...]``. State ``st`` (in/out, 8 floats):
``x, v, y, w`` (m, m/s), in-contact flag, wall; impact rows as ``IMPACT_COLUMNS`` of :mod:`._status`
(a row is opened at contact onset with a NaN separation speed and closed at the end of the contact).
Accumulators ``acc`` (added to): work of F, dissipated by C, dissipated in contacts (J), largest and
smallest x (m).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from .._jit import compile_for, helper, kernel, njit
from ._flight import record_extremum
from ._records import DenseOutput, NmBooks, Turns, as_params, params_record
from ._status import STATUS_DIVERGED, STATUS_MAX_IMPACTS, STATUS_OK

#: One end of a Newmark step: displacements ``x, y`` (m), velocities ``v, w`` (m/s), accelerations
#: ``ax, ay`` (m/s²), the wall in contact ``sw`` (±1, 0 apart), penetration ``d`` (m), contact force
#: ``f`` (N) and the power of the contact damping force ``pw`` (W).
NmPoint = namedtuple("NmPoint", ["x", "v", "y", "w", "ax", "ay", "sw", "d", "f", "pw"])


@helper
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


@helper
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


@njit(inline="always")
def _nm_step(prm, a, h, fx1, escale):
    """The end (:data:`NmPoint`) of one Newmark step of ``h`` s from the point ``a``.

    The step-end accelerations come from Newton iterations on ``M a_x + C v + K x - s F_c - F = 0``,
    ``m a_y + s F_c = 0`` at the step end (force ``fx1`` N there), the predictor being the unchanged
    accelerations; they stop when the correction moves the displacements by at most ``escale`` m
    (or after 30 iterations).
    """
    M, K, C, m, hg, kh, c1, clip = prm.M, prm.K, prm.C, prm.m, prm.half_gap, prm.k_hertz, prm.c1, prm.clip
    hh = 0.25 * h * h
    h2 = 0.5 * h
    bx = a.ax
    by = a.ay
    for _ in range(30):
        x1 = a.x + h * a.v + hh * (a.ax + bx)
        y1 = a.y + h * a.w + hh * (a.ay + by)
        v1 = a.v + h2 * (a.ax + bx)
        w1 = a.w + h2 * (a.ay + by)
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
    x1 = a.x + h * a.v + hh * (a.ax + bx)
    y1 = a.y + h * a.w + hh * (a.ay + by)
    v1 = a.v + h2 * (a.ax + bx)
    w1 = a.w + h2 * (a.ay + by)
    sw1, d1, u1, f1, fe1, _ = _nm_force(x1, y1, v1, w1, hg, kh, c1, clip)
    return NmPoint(x1, v1, y1, w1, bx, by, sw1, d1, f1, (f1 - fe1) * u1)


@njit(inline="always")
def _nm_impacts(hg, a, b, t, h, in_contact, impacts, n, max_impacts):
    """Book the contact of one step from ``a`` to ``b`` (starting at ``t`` s) into the impact rows.

    A row opens at contact onset (time and wall; the approach speed extrapolated from the free
    side, because the paper's damping force jumps at first touch; a NaN separation speed), gathers
    the peak force (N), impulse (N s, trapezoidal) and energy lost (J) while the contact lasts, and
    closes at its end (separation speed m/s and duration s). Onset and end are located by linear
    interpolation of the penetration ``hg`` m past contact. Returns the next free row, or -1 when
    an onset finds no free row (nothing written).
    """
    h2 = 0.5 * h
    now = b.sw != 0.0
    if now and not in_contact:
        if n >= max_impacts:
            return -1
        z0 = b.sw * (a.y - a.x) - hg
        fr = -z0 / (b.d - z0) if b.d != z0 else 1.0
        impacts[n, 0] = t + fr * h
        impacts[n, 1] = b.sw
        impacts[n, 2] = b.sw * (a.w - a.v) + fr * h * b.sw * (a.ay - a.ax)
        impacts[n, 3] = math.nan
        for j in range(4, 8):
            impacts[n, j] = 0.0
        n += 1
    if now:
        r = n - 1
        impacts[r, 5] = max(impacts[r, 5], b.f)
        impacts[r, 6] += h2 * (a.f + b.f) if in_contact else h2 * b.f
        impacts[r, 7] += h2 * (a.pw + b.pw)
    if in_contact and not now:
        r = n - 1
        z1 = a.sw * (b.y - b.x) - hg
        fr = a.d / (a.d - z1) if a.d != z1 else 1.0
        impacts[r, 3] = -(a.sw * (b.w - b.v) - (1.0 - fr) * h * a.sw * (b.ay - b.ax))
        impacts[r, 4] = t + fr * h - impacts[r, 0]
        impacts[r, 6] += h2 * a.f
    return n


@njit(inline="always")
def _nm_dense(a, b, t, t1, h, c_main, ec, en, t_eval, ie, dense):
    """Dense rows (``DENSE_COLUMNS``) at the output times ``t_eval`` (s) of the step ``a`` -> ``b``, ``t`` -> ``t1`` s.

    ``h`` is the step (s) as the caller holds it (``t1 - t`` may differ from it in the last bit).

    Cubic Hermite in displacement, linear acceleration in velocity; the dissipation by the main
    dashpot ``c_main`` (N s/m) and in contacts (J) taken back from the step-end totals ``ec`` and
    ``en`` along the trapezoid. Returns the next output time due.
    """
    h2 = 0.5 * h
    while ie < t_eval.shape[0] and t_eval[ie] <= t1 + 1e-9 * h:
        s = min((t_eval[ie] - t) / h, 1.0)
        h00 = 2 * s**3 - 3 * s**2 + 1
        h10 = s**3 - 2 * s**2 + s
        h01 = -2 * s**3 + 3 * s**2
        h11 = s**3 - s**2
        dense[ie, 0] = h00 * a.x + h10 * h * a.v + h01 * b.x + h11 * h * b.v
        dense[ie, 1] = h00 * a.v + h10 * h * a.ax + h01 * b.v + h11 * h * b.ax
        dense[ie, 2] = h00 * a.y + h10 * h * a.w + h01 * b.y + h11 * h * b.w
        dense[ie, 3] = h00 * a.w + h10 * h * a.ay + h01 * b.w + h11 * h * b.ay
        dense[ie, 4] = ec - (1.0 - s) * h2 * c_main * (a.v * a.v + b.v * b.v)
        dense[ie, 5] = en - (1.0 - s) * h2 * (a.pw + b.pw)
        ie += 1
    return ie


#: Entries of a Newmark run's ``resume`` vector (float64): steps taken since ``t0``, the Newton
#: iterations' energy scale, 1.0 once the step end below holds, then the step end (``NmPoint``).
RESUME_STEPS, RESUME_ESCALE, RESUME_HELD, RESUME_POINT = 0, 1, 2, 3
_POINT_SIZE = len(NmPoint._fields)
RESUME_SIZE = RESUME_POINT + _POINT_SIZE


@helper
def _take_up(resume, a, escale, in_contact, flag):
    """``(steps done, step end, energy scale, in contact)`` where ``resume`` left them, else as given."""
    if resume is None:  # removed at compile time for one call
        return 0, a, escale, in_contact
    if resume[RESUME_HELD] < 0.5:
        return int(resume[RESUME_STEPS]), a, escale, in_contact
    q = RESUME_POINT
    b = NmPoint(resume[q], resume[q + 1], resume[q + 2], resume[q + 3], resume[q + 4], resume[q + 5],
                resume[q + 6], resume[q + 7], resume[q + 8], resume[q + 9])
    return int(resume[RESUME_STEPS]), b, resume[RESUME_ESCALE], b.sw != 0.0 and flag > 0.5


@helper
def _hold(resume, steps, escale, a):
    """Keep in ``resume`` what the next call takes up (nothing without it)."""
    if resume is None:
        return
    resume[RESUME_STEPS] = steps
    resume[RESUME_ESCALE] = escale
    resume[RESUME_HELD] = 1.0
    for i in range(_POINT_SIZE):
        resume[RESUME_POINT + i] = a[i]


@kernel
def newmark_advance(prm, fc, st, t0, h, nsteps, n, books, dense, turns, resume=None):
    """Average-acceleration Newmark-beta (γ = 1/2, β = 1/4), ``nsteps`` steps of ``h`` s from ``t0`` s.

    Each step solves ``M a_x + C v + K x - s F_c - F = 0``, ``m a_y + s F_c = 0`` at the new
    time with ``x1 = x + h v + h²/4 (a + a1)``, ``v1 = v + h/2 (a + a1)`` by Newton iterations on
    the accelerations (:func:`_nm_step`; the paper's scheme, Clough and Penzien). Contacts are
    booked by :func:`_nm_impacts`. Work and dissipation by the trapezoidal rule into
    ``books.acc[0:3]``; with ``books.minmax`` the step-end extremes of x into ``books.acc[3:5]``.

    Extrema of x (into ``turns``) are the turning points of the cubic Hermite interpolant of each
    step whose end velocities differ in sign (:func:`_hermite_turn`), the interpolant of the dense
    output (:func:`_nm_dense`); ``turns=None`` and ``dense=None`` compile them out.

    Parameters
    ----------
    prm : Params
        The model (:class:`~acoustiviz.dynamics._records.Params`, SI).
    fc : ndarray or None
        Forcing ``[ω rad/s, P N, Q N, ...]``; None for free decay (compiled without it).
    st : ndarray
        State (module docstring), updated in place.
    t0, h : float
        Start time and step (s).
    nsteps : int
        Steps to take.
    n : int
        The first free impact row of ``books.impacts``.
    books : NmBooks
        Impact rows and their limit, accumulators (module docstring; added to) and whether the
        step-end extremes of x are tracked (:class:`~acoustiviz.dynamics._records.NmBooks`).
    dense : DenseOutput or None
        Output times (s), the next one due and the (n, 6) dense rows
        (:class:`~acoustiviz.dynamics._records.DenseOutput`); None: no dense output.
    turns : Turns or None
        Turning points of x (rows: time s, x m, ±1) and their count
        (:class:`~acoustiviz.dynamics._records.Turns`); None: not located.
    resume : ndarray or None
        A run continued over several calls (``RESUME_SIZE`` floats, zeros at the start, updated in
        place): step ``k`` of the whole run ends at ``t0 + (k + 1) h`` and each call takes up the
        step end (accelerations and contact force included) and the energy scale where the last
        one stopped, so that the steps are those of one call, bit for bit. None: one call, from
        ``st`` at ``t0`` (compiled out).

    Returns
    -------
    tuple
        ``(n, status, t, ie)``: ``n`` the next free impact row, ``status`` (``STATUS_OK``, ``STATUS_MAX_IMPACTS`` or
        ``STATUS_DIVERGED``), ``t`` the time reached (s; ``st`` holds the state there) and ``ie``
        the next output time due (``dense.ie``, or 0 without dense output).
    """
    M, K, C, m = prm.M, prm.K, prm.C, prm.m
    impacts, max_impacts, acc, minmax = books
    ie = 0
    if dense is not None:  # removed at compile time without dense output
        ie = dense.ie
    om = 0.0
    pc = 0.0
    ps = 0.0
    forced = False
    if fc is not None:  # removed at compile time for free decay
        om, pc, ps = fc[0], fc[1], fc[2]
        forced = True
    x, v, y, w = st[0], st[1], st[2], st[3]
    sw, d, u, f, fe, _ = _nm_force(x, y, v, w, prm.half_gap, prm.k_hertz, prm.c1, prm.clip)
    fx = pc * math.cos(om * t0) + ps * math.sin(om * t0) if forced else 0.0
    a = NmPoint(x, v, y, w, (sw * f - K * x - C * v + fx) / M, -sw * f / m, sw, d, f, (f - fe) * u)
    in_contact = sw != 0.0 and st[4] > 0.5
    wk, ec, en, xmax, xmin = acc[0], acc[1], acc[2], acc[3], acc[4]
    status = STATUS_OK
    h2 = 0.5 * h
    escale = 1e-13 * (abs(v) + abs(w) + 1.0)
    k0, a, escale, in_contact = _take_up(resume, a, escale, in_contact, st[4])
    t = t0 + k0 * h if k0 else t0
    done = 0
    for k in range(k0, k0 + nsteps):
        t1 = t0 + (k + 1) * h
        fx1 = pc * math.cos(om * t1) + ps * math.sin(om * t1) if forced else 0.0
        b = _nm_step(prm, a, h, fx1, escale)
        if not (math.isfinite(b.x) and math.isfinite(b.y)):
            status = STATUS_DIVERGED
            break
        if forced:
            wk += h2 * (fx * a.v + fx1 * b.v)
        ec += h2 * C * (a.v * a.v + b.v * b.v)
        en += h2 * (a.pw + b.pw)
        if minmax:
            xmax = max(xmax, b.x)
            xmin = min(xmin, b.x)
        if in_contact or b.sw != 0.0:  # nothing to book in free flight (the impact rows handed over only here)
            n1 = _nm_impacts(prm.half_gap, a, b, t, h, in_contact, impacts, n, max_impacts)
            if n1 < 0:  # no free row for a new contact: stop at the step end, the contact not opened
                status = STATUS_MAX_IMPACTS
                t = t1
                a = NmPoint(b.x, b.v, b.y, b.w, a.ax, a.ay, a.sw, a.d, a.f, a.pw)
                break
            n = n1
        if turns is not None and (a.v > 0.0) != (b.v > 0.0):  # turns=None: compiled out
            s_turn, x_turn = _hermite_turn(a.x, a.v, b.x, b.v, h)
            record_extremum(turns.rows, turns.count, t + s_turn * h, x_turn, 1.0 if a.v > 0.0 else -1.0)
        # dense=None: compiled out; the arrays are handed over only in the steps that have output
        if dense is not None and ie < dense.t_eval.shape[0] and dense.t_eval[ie] <= t1 + 1e-9 * h:
            ie = _nm_dense(a, b, t, t1, h, C, ec, en, dense.t_eval, ie, dense.rows)
        a = b
        fx = fx1
        in_contact = b.sw != 0.0
        t = t1
        done += 1
    _hold(resume, k0 + done, escale, a)
    st[0] = a.x
    st[1] = a.v
    st[2] = a.y
    st[3] = a.w
    st[4] = 1.0 if in_contact else 0.0
    st[5] = a.sw
    acc[0] = wk
    acc[1] = ec
    acc[2] = en
    acc[3] = xmax
    acc[4] = xmin
    return n, status, t, ie


#: Steps of one call of the compiled Newmark kernel in a free-decay run (a fraction of a second):
#: between calls Python handles a pending Ctrl-C, so a long run stops promptly; the steps are
#: those of one call, bit for bit (``resume`` of :func:`newmark_advance`).
NEWMARK_CHUNK_STEPS = 1 << 19


def _free_decay_args(prm, st, h, n, books, t_eval, ie, dense, turns, resume) -> tuple:
    """The arguments of one call of :func:`newmark_advance` in a free-decay run."""
    out = None if t_eval is None else DenseOutput(t_eval, ie, dense)
    return prm, None, st, 0.0, float(h), 0, n, books, out, turns, resume


def compile_newmark(p, h, t_eval, max_impacts, impacts, dense, ext, n_ext) -> float:
    """Compile (or load) the kernel of :func:`newmark` for these arguments without running it; the wall s."""
    books = NmBooks(impacts, int(max_impacts), np.zeros(5), False)
    turns = None if ext is None else Turns(ext, n_ext)
    return compile_for(newmark_advance, _free_decay_args(params_record(p), np.zeros(8), h, 0, books, t_eval, 0,
                                                         dense, turns, np.zeros(RESUME_SIZE)))


def newmark(p, state0, h, nsteps, t_eval, max_impacts, impacts, dense, final, ext, n_ext, *,
            chunk: int | None = None, progress=None):
    """Free decay by :func:`newmark_advance` from t = 0 (no forcing), ``nsteps`` steps of ``h`` s.

    A start inside a contact opens an impact row at t = 0. A contact still open at the end
    keeps a NaN separation speed and its duration so far. Fills ``final`` (x, v, y, w,
    dissipated by C, dissipated in contacts, δ at the end; SI). Returns
    ``(n_impacts, status, t_reached)``; arrays as in
    :func:`~acoustiviz.dynamics._kernels.event_solver`. The kernel runs ``chunk`` steps per
    call (default :data:`NEWMARK_CHUNK_STEPS`); ``progress(steps done, nsteps)`` is called
    between calls.
    """
    prm = params_record(p)
    hg = prm.half_gap
    st = np.zeros(8)
    st[:4] = state0[:4]
    z = state0[2] - state0[0]
    n = 0
    if abs(z) > hg:  # a start inside a contact
        sw = 1.0 if z > 0.0 else -1.0
        st[4] = 1.0
        st[5] = sw
        impacts[0, :] = 0.0
        impacts[0, 1] = sw
        impacts[0, 2] = sw * (state0[3] - state0[1])
        impacts[0, 3] = math.nan
        n = 1
    acc = np.zeros(5)
    books = NmBooks(impacts, int(max_impacts), acc, False)
    turns = None if ext is None else Turns(ext, n_ext)
    resume = np.zeros(RESUME_SIZE)
    nsteps = int(nsteps)
    chunk = max(1, int(NEWMARK_CHUNK_STEPS if chunk is None else chunk))
    done, ie = 0, 0
    while True:
        args = list(_free_decay_args(prm, st, h, n, books, t_eval, ie, dense, turns, resume))
        args[5] = min(chunk, nsteps - done)
        n, status, t, ie = newmark_advance(*args)
        done += args[5]
        if status != STATUS_OK or done >= nsteps:
            break
        if progress is not None:
            progress(done, nsteps)
    delta = 0.0
    if st[4] > 0.5:
        impacts[n - 1, 4] = t - impacts[n - 1, 0]
        delta = st[5] * (st[2] - st[0]) - hg
    final[:4] = st[:4]
    final[4] = acc[1]
    final[5] = acc[2]
    final[6] = delta
    return n, status, t


@kernel
def central_difference(p, state0, h, nsteps):
    """Explicit central-difference integration; returns the largest |y - x| in m reached.

    Used only to show where an explicit scheme fails: it is stable for ``h < 2 / ω_contact``.
    Damping forces use the previous half-step velocity (explicit).
    """
    prm = as_params(p)
    M, K, C, m, hg, kh, c1, clip = prm.M, prm.K, prm.C, prm.m, prm.half_gap, prm.k_hertz, prm.c1, prm.clip
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
