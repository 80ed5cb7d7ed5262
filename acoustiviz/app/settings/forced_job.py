"""The settings of the forced job: the damper, its excitation, how its attractors are found, their noise, the files.

:class:`ForcedJob` is the whole of what :func:`acoustiviz.app.forced.run` needs, checked once when it is
made (the records' ranges of :mod:`acoustiviz.app.settings.forced`, the forcing frequencies against the
damper, the solver's settings, the executor, the listener in the cavity's surroundings, the memory
budget and the files to write), so ``acoustiviz forced``, a scene's ``[outputs.frequency_response]``,
``[outputs.bifurcation]`` and ``[outputs.operating_noise]`` and a Python caller build the same object
and hand it to the same run.
"""

from __future__ import annotations

import dataclasses

from ...constants import FORCED_MAX_CYCLES, FORCED_RTOL, FORCED_STARTS, FORCED_TOLERANCE, PAPER_RADIUS
from ...errors import ParameterError
from .base import Settings, vocabulary
from .damper import BALL_START, BALLS, CONTACT_LAW, DAMPER, MODEL
from .forced import (
    AMPLITUDE,
    AMPLITUDES,
    EXCITATION_KIND,
    FORCED,
    FORCED_EXECUTION,
    FORCED_OUTPUTS,
    FREQUENCIES,
    NOISE,
    NOISE_LISTENER,
)
from .impact import IMPACT, WAVEFORM
from .room import ROOM
from .table import check_values
from .vocabulary import ALIASES, DERIVED, MEMORY

__all__ = ["FORCED_FILE_KINDS", "ForcedJob"]

#: Each file of the job -> the kind of file :func:`acoustiviz.app.outputs.check_output_file` expects
#: (``response_png``, ``bifurcation_png`` and ``noise_csv`` are a scene's: no option names them).
FORCED_FILE_KINDS = {"wav": "wav", "noise_csv": "csv", "csv": "csv", "png": "figure", "response_png": "figure",
              "bifurcation_png": "figure"}
#: The files that hold the noise in operation.
_NOISE_FILES = ("wav", "noise_csv")


