"""Which optimisation library finds the best damper in operation: ``bench_optimisers.py --mode operation``.

The Table 1 structure (M = 0.5 kg, K = 500 N/m, C = 0.05 N s/m, its resonance near 5.03 Hz) is
driven by a force of F0 = 5 N (as ``docs/guide/optimize.md``'s example and
``benchmarks/bench_operation.py``) at 3 frequencies over 4.5-5.5 Hz, each searched from 3 starts (a band
and a search much coarser than the 9 frequencies of 3-7 Hz and the 6 starts of ``acoustiviz forced``,
so that the comparison, some 500 designs, runs on a shared machine in an hour or so). The variables
are the gap in [0.02, 0.06] m and the impact mass in [0.02, 0.08] kg (the span of the paper's Table 2
designs); a design is one row of :class:`acoustiviz.sweep.modes.InOperation` (``MODES["operation"]``),
what ``acoustiviz optimize --force 5 --freq 4.5:5.5:3 --starts 3`` evaluates. Two problems:

(a) maximise ``min_reduction_db`` (the smallest vibration reduction over the band) subject to
    ``worst_lcpeak_db <= LCPEAK_LIMIT``; a run's result is its best feasible value, compared with the
    best feasible value of every evaluation of the benchmark run (every library, every seed, the grid);
(b) maximise ``min_reduction_db`` and minimise ``worst_lcpeak_db`` under the same constraint; a run's
    result is the hypervolume (dB²) of its feasible front, with the reference point
    ``(min_reduction_db, worst_lcpeak_db) = HV_REFERENCE``, compared with that of every evaluation.

Each library gets the same budget of evaluations per run and the same seeds. How each runs:

* ``acoustiviz optimize``: :func:`acoustiviz.sweep.optimise.run_optimisation` itself (TPE told penalised
  objectives), batches of 8 on its own process pool of 2 workers;
* Optuna TPE plain (constraint not told; multivariate, constant liar) and with ``constraints_func``:
  batches of 8 asked, evaluated on the benchmark's pool of 2 workers, then told;
* pymoo NSGA-II (population 8, constraint as ``G <= 0``): each generation one batch on the pool;
* scipy ``differential_evolution`` (population 8, Sobol start, deferred updating, vectorised, no polish;
  constraint as ``NonlinearConstraint``): each generation one batch on the pool. scipy.optimize has no
  multi-objective method, so (b) is not applicable to it.

The objectives are deterministic for a given design and settings, so every design is evaluated once
per benchmark run (:class:`Evaluations`, keyed by ``(gap, mass)``): a library that proposes a design
already evaluated (Optuna's plain and constrained samplers share their random start for a seed, and
``acoustiviz optimize`` with seed 0 draws the first batch of Optuna's seed 0; the runs of (b) start as those of (a);
scipy asks for the constraint and the objective of the same design) does not pay again. Each row
gives the designs the run asked for, how many of them were new to the benchmark run, and the run's
wall time (a design already evaluated costs nothing, so the times do not compare the libraries). The best
value of every evaluation and the front of every evaluation include those of a 6 x 6 grid over the
same bounds (``--grid 0``: none).
"""

from __future__ import annotations

import math
import sys
import time
import warnings

import numpy as np
from _timing import results_header

GAP = (0.02, 0.06)
MASS = (0.02, 0.08)
FORCE_N = 5.0
BAND_HZ = (4.5, 5.5, 3)
STARTS = 3
#: Bound of the constraint ``worst_lcpeak_db <= LCPEAK_LIMIT`` in dB (binds: the designs of largest
#: ``min_reduction_db`` are louder).
LCPEAK_LIMIT = 112.0
#: Hypervolume reference point: ``(min_reduction_db, worst_lcpeak_db)`` in dB.
HV_REFERENCE = (-12.0, LCPEAK_LIMIT)
BUDGET = 24
SEEDS = (0, 1, 2)
BATCH = 8
WORKERS = 2
GRID = 6
#: A run of (a) passes when its best feasible value lies within this many dB of the reference.
TOLERANCE_DB = 0.5
COMMAND = "python benchmarks/bench_optimisers.py --mode operation --write"


