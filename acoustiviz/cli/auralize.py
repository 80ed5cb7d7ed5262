"""``acoustiviz auralize``: calibrated WAV files of a damper's whole impact sequence.

The damper options are those of ``acoustiviz damper`` (paper eq 15, Table 1 defaults); the run's
impact table (or a CSV of impacts given with ``--impacts``) is rendered at each ``--listener``.
Positions are in m in the frame where the struck surface is ``z = 0`` and the sphere's centre is
``(0, 0, a)``; see :mod:`acoustiviz.sound` for how the two walls map to sources. The options
are the records of :mod:`acoustiviz.app.settings.auralize`; :func:`acoustiviz.app.auralize.auralize`
runs them.
"""

from __future__ import annotations

from ..app.settings.auralize import AURALIZE_GROUPS
from ..app.settings.table import add_option
from ._damper import add_damper_options
from ._impact import add_room_options

#: argparse arguments of an option beyond its record.
_EXTRA = {"--listener": {"action": "append"}, "--wav": {"required": True}}


def add_parser(subparsers) -> None:
    """Register the ``auralize`` subcommand."""
    p = subparsers.add_parser(
        "auralize",
        help="calibrated WAV files (and JSON sidecars) of a damper's impact sequence at listeners",
        description="Render every impact of an impact-damper run into the sound pressure at one or more "
        "listeners: Hertz pulse per impact from its own approach speed, rigid-sphere radiation with image "
        "sources, exact sub-sample times, band-limited to the output rate. Default output: normalised 24-bit "
        "WAV peaking 1 dB below full scale, with OUT.json beside OUT.wav recording the calibration in Pa per full "
        "scale (float32 in pascals with --subtype FLOAT). Lengths in m, times in s.",
    )
    add_damper_options(p, duration_help="simulated time; the WAV lasts this long, or to the end of the last click")
    g = p.add_argument_group("impacts from a file")
    g.add_argument("--impacts", default=None, metavar="CSV",
                   help="render the impacts of this CSV (columns time_s,wall,approach_velocity_m_s, as written "
                        "by 'acoustiviz damper --impacts-csv') instead of simulating; --m, --M, --gap and "
                        "--k-hertz still describe the damper")
    for title, records in AURALIZE_GROUPS:
        group = p.add_argument_group(title)
        for s in records:
            add_option(group, s, **_EXTRA.get(s.option, {}))
        if title == "sound model":  # the room follows; its setup lets "--listener -0.2,0,0.3" read as a value
            add_room_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """Parse the options into :class:`~acoustiviz.app.settings.auralize.AuralizeSettings` and run them."""
    from ..app.auralize import auralize
    from ..app.names import user_terms
    from ..app.settings.auralize import AuralizeSettings, DamperSettings

    with user_terms({**AuralizeSettings.cli_names(), **DamperSettings.cli_names()}):
        settings = AuralizeSettings.from_namespace(vars(args))
    auralize(settings)
    return 0
