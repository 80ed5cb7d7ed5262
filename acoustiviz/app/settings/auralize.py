"""Settings of an auralised damper run: ``acoustiviz auralize`` (the damper run is :class:`DamperSettings`).

One :class:`~acoustiviz.app.settings.table.Setting` per option, grouped as ``--help`` shows them
(:data:`AURALIZE_GROUPS`); the records with a scene key are the keys of a scene's ``[outputs.wav]``.
:class:`AuralizeSettings` holds the command's values as typed and checks the ranges of
:data:`AURALIZE` once; :func:`acoustiviz.app.auralize.job_from_settings` turns them into the
:class:`AuralizeJob` (the sphere, the cavity, the listeners, the damper run or the impacts, the
files), which every front end builds and which checks everything else when it is made. Lengths
in m, times in s, pressures in Pa.
"""

from __future__ import annotations

import dataclasses

from ...constants import (
    CONFIGURATIONS,
    DEFAULT_AIR_DENSITY,
    DEFAULT_DURATION,
    DEFAULT_RTOL,
    DEFAULT_SOUND_SPEED,
    PAPER_GAP,
    PAPER_RADIUS,
    PAPER_V0,
    PULSES,
    SAMPLE_RATES,
    STRIKES,
    TABLE1_PARAMETERS,
    TAIL_SEED,
    WAV_RATE,
)
from .base import Settings, vocabulary
from .damper import BALLS, DAMPER
from .impact import IMPACT
from .room import ROOM, RoomOptions
from .table import Setting, by_name
from .vocabulary import ALIASES, DERIVED, MEMORY, OUTPUT_TABLES

__all__ = ["AURALIZE", "AURALIZE_GROUPS", "AuralizeJob", "AuralizeSettings", "DamperSettings", "DEFAULT_LISTENER",
           "AURALIZE_JOB", "ROOM_SOUND_OPTIONS", "ROOM_SOUND_SCENE_KEYS"]

#: The default listener in m: 0.7 m at 45 degrees from the paper's sphere.
DEFAULT_LISTENER = "0.495,0,0.514"

_W = "outputs.wav"
#: The records of one impact, its medium and its sphere.
_MEDIUM = by_name(IMPACT)

SOUND = (
    Setting("config", "--config", None, "str", "plane",
            "reflecting surfaces: none, the struck surface z = 0, or a wall-floor corner",
            choices=CONFIGURATIONS),
    Setting("wall_distance", "--wall-distance", None, "float", None,
            "wall-floor only: distance in m from the side wall x = -D to the sphere's centre (default 0.05)", "m"),
    Setting("strike", "--strike", None, "str", "floor",
            "wall-floor only: the struck surface; 'wall' puts the damper against the wall, striking along +x",
            choices=STRIKES),
    Setting("height", "--height", None, "float", None,
            "wall strike only: height in m of the sphere's centre above the floor (default: the radius)", "m"),
    # the sphere's records of the commands of one impact and of a scene's [sphere] (their ranges), with the
    # damper's defaults: the paper's sphere, or a solid sphere of the impact mass
    dataclasses.replace(_MEDIUM["radius"], key=None, table="", default=None,
                        doc=f"sphere radius in m (default {PAPER_RADIUS:g}, the paper's sphere, whose levels the "
                            "paper reports whatever the mass)"),
    dataclasses.replace(_MEDIUM["density"], key=None, table="", default=None,
                        doc="instead of --radius: a solid sphere of mass --m and this density (steel 7800: 10.7 mm "
                            "for 40.5 g, about 10 dB quieter)"),
    Setting("pulse", "--pulse", None, "str", "half-sine",
            "acceleration pulse per impact: the paper's peak-matched half-sine, an impulse-matched "
            "half-sine, or the exact Hertz pulse", choices=PULSES),
    Setting("mass_model", "--mass-model", None, "str", "impact",
            "mass in the Hertz pulse: the impact mass against a fixed wall (paper eq 3) or the "
            "effective mass m M/(m + M) of the two bodies", choices=("impact", "effective")),
    Setting("walls", "--walls", "walls", "str", "both",
            "both: impacts on the far wall radiate from it, axis reversed; one: every impact is "
            "heard as a strike on the struck surface (the paper's view)", choices=("both", "one"), table=_W),
    Setting("struck_wall", "--struck-wall", "struck_wall", "int", -1,
            "the damper wall lying on the struck surface z = 0; the other wall is gap + 2a further along +z",
            low=-1, high=1, choices=(-1, 1), table=_W),
    _MEDIUM["c"],  # the fluid's records: the ranges of a scene's [medium] and of the commands of one impact
    _MEDIUM["rho"],
)

