r"""Several balls in operation: the attractors of the forced multi-ball damper at each frequency.

The multi-ball damper (:mod:`acoustiviz.dynamics.balls`) driven as the single-ball damper in
operation (:mod:`acoustiviz.dynamics.forced`): the main mass carries ``F(t) = P cos ωt + Q sin ωt``
(a base motion mapped to it by :meth:`~acoustiviz.dynamics.forced.Excitation.force_coefficients`),
advanced by the compiled multi-ball solver with forcing (:func:`~acoustiviz.dynamics._balls.run_balls`).

At each frequency several starts (:func:`ball_start_states`, the rules of the single-ball
:func:`~acoustiviz.dynamics.forced.start_states`) are each run cycle by cycle on the Poincaré section
at forcing phase 0, where the state has ``2 + 2B`` components (main mass ``x, v``; each ball's
``s_i - x`` and ``w_i - v``, with ``s_i`` its reduced coordinate). A start has settled on a periodic
orbit of period ``n <= MAX_PERIOD`` when each of its last ``n`` section points returns after ``n``
cycles within ``tolerance`` (m and m/s); the orbit is measured over those ``n`` cycles. A start with
no such return within ``max_cycles`` is measured over a window of
:data:`~acoustiviz.dynamics.forced.NONPERIODIC_CYCLES` cycles in batches (the batch means and their
standard error of the single-ball code).

A measured motion's ``final_state`` is ``(x, v, y_1..y_B, w_1..w_B)`` (m, m/s; ball centres) at its
last section point, the single-ball ``(x, v, y, w)`` for one ball.

The Floquet multipliers of a periodic motion come from central differences of the direct map at its
last section point (:func:`ball_multipliers`); ``stable`` says whether they lie within the unit
circle. A motion reached by simulation is stable unless its start lay on an invariant set: two
identical cavities started alike stay alike, on an orbit that may be unstable to their moving
apart (the spread starts are therefore placed differently in each cavity). A section point that
leaves a pair no room for the difference step (inside a contact, a packed column) has no
multipliers and is stable by simulation.

What is left out for several balls: no shooting (no Newton refinement of the orbit, no unstable
orbits looked for), no Lyapunov exponent (a non-periodic motion is ``unresolved``, its amplitude the
batch mean with its error), and continuation is one pass along the sweep (each frequency also
starts from the final states of its neighbour's attractors).

All SI; frequencies in Hz.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from .._jit import compile_for
from .._validate import ParameterError
from ._attractors import FrequencyAttractors
from ._forced_response import AttractorResponse, band, first_round
from ._forced_steady import (
    BATCH_CYCLES,
    MAX_PERIOD,
    WINDOW_BATCHES,
    Excitation,
    SteadyState,
    SteadyStateOptions,
    check_settings,
)
from ._measure import _stats_agree
from ._shooting import STABILITY_MARGIN
from .balls import BallState, MultiBallModel
from .balls_solve import BALLS_COMPILE_S, BATCH_STEPS
from .model import DamperModel

__all__ = ["BallCycles", "ball_start_states", "ball_attractors_at", "ball_attractor_response", "same_ball_motion",
           "check_ball_settings", "section_scales", "settle_balls", "ball_multipliers", "BALL_SAME_ORBIT",
           "MIN_FD_STEP", "PACKED_CLEARANCE", "restart_state"]

#: Smallest central-difference step (scaled) of the multipliers; a point whose pairs leave less room has none.
MIN_FD_STEP = 1e-8
#: Clearance between the neighbours of a packed column at a start, as a fraction of the cavity's free travel.
PACKED_CLEARANCE = 1e-9
#: Scaled distance under which two periodic motions of the balls are one attractor (the single-ball rule).
BALL_SAME_ORBIT = 1e-4
#: A period whose section points also return within this many tolerances at a shorter period (a divisor)
#: is an orbit of the shorter period still settling (:func:`_returned`).
SHORTER_PERIOD_MARGIN = 10.0


def _stand_in(model: MultiBallModel) -> DamperModel:
    """The single-ball damper of the first cavity's first ball (for the checks shared with ``forced``)."""
    c = model.cavities[0]
    return DamperModel(M=model.M, K=model.K, C=model.C, m=c.masses[0], gap=c.gap, k_hertz=c.k_wall, c1=c.c_wall,
                       clip_tensile=model.clip_tensile)


