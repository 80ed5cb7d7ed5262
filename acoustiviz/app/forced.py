"""The damper in operation, for every front-end: frequency response table and figure.

``acoustiviz forced`` parses its options and calls :func:`parse_frequencies`,
:func:`run_forced`, :func:`write_forced_csv` and :func:`write_forced_png`; the physics is in
:mod:`acoustiviz.dynamics.forced`. SI units; frequencies in Hz.

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

from ..constants import P_REF, PAPER_ANGLE_DEG, PAPER_DISTANCE, PAPER_RADIUS
from ..dynamics import DamperModel
from ..dynamics.forced import FORCED_SOLVERS, SWEEPS, FrequencyResponse, describe, frequency_response
from ..errors import ParameterError
from .names import DAMPER_OPTIONS, user_terms

__all__ = ["FORCED_CSV_COLUMNS", "FORCED_OPTIONS", "ForcedRun", "OperatingNoise", "add_operating_noise",
           "default_listener", "operating_noise", "parse_frequencies", "run_forced", "write_forced_csv",
           "write_forced_png", "write_operating_wav", "DesignMap", "design_map"]

#: Columns of the frequency-response CSV, one row per frequency (the first eight are promised).
FORCED_CSV_COLUMNS = (
    "frequency_hz", "amplitude_m", "amplitude_without_damper_m", "reduction_db", "impacts_per_cycle",
    "regime", "laeq_db", "lcpeak_db", "period_cycles", "converged", "cycles", "x_max_m", "x_min_m",
    "mean_impact_speed_m_s", "max_impact_speed_m_s", "impact_phases_deg", "energy_closure",
    "regime_change", "lzpeak_db", "lzeq_db", "sel_per_cycle_db",
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
}
#: Largest number of frequencies of one run.
MAX_FREQUENCIES = 10_000


def parse_frequencies(text: str, name: str = "--freq") -> np.ndarray:
    """Frequencies in Hz from ``"start:stop:count"`` (inclusive, evenly spaced) or ``"f1,f2,..."``."""
    s = str(text).strip()
    try:
        if ":" in s:
            parts = s.split(":")
            if len(parts) != 3:
                raise ValueError
            a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
            if n < 1 or n > MAX_FREQUENCIES:
                raise ParameterError(name, f"count must lie in [1, {MAX_FREQUENCIES}], got {n}")
            if n > 1 and not b > a:
                raise ParameterError(name, f"stop must exceed start, got {a:g}:{b:g}")
            f = np.linspace(a, b, n) if n > 1 else np.array([a])
        else:
            f = np.array([float(p) for p in s.split(",")])
    except ParameterError:
        raise
    except ValueError:
        raise ParameterError(name, f"expected START:STOP:COUNT or a comma list of frequencies in Hz, "
                                   f"got {text!r}") from None
    if f.size == 0 or f.size > MAX_FREQUENCIES or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ParameterError(name, f"frequencies must be finite and > 0 Hz (at most {MAX_FREQUENCIES}), "
                                   f"got {text!r}")
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
               max_cycles: int = 2000, workers: int = 1) -> ForcedRun:
    """Frequency response of ``model`` under a harmonic force (N) or base motion (m).

    Parameters are those of :func:`acoustiviz.dynamics.forced.frequency_response`; ``workers`` > 1
    runs the frequencies on a local process pool (``sweep="independent"`` only: continuation is
    sequential by nature). Errors name the command-line options.
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
        kwargs = {"solver": solver, "restitution": restitution, "tolerance": tolerance, "max_cycles": max_cycles}
        t0 = time.perf_counter()
        if int(workers) > 1:
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
        row.update({"laeq_db": None, "lcpeak_db": None, "regime_change": bool(changes[i])})
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
    """Plot the frequency response (with and without damper) and the bifurcation diagram; return the path."""
    from matplotlib.figure import Figure

    from ..output.plot._style import save_figure, style
    from ..output.plot.forced import plot_bifurcation, plot_frequency_response

    with style():
        fig = Figure(figsize=(7.5, 8.0), layout="constrained")
        ax1, ax2 = fig.subplots(2, 1, sharex=True)
        plot_frequency_response(run.response, ax=ax1)
        plot_bifurcation(run.response, ax=ax2)
        ax1.set_title("Frequency response of the impact damper in operation")
    return save_figure(fig, path)


# --------------------------------------------------------------------------- the noise it makes
#: Columns of the operating-noise levels (Z-weighted: no frequency weighting).
NOISE_COLUMNS = ("lzpeak_db", "lzeq_db", "sel_per_cycle_db")


def default_listener(radius: float = PAPER_RADIUS) -> np.ndarray:
    """The paper's listener in m: 0.7 m at 45° above the floor from a sphere of ``radius`` resting on it."""
    a = math.radians(PAPER_ANGLE_DEG)
    return np.array([PAPER_DISTANCE * math.cos(a), 0.0, radius + PAPER_DISTANCE * math.sin(a)])