def evaluation_mode():
    """The evaluation in operation of ``acoustiviz optimize`` (:data:`acoustiviz.sweep.modes.MODES`)."""
    from acoustiviz.sweep.modes import MODES
    from acoustiviz.sweep.operation import Operation
    from acoustiviz.sweep.spec import FixedSettings, value_range

    return MODES["operation"](FixedSettings(), Operation(FORCE_N, value_range(*BAND_HZ), starts=STARTS))


def values(row: dict) -> tuple[float, float]:
    """``(min_reduction_db, worst_lcpeak_db)`` of a row (NaN when the design failed)."""
    if row.get("error"):
        return math.nan, math.nan
    return float(row["min_reduction_db"]), float(row["worst_lcpeak_db"])


def feasible(row: dict) -> bool:
    """True when the design succeeded and meets ``worst_lcpeak_db <= LCPEAK_LIMIT``."""
    red, peak = values(row)
    return math.isfinite(red) and math.isfinite(peak) and peak <= LCPEAK_LIMIT


def hypervolume(points, reference=HV_REFERENCE) -> float:
    """Area in dB² that ``points`` dominate up to ``reference``.

    Both are ``(min_reduction_db, worst_lcpeak_db)`` pairs, the first maximised, the second minimised.
    """
    # minimise both: (-reduction, peak) against (-reference reduction, reference peak)
    pts = sorted((-r, p) for r, p in points if r > reference[0] and p < reference[1])
    area, last = 0.0, reference[1]
    for a, b in pts:
        if b < last:
            area += (-reference[0] - a) * (last - b)
            last = b
    return area


class Evaluations:
    """Every design's row in operation, each design evaluated once per benchmark run, on a pool of workers."""

    def __init__(self, workers: int = WORKERS):
        from acoustiviz.sweep.execute import local_pool

        self.mode = evaluation_mode()
        self.mode.warm_up()  # the forked workers inherit the loaded kernels
        self.pool = local_pool(workers, self.mode.warm_up)
        self.cache = {}

    def rows(self, points) -> list:
        """The rows of the designs ``points`` (``(gap, mass)`` pairs), those not yet evaluated run as one batch."""
        keys = [(float(g), float(m)) for g, m in points]
        todo = list(dict.fromkeys(k for k in keys if k not in self.cache))
        futures = {k: self.pool.submit(self.mode, len(self.cache) + i, {"gap": k[0], "m": k[1]})
                   for i, k in enumerate(todo)}
        for k, fut in futures.items():
            self.cache[k] = fut.result()
        return [self.cache[k] for k in keys]

    def close(self) -> None:
        """Stop the workers."""
        self.pool.shutdown(wait=True)


class Trace:
    """The designs one library run asked for, in order, and how many of them were new to the benchmark run."""

    def __init__(self, evaluations: Evaluations):
        self.evaluations = evaluations
        self.keys = []
        self.new = 0

    def __call__(self, points) -> list:
        """The rows of ``points``, evaluated (once) through the benchmark run's :class:`Evaluations`."""
        before = len(self.evaluations.cache)
        rows = self.evaluations.rows(points)
        self.new += len(self.evaluations.cache) - before
        self.keys += [(float(g), float(m)) for g, m in points]
        return rows

    def rows(self) -> list:
        """The row of every distinct design asked for."""
        return [self.evaluations.cache[k] for k in dict.fromkeys(self.keys)]

    def best(self) -> tuple[float, float]:
        """``(min_reduction_db, worst_lcpeak_db)`` of the best feasible design asked for (NaN: none)."""
        ok = [values(r) for r in self.rows() if feasible(r)]
        return max(ok) if ok else (math.nan, math.nan)

    def front_hypervolume(self) -> tuple[float, int]:
        """Hypervolume (dB²) of the feasible designs asked for, and the size of their front."""
        ok = [values(r) for r in self.rows() if feasible(r)]
        front = [(r, p) for r, p in ok if not any(r2 >= r and p2 <= p and (r2, p2) != (r, p) for r2, p2 in ok)]
        return hypervolume(ok), len(set(front))


# --------------------------------------------------------------------------- the libraries
def _penalty(row: dict) -> float:
    """``worst_lcpeak_db - LCPEAK_LIMIT`` (<= 0 when feasible; large when the design failed)."""
    peak = values(row)[1]
    return peak - LCPEAK_LIMIT if math.isfinite(peak) else 1e9