def check_ball_settings(model, excitation, settings=None, **kwargs) -> SteadyStateOptions:
    """The forced settings (:func:`~acoustiviz.dynamics.forced.check_settings`) checked for several balls.

    Only the ``event`` solver (the multi-ball kernel) and no ``restitution``.
    """
    if not isinstance(model, MultiBallModel):
        raise ParameterError("model", f"expected a MultiBallModel, got {type(model).__name__}")
    settings = check_settings(_stand_in(model), excitation, settings, **kwargs)
    if settings.solver != "event":
        raise ParameterError("solver", f"several balls are solved by the event solver only, got {settings.solver!r}")
    return settings


def section_scales(model: MultiBallModel, excitation: Excitation) -> np.ndarray:
    """Scale of the section variables ``(x, v, s_i - x..., w_i - v...)`` in m and m/s.

    ``X_s = max(|X|, d/2)`` and ``ω X_s`` for the main mass (the single-ball rule), each ball's
    cavity's ``d/2`` and ``ω d/2``.
    """
    hg = np.concatenate([[0.5 * c.gap] * c.n_balls for c in model.cavities])
    xs = max(abs(excitation.linear_response(model)), float(hg.max()))
    om = excitation.omega
    return np.concatenate([[xs, om * xs], hg, om * hg])


def ball_start_states(model: MultiBallModel, excitation: Excitation, count: int) -> list:
    """``count`` starts at forcing phase 0 (:class:`BallState`), deterministic.

    The rules of :func:`~acoustiviz.dynamics.forced.start_states` with each cavity's column of balls
    packed (:data:`PACKED_CLEARANCE` apart) where the one impact mass would be: the linear start (the
    main mass on its linear steady state, the column at rest at the cavity's centre at rest), rest,
    then the column spread evenly across each cavity's free travel, moving alternately towards
    ``wall+`` and ``wall-`` at ``ω d/2`` relative to the main mass; with several cavities, cavity c
    (from 0) of spread start j takes the place of spread start ``(j + c) mod k``, so that identical
    cavities do not all start alike. One ball: the single-ball starts.
    """
    xc = excitation.linear_response(model)
    x0, v0 = xc.real, -excitation.omega * xc.imag
    off = model.offsets()
    out = []
    k = max(count - 2, 0)
    for j in range(count):
        if j < 2:
            x, v = (x0, v0) if j == 0 else (0.0, 0.0)
            z = [min(max(0.0, x - 0.5 * c.gap), x + 0.5 * c.gap) - x for c in model.cavities]
            u = [-v for _ in model.cavities]
        else:
            x, v = x0, v0
            spread = [(j - 2 + ic) % k for ic in range(len(model.cavities))]  # cavity ic: the next start's place
            z = [0.95 * 0.5 * c.gap * ((2 * i + 1) / k - 1.0) for i, c in zip(spread, model.cavities, strict=True)]
            u = [(1.0 if i % 2 == 0 else -1.0) * excitation.omega * 0.5 * c.gap
                 for i, c in zip(spread, model.cavities, strict=True)]
        s = np.concatenate([x + _column(z[ic], c) for ic, c in enumerate(model.cavities)])
        w = np.concatenate([[v + u[ic]] * c.n_balls for ic, c in enumerate(model.cavities)])
        out.append(BallState(x, v, tuple(s + off), tuple(w)))
    return out[:count]


def _column(z: float, cavity) -> np.ndarray:
    """Reduced coordinates less x (m) of a column packed about ``z``: :data:`PACKED_CLEARANCE` of the gap apart.

    The clearance keeps neighbours, and the end balls of a column pushed against a wall, from overlapping
    by a rounding of their offsets; one ball sits at ``z``.
    """
    n = cavity.n_balls
    if n == 1:
        return np.array([z])
    clr = PACKED_CLEARANCE * cavity.gap
    h = 0.5 * (n - 1) * clr
    zc = min(max(z, -0.5 * cavity.gap + h + clr), 0.5 * cavity.gap - h - clr)
    return zc + clr * (np.arange(n) - 0.5 * (n - 1))


