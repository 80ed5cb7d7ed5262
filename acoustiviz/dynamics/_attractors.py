r"""The attractors of the forced damper at one frequency: several starts, shooting, honest non-periodic motion.

Each start is run cycle by cycle on the Poincaré section (forcing phase 0). Whenever the section
points return close to themselves after n cycles (scaled distance below :data:`TRIGGER` twice in
a row), and at a few checkpoints (when the best return is within ``settings.checkpoint_return``), the
orbit is refined by shooting (:func:`._shooting.shoot`): Newton's method on ``P^n(s) = s``. A
converged orbit is measured over one period (amplitude, impacts, energy) with its Floquet
multipliers; a stable one ends the start, an unstable one (a saddle the run passed by) is kept
aside and the run goes on.

A start that finds no periodic orbit within ``max_cycles`` is measured over a window of
:data:`._forced_steady.WINDOW_BATCHES` batches of :data:`._forced_steady.BATCH_CYCLES` cycles:
the amplitude is the mean of the batches' half peak-to-peak displacement with the standard error
of the batch means, and the largest Lyapunov exponent is estimated alongside by the
two-trajectory method through the impacts (a copy displaced by ``d0`` = 1e-7 in the scaled
section variables, advanced by the same solver and renormalised to ``d0`` every cycle; the mean
of ``log(d / d0)`` per second over each batch, the first batch left out while the displacement
aligns with the most expanding direction). The regime is

* ``chaotic`` when the exponent is positive beyond :data:`._measure.LYAPUNOV_SIGMAS` standard errors;
* ``quasi-periodic`` when it is zero within that error bar and the bar is tight
  (below :data:`._measure.QUASI_PERIODIC_BOUND` per forcing cycle);
* ``unresolved`` otherwise, the reason in ``message`` (a contracting motion with no period up to
  8 found, or an exponent that the window cannot tell from zero); before that verdict the end
  of the window is tried once more by shooting (a slow spiral onto an orbit whose section
  point lay inside a contact when the direct run stopped).

Starts after the first that meet a known attractor are counted in its basin without being
measured again: a stable periodic orbit when the section point comes within
:data:`CAPTURE_DISTANCE` (scaled) of one of its points, or (``settings.reuse_known``) when a shooting
converges onto it (a point of the orbit within the :func:`same_motion` distance, at a multiple of its
period: what the measurement of the shot orbit, its reduction to the smallest period and the
comparison with the known ones would conclude, without their cycles); a non-periodic attractor when the
amplitude and impact rate of the last 32 cycles agree with its batch statistics within
:data:`._measure.LYAPUNOV_SIGMAS` batch standard deviations.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ._forced_direct import MODE_SEARCH, compile_once, run_cycles
from ._forced_steady import (
    BATCH_CYCLES,
    MAX_PERIOD,
    WINDOW_BATCHES,
    Excitation,
    SteadyState,
    SteadyStateOptions,
    _Runner,
    _start,
    check_settings,
    linear_start,
)
from ._measure import (
    SAME_ORBIT,
    _failed,
    _stats_agree,
    measure_periodic,
    measure_window,
    same_motion,
)
from ._shooting import PoincareMap, section_scale, shoot, with_multipliers
from ._status import STATUS_OK
from .model import DamperModel

__all__ = ["FrequencyAttractors", "start_states", "attractors_at", "steady_state", "same_motion",
           "SCREENED_CHECKPOINT_RETURN"]

#: Scaled return distance below which (twice in a row) a period is tried by shooting.
TRIGGER = 1e-2
#: Cycles at which the best period guess is tried by shooting even without a close return.
CHECKPOINTS = (8, 32, 128, 512, 2048)
#: ``checkpoint_return`` of a screened search (:class:`._forced_steady.SteadyStateOptions`): a point
#: farther than this (scaled) from each of its last :data:`MAX_PERIOD` points is far from any periodic
#: orbit, where Newton's method mostly fails after tens of cycles of Jacobians and step halvings. It
#: may also skip the rare solve that converges from there to an orbit with a small basin.
SCREENED_CHECKPOINT_RETURN = 0.1
#: Scaled distance to a known stable periodic orbit within which a start is counted in its basin.
CAPTURE_DISTANCE = 1e-4
#: Cycles between comparisons of a non-periodic start with the known non-periodic attractors.
PROBE_CYCLES = 64
#: Cycles of a probe's statistics.
PROBE_WINDOW = 32
_CHECKPOINTS = np.array(CHECKPOINTS, dtype=np.int64)


def start_states(model: DamperModel, excitation: Excitation, count: int) -> list:
    """``count`` starts ``(x, v, y, w)`` (m, m/s) at forcing phase 0, deterministic.

    The linear start (:func:`._forced_steady.linear_start`), rest, then the main mass on its
    linear steady state with the impact mass spread evenly across the cavity
    (``z = d/2 (2j + 1)/k - d/2``, j < k) moving alternately towards wall +1 and wall -1 at
    ``ω d/2`` relative to the main mass.
    """
    lin = linear_start(model, excitation)
    out = [lin, (0.0, 0.0, 0.0, 0.0)][:count]
    k = count - len(out)
    hg = 0.5 * model.gap
    u0 = excitation.omega * hg
    for j in range(k):
        z = 0.95 * hg * ((2 * j + 1) / k - 1.0)
        u = u0 if j % 2 == 0 else -u0
        out.append((lin[0], lin[1], lin[0] + z, lin[1] + u))
    return out


@dataclass
class _Outcome:
    steady: SteadyState | None = None
    known: int = -1
    unstable: list = field(default_factory=list)
    cycles: int = 0  # cycles of a start captured by a known attractor (not in any steady state)


def _period_guess(pts, k):
    """Return distances ``d_n`` (scaled) of point k to point k - n, n = 1..8 (inf where k < n)."""
    d = np.full(MAX_PERIOD + 1, np.inf)
    m = min(MAX_PERIOD, k)
    if m > 0:  # rows k - 1, ..., k - m at once
        d[1:m + 1] = np.max(np.abs(pts[k] - pts[k - m:k][::-1]), axis=1)
    return d


class _Settler:
    """One start run to its attractor (:func:`settle`): the run, its section points and the shootings."""

    def __init__(self, model, excitation, settings, start, known):
        self.model, self.excitation, self.settings = model, excitation, settings
        self.scale = section_scale(model, excitation)
        self.pmap = PoincareMap(model, excitation, settings)
        self.out = _Outcome()
        self.total = 0
        # the direct run: the transient at ``transient_rtol``, when set (shooting and measurements keep ``rtol``)
        loose = settings if settings.transient_rtol is None else replace(settings, rtol=settings.transient_rtol)
        self.run = _Runner(model, excitation, loose, start, rows=settings.max_impacts_per_cycle)
        n = settings.max_cycles + 1
        self.pts = np.empty((n, 4))
        self.pts[0] = self.run.section() / self.scale
        self.xhi, self.xlo, self.ipc = np.empty(n), np.empty(n), np.empty(n)
        self.periodic_known = [(i, a) for i, a in enumerate(known) if a.period and a.stable]
        self.chaotic_known = [(i, a) for i, a in enumerate(known) if not a.period and a.success]
        self.landed = None  # the known stable orbit a shooting converged to
        self.acc = np.empty(5)  # the direct run's accumulators of one cycle
        orbits = [a.poincare / self.scale for _, a in self.periodic_known]
        self.orbits = np.concatenate(orbits) if orbits else np.empty((0, 4))
        self.orbit_cols = np.concatenate([np.full(len(a.poincare), 2 if a.impacts_per_cycle == 0 else 4)
                                          for _, a in self.periodic_known]).astype(np.int64) if orbits else \
            np.empty(0, dtype=np.int64)

    def refine(self, point, n, k):
        """Shoot a period-``n`` orbit from ``point`` (cycle ``k``); its measured steady state, or None.

        With ``settings.reuse_known``, None also when the orbit is a known stable one (``landed`` then
        holds its index): it is neither measured nor its multipliers taken again.
        """
        s = self.settings
        while True:
            before = self.pmap.cycles
            shot = shoot(self.pmap, point, n, s.tolerance, self.scale, rtol=s.rtol, multipliers=not s.reuse_known)
            self.total += self.pmap.cycles - before
            if not shot.converged:
                return None
            if s.reuse_known:  # a known orbit ends the start; a new one gets its multipliers
                self.landed = self.on_known(shot.point, n)
                if self.landed is not None:
                    return None
                before = self.pmap.cycles
                shot = with_multipliers(self.pmap, shot, n, self.scale, rtol=s.rtol)
                self.total += self.pmap.cycles - before
            steady, smaller = measure_periodic(self.model, self.excitation, s, shot.point, n, shot, k, self.total)
            if steady is not None:
                self.total = steady.cycles_integrated
                return steady
            n = smaller

    def captured(self, i, *, add_run=True) -> _Outcome:
        """The outcome of a start captured by known attractor ``i``."""
        self.out.known, self.out.cycles = i, self.total + (self.run.total if add_run else 0)
        return self.out

    def on_known(self, point, n):
        """Index of the known stable periodic orbit, of a period dividing ``n``, through ``point`` (m, m/s), or None.

        The criterion of :func:`._measure.same_motion`: a point of the orbit within
        :data:`._measure.SAME_ORBIT` times 100 (scaled). A converged shooting landing there has found
        that orbit again (its multiples of the period included, which the measurement would reduce).
        """
        for i, a in self.periodic_known:
            if n % a.period:
                continue
            cols = slice(0, 2) if a.impacts_per_cycle == 0 else slice(0, 4)
            d = np.abs(a.poincare[:, cols] - point[cols]) / self.scale[cols]
            if np.min(np.max(d, axis=1)) < SAME_ORBIT * 100:
                return i
        return None

    def stable(self, steady, *, add_run=True) -> _Outcome:
        """The outcome of a start that reached the stable orbit ``steady``."""
        extra = self.run.total if add_run else 0
        self.out.steady = replace(steady, cycles_integrated=steady.cycles_integrated + extra) if extra else steady
        return self.out

    def periodic_capture(self, k):
        """Index of the known stable periodic attractor whose section point ``k`` lies on, or None."""
        for i, a in self.periodic_known:
            cols = slice(0, 2) if a.impacts_per_cycle == 0 else slice(0, 4)
            d = np.abs(a.poincare[:, cols] / self.scale[cols] - self.pts[k, cols])
            if np.min(np.max(d, axis=1)) < CAPTURE_DISTANCE:
                return i
        return None

    def chaotic_capture(self, k):
        """Index of the known non-periodic attractor whose statistics the last window matches, or None."""
        if not self.chaotic_known or k < PROBE_CYCLES or k % PROBE_CYCLES:
            return None
        w = slice(k - PROBE_WINDOW + 1, k + 1)
        hi = self.xhi[w].reshape(-1, BATCH_CYCLES).max(axis=1)
        lo = self.xlo[w].reshape(-1, BATCH_CYCLES).min(axis=1)
        amp = float(np.mean(0.5 * (hi - lo)))
        rate = float(np.mean(self.ipc[w]))
        for i, a in self.chaotic_known:
            if _stats_agree(a, amp, a.amplitude_std_err * math.sqrt(WINDOW_BATCHES) / math.sqrt(hi.size), rate):
                return i
        return None

    def seed(self, period) -> bool:
        """Shoot a period-``period`` orbit from the start (a continued seed); True when that ends the start."""
        steady = self.refine(self.run.section(), period, 0)
        if self.landed is not None:
            self.captured(self.landed)
            return True
        if steady is not None and steady.stable:
            self.stable(steady, add_run=False)
            return True
        if steady is not None:
            self.out.unstable.append(steady)
        return False

    def advance(self, k0, next_try):
        """Run cycles ``k0``, ... until one may need the search (:func:`._forced_direct.run_cycles`).

        Returns ``(k, failed)``: the cycle reached and a failed outcome when the solver stopped there.
        Newmark runs one cycle at a time.
        """
        run, s = self.run, self.settings
        if run.solver == "newmark":
            return k0, self.step(k0)
        args = (run.prm, run.fc, run.fcs, run.st, run.k, run.T, run.e, run.rtol, run.imp, 0, run.cap, self.acc, True,
                MODE_SEARCH, k0, s.max_cycles, self.scale, self.pts, self.xhi, self.xlo, self.ipc, self.orbits,
                self.orbit_cols, CAPTURE_DISTANCE, TRIGGER, _CHECKPOINTS, float(s.checkpoint_return), next_try,
                PROBE_CYCLES if self.chaotic_known else 0)
        compile_once(run.solver, args)
        k, status, _ = run_cycles(*args)
        run.k += k - k0 + 1
        run.total += k - k0 + 1
        if status != STATUS_OK:
            self.out.steady = _failed(self.model, self.excitation, s, k, status, run.state(), self.total + run.total)
            return k, self.out
        self.section = run.section()
        return k, None

    def step(self, k):
        """Integrate cycle ``k``; a failed outcome when the solver stopped, else None."""
        acc = np.array([0.0, 0.0, 0.0, -np.inf, np.inf])
        n_imp, status = self.run.cycle(0, acc, True)
        if status != STATUS_OK:
            self.out.steady = _failed(self.model, self.excitation, self.settings, k, status, self.run.state(),
                                      self.total + self.run.total)
            return self.out
        self.xhi[k], self.xlo[k] = acc[3], acc[4]
        self.ipc[k] = n_imp
        self.section = self.run.section()
        self.pts[k] = self.section / self.scale
        return None

    def finish(self) -> _Outcome:
        """After the last cycle: a last shooting, else the motion measured over a window."""
        s, k = self.settings, self.settings.max_cycles
        d = _period_guess(self.pts, k)
        for n in dict.fromkeys((int(np.argmin(d)), 1)):  # a last try at the best guess and at period 1
            steady = self.refine(self.run.section(), n, k)
            if self.landed is not None:
                return self.captured(self.landed)
            if steady is not None and steady.stable:
                return self.stable(steady)
        steady = measure_window(self.model, self.excitation, s, self.run.state(), k, self.total + self.run.total)
        if steady.success and steady.regime == "unresolved":  # a slow spiral onto an orbit: shoot from there
            self.total = steady.cycles_integrated
            x, v, y, w = steady.final_state
            last = _period_guess(steady.poincare / self.scale, len(steady.poincare) - 1)
            for n in dict.fromkeys((1, int(np.argmin(last)))):
                orbit = self.refine(np.array([x, v, y - x, w - v]), n, steady.cycles + steady.measured_cycles)
                if self.landed is not None:
                    return self.captured(self.landed, add_run=False)
                if orbit is not None and orbit.stable:
                    return self.stable(orbit, add_run=False)
        self.out.steady = steady
        return self.out


def settle(model, excitation, settings, start, *, known=(), seed_period=0) -> _Outcome:
    """Run one start to its attractor (module docstring); ``known`` attractors may capture it."""
    st = _Settler(model, excitation, settings, start, known)
    if seed_period and st.seed(seed_period):
        return st.out
    next_try, wait = 0, 8
    k = 0
    while k < settings.max_cycles:  # from one cycle that may need the search to the next
        k, failed = st.advance(k + 1, next_try)
        if failed is not None:
            return failed
        i = st.periodic_capture(k)
        if i is not None:
            return st.captured(i)
        d = _period_guess(st.pts, k)
        close = np.flatnonzero((d < TRIGGER) & (_period_guess(st.pts, k - 1) < TRIGGER))
        checkpoint = k in CHECKPOINTS and float(np.min(d)) < settings.checkpoint_return
        n = int(close[0]) if close.size else (int(np.argmin(d)) if checkpoint else 0)
        if n and k >= next_try:
            steady = st.refine(st.section, n, k)
            if st.landed is not None:
                return st.captured(st.landed)
            if steady is not None and steady.stable:
                return st.stable(steady)
            if steady is not None:
                st.out.unstable.append(steady)
            next_try = k + wait  # shooting failed or met a saddle: wait longer each time
            wait *= 2
        i = st.chaotic_capture(k)
        if i is not None:
            return st.captured(i)
    return st.finish()


@dataclass(frozen=True)
class FrequencyAttractors:
    """The distinct motions found at one frequency.

    Attributes
    ----------
    excitation : Excitation
    attractors : tuple of SteadyState
        Stable periodic orbits and non-periodic motions (and runs the solver stopped), in the
        order found.
    counts : tuple of int
        Starts (of ``starts``) that reached each attractor.
    starts : int
        Starts tried (seeds from the neighbouring frequencies not included).
    seeded : tuple of int
        Continued states (seeds) that reached each attractor.
    unstable : tuple of SteadyState
        Unstable periodic orbits met on the way (by shooting from a seed or a passing run).
    cpu_s : float
        CPU time of the process that ran this frequency, in s (all rounds).
    cycles_integrated : int
        Forcing cycles integrated for this frequency (every start and seed, shooting included).
    newton_iterations : int
        Newton steps of the shootings that converged.
    """

    excitation: Excitation
    attractors: tuple
    counts: tuple
    starts: int
    seeded: tuple
    unstable: tuple
    cpu_s: float = math.nan
    cycles_integrated: int = 0
    newton_iterations: int = 0

    @property
    def basin_fractions(self) -> np.ndarray:
        """Fraction of the starts that reached each attractor (0 for one found only by continuation)."""
        return np.array(self.counts, dtype=float) / max(self.starts, 1)


def _add(found, counts, seeded, steady, seed):
    for i, a in enumerate(found):
        if same_motion(a, steady):
            (seeded if seed else counts)[i] += 1
            return i
    found.append(steady)
    counts.append(0 if seed else 1)
    seeded.append(1 if seed else 0)
    return len(found) - 1


def attractors_at(model, excitation, settings, *, seeds=(), previous=None) -> FrequencyAttractors:
    """Run the starts of :func:`start_states` and ``seeds`` to their attractors at one frequency.

    ``seeds`` are ``(state, period)`` continued from neighbouring frequencies; distinct
    attractors are de-duplicated (:func:`same_motion`).

    ``previous`` (a :class:`FrequencyAttractors` of the same frequency) keeps what was found
    before: only the seeds are run then.
    """
    c0 = time.process_time()
    work = [0, 0]

    def tally(o):
        for r in ([o.steady] if o.steady is not None else []) + o.unstable:
            work[1] += r.newton_iterations
        work[0] += o.steady.cycles_integrated if o.steady is not None else o.cycles

    if previous is None:
        found, counts, seeded, unstable = [], [], [], []
        for start in start_states(model, excitation, settings.starts):
            o = settle(model, excitation, settings, start, known=tuple(found))
            tally(o)
            unstable.extend(o.unstable)
            if o.steady is None:
                counts[o.known] += 1
            else:
                _add(found, counts, seeded, o.steady, False)
        cpu0 = 0.0
    else:
        found, counts = list(previous.attractors), list(previous.counts)
        seeded, unstable = list(previous.seeded), list(previous.unstable)
        cpu0 = previous.cpu_s
        work = [previous.cycles_integrated, previous.newton_iterations]
    for state, period in seeds:
        o = settle(model, excitation, settings, state, known=tuple(found), seed_period=period)
        tally(o)
        unstable.extend(o.unstable)
        if o.steady is None:
            seeded[o.known] += 1
        else:
            _add(found, counts, seeded, o.steady, True)
    distinct = []
    for u in unstable:
        if not any(same_motion(u, v) for v in distinct):
            distinct.append(u)
    return FrequencyAttractors(excitation, tuple(found), tuple(counts), settings.starts, tuple(seeded),
                               tuple(distinct), cpu0 + time.process_time() - c0, work[0], work[1])


def steady_state(
    model: DamperModel,
    excitation: Excitation,
    *,
    initial=None,
    settings: SteadyStateOptions | None = None,
    **kwargs,
) -> SteadyState:
    """Run the forced damper from one start to its attractor and measure it.

    Parameters
    ----------
    model : DamperModel
        The damper (paper eq 15, Table 1).
    excitation : Excitation
        Harmonic force or base motion.
    initial : tuple, optional
        ``(x, v, y, w)`` at t = 0 in m and m/s (default: the linear start); a previous
        :attr:`SteadyState.final_state` continues a frequency sweep.
    settings : SteadyStateOptions, optional
        Or its fields as keywords: ``solver``, ``restitution``, ``tolerance`` (Newton residual, m
        and m/s), ``max_cycles``, ``rtol``, ``steps_per_cycle``, ``max_impacts_per_cycle``.

    Returns
    -------
    SteadyState
        A stable periodic orbit found by shooting, or a non-periodic motion measured over a
        window (module docstring), or a run the solver stopped (``success=False``).

    Notes
    -----
    Periodic motion of an impact oscillator with impacts of restitution e: Masri and Caughey
    (1966); the closed-form reference is :func:`acoustiviz.dynamics.periodic.masri_caughey`.
    """
    settings = check_settings(model, excitation, settings, **kwargs)
    state = _start(model, excitation, initial)
    o = settle(model, excitation, settings, state)
    return o.steady
