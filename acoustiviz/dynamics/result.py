"""Results of an impact-damper simulation: the impact table, the energy balance, the time history.

Walls: ``wall = +1`` is struck when ``z = y - x`` reaches ``+d/2`` (the impact mass moving in
``+x`` relative to the main mass), ``wall = -1`` when ``z`` reaches ``-d/2``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from .model import DamperModel, InitialState
from .sequence import ImpactSequence

__all__ = ["ImpactTable", "EnergyBalance", "Extrema", "SimulationResult"]


def _frozen(a) -> np.ndarray:
    out = np.array(a, dtype=float)
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class ImpactTable:
    """One row per contact, in time order; all arrays have the same length.

    Written to CSV, one row per contact with the unit in each column's name, by
    :func:`acoustiviz.output.tables.write_impact_table` (``av.write_impact_table(path, run.impacts)``):
    the physics layers write no files, so the table has no ``to_csv`` of its own.

    Attributes
    ----------
    time : ndarray
        Contact start time in s (first touch, penetration 0).
    wall : ndarray
        +1 (``y - x = +d/2``) or -1 (``y - x = -d/2``), as floats.
    approach_velocity : ndarray
        Relative approach speed at first touch in m/s (positive).
    separation_velocity : ndarray
        Relative separation speed when the bodies part in m/s (positive; NaN if the contact
        was still going on at the end of the run).
    restitution : ndarray
        ``separation_velocity / approach_velocity`` (dimensionless).
    duration : ndarray
        Contact duration in s (for the impact map: the compliant contact's duration, reported
        for sound synthesis but not used by the motion).
    peak_force : ndarray
        Largest contact force in N.
    impulse : ndarray
        Time integral of the contact force in N·s.
    energy_lost : ndarray
        Energy dissipated in the contact in J (by c1, and by clipping when it is on).
    """

    time: np.ndarray
    wall: np.ndarray
    approach_velocity: np.ndarray
    separation_velocity: np.ndarray
    restitution: np.ndarray
    duration: np.ndarray
    peak_force: np.ndarray
    impulse: np.ndarray
    energy_lost: np.ndarray

    def __post_init__(self):
        n = None
        for name in self.__dataclass_fields__:
            arr = _frozen(getattr(self, name))
            if arr.ndim != 1 or (n is not None and arr.size != n):
                raise ValueError(f"impact table column {name!r} must be 1-D of equal length")
            n = arr.size
            object.__setattr__(self, name, arr)

    @classmethod
    def from_rows(cls, rows: np.ndarray) -> ImpactTable:
        """Build the table from the kernels' ``(n, 8)`` array.

        Columns: time (s), wall, approach (m/s), separation (m/s), duration (s), peak force (N),
        impulse (N·s), energy lost (J).
        """
        rows = np.asarray(rows, dtype=float).reshape(-1, 8)
        with np.errstate(invalid="ignore", divide="ignore"):
            e = rows[:, 3] / rows[:, 2]
        return cls(rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], e, rows[:, 4], rows[:, 5], rows[:, 6], rows[:, 7])

    def __len__(self) -> int:
        return int(self.time.size)

    def sequence(self) -> ImpactSequence:
        """The impacts as the package's one :class:`~acoustiviz.dynamics.sequence.ImpactSequence`.

        Contact start times in s, walls -1/+1 and approach speeds in m/s (as magnitudes); the
        table's other columns stay here.
        """
        return ImpactSequence(self.time, self.wall, np.abs(self.approach_velocity))

    def head(self, n: int) -> ImpactTable:
        """The first ``n`` impacts."""
        return ImpactTable(*(getattr(self, f)[:n] for f in self.__dataclass_fields__))


@dataclass(frozen=True)
class EnergyBalance:
    """Energy account of a run in J: initial = final mechanical + dissipated (+ closure error).

    Attributes
    ----------
    initial : float
        Mechanical energy at t = 0 in J.
    kinetic, spring, hertz : float
        Kinetic, main-spring and Hertz (``2/5 K_HZ δ^{5/2}``) energy at the end in J.
    dissipated_main : float
        Energy dissipated by the main dashpot C in J.
    dissipated_contact : float
        Energy dissipated in contacts in J.
    """

    initial: float
    kinetic: float
    spring: float
    hertz: float
    dissipated_main: float
    dissipated_contact: float

    @property
    def closure_error(self) -> float:
        """``initial - (kinetic + spring + hertz + dissipated)`` in J (> 0: energy went missing)."""
        return self.initial - (self.kinetic + self.spring + self.hertz
                               + self.dissipated_main + self.dissipated_contact)

    @property
    def relative_closure_error(self) -> float:
        """Closure error divided by the initial energy (dimensionless)."""
        return self.closure_error / self.initial if self.initial else float("nan")


@dataclass(frozen=True)
class Extrema:
    """Every turning point of the main-mass displacement x(t) in a run, in time order.

    Between two consecutive entries x is monotone. The event solver finds them exactly: in free
    flight as zeros of the closed-form velocity of the damped main oscillator, inside a contact by
    root finding on the contact integration; the impact map adds the kinks where an instantaneous
    impact reverses the main mass; Newmark takes the turning points of its cubic interpolant.

    Attributes
    ----------
    time : ndarray
        Times in s.
    value : ndarray
        Displacements x in m.
    kind : ndarray
        +1 for a local maximum, -1 for a local minimum (floats).
    """

    time: np.ndarray
    value: np.ndarray
    kind: np.ndarray

    def __post_init__(self):
        for name in ("time", "value", "kind"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))

    def __len__(self) -> int:
        return int(self.time.size)


@dataclass(frozen=True)
class SimulationResult:
    """What every solver returns (see :func:`acoustiviz.dynamics.simulate`).

    Attributes
    ----------
    solver : str
        ``"event"``, ``"newmark"`` or ``"impact-map"``.
    settings : Mapping
        The numerical settings used (``rtol``, ``dt``, ...).
    model : DamperModel
    initial : InitialState
    duration : float
        Requested duration in s.
    t_end : float
        Time in s actually reached (less than ``duration`` only on failure).
    impacts : ImpactTable
    t : ndarray
        Output times in s (the requested ``t_eval``; may be empty).
    x, v, y, w : ndarray
        Main-mass displacement (m), velocity (m/s), impact-mass displacement (m), velocity (m/s)
        at ``t``.
    dissipated_main, dissipated_contact : ndarray
        Energy dissipated by C and in contacts up to ``t``, in J.
    energy : EnergyBalance
        The account at ``t_end``.
    success : bool
    message : str
    solver_time : float
        Wall time of the compiled solver alone in s (compilation and set-up excluded).
    final_state : tuple
        ``(x, v, y, w)`` at ``t_end`` in m and m/s.
    extrema : Extrema
        Every turning point of x(t) in [0, t_end] (see :func:`acoustiviz.dynamics.exact_maxima`).
    compile_time : float
        Wall time in s spent before the run compiling the solver's kernels, or loading them from
        numba's cache (milliseconds once compiled on the installation).
    """

    solver: str
    settings: MappingProxyType
    model: DamperModel
    initial: InitialState
    duration: float
    t_end: float
    impacts: ImpactTable
    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    y: np.ndarray
    w: np.ndarray
    dissipated_main: np.ndarray
    dissipated_contact: np.ndarray
    energy: EnergyBalance
    success: bool
    message: str
    solver_time: float
    final_state: tuple = field(default=())
    extrema: Extrema | None = None
    compile_time: float = 0.0

    def mechanical_energy(self) -> np.ndarray:
        """Kinetic + spring + Hertz energy at ``t`` in J."""
        return self.model.energy(self.x, self.v, self.y, self.w)

    def energy_residual(self) -> np.ndarray:
        """``E(0) - (mechanical + dissipated)`` at ``t`` in J (round-off for an exact solver)."""
        return self.energy.initial - (self.mechanical_energy() + self.dissipated_main
                                      + self.dissipated_contact)