@dataclasses.dataclass(frozen=True)
class ForcedJob(Settings):
    """The damper under harmonic excitation over a list of frequencies, its noise in operation and its files.

    Attributes
    ----------
    model : acoustiviz.dynamics.DamperModel, optional
        The damper (paper eq 15): masses in kg, stiffnesses in N/m and N/m^1.5, dashpots in N s/m, the gap
        in m; default the paper's Table 1 with d = 4 cm.
    frequencies : tuple of float, optional
        Forcing frequencies in Hz, stored sorted (default :data:`~acoustiviz.app.settings.forced.FREQUENCIES`'s).
    kind : {"force", "base"}
        A harmonic force on the main mass or a harmonic base displacement.
    amplitude : float
        F0 in N (``kind="force"``) or B in m (``kind="base"``).
    sweep, solver, starts, tolerance, rtol, max_cycles
        How the attractors of each frequency are found (:func:`acoustiviz.dynamics.forced.attractor_response`;
        ``tolerance`` in m and m/s).
    restitution : float, optional
        Impact-map restitution in (0, 1] (None: the compliant contact's at each speed).
    workers : int
        Local processes running the frequencies of each round.
    executor : str
        ``"process"`` (local, ``workers``) or ``"dask://HOST:PORT"``.
    noise : bool
        Whether the noise in operation (the level columns, its table and WAV) is computed.
    listener : (3,) tuple of float, optional
        The listener in m (None: the paper's, 0.7 m at 45 degrees above the plane; required in a room).
    noise_seconds : float
        Least length in s of each level interval (whole periods).
    config : str
        The cavity's surroundings (:data:`acoustiviz.core.geometry.GEOMETRIES`), ``radius`` the radiating
        sphere's radius in m and ``surroundings`` their settings (:func:`acoustiviz.app.wav.cavity`:
        ``{"room": settings}`` in a room, ``{}`` on the paper's plane).
    max_memory_mb : float, optional
        Cap in MB on the working memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).
    wav, csv, png : str, optional
        The WAV of the frequencies in turn (with its JSON sidecar), the table and the three-panel figure.
    noise_csv, response_png, bifurcation_png : str, optional
        A scene's level table, frequency-response figure and bifurcation diagram.
    balls, k_hertz_ball, c1_ball, cavities, ball_material
        Several balls, as :class:`~acoustiviz.app.settings.damper_job.DamperJob`'s (the same records): more
        than one ball or any cavity runs the multi-ball attractors (:mod:`acoustiviz.dynamics.balls_forced`:
        the event solver, no shooting), their noise in operation from every collision
        (:func:`acoustiviz.sound.balls_operating.balls_operating_noise`).
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name (not compared).
    """

    # the balls' material as the damper job's; their start is not the forced run's (it has its own starts)
    TABLE = (EXCITATION_KIND, *FORCED, *FORCED_EXECUTION, NOISE, *FORCED_OUTPUTS, *BALLS, BALL_START[2])
    # the model, the room (a scene's configuration), the frequencies, the amplitude, the listener, the memory cap
    BUILT_FROM = (*DAMPER, *ROOM, FREQUENCIES, AMPLITUDE, NOISE_LISTENER, *MEMORY)
    # the duration is the damper run's, not a room's window; the sound speed is not a setting of the job
    ALIASES = {**ALIASES["damper"], "frequency": FREQUENCIES.name,
               **{k: v for k, v in ALIASES["room"].items() if k not in ("duration", "sound_speed")}}
    LOOKUP = WAVEFORM + IMPACT
    # the first of the scene's listeners; the cavities are a scene's table; the noise its output table
    DERIVED_NAMES = {"scene": {"listener": DERIVED["scene"]["listeners"], "cavities": "damper.cavities",
                               "noise": "outputs.operating_noise"}}
    model: object = None
    frequencies: tuple | None = None
    kind: str = EXCITATION_KIND.default
    amplitude: float = AMPLITUDE.default
    sweep: str = "up"
    solver: str = "event"
    starts: int = FORCED_STARTS
    tolerance: float = FORCED_TOLERANCE
    rtol: float = FORCED_RTOL
    max_cycles: int = FORCED_MAX_CYCLES
    noise_seconds: float = 1.0
    restitution: float | None = None
    workers: int = 1
    executor: str = "process"
    noise: bool = True
    listener: tuple | None = None
    config: str = "plane"
    radius: float = PAPER_RADIUS
    surroundings: dict = dataclasses.field(default_factory=dict)
    max_memory_mb: float | None = None
    wav: str | None = None
    csv: str | None = None
    png: str | None = None
    noise_csv: str | None = None
    response_png: str | None = None
    bifurcation_png: str | None = None
    balls: int = 1
    k_hertz_ball: float | None = None
    c1_ball: float | None = None
    cavities: tuple = ()
    ball_material: str = BALL_START[2].default
    names: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)

    @classmethod
    def names_for(cls, front: str, kind: str = "force") -> dict:
        """The job's vocabulary (:meth:`Settings.names_for`), its ``amplitude`` named as ``kind``'s option.

        A scene names the amplitude ``excitation.amplitude`` whatever the kind, and the configuration by its kind.
        """
        from .scene import CONFIGURATION_KEYS  # its records import the geometries: not on the way to --help

        amplitude = vocabulary(front, (), {"amplitude": AMPLITUDES[kind].name}, lookup=tuple(AMPLITUDES.values()))
        return {**vocabulary(front, CONFIGURATION_KEYS[:1]), **super().names_for(front), **amplitude}

    def files(self) -> dict:
        """``{field: path}`` of the files asked for (strings), in the order they are written."""
        return {key: getattr(self, key) for key in FORCED_FILE_KINDS if getattr(self, key) is not None}

    @property
    def several_balls(self) -> bool:
        """Whether the damper has more than one ball or several cavities (the multi-ball attractors)."""
        return self.balls > 1 or bool(self.cavities)

    def ball_model(self):
        """The :class:`~acoustiviz.dynamics.MultiBallModel` of the balls (:func:`acoustiviz.app.damper.balls_model`)."""
        from ..damper import balls_model

        return balls_model(self)

    @property
    def in_room(self) -> bool:
        """Whether the cavity's surroundings close the fluid (a room)."""
        from ...core.geometry import geometry_class

        return geometry_class(self.config).enclosed

    def validate(self) -> None:
        """The frequencies, the amplitude, the files, the damper, the solver, the listener and the memory."""
        from ...dynamics import DamperModel

        if self.model is None:
            from ..damper import damper_model

            object.__setattr__(self, "model", damper_model())
        if not isinstance(self.model, DamperModel):
            raise ParameterError("model", f"expected a DamperModel, got {type(self.model).__name__}")
        self._check_frequencies()
        unit = AMPLITUDES[self.kind].unit  # the range of the scene's key in the kind's unit
        object.__setattr__(self, "amplitude", dataclasses.replace(AMPLITUDE, unit=unit).check(self.amplitude))
        self._check_files()
        self._check_listener()
        self._check_damper()
        self._check_balls()
        self._check_budget()
        if self.noise or self.listener is not None:
            from ..damper import cavity_positions
            from ..forced_noise import check_listener

            cavities = self.names.get("cavities", "cavities")
            check_listener(self.ball_model() if self.several_balls else self.model, self.listener_position,
                           config=self.config, radius=self.radius, name=self.names.get("listener", "listener"),
                           settings=self.surroundings, positions=cavity_positions(self),
                           positions_name=f"{cavities}[{{k}}].position_m")

    @property
    def listener_position(self):
        """The listener in m as a (3,) array, None for the paper's."""
        import numpy as np  # not imported by --help

        return None if self.listener is None else np.array(self.listener, dtype=float)

    def _check_frequencies(self) -> None:
        from .parse import check_frequencies, parse_frequencies

        if self.frequencies is None:
            f = parse_frequencies(FREQUENCIES.default, "frequencies")
        else:
            f = check_frequencies(self.frequencies, "frequencies")
        object.__setattr__(self, "frequencies", tuple(float(v) for v in f))

    def _check_files(self) -> None:
        from ...output.audio.wav import sidecar_path
        from ..outputs import check_distinct, check_output_file

        paths = {}
        for key, path in self.files().items():
            name = self.names.get(key, key)
            paths[f"{name} ({key})"] = check_output_file(name, path, FORCED_FILE_KINDS[key])
            if key == "wav":
                paths[f"{name} (sidecar)"] = check_output_file(name, sidecar_path(path), "json")
        check_distinct(paths)
        noise = self.names.get("noise", "noise")
        off = f"--no-{noise[2:]}" if noise.startswith("--") else f"{noise} = False"
        for key in _NOISE_FILES:
            if getattr(self, key) is not None and not self.noise:
                raise ParameterError(key, f"needs the noise in operation: drop {off}")

    def _check_listener(self) -> None:
        if self.listener is not None:
            import numpy as np  # not imported by --help

            point = np.asarray(self.listener, dtype=float)
            if point.shape != (3,) or not np.all(np.isfinite(point)):
                raise ParameterError("listener", f"expected three finite coordinates X,Y,Z in m, got {self.listener!r}")
            object.__setattr__(self, "listener", tuple(float(v) for v in point))
        elif self.in_room:
            raise ParameterError("listener", f"required with {self.names.get('dimensions', 'a room')}: the listener's "
                                             "position X,Y,Z in m in the room")

    def _check_damper(self) -> None:
        from ...core.limits import check_forcing_frequencies
        from ...dynamics.forced import Excitation, check_settings
        from ...sweep.execute import check_executor_form

        model = self.model
        check_values({s.name: getattr(model, s.name) for s in MODEL + CONTACT_LAW}, MODEL + CONTACT_LAW)
        check_forcing_frequencies(self.frequencies, M=model.M, K=model.K)
        excitations = [Excitation(f, self.amplitude, self.kind) for f in self.frequencies]
        check_settings(model, excitations[0], solver=self.solver, restitution=self.restitution,
                       tolerance=self.tolerance, rtol=self.rtol, starts=self.starts, max_cycles=self.max_cycles)
        for ex in excitations[1:]:
            ex.linear_response(model)  # refuses an undamped resonance
        check_executor_form(self.executor)

    def _check_balls(self) -> None:
        """Several balls: their cavities, then what the multi-ball attractors do not offer, then their model."""
        from ...dynamics.balls_forced import check_ball_settings
        from ...dynamics.forced import Excitation
        from .damper_job import check_cavities, check_material

        if self.cavities:
            check_cavities(self)
        material = self.names.get("ball_material", "ball_material")
        if not self.several_balls:
            if self.ball_material != BALL_START[2].default:
                raise ParameterError(material, f"applies to several balls: set {self.names.get('balls', 'balls')} "
                                               "above 1")
            return
        check_material(self.ball_material, material)
        what = (f"{len(self.cavities)} cavities ({self.names.get('cavities', 'cavities')})" if self.cavities
                else f"{self.balls} balls ({self.names.get('balls', 'balls')})")
        refused = {"solver": (self.solver != "event", "the balls run by the event solver: drop it or give 'event'"),
                   "restitution": (self.restitution is not None, "applies to one ball (solver impact-map)")}
        for name, (bad, why) in refused.items():
            if bad:
                raise ParameterError(self.names.get(name, name), f"not with {what}: {why}")
        check_ball_settings(self.ball_model(), Excitation(self.frequencies[0], self.amplitude, self.kind),
                            tolerance=self.tolerance, rtol=self.rtol, starts=self.starts, max_cycles=self.max_cycles)

    def _check_budget(self) -> None:
        from ..budget import check_budget, forced_estimate

        names = {k: self.names.get(k, k) for k in ("max_cycles", "frequencies", "noise_seconds")}
        estimate = forced_estimate(len(self.frequencies) * self.starts, self.max_cycles,
                                   noise_seconds=self.noise_seconds if self.noise else 0.0,
                                   wav=self.wav is not None, names=names)
        if self.several_balls:  # a section point of 2 + 2B values and 6 more per cycle, not 16 values
            n = sum(c.balls for c in self.cavities) if self.cavities else self.balls
            which = "cavities" if self.cavities else "balls"
            estimate = dataclasses.replace(estimate, memory=estimate.memory * max(1.0, (8.0 + 2.0 * n) / 16.0),
                                           what=f"{estimate.what}, {n} balls",
                                           options=(*estimate.options, self.names.get(which, which)))
        check_budget(estimate, self.max_memory_mb, cap_name=self.names.get("max_memory_mb", "max_memory_mb"))
