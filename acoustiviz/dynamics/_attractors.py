r"""The attractors of the forced damper at one frequency: several starts, shooting, honest non-periodic motion.

Each start is run cycle by cycle on the Poincaré section (forcing phase 0). Whenever the section
points return close to themselves after n cycles (scaled distance below :data:`TRIGGER` twice in
a row), and at a few checkpoints regardless, the orbit is refined by shooting
(:func:`._shooting.shoot`): Newton's method on ``P^n(s) = s``. A converged orbit is measured over
one period (amplitude, impacts, energy) with its Floquet multipliers; a stable one ends the
start, an unstable one (a saddle the run passed by) is kept aside and the run goes on.

A start that finds no periodic orbit within ``max_cycles`` is measured over a window of
:data:`._forced_steady.WINDOW_BATCHES` batches of :data:`._forced_steady.BATCH_CYCLES` cycles:
the amplitude is the mean of the batches' half peak-to-peak displacement with the standard error
of the batch means, and the largest Lyapunov exponent is estimated alongside by the
two-trajectory method through the impacts (a copy displaced by ``d0`` = 1e-7 in the scaled
section variables, advanced by the same solver and renormalised to ``d0`` every cycle; the mean
of ``log(d / d0)`` per second over each batch, the first batch left out while the displacement
aligns with the most expanding direction). The regime is

* ``chaotic`` when the exponent is positive beyond :data:`LYAPUNOV_SIGMAS` standard errors;
* ``quasi-periodic`` when it is zero within that error bar and the bar is tight
  (below :data:`QUASI_PERIODIC_BOUND` per forcing cycle);
* ``unresolved`` otherwise, the reason in ``message`` (a contracting motion with no period up to
  8 found, or an exponent that the window cannot tell from zero); before that verdict the end
  of the window is tried once more by shooting (a slow spiral onto an orbit whose section
  point lay inside a contact when the direct run stopped).

Starts after the first that meet a known attractor are counted in its basin without being
measured again: a stable periodic orbit when the section point comes within
:data:`CAPTURE_DISTANCE` (scaled) of one of its points; a non-periodic attractor when the
amplitude and impact rate of the last 32 cycles agree with its batch statistics within
:data:`LYAPUNOV_SIGMAS` batch standard deviations.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ._forced_steady import (
    BATCH_CYCLES,
    MAX_PERIOD,
    NONPERIODIC_CYCLES,
    WINDOW_BATCHES,
    Excitation,
    ForcedSettings,
    SteadyState,
    _Runner,
    _start,
    check_settings,
    linear_start,
)
from ._shooting import PoincareMap, section_scale, shoot
from ._status import LIMIT_CYCLE, STATUS_OK, status_message
from .model import DamperModel

__all__ = ["FrequencyAttractors", "start_states", "attractors_at", "steady_state", "same_motion"]

#: Scaled return distance below which (twice in a row) a period is tried by shooting.
TRIGGER = 1e-2
#: Cycles at which the best period guess is tried by shooting even without a close return.
CHECKPOINTS = (8, 32, 128, 512, 2048)
#: Scaled distance to a known stable periodic orbit within which a start is counted in its basin.
CAPTURE_DISTANCE = 1e-4
#: Scaled distance under which two periodic orbits are the same.
SAME_ORBIT = 1e-6
#: Standard errors (batch means) beyond which an exponent or a statistic differs.
LYAPUNOV_SIGMAS = 3.0
#: A Lyapunov exponent zero within an error bar tighter than this (per forcing cycle) is quasi-periodic.
QUASI_PERIODIC_BOUND = 0.01
#: Initial separation of the two trajectories of the Lyapunov estimate (scaled section variables).
LYAPUNOV_D0 = 1e-7
#: Cycles between comparisons of a non-periodic start with the known non-periodic attractors.
PROBE_CYCLES = 64
#: Cycles of a probe's statistics.
PROBE_WINDOW = 32
#: Windows measured at most while the batch amplitudes drift.
WINDOW_TRIES = 3
#: Standard errors between the halves of a window beyond which its amplitudes drift (a false
#: alarm, about 5 % of stationary windows, costs one more window).
DRIFT_SIGMAS = 2.0


def _state(s):
    """``(x, v, y, w)`` from a section point ``(x, v, z, u)``."""
    x, v, z, u = (float(q) for q in s)
    return x, v, x + z, v + u


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


def _settings_dict(settings):
    return {"tolerance": settings.tolerance, "rtol": settings.rtol, "max_cycles": settings.max_cycles,
            "starts": settings.starts, "solver": settings.solver, "restitution": settings.restitution}


def _failed(model, excitation, settings, cycles, status, state, total):
    nan = math.nan
    return SteadyState(
        excitation=excitation, model=model, solver=settings.solver, regime="unresolved", converged=False,
        period=0, cycles=int(cycles), amplitude=nan, x_max=nan, x_min=nan, impacts_per_cycle=nan,
        impact_times=np.empty(0), impact_phases=np.empty(0), impact_speeds=np.empty(0),
        impact_walls=np.empty(0), impact_peak_forces=np.empty(0), impact_durations=np.empty(0),
        work_input=nan, dissipated_main=nan, dissipated_contact=nan, energy_change=nan,
        poincare=np.empty((0, 4)), final_state=tuple(float(q) for q in state),
        message=f"the solver stopped: {status_message(status, LIMIT_CYCLE)} after {cycles} cycles",
        success=False, settings=_settings_dict(settings), measured_cycles=0, stable=False,
        cycles_integrated=int(total))


def _impact_fields(imp, omega, offset):
    t = imp[:, 0] + offset
    return {"impact_times": t, "impact_phases": np.mod(omega * imp[:, 0], 2.0 * math.pi),
            "impact_speeds": imp[:, 2].copy(), "impact_walls": imp[:, 1].copy(),
            "impact_peak_forces": imp[:, 5].copy(), "impact_durations": imp[:, 4].copy()}


def measure_periodic(model, excitation, settings, point, period, shot, cycles, total):
    """A :class:`SteadyState` of the periodic orbit through ``point`` (one period measured).

    Returns ``(steady, smaller)``: ``smaller`` > 0 when the orbit repeats after fewer cycles
    (a divisor of ``period``), to be shot again with that period.
    """
    run = _Runner(model, excitation, settings, _state(point), rows=settings.max_impacts_per_cycle * period)
    run.cap = run.imp.shape[0] - 1
    acc = np.array([0.0, 0.0, 0.0, -np.inf, np.inf])
    e0 = run.energy()
    pts = [run.section()]
    n = 0
    status = STATUS_OK
    for _ in range(period):
        n, status = run.cycle(n, acc, True)
        pts.append(run.section())
        if status != STATUS_OK:
            return _failed(model, excitation, settings, cycles, status, run.state(), total + run.total), 0
    pts = np.array(pts)
    scale = section_scale(model, excitation)
    for j in range(1, period):
        if period % j == 0 and np.max(np.abs(pts[j] - pts[0]) / scale) < SAME_ORBIT:
            return None, j
    imp = run.imp[:n].copy()
    spare = run.imp[-1]
    if n and math.isnan(imp[-1, 3]) and spare[4] > 0:  # a contact open across phase 0: one impact, joined
        imp[-1, 3] = spare[3]
        imp[-1, 4] += spare[4]
        imp[-1, 5] = max(imp[-1, 5], spare[5])
        imp[-1, 6] += spare[6]
        imp[-1, 7] += spare[7]
    amp = 0.5 * (acc[3] - acc[4])
    mu = float(np.max(np.abs(shot.multipliers))) if shot.multipliers.size else math.nan
    msg = (f"period-{period} orbit by shooting after {cycles} direct cycles: Newton residual "
           f"{shot.residual:.2e} (tolerance {settings.tolerance:g} m, m/s) in {shot.iterations} steps; "
           f"largest Floquet multiplier modulus {mu:.6f}")
    steady = SteadyState(
        excitation=excitation, model=model, solver=settings.solver, regime=f"periodic-{period}",
        converged=bool(shot.residual < settings.tolerance), period=int(period), cycles=int(cycles),
        amplitude=float(amp), x_max=float(acc[3]), x_min=float(acc[4]), impacts_per_cycle=n / period,
        **_impact_fields(imp, excitation.omega, cycles * excitation.period),
        work_input=float(acc[0]), dissipated_main=float(acc[1]), dissipated_contact=float(acc[2]),
        energy_change=float(run.energy() - e0), poincare=pts[:-1].copy(),
        final_state=tuple(float(q) for q in _state(pts[0])), message=msg, success=True,
        settings=_settings_dict(settings), measured_cycles=int(period), amplitude_std_err=0.0,
        residual=float(shot.residual), floquet=shot.multipliers, stable=shot.stable,
        newton_iterations=int(shot.iterations), cycles_integrated=int(total + run.total))
    return steady, 0


def _classify(lam, err, period):
    """Regime and reason of a non-periodic motion from its largest Lyapunov exponent (1/s)."""
    if not math.isfinite(lam):
        return "unresolved", "the Lyapunov estimate failed"
    lam, err = float(lam), float(err)
    k = LYAPUNOV_SIGMAS
    if lam - k * err > 0:
        return "chaotic", f"largest Lyapunov exponent {lam:.3g} ± {err:.2g} 1/s, positive beyond {k:g} standard errors"
    if lam + k * err < 0:
        return "unresolved", (f"contracting (largest Lyapunov exponent {lam:.3g} ± {err:.2g} 1/s) yet no periodic "
                              f"orbit of period <= {MAX_PERIOD} converged: a longer period or a slower transient")
    if k * err * period < QUASI_PERIODIC_BOUND:
        return "quasi-periodic", (f"no periodic orbit of period <= {MAX_PERIOD}; largest Lyapunov exponent "
                                  f"{lam:.2g} ± {err:.2g} 1/s, zero within {k:g} standard errors")
    return "unresolved", (f"largest Lyapunov exponent {lam:.3g} ± {err:.2g} 1/s cannot be told from zero "
                          f"over {NONPERIODIC_CYCLES} cycles")


def _drifting(amps) -> bool:
    """True when the two halves of the batch amplitudes differ beyond :data:`DRIFT_SIGMAS` standard errors."""
    h = amps.size // 2
    sd = float(np.std(amps, ddof=1))
    return abs(float(np.mean(amps[:h])) - float(np.mean(amps[h:]))) > DRIFT_SIGMAS * sd * math.sqrt(2.0 / h)


def measure_window(model, excitation, settings, state, cycles, total):
    """A :class:`SteadyState` of a non-periodic motion from ``state``: batch statistics and Lyapunov exponent.

    A window whose batch amplitudes drift (the halves differ beyond :data:`DRIFT_SIGMAS`
    standard errors: still a transient) is followed by another, up to :data:`WINDOW_TRIES`;
    a motion that still drifts is ``unresolved``.
    """
    tries = 0
    while True:
        steady, amps = _window(model, excitation, settings, state, cycles, total)
        if not steady.success or not _drifting(amps):
            break
        tries += 1
        if tries == WINDOW_TRIES:
            return replace(steady, regime="unresolved", message=(
                f"unresolved: the batch amplitudes still drift after {cycles + steady.measured_cycles} cycles "
                f"(a transient slower than the cycle limit); last window: {steady.message}"))
        state, cycles, total = steady.final_state, cycles + steady.measured_cycles, steady.cycles_integrated
    if tries:
        steady = replace(steady, message=f"{steady.message} (after {tries} drifting windows)")
    return steady


def _window(model, excitation, settings, state, cycles, total):
    """One window of :func:`measure_window`: ``(SteadyState, batch amplitudes)``."""
    nb, bc = WINDOW_BATCHES, BATCH_CYCLES
    run = _Runner(model, excitation, settings, state, rows=settings.max_impacts_per_cycle * nb * bc)
    run.cap = settings.max_impacts_per_cycle
    pert = _Runner(model, excitation, settings, state, rows=settings.max_impacts_per_cycle)
    scale = section_scale(model, excitation)
    direction = np.full(4, 0.5)
    e0 = run.energy()
    tot = np.zeros(3)
    amps, xmax, xmin, lams, pts = [], -math.inf, math.inf, [], []
    n = 0
    dummy = np.zeros(5)
    T = excitation.period
    for b in range(nb):
        acc = np.array([0.0, 0.0, 0.0, -np.inf, np.inf])
        logsum = 0.0
        for _ in range(bc):
            ref = run.section()
            pert.set_state(_state(ref + LYAPUNOV_D0 * direction * scale), k=run.k)
            n, status = run.cycle(n, acc, True)
            if status == STATUS_OK:
                _, status = pert.cycle(0, dummy, False)
            if status != STATUS_OK:
                return _failed(model, excitation, settings, cycles + run.k, status, run.state(),
                               total + run.total + pert.total), None
            pts.append(run.section())
            diff = (pert.section() - pts[-1]) / scale
            d = math.hypot(*diff)  # not BLAS: its sum's order depends on the processor
            if d > 0.0:
                logsum += math.log(d / LYAPUNOV_D0)
                direction = diff / d
        amps.append(0.5 * (acc[3] - acc[4]))
        xmax, xmin = max(xmax, acc[3]), min(xmin, acc[4])
        tot += acc[:3]
        if b > 0:
            lams.append(logsum / (bc * T))
    amps, lams = np.array(amps), np.array(lams)
    amp = float(np.mean(amps))
    amp_err = float(np.std(amps, ddof=1) / math.sqrt(nb))
    lam = float(np.mean(lams))
    lam_err = float(np.std(lams, ddof=1) / math.sqrt(lams.size))
    regime, why = _classify(lam, lam_err, T)
    imp = run.imp[:n].copy()
    m = nb * bc
    msg = (f"{regime}: {why}; no periodic orbit found in {cycles} direct cycles; amplitude "
           f"{amp:.6g} ± {amp_err:.2g} m over {nb} batches of {bc} cycles")
    return SteadyState(
        excitation=excitation, model=model, solver=settings.solver, regime=regime, converged=False, period=0,
        cycles=int(cycles), amplitude=amp, x_max=float(xmax), x_min=float(xmin), impacts_per_cycle=n / m,
        **_impact_fields(imp, excitation.omega, cycles * T),
        work_input=float(tot[0]), dissipated_main=float(tot[1]), dissipated_contact=float(tot[2]),
        energy_change=float(run.energy() - e0), poincare=np.array(pts), final_state=tuple(run.state()),
        message=msg, success=True, settings=_settings_dict(settings), measured_cycles=m,
        amplitude_std_err=amp_err, residual=math.nan, stable=True,
        cycles_integrated=int(total + run.total + pert.total), lyapunov=lam, lyapunov_std_err=lam_err), amps


def same_motion(a: SteadyState, b: SteadyState) -> bool:
    """True when ``a`` and ``b`` are the same motion (orbit points, or statistics within their errors)."""
    if not (a.success and b.success):
        return False
    if a.period or b.period:
        if a.period != b.period:
            return False
        scale = section_scale(a.model, a.excitation)
        cols = slice(0, 2) if a.impacts_per_cycle == 0 and b.impacts_per_cycle == 0 else slice(0, 4)
        # without impacts the impact mass floats anywhere: the main mass's motion decides
        d = np.abs(a.poincare[:, None, cols] - b.poincare[None, :, cols]) / scale[cols]
        return bool(np.min(np.max(d, axis=2)) < SAME_ORBIT * 100)
    return _stats_agree(a, b.amplitude, b.amplitude_std_err, b.impacts_per_cycle)


def _stats_agree(known: SteadyState, amp: float, amp_sd: float, ipc: float) -> bool:
    """True when a non-periodic ``known`` attractor and another motion agree.

    The other motion has a mean amplitude ``amp`` (standard error ``amp_sd``) and ``ipc``
    impacts per cycle; they agree within :data:`LYAPUNOV_SIGMAS` errors.
    """
    sd = math.hypot(known.amplitude_std_err, amp_sd)
    sd = max(sd, 1e-3 * known.amplitude)
    return (abs(amp - known.amplitude) <= LYAPUNOV_SIGMAS * sd
            and abs(ipc - known.impacts_per_cycle) <= 0.1 * max(known.impacts_per_cycle, 1.0))


@dataclass
class _Outcome:
    steady: SteadyState | None = None
    known: int = -1
    unstable: list = field(default_factory=list)
    cycles: int = 0  # cycles of a start captured by a known attractor (not in any steady state)


def _period_guess(pts, k):
    """Return distances ``d_n`` (scaled) of point k to point k - n, n = 1..8 (inf where k < n)."""
    d = np.full(MAX_PERIOD + 1, np.inf)
    for n in range(1, min(MAX_PERIOD, k) + 1):
        d[n] = float(np.max(np.abs(pts[k] - pts[k - n])))
    return d


class _Settler:
    """One start run to its attractor (:func:`settle`): the run, its section points and the shootings."""

    def __init__(self, model, excitation, settings, start, known):
        self.model, self.excitation, self.settings = model, excitation, settings
        self.scale = section_scale(model, excitation)
        self.pmap = PoincareMap(model, excitation, settings)
        self.out = _Outcome()
        self.total = 0
        self.run = _Runner(model, excitation, settings, start, rows=settings.max_impacts_per_cycle)
        n = settings.max_cycles + 1
        self.pts = np.empty((n, 4))
        self.pts[0] = self.run.section() / self.scale
        self.xhi, self.xlo, self.ipc = np.empty(n), np.empty(n), np.empty(n)
        self.periodic_known = [(i, a) for i, a in enumerate(known) if a.period and a.stable]
        self.chaotic_known = [(i, a) for i, a in enumerate(known) if not a.period and a.success]

    def refine(self, point, n, k):
        """Shoot a period-``n`` orbit from ``point`` (cycle ``k``); its measured steady state, or None."""
        s = self.settings
        while True:
            before = self.pmap.cycles
            shot = shoot(self.pmap, point, n, s.tolerance, self.scale, rtol=s.rtol)
            self.total += self.pmap.cycles - before
            if not shot.converged:
                return None
            steady, smaller = measure_periodic(self.model, self.excitation, s, shot.point, n, shot, k, self.total)
            if steady is not None:
                self.total = steady.cycles_integrated
                return steady
            n = smaller

    def captured(self, i) -> _Outcome:
        """The outcome of a start captured by known attractor ``i``."""
        self.out.known, self.out.cycles = i, self.total + self.run.total
        return self.out

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
            if steady is not None and steady.stable:
                return self.stable(steady)
        steady = measure_window(self.model, self.excitation, s, self.run.state(), k, self.total + self.run.total)
        if steady.success and steady.regime == "unresolved":  # a slow spiral onto an orbit: shoot from there
            self.total = steady.cycles_integrated
            x, v, y, w = steady.final_state
            last = _period_guess(steady.poincare / self.scale, len(steady.poincare) - 1)
            for n in dict.fromkeys((1, int(np.argmin(last)))):
                orbit = self.refine(np.array([x, v, y - x, w - v]), n, steady.cycles + steady.measured_cycles)
                if orbit is not None and orbit.stable:
                    return self.stable(orbit, add_run=False)
        self.out.steady = steady
        return self.out


def settle(model, excitation, settings, start, *, known=(), seed_period=0) -> _Outcome:
    """Run one start to its attractor (module docstring); ``known`` attractors may capture it."""
    st = _Settler(model, excitation, settings, start, known)
    if seed_period:
        steady = st.refine(st.run.section(), seed_period, 0)
        if steady is not None and steady.stable:
            return st.stable(steady, add_run=False)
        if steady is not None:
            st.out.unstable.append(steady)
    next_try, wait = 0, 8
    prev = np.full(MAX_PERIOD + 1, np.inf)
    for k in range(1, settings.max_cycles + 1):
        failed = st.step(k)
        if failed is not None:
            return failed
        i = st.periodic_capture(k)
        if i is not None:
            return st.captured(i)
        d = _period_guess(st.pts, k)
        close = np.flatnonzero((d < TRIGGER) & (prev < TRIGGER))
        prev = d
        n = int(close[0]) if close.size else (int(np.argmin(d)) if k in CHECKPOINTS else 0)
        if n and k >= next_try:
            steady = st.refine(st.section, n, k)
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
    settings: ForcedSettings | None = None,
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
    settings : ForcedSettings, optional
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
