"""The optimisation job: which damper to build, found by Optuna's TPE sampler over the sweep's variables.

Three parts, shared by ``acoustiviz optimize``, a scene's ``[outputs.optimize]`` and Python callers:

* :class:`~acoustiviz.app.settings.optimize.OptimizeJob`, the settings, checked once when made
  (:func:`optimize_variables` turns the typed variables into it);
* :func:`run`, which evaluates the designs the optimiser asks for (journalled in the job's folder
  as they finish, so that an interrupted run resumes) and returns an :class:`OptimizeResult`;
* :meth:`OptimizeResult.write`, which writes ``evaluations.csv``, ``pareto.csv``,
  ``optimize.json`` and ``pareto.png`` (in operation also ``confirmation.csv``: the chosen design's
  worst case found again by the ``forced`` job with twice the starts, :mod:`acoustiviz.app.optimize_confirm`).
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .settings.optimize import FILES, OptimizeJob

__all__ = ["OptimizeJob", "OptimizeResult", "run", "operation_of", "optimize_variables", "summary"]


def operation_of(given: dict, names: dict | None = None) -> tuple:
    """``(operation, rest)`` of the typed values (:func:`acoustiviz.app.settings.sweep_operation.split_operation`).

    The :class:`~acoustiviz.sweep.Operation` of ``given``'s excitation, band and search (None: free
    vibration) and the other values; errors name ``names[parameter]``.
    """
    from .names import user_terms
    from .settings.sweep_operation import split_operation

    with user_terms(names or {}):
        return split_operation(given)


def optimize_variables(given: dict, names: dict | None = None) -> tuple:
    """``(variables, fixed settings)`` of the typed sweep parameters (``{name: text}``), every bound checked.

    Each of the sweep's parameters (:data:`acoustiviz.sweep.modes.SWEPT_VARIABLES`) given is a
    variable (:func:`acoustiviz.sweep.problem.parse_variable`); the others are the sweep's fixed
    settings. The bounds and choices go through :func:`acoustiviz.app.sweep.sweep_spec`, the rule of
    ``acoustiviz sweep``, so an optimisation refuses what a sweep refuses; a parameter not given is
    held at its default. Errors name ``names[parameter]``.
    """
    from ..sweep.modes import SWEPT_VARIABLES
    from ..sweep.problem import parse_variable
    from .names import user_terms
    from .sweep import sweep_spec

    with user_terms(names or {}):
        kinds = {"material": str, "config": str, "balls": int}
        variables = {k: parse_variable(k, v, kinds.get(k, float))
                     for k, v in given.items() if k in SWEPT_VARIABLES and v is not None}
        ends = {k: (v.low, v.high) if v.kind in ("float", "log", "int") else v.choices
                for k, v in variables.items()}
        spec = sweep_spec(**{k: v for k, v in given.items() if k not in variables and v is not None},
                          **{k: list(v) for k, v in ends.items()})
    held = {"c1": spec.c1, "v0": spec.v0, "distance": spec.distance, "config": spec.config,
            "angle_deg": tuple(math.degrees(a) for a in spec.angle)}
    # the gap or the fill; the balls only when named (a problem of one ball reads as before balls were searched)
    held.update({"gap": spec.gap} if spec.fill is None else {"fill": spec.fill})
    held.update({} if spec.balls is None else {"balls": spec.balls})
    held.update({"m": spec.m} if spec.mass_ratio is None else {"mass_ratio": spec.mass_ratio})
    held.update({"k_hertz": spec.k_hertz} if spec.material is None else {"material": spec.material})
    out = [variables[k] if k in variables else parse_variable(k, held[k][0], type(held[k][0]))
           for k in SWEPT_VARIABLES if k in held]
    return tuple(out), spec.settings


@dataclass(frozen=True, eq=False)
class OptimizeResult:
    """Every evaluation of an :class:`OptimizeJob`, which are feasible and which form the front.

    Attributes
    ----------
    settings : OptimizeJob
        What was run.
    records : tuple of dict
        ``{"evaluation", "params", "row"}`` per evaluation, in index order.
    feasible, pareto : (n,) ndarray of bool
        Feasible designs (succeeded, finite objectives, every constraint met), and the feasible
        designs no other feasible design dominates (with one objective: the best, ties kept).
    confirmation : dict, optional
        In operation, the chosen design's confirmation (:func:`acoustiviz.app.optimize_confirm.confirm`;
        None when no design is feasible or in free vibration).
    """

    settings: OptimizeJob
    records: tuple
    feasible: np.ndarray
    pareto: np.ndarray
    confirmation: dict | None = None

    @property
    def rows(self) -> list:
        """The rows of ``evaluations.csv``: ``evaluation``, the design's columns, ``feasible`` and ``pareto``."""
        return [{"evaluation": r["evaluation"], **r["row"], "feasible": bool(f), "pareto": bool(p)}
                for r, f, p in zip(self.records, self.feasible, self.pareto, strict=True)]

    @property
    def columns(self) -> tuple:
        """The columns of ``evaluations.csv`` and ``pareto.csv``."""
        return ("evaluation", *self.settings.evaluator().columns, "feasible", "pareto")

    def best(self) -> list:
        """The rows of the front (with one objective, the best design), in evaluation order."""
        return [row for row in self.rows if row["pareto"]]

    def write(self, folder=None) -> list:
        """Write ``evaluations.csv``, ``pareto.csv``, ``optimize.json``, ``pareto.png``; return their paths.

        In operation ``confirmation.csv`` too (:attr:`confirmation`).

        Parameters
        ----------
        folder : path-like, optional
            Where the files go (default: the job's ``out``).
        """
        from ..files import write_text_atomic

        folder = Path(folder if folder is not None else self.settings.out)
        folder.mkdir(parents=True, exist_ok=True)
        paths = [write_text_atomic(folder / FILES[0], self._csv(self.rows)),
                 write_text_atomic(folder / FILES[1], self._csv(self.best())),
                 write_text_atomic(folder / FILES[2], optimize_json_text(self.settings)),
                 self._figure(folder / FILES[3])]
        if self.settings.mode == "operation":
            from .optimize_confirm import confirmation_csv_text
            from .settings.optimize import CONFIRMATION

            paths.append(write_text_atomic(folder / CONFIRMATION, confirmation_csv_text(self, self.confirmation)))
        return [Path(p) for p in paths]

    def _csv(self, rows) -> str:
        from ..sweep.store import format_value

        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(self.columns)
        for row in rows:
            w.writerow([("true" if row[c] else "false") if isinstance(row[c], bool) else format_value(row[c])
                        for c in self.columns])
        return buf.getvalue()

    def _figure(self, path: Path) -> Path:
        from ..output.plot.style import save_figure, style
        from .products import new_figure

        objectives = self.settings.problem.objectives
        rows = self.rows
        with style():
            fig = new_figure()
            ax = fig.add_subplot()
            if len(objectives) == 1:
                _plot_history(ax, objectives[0], rows)
            else:
                _plot_front(ax, objectives[:2], rows)
            return save_figure(fig, path)


