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
from .map_job import map_settings, produce_level_map
from .names import SCENE_DAMPER_KEYS, user_terms
from .products import Product, damper_initial, damper_solver, scene_damper_model
from .products import new_figure as _fig
from .products import save as _save
from .scene_levels import check_sound_listeners, levels_settings, produce_levels, produce_spectrum
from .scene_outputs import SUMMARY, preflight
from .sweep import scene_sweep_spec

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
    def configuration(self):
        """Sphere and image sources of the single-impact outputs."""
        return self.scene.configuration()

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

    @property
    def damper_run(self):
        """The damper's :class:`~acoustiviz.dynamics.SimulationResult`."""
        return self.damper.result


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
    room = getattr(setup.configuration, "image_order", None) is not None
    files = {} if out is None else {k: str(Path(out) / f"waveform_{PLACEHOLDER}.{k}") for k in ("csv", "png")}
    names = {"csv": "outputs.waveform", "png": "outputs.waveform", "listeners": "listeners",
             "pulses": "outputs.waveform.pulses", "max_memory_mb": "grids.memory_limit_mb",
             "memory_limit": "grids.memory_limit_mb"}
    return WaveformJob(setup.impact, tuple(scene.pulse(kind=k) for k in kinds), setup.medium, setup.configuration,
                       tuple(Listener(n, p) for n, p in scene.listeners()),
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
    names = {**DirectivityJob.scene_names(), "csv": "outputs.directivity", "png": "outputs.directivity",
             "distance": circle, "angles": "outputs.directivity.step_deg", "max_memory_mb": "grids.memory_limit_mb",
             "memory_limit": "grids.memory_limit_mb", "wall_distance": "configuration.wall_distance_m",
             "window": "configuration.window_s"}
    distance = float(np.linalg.norm(np.asarray(position, dtype=float) - setup.configuration.centre))
    return DirectivityJob(setup.impact, setup.pulse, setup.medium, setup.configuration, distance,
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
        conf = settings.configuration
        figures.update(image_order=str(conf.image_order), images=str(conf.image_count))
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
    from .settings.damper import BALLS
    from .settings.damper_job import DamperJob

    d = scene.section("damper")
    files = {} if out is None else {key: str(Path(out) / name) for kind, names in DAMPER_FILES.items()
                                    if scene.wants(kind) for key, name in names.items()}
    names = {**SCENE_DAMPER_KEYS, "impacts_csv": "outputs.impact_table", "history_csv": "outputs.damper_history",
             "png": "outputs.damper_history", "max_memory_mb": "grids.memory_limit_mb"}
    balls = {s.name: d[s.key] for s in BALLS}
    names.update({s.name: s.path for s in BALLS})
    return DamperJob(scene_damper_model(scene), damper_initial(scene), d["duration_s"], d["solver"], d["tolerance"],
                     max_memory_mb=scene.section("grids")["memory_limit_mb"], names=names, **files, **balls)


def _one_ball_heard(scene) -> None:
    """Refuse a sound of the damper (WAV, levels, spectrum) with several balls: their sound is one ball's alone."""
    from ..errors import ParameterError

    n = scene.section("damper")["balls"]
    if n > 1:
        raise ParameterError("damper.balls", f"the sound of the damper is synthesised for one ball, got {n}: set "
                                             "damper.balls = 1 or ask only for [outputs.impact_table] and "
                                             "[outputs.damper_history]")


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
    """Calibrated WAV of the damper run at each listener, written by the command's own step.

    The scene's :meth:`~acoustiviz.scene.Scene.auralize_settings` (the settings object of
    ``acoustiviz auralize``) run by :func:`acoustiviz.app.auralize.write_sound`.
    """
    from .auralize import Sound, write_sound
    from .scene_levels import damper_sound_setup

    s = ctx.scene.auralize_settings()
    res = ctx.damper_run
    seq, room, model, names, points = damper_sound_setup(ctx)
    ctx.progress(f"auralising {len(seq)} impacts at {len(names)} listener(s), {s.rate} Hz")
    source = f"scene: sphere.damper_radius = {ctx.scene.section('sphere')['damper_radius']!r}"
    sound = Sound(s.radius, source, room, model, points, None, ctx.scene.room_sound())
    paths = [ctx.path("wav_stereo.wav")] if s.stereo else [ctx.path(f"wav_{name}.wav") for name in names]
    files, written = write_sound(s, seq, sound, _damper.damper_description(ctx.damper_model, ctx.damper, res.duration),
                                 duration=res.duration, labels=names, paths=paths, scene_name=ctx.scene.name,
                                 quiet=True)
    products = []
    for wav, w in zip(files, written, strict=True):
        for msg in w["warnings"]:
            ctx.progress(f"warning: {msg}")
        rec = w["record"]
        lvl = max((v for v in rec["peak_spl_db_re_20upa"] if v is not None), default=float("nan"))
        phys = max((v for v in rec["physical_peak_spl_db_re_20upa"] if v is not None), default=float("nan"))
        products += [Product("wav", wav.path, {"impacts": str(len(seq)), "peak_spl_db": f"{lvl:.1f}",
                                               "physical_peak_spl_db": f"{phys:.1f}",
                                               "subtype": rec["subtype"], "rate_hz": str(s.rate)}),
                     Product("wav", w["sidecar"], {})]
    return products


def _plane_options(ctx: RunContext, s) -> dict:
    return {"extent": s.extent, "sections": s.sections, "n_u": s.n_u, "medium": ctx.medium}


def produce_snapshot(ctx: RunContext):
    """Pressure p(x, t) on the planar sections at the requested times (one PNG, side by side)."""
    from ..field.sections import section_field
    from ..output.render import render_snapshot

    s = ctx.scene.view_settings("snapshot")
    times = list(s.times)
    ctx.progress(f"rendering {len(times)} snapshot(s)")
    field = section_field(ctx.pulse(), ctx.configuration, times, **_plane_options(ctx, s))  # once for every file
    path = render_snapshot(ctx.pulse(), ctx.configuration, times if len(times) > 1 else times[0],
                           ctx.path("snapshot.png"), size=s.size, field=field)
    products = [Product("snapshot", path, {"times_ms": ", ".join(f"{1e3 * t:g}" for t in times)})]
    if ctx.scene.output("snapshot")["vtk"]:
        from ..output.vtk import write_snapshot_vtk

        products += [Product("vtk", p) for p in write_snapshot_vtk(ctx.pulse(), ctx.configuration, times,
                                                                    ctx.path("snapshot.vtu"), field=field)]
    return products


def produce_balloon(ctx: RunContext):
    """3-D directivity balloon on the spherical grid around the contact point (PNG)."""
    from ..output.render import balloon_data, render_balloon
    from .views import balloon_levels

    s = ctx.scene.view_settings("balloon")
    pulse, conf = ctx.pulse(), ctx.configuration
    data = balloon_data(pulse, conf, medium=ctx.medium, distance=s.distance, metric=s.metric, n_theta=s.n_theta,
                        levels=balloon_levels(s.metric, pulse, conf, ctx.medium))
    path = render_balloon(pulse, conf, ctx.path("balloon.png"), medium=ctx.medium, db_range=s.db_range,
                          size=s.size, data=data)
    products = [Product("balloon", path, {"metric": s.metric, "max_db": f"{data.max_level:.1f}",
                                          "mean_db": f"{data.mean_level:.1f}", "distance_m": f"{s.distance:g}"})]
    if ctx.scene.output("balloon")["vtk"]:
        from ..output.vtk import write_balloon_vtk

        products += [Product("vtk", p) for p in write_balloon_vtk(pulse, conf, ctx.path("balloon.vtu"),
                                                                   medium=ctx.medium, data=data)]
    return products


def produce_animation(ctx: RunContext):
    """GIF of the wavefront leaving the impact and reflecting, on the planar sections."""
    from ..output.render import render_animation
    from ..output.render.animation import animation_field

    s = ctx.scene.view_settings("animation")
    ctx.progress(f"rendering {s.frames} animation frames")
    field = animation_field(ctx.pulse(), ctx.configuration, frames=s.frames, **_plane_options(ctx, s))  # once
    path = render_animation(ctx.pulse(), ctx.configuration, ctx.path("animation.gif"), fps=s.fps, size=s.size,
                            field=field)
    products = [Product("animation", path, {"frames": str(s.frames), "fps": f"{s.fps:g}"})]
    if ctx.scene.output("animation")["vtk"]:
        from ..output.vtk import write_animation_vtk

        products += [Product("vtk", p) for p in write_animation_vtk(ctx.pulse(), ctx.configuration,
                                                                     ctx.path("animation.vtu"), field=field)]
    return products


def produce_sweep(ctx: RunContext):
    """Sweep over gap and impact mass (paper Figure 6): ``sweep/sweep.csv``, the maps and the design table."""
    from .sweep import run_sweep_outputs

    opts = ctx.scene.output("sweep")
    spec = scene_sweep_spec(ctx.scene)
    ctx.progress(f"sweeping {len(spec.designs())} designs, {opts['duration_s']:g} s of motion each")
    run = run_sweep_outputs(spec, ctx.path("sweep"), workers=opts["workers"] or None, progress=ctx.stream)
    ctx.sweep_table = run.table
    spl = np.asarray(run.table["max_spl_db"])
    figs = {"designs": str(len(run.table))}
    n_failed = int(run.table.failed.sum())
    if n_failed:
        figs["failed_designs"] = str(n_failed)
    if np.isfinite(spl).any():
        figs["max_spl_db_range"] = f"{np.nanmin(spl):.1f}-{np.nanmax(spl):.1f}"
    best = max(run.bands, key=lambda b: b.decrease_db, default=None)
    if best is not None:
        figs["largest_saving_db"] = f"{best.decrease_db:.1f} at {100 * best.low:.3g}-{100 * best.high:.3g} cm/s"
    return [Product("sweep", run.journal, figs)] + [Product("sweep", p, {}) for p in run.paths]


def produce_design_table(ctx: RunContext):
    """Paper Table 2 from the sweep as a figure beside the paper's values, and the quietest design for a target."""
    from ..sweep import load_sweep
    from .sweep import scene_design_table

    opts = ctx.scene.output("design_table")
    table = getattr(ctx, "sweep_table", None)
    if table is None:  # the sweep output runs first; a scene without it is refused at load time
        table = load_sweep(ctx.path("sweep"))
    bands, png, choice = scene_design_table(table, ctx.out, inclination=opts["inclination_m_s"],
                                            tolerance=opts["tolerance_m_s"])
    products = [Product("design_table", png, {"bands": str(len(bands))})]
    if choice is not None:
        path = write_text_atomic(ctx.path("design_choice.txt"), choice.summary() + "\n")
        figs = {"candidates": str(choice.n_candidates)}
        if choice.n_candidates:
            figs["saving_db"] = f"{choice.saving_db:.1f}"
        products.append(Product("design_table", path, figs))
    return products


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
    "wav": produce_wav,
    "levels": produce_levels,
    "spectrum": produce_spectrum,
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
    "sweep": scene_sweep_spec,
    "design_table": scene_sweep_spec,
    "wav": lambda scene: (_one_ball_heard(scene), scene.auralize_settings(), check_sound_listeners(scene)),
    "levels": lambda scene: (_one_ball_heard(scene), levels_settings(scene)),
    "spectrum": lambda scene: (_one_ball_heard(scene), levels_settings(scene)),
    **{view: (lambda scene, view=view: scene.view_settings(view)) for view in ("snapshot", "balloon", "animation")},
    **{kind: (lambda scene: scene.forced_settings()) for kind in ("frequency_response", "bifurcation")},
    "operating_noise": lambda scene: (scene.forced_settings(), _operating_listener(scene)),
}


def _operating_listener(scene) -> None:
    """The first listener, which hears the damper in operation, outside its cavity."""
    from .forced_noise import check_listener

    check_listener(scene_damper_model(scene), scene.listeners()[0][1], config=scene.section("configuration")["kind"],
                   radius=scene.damper_sphere_radius(), name="listeners", settings=scene.geometry_settings())


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
        from ..sweep.store import check_dir

        with user_terms({"out": "outputs.sweep"}):
            check_dir(scene_sweep_spec(scene), out / "sweep")
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

