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

from ..dynamics import DamperModel
from ..dynamics.forced import FORCED_SOLVERS, SWEEPS, FrequencyResponse, describe, frequency_response
from ..errors import ParameterError
from .forced_noise import (
    NOISE_COLUMNS,
    DesignMap,
    OperatingNoise,
    add_operating_noise,
    check_listener,
    default_listener,
    design_map,
    operating_noise,
    write_operating_wav,
)
from .names import DAMPER_OPTIONS, user_terms

__all__ = ["FORCED_CSV_COLUMNS", "FORCED_OPTIONS", "NOISE_COLUMNS", "ForcedRun", "OperatingNoise",
           "add_operating_noise", "check_listener", "default_listener", "operating_noise", "parse_frequencies",
           "run_forced", "write_forced_csv", "write_forced_png", "write_operating_wav", "DesignMap", "design_map"]

#: Columns of the frequency-response CSV, one row per frequency (the first eight are promised).
FORCED_CSV_COLUMNS = (
    "frequency_hz", "amplitude_m", "amplitude_without_damper_m", "reduction_db", "impacts_per_cycle",
    "regime", "laeq_db", "lcpeak_db", "lafmax_db", "period_cycles", "converged", "cycles", "x_max_m", "x_min_m",
    "mean_impact_speed_m_s", "max_impact_speed_m_s", "impact_phases_deg", "energy_closure",
    "regime_change", "lzpeak_db", "lzeq_db", "sel_per_cycle_db", "sel_a_per_cycle_db", "level_interval_s",
)
#: Extra columns when both sweep directions are run.
DOWN_COLUMNS = ("amplitude_down_m", "regime_down", "impacts_per_cycle_down", "hysteresis")
#: API parameter -> command-line option of ``acoustiviz forced``.
FORCED_OPTIONS = {
    **DAMPER_OPTIONS,
    "frequency": "--freq",
    "frequencies": "--freq",
    "sweep": "--sweep",
    "tolerance": "--tolerance",
    "max_cycles": "--max-cycles",
    "restitution": "--restitution",
    "workers": "--workers",
    "executor": "--executor",
}
#: Largest number of frequencies of one run.
MAX_FREQUENCIES = 10_000


def parse_frequencies(text: str, name: str = "--freq") -> np.ndarray:
    """Frequencies in Hz from ``"start:stop:count"`` (inclusive, evenly spaced) or ``"f1,f2,..."``.

    Ranges follow the one range rule of every front-end (:func:`acoustiviz.sweep.spec.value_range`).
    """
    from ..sweep.spec import value_range

    s = str(text).strip()
    try:
        if ":" in s:
            parts = s.split(":")
            if len(parts) != 3:
                raise ValueError
            a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
            f = np.array(value_range(a, b, n))
        else:
            f = np.array([float(p) for p in s.split(",")])
    except ParameterError as exc:
        raise ParameterError(name, f"{exc.detail} (in {s!r})") from None
    except ValueError:
        raise ParameterError(name, f"expected START:STOP:COUNT or a comma list of frequencies in Hz, "
                                   f"got {text!r}") from None
    if f.size == 0 or f.size > MAX_FREQUENCIES:
        raise ParameterError(name, f"expected 1 to {MAX_FREQUENCIES} frequencies, got {f.size}")
    if not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ParameterError(name, f"frequencies must be finite and > 0 Hz, got {text!r}")
    if np.unique(f).size != f.size:
        raise ParameterError(name, f"duplicate frequencies in {text!r}")
    return np.sort(f)


def parse_point(text: str, name: str = "--listener") -> np.ndarray:
    """A point ``"x,y,z"`` in m."""
    try:
        p = np.array([float(v) for v in str(text).split(",")])
    except ValueError:
        p = np.empty(0)
    if p.size != 3 or not np.all(np.isfinite(p)):
        raise ParameterError(name, f"expected X,Y,Z in m, got {text!r}")
    return p


