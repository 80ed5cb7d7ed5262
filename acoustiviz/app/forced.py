"""The forced job: the damper in operation, its frequency response, bifurcation diagram and noise, for every front end.

Three parts, shared by ``acoustiviz forced``, a scene's ``[outputs.frequency_response]``,
``[outputs.bifurcation]`` and ``[outputs.operating_noise]`` and Python callers:

* :class:`~acoustiviz.app.settings.forced_job.ForcedJob`, the settings, checked once when made;
* :func:`run`, which finds every attractor of each frequency (:mod:`acoustiviz.dynamics.forced`) and,
  when asked, their noise in operation (:mod:`acoustiviz.app.forced_noise`: LAeq, LCpeak, LAFmax of
  the steady click train at a listener), returning a :class:`ForcedResult` (no files, no printing);
* :meth:`ForcedResult.write`, which writes the files the settings asked for and returns their paths.

SI units; frequencies in Hz.

Examples
--------
>>> parse_frequencies("3:7:5").tolist()
[3.0, 4.0, 5.0, 6.0, 7.0]
>>> parse_frequencies("4.5, 5").tolist()
[4.5, 5.0]
"""

from __future__ import annotations

import csv
import io
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..dynamics.forced import AttractorResponse, attractor_response, describe
from .forced_noise import (
    NOISE_COLUMNS,
    DesignMap,
    OperatingNoise,
    add_operating_noise,
    check_listener,
    default_listener,
    design_map,
    mark_worst_case,
    noise_statement,
    operating_noise,
    write_noise_csv,
    write_operating_wav,
)
from .settings.forced_job import ForcedJob
from .settings.parse import parse_frequencies

__all__ = ["ForcedJob", "ForcedResult", "run", "forced_settings", "forced_table", "FORCED_CSV_COLUMNS",
           "NOISE_COLUMNS", "OperatingNoise", "add_operating_noise", "check_listener", "default_listener",
           "operating_noise", "parse_frequencies", "write_forced_csv", "write_forced_png", "write_operating_wav",
           "DesignMap", "design_map", "report", "produce_frequency_response", "produce_bifurcation",
           "produce_operating_noise"]

#: Columns of the frequency-response CSV, one row per (frequency, attractor); the first eight
#: and ``attractor, basin_fraction, stable, max_floquet_modulus, residual, amplitude_std_err_m``
#: are promised.
FORCED_CSV_COLUMNS = (
    "frequency_hz", "amplitude_m", "amplitude_without_damper_m", "reduction_db", "impacts_per_cycle",
    "regime", "laeq_db", "lcpeak_db", "lafmax_db", "period_cycles", "converged", "cycles", "x_max_m", "x_min_m",
    "mean_impact_speed_m_s", "max_impact_speed_m_s", "impact_phases_deg", "energy_closure",
    "regime_change", "lzpeak_db", "lzeq_db", "sel_per_cycle_db", "sel_a_per_cycle_db", "level_interval_s",
    "attractor", "basin_fraction", "stable", "max_floquet_modulus", "residual", "amplitude_std_err_m",
    "attractors", "hysteresis", "worst_case", "lyapunov_1_s", "lyapunov_std_err_1_s", "newton_iterations",
    "cycles_integrated", "solver", "tolerance", "rtol", "starts", "max_cycles", "message",
)
#: Columns added with several balls (after :data:`FORCED_CSV_COLUMNS`): the balls on the main mass, the
#: collisions of a ball with a wall and of two balls per cycle, and the two balls' share of all collisions.
BALL_CSV_COLUMNS = ("balls", "cavities", "wall_impacts_per_cycle", "ball_collisions_per_cycle", "ball_ball_share")


