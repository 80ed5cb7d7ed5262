"""Settings of the levels of a calibrated WAV file: ``acoustiviz levels``.

One :class:`~acoustiviz.app.settings.table.Setting` per option (:data:`ALL`, in the order
``--help`` shows them); :class:`LevelsSettings` checks the ranges of :data:`LEVELS` once. The
checks that need the file (its sidecar, its length) are made by :func:`acoustiviz.app.levels.job_from_wav`.
Times in s, pressures in Pa. A scene's ``[outputs.levels]`` evaluates the damper run it computes,
not a file, so these settings have no scene keys.
"""

from __future__ import annotations

import dataclasses

from .base import Settings
from .table import Setting, by_name

__all__ = ["ALL", "LEVELS_JOB", "LEVELS", "LevelsSettings", "LevelsJob"]

#: The file to read, a positional argument: its errors name it ``SIGNAL.wav``, as ``--help`` shows it.
SIGNAL = Setting("signal", "SIGNAL.wav", None, "str", None, "the WAV file", metavar="SIGNAL.wav", positional=True,
                 required=True)

ALL = (
    Setting("csv", "--csv", None, "str", None, "one row per channel; the bands go to OUT_bands.csv beside it",
            metavar="OUT.csv", required=True),
    Setting("pa_per_fs", "--pa-per-fs", None, "float", None,
            "calibration (Pa per full scale) when the file has no sidecar", "Pa", low=0.0, low_open=True,
            metavar="PA"),
    Setting("start", "--start", None, "float", None,
            "start of the interval (default: the start of the file)", "s", low=0.0, metavar="S"),
    Setting("stop", "--stop", None, "float", None,
            "end of the interval (default: the end of the file)", "s", low=0.0, low_open=True, metavar="S"),
    Setting("loudness", "--loudness", "loudness", "bool", False,
            "also ISO 532-1 loudness N5/Nmax (sone) and DIN 45692 sharpness (acum); needs mosqito "
            "(pip install 'acoustiviz[hearing]')", table="outputs.levels",
            scene_doc="also ISO 532-1 loudness and DIN 45692 sharpness (needs mosqito)"),
)

#: The settings whose range :class:`LevelsSettings` checks on its own, before any other check.
LEVELS = tuple(s for s in ALL if s.name in ("pa_per_fs", "start", "stop"))


@dataclasses.dataclass(frozen=True)
class LevelsSettings(Settings):
    """The file, its calibration (Pa per full scale), the interval (s) and the CSV of ``acoustiviz levels``.

    ``max_memory`` is the working-memory cap in MB (None: the default budget); ``names`` maps API names to
    the options or scene keys errors name (:meth:`from_namespace`: the options).
    """

    TABLE = LEVELS
    #: The file and every option: the vocabulary of the errors (the file's and the CSV's checks need the file).
    BUILT_FROM = (SIGNAL, *ALL)
    signal: str | None = None
    csv: str | None = None
    pa_per_fs: float | None = None
    start: float | None = None
    stop: float | None = None
    loudness: bool = False
    max_memory: float | None = None
    names: dict | None = dataclasses.field(default=None, compare=False, repr=False)

    @classmethod
    def from_namespace(cls, ns: dict):
        """The settings of a mapping of option destinations to values (``vars(args)``); errors name the options."""
        fields = {f.name for f in dataclasses.fields(cls)} - {"names"}
        return cls(**{k: v for k, v in ns.items() if k in fields}, names=cls.names_for("cli"))


#: The records :class:`LevelsJob` checks: the interval, the loudness and the levels CSV (the calibration is a
#: fact of the signal, so it keeps its record's range under the job's name).
LEVELS_JOB = (*(s for s in ALL if s.name in ("start", "stop", "loudness", "csv")),
       dataclasses.replace(by_name(ALL)["pa_per_fs"], name="pa_per_full_scale"))


@dataclasses.dataclass(frozen=True, eq=False)
class LevelsJob(Settings):
    """The whole of what :func:`acoustiviz.app.levels.run` needs: a calibrated signal, the interval, the files.

    Each front end builds the signal (``acoustiviz levels`` reads a WAV file and its calibration);
    the interval, the metrics and the files are then one code path. The ranges of :data:`LEVELS_JOB` are
    checked when the job is made, then :meth:`validate`.

    Attributes
    ----------
    signal : acoustiviz.Signal
        Sound pressure in Pa, ``(n_channels, n_samples)``, its times in s.
    channels : tuple of str
        One name per channel of ``signal``.
    pa_per_full_scale : float or None
        The calibration applied to a file's samples, in Pa per full scale (None: a computed signal).
    source : str
        Where the calibration came from (``"given"``, ``"sidecar NAME.json"``) or the signal was computed.
    start, stop : float or None
        The interval in s on the signal's axis (None: its start, its end).
    loudness : bool
        Also ISO 532-1 loudness and DIN 45692 sharpness.
    csv : str or None
        The levels CSV (one row per channel); its bands go to ``OUT_bands.csv`` beside it.
    spectrum_csv, spectrum_png : str or None
        The 1/3-octave spectrum (``channel,band_hz,leq_db,lmax_db``, channels by name) and its figure.
    what : str
        What the signal is, for the figure's title.
    names : dict
        The user's name of each setting (option or scene key), for error messages.

    Two jobs are equal when they evaluate the same pressure (by value) over the same interval with
    the same metrics into the same files; where the calibration came from, the title's wording and
    the vocabulary of errors only describe, and are left out.
    """

    TABLE = LEVELS_JOB
    #: The fields compared by :meth:`__eq__` besides the signal.
    _COMPARED = ("channels", "start", "stop", "loudness", "csv", "spectrum_csv", "spectrum_png")

    signal: object
    channels: tuple
    pa_per_full_scale: float | None = None
    source: str = "computed"
    start: float | None = None
    stop: float | None = None
    loudness: bool = False
    csv: str | None = None
    spectrum_csv: str | None = None
    spectrum_png: str | None = None
    what: str = "the signal"
    names: dict = dataclasses.field(default_factory=dict, repr=False)

    def __eq__(self, other):
        import numpy as np

        if not isinstance(other, LevelsJob):
            return NotImplemented
        a, b = self.signal, other.signal
        return (a.sample_rate == b.sample_rate and a.start == b.start and np.array_equal(a.pressure, b.pressure)
                and all(getattr(self, k) == getattr(other, k) for k in self._COMPARED))

    __hash__ = None

    def validate(self) -> None:
        """A non-empty interval, and one channel name per channel of the signal."""
        from ...errors import ParameterError

        if self.start is not None and self.stop is not None and self.stop <= self.start:
            raise ParameterError(self.names.get("stop", "stop"),
                                 f"must be later than {self.names.get('start', 'start')} ({self.start:g} s), "
                                 f"got {self.stop:g} s")
        if len(self.channels) != self.signal.channels:
            raise ParameterError(self.names.get("signal", "signal"),
                                 f"{len(self.channels)} channel name(s) for {self.signal.channels} channel(s)")