@dataclass(frozen=True)
class ForcedRun:
    """A frequency response and its table.

    Attributes
    ----------
    response : FrequencyResponse
    rows : list of dict
        One row per frequency, keys :data:`FORCED_CSV_COLUMNS` (and :data:`DOWN_COLUMNS`).
    elapsed : float
        Wall time of the runs in s.
    """

    response: FrequencyResponse
    rows: list
    elapsed: float

    @property
    def columns(self) -> tuple:
        """The CSV columns of this run."""
        return FORCED_CSV_COLUMNS + (DOWN_COLUMNS if self.response.down is not None else ())

    @property
    def success(self) -> bool:
        """True when every run completed (converged or honestly non-periodic)."""
        runs = self.response.primary + (self.response.down or ())
        return all(r.success for r in runs)


def run_forced(model: DamperModel, frequencies, amplitude: float, *, kind: str = "force", sweep: str = "up",
               solver: str = "event", restitution: float | None = None, tolerance: float = 1e-6,
               max_cycles: int = 2000, workers: int = 1, executor: str = "process") -> ForcedRun:
    """Frequency response of ``model`` under a harmonic force (N) or base motion (m).

    Parameters are those of :func:`acoustiviz.dynamics.forced.frequency_response`; ``workers`` > 1
    runs the frequencies on a local process pool, and ``executor="dask://HOST:PORT"`` on a Dask
    cluster (the same executors as sweeps, :func:`acoustiviz.sweep.execute.dask_executor`); both
    need ``sweep="independent"``: continuation is sequential by nature. Errors name the
    command-line options.
    """
    with user_terms({**FORCED_OPTIONS, "amplitude": "--force" if kind == "force" else "--base"}):
        if sweep not in SWEEPS:
            raise ParameterError("sweep", f"must be one of {', '.join(SWEEPS)}, got {sweep!r}")
        if solver not in FORCED_SOLVERS:
            raise ParameterError("solver", f"must be one of {', '.join(FORCED_SOLVERS)}, got {solver!r}")
        if int(workers) < 1:
            raise ParameterError("workers", f"must be >= 1, got {workers}")
        if int(workers) > 1 and sweep != "independent":
            raise ParameterError("workers", "more than one worker needs --sweep independent (no continuation)")
        if executor != "process" and sweep != "independent":
            raise ParameterError("executor", "a Dask cluster needs --sweep independent (no continuation)")
        from .limits import check_forcing_frequencies

        check_forcing_frequencies(frequencies, M=model.M, K=model.K)
        kwargs = {"solver": solver, "restitution": restitution, "tolerance": tolerance, "max_cycles": max_cycles}
        t0 = time.perf_counter()
        if executor != "process":
            from ..sweep.execute import dask_executor

            ex, close = dask_executor(executor)
            try:
                resp = frequency_response(model, frequencies, amplitude, kind=kind, sweep=sweep, executor=ex,
                                          **kwargs)
            finally:
                close()
        elif int(workers) > 1:
            from concurrent.futures import ProcessPoolExecutor

            with ProcessPoolExecutor(max_workers=min(int(workers), len(frequencies))) as ex:
                resp = frequency_response(model, frequencies, amplitude, kind=kind, sweep=sweep, executor=ex,
                                          **kwargs)
        else:
            resp = frequency_response(model, frequencies, amplitude, kind=kind, sweep=sweep, **kwargs)
        elapsed = time.perf_counter() - t0
    rows = []
    changes = resp.regime_change
    hyst = resp.hysteresis
    for i, r in enumerate(resp.primary):
        row = describe(r)
        row.update({**dict.fromkeys(NOISE_COLUMNS), "regime_change": bool(changes[i])})
        if resp.down is not None:
            d = resp.down[i]
            row.update({"amplitude_down_m": d.amplitude, "regime_down": d.regime,
                        "impacts_per_cycle_down": d.impacts_per_cycle, "hysteresis": bool(hyst[i])})
        rows.append(row)
    return ForcedRun(resp, rows, elapsed)


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (float, np.floating)):
        return "" if math.isnan(v) else (("inf" if v > 0 else "-inf") if math.isinf(v) else f"{float(v):.10g}")
    return str(v)


