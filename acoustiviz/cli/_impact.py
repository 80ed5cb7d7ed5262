"""Impact, medium, configuration and observer options shared by several subcommands.

Defaults reproduce the paper's Figure 2 scene: a sphere of radius 19.05 mm and density
7800 kg/m³ striking at 1.4 m/s with K_HZ = 5.6e8 N/m^1.5, heard at 0.7 m and 45°.
Angles are in degrees on the command line only; everything else is SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .._validate import ParameterError, check_choice, check_positive, check_range

__all__ = [
    "add_impact_options",
    "add_observer_options",
    "ImpactSetup",
    "impact_from_args",
    "observer_point",
    "CONFIGS",
]

CONFIGS = ("free", "plane", "wall-floor")
DEFAULT_RADIUS = 0.01905
DEFAULT_VELOCITY = 1.4
DEFAULT_K_HERTZ = 5.6e8
DEFAULT_DENSITY = 7800.0


def add_impact_options(parser, *, velocity: bool = True) -> None:
    """Add the sphere, contact, pulse, medium and configuration options to ``parser``."""
    g = parser.add_argument_group("impact (SI units)")
    g.add_argument("--radius", type=float, default=DEFAULT_RADIUS, metavar="M",
                   help="sphere radius in m (default %(default)s)")
    if velocity:
        g.add_argument("--velocity", type=float, default=DEFAULT_VELOCITY, metavar="M/S",
                       help="impact (approach) speed in m/s (default %(default)s)")
    g.add_argument("--k-hertz", type=float, default=None, metavar="N/M^1.5",
                   help=f"Hertz contact stiffness in N/m^1.5 (default {DEFAULT_K_HERTZ:g}, or from "
                        "--material/--surface when given)")
    g.add_argument("--material", default=None, metavar="NAME",
                   help="sphere material from the catalogue (sets density and, with --surface, K_HZ)")
    g.add_argument("--surface", default=None, metavar="NAME",
                   help="surface material from the catalogue (default: same as --material, else steel)")
    g.add_argument("--density", type=float, default=None, metavar="KG/M^3",
                   help=f"sphere density in kg/m^3 (default {DEFAULT_DENSITY:g} or the material's)")
    g.add_argument("--mass", type=float, default=None, metavar="KG",
                   help="sphere mass in kg (replaces --density)")
    g.add_argument("--pulse", default="half-sine", choices=("half-sine", "impulse-matched", "hertz"),
                   help="acceleration pulse: the paper's peak-matched half-sine (default), an "
                        "impulse-matched half-sine, or the exact Hertz pulse")
    m = parser.add_argument_group("medium")
    m.add_argument("--c", type=float, default=343.2, metavar="M/S",
                   help="speed of sound in m/s (default %(default)s, air at 20 degC)")
    m.add_argument("--rho", type=float, default=1.204, metavar="KG/M^3",
                   help="density of the fluid in kg/m^3 (default %(default)s, air at 20 degC)")
    c = parser.add_argument_group("configuration")
    c.add_argument("--config", default="free", choices=CONFIGS,
                   help="free field, a reflecting plane (floor), or a wall-floor corner (default free)")
    c.add_argument("--wall-distance", type=float, default=None, metavar="M",
                   help="wall-floor only: distance in m from the wall to the sphere's centre "
                        "(default 0.05)")
    c.add_argument("--strike", default="floor", choices=("floor", "wall"),
                   help="wall-floor only: the struck surface; 'wall' puts the sphere against the wall, "
                        "accelerating along +x (default floor)")
    c.add_argument("--height", type=float, default=None, metavar="M",
                   help="wall strike only: height in m of the sphere's centre above the floor "
                        "(default: the radius, a ball in the corner)")


def add_observer_options(parser, *, angle: bool = True) -> None:
    """Add ``--distance`` (m) and ``--angle`` (degrees) for one observer."""
    g = parser.add_argument_group("observer")
    g.add_argument("--distance", type=float, default=0.7, metavar="M",
                   help="observer distance in m from the sphere's centre (default %(default)s)")
    if angle:
        g.add_argument("--angle", type=float, default=45.0, metavar="DEG",
                       help="observer angle in degrees from the acceleration axis (the surface "
                            "normal) (default %(default)s)")


@dataclass(frozen=True)
class ImpactSetup:
    """What the shared options describe: the impact, its pulse, the sphere, medium and geometry."""

    impact: object
    pulse: object
    radius: float
    medium: object
    configuration: object
    k_hertz_source: str


def _sphere_volume(radius: float) -> float:
    return 4.0 / 3.0 * math.pi * radius**3


def impact_from_args(args, *, velocity: float | None = None) -> ImpactSetup:
    """Validate the shared options (naming each option in errors) and build the objects.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options from :func:`add_impact_options`.
    velocity : float, optional
        Impact speed in m/s when the command has no ``--velocity`` option.
    """
    from ..contact import Impact, acceleration_pulse, hertz_stiffness
    from ..images import configuration
    from ..materials import material
    from ..medium import Medium

    radius = check_positive("--radius", args.radius, "m")
    u0 = velocity if velocity is not None else args.velocity
    u0 = check_positive("--velocity", u0, "m/s")
    medium = Medium(c=check_positive("--c", args.c, "m/s"), rho=check_positive("--rho", args.rho, "kg/m^3"))

    def lookup(option, name):
        try:
            return material(name)
        except ParameterError as exc:
            raise ParameterError(option, str(exc).split(": ", 1)[1]) from None

    sphere_mat = lookup("--material", args.material) if args.material else None
    surface_mat = lookup("--surface", args.surface) if args.surface else None
    if args.k_hertz is not None:
        if sphere_mat is not None and surface_mat is not None:
            raise ParameterError("--k-hertz", "give either --k-hertz or --material/--surface, not both")
        k = check_positive("--k-hertz", args.k_hertz, "N/m^1.5")
        source = "given"
    elif sphere_mat is not None or surface_mat is not None:
        s_mat = sphere_mat or lookup("--material", "steel")
        f_mat = surface_mat or s_mat
        k = hertz_stiffness(radius, s_mat, f_mat)
        source = f"Hertz, {s_mat.name} on {f_mat.name}"
    else:
        k = DEFAULT_K_HERTZ
        source = "default (paper)"

    if args.mass is not None:
        if args.density is not None:
            raise ParameterError("--mass", "give either --mass or --density, not both")
        mass = check_positive("--mass", args.mass, "kg")
    else:
        if args.density is not None:
            rho_s = check_positive("--density", args.density, "kg/m^3")
        else:
            rho_s = sphere_mat.density if sphere_mat is not None else DEFAULT_DENSITY
        mass = rho_s * _sphere_volume(radius)

    wall = args.wall_distance
    strike = getattr(args, "strike", "floor")
    height = getattr(args, "height", None)
    if args.config != "wall-floor":
        if wall is not None:
            raise ParameterError("--wall-distance", "only applies with --config wall-floor")
        if strike != "floor":
            raise ParameterError("--strike", "only applies with --config wall-floor")
    if height is not None and strike != "wall":
        raise ParameterError("--height", "only applies with --strike wall")
    if args.config == "wall-floor" and strike == "wall":
        if wall is not None:
            raise ParameterError("--wall-distance", "a wall strike puts the sphere against the wall; omit it")
        wall = radius
        height = radius if height is None else check_range("--height", height, radius, math.inf, unit="m")
    elif args.config == "wall-floor":
        wall = 0.05 if wall is None else wall
        check_range("--wall-distance", wall, radius, math.inf, unit="m")
    conf = configuration(check_choice("--config", args.config, CONFIGS), radius, wall_distance=wall,
                         strike=strike, height=height)

    impact = Impact(velocity=u0, k_hertz=k, mass=mass)
    pulse = acceleration_pulse(impact, args.pulse)
    return ImpactSetup(impact, pulse, radius, medium, conf, source)


def observer_point(setup: ImpactSetup, distance: float, angle_deg: float):
    """Observer at ``distance`` m from the sphere's centre, ``angle_deg`` from its acceleration axis.

    The observer lies in the plane spanned by the axis and the horizontal direction away from
    any wall (+x), i.e. for the wall-floor corner in the plane through the centre normal to the
    wall, on the side away from it.
    """
    from ..images import observer_points

    a = setup.radius
    check_range("--distance", distance, a, math.inf, unit="m", low_open=True)
    conf = setup.configuration
    limit = 90.0 if conf.name != "free" else 180.0
    theta = math.radians(check_range("--angle", angle_deg, 0.0, limit, unit="deg"))
    point = observer_points(conf, distance, theta)[0]
    if not bool(conf.in_fluid(point[None, :])[0]):
        raise ParameterError("--angle", "the observer would lie inside a wall or below the floor")
    return point
