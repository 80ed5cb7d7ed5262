"""The damper in operation, for every front-end: frequency response table and figure.

``acoustiviz forced`` parses its options and calls :func:`parse_frequencies`,
:func:`run_forced`, :func:`write_forced_csv` and :func:`write_forced_png`; the physics is in
:mod:`acoustiviz.dynamics.forced`; the noise in operation (LAeq, LCpeak, LAFmax of the steady
click train at a listener) in :mod:`acoustiviz.app.forced_noise`. SI units; frequencies in Hz.

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

import numpy as np

from ..constants import FORCED_MAX_CYCLES, FORCED_RTOL, FORCED_STARTS, FORCED_TOLERANCE
from ..dynamics import DamperModel
from ..dynamics.forced import FORCED_SOLVERS, SWEEPS, AttractorResponse, attractor_response, describe
from ..errors import ParameterError
from .forced_noise import (
    NOISE_COLUMNS,
    DesignMap,
    OperatingNoise,
    add_operating_noise,
    check_listener,
    default_listener,
    design_map,
    mark_worst_case,
    operating_noise,
    write_operating_wav,
)
from .names import DAMPER_OPTIONS, user_terms
from .settings.parse import parse_frequencies

__all__ = ["forced_workflow", "forced_table", "operating_noise_report", "room_surroundings",
           "FORCED_CSV_COLUMNS", "FORCED_OPTIONS", "NOISE_COLUMNS", "ForcedRun", "OperatingNoise",
           "add_operating_noise", "check_listener", "default_listener", "operating_noise", "parse_frequencies",
           "run_forced", "write_forced_csv", "write_forced_png", "write_operating_wav", "DesignMap", "design_map"]

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
#: API parameter -> command-line option of ``acoustiviz forced``.
FORCED_OPTIONS = {
    **DAMPER_OPTIONS,
    "frequency": "--freq",
    "frequencies": "--freq",
    "sweep": "--sweep",
    "tolerance": "--tolerance",
    "rtol": "--rtol",
    "starts": "--starts",
    "max_cycles": "--max-cycles",
    "restitution": "--restitution",
    "workers": "--workers",
    "executor": "--executor",
}


@dataclass(frozen=True)
class ForcedRun:
    """The attractors over a list of frequencies, and their table.

    Attributes
    ----------
    response : AttractorResponse
    rows : list of dict
        One row per (frequency, attractor), keys :data:`FORCED_CSV_COLUMNS`.
    elapsed : float
        Wall time of the runs in s.
    cpu : float
        CPU time of this process during the runs in s (worker processes not included).
    """

    response: AttractorResponse
    rows: list
    elapsed: float
    cpu: float = math.nan

    @property
    def columns(self) -> tuple:
        """The CSV columns of this run."""
        return FORCED_CSV_COLUMNS

    @property
    def steady_states(self) -> list:
        """The :class:`acoustiviz.dynamics.forced.SteadyState` of each row."""
        return [a for _, _, a, _ in self.response.entries()]

    @property
    def success(self) -> bool:
        """True when every run completed (whatever its regime)."""
        return all(r.success for r in self.steady_states)


def run_forced(model: DamperModel, frequencies, amplitude: float, *, kind: str = "force", sweep: str = "up",
               solver: str = "event", restitution: float | None = None, tolerance: float = FORCED_TOLERANCE,
               rtol: float = FORCED_RTOL, starts: int = FORCED_STARTS, max_cycles: int = FORCED_MAX_CYCLES,
               workers: int = 1, executor: str = "process", progress=None) -> ForcedRun:
    """Every attractor of ``model`` under a harmonic force (N) or base motion (m) at each frequency (Hz).

    Parameters are those of :func:`acoustiviz.dynamics.forced.attractor_response` (``tolerance``
    in m and m/s, the Newton residual of a periodic orbit); ``workers`` > 1 runs the frequencies
    of each round on a local process pool, and ``executor="dask://HOST:PORT"`` on a Dask cluster
    (the same executors as sweeps, :func:`acoustiviz.sweep.execute.dask_executor`). Errors name
    the command-line options.
    """
    with user_terms({**FORCED_OPTIONS, "amplitude": "--force" if kind == "force" else "--base"}):
        if sweep not in SWEEPS:
            raise ParameterError("sweep", f"must be one of {', '.join(SWEEPS)}, got {sweep!r}")
        if solver not in FORCED_SOLVERS:
            raise ParameterError("solver", f"must be one of {', '.join(FORCED_SOLVERS)}, got {solver!r}")
        if int(workers) < 1:
            raise ParameterError("workers", f"must be >= 1, got {workers}")
        from ..core.limits import check_forcing_frequencies

        check_forcing_frequencies(frequencies, M=model.M, K=model.K)
        kwargs = {"solver": solver, "restitution": restitution, "tolerance": tolerance, "rtol": rtol,
                  "starts": starts, "max_cycles": max_cycles}
        t0, c0 = time.perf_counter(), time.process_time()
        if executor != "process":
            from ..sweep.execute import dask_executor

            ex, close = dask_executor(executor)
            try:
                resp = attractor_response(model, frequencies, amplitude, kind=kind, sweep=sweep, executor=ex,
                                          progress=progress, **kwargs)
            finally:
                close()
        elif int(workers) > 1:
            from ..sweep.execute import local_pool, shutdown_now

            # workers that leave Ctrl-C to this process: on an interrupt the pending frequencies are
            # cancelled and the workers stopped at once
            ex = local_pool(min(int(workers), len(frequencies)))
            finished = False
            try:
                resp = attractor_response(model, frequencies, amplitude, kind=kind, sweep=sweep, executor=ex,
                                          progress=progress, **kwargs)
                finished = True
            finally:
                if finished:
                    ex.shutdown(wait=True)
                else:
                    shutdown_now(ex)
        else:
            resp = attractor_response(model, frequencies, amplitude, kind=kind, sweep=sweep, progress=progress,
                                      **kwargs)
        elapsed, cpu = time.perf_counter() - t0, time.process_time() - c0
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
    return ForcedRun(resp, rows, elapsed, cpu)


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (float, np.floating)):
        return "" if math.isnan(v) else (("inf" if v > 0 else "-inf") if math.isinf(v) else f"{float(v):.10g}")
    return str(v)


def write_forced_csv(run: ForcedRun, path):
    """Write the frequency-response table (one row per frequency and attractor) atomically; return the path."""
    from ..files import write_text_atomic

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    cols = run.columns
    w.writerow(cols)
    for row in run.rows:
        w.writerow([_cell(row.get(c)) for c in cols])
    return write_text_atomic(path, buf.getvalue())


def write_forced_png(run: ForcedRun, path):
    """Plot the frequency response, the bifurcation diagram and the noise levels if computed; return the path.

    The response is drawn with and without the damper; the third panel (LAeq, LAFmax, LCpeak of
    the click train at the listener) appears when the level columns were filled.
    """
    from matplotlib.figure import Figure

    from ..output.plot.forced import plot_bifurcation, plot_frequency_response, plot_operating_levels
    from ..output.plot.style import save_figure, style

    noise = any(row.get("laeq_db") is not None for row in run.rows)
    with style():
        fig = Figure(figsize=(9.5, 10.5 if noise else 8.0), layout="constrained")
        axes = fig.subplots(3 if noise else 2, 1, sharex=True)
        plot_frequency_response(run.response, ax=axes[0])
        plot_bifurcation(run.response, ax=axes[1])
        if noise:  # the levels of the click train of every attractor
            levels = {c: [np.nan if row.get(c) is None else row[c] for row in run.rows]
                      for c in ("laeq_db", "lafmax_db", "lcpeak_db")}
            plot_operating_levels([row["frequency_hz"] for row in run.rows], levels,
                                  [row["regime"] for row in run.rows], ax=axes[2])
            axes[2].set_ylabel("level at the listener (dB re 20 µPa)")
        for ax in axes[:-1]:
            ax.set_xlabel("")  # shared with the panel below
        axes[0].set_title("Frequency response of the impact damper in operation")
    return save_figure(fig, path)


# --------------------------------------------------------------------------- scene outputs
def _scene_forced_run(ctx) -> ForcedRun:
    """The [excitation] frequency response of a scene run, computed once and kept on ``ctx``."""
    run = getattr(ctx, "_forced_run", None)
    if run is None:
        from .settings.forced import ForcedSettings

        ex, st = ctx.scene.section("excitation"), ctx.scene.forced_settings()
        freqs = parse_frequencies(ex["frequencies_hz"], "excitation.frequencies_hz")
        ctx.progress(f"forced damper: {freqs.size} frequencies, sweep {st.sweep} ({st.solver} solver)")
        with user_terms({"frequencies": "excitation.frequencies_hz", "frequency": "excitation.frequencies_hz",
                         "amplitude": "excitation.amplitude", **ForcedSettings.scene_names()}):
            run = run_forced(ctx.damper_model, freqs, ex["amplitude"], kind=ex["kind"], sweep=st.sweep,
                             solver=st.solver, tolerance=st.tolerance, rtol=st.rtol, starts=st.starts,
                             max_cycles=st.max_cycles)
        ctx._forced_run = run
    return run


def produce_frequency_response(ctx):
    """Scene output ``frequency_response``: the CSV of ``acoustiviz forced`` and its figure."""
    from matplotlib.figure import Figure

    from ..output.plot.forced import plot_frequency_response
    from ..output.plot.style import save_figure, style
    from .products import Product

    run = _scene_forced_run(ctx)
    if ctx.scene.wants("operating_noise"):  # the level columns, at the first listener
        from .forced_noise import scene_noises

        scene_noises(ctx, run)
    csv_path = write_forced_csv(run, ctx.path("frequency_response.csv"))
    with style():
        fig = Figure(figsize=(7.0, 4.2), layout="constrained")
        plot_frequency_response(run.response, ax=fig.add_subplot())
        png = save_figure(fig, ctx.path("frequency_response.png"))
    red = [r["reduction_db"] for r in run.rows]
    figs = {"frequencies": str(run.response.frequencies.size), "attractors": str(len(run.rows)),
            "best_reduction_db": f"{np.nanmax(red):.1f}",
            "non_periodic": str(sum(not r["regime"].startswith("periodic-") for r in run.rows)),
            **{k: f"{v:g}" if isinstance(v, float) else str(v) for k, v in run.response.settings.describe().items()
               if k in ("starts", "tolerance", "rtol", "max_cycles")}}
    failed = sorted({r.excitation.frequency for r in run.steady_states if not r.success})
    if failed:  # the run is incomplete, as with `acoustiviz forced` (exit status 1)
        figs["failed_frequencies_hz"] = " ".join(f"{f:g}" for f in failed)
    return [Product("frequency_response", png, figs), Product("frequency_response", csv_path, {})]


def produce_bifurcation(ctx):
    """Scene output ``bifurcation``: Poincaré displacement against forcing frequency (PNG)."""
    from matplotlib.figure import Figure

    from ..output.plot.forced import plot_bifurcation
    from ..output.plot.style import save_figure, style
    from .products import Product

    run = _scene_forced_run(ctx)
    with style():
        fig = Figure(figsize=(7.0, 4.2), layout="constrained")
        plot_bifurcation(run.response, ax=fig.add_subplot())
        png = save_figure(fig, ctx.path("bifurcation.png"))
    return [Product("bifurcation", png, {"regimes": " ".join(sorted({r["regime"] for r in run.rows}))})]


def produce_operating_noise(ctx):
    """Scene output ``operating_noise``: levels per frequency at the first listener (CSV) and a WAV."""
    from .forced_noise import write_operating_noise

    return write_operating_noise(ctx, _scene_forced_run(ctx))


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


def room_surroundings(room: dict | None, listener, *, room_name: str = "a room") -> dict | None:
    """The cavity's surroundings in a room (``{"room": room}``), or None above the paper's plane.

    In a room the listener must be given: the paper's default (0.7 m at 45 degrees above the
    plane) has no place in it. The room's ``duration`` (s) says how long after each click its
    reflections are heard (the images that arrive within it).

    Parameters
    ----------
    room : dict or None
        The room's settings (:func:`acoustiviz.app.impacts.room_settings`).
    listener : (3,) array_like or None
        The listener in m.
    room_name : str
        How the error names the room (``"--room"`` on the command line).
    """
    if room is None:
        return None
    if listener is None:
        raise ParameterError("listener", f"required with {room_name}: the listener's position X,Y,Z in m in the room")
    return {"room": room}


def operating_noise_report(fr, listener, seconds: float, *, wav=None, settings=None) -> list:
    """Add the noise in operation to ``fr`` at ``listener`` and, with ``wav``, write it; return the report lines.

    Parameters
    ----------
    fr : ForcedRun
        The attractors of each frequency.
    listener : (3,) ndarray or None
        Listener in m (None: the paper's, 0.7 m at 45 degrees).
    seconds : float
        Least length in s of each level interval (whole periods).
    wav : path-like, optional
        The WAV of the frequencies in turn (with its JSON sidecar).
    settings : dict, optional
        The cavity's surroundings (:func:`room_surroundings`; None: the paper's plane).
    """
    import time

    from .forced_noise import noise_statement

    t0 = time.perf_counter()
    noises = add_operating_noise(fr, listener=listener, seconds=seconds, settings=settings)
    where = ("the paper's listener (0.7 m, 45 deg)" if listener is None
             else f"({','.join(f'{v:g}' for v in listener)}) m")
    lines = [f"noise in operation at {where}: {noise_statement(seconds)}; {time.perf_counter() - t0:.2f} s",
             forced_table(fr, noises)]
    if wav:
        rec = write_operating_wav(noises, wav, listener=listener)
        lines.append(f"wrote {wav} (sidecar {rec[0]['sidecar']})")
    return lines


def _check_forced_outputs(job) -> None:
    """Refuse unwritable or clashing output files (before any work)."""
    from .outputs import check_distinct, check_output_file

    outputs = {"--csv": job.csv and check_output_file("--csv", job.csv, "csv"),
               "--png": job.png and check_output_file("--png", job.png, "figure")}
    if job.wav is not None:
        outputs["--wav"] = check_output_file("--wav", job.wav, "wav")
        outputs["--wav (sidecar)"] = check_output_file("--wav", outputs["--wav"].with_suffix(".json"), "json")
    check_distinct(outputs)
    if job.wav is not None and not job.noise:
        raise ParameterError("--wav", "needs the noise in operation: drop --no-noise")


def _checked_job(job) -> tuple:
    """Every check before any work: ``(frequencies in Hz, listener in m or None, room, damper model)``."""
    from ..sweep.execute import check_executor_form
    from .budget import check_budget, forced_estimate
    from .damper import damper_model
    from .names import ROOM_OPTIONS, user_terms
    from .settings.parse import parse_point

    freqs = parse_frequencies(job.freq)
    listener = None if job.listener is None else parse_point(job.listener, "--listener")
    _check_forced_outputs(job)
    st = job.settings
    with user_terms({**ROOM_OPTIONS, "listener": "--listener"}):
        room = room_surroundings(job.room, listener, room_name="--room")
    with user_terms(FORCED_OPTIONS):
        model = damper_model(**job.model)
        check_executor_form(job.executor)
    check_budget(forced_estimate(len(freqs) * st.starts, st.max_cycles,
                                 noise_seconds=st.noise_seconds if job.noise else 0.0,
                                 wav=job.wav is not None), job.max_memory)
    if job.noise or listener is not None:
        with user_terms(ROOM_OPTIONS):  # a room's settings checked here, before any run
            check_listener(model, listener, settings=room)
    return freqs, listener, room, model


def forced_workflow(job, *, echo=print, progress=None) -> int:
    """Run a :class:`~acoustiviz.app.settings.forced.ForcedJob`: check it, run it, ``echo`` the report, write files.

    Errors name the command-line options. ``progress`` receives a line per finished frequency.
    Returns the exit status: 0, or 1 when a frequency's run failed (each one warned about).
    """
    freqs, listener, room, model = _checked_job(job)
    st = job.settings
    kind, amp = ("force", job.force) if job.force is not None else ("base", job.base)
    fr = run_forced(model, freqs, amp, kind=kind, sweep=st.sweep, solver=st.solver, restitution=job.restitution,
                    tolerance=st.tolerance, rtol=st.rtol, starts=st.starts, max_cycles=st.max_cycles,
                    workers=job.workers, executor=job.executor, progress=progress)
    unit = "N" if kind == "force" else "m"
    echo(f"{kind} amplitude {amp:g} {unit}; sweep {st.sweep}; solver {st.solver}; {st.starts} starts; "
         f"tolerance {st.tolerance:g} m, m/s; rtol {st.rtol:g}; max cycles {st.max_cycles}; "
         f"{len(freqs)} frequencies, {len(fr.rows)} attractors in {fr.elapsed:.2f} s")
    failed = [r for r in fr.steady_states if not r.success]
    if not job.noise:
        echo(forced_table(fr, None))
    for r in failed:
        echo(f"warning: {r.excitation.frequency:g} Hz: {r.message}")
    if job.noise:
        for line in operating_noise_report(fr, listener, st.noise_seconds, wav=job.wav, settings=room):
            echo(line)
    if job.csv:
        echo(f"wrote {write_forced_csv(fr, job.csv)}")
    if job.png:
        echo(f"wrote {write_forced_png(fr, job.png)}")
    return 0 if not failed else 1

