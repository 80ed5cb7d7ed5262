"""Settings of an optimisation: ``acoustiviz optimize`` and a scene's ``[outputs.optimize]``.

:data:`OPTIMIZE` holds the records of the objectives, constraints, budget, seed, batch and mode;
:data:`VARIABLES` the variables (the options of ``acoustiviz sweep``'s swept parameters, read here
as ``LO:HI``, ``log:LO:HI``, ``A,B,C`` or one value); :data:`EXECUTION` where the evaluations run.
:class:`OptimizeJob` is the whole of what :func:`acoustiviz.app.optimize.run` needs, checked once.
"""

from __future__ import annotations

import dataclasses

from ...errors import ParameterError
from .base import Settings
from .room import ROOM
from .sweep import SCENE_SWEEP, SWEEP, SWEEP_DAMPER, SWEEP_RUN, SWEEP_SOUND, SWEPT
from .sweep_operation import OPERATION_OPTIONS
from .table import Setting, by_name
from .vocabulary import ALIASES as GROUP_ALIASES

__all__ = ["OPTIMIZE", "VARIABLES", "EXECUTION", "REPEATED", "SCENE_VARIABLES", "SCENE_LEVELS", "SCENE_OPERATION",
           "OptimizeJob", "FILES", "CONFIRMATION"]

_T = "outputs.optimize"
_FORM = "LO:HI, log:LO:HI, A,B,C or one value"

#: The objectives, constraints, budget, seed, batch and mode.
OPTIMIZE = (
    Setting("minimize", "--minimize", "minimize", "str", None,
            "a column of sweep.csv to minimise (repeatable; two or more objectives give a Pareto front), e.g. "
            "max_spl_db", metavar="COLUMN", scene_default=("max_spl_db",), table=_T, scene_kind="texts",
            scene_doc="the columns of sweep.csv to minimise (a list; two or more objectives give a Pareto front), "
                      "e.g. max_spl_db"),
    Setting("maximize", "--maximize", "maximize", "str", None,
            "a column of sweep.csv to maximise (repeatable)", metavar="COLUMN", scene_default=(), table=_T,
            scene_kind="texts", scene_doc="the columns of sweep.csv to maximise (a list)"),
    Setting("constraints", "--constraint", "constraints", "str", None,
            "a feasible design meets 'COLUMN<=VALUE' or 'COLUMN>=VALUE' (repeatable), e.g. "
            "'inclination_two_maxima_m_s>=0.004'", metavar="'COLUMN<=VALUE'", scene_default=(), table=_T,
            scene_kind="texts", scene_doc="a feasible design meets each 'COLUMN<=VALUE' or 'COLUMN>=VALUE' of the "
                                          "list, e.g. 'inclination_two_maxima_m_s>=0.004'"),
    Setting("evaluations", "--evaluations", "evaluations", "int", 60, "designs evaluated in all", low=1,
            high=100000, table=_T),
    Setting("seed", "--seed", "seed", "int", 0, "seed of the optimiser: the same seed gives the same designs "
            "whatever the number of workers", low=0, high=2**32 - 1, table=_T),
    Setting("batch", "--batch", "batch", "int", 8, "designs asked of the optimiser at a time and evaluated in "
            "parallel (the designs depend on it, not on the workers)", low=1, high=1024, table=_T),
    Setting("mode", "--mode", "mode", "str", "free", "what a design's columns are: free vibration from the "
            "Figure 5 start (the columns of sweep.csv) or in operation (the worst-case columns of a sweep in "
            "operation; set by --force or --base)", choices=("free", "operation"), table=_T),
    # a scene's optimisation is a quick look, like its sweep (the record's scene default); the command runs 20 s
    dataclasses.replace(SWEEP[0], table=_T),
)

#: A scene's level columns (the command line's ``--levels`` is the sweep's record).
SCENE_LEVELS = Setting("levels", None, "levels", "bool", False, "also LAFmax, LCpeak and LAeq of each design's run "
                       "(columns lafmax_db, lcpeak_db, laeq_db)", table=_T)

#: A scene's optimisation in operation: under the scene's ``[excitation]``, as ``[outputs.sweep] in_operation``.
SCENE_OPERATION = (
    dataclasses.replace(SCENE_SWEEP[1], table=_T, doc="evaluate every design in operation under the scene's "
                        "[excitation] (its kind, amplitude, frequencies and search) instead of in free vibration; "
                        "the chosen design's worst case is then confirmed with twice the starts"),
    dataclasses.replace(SCENE_SWEEP[2], table=_T),
)

#: The records given as repeated options on the command line and as lists in a scene.
REPEATED = ("minimize", "maximize", "constraints")