class BallCycles:
    """The forced multi-ball damper advanced forcing cycle by cycle from ``initial`` at t = 0.

    Parameters
    ----------
    model : MultiBallModel
    excitation : Excitation
    initial : BallState
    rtol : float
        Relative tolerance of the contact integration.
    max_impacts_per_cycle : int
        More collisions in one cycle than this times the number of balls stop the run (chattering).
    """

    def __init__(self, model, excitation, initial, rtol, max_impacts_per_cycle=200):
        from . import _balls as kern

        self.kern, self.model, self.excitation = kern, model, excitation
        q0, u0 = initial.reduced(model)
        pr, mass = model.pairs(), model.masses()
        self.nb, self.npair = mass.size, pr["pa"].size
        self.y = np.concatenate([q0, u0, np.zeros(2 * self.npair + 2)])
        self.fc = excitation.vector(model)
        scale = section_scales(model, excitation)
        gap = max(c.gap for c in model.cavities)
        uref = max(float(scale[1]), float(np.abs(u0).max()), excitation.omega * 0.5 * gap)
        atol = np.concatenate([np.full(self.nb, rtol * gap), np.full(self.nb, rtol * uref)])
        self.active = np.zeros(self.npair, dtype=np.bool_)
        self.open_row = np.full(self.npair, -1, dtype=np.int64)
        self.peaks = np.zeros(self.npair)
        self.clock = np.array([0.0, 1e-6])
        self.ie = np.zeros(1, dtype=np.int64)
        self.rows = np.empty((int(max_impacts_per_cycle) * model.n_balls + self.npair, 9))
        self.n_rows = np.zeros(1, dtype=np.int64)
        self.ext = np.zeros(5)
        self.k = 0
        self.contact_closed = 0.0
        self.args = [mass, pr["pa"], pr["pb"], pr["hg"], pr["kh"], pr["cc"], pr["cav"], pr["loc"], float(model.K),
                     float(model.C), bool(model.clip_tensile), self.y, self.active, self.open_row, self.peaks,
                     self.clock, 0.0, float(rtol), atol, np.zeros(0), self.ie, np.empty((0, 2 * self.nb)),
                     self.rows, self.n_rows, BATCH_STEPS, self.fc, self.ext]
        self.compile_time = compile_for(kern.run_balls, self.args, "multi-ball solver", BALLS_COMPILE_S)

    def section(self) -> np.ndarray:
        """The section point ``(x, v, s_i - x..., w_i - v...)`` in m and m/s."""
        nb, y = self.nb, self.y
        return np.concatenate([[y[0], y[nb]], y[1:nb] - y[0], y[nb + 1:2 * nb] - y[nb]])

    def energy(self) -> float:
        """Mechanical energy in J (kinetic + main spring + Hertz)."""
        return self.model.energy(self.y[:self.nb], self.y[self.nb:2 * self.nb])

    def totals(self) -> tuple:
        """Work of F, energy dissipated by C and in the contacts so far, in J."""
        nb, npair = self.nb, self.npair
        open_work = float(np.sum(self.y[2 * nb + npair:2 * nb + 2 * npair][self.active]))
        closed = np.ones(self.n_rows[0], dtype=bool)
        closed[self.open_row[self.open_row >= 0]] = False
        closed_work = self.contact_closed + float(np.sum(self.rows[:self.n_rows[0], 8][closed]))
        return float(self.y[-1]), float(self.y[2 * nb + 2 * npair]), closed_work + open_work

    def cycle(self) -> tuple:
        """Advance one forcing period: ``(status, x max m, x min m, impact rows of the cycle)``.

        The rows (:data:`~acoustiviz.dynamics._balls.IMPACT_ROW_COLUMNS`) of the collisions that began
        in the cycle, as they stand at its end.
        """
        kern = self.kern
        keep = self.open_row[self.open_row >= 0]  # contacts under way: their rows move to the front
        closed = np.ones(self.n_rows[0], dtype=bool)
        closed[keep] = False
        self.contact_closed += float(np.sum(self.rows[:self.n_rows[0], 8][closed]))
        order = np.argsort(keep)
        self.rows[:keep.size] = self.rows[keep[order]]
        for new, p in enumerate(np.flatnonzero(self.open_row >= 0)[order]):
            self.open_row[p] = new
        self.n_rows[0] = n0 = keep.size
        self.ext[3] = self.ext[4] = self.y[0]
        self.k += 1
        t_stop = self.k * self.excitation.period
        self.args[16] = t_stop
        status = kern.STATUS_REACHED
        while self.clock[0] < t_stop and status == kern.STATUS_REACHED:
            status = kern.run_balls(*self.args)
        return status, float(self.ext[3]), float(self.ext[4]), self.rows[n0:self.n_rows[0]].copy()


