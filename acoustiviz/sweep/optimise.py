"""Running an optimisation: batches of designs asked of Optuna's TPE sampler, evaluated on any executor.

The optimiser (Optuna, the optional ``optimize`` extra, imported only here and only when a run
starts) is asked for a batch of :attr:`~acoustiviz.sweep.problem.Problem.batch` designs at a time;
the batch is evaluated in parallel (a local process pool or Dask, :mod:`acoustiviz.sweep.execute`)
and each finished evaluation is appended to the journal at once. The batch that starts at
evaluation ``k`` is a function of the problem, the seed and the evaluations before ``k`` alone (a
sampler seeded from ``(seed, k)`` is told every earlier evaluation in index order), so

* the designs are the same whatever the number of workers or the order they finish in, and
* a run interrupted and resumed from its journal asks for exactly the designs the uninterrupted
  run would have asked for, and evaluates only those not yet in the journal.

Constraints are told to the sampler as a penalty added to each objective: its finite range over the
evaluations so far times :data:`PENALTY` times the sum of the relative violations. A graded penalty
keeps an infeasible design just outside the constraint informative about its neighbourhood; with a
chaotic constraint such as the damping inclination, whose feasible set is a scatter of islands, the
sampler thus concentrates where the objective is good and draws feasible designs there, where a
hard feasible/infeasible split would teach it to avoid the whole neighbourhood
(``benchmarks/results/optimisers.md``). The best design and the front are chosen from the feasible
designs only, by the objectives themselves.
"""

from __future__ import annotations

import json
import os
import warnings
from concurrent.futures import FIRST_COMPLETED, wait
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from .execute import _interruptible, _sigint_blocked, dask_executor, local_pool, shutdown_now
from .problem import Problem
from .store import _cut_torn_line, _fsync_dir

__all__ = ["run_optimisation", "read_journal", "ask_batch", "PENALTY", "JOURNAL"]

#: File name of the journal of finished evaluations inside an optimisation's folder.
JOURNAL = "journal.jsonl"
#: Weight of a unit relative violation, in units of an objective's range over the evaluations so far.
PENALTY = 0.3
#: Evaluations of random designs (Sobol-like coverage of TPE's start) before the sampler models them.
STARTUP = 10


def _optuna():
    try:
        import optuna
    except ImportError:
        raise ParameterError("optimizer", "needs the optional dependency: pip install 'acoustiviz[optimize]'") from None
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    return optuna


def _distributions(optuna, problem: Problem) -> dict:
    out = {}
    for v in problem.searched:
        if v.kind == "categorical":
            out[v.name] = optuna.distributions.CategoricalDistribution(list(v.choices))
        elif v.kind == "int":  # every whole number from low to high: Optuna's suggest_int
            out[v.name] = optuna.distributions.IntDistribution(int(v.low), int(v.high))
        else:
            out[v.name] = optuna.distributions.FloatDistribution(v.low, v.high, log=v.kind == "log")
    return out


def _told_values(problem: Problem, history) -> list:
    """The values the sampler is told for each evaluation: penalised objectives, or None (failed)."""
    from .problem import objective_matrix

    rows = [h["row"] for h in history]
    values = objective_matrix(problem, rows) if rows else np.zeros((0, len(problem.objectives)))
    finite = np.isfinite(values)
    spread = [float(np.ptp(values[finite[:, j], j])) if finite[:, j].any() else 0.0
              for j in range(values.shape[1])]
    out = []
    for i, row in enumerate(rows):
        if row.get("error") or not finite[i].all():
            out.append(None)
            continue
        violation = sum(min(c.violation(float(row[c.column])), 1e6) for c in problem.constraints)
        out.append([float(values[i, j] + PENALTY * (spread[j] or 1.0) * violation) for j in range(values.shape[1])])
    return out


def ask_batch(problem: Problem, history, start: int) -> list:
    """The variables (``{name: value}``, fixed ones included) of evaluations ``start`` to the batch's end.

    ``history`` holds the evaluations with an index below ``start`` (``{"evaluation", "params",
    "row"}``); the result depends on them, the problem and the seed alone.
    """
    optuna = _optuna()
    n = min(problem.batch, problem.evaluations - start)
    dists = _distributions(optuna, problem)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the multivariate sampler's "experimental" notice
        sampler = optuna.samplers.TPESampler(seed=(problem.seed * 1_000_003 + start) % 2**32, multivariate=True,
                                             constant_liar=True, n_startup_trials=STARTUP)
        study = optuna.create_study(sampler=sampler,
                                    directions=["minimize"] * len(problem.objectives))
        trials = []
        for h, told in zip(history, _told_values(problem, history), strict=True):
            params = {k: h["params"][k] for k in dists}
            state = optuna.trial.TrialState.FAIL if told is None else optuna.trial.TrialState.COMPLETE
            trials.append(optuna.trial.create_trial(state=state, values=told, params=params, distributions=dists))
        study.add_trials(trials)
        out = []
        for _ in range(n):
            trial = study.ask(dists)
            out.append({**problem.fixed, **{k: _plain(trial.params[k]) for k in dists}})
    return out


def _plain(v):
    return v.item() if isinstance(v, np.generic) else v


