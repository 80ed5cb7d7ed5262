"""Frequency response of the forced impact damper: every attractor per frequency, and sweeps with continuation.

:func:`attractor_response` looks for every attractor at each frequency
(:func:`._attractors.attractors_at`: several starts, each run to its attractor and refined by
shooting) and then continues the attractors found along the frequency axis: the states of the
attractors of a frequency are the seeds of its neighbours (the higher one for ``sweep="up"``, the
lower one for ``"down"``, both for ``"both"``, none for ``"independent"``), which is what a
slowly varied machine speed does; rounds are repeated while a seed finds an attractor that was
not known, so a branch is followed as far as it exists. The frequencies of a round are
independent and go to an executor when one is given (any :class:`concurrent.futures.Executor`:
a local process pool, a Dask executor).

:func:`frequency_response` is the single-start sweep: each frequency from the last state of the
previous one (or the linear start), one attractor per frequency.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice
from ..constants import FREQUENCY_SWEEPS
from ._attractors import attractors_at, steady_state
from ._forced_steady import Excitation, SteadyStateOptions, check_settings
from .model import DamperModel

__all__ = ["SWEEPS", "AttractorResponse", "FrequencyResponse", "attractor_response", "frequency_response",
           "describe", "HYSTERESIS_TOLERANCE"]

#: Sweep directions.
SWEEPS = FREQUENCY_SWEEPS
#: Relative amplitude difference between the two sweep directions flagged as hysteresis.
HYSTERESIS_TOLERANCE = 1e-3


def _run_one(args):
    """One steady state (picklable for process pools)."""
    model, excitation, settings, initial = args
    return steady_state(model, excitation, initial=initial, settings=settings)


def _run_attractors(args):
    """The attractors of one frequency (picklable for process pools)."""
    model, excitation, settings, seeds, previous = args
    return attractors_at(model, excitation, settings, seeds=seeds, previous=previous)


@dataclass(frozen=True)
class FrequencyResponse:
    """Steady states over a list of forcing frequencies.

    Attributes
    ----------
    frequencies : ndarray
        Forcing frequencies in Hz, increasing.
    primary : tuple of SteadyState
        The upward sweep (``sweep`` "up", "both"), the downward one ("down") or the independent
        runs, in increasing frequency.
    down : tuple of SteadyState or None
        The downward sweep when ``sweep="both"``, in increasing frequency.
    sweep : str
    """

    frequencies: np.ndarray
    primary: tuple
    down: tuple | None
    sweep: str

    @property
    def amplitude(self) -> np.ndarray:
        """Main-mass amplitude with the damper (primary sweep) in m."""
        return np.array([r.amplitude for r in self.primary])

    @property
    def amplitude_without_damper(self) -> np.ndarray:
        """Linear steady amplitude of the main mass alone in m."""
        return np.array([r.amplitude_without_damper for r in self.primary])

    @property
    def reduction_db(self) -> np.ndarray:
        """``20 log10(without / with)`` in dB (primary sweep)."""
        return np.array([r.reduction_db for r in self.primary])

    @property
    def regime_change(self) -> np.ndarray:
        """True where the regime differs from the previous frequency's (primary sweep)."""
        reg = [r.regime for r in self.primary]
        return np.array([False] + [a != b for a, b in zip(reg[1:], reg[:-1], strict=True)])

    @property
    def hysteresis(self) -> np.ndarray:
        """True where the up and down sweeps end on different motions.

        Different regimes, or both periodic with amplitudes more than 0.1 % apart. Two
        non-periodic motions are not compared (their measured amplitudes differ anyway).
        """
        if self.down is None:
            return np.zeros(len(self.primary), dtype=bool)
        out = []
        for a, b in zip(self.primary, self.down, strict=True):
            scale = max(abs(a.amplitude), abs(b.amplitude), 1e-300)
            differ = abs(a.amplitude - b.amplitude) > HYSTERESIS_TOLERANCE * scale
            out.append(a.regime != b.regime or (a.converged and b.converged and differ))
        return np.array(out)

    def bifurcation_points(self, which: str = "primary") -> tuple[np.ndarray, np.ndarray]:
        """Poincaré displacements for a bifurcation diagram: ``(frequency Hz, x m)`` pairs.

        The distinct section points of each measured motion (n for period-n, up to 32 for
        non-periodic motion); failed runs are left out.
        """
        runs = self.primary if which == "primary" else self.down
        if runs is None:
            raise ParameterError("which", "no downward sweep in this response")
        fs, xs = [], []
        for f, r in zip(self.frequencies, runs, strict=True):
            if not r.success:  # a failed run has no measured motion
                continue
            pts = r.poincare[-(r.period if r.period else len(r.poincare)):, 0]
            fs.append(np.full(pts.size, f))
            xs.append(pts)
        return np.concatenate(fs), np.concatenate(xs)