@dataclass
class _Record:
    """Per cycle of one start: section points, extrema, collisions, energy totals."""

    pts: list
    xhi: list
    xlo: list
    rows: list
    totals: list
    energy: list


def _steady(model, excitation, settings, rec, first, last, cycles, *, period, message, err=0.0, amp=None):
    """A :class:`SteadyState` measured over the cycles ``first..last`` (1-based, inclusive) of ``rec``."""
    sl = slice(first, last + 1)
    rows = np.concatenate(rec.rows[sl]) if last >= first else np.empty((0, 9))
    m = last - first + 1
    work, diss, cont = (np.array(rec.totals[last]) - np.array(rec.totals[first - 1])).tolist()
    om = excitation.omega
    xhi, xlo = max(rec.xhi[sl]), min(rec.xlo[sl])
    wall = (rows[:, 3] == 0) | (rows[:, 3] == _balls_in(model, rows[:, 2]))
    walls = np.where(rows[:, 3] == 0, -1.0, 1.0) * wall
    return SteadyState(
        excitation=excitation, model=model, solver="event", regime=f"periodic-{period}" if period else "unresolved",
        converged=bool(period), period=period, cycles=int(cycles), amplitude=0.5 * (xhi - xlo) if amp is None else amp,
        x_max=float(xhi), x_min=float(xlo), impacts_per_cycle=len(rows) / m, impact_times=rows[:, 0].copy(),
        impact_phases=np.mod(om * rows[:, 0], 2.0 * math.pi), impact_speeds=rows[:, 4].copy(), impact_walls=walls,
        impact_peak_forces=rows[:, 6].copy(), impact_durations=rows[:, 1] - rows[:, 0], work_input=work,
        dissipated_main=diss, dissipated_contact=cont, energy_change=rec.energy[last] - rec.energy[first - 1],
        poincare=np.array(rec.pts[sl]), final_state=_absolute(rec.pts[last], model), message=message, success=True,
        settings={"tolerance": settings.tolerance, "rtol": settings.rtol, "max_cycles": settings.max_cycles,
                  "starts": settings.starts, "solver": "event", "restitution": None},
        measured_cycles=m, amplitude_std_err=err, stable=True, cycles_integrated=int(len(rec.pts) - 1))


def _balls_in(model, cavity_numbers):
    """The number of balls of each 1-based cavity number (the pair index of its ``wall+``)."""
    n = np.array([c.n_balls for c in model.cavities], dtype=float)
    return n[cavity_numbers.astype(int) - 1] if cavity_numbers.size else np.zeros(0)


def _failed(model, excitation, settings, k, why):
    nan = math.nan
    return SteadyState(
        excitation=excitation, model=model, solver="event", regime="unresolved", converged=False, period=0,
        cycles=int(k), amplitude=nan, x_max=nan, x_min=nan, impacts_per_cycle=nan, impact_times=np.empty(0),
        impact_phases=np.empty(0), impact_speeds=np.empty(0), impact_walls=np.empty(0),
        impact_peak_forces=np.empty(0), impact_durations=np.empty(0), work_input=nan, dissipated_main=nan,
        dissipated_contact=nan, energy_change=nan, poincare=np.empty((0, 2 + 2 * model.n_balls)), final_state=(),
        message=f"the solver stopped: {why} after {k} cycles", success=False,
        settings={"tolerance": settings.tolerance, "rtol": settings.rtol, "max_cycles": settings.max_cycles,
                  "starts": settings.starts, "solver": "event", "restitution": None}, measured_cycles=0,
        stable=False, cycles_integrated=int(k))


def _return_gap(pts, k, n) -> float:
    """Largest distance (m, m/s) of the last ``n`` section points up to ``k`` from those ``n`` cycles before."""
    return max(float(np.max(np.abs(pts[j] - pts[j - n]))) for j in range(k - n + 1, k + 1))