def _variable(record: Setting) -> Setting:
    doc = record.doc.split(" (default")[0].split(";")[0]
    if record.metavar == "NAMES":  # names: one of several, or held
        return dataclasses.replace(record, doc=f"{doc}: A,B,C (one of them) or one name (held)")
    if record.name == "balls":  # whole numbers: every integer between the bounds, no log scale
        return dataclasses.replace(record, doc=f"{doc}: LO:HI (every whole number between), A,B,C or one value",
                                   metavar="LO:HI")
    return dataclasses.replace(record, doc=f"{doc}: {_FORM}", metavar="LO:HI")


#: The variables: the swept parameters of ``acoustiviz sweep`` (each in its damper record's range).
VARIABLES = tuple(_variable(s) for s in SWEPT)


def _scene_variable(name: str) -> Setting:
    """The command line's variable ``name`` as a key of ``[outputs.optimize]`` (the same form, as text)."""
    return dataclasses.replace(by_name(VARIABLES)[name], option=None, scene_kind="str", table=_T)


#: A scene's variables: gap and impact mass, and the balls and their fill as the command line's (the scene's
#: other settings are held fixed); with the balls, the sweep's equal total mass.
SCENE_VARIABLES = (Setting("gap", None, "gap_m", "str", "0.01:0.06", f"total free travel d in m: {_FORM}",
                           table=_T),
                   Setting("m", None, "mass_kg", "str", "0.01:0.08", f"impact mass in kg: {_FORM}", table=_T),
                   _scene_variable("balls"), _scene_variable("fill"),
                   dataclasses.replace(by_name(SWEEP_DAMPER)["equal_total_mass"], option=None, table=_T))

#: Where the evaluations run, and the folder.
EXECUTION = (
    Setting("executor", "--executor", None, "str", "process", "local process pool or a Dask distributed scheduler",
            metavar="process|dask://HOST:PORT"),
    Setting("workers", "--workers", "workers", "int", None, "processes of the local pool (default: all cores)",
            low=1, high=1024, table=_T),
    Setting("out", "--out", None, "str", None, "output folder (an interrupted run in it is resumed)",
            metavar="DIR"),
)

#: The files of the folder.
FILES = ("evaluations.csv", "pareto.csv", "optimize.json", "pareto.png")
#: The file of an optimisation in operation: the chosen design's worst case confirmed.
CONFIRMATION = "confirmation.csv"


