"""An auralised damper run: every impact rendered at the listeners, written as calibrated WAV files.

:func:`auralize` executes an :class:`~acoustiviz.app.settings.auralize.AuralizeSettings`: it checks
every setting before any work (the sphere and the fluid, the room and its sound, the listeners, the
files, the memory), simulates the damper (paper eq 15) or reads its impacts from a CSV, renders the
Hertz pulse of each impact with rigid-sphere radiation and image sources
(:func:`acoustiviz.sound.render`), and writes the files and their sidecars through
:func:`acoustiviz.app.wav.write_wav_files`, the writer a scene's ``[outputs.wav]`` shares. Errors
name the command-line options. Lengths in m, times in s, pressures in Pa.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._validate import check_positive, check_range
from ..errors import ParameterError
from .names import user_terms
from .settings.auralize import ALL, DEFAULT_LISTENER, AuralizeSettings
from .settings.parse import parse_point
from .settings.table import by_name
from .wav import check_scale_fits, write_wav_files

#: Every auralize setting by its API name: the ranges checked here are the table's.
_TABLE = by_name(ALL)

__all__ = ["auralize", "write_sound", "read_impacts_csv", "output_paths", "Sound"]


@dataclass(frozen=True)
class Sound:
    """What a run renders, all checked: the sphere, the scene, the click model, listeners and room sound.

    ``radius`` in m with ``radius_source`` saying where it came from; ``room`` the room's settings
    (None: no room); ``room_sound`` the :class:`~acoustiviz.sound.RoomSound` (None: none).
    """

    radius: float
    radius_source: str
    scene: object
    model: object
    listeners: np.ndarray
    room: dict | None
    room_sound: object


def read_impacts_csv(path):
    """Impact times (s), walls (-1/+1) and approach speeds (m/s) from a damper impact CSV."""
    import warnings

    from ..sound import ImpactSequence

    try:
        with warnings.catch_warnings():  # an empty file: refused below, not warned about
            warnings.simplefilter("ignore", UserWarning)
            data = np.genfromtxt(path, delimiter=",", names=True, ndmin=1)
    except OSError as exc:
        raise ParameterError("--impacts", f"cannot read {path}: {exc}") from None
    except UnicodeDecodeError as exc:
        raise ParameterError("--impacts", f"{path} is not a CSV file (not UTF-8 text: {exc.reason} at byte "
                                          f"{exc.start})") from None
    except (ValueError, IndexError) as exc:
        reason = (str(exc).splitlines() or ["empty"])[0] if not isinstance(exc, IndexError) else "no header row"
        raise ParameterError("--impacts", f"{path} is not a table of impacts: {reason}") from None
    names = data.dtype.names or ()
    need = ("time_s", "wall", "approach_velocity_m_s")
    if any(n not in names for n in need):
        raise ParameterError("--impacts", f"{path} needs the columns {','.join(need)}; it has {','.join(names)}")
    try:
        return ImpactSequence(data["time_s"], data["wall"], np.abs(data["approach_velocity_m_s"]))
    except ParameterError as exc:
        raise ParameterError("--impacts", f"{path}: {exc}") from None


def output_paths(wav, n: int) -> list:
    """``OUT.wav`` for one file, ``OUT-1.wav ... OUT-n.wav`` for several."""
    wav = Path(wav)
    if n == 1:
        return [wav]
    return [wav.with_name(f"{wav.stem}-{i + 1}{wav.suffix}") for i in range(n)]


def _check_sphere_and_medium(s: AuralizeSettings):
    """Validate the damper, sphere and fluid settings; return ``(radius, radius_source, medium)``."""
    from ..constants import PAPER_RADIUS
    from ..core.materials import sphere_radius
    from ..core.medium import Medium

    # the damper's ranges were checked when its DamperSettings were made (app.settings.damper)
    d, table = s.damper, _TABLE
    if Path(s.wav).suffix.lower() != ".wav":
        raise ParameterError("--wav", f"must end in .wav, got {s.wav!r}")
    if s.radius is not None and s.density is not None:
        raise ParameterError("--radius", "give either --radius or --density, not both")
    if s.density is not None:
        radius = sphere_radius(d.m, table["density"].check(s.density, "--density"))
        check_range("--m", radius, table["radius"].low, table["radius"].high, low_open=table["radius"].low_open,
                    unit="m (the radius of a sphere of this mass and --density)")
        radius_source = f"solid sphere of {d.m:g} kg at {s.density:g} kg/m^3"
    else:
        radius = table["radius"].check(PAPER_RADIUS if s.radius is None else s.radius, "--radius")
        radius_source = "given" if s.radius is not None else "default: the paper's sphere"
    return radius, radius_source, Medium(c=s.c, rho=s.rho)


def _room_sound_of(s: AuralizeSettings):
    """The RoomSound of the settings (None without a late tail or absorption bands), refused without a room."""
    from .wav import room_sound

    given = {"--late-tail": s.late_tail or None, "--tail-seed": s.tail_seed, "--tail-decay": s.tail_decay,
             "--transition": s.transition, "--absorption-bands": s.absorption_bands}
    if s.room.room is None:
        for opt, val in given.items():
            if val is not None:
                raise ParameterError(opt, "only applies with --room LX,LY,LZ")
        return None
    if not s.late_tail:
        for opt in ("--tail-seed", "--tail-decay", "--transition"):
            if given[opt] is not None:
                raise ParameterError(opt, "only applies with --late-tail")
    if s.absorption_bands is not None and s.room.absorption is not None:
        raise ParameterError("--absorption-bands", "give either --absorption or --absorption-bands, not both")
    return room_sound(late_tail=s.late_tail, seed=s.tail_seed, decay=s.tail_decay or "eyring",
                      transition=s.transition, absorption_bands=s.absorption_bands)


def _room_of(s: AuralizeSettings, absorption):
    """The room's settings (or None) and the configuration; a rigid room's images are those within the sound."""
    from .impacts import room_settings

    r = s.room
    if r.room is not None and s.config != by_name(ALL)["config"].default:  # a --config besides the room
        raise ParameterError("--config", "give either --config or --room, not both")
    config = "free" if r.room is not None else s.config
    room = room_settings(r.room, absorption=absorption, source=r.source, strike=r.room_strike,
                         order=r.image_order, tolerance_db=r.tolerance_db, config=config)
    if room is not None and "order" not in room:
        try:  # a rigid surface has no finite image energy: the images that arrive within the sound
            rigid = min(float(x) for x in str(room.get("absorption", 0.0)).split(",")) == 0.0
        except ValueError:
            rigid = False  # Room names --absorption
        if rigid:
            room["duration"] = s.damper.duration
    return room, config


def _scene_of(s: AuralizeSettings, radius, medium):
    """The cavity's walls in their surroundings, the room's settings and the room's sound (None: none)."""
    from .names import ROOM_OPTIONS, user_terms
    from .wav import ROOM_SOUND_OPTIONS, cavity, least_absorbing

    rs = _room_sound_of(s)
    absorption = s.room.absorption
    if rs is not None and rs.banded:  # the least absorbing band sets the room's image order and its peaks
        absorption = ",".join(f"{x:.17g}" for x in least_absorbing(rs.band_absorption))
    room, config = _room_of(s, absorption)
    terms = {"wall_distance": "--wall-distance", "strike": "--strike", "height": "--height",
             **(ROOM_OPTIONS if room is not None else {})}
    with user_terms(terms):
        scene = cavity(config, radius, s.damper.gap, struck_wall=s.struck_wall, walls=s.walls,
                       wall_distance=s.wall_distance, strike=s.strike, height=s.height, medium=medium, room=room)
    if rs is not None:
        with user_terms({**ROOM_SOUND_OPTIONS, "order": "--image-order"}):
            rs.check_room(scene.geometry)
    return scene, room, rs