# --------------------------------------------------------------------------- the journal
def read_journal(path, name: str = "out") -> dict:
    """``{evaluation: record}`` of the finished evaluations in the journal (a torn last line left out)."""
    path = Path(path)
    if not path.exists():
        return {}
    text = path.read_bytes().decode("utf-8", errors="replace")
    lines = text.split("\n")
    lines.pop()  # "" after a final newline, or a line torn by a kill
    out = {}
    for k, line in enumerate(lines, start=1):
        try:
            rec = json.loads(line)
            out[int(rec["evaluation"])] = {"evaluation": int(rec["evaluation"]), "params": dict(rec["params"]),
                                           "row": dict(rec["row"])}
        except (ValueError, KeyError, TypeError):
            raise ParameterError(name, f"{path} line {k} is damaged; use another folder") from None
    return out


class _Journal:
    """The journal opened for appending: each evaluation one JSON line, flushed and synced on its own."""

    def __init__(self, path: Path):
        self.path = path
        if path.exists():
            _cut_torn_line(path)
        self._f = open(path, "a", encoding="utf-8")  # noqa: SIM115 - closed by close()
        _fsync_dir(path.parent)

    def append(self, record: dict) -> None:
        self._f.write(json.dumps(record, allow_nan=True) + "\n")
        self._f.flush()
        os.fsync(self._f.fileno())

    def close(self) -> None:
        self._f.close()


# --------------------------------------------------------------------------- the run
class _Pool:
    """The executor of a run: a local process pool (warmed up), or Dask; restarted if a local pool breaks."""

    def __init__(self, executor, workers, evaluate):
        self.evaluate, self.workers, self.close_client = evaluate, workers, None
        self.local = executor in (None, "process")
        if self.local:
            n = int(workers or os.cpu_count() or 1)
            evaluate.warm_up()  # forked workers inherit the loaded kernels
            self.ex = local_pool(n, evaluate.warm_up)
        else:
            self.ex, self.close_client = dask_executor(executor)

    def submit(self, index, params):
        if not self.local:
            return self.ex.submit(self.evaluate, index, params)
        with _sigint_blocked():  # the first submission forks the workers
            return self.ex.submit(self.evaluate, index, params)

    def renew(self):
        if self.local:
            shutdown_now(self.ex)
            self.ex = local_pool(int(self.workers or os.cpu_count() or 1), self.evaluate.warm_up)

    def close(self, interrupted: bool):
        if interrupted:
            shutdown_now(self.ex)
        else:
            self.ex.shutdown(wait=True)
        if self.close_client is not None:
            self.close_client()


def _outcome(fut, index, evaluate) -> tuple[dict, bool]:
    """``(row, broken)`` of a finished future: its row, or a failed row naming the exception."""
    from concurrent.futures.process import BrokenProcessPool

    from .modes import failed_row

    try:
        return fut.result(), False
    except Exception as exc:  # noqa: BLE001 - recorded in the evaluation's row
        broken = isinstance(exc, BrokenProcessPool)
        why = f"the worker process died ({exc})" if broken else f"{type(exc).__name__}: {exc}"
        return failed_row(index, evaluate.columns, why), broken


def _run_batch(pool: _Pool, pending: dict, journal: _Journal, done: dict, report) -> None:
    """Evaluate ``pending`` (``{index: params}``) on the pool, journalling each as it finishes."""
    running = {pool.submit(i, p): i for i, p in pending.items()}
    broken = False
    try:
        while running:
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for fut in [f for f in running if f in finished]:
                i = running.pop(fut)
                row, dead = _outcome(fut, i, pool.evaluate)
                broken |= dead
                record = {"evaluation": i, "params": pending[i], "row": row}
                journal.append(record)
                done[i] = record
                if report is not None:
                    report(record)
    finally:
        for fut in running:
            fut.cancel()
    if broken:
        pool.renew()


def run_optimisation(problem: Problem, evaluate, folder, *, executor=None, workers=None, report=None) -> list:
    """Run (or resume) the optimisation of ``problem``; return every evaluation in index order.

    Parameters
    ----------
    problem : Problem
        Variables, objectives, constraints, budget, seed and batch.
    evaluate : callable
        An evaluation mode (:mod:`acoustiviz.sweep.modes`): ``evaluate(index, params) -> row``.
    folder : path-like
        Folder of the journal (:data:`JOURNAL`, created if needed); its finished evaluations are kept.
    executor : None, "process" or "dask://HOST:PORT"
        Where the evaluations run (a local process pool of ``workers`` processes by default).
    workers : int, optional
        Processes of the local pool (default: all cores).
    report : callable, optional
        Called with each finished record (``{"evaluation", "params", "row"}``).

    Returns
    -------
    list of dict
        ``{"evaluation", "params", "row"}`` per evaluation, in index order.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / JOURNAL
    done = {i: r for i, r in read_journal(path).items() if i < problem.evaluations}
    if len(done) < problem.evaluations:
        _optuna()  # the missing extra is refused before any pool starts
        with _interruptible():
            _run(problem, evaluate, path, done, executor, workers, report)
    return [done[i] for i in sorted(done)]


def _run(problem, evaluate, path, done, executor, workers, report) -> None:
    pool = _Pool(executor, workers, evaluate)
    journal = _Journal(path)
    interrupted = True
    try:
        for start in range(0, problem.evaluations, problem.batch):
            stop = min(start + problem.batch, problem.evaluations)
            if all(i in done for i in range(start, stop)):
                continue
            # batches finish in order, so every earlier evaluation is in (a partial batch is the last one)
            history = [done[i] for i in range(start)]
            params = ask_batch(problem, history, start)
            pending = {i: p for i, p in zip(range(start, stop), params, strict=True) if i not in done}
            _run_batch(pool, pending, journal, done, report)
        interrupted = False
    finally:
        journal.close()
        pool.close(interrupted)
