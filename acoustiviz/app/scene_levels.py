"""Scene outputs ``levels`` and ``spectrum``: how loud the damper run is at each listener.

Both evaluate the damper run rendered at :data:`acoustiviz.app.levels.ANALYSIS_RATE` (96 kHz, the
clicks computed in closed form at >= 1.5 MHz and band-limited flat to 43.2 kHz) at every listener,
once per run whichever of the two outputs asks first. The surroundings of the cavity (struck wall,
walls that radiate) are those of ``[outputs.wav]`` when the scene has one, else its defaults.

* ``levels`` writes ``levels.csv`` (one row per listener: LZpeak ... SEL(A), optionally N5, Nmax
  and sharpness) and reports the figures in the summary, with the run's sound power and the
  radiation efficiency of its loudest impact (:func:`acoustiviz.levels.energy.run_energy`);
* ``spectrum`` writes ``spectrum.csv`` (``channel,band_hz,leq_db,lmax_db``) and ``spectrum.png``.
"""

from __future__ import annotations

import numpy as np

from ..core.listener import Listener
from ..errors import ParameterError
from ..levels import loudness_available
from ..levels.energy import run_energy
from .levels import ANALYSIS_RATE, LevelsResult, summary_lines

__all__ = ["check_levels_settings", "check_sound_listeners", "damper_cavity", "damper_sound_setup", "levels_settings",
           "produce_levels",
           "produce_spectrum"]

_CACHE = "_levels_result"
#: The files each output writes, in its folder.
_FILES = {"levels": {"csv": "levels.csv"}, "spectrum": {"spectrum_csv": "spectrum.csv", "spectrum_png": "spectrum.png"}}


def damper_cavity(scene, model, medium):
    """The cavity a scene's damper sounds in (``[outputs.wav]`` surroundings, or their defaults)."""
    from .wav import cavity

    opts = scene.output_or_defaults("wav")
    return cavity(scene.section("configuration")["kind"], scene.damper_sphere_radius(), model.gap,
                  struck_wall=opts["struck_wall"], walls=opts["walls"], medium=medium, **scene.geometry_settings())


def check_sound_listeners(scene) -> None:
    """Refuse, before any output is made, a listener of the damper's sound (wav, levels, spectrum) in its cavity.

    Several balls (``damper.balls`` or ``[[damper.cavities]]``): checked with every cavity placed, outside
    every column, by the pipeline's check of their sound.
    """
    from ..sound import check_listeners
    from .products import scene_damper_model

    d = scene.section("damper")
    cavities = d.get("cavities", ())
    if (sum(c["balls"] for c in cavities) if cavities else d["balls"]) > 1:
        return
    room = damper_cavity(scene, scene_damper_model(scene), scene.medium())
    check_listeners(np.array([p for _, p in scene.listeners(scene.damper_sphere_radius())]), room, name="listeners")


def damper_sound_setup(ctx):
    """``(sequence, cavity, click model, listener names, positions)`` of a scene's damper run.

    The one setup of a scene's sound: the ``wav`` output renders its files with it and the
    ``levels`` and ``spectrum`` outputs their analysis, so the three hear the same cavity
    (``[outputs.wav]`` surroundings, or their defaults), clicks and listeners. A click longer
    than the run is refused as on the command line (:func:`acoustiviz.app.damper.check_click_fits`).
    """
    from ..sound import ClickModel
    from .damper import check_click_fits, heard_sequence

    radius = ctx.scene.damper_sphere_radius()
    room = damper_cavity(ctx.scene, ctx.damper_model, ctx.medium)
    contact = ctx.scene.section("contact")
    model = ClickModel(k_hertz=ctx.damper_model.k_hertz, mass=ctx.damper_model.m, main_mass=ctx.damper_model.M,
                       mass_model=contact["pulse_mass"], pulse=contact["pulse"])
    named = [Listener(name, position) for name, position in ctx.scene.listeners(radius)]
    seq = heard_sequence(ctx.damper_run)
    d = ctx.damper_model
    check_click_fits(seq, d.k_hertz, d.m, ctx.damper_run.duration,
                     names={"m": "damper.impact_mass_kg", "k_hertz": "contact.k_hertz_n_m1_5",
                            "duration": "damper.duration_s"})
    return seq, room, model, [lst.name for lst in named], np.array([lst.position for lst in named])


def check_levels_settings(scene) -> None:
    """Refuse, before any output is made, levels the run cannot compute: loudness needs mosqito."""
    opts = scene.output("levels") if "levels" in scene.outputs else {}
    if opts.get("loudness") and not loudness_available():
        raise ParameterError("outputs.levels.loudness", "needs mosqito: pip install 'acoustiviz[hearing]'")


