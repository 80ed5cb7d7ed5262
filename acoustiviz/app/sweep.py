"""The sweep job: a grid of damper designs, its journal and its reports (``acoustiviz sweep``, ``[outputs.sweep]``).

Three parts, shared by ``acoustiviz sweep``, a scene's ``[outputs.sweep]`` and Python callers:

* :class:`~acoustiviz.app.settings.sweep_job.SweepJob`, the settings, checked once when made
  (:func:`~acoustiviz.app.settings.sweep_job.sweep_job` builds it from values as typed);
* :func:`run`, which runs (or resumes) the designs into the job's folder -- ``sweep.json`` and one
  ``sweep.csv`` row per finished design, so an interrupted sweep keeps what finished and the same job
  resumes it -- and returns a :class:`SweepResult`;
* :meth:`SweepResult.write`, which writes the reports: ``design_table.csv`` (paper Table 2) and, for
  gap x mass sweeps, the Figure 6 maps (none for a sweep in operation, whose rows are the product and
  which ``acoustiviz design`` ranks).

A job with an ``operation`` (``--force``/``--base`` and ``--freq``, or ``in_operation`` in a scene)
evaluates every design in operation (:mod:`acoustiviz.sweep.in_operation`): ``sweep.csv`` then holds
:data:`~acoustiviz.sweep.OPERATION_COLUMNS`.

The scene builds the job in :func:`sweep_settings` from the same records, so the same settings give the
same ``sweep.json`` -- and either front end resumes the other's folder. SI units; angles in rad.

Examples
--------
>>> spec = sweep_spec(gap="0.02:0.06:5", m="0.02,0.04", duration=1.0)
>>> spec.gap, spec.m, spec.settings.rtol
((0.02, 0.03, 0.04, 0.05, 0.06), (0.02, 0.04), 1e-13)
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

from ..constants import PAPER_RADIUS
from ..sweep import DESIGN_TABLE_CSV, SWEEP_CSV, SweepSpec
from .names import SCENE_SWEEP_KEYS, SWEEP_OPTIONS
from .settings.sweep import sweep_radius
from .settings.sweep_job import INCLINATION_MAP, SPL_MAP, SweepJob, sweep_job

__all__ = ["SweepJob", "SweepResult", "run", "sweep_spec", "sweep_settings", "scene_sweep_spec", "sweep_summary",
           "produce_sweep", "with_room", "SWEEP_OPTIONS"]


@dataclass(frozen=True, eq=False)
class SweepResult:
    """The rows of a finished (or resumed) sweep and its design table.

    Attributes
    ----------
    settings : SweepJob
        What was run.
    table : acoustiviz.sweep.SweepTable
        Every row of the folder.
    bands : tuple of acoustiviz.sweep.Band
        The design table (paper Table 2) with the job's definition and band width (empty in operation:
        no damping inclination).
    seconds : float
        Wall time of this run in s (reported only).
    """

    settings: SweepJob
    table: object
    bands: tuple
    seconds: float

    @property
    def journal(self) -> Path:
        """``sweep.csv``."""
        return self.settings.folder() / SWEEP_CSV

    @property
    def others(self) -> list:
        """Swept axes besides gap and mass (the maps are drawn only for gap x mass sweeps; a fill sets the gaps)."""
        spec = self.table.spec
        return [a for a in spec.swept() if a not in ("gap", "m")] + (["fill"] if spec.fill is not None and
                                                                      "fill" not in spec.swept() else [])

    def write(self, folder=None) -> list:
        """Write ``design_table.csv`` and, for gap x mass sweeps, the two Figure 6 maps; return their paths.

        Parameters
        ----------
        folder : path-like, optional
            Where to write (default: the job's sweep folder).

        Returns
        -------
        list of pathlib.Path
        """
        from ..output.plot.style import save_figure
        from ..sweep import write_design_table

        if self.settings.operation is not None:  # the rows are the product; ranked by acoustiviz design
            return []
        out = self.settings.folder() if folder is None else Path(folder)
        paths = [write_design_table(self.bands, out / DESIGN_TABLE_CSV)]
        if not self.others and len(self.table):
            from ..output.plot.design import plot_inclination_map, plot_spl_map

            ax = plot_inclination_map(self.table, definition=self.settings.definition)
            paths.append(save_figure(ax.figure, out / INCLINATION_MAP))
            ax = plot_spl_map(self.table)
            paths.append(save_figure(ax.figure, out / SPL_MAP))
        return paths


def run(settings: SweepJob, progress=None, *, bar=None) -> SweepResult:
    """Run (or resume) the designs of ``settings`` into its folder; its journal is written as designs finish.

    Parameters
    ----------
    settings : SweepJob
        The job, checked when it was made.
    progress : text stream, optional
        Where to report the resume count, failed designs and a progress bar (None: silent).
    bar : bool, optional
        Draw the bar on ``progress`` (None: only on a terminal).

    Returns
    -------
    SweepResult
    """
    from ..errors import user_terms
    from ..sweep import design_table, run_sweep

    s = settings
    t0 = time.perf_counter()
    if s.operation is not None:
        from ..sweep.in_operation import run_sweep_in_operation

        with user_terms(s.names):
            table = run_sweep_in_operation(s.spec, s.operation, s.folder(), executor=s.executor, workers=s.workers,
                                           progress=progress, bar=bar, overwrite=s.overwrite)
        return SweepResult(s, table, (), time.perf_counter() - t0)
    with user_terms(s.names):
        table = run_sweep(s.spec, s.folder(), executor=s.executor, workers=s.workers, progress=progress, bar=bar,
                          overwrite=s.overwrite)
    seconds = time.perf_counter() - t0
    return SweepResult(s, table, tuple(design_table(table, definition=s.definition, width=s.band_width)), seconds)


def sweep_spec(**given) -> SweepSpec:
    """The :class:`~acoustiviz.sweep.SweepSpec` of values as typed (:func:`.settings.sweep_job.sweep_job`).

    Errors name the API parameters.
    """
    return sweep_job(given).spec


def sweep_summary(result: SweepResult, paths=()) -> list[str]:
    """Lines reporting a sweep: designs, failures, the files ``paths`` written, the largest acoustic saving."""
    table, out = result.table, result.settings.folder()
    lines = [f"sweep: {len(table)} designs in {out} ({result.seconds:.1f} s this run)"]
    n_failed = int(table.failed.sum())
    if n_failed:
        ids = ", ".join(str(i) for i in table["design_id"][table.failed][:10])
        lines.append(f"failed designs: {n_failed} (design_id {ids}{', ...' if n_failed > 10 else ''}; "
                     f"reasons in the error column of {result.journal})")
    lines += [f"wrote {p}" for p in paths]
    if result.settings.operation is not None:
        return lines + _operation_lines(result)
    if result.others:
        lines.append(f"maps skipped: they need only --gap and --m swept (also swept: {', '.join(result.others)})")
    best = max(result.bands, key=lambda b: b.decrease_db, default=None)
    if best is not None:
        lines.append(f"largest acoustic saving at equal damping ({result.settings.definition}): {best.decrease_db:.1f} "
                     f"dB in the band {100 * best.low:.3g}-{100 * best.high:.3g} cm/s ({best.n_designs} designs)")
    return lines


def _operation_lines(result: SweepResult) -> list[str]:
    """The excitation of a sweep in operation and its quietest design by the worst LAeq."""
    from ..sweep.in_operation import rank_in_operation

    op, table = result.settings.operation, result.table
    f = op.frequencies
    unit = "N" if op.kind == "force" else "m"
    lines = [f"in operation: {op.kind} amplitude {op.amplitude:g} {unit}, {len(f)} frequencies "
             f"{f[0]:g}-{f[-1]:g} Hz, {op.starts} starts, solver {op.solver}"]
    best = rank_in_operation(table, "worst_laeq_db")
    if best.size:
        i = best[0]
        lines.append(f"quietest by worst_laeq_db: design {table['design_id'][i]} (m {1000 * table['mass_kg'][i]:.1f} "
                     f"g, d {100 * table['gap_m'][i]:.2f} cm): {table['worst_laeq_db'][i]:.1f} dB, smallest "
                     f"reduction {table['min_reduction_db'][i]:.1f} dB")
    return lines


def _scene_listener(scene) -> tuple:
    """The first listener's distance in m and angle in degrees from the sphere's centre and axis."""
    listener = scene.data["listeners"][0]
    if listener["position_m"] is None:
        return listener["distance_m"], listener["angle_deg"]
    import numpy as np

    (_, pos), *_ = scene.listeners()
    geom = scene.geometry()
    rel = np.asarray(pos) - np.asarray(geom.centre)
    distance = float(np.linalg.norm(rel))
    return distance, math.degrees(math.acos(max(-1.0, min(1.0, float(rel @ np.asarray(geom.axis)) / distance))))


def _scene_operation(scene) -> dict:
    """The values of a sweep in operation (``in_operation``): the scene's ``[excitation]``, else none.

    The excitation is the scene's one, as its frequency response reads it; the level interval is
    ``[outputs.sweep] noise_seconds`` (the record of ``--noise-seconds``).
    """
    opts = scene.output("sweep")
    if not opts["in_operation"]:
        return {}
    from .settings.forced import FORCED

    excitation = scene.section("excitation")
    search = {s.name: excitation[s.key] for s in FORCED if s.table == "excitation"}  # the scene's checked values
    return {excitation["kind"]: excitation["amplitude"], "frequencies": excitation["frequencies_hz"],
            **{k: search[k] for k in ("sweep", "solver", "starts", "tolerance", "rtol", "max_cycles")},
            "noise_seconds": opts["noise_seconds"]}


def _scene_given(scene, solver: str) -> dict:
    """The :func:`~acoustiviz.app.settings.sweep_job.sweep_job` values of a scene's tables."""
    from ..dynamics import solver_method

    opts = scene.output("sweep")
    d, s, c = scene.section("damper"), scene.section("sphere"), scene.section("contact")
    distance, angle_deg = _scene_listener(scene)
    medium = scene.medium()
    from_mass = s["damper_radius"] == "from-mass"
    stiffness = {"material": s["material"]} if (s["material"] and c["k_hertz_n_m1_5"] is None) else \
        {"k_hertz": scene.k_hertz()}
    given = dict(gap=opts["gap_m"], m=opts["mass_kg"], c1=d["contact_damping_n_s_m"], v0=d["initial_velocity_m_s"],
                 distance=distance, angle_deg=angle_deg, config=scene.section("configuration")["kind"],
                 M=d["main_mass_kg"], K=d["stiffness_n_m"], C=d["damping_n_s_m"], clip_tensile=d["clip_tensile"],
                 duration=opts["duration_s"], solver=solver, rtol=solver_method(d["solver"]).run_rtol(d["tolerance"]),
                 radius="mass" if from_mass else s["radius_m"], density=s["density_kg_m3"] if from_mass else None,
                 surface=c["surface"], pulse=c["pulse"], pulse_mass=c["pulse_mass"], c=medium.c, rho=medium.rho,
                 wall_distance=scene.section("configuration")["wall_distance_m"], levels=opts["levels"],
                 room=scene.geometry_settings().get("room"), balls=opts.get("balls"), fill=opts.get("fill"),
                 equal_total_mass=opts.get("equal_total_mass", False), k_hertz_ball=d["k_hertz_ball_n_m1_5"],
                 c1_ball=d["contact_damping_ball_n_s_m"], **stiffness)
    operation = _scene_operation(scene)
    if operation:  # the search's solver and rtol; the free run's own settings left at their defaults
        from .settings.sweep_operation import FREE_VIBRATION_ONLY

        given = {k: v for k, v in given.items() if k not in FREE_VIBRATION_ONLY}
    return {**given, **operation}


def sweep_settings(scene, out=None, *, solver: str | None = None, names=None) -> SweepJob:
    """The scene's ``[outputs.sweep]`` (gap x impact mass) as a :class:`SweepJob`.

    The listener is the scene's first; ``solver`` is the damper solver the scene resolved (default: its
    ``"auto"`` choice); with ``in_operation`` the designs are swept in operation under the scene's
    ``[excitation]`` (its solver and rtol then the search's); the folder is ``sweep`` in folder ``out``
    (None: no folder, the checks of the scene's settings alone, made before the run folder exists); the
    memory within ``grids.memory_limit_mb``; errors name scene keys (``names``: API parameter -> scene key,
    default :data:`~acoustiviz.app.names.SCENE_SWEEP_KEYS`).
    """
    from ..errors import SceneError, user_terms

    if scene.geometry_settings().get("strike", "floor") != "floor":
        raise SceneError(scene.source, "configuration.strike", "sweeps support floor strikes only")
    if solver is None:
        from .products import damper_solver

        solver = damper_solver(scene)
    opts, names = scene.output("sweep"), names or SCENE_SWEEP_KEYS
    with user_terms(names):
        given = _scene_given(scene, solver)
    return sweep_job(given, names=names, out=None if out is None else str(Path(out) / "sweep"),
                     workers=opts["workers"] or None, max_memory_mb=scene.section("grids")["memory_limit_mb"])


def scene_sweep_spec(scene, solver: str | None = None, *, names=None) -> SweepSpec:
    """The :class:`~acoustiviz.sweep.SweepSpec` of a scene's ``[outputs.sweep]`` (:func:`sweep_settings`)."""
    return sweep_settings(scene, solver=solver, names=names).spec


def produce_sweep(ctx):
    """Scene output ``sweep``: the scene's one sweep (``sweep/sweep.csv``), its design table and maps."""
    from .products import Product

    ctx.path("sweep")  # only the folder checked before the run
    result = ctx.sweep
    paths = result.write()
    import numpy as np

    table = result.table
    figs = {"designs": str(len(table))}
    n_failed = int(table.failed.sum())
    if n_failed:
        figs["failed_designs"] = str(n_failed)
    if result.settings.operation is not None:
        laeq = np.asarray(table["worst_laeq_db"])
        if np.isfinite(laeq).any():
            figs["worst_laeq_db_range"] = f"{np.nanmin(laeq):.1f}-{np.nanmax(laeq):.1f}"
        return [Product("sweep", result.journal, figs)]
    spl = np.asarray(table["max_spl_db"])
    if np.isfinite(spl).any():
        figs["max_spl_db_range"] = f"{np.nanmin(spl):.1f}-{np.nanmax(spl):.1f}"
    best = max(result.bands, key=lambda b: b.decrease_db, default=None)
    if best is not None:
        figs["largest_saving_db"] = f"{best.decrease_db:.1f} at {100 * best.low:.3g}-{100 * best.high:.3g} cm/s"
    return [Product("sweep", result.journal, figs)] + [Product("sweep", p, {}) for p in paths]


def with_room(given: dict, room: dict | None, *, names=None) -> dict:
    """The :func:`~acoustiviz.app.settings.sweep_job.sweep_job` values ``given`` with a shoebox room's.

    Parameters
    ----------
    given : dict
        The values given.
    room : dict or None
        The room's settings (:func:`acoustiviz.app.impacts.room_settings`: dimensions in m,
        absorption, source in m, the window ``duration`` in s, ...); None: ``given`` unchanged.

    Returns
    -------
    dict
        ``given`` with ``room`` and, unless a configuration is given, ``config="room"``. The room
        is built once around the sweep's sphere (the paper's radius when it follows the mass), so
        a source too close to a wall or a window without images fails here; errors name the room's
        parameters as ``names`` says (API parameter -> option or scene key; default: the API names).
        Its dimensions, absorption and source are kept as the numbers the room read (text such as
        ``"6,4,3"`` becomes ``(6.0, 4.0, 3.0)``), so the same room typed or listed is the same setting.
    """
    if room is None:
        return given
    from ..core.geometry import geometry
    from ..core.room_geometry import Room
    from ..errors import user_terms

    with user_terms(names or {}):
        built = geometry(Room.name, sweep_radius(given.get("radius", PAPER_RADIUS))[1], **room)
    read = {k: getattr(built, k) for k in ("dimensions", "absorption", "source") if k in room}
    return {**given, "config": given.get("config") or Room.name, "room": {**room, **read}}
