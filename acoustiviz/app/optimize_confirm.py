"""The confirmation of an optimisation in operation: the chosen design's worst case found again by ``forced``.

An optimisation in operation ranks designs by a worst case over the band found with a few starts per
frequency; a start that misses an attractor with a small basin makes a design look better than it is,
and the optimiser is drawn to exactly such designs. :func:`confirm` reruns the ``forced`` job
(:func:`acoustiviz.app.forced.run` on a :class:`~acoustiviz.app.settings.forced_job.ForcedJob`; a design of
several balls: the same multi-ball search on its own balls) on the chosen design with twice the starts and
condenses its attractors as the optimisation did
(:func:`acoustiviz.sweep.operation.summarise`). The two worst amplitudes agree when both are periodic
and equal within the orbits' tolerance, or when they differ by at most :data:`AGREEMENT_ERRORS`
combined standard errors of their batch means.
"""

from __future__ import annotations

import math

__all__ = ["AGREEMENT_ERRORS", "CONFIRMATION_COLUMNS", "confirm", "confirmation_csv_text", "confirmation_line"]

#: Combined standard errors sqrt(se1² + se2²) within which two non-periodic worst amplitudes agree (two: a
#: difference of pure sampling noise passes about 95 % of the time).
AGREEMENT_ERRORS = 2.0
#: The worst-case columns of each side, from the optimisation's row and from the confirmation.
_WORST = ("worst_amplitude_m", "worst_amplitude_std_err_m", "worst_frequency_hz", "worst_regime")
#: The columns of ``confirmation.csv`` after the evaluation and the design's variables.
CONFIRMATION_COLUMNS = ("starts", *_WORST, "confirmation_starts", *(f"confirmed_{c}" for c in _WORST), "agree")


def _chosen(result):
    """The record confirmed: the best feasible design (several objectives: the front's first), or None."""
    best = result.best()
    return result.records[best[0]["evaluation"]] if best else None


def confirm(result, progress=None) -> dict | None:
    """The confirmation row of an optimisation in operation's chosen design (None: no feasible design).

    Parameters
    ----------
    result : acoustiviz.app.optimize.OptimizeResult
        A finished optimisation in operation.
    progress : callable, optional
        Handed to :func:`acoustiviz.app.forced.run`.

    Returns
    -------
    dict or None
        ``evaluation``, the design's variables (API names) and :data:`CONFIRMATION_COLUMNS` (m, Hz).
    """
    from dataclasses import replace

    from ..constants import FORCED_MAX_STARTS
    from ..sweep.operation import _model, _search, summarise
    from .forced import run
    from .settings.forced_job import ForcedJob

    record = _chosen(result)
    if record is None:
        return None
    job = result.settings
    op = job.operation
    design = job.evaluator().design(record["evaluation"], record["params"])
    starts = min(2 * op.starts, FORCED_MAX_STARTS)
    if design.balls > 1:  # the multi-ball search of ``forced --balls``, on the design's own balls (their material)
        again = summarise(_search(_model(design, job.fixed), replace(op, starts=starts), None, math.inf))
    else:
        forced = ForcedJob(model=_model(design, job.fixed), frequencies=op.frequencies, kind=op.kind,
                           amplitude=op.amplitude, sweep=op.sweep, solver=op.solver, starts=starts,
                           tolerance=op.tolerance, rtol=op.rtol, max_cycles=op.max_cycles,
                           restitution=op.restitution, noise=False, workers=1)
        again = summarise(run(forced, progress=progress).response.per_frequency)
    row = record["row"]
    out = {"evaluation": record["evaluation"], **record["params"], "starts": op.starts,
           **{c: row[c] for c in _WORST}, "confirmation_starts": starts,
           **{f"confirmed_{c}": again[c] for c in _WORST}}
    out["agree"] = agree(row, again, op.tolerance)
    return out


def agree(a: dict, b: dict, tolerance: float) -> bool:
    """Whether two worst cases (``worst_amplitude_m`` and its standard error, m) agree (module docstring)."""
    x, y = float(a["worst_amplitude_m"]), float(b["worst_amplitude_m"])
    ex, ey = float(a["worst_amplitude_std_err_m"]), float(b["worst_amplitude_std_err_m"])
    if not all(math.isfinite(v) for v in (x, y, ex, ey)):
        return False
    if ex == 0.0 and ey == 0.0:  # two periodic orbits: the same one, to the tolerance of its shooting
        return math.isclose(x, y, rel_tol=1e-6, abs_tol=tolerance)
    return abs(x - y) <= AGREEMENT_ERRORS * math.hypot(ex, ey)


def confirmation_csv_text(result, row: dict | None) -> str:
    """``confirmation.csv``: a header and the confirmation row (none when no design was feasible)."""
    import csv
    import io

    from ..sweep.store import format_value

    names = [v.name for v in result.settings.problem.variables]
    columns = ("evaluation", *names, *CONFIRMATION_COLUMNS)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    if row is not None:
        w.writerow([("true" if row[c] else "false") if isinstance(row[c], bool) else format_value(row[c])
                    for c in columns])
    return buf.getvalue()


def confirmation_line(row: dict | None) -> str:
    """The one line the command prints about the confirmation."""
    if row is None:
        return "optimize: no feasible design to confirm"
    verdict = "agrees" if row["agree"] else "DISAGREES"
    advice = "" if row["agree"] else "; search each design with more starts"
    return (f"optimize: confirmation of evaluation {row['evaluation']} with {row['confirmation_starts']} starts "
            f"{verdict}: worst amplitude {row['worst_amplitude_m']:.6g} m ({row['worst_regime']}) in the "
            f"optimisation, {row['confirmed_worst_amplitude_m']:.6g} m ({row['confirmed_worst_regime']}) confirmed "
            f"(confirmation.csv{advice})")