def _listeners_of(s: AuralizeSettings, scene, room):
    """The listener positions (m): the given ones, or two ears around one head with ``--stereo``."""
    from ..sound import check_listeners, ear_positions

    points = [parse_point(p, "--listener") for p in (s.listener or [DEFAULT_LISTENER])]
    if s.stereo:
        if len(points) == 1:
            spacing = check_positive("--ear-spacing", s.ear_spacing, "m")
            points = list(ear_positions(points[0], scene, spacing=spacing))
        elif len(points) != 2:
            raise ParameterError("--stereo", f"needs one head position or two --listener positions, got {len(points)}")
    if room is not None:
        scene.geometry.in_room("--listener", np.array(points))
    return check_listeners(np.array(points), scene, name="--listener")


def _check_outputs(s: AuralizeSettings, n_files: int) -> None:
    """Refuse unwritable or clashing WAV, sidecar and figure paths."""
    from .outputs import check_distinct, check_output_file

    outputs = {}
    for path in output_paths(s.wav, n_files):
        outputs[f"--wav {path}"] = check_output_file("--wav", path, "wav")
        outputs[f"--wav {path.with_suffix('.json')}"] = check_output_file("--wav", path.with_suffix(".json"), "json")
    if s.png is not None:
        outputs["--png"] = check_output_file("--png", s.png, "figure")
    check_distinct(outputs)


