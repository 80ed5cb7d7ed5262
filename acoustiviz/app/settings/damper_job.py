"""The settings of the damper job: the damper, its start, its run and its files.

:class:`DamperJob` is the whole of what :func:`acoustiviz.app.damper.run` needs, checked once when it
is made (the records' ranges of :mod:`acoustiviz.app.settings.damper`, the solver's own tolerance, the
physics' limits, the memory budget, the files to write), so ``acoustiviz damper``, a scene's
``[outputs.impact_table]`` and ``[outputs.damper_history]`` and a Python caller build the same object
and hand it to the same run. The records of its command-line files (``--impacts-csv``,
``--history-csv``, ``--png``) live here.
"""

from __future__ import annotations

import dataclasses

from ...constants import DEFAULT_DURATION, DEFAULT_RTOL, PAPER_V0
from .base import Settings
from .damper import BALL_START, BALLS, CAVITY, CONTACT_LAW, DAMPER, MODEL, RUN, SOLVER
from .table import Setting, check_values
from .vocabulary import ALIASES, MEMORY, OUTPUT_TABLES

__all__ = ["DAMPER_OUTPUTS", "FILE_KINDS", "DamperCavity", "DamperJob", "check_cavities", "check_material",
           "scene_balls"]

#: The files of ``acoustiviz damper`` (a scene names them itself: ``impacts.csv`` for ``[outputs.impact_table]``,
#: ``damper_history.csv`` and ``.png`` for ``[outputs.damper_history]``).
DAMPER_OUTPUTS = (
    Setting("impacts_csv", "--impacts-csv", None, "str", None,
            "write the impact table (one row per contact) as CSV; a contact still under way when the run ends "
            "(the last row) has nan separation_velocity_m_s and restitution, and its duration_s is the time it "
            "lasted until then; with --balls above 1 the columns first and second name the two bodies of each "
            "collision (wall-, ball1 ... ballN, wall+)", metavar="PATH"),
    Setting("history_csv", "--history-csv", None, "str", None,
            "write the time history as CSV (columns time_s,x_m,v_m_s,y_m,w_m_s; with several balls "
            "y1_m ... yN_m, w1_m_s ... wN_m_s)", metavar="PATH"),
    Setting("png", "--png", None, "str", None, "plot x(t) with and without the damper (Figure 5) as PNG",
            metavar="PATH"),
)

#: Each file of the job -> the kind of file :func:`acoustiviz.app.outputs.check_output_file` expects.
FILE_KINDS = {"impacts_csv": "csv", "history_csv": "csv", "png": "figure"}


@dataclasses.dataclass(frozen=True)
class DamperCavity:
    """One cavity of several on the main mass: a column of ``balls`` equal spheres of mass ``m``.

    Attributes
    ----------
    gap : float, optional
        Free travel in m, the cavity's length less its balls' diameters (default: the job's ``model.gap``).
    balls : int
        Number of balls in the cavity.
    m : float, optional
        Mass of each ball in kg (default: the job's ``model.m``).
    k_hertz_ball : float, optional
        Hertz stiffness between two balls in N/m^1.5 (default: paper eq 2 for two steel spheres of mass ``m``).
    c1_ball : float, optional
        Contact damping between two balls in N s/m (default: the job's ``model.c1``).
    start : {"spaced", "low", "high", "random"}, optional
        Where the cavity's balls start, at rest (default: the job's ``ball_start``).
    material : str, optional
        The balls' material from the catalogue (default: the job's ``ball_material``): their radius
        from ``m`` and its density, their stiffness from paper eq 2.
    position : (3,) tuple of float, optional
        Where the cavity's sound comes from: its offset in m from the scene's sphere, the cavity moved
        rigidly (default: spaced apart, :func:`acoustiviz.sound.balls_sound.cavity_places`).
    """

    gap: float | None = None
    balls: int = 1
    m: float | None = None
    k_hertz_ball: float | None = None
    c1_ball: float | None = None
    start: str | None = None
    material: str | None = None
    position: tuple | None = None

    def __post_init__(self):
        # a scene's list and the API's tuple make equal cavities; a bad value is left for the job's checks
        if self.position is not None and not isinstance(self.position, str):
            try:
                object.__setattr__(self, "position", tuple(float(x) for x in self.position))
            except (TypeError, ValueError):
                pass


def check_cavities(job) -> None:
    """Each of ``job.cavities``' values in its records' ranges, named ``cavities[i].gap`` (or the scene's key).

    ``job`` is a settings object with the fields ``balls``, ``cavities`` and ``names`` (a damper or a forced job).
    """
    from ..._validate import ParameterError

    if job.balls != 1:
        raise ParameterError(job.names.get("balls", "balls"), "the balls of several cavities are given per "
                             f"cavity ({job.names.get('cavities', 'cavities')}): leave balls at 1")
    where = job.names.get("cavities", "cavities")
    for i, cav in enumerate(job.cavities):
        if not isinstance(cav, DamperCavity):
            raise ParameterError(f"{where}[{i}]", f"must be a DamperCavity, got {cav!r}")
        names = {s.name: f"{where}[{i}].{s.key if where != 'cavities' else s.name}" for s in CAVITY}
        check_values(dataclasses.asdict(cav), CAVITY, names)
        if cav.material is not None:
            check_material(cav.material, names["material"])


