"""``acoustiviz levels``: weighted levels, 1/3-octave bands and loudness of a calibrated WAV file.

The options are the records of :mod:`acoustiviz.app.settings.levels`; :func:`acoustiviz.app.levels.levels`
runs them.
"""

from __future__ import annotations

from ..app.settings.levels import ALL, SIGNAL
from ..app.settings.table import add_option

#: argparse arguments of an option beyond its record.
_EXTRA = {"--csv": {"required": True}}


def add_parser(subparsers) -> None:
    """Register the ``levels`` subcommand."""
    p = subparsers.add_parser(
        "levels",
        help="LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL, SEL(A) and 1/3-octave bands of a WAV file (CSV)",
        description="Sound levels of a WAV file per channel (IEC 61672-1 weightings, IEC 61260-1 1/3-octave bands "
        "from 25 Hz to 20 kHz), in dB re 20 uPa. The calibration (Pa per full scale) is read from the sidecar "
        "SIGNAL.json beside SIGNAL.wav when there is one, else from --pa-per-fs. Times in s.",
    )
    p.add_argument(SIGNAL.name, metavar=SIGNAL.metavar, help=SIGNAL.doc)
    for s in ALL:
        add_option(p, s, **_EXTRA.get(s.option, {}))
    p.set_defaults(func=run)


def run(args) -> int:
    """Parse the options into :class:`~acoustiviz.app.settings.levels.LevelsSettings` and run them."""
    from ..app.levels import levels
    from ..app.names import user_terms
    from ..app.settings.levels import LevelsSettings

    with user_terms(LevelsSettings.cli_names()):
        settings = LevelsSettings.from_namespace(vars(args))
    levels(settings)
    return 0
