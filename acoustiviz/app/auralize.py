"""The auralize job: a damper run (or impacts read from a CSV) heard at listeners, as calibrated WAV files.

Three parts, shared by ``acoustiviz auralize``, a scene's ``[outputs.wav]`` and Python callers:

* :class:`~acoustiviz.app.settings.auralize.AuralizeJob`, the settings, checked once when made
  (:func:`job_from_settings` builds it from the command's options, errors naming them);
* :func:`run`, which simulates the damper (paper eq 15) or takes the impacts given, renders the Hertz
  pulse of each impact with rigid-sphere radiation and image sources (:func:`acoustiviz.sound.render`)
  and, when asked, evaluates the levels with the levels job (:func:`acoustiviz.app.levels.run`),
  returning an :class:`AuralizeResult` (no files, no printing);
* :meth:`AuralizeResult.write`, which writes the levels CSVs, the WAV files with their sidecars
  (:func:`acoustiviz.app.wav.write_wav_files`) and the figure, and returns their paths.

Lengths in m, times in s, pressures in Pa.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from .._validate import check_finite, check_positive, check_range
from ..core.listener import Listener
from ..errors import ParameterError
from .names import user_terms
from .settings.auralize import ALL, DEFAULT_LISTENER, AuralizeJob, AuralizeSettings
from .settings.parse import parse_point
from .settings.table import by_name
from .wav import check_scale_fits, write_wav_files

#: Every auralize setting by its API name: the ranges checked here are the table's.
_TABLE = by_name(ALL)

__all__ = ["AuralizeJob", "AuralizeResult", "run", "job_from_settings", "read_impacts_csv", "output_paths",
           "AURALIZE_OPTIONS"]


#: The options of ``acoustiviz auralize`` by API name: what a job built from them names in its errors.
AURALIZE_OPTIONS = AuralizeJob.names_for("cli")


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


def _cavity_of(s: AuralizeSettings, radius, medium):
    """The cavity's walls in their surroundings and the room's sound (None: none)."""
    from .names import ROOM_OPTIONS
    from .wav import cavity, least_absorbing

    rs = _room_sound_of(s)
    absorption = s.room.absorption
    if rs is not None and rs.banded:  # the least absorbing band sets the room's image order and its peaks
        absorption = ",".join(f"{x:.17g}" for x in least_absorbing(rs.band_absorption))
    room, config = _room_of(s, absorption)
    terms = {**{k: AURALIZE_OPTIONS[k] for k in ("wall_distance", "strike", "height")},
             **(ROOM_OPTIONS if room is not None else {})}
    with user_terms(terms):
        scene = cavity(config, radius, s.damper.gap, struck_wall=s.struck_wall, walls=s.walls,
                       wall_distance=s.wall_distance, strike=s.strike, height=s.height, medium=medium, room=room)
    return scene, rs


def _listeners_of(s: AuralizeSettings, scene) -> tuple:
    """The listeners: the given positions (m), or two ears around one head with ``--stereo``."""
    from ..sound import ear_positions

    points = [parse_point(p, "--listener") for p in (s.listener or [DEFAULT_LISTENER])]
    if s.stereo:
        if len(points) == 1:
            spacing = check_positive("--ear-spacing", s.ear_spacing, "m")
            points = list(ear_positions(points[0], scene, spacing=spacing))
        elif len(points) != 2:
            raise ParameterError("--stereo", f"needs one head position or two --listener positions, got {len(points)}")
        return tuple(Listener(side, p) for side, p in zip(("left", "right"), points, strict=True))
    # the mono file of the i-th --listener names its channel listener<i>
    return tuple(Listener(f"listener{i + 1}", p) for i, p in enumerate(points))


def _run_of(s: AuralizeSettings) -> tuple:
    """``(model, damper job, impacts)``: the damper, and its run to simulate or the impacts of ``--impacts``."""
    from ..dynamics import InitialState
    from .damper import DamperJob, damper_model
    from .names import DAMPER_OPTIONS, MEMORY, vocabulary
    from .outputs import check_input_file
    from .settings.damper import BALLS

    d = s.damper
    names = {**DAMPER_OPTIONS, **vocabulary("cli", MEMORY + BALLS)}
    with user_terms(names):
        model = damper_model(M=d.M, K=d.K, C=d.C, m=d.m, gap=d.gap, k_hertz=d.k_hertz, c1=d.c1,
                             clip_tensile=bool(d.clip_tensile))
        if s.impacts:
            if d.balls > 1:
                raise ParameterError("--balls", f"several balls ({d.balls}) need a simulated run, not --impacts")
            check_input_file("--impacts", s.impacts, "CSV file")
            return model, None, read_impacts_csv(s.impacts)
        job = DamperJob(model, InitialState(x=d.x0, v=check_finite("v", d.v0)), d.duration, d.solver, d.rtol, d.dt,
                        s.max_memory, names=names, balls=d.balls, k_hertz_ball=d.k_hertz_ball, c1_ball=d.c1_ball)
    return model, job, None


def job_from_settings(s: AuralizeSettings) -> AuralizeJob:
    """The :class:`~acoustiviz.app.settings.auralize.AuralizeJob` of ``acoustiviz auralize``'s options.

    The sphere (``--radius``, or ``--density`` and the impact mass), the cavity in its configuration
    or room, the room's sound, the listeners (two ears with ``--stereo`` and one head), the damper
    run to simulate or the impacts of ``--impacts``, then every check of the job; errors name the options.
    """
    from ..sound import ClickModel

    radius, radius_source, medium = _check_sphere_and_medium(s)
    scene, rs = _cavity_of(s, radius, medium)
    click = ClickModel(k_hertz=s.damper.k_hertz, mass=s.damper.m, main_mass=s.damper.M, mass_model=s.mass_model,
                       pulse=s.pulse)
    listeners = _listeners_of(s, scene)
    if Path(s.wav).suffix.lower() != ".wav":  # before the impacts are read and the damper is checked
        raise ParameterError("--wav", f"must end in .wav, got {s.wav!r}")
    model, damper, impacts = _run_of(s)
    files = output_paths(s.wav, 1 if s.stereo else len(listeners))
    return AuralizeJob(model, scene, click, listeners, tuple(str(p) for p in files), s.damper.duration, damper,
                       impacts, s.impacts, rs, stereo=s.stereo, rate=s.rate, subtype=s.subtype, scale=s.scale,
                       headroom=s.headroom, png=s.png, levels=s.levels, levels_csv=s.levels_csv, loudness=s.loudness,
                       max_memory_mb=s.max_memory, radius_source=radius_source, names=AURALIZE_OPTIONS)


@dataclasses.dataclass(frozen=True, eq=False)
class AuralizeResult:
    """The sound of an :class:`~acoustiviz.app.settings.auralize.AuralizeJob`, ready to write.

    Attributes
    ----------
    settings : AuralizeJob
        What was run.
    sequence : acoustiviz.sound.ImpactSequence
        The impacts heard (times in s, walls, approach speeds in m/s).
    rendering : acoustiviz.sound.Rendering
        The sound at every listener at the job's rate (Pa).
    files : tuple of acoustiviz.app.wav.WavFile
        One per file: its name, its calibrated :class:`~acoustiviz.core.signal.Signal` (Pa) and its listeners.
    record : dict
        The damper run (or the impacts file) recorded in every sidecar.
    damper : acoustiviz.app.damper.DamperResult or None
        The damper run simulated (None: the impacts were given).
    levels : acoustiviz.app.levels.LevelsResult or None
        The levels of every channel, evaluated by the levels job on the sound computed at 96 kHz.
    written : list of dict
        Filled by :meth:`write`: per WAV file, its sidecar ``record``, the ``sidecar`` path and any ``warnings``.
    """

    settings: AuralizeJob
    sequence: object
    rendering: object
    files: tuple
    record: dict
    damper: object = None
    levels: object = None
    written: list = dataclasses.field(default_factory=list)

    @property
    def collisions(self) -> dict:
        """The collisions of the run heard: ``impacts`` every one; with several balls ``ball_wall`` and ``ball_ball``.

        One ball (or impacts given): the impacts heard. Several balls: every row of the run's impact
        table, those of a ball on a wall (the sequence) and those of two balls.
        """
        heard = len(self.sequence)
        if self.damper is None or self.settings.damper.total_balls() == 1:
            return {"impacts": heard}
        total = len(self.damper.result.impacts)
        return {"impacts": total, "ball_wall": heard, "ball_ball": total - heard}

    @property
    def file_levels(self) -> list | None:
        """Per file, the levels of its channels as its sidecar records them (None: no levels asked for)."""
        if self.levels is None:
            return None
        groups = [[0, 1]] if self.settings.stereo else [[i] for i in range(len(self.files))]
        return [self.levels.report.subset(g).describe() for g in groups]

    def write(self, folder=None) -> list:
        """Write the files the job asks for into ``folder``; return their paths.

        The levels CSV and its ``_bands.csv`` (:meth:`acoustiviz.app.levels.LevelsResult.write`), each WAV
        file and its sidecar with one shared calibration (:func:`acoustiviz.app.wav.write_wav_files`), and the
        waveforms' figure, in that order, each atomically. ``folder``: where relative file names are put
        (default: as given, the current folder).
        """
        from .wav import WavFile

        s, paths = self.settings, []

        def where(name):
            return Path(name) if folder is None else Path(folder) / name

        if self.levels is not None and s.levels_csv is not None:
            paths += self.levels.write(folder)
        if s.wav_files:
            wavs = [WavFile(where(f.path), f.signal, f.listeners, f.channel_names) for f in self.files]
            written = write_wav_files(wavs, subtype=s.subtype, scale=s.scale, headroom_db=s.headroom,
                                      rendering=self.rendering, scene_name=s.scene_name, damper=self.record,
                                      radius_source=s.radius_source, levels=self.file_levels)
            self.written[:] = written
            for wav, w in zip(wavs, written, strict=True):
                paths += [wav.path, Path(w["sidecar"])]
        if s.png is not None:
            paths.append(Path(self._figure(where(s.png))))
        return paths

    def _figure(self, path):
        """The waveforms of the files as one figure."""
        from ..core.signal import Signal
        from ..output.plot.audio import auralisation_figure
        from ..output.plot.style import save_figure

        if self.settings.stereo:
            (f,) = self.files
            labels = [f"{Path(f.path).name} {side}" for side in f.channel_names]
        else:
            labels = [Path(f.path).name for f in self.files]
        signals = [Signal(row, f.signal.sample_rate) for f in self.files for row in f.pressure]
        return save_figure(auralisation_figure(signals, labels=labels), path)


def _files(job: AuralizeJob, rendering) -> tuple:
    """The files of a rendering: one per listener, or one stereo file of the two listeners."""
    from ..core.signal import Signal
    from .wav import WavFile

    p, rate = rendering.pressure, job.rate
    if job.stereo:
        groups = [(p, list(job.listeners), ["left", "right"])]
    else:
        groups = [(p[i:i + 1], [lst], ["mono"]) for i, lst in enumerate(job.listeners)]
    paths = job.wav_files or [f"{lsts[0].name}.wav" for _, lsts, _ in groups]
    return tuple(WavFile(path, Signal(data, rate), lsts, channels)
                 for path, (data, lsts, channels) in zip(paths, groups, strict=True))


def _impacts(job: AuralizeJob, damper) -> tuple:
    """``(sequence, sidecar record, damper run)``: the impacts given, or those of the damper run (simulated once)."""
    from .damper import damper_description, heard_sequence
    from .damper import run as run_damper

    if job.impacts is not None:
        m = job.model
        return job.impacts, {"impacts_csv": job.impacts_csv, "m_kg": m.m, "M_kg": m.M, "gap_m": m.gap,
                             "k_hertz_n_m1_5": m.k_hertz}, None
    damper = run_damper(job.damper) if damper is None else damper
    record = damper_description(job.model, damper, job.duration)
    if job.damper.total_balls() > 1:
        record["balls"] = job.damper.total_balls()
    if job.damper.cavities:
        record["cavities"] = len(job.damper.cavities)
    return heard_sequence(damper.result), record, damper


def _levels(job: AuralizeJob, seq, rendering, files, damper=None):
    """The levels job's result on the sound computed at 96 kHz (None when no levels are asked for)."""
    if not job.wants_levels:
        return None
    from .damper import cavity_positions, render_run
    from .levels import ANALYSIS_RATE
    from .levels import run as run_levels
    from .settings.levels import LevelsJob

    if rendering.sample_rate != ANALYSIS_RATE:
        points = np.array([lst.position for lst in job.listeners], dtype=float)
        rendering = render_run(damper.result if damper is not None else None, seq, job.cavity, job.click, points,
                               sample_rate=ANALYSIS_RATE, duration=job.duration, room_sound=job.room_sound,
                               positions=cavity_positions(job.damper))
    channels = [n for f in files for n in (f.channel_names if job.stereo else f.names)]
    names = {"csv": job.name("levels_csv"), "loudness": job.name("loudness"), "signal": "damper", "input": "damper"}
    return run_levels(LevelsJob(rendering.signal, tuple(channels), loudness=job.loudness, csv=job.levels_csv,
                                what="the damper run", names=names))


