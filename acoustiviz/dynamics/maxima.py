"""Positive maxima of the main-mass displacement: exact from a run, or from samples.

Positive maxima
    The largest main-mass displacement within each positive excursion (between a zero crossing
    of x upward and the next one downward), so that a kink made by an impact inside an excursion
    never counts as a maximum of its own. An excursion still open at the end of the record is
    not counted; one open at its start counts from the first value.

:func:`exact_maxima` takes them from the turning points a solver records
(:class:`~acoustiviz.dynamics.result.Extrema`): between contacts the main mass is a damped free
oscillator, so its maxima are the zeros of a closed-form velocity; inside a contact they are
roots found on the contact integration itself. Their times and values are as accurate as the
run (no sampling). :func:`positive_maxima` serves records known only by samples (a measurement,
a closed-form response on a grid): the largest sample refined by a parabola.

Examples
--------
>>> from acoustiviz.dynamics import simulate
>>> mx = exact_maxima(simulate(duration=1.0))
>>> bool(mx.value[0] > mx.value[1] > 0)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError

__all__ = ["Maxima", "exact_maxima", "positive_maxima", "excursion_maxima"]


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


def excursion_maxima(t, x) -> Maxima:
    """Positive maxima of a record known at its turning points (between them x is monotone).

    Parameters
    ----------
    t : (n,) array_like
        Increasing times in s: the start of the record, every turning point of x, and its end.
    x : (n,) array_like
        Displacement in m at ``t``.

    Returns
    -------
    Maxima
        For each positive excursion closed within the record, its largest value and the time of
        it. Since x is monotone between the given points, the largest value of an excursion is
        one of them.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    tm, xm = [], []
    best_t, best_x = math.nan, -math.inf
    open_ = False
    if t.shape != x.shape or t.ndim != 1:
        raise ParameterError("t", "t and x must be 1-D arrays of equal length")
    for ti, xi in zip(t, x, strict=True):
        if xi > 0.0:
            if not open_:
                open_, best_t, best_x = True, ti, xi
            elif xi > best_x:
                best_t, best_x = ti, xi
        elif open_:  # x fell to zero or below since the last point: the excursion is over
            tm.append(best_t)
            xm.append(best_x)
            open_ = False
    return Maxima(np.array(tm), np.array(xm))


def exact_maxima(result) -> Maxima:
    """Positive maxima of a run's main-mass displacement, from the turning points its solver found.

    Parameters
    ----------
    result : SimulationResult
        A run of :func:`acoustiviz.dynamics.simulate` (any solver: exact for ``"event"`` and for
        the impact map's instantaneous impacts; for ``"newmark"`` the turning points of its cubic
        interpolant).

    Returns
    -------
    Maxima
        Times in s and values in m (see the module notes for the definition).

    Examples
    --------
    The paper's Table 1 damper started too gently to strike (0.5 m/s: 15.8 mm < half the gap)
    is a free damped oscillator: successive maxima fall by ``exp(-2π ζ / sqrt(1 - ζ²))``:

    >>> from acoustiviz.dynamics import DamperModel, InitialState, simulate
    >>> model = DamperModel()
    >>> mx = exact_maxima(simulate(model, 0.5, initial=InitialState(v=0.5)))
    >>> np.round(mx.value * 1e3, 2)  # mm
    array([15.77, 15.62, 15.46])
    >>> z = model.main_damping_ratio
    >>> round(float(mx.value[1] / mx.value[0]), 6), round(math.exp(-2 * math.pi * z / math.sqrt(1 - z * z)), 6)
    (0.990114, 0.990114)
    """
    ext = getattr(result, "extrema", None)
    if ext is None:
        raise ParameterError("result", "expected a SimulationResult with its extrema (from simulate)")
    x0 = result.initial.x
    xf = result.final_state[0] if result.final_state else math.nan
    t = np.concatenate(([0.0], ext.time, [result.t_end]))
    x = np.concatenate(([x0], ext.value, [xf]))
    return excursion_maxima(t, x)


def positive_maxima(t, x) -> Maxima:
    """Positive maxima of sampled displacement ``x`` (m) at times ``t`` (s); see module notes.

    The largest sample of each excursion, refined by a parabola through it and its neighbours
    (uniform samples). For a simulation use :func:`exact_maxima`.
    """
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