ROOM_SOUND = (
    Setting("late_tail", "--late-tail", "late_tail", "bool", False,
            "images exactly only until the transition time (the mixing time, or when reflections arrive once "
            "per click), then a seeded statistical tail (noise decaying per band at Eyring's T60, from the "
            "images' level) until --tolerance-db of the energy: seconds instead of minutes for a reverberant "
            "room; the direct click and the early images stay exact", table=_W),
    Setting("tail_seed", "--tail-seed", "tail_seed", "int", None,
            f"seed of the tail's noise, an integer >= 0 (default {TAIL_SEED}: the same WAV every run)",
            low=0, high=2**63 - 1, scene_default=TAIL_SEED, table=_W),
    Setting("tail_decay", "--tail-decay", "tail_decay", "str", None,
            "the tail's decay: Eyring's T60 per band (default) or the image sum's own expected decay",
            choices=("eyring", "images"), scene_default="eyring", table=_W),
    Setting("transition", "--transition", "transition_s", "float", None,
            "with --late-tail: transition time from the start of contact (default: max(sqrt(V) ms, one "
            "reflection per contact duration))", "s", low=0.0, high=10.0, low_open=True, metavar="S", table=_W),
    Setting("absorption_bands", "--absorption-bands", "absorption_bands", "str", None,
            "absorption per octave band for the WAV instead of --absorption: comma-separated F:A (band centre "
            "F in Hz in [16, 20000], increasing; alpha A in [0, 1) on every surface) or F:A1/A2/A3/A4/A5/A6 (per "
            "surface x0,x1,y0,y1,z0 floor,z1 ceiling), e.g. 125:0.1,250:0.15,500:0.2,1000:0.25,2000:0.3,"
            "4000:0.35; the images and the tail are filtered per band, the direct click stays broadband",
            metavar="F:A,...", table=_W),
)

FILES = (
    Setting("listener", "--listener", None, "str", None,
            f"listener position in m (repeatable; default {DEFAULT_LISTENER}: 0.7 m at 45 degrees from the "
            "paper's sphere). Several listeners give OUT-1.wav, OUT-2.wav, ...", metavar="X,Y,Z"),
    Setting("stereo", "--stereo", "stereo", "bool", False,
            "one stereo file: two --listener positions (left, right), or one head position and two ears "
            "--ear-spacing apart facing the damper (no head shadow)", table=_W),
    Setting("ear_spacing", "--ear-spacing", None, "float", 0.18,
            "distance between the ears with --stereo and one listener", "m", low=0.0, low_open=True),
    Setting("rate", "--rate", "rate_hz", "int", WAV_RATE, "output sample rate in Hz", "Hz",
            low=min(SAMPLE_RATES), high=max(SAMPLE_RATES), choices=SAMPLE_RATES, table=_W),
    Setting("subtype", "--subtype", "subtype", "str", "PCM_24",
            "PCM_24: normalised 24-bit that plays without clipping, one scale (Pa per full scale) "
            "shared by all files of the run and recorded in each sidecar; FLOAT: float32 in pascals "
            "(1.0 = 1 Pa), for analysis", choices=("PCM_24", "FLOAT"), table=_W),
    Setting("scale", "--scale", None, "float", None,
            "Pa per full scale (default: the run's peak plus --headroom for PCM_24; 1 for FLOAT); a PCM_24 "
            "scale that clips is reported", "Pa", low=0.0, low_open=True, metavar="PA"),
    Setting("headroom", "--headroom", None, "float", 1.0,
            "PCM_24: the run's peak sits this far below full scale", "dB", low=0.0, high=60.0, metavar="DB"),
    Setting("wav", "--wav", None, "str", None, "output WAV (sidecar: same name, .json)", metavar="PATH"),
    Setting("png", "--png", None, "str", None, "also draw the waveform and spectrogram", metavar="PATH"),
)