def axis_label(column: str) -> str:
    """``max_spl_db`` -> ``max spl (dB)``: a column's name with its unit, from the name's suffix."""
    for suffix, unit in (("_db", "dB"), ("_m_s", "m/s"), ("_n_s_m", "N s/m"), ("_n_m1_5", "N/m^1.5"), ("_kg", "kg"),
                         ("_deg", "deg"), ("_j", "J"), ("_m", "m"), ("_s", "s")):
        if column.endswith(suffix):
            return f"{column[:-len(suffix)].replace('_', ' ')} ({unit})"
    return f"{column.replace('_', ' ')} (1)"


def _plot_history(ax, objective, rows) -> None:
    """The best feasible value against evaluations, over every feasible value."""
    c = objective.column
    idx = np.array([r["evaluation"] for r in rows if r["feasible"]], dtype=int)
    val = np.array([float(r[c]) for r in rows if r["feasible"]])
    ax.plot(idx + 1, val, "o", ms=3, color="0.6", label="feasible designs")
    if val.size:
        best = np.minimum.accumulate(val) if objective.sense == "min" else np.maximum.accumulate(val)
        ax.step(idx + 1, best, where="post", label="best so far")
    ax.set_xlim(0, len(rows) + 1)
    ax.set_xlabel("evaluations (1)")
    ax.set_ylabel(axis_label(c))
    ax.set_title(f"{'minimise' if objective.sense == 'min' else 'maximise'} {c}: {val.size} of {len(rows)} "
                 "evaluated designs feasible")
    ax.legend(fontsize=8)


def _plot_front(ax, objectives, rows) -> None:
    """The first two objectives of every feasible design, the front highlighted."""
    a, b = (o.column for o in objectives)
    feas = [r for r in rows if r["feasible"]]
    front = sorted((r for r in feas if r["pareto"]), key=lambda r: float(r[a]))
    ax.plot([float(r[a]) for r in feas], [float(r[b]) for r in feas], "o", ms=3, color="0.6",
            label="feasible designs")
    ax.plot([float(r[a]) for r in front], [float(r[b]) for r in front], "o-", ms=5, label="Pareto front")
    ax.set_xlabel(axis_label(a))
    ax.set_ylabel(axis_label(b))
    ax.set_title(f"Pareto front: {len(front)} designs of {len(rows)} evaluated")
    ax.legend(fontsize=8)