def run_acoustiviz(trace: Trace, seed: int, budget: int, two: bool) -> None:
    """:func:`acoustiviz.sweep.optimise.run_optimisation`, what ``acoustiviz optimize`` runs, on 2 workers."""
    import tempfile

    from acoustiviz.sweep.problem import Objective, Problem, parse_constraint, parse_variable

    objectives = (Objective("min_reduction_db", "max"),) + ((Objective("worst_lcpeak_db", "min"),) if two else ())
    problem = Problem((parse_variable("gap", f"{GAP[0]}:{GAP[1]}"), parse_variable("m", f"{MASS[0]}:{MASS[1]}")),
                      objectives, (parse_constraint("constraint", f"worst_lcpeak_db<={LCPEAK_LIMIT}"),),
                      evaluations=budget, seed=seed, batch=BATCH, columns=trace.evaluations.mode.objective_columns)
    mode = Known(trace.evaluations.mode, dict(trace.evaluations.cache))
    with tempfile.TemporaryDirectory() as folder:
        from acoustiviz.sweep.optimise import run_optimisation

        records = run_optimisation(problem, mode, folder, workers=WORKERS)
    for rec in records:  # the rows computed in the run's own pool join the benchmark run's
        key = (float(rec["params"]["gap"]), float(rec["params"]["m"]))
        if key not in trace.evaluations.cache:
            trace.evaluations.cache[key] = rec["row"]
            trace.new += 1
        trace.keys.append(key)


class Known:
    """An evaluation mode that returns the rows already known (a copy made when the run starts) without work."""

    def __init__(self, mode, known: dict):
        self.mode, self.known = mode, known
        self.columns = mode.columns

    def warm_up(self) -> None:
        """Compile (or load) the kernels."""
        self.mode.warm_up()

    def __call__(self, index: int, params: dict) -> dict:
        """The row of design ``index``: known, or evaluated."""
        row = self.known.get((float(params["gap"]), float(params["m"])))
        return {**row, "design_id": index} if row is not None else self.mode(index, params)


def run_optuna(trace: Trace, seed: int, budget: int, two: bool, constrained: bool) -> None:
    """Optuna's TPE sampler, batches of :data:`BATCH` (constant liar), with or without ``constraints_func``."""
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    warnings.simplefilter("ignore", FutureWarning)  # constraints_func: deprecated in Optuna 5
    warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)

    def constraints(trial):
        return trial.user_attrs["c"]

    sampler = optuna.samplers.TPESampler(seed=seed, multivariate=True, constant_liar=True,
                                         constraints_func=constraints if constrained else None)
    study = optuna.create_study(sampler=sampler, directions=["maximize", "minimize"] if two else ["maximize"])
    while len(study.trials) < budget:
        trials = [study.ask() for _ in range(min(BATCH, budget - len(study.trials)))]
        points = [(t.suggest_float("gap", *GAP), t.suggest_float("m", *MASS)) for t in trials]
        for t, row in zip(trials, trace(points), strict=True):
            t.set_user_attr("c", [_penalty(row)])
            red, peak = values(row)
            if not (math.isfinite(red) and math.isfinite(peak)):
                study.tell(t, state=optuna.trial.TrialState.FAIL)
            else:
                study.tell(t, [red, peak] if two else red)


