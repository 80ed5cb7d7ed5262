"""The design job: the quietest design of a sweep for a target damping inclination (paper Table 2).

Three parts, shared by ``acoustiviz design``, a scene's ``[outputs.design_table]`` and Python callers:

* :class:`~acoustiviz.app.settings.design.DesignJob`, the settings, checked once when made;
* :func:`run`, which reads the sweep (or takes the rows a scene's sweep just made) and answers: the design
  table and, for a target, the choice (no files, no printing);
* :meth:`DesignTableResult.write`, which writes the figure and the answer the settings ask for;
  :meth:`DesignTableResult.lines` is the report the command prints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from .settings.design import DesignJob

__all__ = ["DesignJob", "DesignTableResult", "run", "design_settings", "produce_design_table"]

#: The files of a scene's ``[outputs.design_table]`` in its run folder (:class:`DesignJob` fields -> names).
DESIGN_FILES = {"png": "design_table.png", "choice": "design_choice.txt"}


@dataclass(frozen=True, eq=False)
class DesignTableResult:
    """The design table of a sweep and the choice for a target.

    Attributes
    ----------
    settings : DesignJob
        What was asked.
    table : acoustiviz.sweep.SweepTable
        The sweep's rows.
    bands : tuple of acoustiviz.sweep.Band
        The design table with the job's definition and band width (inclinations in m/s, levels in dB).
    choice : acoustiviz.sweep.DesignChoice or None
        The answer for the target (None without one, and for a sweep in operation).
    ranking : tuple of int
        A sweep in operation: the rows of its successful designs, best first by ``rank_by``
        (:func:`acoustiviz.sweep.in_operation.rank_in_operation`); empty for free vibration.
    """

    settings: DesignJob
    table: object
    bands: tuple
    choice: object
    ranking: tuple = ()

    def lines(self) -> list[str]:
        """The report: an unfinished sweep noted, the choice, and with ``table`` the design table."""
        s, rows = self.settings, self.table
        lines = []
        if not rows.complete:
            lines.append(f"note: the sweep is unfinished ({len(rows)} of {len(rows.spec.designs())} designs)")
        if rows.operation is not None:
            return lines + self._operation_lines()
        if self.choice is not None:
            lines += self.choice.summary().splitlines()
        if s.table:
            lines += ["", f"design table ({s.definition} damping inclination, bands of {100 * s.band_width:g} cm/s):",
                      f"{'e (cm/s)':>9} {'n':>4} {'min SPLmax':>11} {'max SPLmax':>11} {'decrease':>9}  "
                      "quietest (m, d)"]
            lines += [_band_line(b) for b in self.bands]
        return lines

    def _operation_lines(self) -> list[str]:
        """A sweep in operation: its excitation, then its designs best first by ``rank_by`` (at most ten)."""
        from ..sweep.in_operation import OPERATION_RANK

        op, rows, k = self.table.operation, self.table, self.settings.rank_by
        f, unit = op.frequencies, "N" if op.kind == "force" else "m"
        sense = "smallest" if OPERATION_RANK[k] > 0 else "largest"
        lines = [f"sweep in operation: {op.kind} amplitude {op.amplitude:g} {unit} at {len(f)} frequencies "
                 f"{f[0]:g}-{f[-1]:g} Hz; {len(self.ranking)} of {len(rows)} designs ranked by {k} ({sense} first; "
                 "failed designs and designs without a value left out)"]
        if self.ranking:
            i = self.ranking[0]
            lines.append(f"best: design {rows['design_id'][i]} (m = {rows['mass_kg'][i]:.6g} kg, d = "
                         f"{rows['gap_m'][i]:.6g} m): {k} {rows[k][i]:.6g}")
            cols = [k] + [c for c in ("worst_laeq_db", "min_reduction_db", "worst_amplitude_m") if c != k]
            head = f"{'rank':>4} {'design':>6} {'m (kg)':>10} {'d (m)':>10} "
            lines.append(head + " ".join(f"{c:>18}" for c in cols))
            lines += [f"{n + 1:4d} {rows['design_id'][i]:6d} {rows['mass_kg'][i]:10.6g} {rows['gap_m'][i]:10.6g} "
                      + " ".join(f"{rows[c][i]:18.6g}" for c in cols) for n, i in enumerate(self.ranking[:10])]
        return lines

    def write(self, folder=None) -> list:
        """Write the figure and the answer the settings ask for into ``folder``; return their paths.

        Parameters
        ----------
        folder : path-like, optional
            Where relative file names are put (default: as given, the current folder).

        Returns
        -------
        list of pathlib.Path
        """
        from ..files import write_text_atomic

        files = {k: Path(v) if folder is None else Path(folder) / v for k, v in self.settings.files().items()}
        paths = []
        if "png" in files:
            from ..output.plot.design import plot_design_table
            from ..output.plot.style import save_figure
            from ..sweep import PAPER_TABLE2

            ax = plot_design_table(self.bands, paper=PAPER_TABLE2)
            paths.append(save_figure(ax.figure, files["png"]))
        if "choice" in files and self.table.operation is not None:  # the ranking of a sweep in operation
            paths.append(write_text_atomic(files["choice"], "\n".join(self._operation_lines()) + "\n"))
        elif "choice" in files and self.choice is not None:
            paths.append(write_text_atomic(files["choice"], self.choice.summary() + "\n"))
        return paths


def _band_line(b) -> str:
    ranges = "".join(f"; {name} {lo:.1f}-{hi:.1f} dB" for name, (lo, hi) in
                     zip(("LAFmax", "LCpeak", "LAeq"), (b.level_ranges or {}).values(), strict=False)
                     if math.isfinite(lo))
    return (f"{100 * b.centre:9.2f} {b.n_designs:4d} {b.min_spl_db:11.1f} {b.max_spl_db:11.1f} "
            f"{b.decrease_db:9.1f}  {1000 * b.quietest_mass:.1f} g, {100 * b.quietest_gap:.2f} cm{ranges}")


def run(settings: DesignJob, table=None) -> DesignTableResult:
    """Answer ``settings`` from its sweep folder, or from ``table`` (the rows of a sweep just run).

    Parameters
    ----------
    settings : DesignJob
        The job, checked when it was made.
    table : acoustiviz.sweep.SweepTable, optional
        The sweep's rows (default: read from ``settings.sweep``).

    Returns
    -------
    DesignTableResult
    """
    from ..errors import ParameterError, user_terms
    from ..sweep import design, design_table
    from ..sweep.in_operation import load_any_sweep, rank_in_operation

    s = settings
    if table is None:
        if s.sweep is None:
            raise ParameterError(s.names.get("sweep", "sweep"), "a design needs a sweep folder or its rows")
        with user_terms(s.names):
            table = load_any_sweep(s.sweep)
    if table.operation is not None:
        with user_terms(s.names):
            return DesignTableResult(s, table, (), None, tuple(int(i) for i in rank_in_operation(table, s.rank_by)))
    bands = tuple(design_table(table, definition=s.definition, width=s.band_width))
    choice = None if s.inclination is None else design(table, s.inclination, s.tolerance, definition=s.definition,
                                                       rank_by=s.rank_by)
    return DesignTableResult(s, table, bands, choice)


def design_settings(scene, out=None) -> DesignJob:
    """The scene's ``[outputs.design_table]`` as a :class:`DesignJob`.

    The sweep is the scene's (``sweep`` in folder ``out``, once it exists), the files ``design_table.png`` and
    ``design_choice.txt`` in ``out`` (None: no files, the checks of the scene's settings alone, made before the
    run folder exists); errors name scene keys.
    """
    opts = scene.output("design_table")
    in_operation = scene.output("sweep")["in_operation"]  # a ranking, no design table figure
    files = {} if out is None else {k: str(Path(out) / name) for k, name in DESIGN_FILES.items()
                                    if not (in_operation and k == "png")}
    sweep = None if out is None or not (Path(out) / "sweep").is_dir() else str(Path(out) / "sweep")
    names = DesignJob.names_for("scene")
    return DesignJob(inclination=opts["inclination_m_s"], tolerance=opts["tolerance_m_s"], sweep=sweep,
                     rank_by=opts["rank_by"],
                     max_memory_mb=scene.section("grids")["memory_limit_mb"], names=names, **files)


def produce_design_table(ctx):
    """Paper Table 2 from the scene's sweep as a figure beside the paper's, and the quietest design for a target."""
    from .products import Product

    rows = ctx.sweep.table  # the scene's one sweep (a scene without [outputs.sweep] is refused at load time)
    settings = design_settings(ctx.scene, ctx.out)
    for path in settings.files().values():  # only the files checked before the run
        ctx.path(Path(path).name)
    result = run(settings, table=rows)
    if rows.operation is not None:
        figs = {"ranked": str(len(result.ranking))}
        if result.ranking:
            figs["best_design"] = str(rows["design_id"][result.ranking[0]])
        return [Product("design_table", p, figs) for p in result.write()]
    png, *choice = result.write()
    products = [Product("design_table", png, {"bands": str(len(result.bands))})]
    if choice:
        figs = {"candidates": str(result.choice.n_candidates)}
        if result.choice.n_candidates:
            figs["saving_db"] = f"{result.choice.saving_db:.1f}"
        products.append(Product("design_table", choice[0], figs))
    return products
