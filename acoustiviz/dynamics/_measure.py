r"""A motion of the forced damper measured: a periodic orbit over its period, anything else over a window.

A converged periodic orbit (:func:`measure_periodic`) is measured over one period: amplitude,
impacts, energy, with its Floquet multipliers. A motion without a period (:func:`measure_window`)
is measured over :data:`._forced_steady.WINDOW_BATCHES` batches of
:data:`._forced_steady.BATCH_CYCLES` cycles: the amplitude is the mean of the batches' half
peak-to-peak displacement with the standard error of the batch means, and the largest Lyapunov
exponent is estimated alongside by the two-trajectory method through the impacts (a copy
displaced by ``d0`` = :data:`LYAPUNOV_D0` in the scaled section variables, advanced by the same
solver and renormalised to ``d0`` every cycle; the mean of ``log(d / d0)`` per second over each
batch, the first batch left out while the displacement aligns with the most expanding
direction). The regime follows from the exponent and its error (:func:`_classify`; see
:mod:`._attractors`). :func:`same_motion` tells whether two measured motions are one attractor.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ._forced_steady import (
    BATCH_CYCLES,
    MAX_PERIOD,
    NONPERIODIC_CYCLES,
    WINDOW_BATCHES,
    SteadyState,
    _Runner,
    section_of,
)
from ._shooting import section_scale
from ._status import LIMIT_CYCLE, STATUS_OK, status_message

#: Scaled distance under which two periodic orbits are the same.
SAME_ORBIT = 1e-6
#: Standard errors (batch means) beyond which an exponent or a statistic differs.
LYAPUNOV_SIGMAS = 3.0
#: A Lyapunov exponent zero within an error bar tighter than this (per forcing cycle) is quasi-periodic.
QUASI_PERIODIC_BOUND = 0.01
#: Initial separation of the two trajectories of the Lyapunov estimate (scaled section variables).
LYAPUNOV_D0 = 1e-7
#: Windows measured at most while the batch amplitudes drift.
WINDOW_TRIES = 3
#: Standard errors between the halves of a window beyond which its amplitudes drift (a false
#: alarm, about 5 % of stationary windows, costs one more window).
DRIFT_SIGMAS = 2.0


def _state(s):
    """``(x, v, y, w)`` from a section point ``(x, v, z, u)``."""
    x, v, z, u = (float(q) for q in s)
    return x, v, x + z, v + u


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
    start = run.section()
    states = np.empty((period, 4))
    n, status, _ = run.cycles(period, 0, acc, True, states)  # the period in one compiled call
    if status != STATUS_OK:
        return _failed(model, excitation, settings, cycles, status, run.state(), total + run.total), 0
    pts = np.array([start] + [section_of(q) for q in states])
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
    T = excitation.period
    states = np.empty((bc, 4))
    for b in range(nb):
        acc = np.array([0.0, 0.0, 0.0, -np.inf, np.inf])
        k0, total0, ref = run.k, run.total, run.section()
        n, status, done = run.cycles(bc, n, acc, True, states)  # the batch in one compiled call
        ok = done if status == STATUS_OK else done - 1  # the run's cycles the twin follows
        logsum, direction, j, twin = _twin(pert, ref, states[:ok], direction, scale, k0)
        if j < done:  # the twin stopped at cycle j, or the run at cycle done - 1 (then j == ok)
            return _failed(model, excitation, settings, cycles + k0 + j + 1, twin if j < ok else status,
                           states[j], total + total0 + j + 1 + pert.total), None
        pts.extend(section_of(q) for q in states)
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


def _twin(pert, ref, states, direction, scale, k0):
    """The Lyapunov twin of :func:`_window` along the states ``(x, v, y, w)`` a run reached after its cycles.

    Before each cycle ``j`` (cycle ``k0 + j`` of the run) the twin starts from the run's section point
    (``ref``, then the one reached), displaced by :data:`LYAPUNOV_D0` along ``direction`` (scaled), and
    runs that cycle. Returns ``(sum of log(d / d0), direction, j, status)``: ``j`` the cycles the twin
    completed (``len(states)`` unless its solver stopped at cycle ``j``, with that ``status``).
    """
    logsum = 0.0
    dummy = np.zeros(5)
    for j, q in enumerate(states):
        pert.set_state(_state(ref + LYAPUNOV_D0 * direction * scale), k=k0 + j)
        _, status = pert.cycle(0, dummy, False)
        if status != STATUS_OK:
            return logsum, direction, j, status
        ref = section_of(q)
        diff = (pert.section() - ref) / scale
        d = math.hypot(*diff)  # not BLAS: its sum's order depends on the processor
        if d > 0.0:
            logsum += math.log(d / LYAPUNOV_D0)
            direction = diff / d
    return logsum, direction, len(states), STATUS_OK


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