def _returned(rec, k, tol) -> int:
    """The smallest period n <= MAX_PERIOD whose last n section points all return within ``tol``, else 0.

    A period n whose points also return within ``SHORTER_PERIOD_MARGIN`` tol at a divisor d of n is not
    decided yet (0): that is an orbit of period d approached by deviations that alternate (multipliers of
    negative real part), which returns at n before it does at d; the run goes on until it returns at d.
    """
    pts = rec.pts
    for n in range(1, MAX_PERIOD + 1):
        if k < 2 * n:
            break
        if _return_gap(pts, k, n) < tol:
            if any(n % d == 0 and _return_gap(pts, k, d) < SHORTER_PERIOD_MARGIN * tol for d in range(1, n)):
                return 0
            return n
    return 0


def _clearance(model: MultiBallModel, point) -> float:
    """Smallest distance in m between the two bodies of any pair at section point ``point`` (<= 0: in contact)."""
    nb = model.n_balls
    q = np.concatenate([[0.0], np.asarray(point[2:2 + nb])])  # reduced coordinates less x
    pr = model.pairs()
    return float(np.min(pr["hg"] - (q[pr["pa"]] - q[pr["pb"]])))


def ball_multipliers(model, excitation, settings, point, n) -> tuple:
    """Floquet multipliers of the period-``n`` orbit through section point ``point``, and the cycles they cost.

    The monodromy matrix ``dP^n/ds`` by central differences of the direct map in the scaled section
    variables (:func:`section_scales`), the step of the single-ball shooting
    (:func:`~acoustiviz.dynamics._shooting.fd_step`) kept below a quarter of the smallest clearance of
    a pair, so that no perturbed start overlaps. Empty (no multipliers) when the point lies inside a
    contact or a perturbed run stops; sorted by decreasing modulus.
    """
    from ._shooting import fd_step

    scale = section_scales(model, excitation)
    room = _clearance(model, point)
    dim = scale.size
    h = min(fd_step(settings.rtol), 0.25 * room / float(np.max(scale[2:2 + model.n_balls])))
    if h < MIN_FD_STEP:  # inside a contact, or a packed column: no perturbation keeps every pair apart
        return np.empty(0, dtype=complex), 0
    q = np.asarray(point, dtype=float) / scale

    def fmap(qq):
        run = BallCycles(model, excitation, _ball_state(qq * scale, model), settings.rtol,
                         settings.max_impacts_per_cycle)
        for _ in range(n):
            if run.cycle()[0] != run.kern.STATUS_REACHED:
                return None
        return run.section() / scale

    jac = np.empty((dim, dim))
    for j in range(dim):
        e = np.zeros(dim)
        e[j] = h
        fp, fm = fmap(q + e), fmap(q - e)
        if fp is None or fm is None:
            return np.empty(0, dtype=complex), 2 * n * (j + 1)
        jac[:, j] = (fp - fm) / (2.0 * h)
    mult = np.linalg.eigvals(jac).astype(complex)
    return mult[np.argsort(-np.abs(mult), kind="stable")], 2 * n * dim


def settle_balls(model, excitation, settings, start: BallState) -> SteadyState:
    """Run one start to its attractor (module docstring) and measure it."""
    from ._balls import STATUS_MAX_IMPACTS

    run = BallCycles(model, excitation, start, settings.rtol, settings.max_impacts_per_cycle)
    rec = _Record([run.section()], [run.y[0]], [run.y[0]], [np.empty((0, 9))], [run.totals()], [run.energy()])
    window = WINDOW_BATCHES * BATCH_CYCLES
    limit = settings.max_cycles + window
    for k in range(1, limit + 1):
        status, hi, lo, rows = run.cycle()
        if status != run.kern.STATUS_REACHED:
            why = (f"more than {settings.max_impacts_per_cycle} collisions per ball in one cycle (chattering?)"
                   if status == STATUS_MAX_IMPACTS else "contact step size underflow")
            return _failed(model, excitation, settings, k, why)
        rec.pts.append(run.section())
        rec.xhi.append(hi)
        rec.xlo.append(lo)
        rec.rows.append(rows)
        if MAX_PERIOD < k <= settings.max_cycles + MAX_PERIOD:  # rows no orbit or window will measure
            rec.rows[k - MAX_PERIOD] = None
        rec.totals.append(run.totals())
        rec.energy.append(run.energy())
        n = _returned(rec, k, settings.tolerance)
        if n:
            mult, cost = ball_multipliers(model, excitation, settings, rec.pts[k], n)
            top = float(np.max(np.abs(mult))) if mult.size else math.nan
            stable = not top > 1.0 + STABILITY_MARGIN
            why = ("stable by simulation (no multipliers: the section point leaves a pair no room)" if not mult.size
                   else "stable" if stable else
                   f"unstable (largest multiplier modulus {top:.4g}): a start on an invariant set, such as "
                   "identical cavities started alike, stays on it")
            steady = _steady(model, excitation, settings, rec, k - n + 1, k, k - n, period=n,
                             message=f"periodic-{n}: the section points return within {settings.tolerance:g} "
                                     f"(m, m/s) after {k} direct cycles; {why}")
            return replace(steady, floquet=mult, stable=stable, cycles_integrated=steady.cycles_integrated + cost)
    first = settings.max_cycles + 1
    amps = [0.5 * (max(rec.xhi[b:b + BATCH_CYCLES]) - min(rec.xlo[b:b + BATCH_CYCLES]))
            for b in range(first, first + window, BATCH_CYCLES)]
    amp, err = float(np.mean(amps)), float(np.std(amps, ddof=1) / math.sqrt(len(amps)))
    return _steady(model, excitation, settings, rec, first, limit, settings.max_cycles, period=0, amp=amp, err=err,
                   message=f"unresolved: no period up to {MAX_PERIOD} within {settings.max_cycles} direct cycles; "
                           f"amplitude {amp:.6g} ± {err:.2g} m over {WINDOW_BATCHES} batches of {BATCH_CYCLES} "
                           f"cycles (no Lyapunov exponent for several balls)")