def optimize_json_text(job: OptimizeJob) -> str:
    """``optimize.json`` as written (two-space indented JSON, a final newline)."""
    return json.dumps(job.document(), indent=2) + "\n"


def run(job: OptimizeJob, progress=None) -> OptimizeResult:
    """Evaluate the designs the optimiser asks for (resuming the job's folder); return the result.

    Parameters
    ----------
    job : OptimizeJob
        The job, checked when it was made.
    progress : text stream, optional
        Where to report the resume count, each failed design and, on a terminal, a progress bar
        (e.g. ``sys.stderr``); None: silent.

    Returns
    -------
    OptimizeResult

    Notes
    -----
    With a folder, its ``optimize.json`` is written first and every finished evaluation is
    appended to its journal at once (:mod:`acoustiviz.sweep.optimise`), so a Ctrl-C keeps them and
    the same job resumes them; without one the journal lives in a temporary folder.
    """
    import tempfile

    from ..files import write_text_atomic
    from ..sweep.optimise import JOURNAL, read_journal, run_optimisation
    from ..sweep.problem import feasible_mask, objective_matrix, pareto_mask
    from ..sweep.progress import Progress
    from .names import user_terms

    with user_terms(job.names), tempfile.TemporaryDirectory() as scratch:
        folder = Path(job.out) if job.out is not None else Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        if job.out is not None:
            write_text_atomic(folder / FILES[2], optimize_json_text(job))
        before = min(len(read_journal(folder / JOURNAL, "out")), job.evaluations)
        bar = Progress(job.evaluations, before, progress, bar=None if before < job.evaluations else False,
                       desc="optimize", unit="design")
        if before:
            bar.say(f"optimize: resuming {folder}: {before} of {job.evaluations} evaluations done before")

        def report(record):
            bar.update()
            if record["row"].get("error"):
                bar.say(f"optimize: evaluation {record['evaluation']} failed: {record['row']['error']}")

        try:
            records = run_optimisation(job.problem, job.evaluator(), folder, executor=job.executor,
                                       workers=job.workers, report=report)
        except KeyboardInterrupt:
            bar.close()
            kept = len(read_journal(folder / JOURNAL, "out"))
            bar.say(f"optimize: stopped; {kept} of {job.evaluations} evaluations kept in {folder / JOURNAL}")
            raise
        finally:
            bar.close()
    rows = [r["row"] for r in records]
    feasible = feasible_mask(job.problem, rows)
    front = pareto_mask(objective_matrix(job.problem, rows), feasible) if rows else feasible
    result = OptimizeResult(job, tuple(records), feasible, front)
    if job.mode != "operation":
        return result
    from dataclasses import replace

    from .optimize_confirm import confirm

    if progress is not None:
        progress.write("optimize: confirming the chosen design's worst case with twice the starts\n")
    return replace(result, confirmation=confirm(result))


def summary(result: OptimizeResult) -> list:
    """Lines reporting the best feasible design or the size of the front, or that none is feasible."""
    job = result.settings
    n, n_ok = len(result.records), int(result.feasible.sum())
    failed = sum(1 for r in result.records if r["row"].get("error"))
    lines = [f"optimize: {n} designs evaluated ({failed} failed), {n_ok} feasible"]
    if not n_ok:
        return lines + ["optimize: no evaluated design is feasible: loosen the constraints or evaluate more"]
    if job.mode == "operation":  # the chosen design's confirmation, after the lines about it
        from .optimize_confirm import confirmation_line

        return _design_lines(result, lines) + [confirmation_line(result.confirmation)]
    return _design_lines(result, lines)


def _design_lines(result: OptimizeResult, lines: list) -> list:
    """``lines`` and the size of the front or the best design."""
    job = result.settings
    best = result.best()
    objectives = job.problem.objectives
    searched = [v.name for v in job.problem.searched]
    if len(objectives) > 1:
        lines.append(f"optimize: Pareto front of {len(best)} designs (pareto.csv)")
        return lines
    row = best[0]
    rec = result.records[row["evaluation"]]
    where = ", ".join(f"{k} = {rec['params'][k]:.6g}" if isinstance(rec["params"][k], float) else
                      f"{k} = {rec['params'][k]}" for k in searched)
    o = objectives[0]
    lines.append(f"optimize: best design (evaluation {row['evaluation']}): {where}: {o.column} = {row[o.column]:.6g}")
    return lines