def write_forced_csv(run: ForcedRun, path):
    """Write the frequency-response table (one row per frequency) atomically; return the path."""
    from ..output.writers import write_text_atomic

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

    from ..output.plot._style import save_figure, style
    from ..output.plot.forced import plot_bifurcation, plot_frequency_response, plot_operating_levels

    noise = any(row.get("laeq_db") is not None for row in run.rows)
    with style():
        fig = Figure(figsize=(9.5, 10.5 if noise else 8.0), layout="constrained")
        axes = fig.subplots(3 if noise else 2, 1, sharex=True)
        plot_frequency_response(run.response, ax=axes[0])
        plot_bifurcation(run.response, ax=axes[1])
        if noise:  # the levels of the click train (primary sweep)
            levels = {c: [np.nan if row.get(c) is None else row[c] for row in run.rows]
                      for c in ("laeq_db", "lafmax_db", "lcpeak_db")}
            plot_operating_levels(run.response.frequencies, levels, [row["regime"] for row in run.rows],
                                  ax=axes[2])
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
        from ..scene import parse_range

        ex = ctx.scene.section("excitation")
        freqs = np.asarray(parse_range(ex["frequencies_hz"], "excitation.frequencies_hz"), dtype=float)
        ctx.progress(f"forced damper: {freqs.size} frequencies, sweep {ex['sweep']} ({ex['solver']} solver)")
        with user_terms({"frequencies": "excitation.frequencies_hz", "frequency": "excitation.frequencies_hz",
                         "amplitude": "excitation.amplitude", "tolerance": "excitation.tolerance",
                         "max_cycles": "excitation.max_cycles"}):
            run = run_forced(ctx.damper_model, freqs, ex["amplitude"], kind=ex["kind"], sweep=ex["sweep"],
                             solver=ex["solver"], tolerance=ex["tolerance"], max_cycles=ex["max_cycles"])
        ctx._forced_run = run
    return run


def produce_frequency_response(ctx):
    """Scene output ``frequency_response``: the CSV of ``acoustiviz forced`` and its figure."""
    from matplotlib.figure import Figure

    from ..output.plot._style import save_figure, style
    from ..output.plot.forced import plot_frequency_response
    from .pipeline import Product

    run = _scene_forced_run(ctx)
    if ctx.scene.wants("operating_noise"):  # the level columns, at the first listener
        from .forced_noise import scene_noises

        scene_noises(ctx, run)
    csv_path = write_forced_csv(run, ctx.path("frequency_response.csv"))
    with style():
        fig = Figure(figsize=(7.0, 4.2), layout="constrained")
        plot_frequency_response(run.response, ax=fig.add_subplot())
        png = save_figure(fig, ctx.path("frequency_response.png"))
    red = run.response.reduction_db
    figs = {"frequencies": str(len(run.rows)), "best_reduction_db": f"{np.nanmax(red):.1f}",
            "non_periodic": str(sum(r["regime"] == "non-periodic" for r in run.rows))}
    failed = [r.excitation.frequency for r in run.response.primary + (run.response.down or ()) if not r.success]
    if failed:  # the run is incomplete, as with `acoustiviz forced` (exit status 1)
        figs["failed_frequencies_hz"] = " ".join(f"{f:g}" for f in failed)
    return [Product("frequency_response", png, figs), Product("frequency_response", csv_path, {})]


def produce_bifurcation(ctx):
    """Scene output ``bifurcation``: Poincaré displacement against forcing frequency (PNG)."""
    from matplotlib.figure import Figure

    from ..output.plot._style import save_figure, style
    from ..output.plot.forced import plot_bifurcation
    from .pipeline import Product

    run = _scene_forced_run(ctx)
    with style():
        fig = Figure(figsize=(7.0, 4.2), layout="constrained")
        plot_bifurcation(run.response, ax=fig.add_subplot())
        png = save_figure(fig, ctx.path("bifurcation.png"))
    return [Product("bifurcation", png, {"regimes": " ".join(sorted({r["regime"] for r in run.rows}))})]


def produce_operating_noise(ctx):
    """Scene output ``operating_noise``: levels per frequency at the first listener (CSV) and a WAV."""
    from .forced_noise import produce_operating_noise as produce

    return produce(ctx, _scene_forced_run(ctx))