def same_ball_motion(a: SteadyState, b: SteadyState) -> bool:
    """True when two motions of the balls are one attractor (the rule of ``same_motion``, in 2 + 2B variables)."""
    if not (a.success and b.success):
        return False
    if a.period or b.period:
        if a.period != b.period:
            return False
        scale = section_scales(a.model, a.excitation)
        d = np.abs(a.poincare[:, None, :] - b.poincare[None, :, :]) / scale
        return bool(np.min(np.max(d, axis=2)) < BALL_SAME_ORBIT)
    return _stats_agree(a, b.amplitude, b.amplitude_std_err, b.impacts_per_cycle)


def _absolute(point, model: MultiBallModel) -> tuple:
    """``(x, v, y_1..y_B, w_1..w_B)`` in m and m/s (ball centres) of a section point."""
    nb = model.n_balls
    x, v = float(point[0]), float(point[1])
    return (x, v, *(x + point[2:2 + nb] + model.offsets()).tolist(), *(v + point[2 + nb:]).tolist())


def _ball_state(point, model: MultiBallModel) -> BallState:
    """The :class:`BallState` of a section point ``(x, v, s_i - x..., w_i - v...)``."""
    s = _absolute(point, model)
    nb = model.n_balls
    return BallState(s[0], s[1], tuple(s[2:2 + nb]), tuple(s[2 + nb:]))


def restart_state(steady: SteadyState) -> tuple | None:
    """``(cycles, start, overlap)``: a section point of a measured motion that can start a run, or None.

    The solver begins with every contact open, so a section point inside a contact (two bodies pressed
    into each other) cannot start it: the latest point outside every contact is taken, ``cycles`` forcing
    cycles before the last (0: the final state), ``overlap`` 0. When every point lies inside a contact (a
    column that never separates), the last one is taken with its pressed bodies moved apart to touch
    (:func:`_separate`), ``overlap`` the largest compression removed in m; None if they cannot be.
    ``start`` is a :class:`BallState` at forcing phase 0.
    """
    model = steady.model
    points = np.asarray(steady.poincare, dtype=float)
    for back, point in enumerate(points[::-1]):
        start = _ball_state(point, model)
        try:
            start.reduced(model)
        except ParameterError:
            continue
        return back, start, 0.0
    if not len(points):
        return None
    point, overlap = _separate(points[-1], model)
    start = _ball_state(point, model)
    try:
        start.reduced(model)
    except ParameterError:
        return None
    return 0, start, overlap