def run_pymoo(trace: Trace, seed: int, budget: int, two: bool) -> None:
    """NSGA-II of pymoo, population :data:`BATCH`, the constraint as ``G <= 0``; each generation one batch."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    class Operation(Problem):
        def __init__(self):
            super().__init__(n_var=2, n_obj=2 if two else 1, n_ieq_constr=1, xl=np.array([GAP[0], MASS[0]]),
                             xu=np.array([GAP[1], MASS[1]]))

        def _evaluate(self, x, out, *args, **kwargs):
            rows = trace([tuple(p) for p in x])
            v = np.array([values(r) for r in rows])
            v = np.where(np.isfinite(v), v, [-1e9, 1e9])  # a failed design: the worst values
            out["F"] = np.column_stack([-v[:, 0], v[:, 1]]) if two else -v[:, :1]
            out["G"] = np.array([[_penalty(r)] for r in rows])

    minimize(Operation(), NSGA2(pop_size=BATCH), ("n_evals", budget), seed=seed, verbose=False)


def run_scipy(trace: Trace, seed: int, budget: int, two: bool) -> None:
    """The ``differential_evolution`` of scipy (problem (a) only), population :data:`BATCH`, a batch per generation."""
    from scipy.optimize import NonlinearConstraint, differential_evolution

    def points(x):
        return [tuple(p) for p in np.asarray(x).reshape(2, -1).T]  # vectorised: x is (2, population)

    def objective(x):
        red = np.array([values(r)[0] for r in trace(points(x))])
        return np.where(np.isfinite(red), -red, 1e9)

    def constraint(x):
        return np.array([[_penalty(r) for r in trace(points(x))]])  # (1 constraint, population)

    # the constraint is asked first (the objective only of the feasible designs): both through the cache
    generations = max(0, budget // BATCH - 1)
    differential_evolution(objective, [GAP, MASS], popsize=BATCH // 2, maxiter=generations, polish=False,
                           rng=seed, init="sobol", tol=0.0, updating="deferred", vectorized=True,
                           constraints=NonlinearConstraint(constraint, -np.inf, 0.0))


LIBRARIES = (
    ("acoustiviz optimize (optuna TPE, penalty)", run_acoustiviz),
    ("optuna TPE (constraint not told)", lambda *a: run_optuna(*a, constrained=False)),
    ("optuna TPE (constraints_func)", lambda *a: run_optuna(*a, constrained=True)),
    ("pymoo NSGA-II", run_pymoo),
    ("scipy differential_evolution", run_scipy),
)


# --------------------------------------------------------------------------- the tables
def _runs(evaluations: Evaluations, two: bool, budget: int, seeds) -> list:
    """``(library, seed, trace, seconds)`` of every run of one problem (scipy: None, in (b))."""
    out = []
    for name, run in LIBRARIES:
        for seed in seeds:
            trace = Trace(evaluations)
            if two and run is run_scipy:
                out.append((name, seed, None, 0.0))
                continue
            t0 = time.perf_counter()
            run(trace, seed, budget, two)
            elapsed = time.perf_counter() - t0
            print(f"{'(b)' if two else '(a)'} {name} seed {seed}: {len(trace.rows())} asked, {trace.new} new, "
                  f"{elapsed:.0f} s; {len(evaluations.cache)} designs evaluated so far", file=sys.stderr, flush=True)
            out.append((name, seed, trace, elapsed))
    return out


def table_single(runs, reference: float) -> list:
    """The lines of problem (a)'s table and its summary per library."""
    lines = ["| library | seed | best min_reduction_db (dB) | its worst_lcpeak_db (dB) | designs asked | new "
             f"| within {TOLERANCE_DB:g} dB of the reference | time (s) |", "|---|---|---|---|---|---|---|---|"]
    summary = {}
    for name, seed, trace, elapsed in runs:
        red, peak = trace.best()
        ok = math.isfinite(red) and red >= reference - TOLERANCE_DB
        summary.setdefault(name, []).append((red, ok))
        lines.append(f"| {name} | {seed} | {red:.3f} | {peak:.3f} | {len(trace.rows())} | {trace.new} | "
                     f"{'yes' if ok else 'no'} | {elapsed:.0f} |")
    lines += ["", "| library | runs within the tolerance | best values (dB) |", "|---|---|---|"]
    for name, res in summary.items():
        lines.append(f"| {name} | {sum(ok for _, ok in res)} of {len(res)} | "
                     f"{', '.join(f'{r:.2f}' for r, _ in res)} |")
    return lines


def table_two(runs, reference: float) -> list:
    """The lines of problem (b)'s table and its summary per library."""
    lines = ["| library | seed | hypervolume (dB²) | front size | feasible designs | designs asked | new | time (s) |",
             "|---|---|---|---|---|---|---|---|"]
    summary = {}
    for name, seed, trace, elapsed in runs:
        if trace is None:
            lines.append(f"| {name} | {seed} | not applicable (no multi-objective method) | | | | | |")
            continue
        hv, size = trace.front_hypervolume()
        summary.setdefault(name, []).append(hv)
        n_ok = sum(feasible(r) for r in trace.rows())
        lines.append(f"| {name} | {seed} | {hv:.2f} | {size} | {n_ok} | {len(trace.rows())} | {trace.new} | "
                     f"{elapsed:.0f} |")
    lines += ["", "| library | mean hypervolume (dB²) | of the reference | per seed (dB²) |", "|---|---|---|---|"]
    for name, hvs in summary.items():
        lines.append(f"| {name} | {np.mean(hvs):.2f} | {100 * np.mean(hvs) / reference:.0f} % | "
                     f"{', '.join(f'{h:.2f}' for h in hvs)} |")
    return lines


