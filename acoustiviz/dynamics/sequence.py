"""The one impact sequence of the package: when each impact starts, the wall it strikes, how fast.

:class:`ImpactSequence` is what every consumer of impacts takes (the synthesis of
:mod:`acoustiviz.sound`, the levels of a run, the auralize job). A simulation's
:class:`~acoustiviz.dynamics.ImpactTable` keeps its own columns (separation speed, restitution,
contact duration, peak force, impulse, energy lost) and gives its sequence with
:meth:`~acoustiviz.dynamics.ImpactTable.sequence`; a forced steady state's measured impacts give
theirs with :meth:`ImpactSequence.from_steady_state`. Times in s, speeds in m/s, walls -1 or +1
(the convention of :mod:`acoustiviz.dynamics.result`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError

__all__ = ["ImpactSequence"]


@dataclass(frozen=True)
class ImpactSequence:
    """The impacts to render: contact start times, walls and approach speeds.

    Parameters
    ----------
    times : (n,) array_like
        Contact start times in s (>= 0, any order).
    walls : (n,) array_like of int
        The wall struck, -1 or +1 (the convention of :mod:`acoustiviz.dynamics`).
    velocities : (n,) array_like
        Relative approach speeds in m/s (> 0).

    Examples
    --------
    >>> seq = ImpactSequence([0.01, 0.2], [-1, 1], [1.3, 0.9])
    >>> len(seq), seq.count(+1)
    (2, 1)
    """

    times: np.ndarray
    walls: np.ndarray
    velocities: np.ndarray

    def __post_init__(self):
        t = np.array(self.times, dtype=float).reshape(-1)
        v = np.array(self.velocities, dtype=float).reshape(-1)
        try:
            w = np.array(self.walls, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ParameterError("walls", "expected -1 or +1 for every impact") from None
        if not (t.size == w.size == v.size):
            raise ParameterError("times", f"times ({t.size}), walls ({w.size}) and velocities ({v.size}) "
                                          "must have the same length")
        if not np.all(np.isfinite(t)) or np.any(t < 0):
            raise ParameterError("times", "impact times must be finite and >= 0 s")
        if not np.all(np.isin(w, (-1.0, 1.0))):
            raise ParameterError("walls", f"every wall must be -1 or +1, got {sorted(set(w.tolist()))}")
        if not np.all(np.isfinite(v)) or np.any(v <= 0):
            raise ParameterError("velocities", "approach speeds must be finite and > 0 m/s")
        wi = w.astype(np.int8)
        for name, arr in (("times", t), ("walls", wi), ("velocities", v)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def __len__(self) -> int:
        return int(self.times.size)

    def __eq__(self, other):
        if not isinstance(other, ImpactSequence):
            return NotImplemented
        return all(np.array_equal(getattr(self, k), getattr(other, k)) for k in ("times", "walls", "velocities"))

    def count(self, wall: int) -> int:
        """Number of impacts on ``wall`` (-1 or +1)."""
        return int(np.count_nonzero(self.walls == wall))

    @classmethod
    def from_steady_state(cls, state, *, origin: float = 0.0) -> ImpactSequence:
        """The impacts measured on a forced damper's steady motion (:class:`acoustiviz.dynamics.SteadyState`).

        Its ``impact_times``, ``impact_walls`` and ``impact_speeds`` (relative approach speeds in m/s),
        of the impacts with a positive approach speed: a contact the solver records at zero (or, by
        round-off, negative) approach speed is a graze, with no approach to make a click of. The phases,
        peak forces and contact durations stay on the state.

        Parameters
        ----------
        state : SteadyState
            The measured steady motion (any object with the three arrays).
        origin : float, optional
            The time in s the sequence's times count from (default 0: the start of the run; the start
            of the measured cycles is ``state.cycles * state.excitation.period``).

        Examples
        --------
        >>> from types import SimpleNamespace
        >>> state = SimpleNamespace(impact_times=[1.25, 1.5, 1.75], impact_walls=[1, -1, 1],
        ...                         impact_speeds=[0.4, 0.0, 0.5])
        >>> ImpactSequence.from_steady_state(state, origin=1.0).times.tolist()
        [0.25, 0.75]
        """
        speeds = np.asarray(state.impact_speeds, dtype=float)
        keep = speeds > 0
        return cls(np.asarray(state.impact_times, dtype=float)[keep] - origin, np.asarray(state.impact_walls)[keep],
                   speeds[keep])

    @classmethod
    def from_table(cls, table) -> ImpactSequence:
        """Build from an impact table with ``times``/``time``, ``walls``/``wall`` and approach speeds.

        Accepts any object (or mapping) exposing the contact start times in s, the wall (-1/+1)
        and the relative approach speed in m/s under the names used by
        :mod:`acoustiviz.dynamics` (``time``, ``wall``, ``approach_velocity``, singular or plural).
        Speeds are taken as magnitudes.
        """

        def get(*names):
            for nm in names:
                if isinstance(table, dict) and nm in table:
                    return table[nm]
                if hasattr(table, nm):
                    return getattr(table, nm)
            raise ParameterError("table", f"the impact table has none of {names}")

        t = get("times", "time", "time_s", "start", "t")
        w = get("walls", "wall")
        v = get("approach_velocities", "approach_velocity", "approach_velocity_m_s", "approach_speed",
                "velocity_in")
        return cls(t, w, np.abs(np.asarray(v, dtype=float)))