def frequency_response(
    model: DamperModel,
    frequencies,
    amplitude: float,
    *,
    kind: str = "force",
    sweep: str = "up",
    executor=None,
    **kwargs,
) -> FrequencyResponse:
    """Steady-state response of the forced damper over ``frequencies``.

    Parameters
    ----------
    model : DamperModel
        The damper (paper eq 15).
    frequencies : array_like
        Forcing frequencies in Hz (> 0; sorted here, duplicates refused).
    amplitude : float
        Force amplitude in N (``kind="force"``) or base amplitude in m (``kind="base"``).
    kind : {"force", "base"}
    sweep : {"up", "down", "both", "independent"}
        Continuation direction(s), or independent runs from the linear start (module docstring).
    executor : concurrent.futures.Executor, optional
        Runs the independent frequencies in parallel (``sweep="independent"`` only).
    **kwargs
        Settings of :func:`._attractors.steady_state` (solver, restitution, tolerance, max_cycles, rtol).

    Returns
    -------
    FrequencyResponse
    """
    check_choice("sweep", sweep, SWEEPS)
    f = _frequencies(frequencies)
    if executor is not None and sweep != "independent":
        raise ParameterError("executor", "runs in parallel only with sweep='independent' (no continuation)")
    excitations = [Excitation(float(fi), amplitude, kind) for fi in f]
    settings = check_settings(model, excitations[0], **kwargs)

    def chain(order):
        out, state = {}, None
        for i in order:
            r = steady_state(model, excitations[i], initial=state, settings=settings)
            out[i] = r
            state = r.final_state if r.success else None
        return tuple(out[i] for i in range(f.size))

    up = range(f.size)
    down = range(f.size - 1, -1, -1)
    if sweep == "independent":
        tasks = [(model, ex, settings, None) for ex in excitations]
        results = list(executor.map(_run_one, tasks)) if executor is not None else [_run_one(t) for t in tasks]
        return FrequencyResponse(f, tuple(results), None, sweep)
    if sweep == "down":
        return FrequencyResponse(f, chain(down), None, sweep)
    primary = chain(up)
    return FrequencyResponse(f, primary, chain(down) if sweep == "both" else None, sweep)


def _frequencies(frequencies) -> np.ndarray:
    try:
        f = np.sort(np.asarray(frequencies, dtype=float).ravel())
    except (TypeError, ValueError):
        raise ParameterError("frequencies", "expected numbers in Hz") from None
    if f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ParameterError("frequencies", "expected one or more finite frequencies > 0 Hz")
    if np.any(np.diff(f) == 0):
        raise ParameterError("frequencies", "duplicate frequencies")
    return f