LEVELS = (
    Setting("levels", "--levels", None, "bool", False,
            "print LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL and SEL(A) per listener and record them and "
            "the 1/3-octave bands in the sidecars; evaluated on the signal computed at 96 kHz, not on the file"),
    Setting("levels_csv", "--levels-csv", None, "str", None,
            "also write the levels (one row per listener) and OUT_bands.csv (implies --levels)", metavar="OUT.csv"),
    Setting("loudness", "--loudness", None, "bool", False,
            "with the levels, ISO 532-1 loudness N5/Nmax (sone) and DIN 45692 sharpness (acum); needs mosqito "
            "(pip install 'acoustiviz[hearing]')"),
)

IMPACTS = (
    Setting("impacts", "--impacts", None, "str", None,
            "render the impacts of this CSV (columns time_s,wall,approach_velocity_m_s, as written by 'acoustiviz "
            "damper --impacts-csv') instead of simulating; --m, --M, --gap and --k-hertz still describe the damper",
            metavar="CSV"),
)

#: ``(--help group title, its settings)`` in the order ``acoustiviz auralize --help`` shows them.
AURALIZE_GROUPS = (("impacts from a file", IMPACTS), ("sound model", SOUND), ("room sound (with --room)", ROOM_SOUND),
                   ("listeners and files", FILES), ("levels", LEVELS))

#: Every option of ``acoustiviz auralize`` besides the damper's and the room's.
ALL = IMPACTS + SOUND + ROOM_SOUND + FILES + LEVELS

#: :class:`~acoustiviz.sound.RoomSound` parameter -> ``acoustiviz auralize`` option, and -> ``[outputs.wav]`` key.
ROOM_SOUND_OPTIONS = vocabulary("cli", (), ALIASES["room_sound"], lookup=ROOM_SOUND)
ROOM_SOUND_SCENE_KEYS = vocabulary("scene", (), ALIASES["room_sound"], lookup=ROOM_SOUND)

#: The settings whose range :class:`AuralizeSettings` checks on its own, before any other check.
AURALIZE = tuple(s for s in ALL if s.name in ("c", "rho", "headroom"))


@dataclasses.dataclass(frozen=True)
class DamperSettings(Settings):
    """The impact damper and its run (paper eq 15; defaults Table 1 and Figure 5), shared with ``acoustiviz damper``.

    Masses in kg, stiffnesses in N/m and N/m^1.5, dashpots in N s/m, the gap in m, speeds in m/s, times in s.
    The ranges of :data:`~acoustiviz.app.settings.damper.DAMPER` are checked when the settings are made;
    the physics' limits (:func:`acoustiviz.core.limits.check_damper`) when the run is set up.
    """

    TABLE = DAMPER + BALLS

    M: float = TABLE1_PARAMETERS["M"]
    K: float = TABLE1_PARAMETERS["K"]
    C: float = TABLE1_PARAMETERS["C"]
    m: float = TABLE1_PARAMETERS["m"]
    gap: float = PAPER_GAP
    k_hertz: float = TABLE1_PARAMETERS["k_hertz"]
    c1: float = TABLE1_PARAMETERS["c1"]
    clip_tensile: bool = False
    x0: float = 0.0
    v0: float = PAPER_V0
    duration: float = DEFAULT_DURATION
    solver: str = "event"
    dt: float | None = None
    rtol: float = DEFAULT_RTOL
    balls: int = 1
    k_hertz_ball: float | None = None
    c1_ball: float | None = None
    names: dict | None = dataclasses.field(default=None, compare=False, repr=False)

    def validate(self) -> None:
        """The tolerance in the range of the solver asked for (:data:`acoustiviz.dynamics.METHODS`)."""
        from ...dynamics import solver_method

        solver_method(self.solver).check_rtol(self.rtol)