def _impacts_given(s: AuralizeSettings, n_listeners: int):
    """The impacts read from ``impacts`` (or None), with the sound's length checked against the budget."""
    from .budget import check_budget, wav_estimate
    from .outputs import check_input_file

    seq = None
    sound_length, length_options = s.damper.duration, ("--duration",)
    if s.impacts:
        check_input_file("--impacts", s.impacts, "CSV file")
        seq = read_impacts_csv(s.impacts)
        last = float(seq.times.max()) if len(seq) else 0.0
        if last > s.damper.duration:  # the sound lasts until the last click has died away
            sound_length, length_options = last, ("--impacts", "--duration")
    check_budget(wav_estimate(sound_length, s.rate, n_listeners, options=length_options), s.max_memory)
    return seq


def _check_run_and_levels(s: AuralizeSettings) -> None:
    """The damper to simulate (when no impacts are given), the file's scale and the levels asked for."""
    d = s.damper
    if not s.impacts:
        from ..core.limits import check_damper
        from .names import DAMPER_OPTIONS, user_terms

        with user_terms(DAMPER_OPTIONS):
            check_damper(M=d.M, K=d.K, m=d.m, gap=d.gap, k_hertz=d.k_hertz, v=d.v0, duration=d.duration, c1=d.c1)
    if s.scale is not None:
        check_positive("--scale", s.scale, "Pa")
    if s.levels_csv is not None and Path(s.levels_csv).suffix.lower() != ".csv":
        raise ParameterError("--levels-csv", f"must end in .csv, got {s.levels_csv!r}")
    if s.loudness:
        from ..levels import loudness_available

        if not loudness_available():
            raise ParameterError("--loudness", "needs mosqito: pip install 'acoustiviz[hearing]'")


def check_sound(s: AuralizeSettings):
    """Every check a run makes before any work, in the order it meets them; return the :class:`Sound` and impacts.

    The impacts are those of ``s.impacts`` (None: to be simulated).
    """
    from ..sound import ClickModel

    radius, radius_source, medium = _check_sphere_and_medium(s)
    scene, room, rs = _scene_of(s, radius, medium)
    model = ClickModel(k_hertz=s.damper.k_hertz, mass=s.damper.m, main_mass=s.damper.M, mass_model=s.mass_model,
                       pulse=s.pulse)
    listeners = _listeners_of(s, scene, room)
    _check_outputs(s, 1 if s.stereo else len(listeners))
    seq = _impacts_given(s, len(listeners))
    _check_run_and_levels(s)
    return Sound(radius, radius_source, scene, model, listeners, room, rs), seq


def _simulate(s: AuralizeSettings, echo):
    """Run the damper as ``acoustiviz damper`` would; return the impact sequence and a description."""
    from ..sound import ImpactSequence
    from .damper import damper_description, run_damper_settings

    model, run = run_damper_settings(s.damper, s.max_memory)
    for msg in run.warnings:
        echo(f"warning: {msg}")
    if not run.result.success:
        echo(f"warning: the damper solver stopped early: {run.result.message}")
    return ImpactSequence.from_table(run.result.impacts), damper_description(model, run, s.damper.duration)


def auralize(s: AuralizeSettings, echo=print) -> list:
    """Simulate (or read) the impacts, render them, write the WAVs and sidecars; ``echo`` each summary line.

    Returns
    -------
    list of pathlib.Path
        The WAV files written (each with its ``.json`` sidecar beside it).
    """
    from .damper import check_click_fits

    sound, seq = check_sound(s)
    d = s.damper
    if seq is not None:
        run_desc = {"impacts_csv": str(s.impacts), "m_kg": d.m, "M_kg": d.M, "gap_m": d.gap,
                    "k_hertz_n_m1_5": d.k_hertz}
    else:
        seq, run_desc = _simulate(s, echo)
    check_click_fits(seq, d.k_hertz, d.m, d.duration, names={"m": "--m", "k_hertz": "--k-hertz",
                                                                "duration": "--duration", "velocities": "--impacts"})
    files, _ = write_sound(s, seq, sound, run_desc, duration=d.duration, echo=echo)
    if s.png:
        _write_png(s, [f.path for f in files], [f.pressure for f in files], echo)
    return [f.path for f in files]