@dataclass(frozen=True, eq=False)
class ForcedResult:
    """The attractors of a :class:`~acoustiviz.app.settings.forced_job.ForcedJob`, their table and their noise.

    Attributes
    ----------
    settings : ForcedJob
        What was computed.
    response : AttractorResponse
        Every attractor of each frequency.
    rows : tuple of dict
        One row per (frequency, attractor), keys :data:`FORCED_CSV_COLUMNS` (the level columns filled
        with the noise in operation).
    noises : tuple or None
        The :class:`OperatingNoise` of each row (None where its run failed); None without the noise.
    elapsed : float
        Wall time of the attractors' runs in s.
    cpu : float
        CPU time of this process during those runs in s (worker processes not included).
    noise_elapsed : float
        Wall time of the noise in operation in s (0 without it).
    """

    settings: ForcedJob
    response: AttractorResponse
    rows: tuple
    noises: tuple | None
    elapsed: float
    cpu: float = math.nan
    noise_elapsed: float = 0.0

    @property
    def columns(self) -> tuple:
        """The CSV columns of this run (with several balls, :data:`BALL_CSV_COLUMNS` added)."""
        return FORCED_CSV_COLUMNS + (BALL_CSV_COLUMNS if self.settings.several_balls else ())

    @property
    def steady_states(self) -> list:
        """The :class:`acoustiviz.dynamics.forced.SteadyState` of each row."""
        return [a for _, _, a, _ in self.response.entries()]

    @property
    def failed(self) -> list:
        """The steady states whose run failed."""
        return [r for r in self.steady_states if not r.success]

    @property
    def success(self) -> bool:
        """True when every run completed (whatever its regime)."""
        return not self.failed

    def write(self, folder=None, *, only=None) -> list:
        """Write the files the settings ask for into ``folder``; return their paths.

        The WAV of the frequencies in turn and its JSON sidecar, the level table, the attractors' table,
        the three-panel figure, the frequency response and the bifurcation diagram, each atomically.

        Parameters
        ----------
        folder : path-like, optional
            Where relative file names are put (default: as given, the current folder).
        only : iterable of str, optional
            Write only these files of the settings (:data:`~acoustiviz.app.settings.forced_job.FORCED_FILE_KINDS`
            keys; default all).

        Returns
        -------
        list of pathlib.Path
        """
        s = self.settings
        paths = []
        for key, name in s.files().items():
            if only is not None and key not in only:
                continue
            path = Path(name) if folder is None else Path(folder) / name
            if key == "wav":
                rec = write_operating_wav(self.noises, path, listener=s.listener_position, radius=s.radius)
                paths += [path, Path(rec[0]["sidecar"])]
            elif key == "noise_csv":
                paths.append(write_noise_csv(path, self.steady_states, self.noises))
            else:
                paths.append(_WRITERS[key](self, path))
        return paths


def run(settings: ForcedJob, *, progress=None) -> ForcedResult:
    """Find every attractor of ``settings`` at each frequency and, when asked, their noise in operation (no files).

    ``workers`` > 1 runs the frequencies of each round on a local process pool, and
    ``executor="dask://HOST:PORT"`` on a Dask cluster (the same executors as sweeps,
    :func:`acoustiviz.sweep.execute.dask_executor`).

    Parameters
    ----------
    settings : ForcedJob
        The job, checked when it was made.
    progress : callable, optional
        Called with a one-line message after each frequency and each continuation round.

    Returns
    -------
    ForcedResult
    """
    from .names import user_terms

    s = settings
    t0, c0 = time.perf_counter(), time.process_time()
    with user_terms(s.names):  # a Dask scheduler found unreachable on connecting: the option that named it
        resp = _attractors(s, progress)
    elapsed, cpu = time.perf_counter() - t0, time.process_time() - c0
    rows = _rows(resp)
    if s.several_balls:
        _ball_columns(rows, resp, s.ball_model())
    noises, noise_elapsed = None, 0.0
    if s.noise:  # the level columns of every attractor
        from .damper import cavity_positions

        t0 = time.perf_counter()
        noises = tuple(add_operating_noise(rows, [a for _, _, a, _ in resp.entries()], listener=s.listener_position,
                                           kind=s.config, radius=s.radius, seconds=s.noise_seconds,
                                           settings=s.surroundings, positions=cavity_positions(s)))
        noise_elapsed = time.perf_counter() - t0
    return ForcedResult(s, resp, tuple(rows), noises, elapsed, cpu, noise_elapsed)


def _ball_columns(rows: list, resp: AttractorResponse, model) -> None:
    """Fill :data:`BALL_CSV_COLUMNS` of each row from its steady state's collisions (``impact_walls`` 0: two balls)."""
    for row, (_, _, a, _) in zip(rows, resp.entries(), strict=True):
        m = max(a.measured_cycles, 1)
        ball = int(np.sum(a.impact_walls == 0))
        total = a.impact_walls.size
        row.update({"balls": model.n_balls, "cavities": len(model.cavities),
                    "wall_impacts_per_cycle": (total - ball) / m if a.success else math.nan,
                    "ball_collisions_per_cycle": ball / m if a.success else math.nan,
                    "ball_ball_share": ball / total if total else math.nan})


