"""Settings of the levels of a calibrated WAV file: ``acoustiviz levels``.

One :class:`~acoustiviz.app.settings.table.Setting` per option (:data:`ALL`, in the order
``--help`` shows them); :class:`LevelsSettings` checks the ranges of :data:`LEVELS` once. The
checks that need the file (its sidecar, its length) are made by :func:`acoustiviz.app.levels.levels`.
Times in s, pressures in Pa. A scene's ``[outputs.levels]`` evaluates the damper run it computes,
not a file, so these settings have no scene keys.
"""

from __future__ import annotations

import dataclasses

from .base import Settings
from .table import Setting

__all__ = ["ALL", "LEVELS", "LevelsSettings"]

SIGNAL = Setting("signal", None, None, "str", None, "the WAV file", metavar="SIGNAL.wav")

ALL = (
    Setting("csv", "--csv", None, "str", None, "one row per channel; the bands go to OUT_bands.csv beside it",
            metavar="OUT.csv"),
    Setting("pa_per_fs", "--pa-per-fs", None, "float", None,
            "calibration (Pa per full scale) when the file has no sidecar", "Pa", low=0.0, low_open=True,
            metavar="PA"),
    Setting("start", "--start", None, "float", None,
            "start of the interval (default: the start of the file)", "s", low=0.0, metavar="S"),
    Setting("stop", "--stop", None, "float", None,
            "end of the interval (default: the end of the file)", "s", low=0.0, low_open=True, metavar="S"),
    Setting("loudness", "--loudness", None, "bool", False,
            "also ISO 532-1 loudness N5/Nmax (sone) and DIN 45692 sharpness (acum); needs mosqito "
            "(pip install 'acoustiviz[hearing]')"),
)

#: The settings whose range :class:`LevelsSettings` checks on its own, before any other check.
LEVELS = tuple(s for s in ALL if s.name in ("pa_per_fs", "start", "stop"))


@dataclasses.dataclass(frozen=True)
class LevelsSettings(Settings):
    """The file, its calibration (Pa per full scale), the interval (s) and the CSV of ``acoustiviz levels``.

    ``max_memory`` is the working-memory cap in MB (None: the default budget).
    """

    TABLE = LEVELS
    signal: str | None = None
    csv: str | None = None
    pa_per_fs: float | None = None
    start: float | None = None
    stop: float | None = None
    loudness: bool = False
    max_memory: float | None = None

    @classmethod
    def from_namespace(cls, ns: dict):
        """The settings of a mapping of option destinations to values (``vars(args)``)."""
        names = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in ns.items() if k in names})
