"""Settings of a design choice: ``acoustiviz design`` and a scene's ``[outputs.design_table]``.

:data:`DESIGN` holds the target and its band; :data:`DESIGN_RUN` the sweep folder, the report and the
files of the design job (:class:`DesignJob`); :data:`DEFINITION` and :data:`BAND_WIDTH` are shared with
the design report of ``acoustiviz sweep``.
"""

from __future__ import annotations

import dataclasses

from ...constants import MAX_INCLINATION
from .base import Settings
from .table import Setting
from .vocabulary import MEMORY, OUTPUT_TABLES

__all__ = ["DESIGN", "DESIGN_RUN", "RANK_BY", "DEFINITION", "BAND_WIDTH", "DesignSettings", "DesignJob",
           "DEFAULT_TOLERANCE"]

#: Half-width in m/s of the inclination band around a target: half the paper's 0.1 cm/s bands of Table 2.
DEFAULT_TOLERANCE = 0.0005

DESIGN = (
    Setting("inclination", "--inclination", "inclination_m_s", "float", None, "target damping inclination",
            "m/s", low=0.0, high=MAX_INCLINATION, low_open=True, table="outputs.design_table"),
    Setting("tolerance", "--tolerance", "tolerance_m_s", "float", DEFAULT_TOLERANCE,
            "accepted deviation from the target: the half-width of the inclination band", "m/s", low=0.0,
            high=MAX_INCLINATION, low_open=True, table="outputs.design_table"),
)


#: The damping-inclination definition of a design table and its choice (:data:`acoustiviz.sweep.DEFINITIONS`).
DEFINITION = Setting("definition", "--definition", None, "str", "two-maxima",
                     "damping inclination: paper eq 16 from the first two maxima, or the linear fit of the maxima "
                     "envelope", choices=("two-maxima", "fit"))
#: The width of a design table's inclination bands (paper Table 2: 0.1 cm/s).
BAND_WIDTH = Setting("band_width", "--band-width", None, "float", 0.001, "width of the design table's inclination "
                     "bands", "m/s", low=0.0, low_open=True, metavar="M/S")

#: The ranking column of a design report (a scene's ``[outputs.design_table] rank_by``).
RANK_BY = Setting("rank_by", "--rank-by", "rank_by", "str", "max_spl_db",
                 "numeric column of sweep.csv whose smallest value is the quietest: max_spl_db (paper Table 2), "
                 "lafmax_db, lcpeak_db, laeq_db (sweeps run with --levels), settling_time_s, ...; a sweep in "
                 "operation ranks by one of its columns: worst_laeq_db, worst_lcpeak_db, worst_amplitude_m "
                 "(smallest first), min_reduction_db, mean_reduction_db (largest first), ...", metavar="COLUMN",
                 table="outputs.design_table")

#: The sweep folder, the report and the files of ``acoustiviz design``.
DESIGN_RUN = (
    Setting("sweep", "--sweep", None, "str", None, "sweep directory (holds sweep.csv)", metavar="DIR"),
    DEFINITION,
    Setting("table", "--table", None, "bool", False, "also print the design table (paper Table 2) of the whole sweep"),
    BAND_WIDTH,
    RANK_BY,
    Setting("png", "--png", None, "str", None, "the design table as a figure beside the paper's Table 2",
            metavar="PATH"),
    Setting("choice", "--choice", None, "str", None, "the answer for the target as text", metavar="PATH"),
)


@dataclasses.dataclass(frozen=True)
class DesignSettings(Settings):
    """The target damping inclination and the band around it in which designs are compared."""

    TABLE = DESIGN
    inclination: float | None = None
    tolerance: float = DEFAULT_TOLERANCE