def section(evaluations: Evaluations, single, two, grid_trace, budget: int, seeds, grid: int) -> str:
    """The section of ``benchmarks/results/optimisers.md``: what has run so far (``two`` None: (b) not yet)."""
    every = Trace(evaluations)
    every.keys = list(evaluations.cache)
    best, best_peak = every.best()
    hv_all, front_all = every.front_hypervolume()
    grid_done = grid and grid_trace.keys
    command = COMMAND.replace(" --write", f" --budget {budget} --seeds {len(seeds)} --grid {grid} --write")
    text = ["## In operation", "", results_header(command), "",
            f"Table 1 structure under F0 = {FORCE_N:g} N at {BAND_HZ[2]} frequencies over "
            f"{BAND_HZ[0]:g}-{BAND_HZ[1]:g} Hz, {STARTS} starts each; gap {GAP[0]:g}..{GAP[1]:g} m, "
            f"mass {MASS[0]:g}..{MASS[1]:g} kg; "
            f"budget {budget} designs per run, seeds {', '.join(map(str, seeds))}, {WORKERS} workers. "
            f"{len(evaluations.cache)} distinct designs evaluated in all.", "",
            f"(a) maximise min_reduction_db subject to worst_lcpeak_db <= {LCPEAK_LIMIT:g} dB. Reference: the best "
            f"feasible value of every evaluation = {best:.3f} dB (worst_lcpeak_db {best_peak:.3f} dB)"
            + (f"; of the {grid} x {grid} grid alone = {grid_trace.best()[0]:.3f} dB" if grid_done else "")
            + f"; pass: within {TOLERANCE_DB:g} dB.", "", *table_single(single, best), ""]
    if two is None:
        return "\n".join([*text, "(b) not run yet."])
    text += [f"(b) maximise min_reduction_db, minimise worst_lcpeak_db, subject to worst_lcpeak_db <= "
             f"{LCPEAK_LIMIT:g} dB: hypervolume of the feasible front against the reference point "
             f"(min_reduction_db, worst_lcpeak_db) = ({HV_REFERENCE[0]:g}, {HV_REFERENCE[1]:g}) dB. Reference: the "
             f"front of every evaluation = {hv_all:.2f} dB² ({front_all} designs)"
             + (f"; of the {grid} x {grid} grid alone = {grid_trace.front_hypervolume()[0]:.2f} dB²" if grid_done
                else "") + ".", "", *table_two(two, hv_all)]
    return "\n".join(text)


def main_operation(budget=None, seeds=None, grid=None, keep=None) -> str:
    """Run both problems and print their tables; return the section of ``benchmarks/results/optimisers.md``.

    ``keep(section)``, when given, is called with the section after each stage ((a), (b), the grid), so a
    run stopped early keeps what it finished.
    """
    budget = BUDGET if budget is None else int(budget)
    seeds = SEEDS if seeds is None else tuple(range(int(seeds)))
    grid = GRID if grid is None else int(grid)
    from acoustiviz.sweep.spec import value_range

    evaluations = Evaluations()
    keep = keep or (lambda text: None)
    grid_trace = Trace(evaluations)
    try:
        single = _runs(evaluations, False, budget, seeds)
        keep(section(evaluations, single, None, grid_trace, budget, seeds, grid))
        two = _runs(evaluations, True, budget, seeds)
        keep(section(evaluations, single, two, grid_trace, budget, seeds, grid))
        if grid:
            grid_trace([(g, m) for g in value_range(*GAP, grid) for m in value_range(*MASS, grid)])
    finally:
        evaluations.close()
    out = section(evaluations, single, two, grid_trace, budget, seeds, grid)
    keep(out)
    print(out, flush=True)
    return out
