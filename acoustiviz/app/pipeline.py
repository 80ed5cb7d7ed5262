"""Run a scene: produce exactly the outputs it names, computing no more than they need.

Each output kind has a producer that writes its files atomically into the output folder and
returns :class:`Product` records (path and key figures) for ``summary.md``. Shared work is
computed lazily and once per run by :class:`RunContext` (for example the damper simulation
serves the time history, the impact table and the WAV files), so a scene that asks only for a
waveform never runs the damper, and one that asks only for a WAV never evaluates a grid.

It sits in the application layer: it imports the core, the field evaluator, plots, renders,
audio and sweeps, and shares the rules of :mod:`acoustiviz.app` with the command line; nothing
imports it but the command line.
"""

from __future__ import annotations

import contextlib
import functools
import time
from pathlib import Path

import numpy as np

from ..core.listener import Listener
from ..errors import ParameterError
from ..files import write_csv_atomic, write_text_atomic
from . import damper as _damper
from . import forced as _forced
from . import sweep as _sweep
from .design import design_settings, produce_design_table
from .map_job import map_settings, produce_level_map
from .products import Product, damper_initial, damper_solver, scene_damper_model
from .products import new_figure as _fig
from .products import save as _save
from .render_job import (
    animation_settings,
    balloon_settings,
    produce_animation,
    produce_balloon,
    produce_snapshot,
    snapshot_settings,
)
from .scene_levels import levels_settings, produce_levels, produce_spectrum
from .scene_optimize import optimize_settings, produce_optimize
from .scene_outputs import SUMMARY, preflight
from .scene_run_field import run_field_settings
from .scene_wav import wav_settings
from .sweep import produce_sweep, sweep_settings

__all__ = ["Product", "RunContext", "run_scene", "incomplete", "PRODUCERS"]

#: Figures of a :class:`Product` that mark it incomplete (some of its work failed; the command
#: line exits with status 1 after writing everything, as its single commands do).
INCOMPLETE_FIGURES = ("failed_frequencies_hz",)


def incomplete(products) -> list:
    """``"kind: figure = value"`` for every product of a run marked incomplete (:data:`INCOMPLETE_FIGURES`)."""
    return [f"{p.kind}: {k} = {p.figures[k]}" for p in products for k in INCOMPLETE_FIGURES if k in p.figures]


