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

__all__ = ["DESIGN", "DESIGN_RUN", "DEFINITION", "BAND_WIDTH", "DesignSettings", "DesignJob", "DEFAULT_TOLERANCE"]

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

#: The sweep folder, the report and the files of ``acoustiviz design``.
DESIGN_RUN = (
    Setting("sweep", "--sweep", None, "str", None, "sweep directory (holds sweep.csv)", metavar="DIR"),
    DEFINITION,
    Setting("table", "--table", None, "bool", False, "also print the design table (paper Table 2) of the whole sweep"),
    BAND_WIDTH,
    Setting("rank_by", "--rank-by", None, "str", "max_spl_db",
            "numeric column of sweep.csv whose smallest value is the quietest: max_spl_db (paper Table 2), "
            "lafmax_db, lcpeak_db, laeq_db (sweeps run with --levels), settling_time_s, ...", metavar="COLUMN"),
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
        The column whose smallest value is the quietest (:data:`acoustiviz.sweep.RANK_COLUMNS`).
    png, choice : str, optional
        The design table as a figure beside the paper's Table 2, and the answer for the target as text.
    max_memory_mb : float, optional
        Cap in MB on the estimated memory of reading the sweep.
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name (not compared).
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

    def files(self) -> dict:
        """``{"png": path, "choice": path}`` as asked (strings)."""
        return {key: getattr(self, key) for key in ("png", "choice") if getattr(self, key) is not None}

    def validate(self) -> None:
        """The ranking column, the sweep folder and the memory of reading it, then the files."""
        from ...errors import ParameterError
        from ...sweep import RANK_COLUMNS

        if self.rank_by not in RANK_COLUMNS:
            raise ParameterError("rank_by", f"must be one of {', '.join(RANK_COLUMNS)}; got {self.rank_by!r}")
        if self.sweep is not None:
            from pathlib import Path

            from ..budget import check_budget, design_estimate

            if not Path(self.sweep).is_dir():
                raise ParameterError("sweep", f"no such directory: {self.sweep}")
            check_budget(design_estimate(Path(self.sweep) / "sweep.csv", options=(self._name("sweep"),)),
                         self.max_memory_mb, cap_name=self._name("max_memory_mb"))
        self._check_files()

    def _check_files(self) -> None:
        from ..outputs import check_distinct, check_output_file

        kinds = {"png": "figure", "choice": "text"}
        for key, path in self.files().items():
            check_output_file(self._name(key), path, kinds[key])
        check_distinct({f"{self._name(k)} ({k})": p for k, p in self.files().items()})

    def _name(self, api: str) -> str:
        """The option or scene key of API parameter ``api`` (itself without one)."""
        return self.names.get(api, api)