def _separate(point, model: MultiBallModel, sweeps: int = 1000) -> tuple:
    """``(point, overlap)``: a section point with every pressed pair moved apart to touch, the largest overlap in m.

    Sweeps over the pairs: a ball pressed into a wall moves off it, two pressed balls each move half the
    overlap, each by :data:`PACKED_CLEARANCE` of its cavity's gap more (the main mass and the velocities stay).
    """
    nb = model.n_balls
    pr = model.pairs()
    gap = np.array([c.gap for c in model.cavities])[pr["cav"].astype(int) - 1]
    q = np.concatenate([[point[0]], point[0] + point[2:2 + nb]])
    largest = 0.0
    for _ in range(sweeps):
        over = q[pr["pa"]] - q[pr["pb"]] - pr["hg"]
        if not np.any(over > 0.0):
            break
        largest = max(largest, float(over.max()))
        for k in np.flatnonzero(over > 0.0):
            a, b, move = pr["pa"][k], pr["pb"][k], float(over[k]) + PACKED_CLEARANCE * gap[k]
            if a == 0:
                q[b] += move
            elif b == 0:
                q[a] -= move
            else:
                q[a] -= 0.5 * move
                q[b] += 0.5 * move
    out = np.array(point, dtype=float)
    out[2:2 + nb] = q[1:] - q[0]
    return out, largest


def _state_of(a: SteadyState, model: MultiBallModel) -> BallState:
    """The start (at t = 0) that continues ``a`` at another frequency: its final state."""
    nb = model.n_balls
    s = a.final_state
    return BallState(s[0], s[1], tuple(s[2:2 + nb]), tuple(s[2 + nb:]))


def ball_attractors_at(model, excitation, settings, *, seeds=(), previous=None) -> FrequencyAttractors:
    """The starts of :func:`ball_start_states` and ``seeds`` (:class:`BallState`) run to their attractors.

    ``previous`` (a :class:`FrequencyAttractors` of the same frequency) keeps what was found before:
    only the seeds are run then.
    """
    c0 = time.process_time()
    if previous is None:
        found, counts, seeded, cycles, cpu = [], [], [], 0, 0.0
        starts = ball_start_states(model, excitation, settings.starts)
    else:
        found, counts, seeded = list(previous.attractors), list(previous.counts), list(previous.seeded)
        cycles, cpu, starts = previous.cycles_integrated, previous.cpu_s, []
    for k, start in enumerate([*starts, *seeds]):
        seed = k >= len(starts)
        steady = settle_balls(model, excitation, settings, start)
        cycles += steady.cycles_integrated
        for i, a in enumerate(found):
            if same_ball_motion(a, steady):
                (seeded if seed else counts)[i] += 1
                break
        else:
            found.append(steady)
            counts.append(0 if seed else 1)
            seeded.append(1 if seed else 0)
    return FrequencyAttractors(excitation, tuple(found), tuple(counts), settings.starts, tuple(seeded), (),
                               cpu + time.process_time() - c0, cycles, 0)


def _run_starts(args):
    """The starts of one frequency (picklable for process pools)."""
    model, excitation, settings = args
    return ball_attractors_at(model, excitation, settings)


def ball_attractor_response(model: MultiBallModel, frequencies, amplitude: float, *, kind: str = "force",
                            sweep: str = "up", executor=None, settings: SteadyStateOptions | None = None,
                            progress=None, **kwargs) -> AttractorResponse:
    """Every attractor of the forced multi-ball damper at each of ``frequencies`` (module docstring).

    Parameters as :func:`~acoustiviz.dynamics.forced.attractor_response`. The starts of every frequency
    run first (on ``executor`` when given, any :class:`concurrent.futures.Executor`); then ``sweep``
    "up" / "down" runs, frequency after frequency in that direction, the final states of the
    attractors of the one before as seeds (one pass), "both" makes both passes, "independent" none.
    """
    f, excitations, settings = band(model, frequencies, amplitude, kind, sweep, settings, kwargs, check_ball_settings)
    results = first_round(_run_starts, [(model, ex, settings) for ex in excitations], f, settings, executor, progress)
    orders = {"up": [range(f.size)], "down": [range(f.size - 1, -1, -1)], "independent": [],
              "both": [range(f.size), range(f.size - 1, -1, -1)]}[sweep]
    for order in orders:  # continuation: the seeds of each frequency depend on its neighbour's
        prev = None
        for i in order:
            if prev is not None:
                seeds = tuple(_state_of(a, model) for a in prev.attractors if a.success)
                results[i] = ball_attractors_at(model, excitations[i], settings, seeds=seeds, previous=results[i])
            prev = results[i]
        if progress:
            progress(f"continuation {'up' if order.step > 0 else 'down'}: "
                     f"{sum(len(r.attractors) for r in results)} attractors")
    return AttractorResponse(f, tuple(results), sweep, settings, len(orders))