class RunContext:
    """The scene, the output folder and the lazily computed shared results of one run."""

    def __init__(self, scene, out: Path, progress=None, stream=None, planned=None):
        self.scene = scene
        self.out = Path(out)
        self.progress = progress or (lambda msg: None)
        self.stream = stream  # where long steps draw their progress bars (None: silent)
        self.planned = planned  # the file names checked before the run (None: any)

    def path(self, name: str) -> Path:
        """Path of an output file (or folder) directly inside the run folder.

        ``name`` must be a plain file name: one holding a separator, ``..`` or a NUL is refused
        (a :class:`ParameterError`), so nothing is written outside the output folder whatever the
        scene says (its labels are checked at load time too, :func:`acoustiviz.files.label_problem`).
        """
        if not name or name in (".", "..") or "/" in name or "\\" in name or "\x00" in name:
            raise ParameterError("--out", f"refusing to write {name!r}: not a file name inside {self.out}")
        if self.planned is not None and name not in self.planned:  # scene_outputs.output_files must name it
            raise RuntimeError(f"{name} was not checked before the run (acoustiviz.app.scene_outputs)")
        return self.out / name

    # -- physics objects shared by several outputs
    @functools.cached_property
    def medium(self):
        """The fluid."""
        return self.scene.medium()

    @functools.cached_property
    def geometry(self):
        """Sphere and image sources of the single-impact outputs."""
        return self.scene.geometry()

    @functools.cached_property
    def listeners(self):
        """The scene's listeners, a list of :class:`~acoustiviz.core.listener.Listener` (positions in m)."""
        return [Listener(name, position) for name, position in self.scene.listeners()]

    def pulse(self, kind=None):
        """The single impact's acceleration pulse (scene pulse, or ``kind``)."""
        return self.scene.pulse(kind=kind)

    @functools.cached_property
    def damper_model(self):
        """The scene's :class:`~acoustiviz.dynamics.DamperModel`."""
        return scene_damper_model(self.scene)

    @property
    def damper_initial(self):
        """Initial state of the damper run."""
        return damper_initial(self.scene)

    @functools.cached_property
    def damper(self):
        """The scene's one damper run (:class:`~acoustiviz.app.damper.DamperResult` of :func:`damper_settings`).

        Computed once per scene run, for every output that wants it (history, impact table, WAV, levels, spectrum).
        """
        settings = damper_settings(self.scene, self.out)
        name = damper_solver(self.scene, self.progress)
        self.progress(f"simulating the damper for {settings.duration:g} s ({name} solver)")
        return _damper.run(settings)

    @functools.cached_property
    def sweep(self):
        """The scene's one sweep (:class:`~acoustiviz.app.sweep.SweepResult` of :func:`sweep_settings`).

        Run (or resumed) once per scene run, for the sweep's reports and the design table.
        """
        settings = sweep_settings(self.scene, self.out)
        self.progress(f"sweeping {len(settings.spec.designs())} designs, {settings.settings.duration:g} s of motion "
                      "each")
        return _sweep.run(settings, progress=self.stream)

    @property
    def damper_run(self):
        """The damper's :class:`~acoustiviz.dynamics.SimulationResult`."""
        return self.damper.result

    @functools.cached_property
    def forced(self):
        """The scene's one forced run (:class:`~acoustiviz.app.forced.ForcedResult` of its ``forced_settings``).

        Computed once per scene run, for every output that wants it (frequency response, bifurcation, noise).
        """
        settings = _forced.forced_settings(self.scene, self.out)
        self.progress(f"forced damper: {len(settings.frequencies)} frequencies, sweep {settings.sweep} "
                      f"({settings.solver} solver)")
        return _forced.run(settings)


# --------------------------------------------------------------------------- producers
def waveform_settings(scene, out=None):
    """The scene's ``[outputs.waveform]`` as a :class:`~acoustiviz.app.settings.waveform.WaveformJob`.

    Every listener and every pulse of ``outputs.waveform.pulses`` (default ``contact.pulse``), the
    files ``waveform_NAME.csv`` and ``.png`` in folder ``out`` (None: no files, the checks of the
    scene's settings alone, made before the run folder exists); errors name scene keys.
    """
    from .settings.waveform import PLACEHOLDER, WaveformJob

    kinds = scene.output("waveform")["pulses"] or [scene.section("contact")["pulse"]]
    setup = scene.setup()
    room = getattr(setup.geometry, "image_order", None) is not None
    files = {} if out is None else {k: str(Path(out) / f"waveform_{PLACEHOLDER}.{k}") for k in ("csv", "png")}
    names = WaveformJob.names_for("scene")
    return WaveformJob(impact=setup.impact, pulses=tuple(scene.pulse(kind=k) for k in kinds), medium=setup.medium,
                       geometry=setup.geometry, listeners=tuple(Listener(n, p) for n, p in scene.listeners()),
                       max_memory_mb=scene.section("grids")["memory_limit_mb"],
                       k_hertz_source=setup.k_hertz_source, names=names,
                       size_options=("configuration.window_s",) if room else ("listeners",), **files)