def _attractors(s: ForcedJob, progress) -> AttractorResponse:
    """The attractors of every frequency, run here, on a local pool or on a Dask cluster.

    One ball: :func:`~acoustiviz.dynamics.forced.attractor_response`; several balls or cavities:
    :func:`~acoustiviz.dynamics.balls_forced.ball_attractor_response`, with the same settings.
    """
    if s.several_balls:
        from ..dynamics.balls_forced import ball_attractor_response

        model, respond = s.ball_model(), ball_attractor_response
    else:
        model, respond = s.model, attractor_response
    kwargs = {"kind": s.kind, "sweep": s.sweep, "progress": progress, "solver": s.solver,
              "restitution": s.restitution, "tolerance": s.tolerance, "rtol": s.rtol, "starts": s.starts,
              "max_cycles": s.max_cycles}
    if s.executor != "process":
        from ..sweep.execute import dask_executor

        ex, close = dask_executor(s.executor)
        try:
            return respond(model, s.frequencies, s.amplitude, executor=ex, **kwargs)
        finally:
            close()
    if s.workers > 1:
        from ..sweep.execute import local_pool, shutdown_now

        # workers that leave Ctrl-C to this process: on an interrupt the pending frequencies are
        # cancelled and the workers stopped at once
        ex = local_pool(min(s.workers, len(s.frequencies)))
        finished = False
        try:
            resp = respond(model, s.frequencies, s.amplitude, executor=ex, **kwargs)
            finished = True
        finally:
            if finished:
                ex.shutdown(wait=True)
            else:
                shutdown_now(ex)
        return resp
    return respond(model, s.frequencies, s.amplitude, **kwargs)


def _rows(resp: AttractorResponse) -> list:
    """One row per (frequency, attractor) of ``resp``, the level columns empty and the worst cases marked."""
    rows = []
    settings = resp.settings.describe()
    prev_regimes: set = set()
    for i, fa in enumerate(resp.per_frequency):
        regimes = {a.regime for a in fa.attractors}
        for j, a in enumerate(fa.attractors):
            row = describe(a)
            row.update({**dict.fromkeys(NOISE_COLUMNS), "attractor": j + 1,
                        "basin_fraction": float(fa.basin_fractions[j]), "attractors": len(fa.attractors),
                        "hysteresis": len(fa.attractors) > 1, "regime_change": bool(i and regimes != prev_regimes),
                        "worst_case": "", **settings})
            rows.append(row)
        prev_regimes = regimes
    mark_worst_case(rows)
    return rows


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (float, np.floating)):
        return "" if math.isnan(v) else (("inf" if v > 0 else "-inf") if math.isinf(v) else f"{float(v):.10g}")
    return str(v)


def write_forced_csv(result: ForcedResult, path):
    """Write the frequency-response table (one row per frequency and attractor) atomically; return the path."""
    from ..files import write_text_atomic

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    cols = result.columns
    w.writerow(cols)
    for row in result.rows:
        w.writerow([_cell(row.get(c)) for c in cols])
    return write_text_atomic(path, buf.getvalue())


def write_forced_png(result: ForcedResult, path):
    """Plot the frequency response, the bifurcation diagram and the noise levels if computed; return the path.

    The response is drawn with and without the damper; the third panel (LAeq, LAFmax, LCpeak of
    the click train at the listener) appears when the level columns were filled.
    """
    from matplotlib.figure import Figure

    from ..output.plot.forced import plot_bifurcation, plot_frequency_response, plot_operating_levels
    from ..output.plot.style import save_figure, style

    noise = any(row.get("laeq_db") is not None for row in result.rows)
    with style():
        fig = Figure(figsize=(9.5, 10.5 if noise else 8.0), layout="constrained")
        axes = fig.subplots(3 if noise else 2, 1, sharex=True)
        plot_frequency_response(result.response, ax=axes[0])
        plot_bifurcation(result.response, ax=axes[1])
        if noise:  # the levels of the click train of every attractor
            levels = {c: [np.nan if row.get(c) is None else row[c] for row in result.rows]
                      for c in ("laeq_db", "lafmax_db", "lcpeak_db")}
            plot_operating_levels([row["frequency_hz"] for row in result.rows], levels,
                                  [row["regime"] for row in result.rows], ax=axes[2])
            axes[2].set_ylabel("level at the listener (dB re 20 µPa)")
        for ax in axes[:-1]:
            ax.set_xlabel("")  # shared with the panel below
        axes[0].set_title("Frequency response of the impact damper in operation")
    return save_figure(fig, path)


def _one_panel(plot: str):
    """A writer of the one panel drawn by :mod:`acoustiviz.output.plot.forced`'s ``plot``, in the scene's size."""
    def write(result: ForcedResult, path):
        from matplotlib.figure import Figure

        from ..output.plot import forced as plots
        from ..output.plot.style import save_figure, style

        with style():
            fig = Figure(figsize=(7.0, 4.2), layout="constrained")
            getattr(plots, plot)(result.response, ax=fig.add_subplot())
            return save_figure(fig, path)

    return write


