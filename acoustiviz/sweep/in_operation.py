"""A sweep folder of designs in operation: the journal of :func:`acoustiviz.sweep.operation.run_operation`'s rows.

A sweep in operation keeps the files of a sweep of free vibration (:mod:`acoustiviz.sweep.store`):
``sweep.json`` holds the grid and, under its ``operation`` key, the excitation and search settings
(:func:`operation_document`) and the chain length; ``sweep.csv`` holds one row of
:data:`~acoustiviz.sweep.operation.OPERATION_COLUMNS` (with ``balls`` and ``fill`` when the designs name them,
:func:`~acoustiviz.sweep.operation.operation_columns`) per design, appended, flushed and synced as each
chain of designs finishes. A folder resumes only with the same grid and the same operation (a folder of
free vibration, or one made under another excitation, is refused as made with different settings); the
chains are cut from the whole design list, so a resumed sweep runs only the chains it lacks, each whole,
and writes the rows an uninterrupted one would. Ranking: :data:`OPERATION_RANK` says, for each numeric
column, whether the smaller or the larger value is the better design.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from .operation import Operation, check_operation, operation_chains, operation_columns, run_chains
from .progress import Progress
from .spec import SweepSpec
from .store import (
    SWEEP_CSV,
    SWEEP_JSON,
    Journal,
    SweepTable,
    load_sweep,
    prepare_dir,
    put_in_design_order,
    read_document,
    read_rows,
    read_spec,
    table_from_rows,
)

__all__ = ["OPERATION_CHAIN", "OPERATION_RANK", "operation_document", "operation_from_document",
           "run_sweep_in_operation", "load_any_sweep", "rank_in_operation"]

#: Consecutive designs one worker evaluates in order, sharing attractors (:func:`~acoustiviz.sweep.operation.
#: run_operation`'s ``chain``); recorded in ``sweep.json``, since the rows depend on it.
OPERATION_CHAIN = 8

#: Numeric column of a sweep in operation -> +1 when its smallest value is the best design, -1 its largest.
OPERATION_RANK = {
    "worst_amplitude_m": 1, "worst_amplitude_std_err_m": 1, "max_amplitude_without_damper_m": 1,
    "min_reduction_db": -1, "mean_reduction_db": -1, "worst_lcpeak_db": 1, "worst_laeq_db": 1,
    "worst_lafmax_db": 1, "chaotic_fraction": 1, "failed_runs": 1, "cycles_integrated": 1,
}


def operation_document(operation: Operation, chain: int = OPERATION_CHAIN) -> dict:
    """``operation`` and the chain length as the plain values ``sweep.json`` keeps (frequencies in Hz as a list)."""
    d = dataclasses.asdict(operation)
    d["frequencies"] = list(d["frequencies"])
    return {**d, "chain": int(chain)}


def operation_from_document(d: dict, name: str = "sweep") -> tuple:
    """``(Operation, chain)`` of :func:`operation_document`'s values; a damaged one raises ParameterError ``name``."""
    try:
        d = dict(d)
        chain = int(d.pop("chain"))
        return Operation(**{**d, "frequencies": tuple(d["frequencies"])}), chain
    except (TypeError, ValueError, KeyError, ParameterError) as exc:
        raise ParameterError(name, f"the operation in its {SWEEP_JSON} is damaged: {exc}") from None