def produce_waveform(ctx: RunContext):
    """Pressure waveform at each listener for each requested pulse: :func:`acoustiviz.app.waveform.run`."""
    from .waveform import run

    settings = waveform_settings(ctx.scene, ctx.out)
    for lst in settings.listeners:  # only the files checked before the run
        for path in settings.files(lst).values():
            ctx.path(Path(path).name)
    result = run(settings)
    result.write()
    products = []
    for i, lst in enumerate(settings.listeners):
        high, low = result.peak_positive[i], result.peak_negative[i]
        figs = {"pulse": settings.pulses[0].kind, "max_pa": f"{high:.4g}", "min_pa": f"{low:.4g}",
                "peak_spl_db": f"{result.peak_spl_db[i]:.1f}"}
        if result.images:  # a room: its image model
            figs.update(image_order=str(result.images["image_order"]), images=str(result.images["images"]),
                        neglected_energy_db=f"{result.images['neglected_energy_db']:.1f}")
        files = settings.files(lst)
        products += [Product("waveform", Path(files[k]), figs if k == "csv" else {}) for k in ("csv", "json", "png")
                     if k in files]
    return products


def directivity_settings(scene, out=None):
    """The scene's ``[outputs.directivity]`` as a :class:`~acoustiviz.app.settings.directivity.DirectivityJob`.

    The circle's radius is the first listener's distance from the sphere's centre; the files are
    ``directivity.csv`` and ``.png`` in folder ``out`` (None: no files, the checks of the scene's settings
    alone, made before the run folder exists); errors name scene keys.
    """
    from .settings.directivity import DirectivityJob

    opts, setup = scene.output("directivity"), scene.setup()
    (_, position), *_ = scene.listeners()
    first = scene.data["listeners"][0]
    circle = "listeners[0]." + ("position_m" if first.get("position_m") is not None else "distance_m")
    files = {} if out is None else {k: str(Path(out) / f"directivity.{k}") for k in ("csv", "png")}
    names = {**DirectivityJob.names_for("scene"), "distance": circle}  # the circle is the first listener's
    distance = float(np.linalg.norm(np.asarray(position, dtype=float) - setup.geometry.centre))
    return DirectivityJob(impact=setup.impact, pulse=setup.pulse, medium=setup.medium,
                          geometry=setup.geometry, distance=distance,
                          step_deg=opts["step_deg"], metric=opts.get("metric", "peak-spl"),
                          max_memory_mb=scene.section("grids")["memory_limit_mb"],
                          k_hertz_source=setup.k_hertz_source, names=names, **files)


def produce_directivity(ctx: RunContext):
    """Peak, RMS and SPL (and a chosen level) against angle at the first listener's distance: the directivity job."""
    from .directivity import run

    settings = directivity_settings(ctx.scene, ctx.out)
    for path in settings.files().values():  # only the files checked before the run
        ctx.path(Path(path).name)
    result = run(settings)
    csv, png = result.write()
    i = result.loudest()
    figures = {"max_spl_db": f"{result.spl_db[i]:.1f}", "at_deg": f"{result.angles_deg[i]:g}",
               "distance_m": f"{settings.distance:g}"}
    if result.levels is not None:
        figures[f"max_{result.column}"] = f"{np.nanmax(result.levels):.1f}"
    if settings.in_room:  # a room: its image model
        geometry = settings.geometry
        figures.update(image_order=str(geometry.image_order), images=str(geometry.image_count))
    return [Product("directivity", csv, figures), Product("directivity", png, {})]


#: The files of each damper output (:class:`~acoustiviz.app.settings.damper_job.DamperJob` fields -> file names).
DAMPER_FILES = {"impact_table": {"impacts_csv": "impacts.csv"},
                "damper_history": {"history_csv": "damper_history.csv", "png": "damper_history.png"}}