#: File of the settings -> its writer ``(result, path) -> path``.
_WRITERS = {"csv": write_forced_csv, "png": write_forced_png,
            "response_png": _one_panel("plot_frequency_response"), "bifurcation_png": _one_panel("plot_bifurcation")}


def forced_table(fr, noises=None) -> str:
    """The attractors as text: one line per (frequency, attractor), the worst case marked.

    The worst case is the largest amplitude and, with ``noises`` (one :class:`OperatingNoise` or None
    per row), the largest LCpeak; rows that are not periodic are followed by their message.
    """
    lv = noises is not None
    lines = [f"{'f (Hz)':>8} {'#':>2} {'A (mm)':>9} {'±':>7} {'A0 (mm)':>9} {'red dB':>7} {'imp/cyc':>7} "
             f"{'basin':>5} {'|mu|max':>8} {'stable':>6}" + (f" {'LAeq':>6} {'LAFmax':>6} {'LCpeak':>6}" if lv else "")
             + "  regime  (worst case)"]
    for k, row in enumerate(fr.rows):
        mu = row["max_floquet_modulus"]
        line = (f"{row['frequency_hz']:8.3f} {row['attractor']:2d} {1e3 * row['amplitude_m']:9.3f} "
                f"{1e3 * row['amplitude_std_err_m']:7.3f} {1e3 * row['amplitude_without_damper_m']:9.3f} "
                f"{row['reduction_db']:7.2f} {row['impacts_per_cycle']:7.3f} {row['basin_fraction']:5.2f} "
                f"{'' if math.isnan(mu) else f'{mu:.4f}':>8} {'yes' if row['stable'] else 'no':>6}")
        if lv:
            nz = noises[k]
            line += (f" {nz.laeq_db:6.1f} {nz.lafmax_db:6.1f} {nz.lcpeak_db:6.1f}" if nz is not None
                     else f" {'':>6} {'':>6} {'':>6}")
        lines.append(line + f"  {row['regime']}" + (f"  ({row['worst_case']})" if row["worst_case"] else ""))
    odd = [row for row in fr.rows if not row["regime"].startswith("periodic-")]
    for row in odd:
        lines.append(f"{row['frequency_hz']:g} Hz #{row['attractor']}: {row['message']}")
    return "\n".join(lines)


def report(result: ForcedResult) -> list:
    """The lines ``acoustiviz forced`` prints: the settings and timings, the table, the failures, the noise."""
    s = result.settings
    unit = "N" if s.kind == "force" else "m"
    lines = [f"{s.kind} amplitude {s.amplitude:g} {unit}; sweep {s.sweep}; solver {s.solver}; {s.starts} starts; "
             f"tolerance {s.tolerance:g} m, m/s; rtol {s.rtol:g}; max cycles {s.max_cycles}; "
             f"{len(s.frequencies)} frequencies, {len(result.rows)} attractors in {result.elapsed:.2f} s"]
    if s.several_balls:
        model = s.ball_model()
        cavities = f"{len(model.cavities)} {'cavity' if len(model.cavities) == 1 else 'cavities'}"
        lines.append(f"{model.n_balls} balls in {cavities}: attractors reached by simulation, "
                     "Floquet multipliers by differences of the direct map (no shooting, no Lyapunov exponent)")
    if not s.noise:
        lines.append(forced_table(result, None))
    lines += [f"warning: {r.excitation.frequency:g} Hz: {r.message}" for r in result.failed]
    if s.noise:
        where = ("the paper's listener (0.7 m, 45 deg)" if s.listener is None
                 else f"({','.join(f'{v:g}' for v in s.listener)}) m")
        lines += [f"noise in operation at {where}: {noise_statement(s.noise_seconds)}; {result.noise_elapsed:.2f} s",
                  forced_table(result, result.noises)]
    return lines


# --------------------------------------------------------------------------- scene outputs
#: The files of each scene output (:class:`ForcedJob` fields -> file names; ``{name}``: the first listener's).
FORCED_FILES = {"frequency_response": {"csv": "frequency_response.csv", "response_png": "frequency_response.png"},
                "bifurcation": {"bifurcation_png": "bifurcation.png"},
                "operating_noise": {"noise_csv": "operating_noise.csv", "wav": "operating_noise_{name}.wav"}}


