"""Simulating a multi-ball damper (:mod:`acoustiviz.dynamics.balls`): :func:`simulate_balls` and its results.

The compiled solver is :mod:`acoustiviz.dynamics._balls` (closed-form flights, contacts located as
events; a contact alone by the single-ball contact kernel, overlapping contacts by DOP853 on every
body). The run goes in batches of steps, so a caller can show progress and Ctrl-C stops it between
two batches.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from .._jit import compile_for
from .._validate import ParameterError, check_positive
from ..constants import DEFAULT_RTOL, SOLVER_RTOL_RANGE
from . import _balls as kern
from .balls import BallState, MultiBallModel, cavity_body_names
from .result import EnergyBalance

__all__ = ["BallImpactTable", "MultiBallResult", "simulate_balls", "BALLS_COMPILE_S"]

#: CPU time in s of the multi-ball kernel's first compilation (quoted to the user when it happens).
BALLS_COMPILE_S = 7.0
#: Steps of one batch of the compiled solver (between two, progress is reported and Ctrl-C is seen).
BATCH_STEPS = 200_000


def _frozen(a, dtype=float) -> np.ndarray:
    out = np.array(a, dtype=dtype)
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class BallImpactTable:
    """One row per collision, in order of first touch; all arrays have the same length.

    Attributes
    ----------
    time, end : ndarray
        First touch and parting in s (for a contact still under way, the end of the run).
    first, second : ndarray of str
        The two bodies in axis order among ``wall-``, ``ball1`` ... ``ballN``, ``wall+`` (with several
        cavities prefixed by the cavity's number, ``c2:ball1``).
    approach_velocity, separation_velocity : ndarray
        Relative speed of the pair at first touch and at parting in m/s (positive; the separation NaN
        while under way).
    restitution : ndarray
        ``separation_velocity / approach_velocity`` of the pair.
    peak_force : ndarray
        Largest contact force in N.
    impulse : ndarray
        Time integral of the contact force in N s.
    energy_lost : ndarray
        Work of the dissipative part of the force in J, ``∫ (F - K δ^{3/2}) dδ/dt dt``.
    """

    time: np.ndarray
    end: np.ndarray
    first: np.ndarray
    second: np.ndarray
    approach_velocity: np.ndarray
    separation_velocity: np.ndarray
    restitution: np.ndarray
    peak_force: np.ndarray
    impulse: np.ndarray
    energy_lost: np.ndarray

    def __post_init__(self):
        for name in self.__dataclass_fields__:
            dtype = object if name in ("first", "second") else float
            object.__setattr__(self, name, _frozen(getattr(self, name), dtype))

    def __len__(self) -> int:
        return int(self.time.size)

    @property
    def duration(self) -> np.ndarray:
        """Contact durations in s."""
        return self.end - self.time


@dataclass(frozen=True)
class MultiBallResult:
    """A run of :func:`simulate_balls`.

    Attributes
    ----------
    model : MultiBallModel
    initial : BallState
    duration, t_end : float
        Requested and reached time in s.
    impacts : BallImpactTable
    t : ndarray
        Output times in s.
    x, v : ndarray
        Main-mass displacement (m) and velocity (m/s) at ``t``.
    y, w : ndarray (n_t, n_balls)
        Ball centres (m) and velocities (m/s) at ``t``, cavity and axis order.
    energy : EnergyBalance
        The account at ``t_end`` in J.
    success : bool
    message : str
    solver_time, compile_time : float
        Wall time in s of the compiled solver alone, and of its compilation or cache load.
    solver : str
        ``"event"``: contacts located as events, flights in closed form.
    settings : Mapping
        The numerical settings used (``rtol``, the number of ``balls``).
    excitation : Excitation or None
        The harmonic excitation of the main mass (None: free vibration).
    work_input : float
        Work in J of the excitation on the main mass over the run; the balance then reads
        ``initial + work_input = kinetic + spring + hertz + dissipated``.
    """

    model: MultiBallModel
    initial: BallState
    duration: float
    t_end: float
    impacts: BallImpactTable
    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    y: np.ndarray
    w: np.ndarray
    energy: EnergyBalance
    success: bool
    message: str
    solver_time: float
    compile_time: float = 0.0
    solver: str = "event"
    settings: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    excitation: object = None
    work_input: float = 0.0


def _table(rows: np.ndarray, model: MultiBallModel, y: np.ndarray, open_row: np.ndarray, peaks, nb: int,
           t_end: float):
    """The impact table of the filled ``rows``; contacts under way get their end, impulse and work so far."""
    rows = rows.copy()
    npair = open_row.size
    for p in np.flatnonzero(open_row >= 0):
        r = open_row[p]
        rows[r, 1] = t_end
        rows[r, 6] = peaks[p]
        rows[r, 7] = y[2 * nb + p]
        rows[r, 8] = y[2 * nb + npair + p]
    names = cavity_body_names(model)
    first_pair = np.cumsum([0] + [c.n_balls + 1 for c in model.cavities])
    idx = (first_pair[rows[:, 2].astype(int) - 1] + rows[:, 3].astype(int)) if len(rows) else np.zeros(0, int)
    with np.errstate(invalid="ignore", divide="ignore"):
        e = rows[:, 5] / rows[:, 4]
    return BallImpactTable(rows[:, 0], rows[:, 1], [names[i][0] for i in idx], [names[i][1] for i in idx],
                           rows[:, 4], rows[:, 5], e, rows[:, 6], rows[:, 7], rows[:, 8])


def _check(model, initial, duration, rtol, max_impacts):
    if not isinstance(model, MultiBallModel):
        raise ParameterError("model", f"expected a MultiBallModel, got {type(model).__name__}")
    if not isinstance(initial, BallState):
        raise ParameterError("initial", f"expected a BallState, got {type(initial).__name__}")
    if not model.underdamped:
        raise ParameterError("C", f"the multi-ball solver needs an underdamped main oscillator, C < 2 sqrt(K M) = "
                                  f"{2 * math.sqrt(model.K * model.M):g} N s/m, got {model.C:g} N s/m")
    duration = check_positive("duration", duration, "s")
    lo, hi = SOLVER_RTOL_RANGE
    if not lo <= rtol <= hi:
        raise ParameterError("rtol", f"must lie in [{lo:g}, {hi:g}], got {rtol!r}")
    if int(max_impacts) < 1:
        raise ParameterError("max_impacts", f"must be >= 1, got {max_impacts}")
    return duration


def simulate_balls(model: MultiBallModel, duration: float = 20.0, *, initial: BallState | None = None,
                   rtol: float = DEFAULT_RTOL, t_eval=None, max_impacts: int = 1_000_000,
                   progress=None, excitation=None) -> MultiBallResult:
    """Simulate a multi-ball damper from ``initial`` for ``duration`` s.

    Parameters
    ----------
    model : MultiBallModel
        The main mass and its cavities of balls.
    duration : float
        Simulated time in s.
    initial : BallState, optional
        The start (default: the paper's Figure 5, x = 0, dx/dt = 2 m/s, the balls at rest with the free
        travel of each cavity split into N + 1 equal spaces).
    rtol : float
        Relative tolerance of the integration, in :data:`~acoustiviz.constants.SOLVER_RTOL_RANGE`.
    t_eval : array_like, optional
        Non-decreasing output times in s in [0, duration].
    max_impacts : int
        Stop (``success=False``) after this many collisions.
    progress : callable, optional
        Called with the time reached (s) after each batch of steps.
    excitation : Excitation, optional
        A harmonic force ``P cos ωt + Q sin ωt`` on the main mass, or a base motion mapped to it
        (:meth:`~acoustiviz.dynamics.forced.Excitation.force_coefficients`); None: free vibration.

    Returns
    -------
    MultiBallResult

    Examples
    --------
    >>> from acoustiviz.dynamics import DamperModel
    >>> r = simulate_balls(MultiBallModel.from_damper(DamperModel(), 2), duration=0.5)
    >>> r.success, r.impacts.first[0], r.impacts.second[0]  # the left wall strikes the first ball
    (True, 'wall-', 'ball1')
    """
    initial = BallState() if initial is None else initial
    duration = _check(model, initial, duration, rtol, max_impacts)
    q0, u0 = initial.reduced(model)
    t_eval = np.zeros(0) if t_eval is None else np.ascontiguousarray(np.atleast_1d(np.asarray(t_eval, float)))
    if t_eval.ndim != 1 or not np.all(np.isfinite(t_eval)) or np.any(np.diff(t_eval) < 0) or (
            t_eval.size and (t_eval[0] < 0 or t_eval[-1] > duration)):
        raise ParameterError("t_eval", f"must be non-decreasing finite times in [0, {duration:g}] s")
    pr, mass = model.pairs(), model.masses()
    nb, npair = mass.size, pr["pa"].size
    fc = None if excitation is None else excitation.vector(model)
    y = np.concatenate([q0, u0, np.zeros(2 * npair + (1 if fc is None else 2))])
    e0 = model.energy(q0, u0)
    # absolute tolerances: positions on the scale of the largest free travel, velocities of the fastest
    # speed the initial energy allows
    gap = max(c.gap for c in model.cavities)
    uref = max(math.sqrt(2.0 * e0 / float(mass.min())), float(np.abs(u0).max()), 1e-9)
    if excitation is not None:  # the forcing brings energy: the main mass's linear speed, or the cavity's
        uref = max(uref, excitation.omega * max(abs(excitation.linear_response(model)), 0.5 * gap))
    atol = np.concatenate([np.full(nb, rtol * gap), np.full(nb, rtol * uref)])
    active = np.zeros(npair, dtype=np.bool_)
    open_row = np.full(npair, -1, dtype=np.int64)
    peaks = np.zeros(npair)
    clock = np.array([0.0, 1e-6])
    ie = np.zeros(1, dtype=np.int64)
    dense = np.empty((t_eval.size, 2 * nb))
    rows = np.empty((int(max_impacts), 9))
    n_rows = np.zeros(1, dtype=np.int64)
    args = (mass, pr["pa"], pr["pb"], pr["hg"], pr["kh"], pr["cc"], pr["cav"], pr["loc"], float(model.K),
            float(model.C), bool(model.clip_tensile), y, active, open_row, peaks, clock, float(duration), float(rtol),
            atol, t_eval, ie, dense, rows, n_rows, BATCH_STEPS, fc, None)
    compiled = compile_for(kern.run_balls, args, "multi-ball solver", BALLS_COMPILE_S)
    t0 = time.perf_counter()
    status = kern.STATUS_REACHED
    while clock[0] < duration and status == kern.STATUS_REACHED:
        status = kern.run_balls(*args)
        if progress is not None:
            progress(float(clock[0]))
    elapsed = time.perf_counter() - t0
    return _result(model, initial, duration, status, clock, y, open_row, peaks, rows[:n_rows[0]], t_eval, ie,
                   dense, e0, elapsed, compiled, rtol, excitation)


def _result(model, initial, duration, status, clock, y, open_row, peaks, rows, t_eval, ie, dense, e0, elapsed,
            compiled, rtol, excitation=None) -> MultiBallResult:
    nb = model.n_balls + 1
    q, u = y[:nb], y[nb:2 * nb]
    mass = model.masses()
    pr = model.pairs()
    d = np.maximum(q[pr["pa"]] - q[pr["pb"]] - pr["hg"], 0.0)
    impacts = _table(rows, model, y, open_row, peaks, nb, float(clock[0]))
    energy = EnergyBalance(initial=e0, kinetic=float(0.5 * np.sum(mass * u**2)), spring=0.5 * model.K * q[0] ** 2,
                           hertz=float(np.sum(0.4 * pr["kh"] * d**2.5)),
                           dissipated_main=float(y[2 * nb + 2 * pr["pa"].size]),
                           dissipated_contact=float(np.sum(impacts.energy_lost)))
    n_out = int(ie[0])
    off = model.offsets()
    messages = {kern.STATUS_REACHED: "reached the end of the run",
                kern.STATUS_MAX_IMPACTS: "stopped: the impact table is full (max_impacts)",
                kern.STATUS_STEP_UNDERFLOW: "stopped: the step size vanished"}
    return MultiBallResult(
        model=model, initial=initial, duration=duration, t_end=float(clock[0]), impacts=impacts,
        t=_frozen(t_eval[:n_out]), x=_frozen(dense[:n_out, 0]), v=_frozen(dense[:n_out, nb]),
        y=_frozen(dense[:n_out, 1:nb] + off), w=_frozen(dense[:n_out, nb + 1:2 * nb]), energy=energy,
        success=status == kern.STATUS_REACHED, message=messages[status] + f" at t = {clock[0]:.6g} s",
        solver_time=elapsed, compile_time=compiled,
        settings=MappingProxyType({"rtol": rtol, "balls": model.n_balls}), excitation=excitation,
        work_input=0.0 if excitation is None else float(y[-1]))