def run_sweep_in_operation(spec: SweepSpec, operation: Operation, out_dir, *, executor=None,
                           workers: int | None = None, progress=None, bar: bool | None = None,
                           overwrite: bool = False, chain: int = OPERATION_CHAIN) -> SweepTable:
    """Run (or resume) every design of ``spec`` in operation, one ``sweep.csv`` row per design.

    Parameters
    ----------
    spec : SweepSpec
        The designs and fixed settings.
    operation : Operation
        The excitation and the search of each design's attractors.
    out_dir : path-like
        The sweep folder (created if needed); one holding this sweep is resumed.
    executor, workers, progress, bar, overwrite
        As for :func:`acoustiviz.sweep.run_sweep`.
    chain : int
        Consecutive designs evaluated in order by one worker (:func:`~acoustiviz.sweep.run_operation`).

    Returns
    -------
    SweepTable
        Every row of the folder (:func:`~acoustiviz.sweep.operation.operation_columns`), with ``operation`` set.

    Notes
    -----
    The rows of each chain are appended and synced as it finishes; on ``KeyboardInterrupt`` the
    pending chains are cancelled and the interrupt propagates, the rows written kept.
    """
    from .execute import check_executor_form

    if not isinstance(spec, SweepSpec):
        raise ParameterError("spec", f"expected a SweepSpec, got {type(spec).__name__}")
    check_executor_form(executor)
    designs = spec.designs()
    check_operation(designs, spec.settings, operation)
    chains = operation_chains(designs, chain)
    out = Path(out_dir)
    prepare_dir(spec, out, overwrite, operation_document(operation, chain))
    path = out / SWEEP_CSV
    columns = operation_columns(spec.with_balls)
    rows = read_rows(path, spec, "out", columns=columns)
    pending = [c for c in chains if any(d.design_id not in rows for d in c)]
    n_pending = sum(len(c) for c in pending)
    report = Progress(len(designs), len(designs) - n_pending, progress, bar=bar if pending else False)
    if not pending:
        report.say(f"sweep: all {len(designs)} designs already in {path}; nothing to compute")
    elif rows:
        report.say(f"sweep: resuming {out}: {len(rows)} of {len(designs)} designs done before, "
                   f"{n_pending} to compute")
    if pending:
        _run(pending, spec, operation, path, rows, report, executor=executor, workers=workers)
    put_in_design_order(path, rows, designs, columns)
    return table_from_rows(spec, rows, "out", columns=columns, operation=operation)


def _run(pending, spec, operation, path, rows, report, *, executor, workers) -> None:
    """Run the chains ``pending``, journaling each one's rows into ``rows`` and ``path`` as it finishes."""
    interrupted = True
    columns = operation_columns(spec.with_balls)
    try:
        with Journal(path, columns) as journal:
            def keep(chain_rows):
                for r in chain_rows:
                    if r["design_id"] not in rows:  # a chain torn by a kill: its rows written are kept
                        rows[r["design_id"]] = journal.append(r)
                    report.update()
                    if r["error"]:
                        report.say(f"sweep: design {r['design_id']} failed: {r['error']}")

            run_chains(pending, spec.settings, operation, executor=executor, workers=workers, on_rows=keep)
        interrupted = False
    finally:
        report.close()
        if interrupted:
            kept = len(read_rows(path, spec, "out", columns=columns))
            report.say(f"sweep: stopped; {kept} of {len(spec.designs())} designs kept in {path}")


def load_any_sweep(out_dir, name: str = "sweep") -> SweepTable:
    """A sweep folder of either kind as a :class:`SweepTable` (``operation`` set for one in operation)."""
    doc = read_document(out_dir, name)
    if "operation" not in doc["spec"]:
        return load_sweep(out_dir, name)
    operation, _ = operation_from_document(doc["spec"]["operation"], name)
    spec = read_spec(out_dir, name)
    path = Path(out_dir) / SWEEP_CSV
    if not path.is_file():
        raise ParameterError(name, f"{out_dir} holds no {SWEEP_CSV}")
    columns = operation_columns(spec.with_balls)
    rows = read_rows(path, spec, name, columns=columns)
    return table_from_rows(spec, rows, name, columns=columns, operation=operation)


def rank_in_operation(table: SweepTable, rank_by: str) -> np.ndarray:
    """Row indices of ``table``'s successful designs with a value of ``rank_by``, best first (ties: design order).

    Raises
    ------
    ParameterError
        Named ``rank_by`` when the column is not one of :data:`OPERATION_RANK`.
    """
    if rank_by not in OPERATION_RANK:
        raise ParameterError("rank_by", f"a sweep in operation ranks by one of {', '.join(OPERATION_RANK)}; "
                                        f"got {rank_by!r}")
    value = np.asarray(table[rank_by], dtype=float)
    ok = np.flatnonzero((table["success"] == 1) & np.isfinite(value))
    return ok[np.argsort(OPERATION_RANK[rank_by] * value[ok], kind="stable")]