def write_sound(s: AuralizeSettings, seq, sound: Sound, run_desc: dict, *, duration: float, labels=None,
                paths=None, scene_name=None, echo=print, quiet: bool = False) -> tuple:
    """Render the impacts ``seq`` at the listeners of ``sound`` and write the files ``s`` asks for.

    The one application step of ``acoustiviz auralize`` and a scene's ``[outputs.wav]``: the Hertz
    pulse of each impact radiated by the rigid sphere with its image sources
    (:func:`acoustiviz.sound.render`, ``duration`` in s), the levels when ``s`` asks for
    them, and the WAV files and sidecars with one shared calibration
    (:func:`acoustiviz.app.wav.write_wav_files`).

    Parameters
    ----------
    s : AuralizeSettings
        Rate, sample format, scale, headroom, stereo and levels of the files.
    seq : acoustiviz.sound.ImpactSequence
        The impacts (times in s, walls, approach speeds in m/s).
    sound : Sound
        The checked sphere, cavity, click model and listeners (m).
    run_desc : dict
        The damper run recorded in every sidecar.
    labels : sequence of str, optional
        Listener names (default: ``listener1``, ``listener2``, ... in the order given, or ``left``/``right``).
    paths : sequence of path-like, optional
        The files (default: :func:`output_paths` of ``s.wav``).
    scene_name : str, optional
        Recorded in every sidecar.
    echo : callable
        Called with each summary line (none with ``quiet``).

    Returns
    -------
    tuple
        ``(files, written)``: the :class:`~acoustiviz.app.wav.WavFile` list and, per file, what
        :func:`~acoustiviz.app.wav.write_wav_files` returns (its record, sidecar and warnings).
    """
    from ..sound import render

    say = (lambda msg: None) if quiet else echo
    out = render(seq, sound.scene, sound.model, sound.listeners, sample_rate=s.rate, duration=duration,
                 room_sound=sound.room_sound)
    _print_sound(seq, sound, out, s.rate, say)
    files = _files(s, out, sound.listeners, labels, paths)
    with user_terms({"scale": "--scale"}):  # refused before the levels and the files, not after
        check_scale_fits(files, s.subtype, s.scale)
    per_file = _levels_per_file(s, seq, sound, files, out, duration, say)
    written = write_wav_files(files, subtype=s.subtype, scale=s.scale, headroom_db=s.headroom,
                              rendering=out, scene_name=scene_name, damper=run_desc,
                              radius_source=sound.radius_source, levels=per_file)
    _print_written(s, files, written, say)
    return files, written


def _files(s: AuralizeSettings, out, listeners, labels=None, paths=None) -> list:
    """The WAV files of a rendering: one per listener, or one stereo file of the first two listeners."""
    from ..core.listener import Listener
    from ..core.signal import Signal
    from .wav import WavFile

    p = out.pressure
    if s.stereo:
        groups = [(p[:2], listeners[:2], list(labels[:2]) if labels else ["left", "right"], ["left", "right"])]
    else:  # without labels the mono file of the i-th --listener names its channel listener<i>
        groups = [(p[i:i + 1], listeners[i:i + 1], [labels[i] if labels else f"listener{i + 1}"], ["mono"])
                  for i in range(p.shape[0])]
    paths = output_paths(s.wav, len(groups)) if paths is None else paths
    return [WavFile(path, Signal(data, s.rate), [Listener(n, q) for n, q in zip(names, pts, strict=True)], channels)
            for path, (data, pts, names, channels) in zip(paths, groups, strict=True)]


