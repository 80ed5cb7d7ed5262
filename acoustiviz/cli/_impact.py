"""Impact, medium, configuration and observer options shared by several subcommands.

Defaults reproduce the paper's Figure 2 scene: a sphere of radius 19.05 mm and density
7800 kg/m³ striking at 1.4 m/s with K_HZ = 5.6e8 N/m^1.5, heard at 0.7 m and 45°.
Angles are in degrees on the command line only; everything else is SI.
"""

from __future__ import annotations

from ..app.settings.impact import IMPACT_GROUPS, OBSERVER, WAVEFORM
from ..app.settings.room import ROOM
from ..app.settings.table import add_option

__all__ = ["add_impact_options", "add_observer_options", "add_room_options", "room_settings_from_args", "room_duration",
           "impact_from_args", "observer_point_from_options"]


def add_impact_options(parser, *, velocity: bool = True) -> None:
    """Add the sphere, contact, pulse, medium and configuration options to ``parser``."""
    for title, records in IMPACT_GROUPS:
        g = parser.add_argument_group(title)
        for s in records:
            if velocity or s.name != "velocity":
                add_option(g, s)


def add_room_options(parser, *, duration: bool = False) -> None:
    """Add the shoebox room's options (``--room``, ``--absorption``, ``--source``, ...) to ``parser``.

    ``duration``: also add ``--duration`` (the window in s the images must reach).
    """
    import re

    # let "--room -6,4,3" or "--source -1,0,0" reach the validation (argparse takes only plain negative numbers)
    parser._negative_number_matcher = re.compile(r"^-\d*\.?\d+([eE][-+]?\d+)?(,.*)?$")
    g = parser.add_argument_group("room (a shoebox [0, LX] x [0, LY] x [0, LZ] m, floor z = 0)")
    for s in ROOM:
        add_option(g, s)
    if duration:
        add_option(g, WAVEFORM[1], metavar="S")


def room_settings_from_args(args, *, duration=None, max_memory_mb=None) -> dict | None:
    """The room settings of the options (:func:`acoustiviz.app.impacts.room_settings`); None without ``--room``."""
    from ..app.impacts import room_settings as _room_settings

    return _room_settings(args.room, absorption=args.absorption, source=args.source, strike=args.room_strike,
                          order=args.image_order, tolerance_db=args.tolerance_db, duration=duration,
                          config=getattr(args, "config", None), max_memory_mb=max_memory_mb)


def room_duration(args):
    """The ``--duration`` window in s of a command with ``--room`` (required there, refused without it)."""
    from .._validate import ParameterError

    if args.room is None:
        if args.duration is not None:
            raise ParameterError("--duration", "only applies with --room LX,LY,LZ")
        return None
    if args.duration is None:
        raise ParameterError("--duration", "required with --room: the window in s from the start of contact")
    return args.duration


def add_observer_options(parser, *, angle: bool = True) -> None:
    """Add ``--distance`` (m) and ``--angle`` (degrees) for one observer."""
    g = parser.add_argument_group("observer")
    distance, angle_deg = OBSERVER
    add_option(g, distance)
    if angle:
        add_option(g, angle_deg)


def impact_from_args(args, *, velocity: float | None = None):
    """Build the impact of the shared options (:func:`acoustiviz.app.impacts.impact_setup`), errors naming options.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options from :func:`add_impact_options`.
    velocity : float, optional
        Impact speed in m/s when the command has no ``--velocity`` option.

    Returns
    -------
    acoustiviz.app.impacts.ImpactSetup
    """
    from ..app.impacts import impact_setup
    from ..app.names import IMPACT_OPTIONS, MEMORY, ROOM_OPTIONS, vocabulary
    from ..app.settings.impact import IMPACT
    from ..app.settings.room import ROOM
    from ..app.settings.table import check_values

    records = IMPACT + ROOM  # the records' fixed ranges first, then the physics' limits
    check_values({s.name: getattr(args, s.name) for s in records if hasattr(args, s.name)}, records,
                 vocabulary("cli", records))
    cap = getattr(args, "max_memory", None)  # also caps a room's image order
    room = room_settings_from_args(args, duration=getattr(args, "duration", None), max_memory_mb=cap) \
        if hasattr(args, "room") else None
    names = {**IMPACT_OPTIONS, **ROOM_OPTIONS, **vocabulary("cli", MEMORY)} if room is not None else IMPACT_OPTIONS
    return impact_setup(radius=args.radius, velocity=args.velocity if velocity is None else velocity,
                        k_hertz=args.k_hertz, sphere_material=args.material, surface_material=args.surface,
                        density=args.density, mass=args.mass, pulse=args.pulse, c=args.c, rho=args.rho,
                        config=args.config, wall_distance=args.wall_distance,
                        strike=getattr(args, "strike", "floor"), height=getattr(args, "height", None),
                        room=room, names=names)


def observer_point_from_options(setup, distance: float, angle_deg: float):
    """The observer of ``--distance`` (m) and ``--angle`` (degrees) (:func:`acoustiviz.app.impacts.observer_point`)."""
    from ..app.impacts import observer_point as _observer_point
    from ..app.names import IMPACT_OPTIONS

    return _observer_point(setup, distance, angle_deg, names=IMPACT_OPTIONS)