def levels_settings(scene, out=None, signal=None, channels=()):
    """The scene's ``[outputs.levels]`` and ``[outputs.spectrum]`` as one :class:`~acoustiviz.app.levels.LevelsJob`.

    ``signal``: the damper run's sound at the listeners (named ``channels``), computed at
    :data:`ANALYSIS_RATE`; the files are those of the two outputs the scene asks for, in folder ``out``.
    Without a signal (before the run) only the checks are made: loudness needs mosqito, the
    listeners lie outside the cavity; None is returned.
    """
    from pathlib import Path

    from .settings.levels import LevelsJob

    check_levels_settings(scene)
    if signal is None:
        check_sound_listeners(scene)
        return None
    opts = scene.output("levels") if "levels" in scene.outputs else {}
    files = {k: str(Path(out) / v) if out is not None else v
             for kind, names in _FILES.items() if kind in scene.outputs for k, v in names.items()}
    return LevelsJob(signal, tuple(channels), None, "computed", loudness=bool(opts.get("loudness", False)),
                     what="the damper run", names={"signal": "damper", "input": "damper", "loudness":
                                                   "outputs.levels.loudness"}, **files)


def _result(ctx) -> LevelsResult:
    """The run's levels, computed and their files written once per run; kept on the context."""
    from .damper import cavity_positions, render_run
    from .levels import run

    if _CACHE not in ctx.__dict__:
        check_levels_settings(ctx.scene)
        seq, room, model, names, points = damper_sound_setup(ctx)
        ctx.progress(f"levels of {len(ctx.damper_run.impacts)} impacts at {len(names)} listener(s), rendered at "
                     f"{ANALYSIS_RATE / 1e3:g} kHz")
        rendering = render_run(ctx.damper_run, seq, room, model, points, sample_rate=ANALYSIS_RATE,
                               duration=ctx.damper_run.duration, room_sound=ctx.scene.room_sound(),
                               positions=cavity_positions(ctx.damper.settings))
        result = run(levels_settings(ctx.scene, ctx.out, rendering.signal, names))
        ctx.__dict__[_CACHE] = result, result.write()
    return ctx.__dict__[_CACHE]


def produce_levels(ctx):
    """``levels.csv`` (+ its bands): weighted levels of the damper run at each listener."""
    from .products import Product

    result, written = _result(ctx)
    report = result.report
    for line in summary_lines(report, rate_note=" (computed signal)"):
        ctx.progress(line)
    main, bands = [p for p in written if p.name in ("levels.csv", "levels_bands.csv")]
    lv = report.levels
    figures = {"evaluated_at_hz": f"{lv.sample_rate:g}",
               "lcpeak_db": f"{np.max(lv.lcpeak_db):.1f}", "lafmax_db": f"{np.max(lv.lafmax_db):.1f}",
               "laeq_db": f"{np.max(lv.laeq_db):.1f}", "sel_a_db": f"{np.max(lv.sel_a_db):.1f}"}
    _, room, model, _, _ = damper_sound_setup(ctx)
    if room.geometry.enclosed:  # a room returns the sound: no radiated energy, no sound power
        ctx.progress("sound power and radiation efficiency: not defined in a room (its walls close the fluid, so "
                     "no surface around the sphere encloses the energy radiated away)")
        return [Product("levels", main, figures), Product("levels", bands, {})]
    if ctx.damper.settings.total_balls() > 1:  # the energy account is per ball-wall impact of one ball
        ctx.progress("sound power and radiation efficiency: computed for one ball only")
        return [Product("levels", main, figures), Product("levels", bands, {})]
    energy = run_energy(ctx.damper_run.impacts, room, model, ctx.damper_run.duration)
    if energy.loudest >= 0:
        k = energy.loudest
        figures["sound_power_level_db_re_1pw"] = f"{energy.sound_power_level_db:.1f}"
        figures["loudest_impact_energy_j"] = f"{energy.energy_j[k]:.3g}"
        figures["loudest_impact_radiation_efficiency"] = f"{energy.efficiency[k]:.3g}"
        speed = abs(ctx.damper_run.impacts.approach_velocity[k])
        ctx.progress(f"sound power {energy.sound_power_w:.3g} W ({energy.sound_power_level_db:.1f} dB re 1 pW); "
                     f"loudest impact ({speed:.3g} m/s): {energy.energy_j[k]:.3g} J radiated of "
                     f"{energy.energy_lost_j[k]:.3g} J lost, radiation efficiency {energy.efficiency[k]:.3g}")
    if report.loudness is not None:
        figures["n5_sone"] = f"{np.max(report.loudness.n5_sone):.2f}"
        figures["sharpness_acum"] = f"{np.max(report.loudness.sharpness_acum):.2f}"
    return [Product("levels", main, figures), Product("levels", bands, {})]


def produce_spectrum(ctx):
    """``spectrum.csv`` and ``spectrum.png``: 1/3-octave band Leq and LFmax at each listener."""
    from .products import Product

    result, written = _result(ctx)
    csv, png = [p for p in written if p.name in ("spectrum.csv", "spectrum.png")]
    bl = result.report.bands
    k = int(np.argmax(np.max(bl.leq_db, axis=0)))
    return [Product("spectrum", csv, {"loudest_band_hz": f"{bl.nominal_hz[k]:g}",
                                      "loudest_band_leq_db": f"{np.max(bl.leq_db[:, k]):.1f}"}),
            Product("spectrum", png, {})]
