"""Frequency response of the forced impact damper: sweeps up and down with continuation.

Each frequency is run to its periodic steady state (:func:`.forced.steady_state`). With
continuation (``sweep="up"``, ``"down"`` or ``"both"``) a run starts from the last state of the
previous frequency (at forcing phase 0), so the sweep follows a branch of periodic motions as a
slowly varied machine speed would, and the two directions can end on different branches
(hysteresis). ``sweep="independent"`` starts every frequency from the linear steady state
(:func:`.forced.linear_start`); those runs are independent and go to an executor when one is
given (any :class:`concurrent.futures.Executor`: a local process pool, a Dask executor).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice
from ..constants import FREQUENCY_SWEEPS
from .model import DamperModel

# .forced re-exports this module's public names, so its names are imported where used

__all__ = ["SWEEPS", "FrequencyResponse", "frequency_response", "HYSTERESIS_TOLERANCE"]

#: Sweep directions.
SWEEPS = FREQUENCY_SWEEPS
#: Relative amplitude difference between the two sweep directions flagged as hysteresis.
HYSTERESIS_TOLERANCE = 1e-3


def _run_one(args):
    """One steady state (picklable for process pools)."""
    from .forced import steady_state

    model, excitation, kwargs, initial = args
    return steady_state(model, excitation, initial=initial, **kwargs)


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
        Passed to :func:`.forced.steady_state` (solver, restitution, tolerance, max_cycles, rtol).

    Returns
    -------
    FrequencyResponse
    """
    from .forced import Excitation, check_settings, steady_state

    check_choice("sweep", sweep, SWEEPS)
    try:
        f = np.sort(np.asarray(frequencies, dtype=float).ravel())
    except (TypeError, ValueError):
        raise ParameterError("frequencies", "expected numbers in Hz") from None
    if f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ParameterError("frequencies", "expected one or more finite frequencies > 0 Hz")
    if np.any(np.diff(f) == 0):
        raise ParameterError("frequencies", "duplicate frequencies")
    if executor is not None and sweep != "independent":
        raise ParameterError("executor", "runs in parallel only with sweep='independent' (no continuation)")
    excitations = [Excitation(float(fi), amplitude, kind) for fi in f]
    check_settings(model, excitations[0], **kwargs)

    def chain(order):
        out, state = {}, None
        for i in order:
            r = steady_state(model, excitations[i], initial=state, **kwargs)
            out[i] = r
            state = r.final_state if r.success else None
        return tuple(out[i] for i in range(f.size))

    up = range(f.size)
    down = range(f.size - 1, -1, -1)
    if sweep == "independent":
        tasks = [(model, ex, kwargs, None) for ex in excitations]
        results = list(executor.map(_run_one, tasks)) if executor is not None else [_run_one(t) for t in tasks]
        return FrequencyResponse(f, tuple(results), None, sweep)
    if sweep == "down":
        return FrequencyResponse(f, chain(down), None, sweep)
    primary = chain(up)
    return FrequencyResponse(f, primary, chain(down) if sweep == "both" else None, sweep)


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
    }