def forced_settings(scene, out=None) -> ForcedJob:
    """The scene's ``[excitation]`` and its forced outputs as a :class:`ForcedJob`.

    The damper of ``[damper]``; the noise in operation when the scene asks for ``[outputs.operating_noise]``,
    at its first listener, from the damper's sphere in the scene's configuration; the files of the forced
    outputs it asks for in folder ``out`` (None: no files, the checks of the scene's settings alone, made
    before the run folder exists); the working memory within ``grids.memory_limit_mb``; errors name scene keys.
    """
    from .products import scene_damper_model
    from .settings.damper import BALL_START, BALLS
    from .settings.damper_job import scene_balls
    from .settings.forced import FORCED, FREQUENCIES

    ex = scene.section("excitation")
    noise = scene.wants("operating_noise")
    (name, position), *_ = scene.listeners()
    files = {} if out is None else {key: str(Path(out) / file.format(name=name)) for kind, names in FORCED_FILES.items()
                                    if scene.wants(kind) for key, file in names.items()}
    # a scene's files are named by the output table that asks for them
    names = {**ForcedJob.names_for("scene", ex["kind"]),
             **{key: f"outputs.{kind}" for kind, keys in FORCED_FILES.items() for key in keys}}
    freqs = parse_frequencies(ex["frequencies_hz"], FREQUENCIES.path)
    return ForcedJob(scene_damper_model(scene), tuple(freqs), kind=ex["kind"], amplitude=ex["amplitude"],
                     **{s.name: ex[s.key] for s in FORCED if s.table == "excitation"},
                     noise_seconds=scene.output_or_defaults("operating_noise")["seconds"], noise=noise,
                     listener=tuple(position) if noise else None, config=scene.section("configuration")["kind"],
                     radius=scene.damper_sphere_radius(), surroundings=scene.geometry_settings(),
                     max_memory_mb=scene.section("grids")["memory_limit_mb"], names=names, **files,
                     **scene_balls(scene.section("damper"), (*BALLS, BALL_START[2])))


def _write(ctx, kind: str) -> list:
    """Write the files of forced output ``kind`` of the scene's one forced run; return their paths."""
    s = ctx.forced.settings
    keys = [key for key in FORCED_FILES[kind] if getattr(s, key) is not None]
    for key in keys:  # only the files checked before the run
        ctx.path(Path(getattr(s, key)).name)
    return ctx.forced.write(only=keys)


def produce_frequency_response(ctx):
    """Scene output ``frequency_response``: the CSV of ``acoustiviz forced`` and its figure."""
    from .products import Product

    result = ctx.forced
    csv_path, png = _write(ctx, "frequency_response")
    red = [r["reduction_db"] for r in result.rows]
    figs = {"frequencies": str(result.response.frequencies.size), "attractors": str(len(result.rows)),
            "best_reduction_db": f"{np.nanmax(red):.1f}",
            "non_periodic": str(sum(not r["regime"].startswith("periodic-") for r in result.rows)),
            **{k: f"{v:g}" if isinstance(v, float) else str(v)
               for k, v in result.response.settings.describe().items() if k in ("starts", "tolerance", "rtol",
                                                                               "max_cycles")}}
    failed = sorted({r.excitation.frequency for r in result.failed})
    if failed:  # the run is incomplete, as with `acoustiviz forced` (exit status 1)
        figs["failed_frequencies_hz"] = " ".join(f"{f:g}" for f in failed)
    return [Product("frequency_response", png, figs), Product("frequency_response", csv_path, {})]


def produce_bifurcation(ctx):
    """Scene output ``bifurcation``: Poincaré displacement against forcing frequency (PNG)."""
    from .products import Product

    (png,) = _write(ctx, "bifurcation")
    return [Product("bifurcation", png, {"regimes": " ".join(sorted({r["regime"] for r in ctx.forced.rows}))})]


def produce_operating_noise(ctx):
    """Scene output ``operating_noise``: levels per frequency at the first listener (CSV) and a WAV."""
    from .forced_noise import NOISE_RATE
    from .products import Product

    wav, _, csv_path = _write(ctx, "operating_noise")
    ok = [n for n in ctx.forced.noises if n is not None]
    laeq = max((n.laeq_db for n in ok), default=-math.inf)
    peak = max((n.lcpeak_db for n in ok), default=-math.inf)
    return [Product("operating_noise", csv_path, {"listener": ctx.listeners[0].name, "max_laeq_db": f"{laeq:.1f}",
                                                 "max_lcpeak_db": f"{peak:.1f}",
                                                 "levels": f"{NOISE_RATE / 1000:g} kHz, whole periods"}),
            Product("operating_noise", wav, {})]