@dataclass(frozen=True)
class OperatingNoise:
    """The steady click train of the damper in operation at one listener.

    Attributes
    ----------
    frequency_hz : float
        Forcing frequency in Hz.
    pressure : ndarray
        Sound pressure in Pa at ``sample_rate`` (the measured cycles repeated to ``duration``).
    sample_rate : int
        Hz.
    duration : float
        Whole forcing cycles rendered, in s.
    lzpeak_db : float
        Peak SPL in dB re 20 µPa (unweighted, band-limited samples; -inf when silent).
    lzeq_db : float
        Equivalent continuous level over ``duration`` in dB re 20 µPa (unweighted).
    sel_per_cycle_db : float
        Sound exposure level of one forcing cycle in dB re (20 µPa)² s.
    """

    frequency_hz: float
    pressure: np.ndarray
    sample_rate: int
    duration: float
    lzpeak_db: float
    lzeq_db: float
    sel_per_cycle_db: float
    rendering: dict


def operating_noise(steady, *, listener=None, config: str = "plane", radius: float = PAPER_RADIUS,
                    seconds: float = 1.0, sample_rate: int = 48000) -> OperatingNoise:
    """Render the steady-state impacts of ``steady`` at a listener and give their levels.

    The measured cycles of the steady state (one period, or 32 cycles of non-periodic motion)
    are repeated to at least ``seconds`` s; each impact is a Hertz click of its own approach
    speed radiated by the rigid sphere of ``radius`` m with image sources
    (:func:`acoustiviz.output.audio.render`, paper eqs 12-14), the struck wall alternating as the
    impact mass strikes wall -1 or +1 of the cavity.

    Parameters
    ----------
    steady : acoustiviz.dynamics.forced.SteadyState
    listener : (3,) array_like, optional
        Position in m (default :func:`default_listener`).
    config : {"free", "plane", "wall-floor"}
    radius : float
        Sphere radius in m (default: the paper's 19.05 mm).
    seconds : float
        Least duration in s, (0, 60].
    sample_rate : {44100, 48000, 96000}
    """
    from ..output.audio import ClickModel, ImpactSequence, render
    from ..output.audio.sources import spl
    from .wav import cavity

    seconds = float(seconds)
    if not 0.0 < seconds <= 60.0:
        raise ParameterError("seconds", f"must lie in (0, 60] s, got {seconds:g}")
    model = steady.model
    period = steady.excitation.period
    window = steady.measured_cycles * period
    reps = max(1, math.ceil(seconds / window - 1e-9)) if steady.converged else 1
    t0 = steady.cycles * period
    keep = steady.impact_speeds > 0
    base = steady.impact_times[keep] - t0
    times = np.concatenate([base + k * window for k in range(reps)]) if base.size else np.empty(0)
    walls = np.tile(steady.impact_walls[keep], reps)
    speeds = np.tile(steady.impact_speeds[keep], reps)
    scene = cavity(config, radius, model.gap)
    pts = default_listener(radius) if listener is None else np.asarray(listener, dtype=float)
    seq = ImpactSequence(times, walls.astype(int), speeds)
    clicks = ClickModel(k_hertz=model.k_hertz, mass=model.m, main_mass=model.M)
    duration = reps * window
    out = render(seq, scene, clicks, pts, sample_rate=sample_rate, duration=duration)
    p = out.pressure[0]
    energy = float(np.sum(p * p)) / out.sample_rate  # Pa² s
    ref = P_REF * P_REF
    lzeq = 10.0 * math.log10(energy / (duration * ref)) if energy > 0 else -math.inf
    sel = 10.0 * math.log10(energy / (reps * steady.measured_cycles) / ref) if energy > 0 else -math.inf
    return OperatingNoise(steady.excitation.frequency, p, out.sample_rate, duration, spl(p), lzeq, sel,
                          out.describe())


def check_listener(model: DamperModel, listener=None, *, config: str = "plane", radius: float = PAPER_RADIUS,
                   name: str = "--listener") -> np.ndarray:
    """Check (before any run) that ``listener`` (m) lies outside the cavity's sphere and above its surfaces."""
    from ..output.audio import check_listeners
    from .wav import cavity

    pts = default_listener(radius) if listener is None else np.asarray(listener, dtype=float)
    return check_listeners(pts, cavity(config, radius, model.gap), name=name)[0]


def add_operating_noise(run: ForcedRun, **kwargs) -> list:
    """Fill the noise columns of ``run.rows`` (primary sweep) in place; return the :class:`OperatingNoise` list."""
    noises = []
    for row, r in zip(run.rows, run.response.primary, strict=True):
        if not r.success:
            noises.append(None)
            continue
        nz = operating_noise(r, **kwargs)
        row.update({"lzpeak_db": nz.lzpeak_db, "lzeq_db": nz.lzeq_db, "sel_per_cycle_db": nz.sel_per_cycle_db})
        noises.append(nz)
    return noises