def damper_settings(scene, out=None):
    """The scene's ``[damper]`` and its damper outputs as a :class:`~acoustiviz.app.settings.damper_job.DamperJob`.

    The files of ``[outputs.impact_table]`` and ``[outputs.damper_history]`` the scene asks for, in
    folder ``out`` (None: no files, the checks of the scene's settings alone, made before the run folder
    exists); the working memory within ``grids.memory_limit_mb``; errors name scene keys.
    """
    from .settings.damper import BALL_START, BALLS
    from .settings.damper_job import DamperJob, scene_balls

    d = scene.section("damper")
    files = {} if out is None else {key: str(Path(out) / name) for kind, names in DAMPER_FILES.items()
                                    if scene.wants(kind) for key, name in names.items()}
    return DamperJob(scene_damper_model(scene), damper_initial(scene), d["duration_s"], d["solver"], d["tolerance"],
                     max_memory_mb=scene.section("grids")["memory_limit_mb"], names=DamperJob.names_for("scene"),
                     **files, **scene_balls(d, BALLS + BALL_START))


def _balls_heard(scene) -> None:
    """Check the sound (WAV, levels, spectrum) of several balls before any work, naming scene keys.

    Every cavity of ``[[damper.cavities]]`` placed (``position_m``: in the fluid, no two overlapping) and
    every listener outside every column of balls; in a room every image is summed to the room's
    tolerance, so a late tail or absorption bands of ``[outputs.wav]`` are refused.
    """
    from ..errors import ParameterError
    from ..sound.balls_sound import check_ball_scene
    from .damper import balls_model, cavity_positions
    from .scene_levels import damper_cavity
    from .settings.auralize import ROOM_SOUND_SCENE_KEYS

    d = scene.section("damper")
    if d["balls"] == 1 and not d.get("cavities", ()):
        return
    job = damper_settings(scene)
    if job.total_balls() == 1:
        return
    rs = scene.room_sound()
    if rs is not None:
        key = ROOM_SOUND_SCENE_KEYS["late_tail" if rs.late_tail else "band_centres"]
        raise ParameterError(key, f"several balls ({job.total_balls()}) in a room are heard with every image to the "
                                  "room's tolerance: no late tail and no absorption bands")
    points = np.array([p for _, p in scene.listeners(scene.damper_sphere_radius())])
    check_ball_scene(balls_model(job), damper_cavity(scene, job.model, scene.medium()), points, cavity_positions(job),
                     name="listeners", positions_name="damper.cavities[{k}].position_m")


def _write_damper(ctx: RunContext, kind: str) -> list:
    """Write the files of damper output ``kind`` of the scene's one damper run; return their paths."""
    for name in DAMPER_FILES[kind].values():  # only the files checked before the run
        ctx.path(name)
    return ctx.damper.write(only=DAMPER_FILES[kind])


def produce_damper_history(ctx: RunContext):
    """Main-mass displacement with and without the damper (paper Figure 5) as PNG and CSV."""
    csv, png = _write_damper(ctx, "damper_history")
    return [Product("damper_history", png, _damper.damping_figures(ctx.damper)), Product("damper_history", csv, {})]


def produce_impact_table(ctx: RunContext):
    """One row per contact of the damper run (CSV with the damper command's columns)."""
    (path,) = _write_damper(ctx, "impact_table")
    imp = ctx.damper_run.impacts
    figs = {"impacts": str(len(imp))}
    if len(imp):
        figs["max_approach_m_s"] = f"{np.max(imp.approach_velocity):.4g}"
    return [Product("impact_table", path, figs)]


def produce_restitution(ctx: RunContext):
    """Coefficient of restitution against impact mass and speed (paper Figure 7), CSV and PNG."""
    from ..dynamics.metrics import restitution_curve
    from ..output.plot.dynamics import plot_restitution
    from ..output.plot.style import style

    opts = ctx.scene.output("restitution")
    masses, speeds = np.asarray(opts["masses_kg"]), np.asarray(opts["velocities_m_s"])
    e = restitution_curve(masses, speeds, ctx.damper_model)
    header = ["mass_kg"] + [f"restitution_at_{u:g}_m_s" for u in speeds]
    csv = write_csv_atomic(ctx.path("restitution.csv"), header, [masses, *e.T], fmt="%.8g")
    with style():
        fig = _fig()
        plot_restitution(masses, speeds, e, ax=fig.add_subplot(), clip_tensile=ctx.damper_model.clip_tensile)
        png = _save(fig, ctx.path("restitution.png"))
    return [Product("restitution", csv, {"min": f"{e.min():.4f}", "max": f"{e.max():.4f}"}),
            Product("restitution", png, {})]


