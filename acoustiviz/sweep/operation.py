r"""Designs in operation: one row of summary columns per design under a harmonic excitation over a band.

A design (:class:`~acoustiviz.sweep.spec.Design` with the sweep's
:class:`~acoustiviz.sweep.spec.FixedSettings`) works under the excitation of an :class:`Operation`:
a force ``F0 cos(ωt)`` on the main mass or a base motion ``B cos(ωt)``, at each frequency of a band.
Every attractor of each frequency is looked for as ``acoustiviz forced`` does
(:func:`acoustiviz.dynamics.forced.attractor_response`: several starts per frequency, shooting,
batch statistics of non-periodic motion, continuation along the band), and its steady click train is
heard at the design's listener (:func:`acoustiviz.sound.operating.operating_noise`: LCpeak, LAeq and
LAFmax over whole periods after a settled lead-in). :func:`evaluate_in_operation` condenses all of it
into one row (:data:`OPERATION_COLUMNS`, defined in :data:`OPERATION_DEFINITIONS`): the worst case
over the band and every attractor, which is what an optimiser ranks designs by.

A design of several balls (``Design.balls > 1``) has its attractors found as ``acoustiviz forced --balls``
finds them (:func:`acoustiviz.dynamics.balls_forced.ball_attractor_response`, the event solver only) and
its steady collisions heard as ``forced --balls`` hears them
(:func:`acoustiviz.sound.balls_operating.balls_operating_noise`, each ball a sphere of its own radius).
Only a design of the same balls and dynamics gives it its attractors (``warm_radius`` applies to one ball:
the final states of balls of another size or gap need not fit its cavity).

Warm starts
-----------
Neighbouring designs of a sweep have neighbouring attractors. A :class:`WarmStart` holds the
attractors of the designs already evaluated by one worker. A design with the same dynamics as a
cached one (the same gap, impact mass, contact damping and Hertz stiffness: another listener or
configuration) takes its attractors as they are, exactly what its own search would find. With
``warm_radius`` > 0, a design within that largest relative difference of those four parameters
of a cached one starts, at each frequency, from the nearest one's attractors (each continued by
:data:`acoustiviz.dynamics.forced.continuation_seed`: a periodic orbit's section point and period,
a non-periodic motion's final state) and from the first ``warm_starts`` of its own starts (the
linear start), instead of all ``starts`` starts and the continuation rounds.

That shortcut is off by default, because it can miss an attractor. Coexisting attractors' basins
move fast with the design: on the Table 1 damper at 5 Hz every start of m = 40.5 g ends on one
chaotic motion, while at 41.5 g five of the six starts end on a periodic orbit and one on a chaotic
motion 6 % larger, which neither the 40.5 g attractor nor the linear start reaches; the worst case
of the warm-started search is then the periodic orbit, 27 standard errors below the search from
scratch (``benchmarks/results/operation.md``). With every own start (``warm_starts = starts``) the
neighbour's attractors only add to the search, at about its cost from scratch.

Which designs seed which is fixed by the design list alone: :func:`run_operation` cuts the designs,
in grid order, into chains of ``chain`` consecutive designs, each chain evaluated in order in one
worker with a fresh cache. The rows therefore depend on the designs and the chain length, never on
the number of workers, the executor or the order in which chains finish.

SI units: m, kg, N, Hz; levels in dB re 20 µPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .._validate import check_choice, check_range
from ..constants import (
    EXCITATIONS,
    FORCED_MAX_CYCLES,
    FORCED_MAX_STARTS,
    FORCED_RTOL,
    FORCED_STARTS,
    FORCED_TOLERANCE,
    FREQUENCY_SWEEPS,
)
from ..errors import ParameterError
from .spec import Design, FixedSettings

__all__ = ["OPERATION_COLUMNS", "OPERATION_DEFINITIONS", "operation_columns", "Operation",
           "WarmStart", "evaluate_in_operation", "evaluate_in_operation_or_fail", "failed_operation_row",
           "evaluate_chain", "operation_chains", "run_operation", "run_chains", "check_operation"]

#: Column -> its unit and definition (one row per design; "attractor" means every attractor of every
#: frequency of the band whose run the solver completed).
OPERATION_DEFINITIONS = {
    "design_id": "position of the design in the sweep's grid",
    "gap_m": "total free travel d of the impact mass, m",
    "mass_kg": "impact mass m, kg",
    "c1_n_s_m": "contact damping c1, N s/m",
    "k_hertz_n_m1_5": "Hertz stiffness, N/m^1.5",
    "material": "sphere material ('' when K_HZ was given)",
    "distance_m": "listener distance from the sphere's centre, m",
    "angle_deg": "listener angle from the acceleration axis, degrees",
    "config": "configuration of the sphere's surroundings",
    "radius_m": "radius of the radiating sphere, m",
    "worst_amplitude_m": "largest main-mass amplitude (half peak-to-peak; the batch mean of a non-periodic "
                         "motion) over the band and every attractor, m",
    "worst_amplitude_std_err_m": "standard error of worst_amplitude_m from the batch means (0: periodic), m",
    "worst_frequency_hz": "frequency of worst_amplitude_m, Hz",
    "worst_regime": "regime of the attractor of worst_amplitude_m",
    "max_amplitude_without_damper_m": "largest amplitude of the main mass alone over the band "
                                      "(linear steady state, exact), m",
    "min_reduction_db": "smallest reduction 20 log10(A without / A with the damper) over the band and every "
                        "attractor (the linear amplitude without the damper exact), dB",
    "mean_reduction_db": "mean over the band's frequencies of each frequency's smallest reduction, dB",
    "worst_lcpeak_db": "largest LCpeak of the steady click train at the listener over the band and every "
                       "attractor, dB re 20 uPa (-inf: no impact; empty without levels)",
    "worst_laeq_db": "largest LAeq over whole periods, same attractors, dB re 20 uPa (empty as worst_lcpeak_db)",
    "worst_lafmax_db": "largest LAFmax, same attractors, dB re 20 uPa (empty as worst_lcpeak_db)",
    "chaotic_fraction": "fraction of the band's frequencies at which an attractor is chaotic (several balls: "
                        "non-periodic, their motions having no Lyapunov exponent)",
    "attractors": "attractors found over the band (summed over the frequencies)",
    "failed_runs": "attractor runs the solver stopped (left out of every other column)",
    "cycles_integrated": "forcing cycles integrated for the design (every start, seed, shooting, window)",
    "warm_from": "design_id whose attractors started this design's search (-1: from scratch)",
    "success": "1 when every run completed, else 0 with the reason in error",
    "error": "why the design failed, one line",
}
#: The columns of a design's row, in order (:func:`operation_columns`: with ``balls`` and ``fill``).
OPERATION_COLUMNS = tuple(OPERATION_DEFINITIONS)
#: The level columns and the :class:`~acoustiviz.sound.operating.OperatingNoise` attribute of each.
_LEVELS = {"worst_lcpeak_db": "lcpeak_db", "worst_laeq_db": "laeq_db", "worst_lafmax_db": "lafmax_db"}

@dataclass(frozen=True)
class Operation:
    """The excitation a design works under, over a band of frequencies, and how its attractors are found.

    Parameters
    ----------
    amplitude : float
        Force amplitude F0 in N (``kind="force"``) or base displacement amplitude B in m (``"base"``).
    frequencies : tuple of float
        Forcing frequencies in Hz (> 0, distinct; kept sorted).
    kind : {"force", "base"}
    sweep : {"up", "down", "both", "independent"}
        Continuation of the attractors along the band (:func:`acoustiviz.dynamics.forced.attractor_response`).
    solver : {"event", "impact-map", "newmark"}
    starts : int
        Starts per frequency of a search from scratch.
    tolerance : float
        Newton residual of a periodic orbit, m and m/s.
    rtol : float
        Relative tolerance of the contact integration (event solver).
    max_cycles : int
        Cycles each start runs before its motion is measured as non-periodic.
    restitution : float or None
        Impact-map restitution (None: the compliant contact's at each speed).
    levels : bool
        Hear each attractor's click train at the design's listener (the level columns; otherwise empty).
    noise_seconds : float or None
        Least length in s of each level interval, (0, 60] (None: that of
        :func:`acoustiviz.sound.operating.operating_noise`, as ``acoustiviz forced``).
    warm_starts : int
        Own starts of a warm-started design (the first of :func:`acoustiviz.dynamics.forced.start_states`:
        1 is the linear start), 0 to ``starts``.
    warm_radius : float
        Largest relative difference of gap, impact mass, contact damping and Hertz stiffness to a design
        already evaluated for its attractors to start this one's search with ``warm_starts`` own starts
        (module docstring: it may miss an attractor). 0 (default): only a design of the same dynamics,
        whose attractors are then taken as they are (always so for several balls).
    """

    amplitude: float
    frequencies: tuple
    kind: str = "force"
    sweep: str = "up"
    solver: str = "event"
    starts: int = FORCED_STARTS
    tolerance: float = FORCED_TOLERANCE
    rtol: float = FORCED_RTOL
    max_cycles: int = FORCED_MAX_CYCLES
    restitution: float | None = None
    levels: bool = True
    noise_seconds: float | None = None
    warm_starts: int = 1
    warm_radius: float = 0.0

    def __post_init__(self):
        from ..dynamics._forced_response import _frequencies
        from ..dynamics.forced import Excitation

        check_choice("kind", self.kind, EXCITATIONS)
        check_choice("sweep", self.sweep, FREQUENCY_SWEEPS)
        f = tuple(float(x) for x in _frequencies(self.frequencies))
        object.__setattr__(self, "frequencies", f)
        Excitation(f[0], self.amplitude, self.kind)  # the amplitude's range, in one place
        if not isinstance(self.levels, bool):
            raise ParameterError("levels", f"must be True or False, got {self.levels!r}")
        if self.noise_seconds is not None:
            check_range("noise_seconds", self.noise_seconds, 0.0, 60.0, low_open=True, unit="s")
        top = self.starts if _is_int(self.starts) else FORCED_MAX_STARTS  # starts itself: check_operation
        if not _is_int(self.warm_starts) or not 0 <= self.warm_starts <= top:
            raise ParameterError("warm_starts", f"must be an integer in [0, starts = {top}], got {self.warm_starts!r}")
        check_range("warm_radius", self.warm_radius, 0.0, math.inf)

    def options(self):
        """The :class:`~acoustiviz.dynamics.forced.SteadyStateOptions` of a search from scratch.

        Screened checkpoints (:data:`acoustiviz.dynamics.forced.SCREENED_CHECKPOINT_RETURN`): a design's
        worst case is that of its large attractors; a shooting from a point far from any return, which
        rarely converges, is left out (it may skip an orbit with a small basin that one start reached so).
        A start whose shooting lands on a stable orbit already found at its frequency ends there without
        measuring it again (``reuse_known``: the same attractors, fewer cycles).
        """
        from ..dynamics.forced import SCREENED_CHECKPOINT_RETURN, SteadyStateOptions

        return SteadyStateOptions(solver=self.solver, restitution=self.restitution, tolerance=self.tolerance,
                                  rtol=self.rtol, max_cycles=self.max_cycles, starts=self.starts,
                                  checkpoint_return=SCREENED_CHECKPOINT_RETURN,
                                  reuse_known=True)

    def excitation(self, frequency: float):
        """The :class:`~acoustiviz.dynamics.forced.Excitation` at ``frequency`` Hz."""
        from ..dynamics.forced import Excitation

        return Excitation(float(frequency), self.amplitude, self.kind)


def operation_columns(with_balls: bool) -> tuple:
    """:data:`OPERATION_COLUMNS`, with ``balls`` and ``fill`` after ``radius_m`` when the designs name their balls.

    The rule of ``sweep.csv`` in free vibration (:func:`acoustiviz.sweep.store.row_columns`): a sweep that names
    neither balls nor fills writes the columns it always wrote.
    """
    from .store import row_columns

    return row_columns(with_balls, OPERATION_COLUMNS)


def _is_int(v) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


def _model(design: Design, fixed: FixedSettings):
    """The damper of ``design``: a DamperModel, or with several balls their MultiBallModel."""
    from ..dynamics import DamperModel

    if design.balls > 1:
        from .balls import design_balls_model

        return design_balls_model(design, fixed)[1]

    return DamperModel(M=fixed.M, K=fixed.K, C=fixed.C, m=design.m, gap=design.gap, k_hertz=design.k_hertz,
                       c1=design.c1, clip_tensile=fixed.clip_tensile)


def check_operation(designs, fixed: FixedSettings, operation: Operation) -> None:
    """Every check before any work: the forced settings and the band against each design's damper.

    Raises
    ------
    ParameterError
        Named after the :class:`Operation` field (``starts``, ``tolerance``, ``frequencies``...).
    """
    from ..core.limits import check_forcing_frequencies
    from ..dynamics.balls_forced import check_ball_settings
    from ..dynamics.forced import check_settings

    if not isinstance(operation, Operation):
        raise ParameterError("operation", f"expected an Operation, got {type(operation).__name__}")
    check_forcing_frequencies(operation.frequencies, M=fixed.M, K=fixed.K)
    for d in designs:
        model = _model(d, fixed)
        check = check_ball_settings if d.balls > 1 else check_settings  # several balls: the event solver only
        check(model, operation.excitation(operation.frequencies[0]), operation.options())
        for f in operation.frequencies[1:]:
            operation.excitation(f).linear_response(model)  # an undamped resonance is refused


# --------------------------------------------------------------------------- warm starts
def _key(design: Design) -> tuple:
    """The parameters that set a design's dynamics under the sweep's fixed settings."""
    return design.gap, design.m, design.c1, design.k_hertz


def _distance(a: tuple, b: tuple) -> float:
    """Largest relative difference of two :func:`_key` tuples (0: the same dynamics)."""
    return max((abs(x - y) / max(abs(x), abs(y)) if x != y else 0.0) for x, y in zip(a, b, strict=True))


def _kind(design: Design) -> tuple:
    """What must match for attractors to seed each other: the balls (and their material, which sizes them)."""
    return (design.balls, design.material) if design.balls > 1 else (1, "")


@dataclass(frozen=True)
class _Cached:
    design_id: int
    key: tuple
    per_frequency: tuple
    kind: tuple = (1, "")


class WarmStart:
    """The attractors of the designs one worker has evaluated, to start the next designs' searches.

    Filled by :func:`evaluate_in_operation`; hand the same object to the evaluations of one chain
    of designs, in order (module docstring).
    """

    def __init__(self):
        self._cached: list[_Cached] = []

    def __len__(self) -> int:
        return len(self._cached)

    def nearest(self, design: Design, radius: float) -> tuple[_Cached | None, float]:
        """The cached design nearest to ``design`` within ``radius`` (earliest on a tie) and its distance."""
        key, kind = _key(design), _kind(design)
        radius = radius if design.balls == 1 else 0.0  # other balls' final states may not fit this cavity
        best, dist = None, math.inf
        for c in (c for c in self._cached if c.kind == kind):  # a section point has 2 + 2 N values
            d = _distance(key, c.key)
            if d < dist:
                best, dist = c, d
        return (best, dist) if best is not None and dist <= radius else (None, math.inf)

    def add(self, design: Design, per_frequency: tuple) -> None:
        """Keep ``design``'s attractors (a tuple of FrequencyAttractors, one per frequency)."""
        self._cached.append(_Cached(design.design_id, _key(design), tuple(per_frequency), _kind(design)))


def _search(model, operation: Operation, source: _Cached | None, distance: float) -> tuple:
    """The attractors per frequency: from scratch, from ``source``'s, or ``source``'s when ``distance`` is 0.

    One ball: :func:`acoustiviz.dynamics.forced.attractor_response`; several balls (a ``MultiBallModel``):
    :func:`acoustiviz.dynamics.balls_forced.ball_attractor_response`, as ``acoustiviz forced --balls`` runs them.
    """
    from ..dynamics import MultiBallModel, forced
    from ..dynamics import balls_forced as balls

    if source is None:
        several = isinstance(model, MultiBallModel)
        respond = balls.ball_attractor_response if several else forced.attractor_response
        resp = respond(model, operation.frequencies, operation.amplitude, kind=operation.kind,
                       sweep=operation.sweep, settings=operation.options())
        return resp.per_frequency
    if distance == 0.0:
        return source.per_frequency
    warm = replace(operation.options(), starts=operation.warm_starts)
    out = []
    for f, fa in zip(operation.frequencies, source.per_frequency, strict=True):  # one ball (WarmStart.nearest)
        seeds = tuple(forced.continuation_seed(a) for a in fa.attractors if a.success)
        out.append(forced.attractors_at(model, operation.excitation(f), warm, seeds=seeds))
    return tuple(out)


# --------------------------------------------------------------------------- one design
def _design_cells(design: Design, fixed: FixedSettings) -> dict:
    return {"design_id": design.design_id, "gap_m": design.gap, "mass_kg": design.m, "c1_n_s_m": design.c1,
            "k_hertz_n_m1_5": design.k_hertz, "material": design.material, "distance_m": design.distance,
            "angle_deg": math.degrees(design.angle), "config": design.config, "radius_m": design.radius,
            **({} if design.fill is None else {"balls": design.balls, "fill": design.fill})}


def _chaotic(a) -> bool:
    """Whether a steady motion counts as chaotic: several balls' non-periodic motions have no Lyapunov exponent."""
    return a.regime == "chaotic" or (a.regime == "unresolved" and getattr(a.model, "n_balls", 1) > 1)


def _noise(steady, design: Design, fixed: FixedSettings, operation: Operation):
    """The :class:`~acoustiviz.sound.operating.OperatingNoise` of one attractor at the design's listener.

    One ball: :func:`acoustiviz.sound.operating.operating_noise`; several balls (a ``MultiBallModel``):
    :func:`acoustiviz.sound.balls_operating.balls_operating_noise`, with the same listener, surroundings
    and length, as ``acoustiviz forced --balls`` hears them.
    """
    from ..core.geometry import geometry_class
    from ..core.medium import Medium
    from ..dynamics import MultiBallModel
    from ..sound.balls_operating import balls_operating_noise
    from ..sound.operating import operating_noise
    from .evaluate import listener_point

    geometry = design.geometry(fixed)
    point = listener_point(geometry, design.distance, design.angle)[0]
    medium = Medium(c=fixed.c, rho=fixed.rho)
    own = geometry_class(design.config).relevant(fixed.geometry_settings)  # the design's geometry's settings
    where = {"room": own} if geometry.enclosed else own
    seconds = {} if operation.noise_seconds is None else {"seconds": operation.noise_seconds}
    hear = balls_operating_noise if isinstance(steady.model, MultiBallModel) else operating_noise
    return hear(steady, listener=point, kind=design.config, radius=design.radius,
                settings={**where, "medium": medium}, **seconds)


def summarise(per_frequency, levels=None) -> dict:
    """The summary columns of the attractors of each frequency (``levels``: per attractor, in the same order).

    Parameters
    ----------
    per_frequency : sequence of FrequencyAttractors
        One per frequency of the band.
    levels : list of list of dict, optional
        Per frequency and attractor, ``{"lcpeak_db", "laeq_db", "lafmax_db"}`` in dB (None: not heard).

    Returns
    -------
    dict
        The columns of :data:`OPERATION_COLUMNS` from ``worst_amplitude_m`` to ``failed_runs`` and
        ``cycles_integrated``.
    """
    ok = [(i, j, a) for i, fa in enumerate(per_frequency) for j, a in enumerate(fa.attractors) if a.success]
    nan = math.nan
    row = {c: nan for c in OPERATION_COLUMNS[10:21]}
    row.update(worst_regime="", attractors=sum(len(fa.attractors) for fa in per_frequency),
               failed_runs=sum(not a.success for fa in per_frequency for a in fa.attractors),
               cycles_integrated=sum(fa.cycles_integrated for fa in per_frequency))
    lin = [abs(fa.excitation.linear_response(fa.attractors[0].model)) for fa in per_frequency if fa.attractors]
    if lin:
        row["max_amplitude_without_damper_m"] = max(lin)
    if not ok:
        return row
    i, _, w = max(ok, key=lambda t: t[2].amplitude)  # the first of equal amplitudes
    row.update(worst_amplitude_m=w.amplitude, worst_amplitude_std_err_m=w.amplitude_std_err,
               worst_frequency_hz=w.excitation.frequency, worst_regime=w.regime,
               min_reduction_db=min(a.reduction_db for _, _, a in ok))
    per_f = {}
    for i, _, a in ok:
        per_f[i] = min(per_f.get(i, math.inf), a.reduction_db)
    row["mean_reduction_db"] = float(np.mean(list(per_f.values())))
    chaotic = {i for i, _, a in ok if _chaotic(a)}
    row["chaotic_fraction"] = len(chaotic) / len(per_frequency)
    if levels is not None:
        for col, name in _LEVELS.items():
            row[col] = max(levels[i][j][name] for i, j, _ in ok)
    return row


def evaluate_in_operation(design: Design, fixed: FixedSettings, operation: Operation, *,
                          warm: WarmStart | None = None) -> dict:
    """One design in operation over the band: its row of :data:`OPERATION_COLUMNS`.

    Parameters
    ----------
    design : Design
    fixed : FixedSettings
        The sweep's fixed settings (main system, air, wall distance or room).
    operation : Operation
    warm : WarmStart, optional
        The attractors of designs evaluated before (module docstring); this design's are added.

    Returns
    -------
    dict
        Column -> value (SI; levels in dB re 20 µPa).
    """
    model = _model(design, fixed)
    source, distance = warm.nearest(design, operation.warm_radius) if warm is not None else (None, math.inf)
    per_frequency = _search(model, operation, source, distance)
    if warm is not None:
        warm.add(design, per_frequency)
    levels = None
    if operation.levels:
        levels = [[{k: getattr(nz, k) for k in _LEVELS.values()} if nz is not None else None
                   for nz in (_noise(a, design, fixed, operation) if a.success else None for a in fa.attractors)]
                  for fa in per_frequency]
    row = {**_design_cells(design, fixed), **summarise(per_frequency, levels)}
    if levels is None:
        row.update(dict.fromkeys(_LEVELS, math.nan))
    failed = [a for fa in per_frequency for a in fa.attractors if not a.success]
    why = f"{failed[0].excitation.frequency:g} Hz: {failed[0].message}" if failed else ""
    row.update(warm_from=-1 if source is None else source.design_id, success=int(not failed),
               error=" ".join(why.split()))
    return {c: row[c] for c in operation_columns(design.fill is not None)}


def failed_operation_row(design: Design, fixed: FixedSettings, reason: str) -> dict:
    """The row of a design that could not be evaluated: NaN values, ``success`` 0, ``reason`` on one line."""
    row = dict.fromkeys(operation_columns(design.fill is not None), math.nan)
    row.update(_design_cells(design, fixed), worst_regime="", attractors=0, failed_runs=0, cycles_integrated=0,
               warm_from=-1, success=0, error=" ".join(str(reason).split()) or "unknown error")
    return row


def evaluate_in_operation_or_fail(design: Design, fixed: FixedSettings, operation: Operation, *,
                                  warm: WarmStart | None = None) -> dict:
    """:func:`evaluate_in_operation`, or a failed row naming the exception that stopped it.

    ``KeyboardInterrupt`` and ``SystemExit`` still propagate.
    """
    try:
        return evaluate_in_operation(design, fixed, operation, warm=warm)
    except Exception as exc:  # noqa: BLE001 - any failure of one design is recorded in its row
        return failed_operation_row(design, fixed, f"{type(exc).__name__}: {exc}")


def evaluate_chain(designs, fixed: FixedSettings, operation: Operation) -> list:
    """The rows of a chain of designs evaluated in order with one :class:`WarmStart` (one executor task)."""
    warm = WarmStart()
    return [evaluate_in_operation_or_fail(d, fixed, operation, warm=warm) for d in designs]


def operation_chains(designs, chain: int) -> list:
    """``designs`` cut, in order, into chains of ``chain`` consecutive designs (the last may be shorter)."""
    if isinstance(chain, bool) or int(chain) != chain or chain < 1:
        raise ParameterError("chain", f"must be an integer >= 1, got {chain!r}")
    designs = tuple(designs)
    return [designs[k:k + int(chain)] for k in range(0, len(designs), int(chain))]


# --------------------------------------------------------------------------- many designs
def _chain_failed(designs, fixed, exc) -> list:
    from .execute import _is_broken_pool

    why = (f"the worker process died ({type(exc).__name__}: {exc})" if _is_broken_pool(exc)
           else f"{type(exc).__name__}: {exc}")
    return [failed_operation_row(d, fixed, why) for d in designs]


def run_operation(spec, operation: Operation, *, executor=None, workers: int | None = None, chain: int = 8,
                  progress=None, on_rows=None) -> list:
    """Every design of ``spec`` in operation: one row per design, in design order.

    Parameters
    ----------
    spec : SweepSpec
        The designs and the fixed settings.
    operation : Operation
    executor : None, "process", "dask://HOST:PORT" or concurrent.futures.Executor
        Where the chains run, as for :func:`acoustiviz.sweep.run_sweep` (None or ``"process"``: a
        local process pool of ``workers`` processes; an Executor is used as given, not shut down).
    workers : int, optional
        Processes of the local pool (default ``os.cpu_count()``).
    chain : int
        Consecutive designs evaluated in order by one task with one :class:`WarmStart`; the rows
        depend on it (module docstring), not on ``workers`` or the executor. 1: every design from
        scratch.
    progress : callable, optional
        Called with a one-line message after each chain.
    on_rows : callable, optional
        Called in this process with the rows of each chain as it finishes (to keep them, e.g. in a
        journal, before the sweep ends or is interrupted).

    Returns
    -------
    list of dict
        The rows (:data:`OPERATION_COLUMNS`); a design whose evaluation raised, or whose worker
        died, has ``success`` 0 and the reason in ``error``. On ``KeyboardInterrupt`` the pending
        chains are cancelled, the pool stopped and the interrupt propagates.
    """
    from .execute import check_executor_form
    from .spec import SweepSpec

    if not isinstance(spec, SweepSpec):
        raise ParameterError("spec", f"expected a SweepSpec, got {type(spec).__name__}")
    if workers is not None and (int(workers) != workers or workers < 1):
        raise ParameterError("workers", f"must be an integer >= 1, got {workers!r}")
    check_executor_form(executor)
    designs = spec.designs()
    check_operation(designs, spec.settings, operation)
    chains = operation_chains(designs, chain)
    rows = run_chains(chains, spec.settings, operation, executor=executor, workers=workers, progress=progress,
                      on_rows=on_rows, total=len(designs))
    return [rows[d.design_id] for d in designs]


def run_chains(chains, fixed: FixedSettings, operation: Operation, *, executor=None, workers: int | None = None,
               progress=None, on_rows=None, total: int | None = None) -> dict:
    """The rows of the chains of designs ``chains`` (:func:`operation_chains`), keyed by design id.

    What :func:`run_operation` does once its inputs are checked; a resumed sweep hands it only the chains
    it still lacks (:mod:`acoustiviz.sweep.in_operation`). ``total`` is the designs counted by ``progress``
    (default: those of ``chains``).
    """
    from concurrent.futures import FIRST_COMPLETED, wait

    from .execute import _interruptible, _sigint_blocked, make_executor, shutdown_now

    total = sum(len(c) for c in chains) if total is None else total
    rows = {}
    if not chains:
        return rows
    with _interruptible():
        ex, kind, cleanup, _ = make_executor(executor, workers, fixed, len(chains))
        interrupted = True
        try:
            with _sigint_blocked():  # the first submission forks a local pool's workers
                running = {ex.submit(evaluate_chain, c, fixed, operation): c for c in chains}
            while running:
                done, _ = wait(running, return_when=FIRST_COMPLETED)
                for fut in [f for f in running if f in done]:
                    c = running.pop(fut)
                    try:
                        out = fut.result()
                    except Exception as exc:  # noqa: BLE001 - recorded in the chain's rows
                        out = _chain_failed(c, fixed, exc)
                    rows.update((r["design_id"], r) for r in out)
                    if on_rows is not None:
                        on_rows(out)
                    if progress:
                        progress(f"operation: {len(rows)} of {total} designs")
            interrupted = False
        finally:
            if kind != "given":
                if interrupted:
                    shutdown_now(ex)
                else:
                    ex.shutdown(wait=True)
            if cleanup is not None:
                cleanup()
    return rows