def write_operating_wav(noises, path, *, sample_rate: int = 48000, listener=None, radius: float = PAPER_RADIUS):
    """One WAV (and JSON sidecar) of the damper in operation: each frequency's click train in turn.

    Returns the written record list of :func:`acoustiviz.app.wav.write_wav_files`.
    """
    from .wav import WavFile, write_wav_files

    parts = [n.pressure[: int(round(n.duration * n.sample_rate))] for n in noises if n is not None]
    pressure = np.concatenate(parts) if parts else np.zeros(1)
    pts = default_listener(radius) if listener is None else np.asarray(listener, dtype=float)
    wav = WavFile(path, pressure[None, :], ["listener1"], pts[None, :], ["mono"])
    first = next((n for n in noises if n is not None), None)
    rendering = dict(first.rendering) if first is not None else {}
    rendering["operating_sequence"] = [{"frequency_hz": n.frequency_hz, "duration_s": n.duration}
                                       for n in noises if n is not None]
    return write_wav_files([wav], sample_rate=sample_rate, rendering=rendering,
                           radius_source="default: the paper's sphere")


@dataclass(frozen=True)
class DesignMap:
    """Amplitude reduction and operating noise over impact mass and gap at one forcing.

    Attributes
    ----------
    masses, gaps : ndarray
        Impact masses in kg and gaps in m (the axes).
    reduction_db : ndarray
        ``(n_mass, n_gap)`` amplitude reduction in dB (positive: the damper helps).
    lzeq_db : ndarray
        ``(n_mass, n_gap)`` unweighted Leq at the listener in dB re 20 µPa (-inf: no impacts).
    regime : ndarray of str
        ``(n_mass, n_gap)`` regimes.
    """

    masses: np.ndarray
    gaps: np.ndarray
    reduction_db: np.ndarray
    lzeq_db: np.ndarray
    regime: np.ndarray


def design_map(model: DamperModel, masses, gaps, frequency: float, amplitude: float, *, kind: str = "force",
               listener=None, **kwargs) -> DesignMap:
    """Amplitude reduction against operating noise over impact mass (kg) and gap (m).

    Each design runs from the linear start at ``frequency`` Hz to its steady state
    (:func:`acoustiviz.dynamics.forced.steady_state`, ``**kwargs``) and its click train is
    rendered at ``listener`` (:func:`operating_noise`).
    """
    from dataclasses import replace

    from ..dynamics.forced import Excitation, steady_state

    masses = np.atleast_1d(np.asarray(masses, dtype=float))
    gaps = np.atleast_1d(np.asarray(gaps, dtype=float))
    red = np.full((masses.size, gaps.size), np.nan)
    leq = np.full_like(red, np.nan)
    reg = np.empty(red.shape, dtype=object)
    ex = Excitation(frequency, amplitude, kind)
    for i, m in enumerate(masses):
        for j, g in enumerate(gaps):
            r = steady_state(replace(model, m=float(m), gap=float(g)), ex, **kwargs)
            reg[i, j] = r.regime if r.success else "failed"
            if r.success:
                red[i, j] = r.reduction_db
                leq[i, j] = operating_noise(r, listener=listener).lzeq_db
    return DesignMap(masses, gaps, red, leq, reg)


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
    csv_path = write_forced_csv(run, ctx.path("frequency_response.csv"))
    with style():
        fig = Figure(figsize=(7.0, 4.2), layout="constrained")
        plot_frequency_response(run.response, ax=fig.add_subplot())
        png = save_figure(fig, ctx.path("frequency_response.png"))
    red = run.response.reduction_db
    figs = {"frequencies": str(len(run.rows)), "best_reduction_db": f"{np.nanmax(red):.1f}",
            "non_periodic": str(sum(r["regime"] == "non-periodic" for r in run.rows))}
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
    from .pipeline import Product

    run = _scene_forced_run(ctx)
    opts = ctx.scene.output("operating_noise")
    name, position = ctx.listeners[0]
    radius = ctx.scene.damper_sphere_radius()
    config = ctx.scene.section("configuration")["kind"]
    noises = []
    for r in run.response.primary:
        noises.append(operating_noise(r, listener=position, config=config, radius=radius, seconds=opts["seconds"])
                      if r.success else None)
    ok = [n for n in noises if n is not None]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(("frequency_hz", "regime", "impacts_per_cycle", *NOISE_COLUMNS))
    for r, n in zip(run.response.primary, noises, strict=True):
        levels = (n.lzpeak_db, n.lzeq_db, n.sel_per_cycle_db) if n is not None else (None, None, None)
        w.writerow([_cell(v) for v in (r.excitation.frequency, r.regime, r.impacts_per_cycle, *levels)])
    from ..output.writers import write_text_atomic

    csv_path = write_text_atomic(ctx.path("operating_noise.csv"), buf.getvalue())
    wav = ctx.path(f"operating_noise_{name}.wav")
    write_operating_wav(noises, wav, listener=position, radius=radius)
    peak = max((n.lzpeak_db for n in ok), default=-math.inf)
    return [Product("operating_noise", csv_path, {"listener": name, "max_peak_spl_db": f"{peak:.1f}"}),
            Product("operating_noise", wav, {})]