def _print_sound(seq, sound: Sound, out, rate, echo) -> None:
    """The impacts, the sound model and (in a room) its images, one line each."""
    scene, model = out.scene, sound.model
    echo(f"impacts: {len(seq)} ({seq.count(-1)} on wall -1, {seq.count(1)} on wall +1), "
         f"approach speeds {seq.velocities.min():.3g}-{seq.velocities.max():.3g} m/s" if len(seq)
         else "impacts: 0 (silence)")
    echo(f"sound: sphere radius {sound.radius * 1e3:.2f} mm ({sound.radius_source}), pulse {model.pulse}, "
         f"mass model {model.mass_model}, configuration {scene.geometry.name}, walls {scene.walls}; "
         f"{rate} Hz (computed at {out.internal_rate / 1e3:g} kHz, band-limited)")
    if sound.room is not None and out.room is not None:
        r = out.room
        neg = r["neglected_energy_db"]
        tail = (f"late tail from {r['transition_s']:.4f} s to {r['tail_end_s']:.3f} s ({r['tail_decay']}, seed "
                f"{r['tail_seed']})" if r["late_tail"] else "no late tail")
        bands = f", absorption in {len(r['absorption_bands_hz'])} bands" if "absorption_bands_hz" in r else ""
        echo(f"room: {scene.geometry.caption()}; image_order {r['image_order']}, images {r['images']}, "
             f"{tail}{bands}, neglected_energy_db " + (f"{neg:.1f}" if isinstance(neg, float) else str(neg)))
    elif sound.room is not None:
        conf = scene.geometry
        echo(f"room: {conf.caption()}; image_order {conf.image_order}, images {conf.image_count}, "
             f"neglected_energy_db {conf.neglected_energy_db:.1f}" + (" (capped by the memory budget)"
                                                                       if conf.order_capped else ""))


def _levels_per_file(s: AuralizeSettings, seq, sound: Sound, files, out, duration, echo):
    """The levels of each file when asked for (echoed, and written as ``levels_csv``), else None."""
    if not (s.levels or s.levels_csv is not None or s.loudness):
        return None
    from .levels import rendered_levels, summary_lines, write_levels_csv

    names_all = [n for f in files for n in (f.channel_names if s.stereo else f.names)]
    report = rendered_levels(seq, sound.scene, sound.model, sound.listeners, duration=duration,
                             channels=names_all, with_loudness=s.loudness, rendering=out, room_sound=sound.room_sound)
    for line in summary_lines(report, rate_note=" (computed signal, flat to 43.2 kHz)"):
        echo(line)
    groups = [[0, 1]] if s.stereo else [[i] for i in range(len(files))]
    per_file = [report.subset(g).describe() for g in groups]
    if s.levels_csv is not None:
        for path in write_levels_csv(s.levels_csv, report):
            echo(f"wrote {path}")
    return per_file


def _print_written(s: AuralizeSettings, files, written, echo) -> None:
    """Each file's warnings, peak, calibration and name."""
    for wav, w in zip(files, written, strict=True):
        for msg in w["warnings"]:
            echo(f"warning: {msg}")
        rec = w["record"]
        spls, peaks = rec["peak_spl_db_re_20upa"], rec["peak_pa"]
        lvl = ", ".join(f"{v:.1f}" if v is not None else "silent" for v in spls)
        echo(f"peak SPL: {lvl} dB re 20 uPa (peak {max(peaks):.4g} Pa)")
        if rec["subtype"] == "PCM_24":
            top = max((v for v in rec["peak_dbfs"] if v is not None), default=None)
            echo(f"calibration: {rec['scale_pa_per_full_scale']:.6g} Pa per full scale ({rec['scale_source']})"
                 + (f"; peak {top:.1f} dBFS" if top is not None else ""))
        over = rec["clipping"]["peak_over_full_scale_db"]
        if s.subtype == "FLOAT" and over > 0:
            echo(f"note: the peak is {over:.1f} dB above 1.0 = {rec['scale_pa_per_full_scale']:g} Pa; the float "
                 "file stores it exactly, but players that treat 1.0 as full scale will clip it (use --subtype "
                 "PCM_24 for listening)")
        echo(f"wrote {wav.path}")
        echo(f"wrote {w['sidecar']}")


def _write_png(s: AuralizeSettings, paths, channels, echo) -> None:
    """The waveforms of the files as one figure."""
    from ..core.signal import Signal
    from ..output.plot.audio import auralisation_figure
    from ..output.plot.style import save_figure

    if s.stereo:
        labels = [f"{Path(paths[0]).name} {side}" for side in ("left", "right")]
        signals = [Signal(c, s.rate) for c in channels[0]]
    else:
        labels = [Path(p).name for p in paths]
        signals = [Signal(c[0], s.rate) for c in channels]
    save_figure(auralisation_figure(signals, labels=labels), s.png)
    echo(f"wrote {s.png}")

