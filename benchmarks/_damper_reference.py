"""Converged reference runs and solver comparisons for the impact damper (a test harness).

Kept outside the installed package: the benchmarks, the tests (``pythonpath = ["benchmarks"]``
in the pytest settings) and the gallery import it as ``_damper_reference``.

The Table 1 motion is chaotic: a change of one part in 1e14 in the initial velocity grows to
about 1e-7 by the 35th impact and the impact sequence changes after roughly 50 impacts. Solvers
are therefore compared impact by impact over the first 40 impacts only, and a method of a given
accuracy only over the leading impacts it resolves (:func:`resolved_impacts`).

Reference
---------
:func:`reference` is the event-driven solver at ``rtol = REFERENCE_RTOL`` (2e-15). It is checked
(in ``benchmarks/bench_dynamics.py``) by its energy closure, by its agreement with the same solver
at 2.5× looser tolerance, and by a second, independent method, :func:`solve_ivp_impacts`
(scipy's DOP853 with terminal events, stopping and restarting at every contact onset and end).
That method is run at tolerances well above the round-off floor of double precision
(:data:`IVP_MIN_RTOL`): at 3e-14 scipy's step-size control gives up or not depending on the
CPU and the math library's rounding.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from acoustiviz.dynamics import TABLE1, DamperModel, ImpactTable, InitialState, SimulationResult, simulate
from acoustiviz.dynamics.metrics import damping_metrics
from acoustiviz.errors import AccuracyWarning

__all__ = [
    "REFERENCE_RTOL",
    "N_COMPARE",
    "ImpactComparison",
    "BenchmarkRow",
    "reference",
    "compare_impacts",
    "solve_ivp_impacts",
    "resolved_impacts",
    "RESOLVED_BOUND",
    "speed_accuracy",
    "IVP_MIN_RTOL",
    "IVP_RTOL",
]

#: Contact tolerance of the reference run.
REFERENCE_RTOL = 2e-15
#: Number of leading impacts compared (the motion is chaotic beyond about 50).
N_COMPARE = 40
#: Finest tolerance :func:`solve_ivp_impacts` accepts: 450 times the double-precision epsilon.
#: Below about 1e-13 scipy's DOP853 may stop with "required step size is less than spacing
#: between numbers", depending on the CPU's and the math library's rounding.
IVP_MIN_RTOL = 1e-13
#: Tolerance of the independent method in the reference checks (4500 epsilon: far from the floor).
IVP_RTOL = 1e-12


@dataclass(frozen=True)
class ImpactComparison:
    """Agreement of two impact tables over their first ``n`` impacts.

    Attributes
    ----------
    n : int
        Number of impacts compared (fewer than requested if a table is shorter).
    time_error : float
        Largest |difference| of contact start times in s.
    velocity_error : float
        Largest relative difference of approach speeds (dimensionless).
    walls_match : bool
        Whether the walls struck agree impact by impact.
    n_agree : int
        Number of leading impacts on the same wall with approach speeds within 1e-3 (relative):
        how long a solver follows the reference before the chaotic motion takes it elsewhere.
    """

    n: int
    time_error: float
    velocity_error: float
    walls_match: bool
    n_agree: int = 0


@dataclass(frozen=True)
class BenchmarkRow:
    """One solver setting of the speed-versus-accuracy benchmark.

    Attributes
    ----------
    solver : str
    label : str
        The setting, e.g. ``"dt=1e-07"`` or ``"rtol=1e-14"``.
    time_s : float
        Warm solver wall time in s (best of the repeats).
    n_impacts : int
        Impacts over the whole run.
    comparison : ImpactComparison
        Against the reference over the first :data:`N_COMPARE` impacts.
    energy_error : float
        Relative energy closure error of the run (dimensionless).
    inclination_error : float
        Relative error of the damping inclination of eq 16 (first two exact positive maxima)
        against the reference's (dimensionless).
    """

    solver: str
    label: str
    time_s: float
    n_impacts: int
    comparison: ImpactComparison
    energy_error: float
    inclination_error: float = math.nan


def reference(model: DamperModel = TABLE1, duration: float = 20.0,
              initial: InitialState | None = None, t_eval=None) -> SimulationResult:
    """The converged reference run (event solver at :data:`REFERENCE_RTOL`)."""
    return simulate(model, duration, solver="event", initial=initial, rtol=REFERENCE_RTOL,
                    t_eval=t_eval)


def compare_impacts(table: ImpactTable, ref: ImpactTable, n: int = N_COMPARE) -> ImpactComparison:
    """Compare the first ``n`` impacts of ``table`` with those of ``ref``.

    If either table is shorter than ``n`` the comparison covers the common part and its errors
    are infinite when the shorter one is ``table`` (a missed impact is a failure).
    """
    k = min(n, len(table), len(ref))
    if k == 0:
        return ImpactComparison(0, math.inf, math.inf, False, 0)
    rel = np.abs(table.approach_velocity[:k] / ref.approach_velocity[:k] - 1.0)
    dt = float(np.max(np.abs(table.time[:k] - ref.time[:k])))
    du = float(np.max(rel))
    walls = bool(np.array_equal(table.wall[:k], ref.wall[:k]))
    bad = np.flatnonzero((rel > 1e-3) | (table.wall[:k] != ref.wall[:k]))
    agree = int(bad[0]) if bad.size else k
    if len(table) < min(n, len(ref)):
        dt = du = math.inf
    return ImpactComparison(k, dt, du, walls, agree)


def solve_ivp_impacts(model: DamperModel = TABLE1, initial: InitialState | None = None,
                      n_impacts: int = 10, rtol: float = 1e-13) -> ImpactTable:
    """First ``n_impacts`` contacts by an independent method: scipy DOP853 with terminal events.

    The right-hand side of eq 15 is evaluated in Python; each free flight and each contact is a
    separate ``solve_ivp`` call stopped by an event at the contact onset (``|y - x| = d/2``
    reached from inside) or end (penetration back to zero). Slow (seconds), for checking only.

    Parameters
    ----------
    model : DamperModel
    initial : InitialState, optional
    n_impacts : int
        Number of contacts to compute.
    rtol : float
        Relative tolerance of solve_ivp (absolute tolerance 1e-15 in m and m/s), at least
        :data:`IVP_MIN_RTOL`.

    Returns
    -------
    ImpactTable
        Exactly ``n_impacts`` rows. Peak force, impulse and energy lost are NaN (not computed by
        this method).

    Raises
    ------
    ValueError
        If ``rtol`` is below :data:`IVP_MIN_RTOL`.
    RuntimeError
        If an integration stops before its event, naming the impact, the time and scipy's message.
    """
    from scipy.integrate import solve_ivp

    if not rtol >= IVP_MIN_RTOL:
        raise ValueError(f"rtol: at least {IVP_MIN_RTOL:g} (the round-off floor of double precision), got {rtol!r}")

    initial = InitialState() if initial is None else initial
    M, K, C, m = model.M, model.K, model.C, model.m
    hg, kh, c1, clip = 0.5 * model.gap, model.k_hertz, model.c1, model.clip_tensile

    def rhs_for(s):
        def rhs(_t, q):
            x, v, y, w = q
            f = 0.0
            if s != 0:
                d = s * (y - x) - hg
                if d > 0:
                    f = kh * d**1.5 + c1 * s * (w - v)
                    if clip and f < 0:
                        f = 0.0
            return [v, (s * f - K * x - C * v) / M, w, -s * f / m]

        return rhs

    def crossing(s, direction):
        def g(_t, q):
            return s * (q[2] - q[0]) - hg

        g.terminal = True
        g.direction = direction
        return g

    q = np.array(initial.as_tuple(model))
    t0 = 0.0
    rows = []
    period = 2 * math.pi / model.main_frequency

    def phase(rhs, q, events, what, **kw):
        sol = solve_ivp(rhs, (t0, t0 + 50 * period), q, method="DOP853", rtol=rtol, atol=1e-15,
                        events=events, **kw)
        if sol.status != 1:  # a failure is reported, never a silently shorter table
            raise RuntimeError(f"solve_ivp_impacts: the {what} of impact {len(rows) + 1} of {n_impacts} "
                               f"(after t = {t0:.9g} s) did not end: {sol.message}")
        return sol

    while len(rows) < n_impacts:
        sol = phase(rhs_for(0), q, [crossing(1, 1), crossing(-1, 1)], "free flight before the onset")
        k = 0 if sol.t_events[0].size else 1
        s = 1 if k == 0 else -1
        t0 = float(sol.t_events[k][0])
        q = sol.y_events[k][0]
        u0 = s * (q[3] - q[1])
        sol = phase(rhs_for(s), q, [crossing(s, -1)], "contact", first_step=1e-9)
        t1 = float(sol.t_events[0][0])
        q = sol.y_events[0][0]
        rows.append((t0, s, u0, -s * (q[3] - q[1]), t1 - t0, math.nan, math.nan, math.nan))
        t0 = t1
    return ImpactTable.from_rows(np.array(rows))


#: Impacts are compared while the independent method's runs 10x apart in tolerance agree to this
#: (s); its own error there is at most about 1.5e-10 s (:func:`resolved_impacts`).
RESOLVED_BOUND = 1e-10


def resolved_impacts(table: ImpactTable, coarser: ImpactTable, bound: float) -> int:
    """Number of leading impacts a method resolves to within ``bound`` seconds.

    ``table`` and ``coarser`` are the same method at two tolerances, the second ten times looser.
    The method's error grows with its tolerance (and, impact after impact, with the motion's own
    sensitivity), so ``|t_coarser - t_table|`` estimates the error of ``table``: for scipy's DOP853
    on the Table 1 damper the error falls only about 2.2x for the 10x tighter tolerance, so
    ``table`` is off the reference by 1.2 to 1.5 times that difference (measured over the first 22
    impacts). The count is that of the leading impacts on the same walls whose
    difference stays below ``bound``: beyond it the chaotic growth of the method's own error
    takes over.

    Parameters
    ----------
    table, coarser : ImpactTable
    bound : float
        Time resolution asked for, in s.

    Returns
    -------
    int
    """
    k = min(len(table), len(coarser))
    bad = np.flatnonzero((np.abs(table.time[:k] - coarser.time[:k]) >= bound)
                         | (table.wall[:k] != coarser.wall[:k]))
    return int(bad[0]) if bad.size else k


def speed_accuracy(cases, *, model: DamperModel = TABLE1, duration: float = 20.0,
                   initial: InitialState | None = None, ref: SimulationResult | None = None,
                   n_compare: int = N_COMPARE, repeats: int = 3) -> list[BenchmarkRow]:
    """Run each solver setting, time it warm and compare its first impacts with the reference.

    Parameters
    ----------
    cases : sequence of (str, dict)
        Solver name and keyword settings for :func:`simulate`, e.g. ``("newmark", {"dt": 1e-7})``.
    model, initial : optional
        The damper and its start (default Table 1, Figure 5).
    duration : float
        Simulated time in s.
    ref : SimulationResult, optional
        Reference run (default :func:`reference`).
    n_compare : int
        Leading impacts compared.
    repeats : int
        Timed repetitions of runs shorter than 0.5 s (best is kept); longer runs are timed once.

    Returns
    -------
    list of BenchmarkRow
    """
    ref = reference(model, duration, initial) if ref is None else ref
    e_ref = damping_metrics(ref).two_maxima.value
    rows = []
    for solver, kw in cases:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AccuracyWarning)
            best = math.inf
            res = None
            for i in range(max(int(repeats), 1)):
                t0 = time.perf_counter()
                res = simulate(model, duration, solver=solver, initial=initial, **kw)
                _ = time.perf_counter() - t0
                best = min(best, res.solver_time)
                if res.solver_time > 0.5 or i + 1 >= repeats:
                    break
        label = ", ".join(f"{k}={v:g}" for k, v in kw.items()) or "default"
        rows.append(BenchmarkRow(solver, label, best, len(res.impacts),
                                 compare_impacts(res.impacts, ref.impacts, n_compare),
                                 float(res.energy.relative_closure_error),
                                 abs(damping_metrics(res).two_maxima.value / e_ref - 1.0)))
    return rows
