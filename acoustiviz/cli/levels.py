"""``acoustiviz levels``: weighted levels, 1/3-octave bands and loudness of a calibrated WAV file.

argv -> :class:`~acoustiviz.app.settings.levels.LevelsJob` (:func:`settings_from_args`, the options
generated from the records of :mod:`acoustiviz.app.settings.levels`) -> :func:`acoustiviz.app.levels.run`
-> the summary -> :meth:`~acoustiviz.app.levels.LevelsResult.write`.
"""

from __future__ import annotations

from ..app.settings.levels import ALL, SIGNAL
from ..app.settings.table import add_option


def add_parser(subparsers) -> None:
    """Register the ``levels`` subcommand."""
    p = subparsers.add_parser(
        "levels",
        help="LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL, SEL(A) and 1/3-octave bands of a WAV file (CSV)",
        description="Sound levels of a WAV file per channel (IEC 61672-1 weightings, IEC 61260-1 1/3-octave bands "
        "from 25 Hz to 20 kHz), in dB re 20 uPa. The calibration (Pa per full scale) is read from the sidecar "
        "SIGNAL.json beside SIGNAL.wav when there is one, else from --pa-per-fs. Times in s.",
    )
    for s in (SIGNAL, *ALL):
        add_option(p, s)
    p.set_defaults(func=run)


def settings_from_args(args, echo=print):
    """The :class:`~acoustiviz.app.settings.levels.LevelsJob` of the options; errors name the options.

    The options' ranges are checked first, then the file, the CSV and the memory, then the file and its
    calibration are read (:func:`acoustiviz.app.levels.job_from_wav`).
    """
    from ..app.levels import job_from_wav
    from ..app.settings.levels import LevelsSettings

    return job_from_wav(LevelsSettings.from_namespace(vars(args)), echo)


def run(args) -> int:
    """Compute the levels (:func:`acoustiviz.app.levels.run`), print them and write the CSV files."""
    from ..app.levels import file_summary, silent_notes
    from ..app.levels import run as run_job

    result = run_job(settings_from_args(args))
    silent_notes(result.report, print)
    for line in file_summary(result):
        print(line)
    for path in result.write():
        print(f"wrote {path}")
    return 0