def produce_wav(ctx: RunContext):
    """Calibrated WAV of the damper run at each listener: the auralize job of :func:`.scene_wav.wav_settings`.

    The job's damper is the scene's one damper run (:attr:`RunContext.damper`), simulated once for every output.
    """
    from .auralize import run
    from .scene_wav import wav_products, wav_settings

    job = wav_settings(ctx.scene, ctx.out, damper_settings(ctx.scene))
    for path in job.wav_files:  # only the files checked before the run
        ctx.path(Path(path).name)
    damper = ctx.damper
    ctx.progress(f"auralising {len(damper.result.impacts)} impacts at {len(job.listeners)} listener(s), {job.rate} Hz")
    result = run(job, damper=damper)
    result.write()
    for w in result.written:
        for msg in w["warnings"]:
            ctx.progress(f"warning: {msg}")
    return wav_products(result)


def produce_run_field(ctx: RunContext):
    """The damper run's levels on a grid and its waveform: :func:`.scene_run_field.run_field_settings`."""
    from .scene_run_field import run_field_products

    return run_field_products(ctx, run_field_settings(ctx.scene, ctx.out, damper_settings(ctx.scene)))


PRODUCERS = {
    "waveform": produce_waveform,
    "directivity": produce_directivity,
    "level_map": produce_level_map,
    "damper_history": produce_damper_history,
    "impact_table": produce_impact_table,
    "snapshot": produce_snapshot,
    "balloon": produce_balloon,
    "animation": produce_animation,
    "restitution": produce_restitution,
    "sweep": produce_sweep,
    "design_table": produce_design_table,
    "optimize": produce_optimize,
    "wav": produce_wav,
    "levels": produce_levels,
    "spectrum": produce_spectrum,
    "run_field": produce_run_field,
    "frequency_response": _forced.produce_frequency_response,
    "bifurcation": _forced.produce_bifurcation,
    "operating_noise": _forced.produce_operating_noise,
}


# --------------------------------------------------------------------------- the run
#: Output kind -> the settings object its producer builds, built before any output is computed.
_SETTINGS = {
    "waveform": waveform_settings,
    **{kind: damper_settings for kind in DAMPER_FILES},
    "directivity": directivity_settings,
    "level_map": map_settings,
    "sweep": sweep_settings,
    "design_table": lambda scene: (sweep_settings(scene), design_settings(scene)),
    "wav": lambda scene: (_balls_heard(scene), wav_settings(scene, None, damper_settings(scene))),
    "optimize": optimize_settings,
    "levels": lambda scene: (_balls_heard(scene), levels_settings(scene)),
    "spectrum": lambda scene: (_balls_heard(scene), levels_settings(scene)),
    "run_field": lambda scene: (_balls_heard(scene), run_field_settings(scene, None, damper_settings(scene))),
    "snapshot": snapshot_settings,
    "balloon": balloon_settings,
    "animation": animation_settings,
    **{kind: _forced.forced_settings for kind in _forced.FORCED_FILES},
}


