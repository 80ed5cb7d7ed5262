"""Measures of damper performance: maxima, damping inclination (paper eq 16), settling time.

Definitions
-----------
Positive maxima
    The largest main-mass displacement within each positive excursion (between a zero crossing
    of x upward and the next one downward), so that a kink made by an impact inside an excursion
    never counts as a maximum of its own. Found on samples of x and refined by a parabola.
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
from .model import TABLE1, DamperModel, InitialState

__all__ = [
    "Maxima",
    "Inclination",
    "positive_maxima",
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
class Maxima:
    """Positive maxima of the main-mass displacement.

    Attributes
    ----------
    time : ndarray
        Times of the maxima in s.
    value : ndarray
        Displacements at the maxima in m.
    """

    time: np.ndarray
    value: np.ndarray


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


def positive_maxima(t, x) -> Maxima:
    """Positive maxima of sampled displacement ``x`` (m) at times ``t`` (s); see module notes."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.shape != x.shape or t.ndim != 1 or t.size < 3:
        raise ParameterError("t", "t and x must be 1-D arrays of equal length >= 3")
    pos = x > 0
    edges = np.flatnonzero(np.diff(pos.astype(np.int8)))
    starts = ([0] if pos[0] else []) + [i + 1 for i in edges if not pos[i]]
    ends = [i + 1 for i in edges if pos[i]]
    tm, xm = [], []
    for s in starts:
        later = [e for e in ends if e > s]
        if not later:
            break  # excursion still open at the end of the record
        e = later[0]
        seg = x[s:e]
        if seg.size == 0 or seg.max() <= 0:
            continue
        k = s + int(np.argmax(seg))
        tk, xk = t[k], x[k]
        if 0 < k < t.size - 1:
            x0, x1, x2 = x[k - 1], x[k], x[k + 1]
            den = x0 - 2 * x1 + x2
            h = t[k + 1] - t[k]
            if den < 0 and abs(t[k] - t[k - 1] - h) < 1e-9 * h:
                off = 0.5 * (x0 - x2) / den
                if abs(off) <= 1:
                    tk = t[k] + off * h
                    xk = x1 - 0.25 * (x0 - x2) * off
        tm.append(tk)
        xm.append(xk)
    return Maxima(np.array(tm), np.array(xm))


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


def damping_metrics(t, x, *, window_fraction: float = 0.3, settling_fraction: float = 0.05) -> DampingMetrics:
    """Damping inclination (eq 16 and envelope fit) and settling time of a displacement history.

    Parameters
    ----------
    t, x : (n,) array_like
        Times in s and main-mass displacement in m (dense enough to resolve the maxima).
    window_fraction : float
        Envelope fit over the maxima down to this fraction of the first (:func:`envelope_inclination`).
    settling_fraction : float
        Settled once the maxima stay below this fraction of the first (:func:`settling_time`).

    Returns
    -------
    DampingMetrics
    """
    maxima = positive_maxima(t, x)
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