def run(job: AuralizeJob, *, damper=None) -> AuralizeResult:
    """Simulate (or take) the impacts, render them at the listeners and evaluate the levels asked for.

    Physics only: no file is written and nothing printed.

    Parameters
    ----------
    job : AuralizeJob
        The job, checked when it was made.
    damper : acoustiviz.app.damper.DamperResult, optional
        The run of ``job.damper`` already simulated (a scene's one damper run), used instead of simulating again.

    Returns
    -------
    AuralizeResult
    """
    from .damper import cavity_positions, check_click_fits, render_run

    seq, record, damper = _impacts(job, damper)
    check_click_fits(seq, job.model.k_hertz, job.model.m, job.duration,
                     names={k: job.name(k) for k in ("m", "k_hertz", "duration", "velocities")})
    points = np.array([lst.position for lst in job.listeners], dtype=float)
    rendering = render_run(damper.result if damper is not None else None, seq, job.cavity, job.click, points,
                           sample_rate=job.rate, duration=job.duration, room_sound=job.room_sound,
                           positions=cavity_positions(job.damper))
    files = _files(job, rendering)
    with user_terms({"scale": job.name("scale")}):  # refused before the levels and the files, not after
        check_scale_fits(files, job.subtype, job.scale)
    return AuralizeResult(job, seq, rendering, files, record, damper, _levels(job, seq, rendering, files, damper))