def _check_out(out: Path, force: bool) -> None:
    if out.exists() and not out.is_dir():
        raise ParameterError("--out", f"{out} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise ParameterError("--out", f"{out} exists and is not empty; pass --force to write into it")


def _summary(scene, products, seconds: float) -> str:
    lines = [f"# acoustiviz run: {scene.name}", "", scene.section("scene")["description"] or "", "",
             f"Scene: `{scene.source}`. Outputs asked for: {', '.join(scene.outputs) or 'none'}.",
             f"Wall time: {seconds:.1f} s.", "", "| output | file | key figures |", "|---|---|---|"]
    for p in products:
        figs = ", ".join(f"{k} = {v}" for k, v in p.figures.items())
        lines.append(f"| {p.kind} | `{p.path.name}` | {figs} |")
    return "\n".join(lines) + "\n"


@contextlib.contextmanager
def _collect_per_output():
    """Yield a function that collects the garbage of the output just made and sets what survives aside.

    A run imports most of numpy, scipy, numba, matplotlib and VTK: several hundred thousand
    long-lived objects that each of Python's full collections would traverse again, several times
    per run (``benchmarks/results/design_timings.md``). Before the first output and after each one the garbage
    (figures, plotters, signals) is collected, which then costs only the objects made since the
    previous output, and what survives is frozen out of later collections (:func:`gc.freeze`),
    so no output's garbage outlives it and none of the files changes; on leaving, the frozen
    objects are handed back to the collector (:func:`gc.unfreeze`). A caller that disabled the
    collector or froze objects of its own is left as it is (the function does nothing).
    """
    import gc

    if not gc.isenabled() or gc.get_freeze_count():
        yield lambda: None
        return

    def collect():
        gc.collect()
        gc.freeze()

    try:
        collect()  # what the scene's loading made
        yield collect
    finally:
        gc.unfreeze()


def run_scene(scene, out, *, force: bool = False, progress=None, stream=None):
    r"""Produce every output the scene names into folder ``out``.

    Parameters
    ----------
    scene : acoustiviz.scene.Scene
        A validated scene (:func:`acoustiviz.scene.load_scene`).
    out : path-like
        Output folder; created if missing. An existing non-empty folder is refused unless
        ``force``.
    force : bool
        Write into an existing folder, replacing files of the same name (each atomically).
    progress : callable, optional
        Called with a one-line message at each step.
    stream : file-like, optional
        Where long steps (sweeps) draw a progress bar with count and ETA.

    Returns
    -------
    list of Product
        Every file written, ``summary.md`` last.

    Examples
    --------
    The paper's Figure 2 waveform from a two-table scene (the listener defaults to 0.7 m at 45°
    above a reflecting plane): a peak SPL of 88.8 dB.

    >>> import tempfile
    >>> from acoustiviz.scene import load_scene
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "fig2.toml"
    ...     _ = path.write_text('[sphere]\nradius_m = 0.01905\ndensity_kg_m3 = 7800.0\n[outputs.waveform]\n')
    ...     products = run_scene(load_scene(path), Path(folder) / "out")
    >>> [(p.kind, p.path.name) for p in products]  # doctest: +NORMALIZE_WHITESPACE
    [('waveform', 'waveform_paper.csv'), ('waveform', 'waveform_paper.png'), ('summary', 'summary.md')]
    >>> products[0].figures["peak_spl_db"]
    '88.8'
    """
    out = Path(out)
    _check_out(out, force)
    missing = [k for k in scene.outputs if k not in PRODUCERS]
    if missing:
        raise ParameterError("outputs", f"this build cannot produce {', '.join(missing)}")
    planned = preflight(scene, out, _SETTINGS)  # every output's settings and files, before the first
    if scene.wants("sweep"):  # a sweep folder of an earlier run: resumed only when it is the same, undamaged sweep
        sweep_settings(scene, out)
    out.mkdir(parents=True, exist_ok=True)
    say = progress or (lambda msg: None)
    ctx = RunContext(scene, out, say, stream, planned)
    start = time.perf_counter()
    products = []
    with _collect_per_output() as collect:
        for i, kind in enumerate(scene.outputs, 1):
            say(f"[{i}/{len(scene.outputs)}] {kind}")
            t0 = time.perf_counter()
            products += PRODUCERS[kind](ctx)
            collect()
            say(f"[{i}/{len(scene.outputs)}] {kind} done in {time.perf_counter() - t0:.1f} s")
    summary = write_text_atomic(out / SUMMARY, _summary(scene, products, time.perf_counter() - start))
    products.append(Product("summary", summary, {}))
    return products

