"""Measures of damper performance: maxima, damping inclination (paper eq 16), settling time.

Definitions
-----------
Positive maxima
    The largest main-mass displacement within each positive excursion (between a zero crossing
    of x upward and the next one downward), so that a kink made by an impact inside an excursion
    never counts as a maximum of its own (:mod:`acoustiviz.dynamics.maxima`). From a run they are
    exact (:func:`exact_maxima`: zeros of the closed-form velocity between contacts, roots on the
    contact integration inside them); from samples, refined by a parabola (:func:`positive_maxima`).
Damping inclination, two maxima (paper eq 16)
    ``e = (X1 - X2) / (t2 - t1)`` in m/s from the first two positive maxima. Fragile: one impact
    near a maximum changes it a lot, even its sign, across a sweep.
Damping inclination, envelope fit
    Minus the slope in m/s of a least-squares line through the positive maxima that lie in the
    window from the first maximum to the last one still above ``window_fraction`` × X1
    (default 0.3: the "initially linear decrease"). The window is returned with the value.
Settling time
    The time in s of the first positive maximum after which every later positive maximum stays
    below ``fraction`` × X1 (default 5 %); NaN if the motion has not settled within the run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_positive, check_range
from ..core.contact import restitution
from .maxima import Maxima, exact_maxima, positive_maxima
from .model import TABLE1, DamperModel, InitialState
from .result import SimulationResult

__all__ = [
    "Maxima",
    "Inclination",
    "positive_maxima",
    "exact_maxima",
    "metrics_from_maxima",
    "damping_inclination",
    "envelope_inclination",
    "settling_time",
    "DampingMetrics",
    "damping_metrics",
    "free_response",
    "sample_times",
    "restitution_curve",
]


@dataclass(frozen=True)
class Inclination:
    """A damping inclination in m/s and the window it was measured over.

    Attributes
    ----------
    value : float
        Damping inclination in m/s (positive: the maxima decrease); NaN if undefined.
    t_start, t_stop : float
        Times in s of the first and last maxima used.
    n_maxima : int
        Number of maxima used.
    method : str
        ``"two-maxima"`` (paper eq 16) or ``"envelope-fit"``.
    """

    value: float
    t_start: float
    t_stop: float
    n_maxima: int
    method: str


def sample_times(duration: float, model: DamperModel = TABLE1, per_period: int = 200) -> np.ndarray:
    """Uniform times in s covering [0, duration] with ``per_period`` samples per main period."""
    duration = check_positive("duration", duration, "s")
    if int(per_period) < 8:
        raise ParameterError("per_period", f"must be >= 8, got {per_period}")
    period = 2.0 * math.pi / model.main_frequency
    n = int(math.ceil(duration / period * per_period)) + 1
    return np.linspace(0.0, duration, n)


def damping_inclination(maxima: Maxima) -> Inclination:
    """Paper eq 16, ``(X1 - X2) / (t2 - t1)`` in m/s, from the first two positive maxima."""
    if maxima.time.size < 2:
        return Inclination(math.nan, math.nan, math.nan, int(maxima.time.size), "two-maxima")
    x1, x2 = maxima.value[:2]
    t1, t2 = maxima.time[:2]
    return Inclination(float((x1 - x2) / (t2 - t1)), float(t1), float(t2), 2, "two-maxima")


def envelope_inclination(maxima: Maxima, window_fraction: float = 0.3) -> Inclination:
    """Minus the slope in m/s of a line fitted to the maxima above ``window_fraction`` × X1.

    The window runs from the first maximum to the last maximum whose value is still at least
    ``window_fraction`` times the first one (``0 < window_fraction < 1``).
    """
    frac = check_range("window_fraction", window_fraction, 0.0, 1.0, low_open=True, high_open=True)
    if maxima.time.size < 2:
        return Inclination(math.nan, math.nan, math.nan, int(maxima.time.size), "envelope-fit")
    above = np.flatnonzero(maxima.value >= frac * maxima.value[0])
    last = int(above[-1])
    n = max(last + 1, 2)
    t = maxima.time[:n]
    x = maxima.value[:n]
    slope = np.polyfit(t, x, 1)[0]
    return Inclination(float(-slope), float(t[0]), float(t[-1]), int(n), "envelope-fit")


def settling_time(maxima: Maxima, fraction: float = 0.05) -> float:
    """Time in s after which all positive maxima stay below ``fraction`` × X1 (NaN if never)."""
    frac = check_range("fraction", fraction, 0.0, 1.0, low_open=True, high_open=True)
    if maxima.time.size == 0:
        return math.nan
    big = np.flatnonzero(maxima.value >= frac * maxima.value[0])
    nxt = int(big[-1]) + 1
    if nxt >= maxima.time.size:
        return math.nan
    return float(maxima.time[nxt])


@dataclass(frozen=True)
class DampingMetrics:
    """How fast a run decays: both damping inclinations and the settling time.

    Attributes
    ----------
    two_maxima : Inclination
        Paper eq 16 from the first two positive maxima.
    fit : Inclination
        Linear fit of the decaying maxima envelope (its window in ``t_start``/``t_stop``).
    settling_time : float
        Time in s after which every positive maximum stays below the settling fraction of the
        first (NaN if never within the run).
    maxima : Maxima
        The positive maxima they were computed from.
    """

    two_maxima: Inclination
    fit: Inclination
    settling_time: float
    maxima: Maxima


def damping_metrics(run, x=None, *, window_fraction: float = 0.3, settling_fraction: float = 0.05) -> DampingMetrics:
    """Damping inclination (eq 16 and envelope fit) and settling time of a run or of a record.

    Parameters
    ----------
    run : SimulationResult or (n,) array_like
        A run of :func:`~acoustiviz.dynamics.simulate`, whose exact maxima are used
        (:func:`~acoustiviz.dynamics.maxima.exact_maxima`); or the times in s of a sampled record,
        with ``x``.
    x : (n,) array_like, optional
        Main-mass displacement in m at the times ``run`` (a sampled record only; maxima refined
        by a parabola, :func:`~acoustiviz.dynamics.maxima.positive_maxima`).
    window_fraction : float
        Envelope fit over the maxima down to this fraction of the first (:func:`envelope_inclination`).
    settling_fraction : float
        Settled once the maxima stay below this fraction of the first (:func:`settling_time`).

    Returns
    -------
    DampingMetrics

    Examples
    --------
    >>> from acoustiviz.dynamics import simulate
    >>> m = damping_metrics(simulate(duration=2.0))
    >>> m.two_maxima.method, m.two_maxima.n_maxima
    ('two-maxima', 2)
    """
    if isinstance(run, SimulationResult):
        if x is not None:
            raise ParameterError("x", "give x only with sampled times, not with a SimulationResult")
        maxima = exact_maxima(run)
    else:
        if x is None:
            raise ParameterError("x", "a sampled record needs its displacements x in m")
        maxima = positive_maxima(run, x)
    return metrics_from_maxima(maxima, window_fraction=window_fraction, settling_fraction=settling_fraction)


def metrics_from_maxima(maxima: Maxima, *, window_fraction: float = 0.3,
                        settling_fraction: float = 0.05) -> DampingMetrics:
    """:class:`DampingMetrics` of given positive maxima (see :func:`damping_metrics`)."""
    return DampingMetrics(damping_inclination(maxima), envelope_inclination(maxima, window_fraction),
                          settling_time(maxima, settling_fraction), maxima)


def free_response(t, model: DamperModel = TABLE1, initial: InitialState | None = None):
    """Main-mass displacement in m at times ``t`` (s) without the impact damper (paper Figure 5).

    The impact mass is removed: ``M x'' + C x' + K x = 0`` from ``initial.x``, ``initial.v``
    (closed form, any damping ratio).
    """
    initial = InitialState() if initial is None else initial
    t = np.asarray(t, dtype=float)
    a = model.C / (2 * model.M)
    w0 = model.main_frequency
    x0, v0 = initial.x, initial.v
    e = np.exp(-a * t)
    if a < w0:
        wd = math.sqrt(w0 * w0 - a * a)
        return e * (x0 * np.cos(wd * t) + (v0 + a * x0) / wd * np.sin(wd * t))
    if a == w0:
        return e * (x0 + (v0 + a * x0) * t)
    wd = math.sqrt(a * a - w0 * w0)
    return e * (x0 * np.cosh(wd * t) + (v0 + a * x0) / wd * np.sinh(wd * t))


def restitution_curve(masses, velocities, model: DamperModel = TABLE1) -> np.ndarray:
    """Coefficient of restitution of the compliant contact versus impact mass and speed (Figure 7).

    Parameters
    ----------
    masses : (n,) array_like
        Impact masses m in kg (the main mass is ``model.M``).
    velocities : (k,) array_like
        Relative approach speeds in m/s.
    model : DamperModel
        Supplies M, K_HZ, c1 and the clipping choice.

    Returns
    -------
    (n, k) ndarray
        Restitution (dimensionless), from :func:`acoustiviz.core.contact.restitution`.
    """
    m = np.atleast_1d(np.asarray(masses, dtype=float))
    if m.ndim != 1 or not np.all(m > 0):
        raise ParameterError("masses", "must be a 1-D array of masses > 0 kg")
    u = np.atleast_1d(np.asarray(velocities, dtype=float))
    return np.array([
        restitution(u, model.k_hertz, mi, model.M, model.c1, model.clip_tensile) for mi in m
    ]).reshape(m.size, u.size)