@dataclasses.dataclass(frozen=True)
class AuralizeSettings(Settings):
    """An auralised run: the damper, the room, the sound model, the listeners and the files.

    Field names are those of :data:`ALL` (the options' API names); ``impacts`` is a CSV of impacts
    to render instead of simulating, ``max_memory`` the working-memory cap in MB; ``names`` maps API names
    (the damper's too) to the options or scene keys errors name (:meth:`from_namespace`: the options).
    """

    TABLE = AURALIZE
    BUILT_FROM = DAMPER + BALLS
    wav: str = "out.wav"
    damper: DamperSettings = dataclasses.field(default_factory=DamperSettings)
    room: RoomOptions = dataclasses.field(default_factory=RoomOptions)
    impacts: str | None = None
    config: str = "plane"
    wall_distance: float | None = None
    strike: str = "floor"
    height: float | None = None
    radius: float | None = None
    density: float | None = None
    pulse: str = "half-sine"
    mass_model: str = "impact"
    walls: str = "both"
    struck_wall: int = -1
    c: float = DEFAULT_SOUND_SPEED
    rho: float = DEFAULT_AIR_DENSITY
    late_tail: bool = False
    tail_seed: int | None = None
    tail_decay: str | None = None
    transition: float | None = None
    absorption_bands: str | None = None
    listener: tuple | None = None
    stereo: bool = False
    ear_spacing: float = 0.18
    rate: int = WAV_RATE
    subtype: str = "PCM_24"
    scale: float | None = None
    headroom: float = 1.0
    png: str | None = None
    levels: bool = False
    levels_csv: str | None = None
    loudness: bool = False
    max_memory: float | None = None
    names: dict | None = dataclasses.field(default=None, compare=False, repr=False)

    @classmethod
    def from_namespace(cls, ns: dict):
        """The settings of a mapping of option destinations to values (``vars(args)``); errors name the options."""
        def pick(klass):
            fields = {f.name for f in dataclasses.fields(klass)} - {"names"}
            return {k: v for k, v in ns.items() if k in fields}

        names = cls.names_for("cli")
        values = pick(cls)
        values.pop("room", None)
        if values.get("listener") is not None:
            values["listener"] = tuple(values["listener"])
        return cls(damper=DamperSettings(**pick(DamperSettings), names=names), room=RoomOptions(**pick(RoomOptions)),
                   names=names, **values)


#: The records :class:`AuralizeJob` checks when it is made: the files' format and the levels wanted.
AURALIZE_JOB = tuple(s for s in FILES + LEVELS if s.name not in ("listener", "ear_spacing", "wav"))


def _room_sound_key(rs) -> tuple | None:
    """The values of a :class:`~acoustiviz.sound.RoomSound` (None: none), for comparing two jobs."""
    if rs is None:
        return None
    import numpy as np

    bands = None if not rs.banded else tuple(tuple(np.ravel(a).tolist()) for a in (rs.band_centres,
                                                                                   rs.band_absorption))
    return rs.late_tail, rs.seed, rs.decay, rs.transition, bands