@dataclass(frozen=True)
class AttractorResponse:
    """Every attractor found at each of a list of forcing frequencies.

    Attributes
    ----------
    frequencies : ndarray
        Forcing frequencies in Hz, increasing.
    per_frequency : tuple of FrequencyAttractors
        The attractors (with their basin fractions) and the unstable orbits met, per frequency.
    sweep : str
        Continuation of the attractors along the frequencies (module docstring).
    settings : SteadyStateOptions
    rounds : int
        Rounds of continuation run.
    """

    frequencies: np.ndarray
    per_frequency: tuple
    sweep: str
    settings: SteadyStateOptions
    rounds: int = 0

    def entries(self) -> list:
        """``(frequency index, attractor index, SteadyState, basin fraction)`` of every attractor."""
        out = []
        for i, fa in enumerate(self.per_frequency):
            fr = fa.basin_fractions
            for j, a in enumerate(fa.attractors):
                out.append((i, j, a, float(fr[j])))
        return out

    @property
    def unstable(self) -> list:
        """``(frequency index, SteadyState)`` of the unstable periodic orbits found."""
        return [(i, u) for i, fa in enumerate(self.per_frequency) for u in fa.unstable]

    @property
    def cycles_integrated(self) -> int:
        """Forcing cycles integrated in all (attractors and unstable orbits as recorded)."""
        return sum(a.cycles_integrated for _, _, a, _ in self.entries())

    def bifurcation_points(self, stable: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Poincaré displacements ``(frequency Hz, x m)`` of the attractors (``stable``) or unstable orbits.

        The n points of a period-n orbit, the window's points of non-periodic motion; runs the
        solver stopped are left out.
        """
        runs = ([(i, a) for i, _, a, _ in self.entries()] if stable else self.unstable)
        fs, xs = [np.empty(0)], [np.empty(0)]
        for i, r in runs:
            if r.success and r.poincare.size:
                fs.append(np.full(len(r.poincare), self.frequencies[i]))
                xs.append(r.poincare[:, 0])
        return np.concatenate(fs), np.concatenate(xs)


def _seed(a):
    """``(state, period)`` continuing attractor ``a`` at a neighbouring frequency."""
    if a.period:
        x, v, z, u = (float(q) for q in a.poincare[0])
        return (x, v, x + z, v + u), a.period
    return a.final_state, 0


def _neighbour_seeds(new, sweep) -> list:
    """Per frequency, the seeds its neighbours' newly found attractors give it (``sweep`` says which side)."""
    up, down = sweep in ("up", "both"), sweep in ("down", "both")
    seeds = [[] for _ in new]
    for i, fresh in enumerate(new):
        for a in fresh:
            if not a.success:
                continue
            if up and i + 1 < len(new):
                seeds[i + 1].append(_seed(a))
            if down and i > 0:
                seeds[i - 1].append(_seed(a))
    return seeds


def band(model, frequencies, amplitude: float, kind: str, sweep: str, settings, kwargs: dict, check):
    """``(frequencies Hz, excitations, settings)`` of a frequency response, every refusal before any run.

    ``check(model, excitation, settings, **kwargs)`` validates the settings of the model's solver (one
    ball or several); an undamped resonance at any frequency is refused too.
    """
    check_choice("sweep", sweep, SWEEPS)
    f = _frequencies(frequencies)
    excitations = [Excitation(float(fi), amplitude, kind) for fi in f]
    settings = check(model, excitations[0], settings, **kwargs)
    for ex in excitations[1:]:
        ex.linear_response(model)  # refuses an undamped resonance before any run
    return f, excitations, settings


def first_round(work, tasks: list, f, settings, executor, progress) -> list:
    """The starts of every frequency: ``work(task)`` for each, on ``executor`` if given, reported in order."""
    run = executor.map if executor is not None else map
    results = []
    for k, r in enumerate(run(work, tasks)):
        results.append(r)
        if progress:
            progress(f"{f[k]:g} Hz ({k + 1}/{f.size}): {len(r.attractors)} attractor(s) from {settings.starts} starts")
    return results


def attractor_response(
    model: DamperModel,
    frequencies,
    amplitude: float,
    *,
    kind: str = "force",
    sweep: str = "up",
    executor=None,
    settings: SteadyStateOptions | None = None,
    progress=None,
    **kwargs,
) -> AttractorResponse:
    """Every attractor of the forced damper at each of ``frequencies`` (module docstring).

    Parameters
    ----------
    model : DamperModel
    frequencies : array_like
        Forcing frequencies in Hz (> 0; sorted here, duplicates refused).
    amplitude : float
        Force amplitude in N (``kind="force"``) or base amplitude in m (``kind="base"``).
    kind : {"force", "base"}
    sweep : {"up", "down", "both", "independent"}
        Which neighbours' attractors seed a frequency (module docstring).
    executor : concurrent.futures.Executor, optional
        Runs the frequencies of each round in parallel.
    settings : SteadyStateOptions, optional
        Or its fields as keywords (tolerance, rtol, starts, max_cycles, solver, restitution).
    progress : callable, optional
        Called with a one-line message after each frequency of the first round and after each
        continuation round.

    Returns
    -------
    AttractorResponse
    """
    f, excitations, settings = band(model, frequencies, amplitude, kind, sweep, settings, kwargs, check_settings)
    results = first_round(_run_attractors, [(model, ex, settings, (), None) for ex in excitations], f, settings,
                          executor, progress)
    run = executor.map if executor is not None else map  # the continuation rounds
    new = [list(r.attractors) for r in results]
    rounds = 0
    if progress:
        progress(f"{f.size} frequencies x {settings.starts} starts: "
                 f"{sum(len(r.attractors) for r in results)} attractors")
    while sweep != "independent" and rounds < f.size:
        seeds = _neighbour_seeds(new, sweep)
        todo = [i for i in range(f.size) if seeds[i]]
        if not todo:
            break
        rounds += 1
        before = [len(r.attractors) for r in results]
        done = list(run(_run_attractors, [(model, excitations[i], settings, tuple(seeds[i]), results[i])
                                          for i in todo]))
        new = [[] for _ in f]
        for i, r in zip(todo, done, strict=True):
            results[i] = r
            new[i] = list(r.attractors[before[i]:])
        if progress:
            progress(f"continuation round {rounds}: {sum(len(x) for x in new)} new attractors")
    return AttractorResponse(f, tuple(results), sweep, settings, rounds)


def describe(r) -> dict:
    """Summary of one steady state for tables (SI units; phases in degrees)."""
    speeds = r.impact_speeds
    return {
        "frequency_hz": r.excitation.frequency,
        "amplitude_m": r.amplitude,
        "amplitude_without_damper_m": r.amplitude_without_damper,
        "reduction_db": r.reduction_db,
        "impacts_per_cycle": r.impacts_per_cycle,
        "regime": r.regime,
        "period_cycles": r.period,
        "converged": r.converged,
        "cycles": r.cycles,
        "x_max_m": r.x_max,
        "x_min_m": r.x_min,
        "mean_impact_speed_m_s": float(np.mean(speeds)) if speeds.size else math.nan,
        "max_impact_speed_m_s": float(np.max(speeds)) if speeds.size else math.nan,
        "impact_phases_deg": " ".join(f"{math.degrees(p):.2f}" for p in r.impact_phases),
        "energy_closure": r.energy_closure,
        "stable": r.stable,
        "max_floquet_modulus": r.max_floquet_modulus,
        "residual": r.residual,
        "amplitude_std_err_m": r.amplitude_std_err,
        "lyapunov_1_s": r.lyapunov,
        "lyapunov_std_err_1_s": r.lyapunov_std_err,
        "newton_iterations": r.newton_iterations,
        "cycles_integrated": r.cycles_integrated,
        "message": r.message,
    }
