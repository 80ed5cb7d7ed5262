"""Which optimisation library finds the quietest damper: Optuna, pymoo and scipy.optimize on one problem.

The problem is the paper's design question in free vibration: over the gap d in [0.01, 0.06] m and
the impact mass m in [0.01, 0.08] kg (Table 1 otherwise, 1 s of motion per design, the listener at
0.7 m and 45 degrees over a reflecting plane), minimise the maximum SPL ``max_spl_db`` subject to a
damping inclination (paper eq 16, ``inclination_two_maxima_m_s``) in the band [0.004, 0.006] m/s.
The SPL is smooth in d and m; the inclination is not (the motion is chaotic), so the feasible set is
a scatter of islands. The reference is the best feasible design of a 30 x 30 grid over the same
bounds (900 designs, computed once and cached in ``benchmarks/results/optimisers_grid.csv``); each
library gets a budget of 90 evaluations (a tenth of the grid) and 5 seeds, and a run passes when its
best feasible value lies within 0.3 dB of the grid's (or below it).

Candidates: Optuna's TPE sampler as ``acoustiviz optimize`` runs it (batches of 8, constraints as a
graded penalty on the objective, :mod:`acoustiviz.sweep.optimise`), Optuna's TPE sampler with its own
constraint handling (``constraints_func``, batches of 8), pymoo's NSGA-II (constraints as ``G <= 0``, population 10
for 9 generations) and scipy's ``differential_evolution`` (``NonlinearConstraint``, population 10,
8 generations plus the initial one, no polishing). Each prints one row per seed.

``--mode operation`` asks the same libraries the question in operation (:func:`main_operation`,
:mod:`bench_optimisers_operation`), whose table is kept below this one in the same file.

Run ``python benchmarks/bench_optimisers.py`` (``--write`` keeps the table in
``benchmarks/results/optimisers.md``).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from _timing import RESULTS, results_header

GAP = (0.01, 0.06)
MASS = (0.01, 0.08)
BAND = (0.004, 0.006)
DURATION = 1.0
GRID = 30
BUDGET = 90
SEEDS = (0, 1, 2, 3, 4)
TOLERANCE_DB = 0.3
GRID_CSV = RESULTS / "optimisers_grid.csv"
#: The first line of the section in operation in ``benchmarks/results/optimisers.md``.
OPERATION_MARKER = "## In operation"


def evaluate(gap: float, mass: float) -> tuple[float, float]:
    """``(max_spl_db, inclination_two_maxima_m_s)`` of one design (NaN when it fails)."""
    from acoustiviz.sweep.evaluate import evaluate_or_fail
    from acoustiviz.sweep.spec import FixedSettings, SweepSpec

    settings = FixedSettings(duration=DURATION)
    design = SweepSpec(gap=(float(gap),), m=(float(mass),), settings=settings).designs()[0]
    row = evaluate_or_fail(design, settings).row()
    return row["max_spl_db"], row["inclination_two_maxima_m_s"]


def feasible(inclination: float) -> bool:
    """True when the inclination lies in the band."""
    return BAND[0] <= inclination <= BAND[1]


def grid_best() -> float:
    """Best feasible ``max_spl_db`` of the 30 x 30 grid (cached in :data:`GRID_CSV`)."""
    from acoustiviz.sweep.spec import value_range

    if not GRID_CSV.exists():
        rows = [(g, m, *evaluate(g, m)) for g in value_range(*GAP, GRID) for m in value_range(*MASS, GRID)]
        np.savetxt(GRID_CSV, np.array(rows), delimiter=",", comments="", fmt="%.17g",
                   header="gap_m,mass_kg,max_spl_db,inclination_two_maxima_m_s")
    data = np.loadtxt(GRID_CSV, delimiter=",", skiprows=1)
    ok = (data[:, 3] >= BAND[0]) & (data[:, 3] <= BAND[1])
    return float(data[ok, 2].min())


class Counted:
    """The objective and constraint of a design, each design evaluated once (libraries ask twice)."""

    def __init__(self):
        self.cache = {}
        self.best = math.inf

    def __call__(self, x):
        """``(max_spl_db, inclination)`` of the design ``x = (gap, mass)``."""
        key = (float(x[0]), float(x[1]))
        if key not in self.cache:
            spl, inc = evaluate(*key)
            self.cache[key] = (spl, inc)
            if math.isfinite(spl) and feasible(inc):
                self.best = min(self.best, spl)
        return self.cache[key]


def run_optuna(seed: int) -> Counted:
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    f = Counted()

    def constraints(trial):
        return trial.user_attrs["c"]

    import warnings

    warnings.simplefilter("ignore", FutureWarning)  # constraints_func: deprecated in Optuna 5
    sampler = optuna.samplers.TPESampler(seed=seed, constraints_func=constraints, multivariate=True,
                                         constant_liar=True)
    study = optuna.create_study(sampler=sampler)
    while len(f.cache) < BUDGET:
        trials = [study.ask() for _ in range(min(8, BUDGET - len(study.trials)))]
        for t in trials:
            spl, inc = f((t.suggest_float("gap", *GAP), t.suggest_float("m", *MASS)))
            inc = inc if math.isfinite(inc) else 1e9
            t.set_user_attr("c", [BAND[0] - inc, inc - BAND[1]])
            study.tell(t, spl)
        if len(study.trials) >= BUDGET:
            break
    return f


def run_pymoo(seed: int) -> Counted:
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import ElementwiseProblem
    from pymoo.optimize import minimize

    f = Counted()

    class Problem(ElementwiseProblem):
        def __init__(self):
            super().__init__(n_var=2, n_obj=1, n_ieq_constr=2, xl=np.array([GAP[0], MASS[0]]),
                             xu=np.array([GAP[1], MASS[1]]))

        def _evaluate(self, x, out, *args, **kwargs):
            spl, inc = f(x)
            inc = inc if math.isfinite(inc) else 1e9
            out["F"] = [spl]
            out["G"] = [BAND[0] - inc, inc - BAND[1]]

    minimize(Problem(), NSGA2(pop_size=10), ("n_evals", BUDGET), seed=seed, verbose=False)
    return f


def run_scipy(seed: int) -> Counted:
    from scipy.optimize import NonlinearConstraint, differential_evolution

    f = Counted()

    def inclination(x):
        inc = f(x)[1]
        return inc if math.isfinite(inc) else 1e9

    differential_evolution(lambda x: f(x)[0], [GAP, MASS], popsize=5, maxiter=8, polish=False, seed=seed,
                           constraints=NonlinearConstraint(inclination, *BAND), tol=0.0, init="sobol")
    return f


def run_acoustiviz(seed: int) -> Counted:
    """What ``acoustiviz optimize`` runs: Optuna's TPE told penalised objectives, batches of 8."""
    import tempfile

    from acoustiviz.sweep.modes import FreeVibration
    from acoustiviz.sweep.optimise import run_optimisation
    from acoustiviz.sweep.problem import Objective, Problem, parse_constraint, parse_variable
    from acoustiviz.sweep.spec import FixedSettings

    f = Counted()
    evaluate = FreeVibration(FixedSettings(duration=DURATION))
    problem = Problem((parse_variable("gap", f"{GAP[0]}:{GAP[1]}"), parse_variable("m", f"{MASS[0]}:{MASS[1]}")),
                      (Objective("max_spl_db", "min"),),
                      (parse_constraint("c", f"inclination_two_maxima_m_s>={BAND[0]}"),
                       parse_constraint("c", f"inclination_two_maxima_m_s<={BAND[1]}")),
                      evaluations=BUDGET, seed=seed, batch=8)
    with tempfile.TemporaryDirectory() as folder:
        for rec in run_optimisation(problem, evaluate, folder, workers=1):
            f((rec["params"]["gap"], rec["params"]["m"]))
    return f