@dataclasses.dataclass(frozen=True, eq=False)
class AuralizeJob(Settings):
    """The whole of what :func:`acoustiviz.app.auralize.run` needs: an auralised damper run and its files.

    ``acoustiviz auralize`` (:func:`acoustiviz.app.auralize.job_from_settings`), a scene's
    ``[outputs.wav]`` (:func:`acoustiviz.app.scene_wav.wav_settings`) and Python callers build it;
    the ranges of :data:`AURALIZE_JOB` are checked when it is made, then :meth:`validate` makes every other
    check before any work. Lengths in m, times in s, pressures in Pa.

    Attributes
    ----------
    model : acoustiviz.dynamics.DamperModel
        The damper (masses in kg, stiffness in N/m^1.5, gap in m): it sets the clicks and the record.
    cavity : acoustiviz.sound.CavityScene
        The cavity's walls in their surroundings (a configuration or a room), the medium.
    click : acoustiviz.sound.ClickModel
        The Hertz pulse of each impact.
    listeners : tuple of Listener
        Who hears each channel (name, position in m): one file each, or the two channels of ``stereo``.
    wav_files : tuple of str
        The WAV files (each with its ``.json`` sidecar): one per listener, one with ``stereo``; empty:
        none (the checks of a scene's settings before its run folder exists).
    duration : float
        Length of the sound in s (at least: the sound lasts until the last click has died away).
    damper : acoustiviz.app.settings.damper_job.DamperJob, optional
        The damper run to simulate; or
    impacts : acoustiviz.sound.ImpactSequence, optional
        The impacts to render (read from ``impacts_csv``, recorded in the sidecars).
    room_sound : acoustiviz.sound.RoomSound, optional
        In a room: the late tail and the absorption bands.
    stereo, rate, subtype, scale, headroom, png, levels, levels_csv, loudness
        As the records of :data:`AURALIZE_JOB` say (rate in Hz, scale in Pa per full scale, headroom in dB).
    max_memory_mb : float, optional
        Cap in MB on the working memory.
    radius_source, scene_name : str
        Where the sphere's radius came from and the scene that asked, recorded in each sidecar.
    names : dict
        API parameter -> the option or scene key named in errors.

    Two jobs are equal when they render the same impacts or damper run into the same files with the
    same settings; the sidecars' descriptions and the vocabulary of errors are left out.
    """

    TABLE = AURALIZE_JOB
    # every option of the command (the room's sound, the damper), the memory cap and the files
    BUILT_FROM = (*ALL, *DAMPER, *BALLS, *MEMORY)
    ALIASES = {**ALIASES["damper"], **ALIASES["room_sound"], "wav_files": "wav", "order": "image_order",
               "velocities": "impacts"}
    LOOKUP = ROOM  # the room's image order
    DERIVED_NAMES = {"cli": {"listeners": DERIVED["cli"]["listeners"]},
                     "scene": {"listeners": DERIVED["scene"]["listeners"], **OUTPUT_TABLES["wav"]}}
    #: The fields compared by :meth:`__eq__` (the room's sound by its values).
    _COMPARED = ("model", "cavity", "click", "listeners", "wav_files", "duration", "damper", "impacts", "impacts_csv",
                 "stereo", "rate", "subtype", "scale", "headroom", "png", "levels", "levels_csv", "loudness",
                 "max_memory_mb")

    model: object
    cavity: object
    click: object
    listeners: tuple
    wav_files: tuple = ()
    duration: float = DEFAULT_DURATION
    damper: object = None
    impacts: object = None
    impacts_csv: str | None = None
    room_sound: object = None
    stereo: bool = False
    rate: int = WAV_RATE
    subtype: str = "PCM_24"
    scale: float | None = None
    headroom: float = 1.0
    png: str | None = None
    levels: bool = False
    levels_csv: str | None = None
    loudness: bool = False
    max_memory_mb: float | None = None
    radius_source: str = ""
    scene_name: str | None = None
    names: dict = dataclasses.field(default_factory=dict, repr=False)

    def __eq__(self, other):
        if not isinstance(other, AuralizeJob):
            return NotImplemented
        return (all(getattr(self, k) == getattr(other, k) for k in self._COMPARED)
                and _room_sound_key(self.room_sound) == _room_sound_key(other.room_sound))

    __hash__ = None

    #: The fields that make the sound itself (not its files, format or levels), compared by :meth:`same_sound`.
    _SOUND = ("model", "cavity", "click", "listeners", "duration", "damper", "impacts", "impacts_csv", "stereo",
              "rate", "max_memory_mb")

    def same_sound(self, other) -> bool:
        """Whether ``other`` renders the same sound at the same listeners and rate, whatever files it writes."""
        return (isinstance(other, AuralizeJob) and all(getattr(self, k) == getattr(other, k) for k in self._SOUND)
                and _room_sound_key(self.room_sound) == _room_sound_key(other.room_sound))

    @property
    def wants_levels(self) -> bool:
        """Whether the levels are computed (printed, recorded in the sidecars, written as ``levels_csv``)."""
        return self.levels or self.levels_csv is not None or self.loudness

    def name(self, key: str) -> str:
        """The user's name of setting ``key`` (the API name when the front end gave none)."""
        return self.names.get(key, key)

    def validate(self) -> None:
        """The run, the room's sound, the listeners, the files, the memory and the levels, in that order."""
        import numpy as np

        from ...errors import ParameterError, user_terms
        from ...sound import ImpactSequence

        object.__setattr__(self, "listeners", tuple(self.listeners))
        object.__setattr__(self, "wav_files", tuple(str(p) for p in self.wav_files))
        if (self.damper is None) == (self.impacts is None):
            raise ParameterError(self.name("impacts"), "give either the damper run to simulate or the impacts to "
                                                       "render, not both or neither")
        if self.impacts is not None and not isinstance(self.impacts, ImpactSequence):
            raise ParameterError(self.name("impacts"), f"expected an ImpactSequence, got {type(self.impacts).__name__}")
        geometry = self.cavity.geometry
        if self.room_sound is not None:
            with user_terms({k: self.name(k) for k in (*ROOM_SOUND_OPTIONS, "order")}):
                self.room_sound.check_room(geometry)
        points = np.array([lst.position for lst in self.listeners], dtype=float).reshape(-1, 3)
        if self.stereo and len(points) != 2:
            raise ParameterError(self.name("stereo"), f"needs two listeners (left, right), got {len(points)}")
        self.check_listeners(points)
        self._check_files()
        self._check_budget()
        self._check_levels()

    def check_listeners(self, points) -> None:
        """Listeners ``(n, 3)`` in m in the fluid, outside the cavity; several balls: outside every column placed.

        Several balls in a room are heard with every image to the room's tolerance: a late tail or
        absorption bands are refused, naming their option or key.
        """
        from ...sound import check_listeners

        geometry = self.cavity.geometry
        if getattr(geometry, "enclosed", False):
            geometry.in_room(self.name("listeners"), points)
        if self.damper is None or self.damper.total_balls() == 1:
            check_listeners(points, self.cavity, name=self.name("listeners"))
            return
        from ...errors import ParameterError
        from ...sound.balls_sound import check_ball_scene
        from ..damper import balls_model, cavity_positions

        if self.room_sound is not None:
            key = "late_tail" if self.room_sound.late_tail else "absorption_bands"
            raise ParameterError(self.name(key), f"several balls ({self.damper.total_balls()}) in a room are heard "
                                                 "with every image to the room's tolerance: no late tail and no "
                                                 "absorption bands")
        where = self.damper.names.get("cavities", "cavities")
        field = "position" if where == "cavities" else "position_m"
        check_ball_scene(balls_model(self.damper), self.cavity, points, cavity_positions(self.damper),
                         name=self.name("listeners"), positions_name=f"{where}[{{k}}].{field}")

    def _check_files(self) -> None:
        """WAV files (and sidecars), figure and levels CSVs writable and distinct; one WAV per file the run makes."""
        from pathlib import Path

        from ...errors import ParameterError
        from ..levels import bands_path
        from ..outputs import check_distinct, check_output_file

        option = self.name("wav_files")
        n = 1 if self.stereo else len(self.listeners)
        if self.wav_files and len(self.wav_files) != n:
            raise ParameterError(option, f"{n} file(s) for {len(self.listeners)} listener(s), got "
                                         f"{len(self.wav_files)}")
        outputs = {}
        for path in map(Path, self.wav_files):
            if path.suffix.lower() != ".wav":
                raise ParameterError(option, f"must end in .wav, got {str(path)!r}")
            outputs[f"{option} {path}"] = check_output_file(option, path, "wav")
            outputs[f"{option} {path.with_suffix('.json')}"] = check_output_file(option, path.with_suffix(".json"),
                                                                                 "json")
        if self.png is not None:
            outputs[self.name("png")] = check_output_file(self.name("png"), self.png, "figure")
        if self.levels_csv is not None:
            option = self.name("levels_csv")
            if Path(self.levels_csv).suffix.lower() != ".csv":
                raise ParameterError(option, f"must end in .csv, got {self.levels_csv!r}")
            outputs[option] = check_output_file(option, self.levels_csv, "csv")
            outputs[f"{option} (bands)"] = check_output_file(option, bands_path(self.levels_csv), "csv")
        check_distinct(outputs)

    def _check_budget(self) -> None:
        """The sound at the file's rate within the memory cap (it lasts until the last impact given, if later)."""
        from ..budget import check_budget, wav_estimate

        length, options = self.duration, (self.name("duration"),)
        if self.impacts is not None and len(self.impacts):
            last = float(self.impacts.times.max())
            if last > self.duration:  # the sound lasts until the last click has died away
                length, options = last, (self.name("impacts"), self.name("duration"))
        check_budget(wav_estimate(length, self.rate, len(self.listeners), options=options), self.max_memory_mb,
                     cap_name=self.name("max_memory_mb"))

    def _check_levels(self) -> None:
        from ...errors import ParameterError

        if self.loudness:
            from ...levels import loudness_available

            if not loudness_available():
                raise ParameterError(self.name("loudness"), "needs mosqito: pip install 'acoustiviz[hearing]'")
