"""Impact, medium, configuration and observer options shared by several subcommands.

Defaults reproduce the paper's Figure 2 scene: a sphere of radius 19.05 mm and density
7800 kg/m³ striking at 1.4 m/s with K_HZ = 5.6e8 N/m^1.5, heard at 0.7 m and 45°.
Angles are in degrees on the command line only; everything else is SI.
"""

from __future__ import annotations

from ..app.settings.impact import WAVEFORM
from ..app.settings.room import ROOM
from ..app.settings.table import add_option
from ..constants import (
    DEFAULT_AIR_DENSITY,
    DEFAULT_SOUND_SPEED,
    DEFAULT_WALL_DISTANCE,
    PAPER_ANGLE_DEG,
    PAPER_DENSITY,
    PAPER_DISTANCE,
    PAPER_K_HERTZ,
    PAPER_RADIUS,
    PAPER_VELOCITY,
    PULSES,
    STRIKES,
)
from ..core.geometry import CONFIGURATIONS

__all__ = ["add_impact_options", "add_observer_options", "add_room_options", "room_settings", "room_duration",
           "impact_from_args", "observer_point"]


def add_impact_options(parser, *, velocity: bool = True) -> None:
    """Add the sphere, contact, pulse, medium and configuration options to ``parser``."""
    g = parser.add_argument_group("impact (SI units)")
    g.add_argument("--radius", type=float, default=PAPER_RADIUS, metavar="M",
                   help="sphere radius in m (default %(default)s)")
    if velocity:
        g.add_argument("--velocity", type=float, default=PAPER_VELOCITY, metavar="M/S",
                       help="impact (approach) speed in m/s (default %(default)s)")
    g.add_argument("--k-hertz", type=float, default=None, metavar="N/M^1.5",
                   help=f"Hertz contact stiffness in N/m^1.5 (default {PAPER_K_HERTZ:g}, or from "
                        "--material/--surface when given)")
    g.add_argument("--material", default=None, metavar="NAME",
                   help="sphere material from the catalogue (sets density and, with --surface, K_HZ)")
    g.add_argument("--surface", default=None, metavar="NAME",
                   help="surface material from the catalogue (default: same as --material, else steel)")
    g.add_argument("--density", type=float, default=None, metavar="KG/M^3",
                   help=f"sphere density in kg/m^3 (default {PAPER_DENSITY:g} or the material's)")
    g.add_argument("--mass", type=float, default=None, metavar="KG",
                   help="sphere mass in kg (replaces --density)")
    g.add_argument("--pulse", default="half-sine", choices=PULSES,
                   help="acceleration pulse: the paper's peak-matched half-sine (default), an "
                        "impulse-matched half-sine, or the exact Hertz pulse")
    m = parser.add_argument_group("medium")
    m.add_argument("--c", type=float, default=DEFAULT_SOUND_SPEED, metavar="M/S",
                   help="speed of sound in m/s (default %(default)s, air at 20 degC)")
    m.add_argument("--rho", type=float, default=DEFAULT_AIR_DENSITY, metavar="KG/M^3",
                   help="density of the fluid in kg/m^3 (default %(default)s, air at 20 degC)")
    c = parser.add_argument_group("configuration")
    c.add_argument("--config", default="free", choices=CONFIGURATIONS,
                   help="free field, a reflecting plane (floor), or a wall-floor corner (default free)")
    c.add_argument("--wall-distance", type=float, default=None, metavar="M",
                   help="wall-floor only: distance in m from the wall to the sphere's centre "
                        f"(default {DEFAULT_WALL_DISTANCE:g})")
    c.add_argument("--strike", default="floor", choices=STRIKES,
                   help="wall-floor only: the struck surface; 'wall' puts the sphere against the wall, "
                        "accelerating along +x (default floor)")
    c.add_argument("--height", type=float, default=None, metavar="M",
                   help="wall strike only: height in m of the sphere's centre above the floor "
                        "(default: the radius, a ball in the corner)")


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


def room_settings(args, *, duration=None) -> dict | None:
    """The room settings of the options (:func:`acoustiviz.app.impacts.room_settings`); None without ``--room``."""
    from ..app.impacts import room_settings as _room_settings

    return _room_settings(args.room, absorption=args.absorption, source=args.source, strike=args.room_strike,
                          order=args.image_order, tolerance_db=args.tolerance_db, duration=duration,
                          config=getattr(args, "config", None))


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
    g.add_argument("--distance", type=float, default=PAPER_DISTANCE, metavar="M",
                   help="observer distance in m from the sphere's centre (default %(default)s)")
    if angle:
        g.add_argument("--angle", type=float, default=PAPER_ANGLE_DEG, metavar="DEG",
                       help="observer angle in degrees from the acceleration axis (the surface "
                            "normal) (default %(default)s)")


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
    from ..app.names import IMPACT_OPTIONS, ROOM_OPTIONS, user_terms

    room = room_settings(args, duration=getattr(args, "duration", None)) if hasattr(args, "room") else None
    terms = {**IMPACT_OPTIONS, **ROOM_OPTIONS} if room is not None else IMPACT_OPTIONS
    with user_terms(terms):
        return impact_setup(radius=args.radius, velocity=args.velocity if velocity is None else velocity,
                            k_hertz=args.k_hertz, sphere_material=args.material, surface_material=args.surface,
                            density=args.density, mass=args.mass, pulse=args.pulse, c=args.c, rho=args.rho,
                            config=args.config, wall_distance=args.wall_distance,
                            strike=getattr(args, "strike", "floor"), height=getattr(args, "height", None),
                            room=room)


def observer_point(setup, distance: float, angle_deg: float):
    """The observer of ``--distance`` (m) and ``--angle`` (degrees) (:func:`acoustiviz.app.impacts.observer_point`)."""
    from ..app.impacts import observer_point as _observer_point
    from ..app.names import IMPACT_OPTIONS, user_terms

    with user_terms(IMPACT_OPTIONS):
        return _observer_point(setup, distance, angle_deg)