@dataclasses.dataclass(frozen=True)
class DesignJob(DesignSettings):
    """The design choice of a sweep: the target and its band, the report and the files.

    Attributes
    ----------
    inclination : float, optional
        Target damping inclination in m/s (None: no choice, the design table alone).
    tolerance : float
        Accepted deviation from the target in m/s.
    sweep : str, optional
        The sweep folder (None: the table is handed to :func:`acoustiviz.app.design.run`).
    definition : {"two-maxima", "fit"}
        Damping-inclination definition.
    table : bool
        Also report the design table of the whole sweep.
    band_width : float
        Width of the design table's bands in m/s.
    rank_by : str
        The column whose smallest value is the quietest (:data:`acoustiviz.sweep.RANK_COLUMNS`); for a sweep
        in operation one of :data:`acoustiviz.sweep.in_operation.OPERATION_RANK`, in its sense.
    png, choice : str, optional
        The design table as a figure beside the paper's Table 2, and the answer for the target as text.
    max_memory_mb : float, optional
        Cap in MB on the estimated memory of reading the sweep.
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name (not compared).
    operation : acoustiviz.sweep.Operation or None
        The excitation of the sweep folder when it is a sweep in operation, read by :meth:`validate`
        (not compared; None: free vibration, or no folder yet).
    """

    TABLE = DESIGN + DESIGN_RUN
    BUILT_FROM = MEMORY
    ALIASES = {"width": "band_width"}
    DERIVED_NAMES = {"scene": OUTPUT_TABLES["design_table"]}
    sweep: str | None = None
    definition: str = DEFINITION.default
    table: bool = False
    band_width: float = BAND_WIDTH.default
    rank_by: str = "max_spl_db"
    png: str | None = None
    choice: str | None = None
    max_memory_mb: float | None = None
    names: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)
    operation: object = dataclasses.field(default=None, init=False, compare=False, repr=False)

    def files(self) -> dict:
        """``{"png": path, "choice": path}`` as asked (strings)."""
        return {key: getattr(self, key) for key in ("png", "choice") if getattr(self, key) is not None}

    def validate(self) -> None:
        """The ranking column, the sweep folder and the memory of reading it, then the files."""
        from ...errors import ParameterError
        from ...sweep import RANK_COLUMNS
        from ...sweep.in_operation import OPERATION_RANK

        if self.rank_by not in RANK_COLUMNS and self.rank_by not in OPERATION_RANK:
            raise ParameterError("rank_by", f"must be one of {', '.join(RANK_COLUMNS)} or, for a sweep in operation, "
                                            f"{', '.join(OPERATION_RANK)}; got {self.rank_by!r}")
        if self.sweep is not None:
            from pathlib import Path

            from ..budget import check_budget, design_estimate

            if not Path(self.sweep).is_dir():
                raise ParameterError("sweep", f"no such directory: {self.sweep}")
            check_budget(design_estimate(Path(self.sweep) / "sweep.csv", options=(self._name("sweep"),)),
                         self.max_memory_mb, cap_name=self._name("max_memory_mb"))
            self._check_mode()
        self._check_files()

    def _check_mode(self) -> None:
        """A sweep in operation: ranked by one of its columns, with no target inclination and no figure."""
        from pathlib import Path

        from ...errors import ParameterError
        from ...sweep import RANK_COLUMNS, SWEEP_JSON
        from ...sweep.in_operation import OPERATION_RANK, operation_from_document
        from ...sweep.store import read_document

        if not (Path(self.sweep) / SWEEP_JSON).is_file():  # not run yet: read when it is
            return
        document = read_document(self.sweep, "sweep")["spec"].get("operation")
        if document is None:
            if self.rank_by not in RANK_COLUMNS:
                raise ParameterError("rank_by", f"{self.rank_by} is a column of a sweep in operation; {self.sweep} "
                                                f"is a sweep of free vibration: one of {', '.join(RANK_COLUMNS)}")
            return
        object.__setattr__(self, "operation", operation_from_document(document, "sweep")[0])
        if self.rank_by not in OPERATION_RANK:
            raise ParameterError("rank_by", f"{self.sweep} is a sweep in operation: rank it by one of "
                                            f"{', '.join(OPERATION_RANK)}; got {self.rank_by!r}")
        for key in ("inclination", "png"):
            if getattr(self, key) is not None:
                raise ParameterError(key, f"{self.sweep} is a sweep in operation, which has no damping inclination "
                                          "nor design table: rank its designs by the rank column alone")

    def _check_files(self) -> None:
        from ..outputs import check_distinct, check_output_file

        kinds = {"png": "figure", "choice": "text"}
        for key, path in self.files().items():
            check_output_file(self._name(key), path, kinds[key])
        check_distinct({f"{self._name(k)} ({k})": p for k, p in self.files().items()})

    def _name(self, api: str) -> str:
        """The option or scene key of API parameter ``api`` (itself without one)."""
        return self.names.get(api, api)