@dataclasses.dataclass(frozen=True)
class OptimizeJob(Settings):
    """An optimisation of damper designs and the folder its files go to.

    Attributes
    ----------
    variables : tuple of acoustiviz.sweep.problem.Variable
        Every design variable (API names of :func:`acoustiviz.app.sweep.sweep_spec`; fixed ones included).
    fixed : acoustiviz.sweep.FixedSettings
        The damper, solver and sound held fixed.
    minimize, maximize : tuple of str
        Columns to minimise and maximise.
    constraints : tuple of str
        ``COLUMN<=VALUE`` or ``COLUMN>=VALUE``.
    evaluations, seed, batch : int
        Budget, seed of the optimiser, designs per batch.
    mode : str
        The evaluation mode (:data:`acoustiviz.sweep.modes.MODES`): ``"free"`` or ``"operation"``.
    operation : acoustiviz.sweep.Operation, optional
        In operation (required then, refused otherwise): the excitation, the band and the search.
    out : str, optional
        Folder of the journal and the files (None: the run keeps no journal and nothing is written).
    executor : str
        ``"process"`` or ``"dask://HOST:PORT"`` (not compared: the result does not depend on it).
    workers : int, optional
        Processes of the local pool (not compared).
    names : dict
        API parameter -> option or scene key (not compared).
    """

    TABLE = OPTIMIZE[3:7] + EXECUTION
    # the sweep's records this job shares, those of a sweep in operation and the sweep's room with its window
    BUILT_FROM = VARIABLES + OPTIMIZE + SWEEP_DAMPER + SWEEP_SOUND + OPERATION_OPTIONS + ROOM + \
        (by_name(SWEEP_RUN)["room_window"],)
    # the duration is the damper run's, not the room's window (--room-window); the sound speed is --c
    ALIASES = {"angle": "angle_deg", "radius_mode": "radius", "objectives": "minimize", "variables": "gap",
               **{k: v for k, v in GROUP_ALIASES["room"].items() if k not in ("duration", "sound_speed")}}
    variables: tuple
    fixed: object
    minimize: tuple = ()
    maximize: tuple = ()
    constraints: tuple = ()
    evaluations: int = OPTIMIZE[3].default
    seed: int = OPTIMIZE[4].default
    batch: int = OPTIMIZE[5].default
    mode: str = OPTIMIZE[6].default
    operation: object = None
    out: str | None = None
    executor: str = dataclasses.field(default="process", compare=False)
    workers: int | None = dataclasses.field(default=None, compare=False)
    names: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)
    problem: object = dataclasses.field(default=None, init=False, compare=False, repr=False)

    def evaluator(self):
        """The evaluation mode's callable, made from the fixed settings."""
        from ...sweep.modes import MODES

        named = {v.name for v in self.variables}
        with_balls = bool({"balls", "fill"} & named) or self.fixed.equal_total_mass
        if self.operation is not None:
            return MODES[self.mode](self.fixed, self.operation, with_balls)
        return MODES[self.mode](self.fixed, with_balls)

    @property
    def files(self) -> tuple:
        """The names of the folder's files (in operation with the confirmation)."""
        return FILES + ((CONFIRMATION,) if self.mode == "operation" else ())

    def _check_mode(self) -> None:
        from ...sweep import Operation

        if self.mode == "operation" and self.operation is None:
            raise ParameterError("mode", "operation needs an excitation: --force F0 or --base B, and --freq")
        if self.operation is not None:
            if self.mode != "operation":
                raise ParameterError("mode", f"an excitation is given: the mode is 'operation', not {self.mode!r}")
            if not isinstance(self.operation, Operation):
                raise ParameterError("operation", f"expected an Operation, got {type(self.operation).__name__}")

    def validate(self) -> None:
        """The objectives and constraints against the mode's columns, the executor and the folder."""
        from ...sweep.problem import Objective, Problem, parse_constraint

        for key in REPEATED:
            object.__setattr__(self, key, tuple(getattr(self, key) or ()))
        self._check_mode()
        evaluate = self.evaluator()
        objectives = tuple(Objective(c, "min") for c in self.minimize) + \
            tuple(Objective(c, "max") for c in self.maximize)
        constraints = tuple(parse_constraint("constraints", t) for t in self.constraints)
        problem = Problem(tuple(self.variables), objectives, constraints, self.evaluations, self.seed, self.batch,
                          columns=evaluate.objective_columns)
        if not self.fixed.levels:
            for item in objectives + constraints:
                if item.column in evaluate.level_columns:
                    name = "constraints" if item in constraints else ("minimize" if item.sense == "min" else
                                                                      "maximize")
                    raise ParameterError(name, f"column {item.column} needs the levels of each run (--levels, "
                                               "scene key outputs.optimize.levels)")
        object.__setattr__(self, "problem", problem)
        from ...sweep.execute import check_executor_form

        check_executor_form(self.executor)
        if self.out is not None:
            self._check_folder()

    def document(self) -> dict:
        """``optimize.json``: the specification (problem, mode and fixed settings; not where it ran)."""
        from dataclasses import asdict

        from ... import __version__

        fixed = asdict(self.fixed)
        if fixed.get("room") is None:
            fixed.pop("room", None)
        for name, unset in (("equal_total_mass", False), ("k_hertz_ball", None), ("c1_ball", None)):
            if fixed.get(name, unset) is unset:  # a problem of one ball reads as before balls were searched
                fixed.pop(name, None)
        doc = {"format": "acoustiviz-optimize", "format_version": 1, "written_by": f"acoustiviz {__version__}",
               "optimizer": "optuna TPE", "mode": self.mode, **self.problem.to_dict(), "fixed": fixed}
        if self.operation is not None:
            from ...sweep.in_operation import operation_document

            doc["operation"] = {k: v for k, v in operation_document(self.operation).items() if k != "chain"}
        return doc

    def _check_folder(self) -> None:
        import json
        from pathlib import Path

        from ..outputs import check_output_dir, check_output_file

        out = Path(check_output_dir("out", self.out))
        spec = out / FILES[2]
        if spec.is_file():  # a run to resume: only with the same specification
            try:
                old = json.loads(spec.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                old = None
            mine = json.loads(json.dumps(self.document()))
            # the budget may change: the designs of a batch depend only on the evaluations before it
            free = ("written_by", "evaluations")
            if not isinstance(old, dict) or {k: v for k, v in old.items() if k not in free} != \
                    {k: v for k, v in mine.items() if k not in free}:
                raise ParameterError("out", f"{out} holds an optimisation with other settings; use another folder")
            return
        for name in self.files:
            if (out / name).exists() or (out / name).is_symlink():
                check_output_file("out", out / name, name.rsplit(".", 1)[1])