LIBRARIES = (("acoustiviz optimize (optuna TPE, penalty)", run_acoustiviz), ("optuna TPE", run_optuna),
             ("pymoo NSGA-II", run_pymoo), ("scipy differential_evolution", run_scipy))


def write_section(text: str, operation: bool) -> None:
    """Keep ``text`` in ``benchmarks/results/optimisers.md``: free vibration first, the section in operation after.

    Writing one mode's section keeps the other's.
    """
    path = RESULTS / "optimisers.md"
    old = path.read_text(encoding="utf-8") if path.exists() else ""
    cut = old.find(OPERATION_MARKER)
    free, op = (old, "") if cut < 0 else (old[:cut], old[cut:])
    free, op = (free, text) if operation else (text, op)
    new = free.rstrip("\n") + "\n" + ("\n" + op.rstrip("\n") + "\n" if op else "")
    tmp = path.with_suffix(".md.tmp")
    tmp.write_text(new, encoding="utf-8")
    tmp.replace(path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="also keep the table in benchmarks/results/optimisers.md")
    parser.add_argument("--mode", choices=("free", "operation"), default="free",
                        help="free vibration (default) or in operation (bench_optimisers_operation.py)")
    parser.add_argument("--budget", type=int, default=None, help="in operation: evaluations per run (default 24)")
    parser.add_argument("--seeds", type=int, default=None, help="in operation: seeds per library (default 3)")
    parser.add_argument("--grid", type=int, default=None, help="in operation: points per side of the grid (0: none)")
    args = parser.parse_args(argv)
    if args.mode == "operation":
        from bench_optimisers_operation import main_operation

        keep = (lambda text: write_section(text, operation=True)) if args.write else None
        main_operation(budget=args.budget, seeds=args.seeds, grid=args.grid, keep=keep)
        return 0
    reference = grid_best()
    lines = [f"Reference: best feasible max_spl_db of the {GRID} x {GRID} grid = {reference:.3f} dB "
             f"(band {BAND[0]:g}..{BAND[1]:g} m/s, gap {GAP[0]:g}..{GAP[1]:g} m, mass {MASS[0]:g}..{MASS[1]:g} kg, "
             f"{DURATION:g} s per design); budget {BUDGET} evaluations, pass: within {TOLERANCE_DB:g} dB.", "",
             "| library | seed | best value found (dB) | evaluations | within 0.3 dB of grid | time (s) |",
             "|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    for name, run in LIBRARIES:
        for seed in SEEDS:
            t0 = time.perf_counter()
            f = run(seed)
            elapsed = time.perf_counter() - t0
            ok = "yes" if f.best <= reference + TOLERANCE_DB else "no"
            line = f"| {name} | {seed} | {f.best:.3f} | {len(f.cache)} | {ok} | {elapsed:.2f} |"
            print(line, flush=True)
            lines.append(line)
    if args.write:
        write_section(results_header("python benchmarks/bench_optimisers.py --write") + "\n\n" + "\n".join(lines),
                      operation=False)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