def check_material(name: str, where: str) -> None:
    """``name`` a material of the catalogue (:func:`acoustiviz.core.materials.material`); the error names ``where``."""
    from ..._validate import ParameterError
    from ...core.materials import material

    try:
        material(name)
    except ParameterError as exc:
        raise exc.renamed(where) from None


def scene_balls(damper: dict, records=BALLS) -> dict:
    """A scene's ``[damper]`` section -> a job's ball fields: those of ``records`` and ``cavities``.

    A damper job takes ``BALLS + BALL_START`` (the start and material of the balls too), a forced job ``BALLS``.
    """
    balls = {s.name: damper[s.key] for s in records}
    cavities = tuple(DamperCavity(**{s.name: c[s.key] for s in CAVITY}) for c in damper.get("cavities", ()))
    return {**balls, "cavities": cavities}


@dataclasses.dataclass(frozen=True)
class DamperJob(Settings):
    """One run of the impact damper (paper eq 15), its damping and the files wanted of it.

    Attributes
    ----------
    model : acoustiviz.dynamics.DamperModel
        The damper: masses in kg, stiffnesses in N/m and N/m^1.5, dashpots in N s/m, the gap in m.
    initial : acoustiviz.dynamics.InitialState, optional
        The start (m, m/s); default the paper's Figure 5 start (x = 0, dx/dt = V0, impact mass centred
        and at rest).
    duration : float
        Simulated time in s.
    solver : {"event", "newmark", "impact-map", "auto"}
        The solver (:data:`acoustiviz.dynamics.METHODS`); ``"auto"``: the cheapest whose error suits ``rtol``.
    rtol : float
        Relative tolerance; each solver checks its own range.
    dt : float, optional
        Newmark step in s (default: 1/50 of the shortest possible contact).
    max_memory_mb : float, optional
        Cap in MB on the working memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).
    impacts_csv, history_csv, png : str, optional
        The impact table, the time history and the Figure 5 plot; relative to the folder
        :meth:`acoustiviz.app.damper.DamperResult.write` is given.
    balls : int
        Equal spheres of the impact mass ``model.m`` in the cavity (a column; ``model.gap`` is their free
        travel). One is the single-ball damper; more run the multi-ball solver
        (:func:`acoustiviz.dynamics.simulate_balls`, the event solver's method for a column).
    k_hertz_ball : float, optional
        Hertz stiffness between two balls in N/m^1.5 (default: paper eq 2 for two steel spheres of the
        impact mass); ``model.k_hertz`` stays the ball-wall stiffness.
    c1_ball : float, optional
        Contact damping between two balls in N s/m (default ``model.c1``).
    cavities : tuple of DamperCavity
        Several cavities on the main mass, numbered from 1 (``c2:ball1`` in the impact table); each
        value it leaves out is the model's. Empty (default): the one cavity of ``model`` and ``balls``.
    ball_start : {"spaced", "low", "high", "random"}
        Where the balls start, at rest (:class:`acoustiviz.dynamics.BallState`); with several balls.
    ball_seed : int, optional
        Seed of the ``random`` start (None: a fresh one each run).
    ball_material : str
        The balls' material from the catalogue (a cavity's own ``material`` first); with several balls.
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name
        (not compared; default: the API names).
    """

    TABLE = (RUN[2], *SOLVER, RUN[3], *DAMPER_OUTPUTS, *BALLS, *BALL_START)  # duration ... the files, the balls
    BUILT_FROM = (*DAMPER, *MEMORY)  # the model and the start; the memory cap
    ALIASES = ALIASES["damper"]
    DERIVED_NAMES = {"scene": {**OUTPUT_TABLES["damper"], "cavities": "damper.cavities"}}
    model: object
    initial: object = None
    duration: float = DEFAULT_DURATION
    solver: str = "event"
    rtol: float = DEFAULT_RTOL
    dt: float | None = None
    max_memory_mb: float | None = None
    impacts_csv: str | None = None
    history_csv: str | None = None
    png: str | None = None
    balls: int = 1
    k_hertz_ball: float | None = None
    c1_ball: float | None = None
    cavities: tuple = ()
    ball_start: str = "spaced"
    ball_seed: int | None = None
    ball_material: str = "steel"
    names: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)

    def files(self) -> dict:
        """``{"impacts_csv": path, "history_csv": path, "png": path}`` of the files asked for (strings)."""
        return {key: getattr(self, key) for key in FILE_KINDS if getattr(self, key) is not None}

    def validate(self) -> None:
        """The model's and the start's ranges, the solver's tolerance, the physics' limits, the memory, the files."""
        from ...core.limits import check_damper
        from ...dynamics import InitialState, solver_method

        if self.initial is None:
            object.__setattr__(self, "initial", InitialState(v=PAPER_V0))
        model, start = self.model, self.initial
        check_values({s.name: getattr(model, s.name) for s in MODEL + CONTACT_LAW}, MODEL + CONTACT_LAW)
        check_values({"x0": start.x, "v0": start.v}, RUN)
        solver_method(self.solver).check_rtol(self.rtol)
        if self.cavities:
            self._check_cavities()
        if self.balls > 1 or self.cavities:
            self._check_balls()
        else:
            self._check_one_ball()
        check_damper(M=model.M, K=model.K, m=model.m, gap=model.gap, k_hertz=model.k_hertz, v=start.v,
                     duration=self.duration, c1=model.c1)
        self._check_cavity_physics()
        self._check_budget()
        self._check_files()

    def _check_balls(self) -> None:
        """Several balls: the multi-ball solver, in its tolerance range, on an underdamped main oscillator."""
        from ..._validate import ParameterError
        from ...constants import SOLVER_RTOL_RANGE
        from ...dynamics import solver_method

        name = self.names.get("solver", "solver")
        if self.solver not in ("event", "auto"):
            what = (f"{self.names.get('cavities', 'cavities')} ({len(self.cavities)})" if self.cavities
                    else f"{self.names.get('balls', 'balls')} {self.balls}")
            raise ParameterError(name, f"{self.solver!r} takes one ball; with {what} the balls run by the event "
                                       "method (solver 'event' or 'auto')")
        lo, hi = SOLVER_RTOL_RANGE
        if not lo <= self.rtol <= hi:
            raise ParameterError(self.names.get("rtol", "rtol"), f"must lie in [{lo:g}, {hi:g}] with several balls, "
                                                                f"got {self.rtol!r}")
        solver_method("event").settings(self.model, self.initial, self.duration, self.rtol, None)  # C underdamped
        check_material(self.ball_material, self.names.get("ball_material", "ball_material"))

    def _check_one_ball(self) -> None:
        """The start and material of several balls left at their defaults for the one-ball damper."""
        from ..._validate import ParameterError

        several = f"set {self.names.get('balls', 'balls')} above 1"
        if "cavities" in self.names or not self.names:
            several += f" or give {self.names.get('cavities', 'cavities')}"
        for s in BALL_START:
            if getattr(self, s.name) != s.default:
                raise ParameterError(self.names.get(s.name, s.name), f"applies to several balls: {several}")

    def _check_cavities(self) -> None:
        """Each cavity's values in its records' ranges (:func:`check_cavities`)."""
        check_cavities(self)

    def _check_cavity_physics(self) -> None:
        """Each cavity's contacts within what the solver can follow (:func:`acoustiviz.core.limits.check_damper`).

        An error about the ball mass or the travel names the cavity's key, any other the cavity.
        """
        from ..._validate import ParameterError
        from ...core.limits import check_damper

        model, where = self.model, self.names.get("cavities", "cavities")
        for i, cav in enumerate(self.cavities):
            m, gap = model.m if cav.m is None else cav.m, model.gap if cav.gap is None else cav.gap
            try:
                check_damper(M=model.M, K=model.K, m=m, gap=gap, k_hertz=model.k_hertz, v=self.initial.v,
                             duration=self.duration, c1=model.c1)
            except ParameterError as exc:
                field = {"m": "impact_mass_kg", "gap": "gap_m"} if where != "cavities" else {"m": "m", "gap": "gap"}
                name = f"{where}[{i}].{field[exc.name]}" if exc.name in field else f"{where}[{i}]"
                raise exc.renamed(name) from None

    def total_balls(self) -> int:
        """Number of balls on the main mass, in every cavity."""
        return sum(c.balls for c in self.cavities) if self.cavities else self.balls

    def _check_budget(self) -> None:
        import dataclasses

        from ..budget import check_budget, damper_estimate

        option = self.names.get("duration", "duration")
        estimate = damper_estimate(self.model, self.duration, solver=self.solver, dt=self.dt, options=(option,))
        n = self.total_balls()
        if self.balls > 1 or self.cavities:  # the position and velocity of every body at every sample, not 6 columns
            estimate = dataclasses.replace(estimate, memory=estimate.memory * (2 * n + 2) / 16.0,
                                           what=f"{estimate.what} x {n} balls",
                                           options=(option, self.names.get("cavities" if self.cavities else "balls",
                                                                           "balls")))
        check_budget(estimate, self.max_memory_mb, cap_name=self.names.get("max_memory_mb", "max_memory_mb"))

    def _check_files(self) -> None:
        from ..outputs import check_distinct, check_output_file

        files = self.files()
        for key, path in files.items():
            check_output_file(key, path, FILE_KINDS[key])
        check_distinct({f"{self.names.get(k, k)} ({k})": p for k, p in files.items()})
