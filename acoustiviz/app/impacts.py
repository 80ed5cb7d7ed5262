"""One impact from a user's settings: sphere, contact, pulse, medium, configuration, observers.

:func:`impact_setup` holds every rule that turns the settings a user gives (radius, mass or
density or material, K_HZ or materials, pulse, fluid, configuration) into the physics objects;
``acoustiviz waveform``, ``directivity``, ``render`` and scene files all call it, so they resolve
defaults and conflicts the same way. Errors name the API parameter, or what the user typed where a
front end passes its ``names`` (:meth:`acoustiviz.app.settings.base.Settings.names_for`). SI units; angles
in degrees only where a name says ``_deg``.

Examples
--------
>>> s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config="plane")
>>> round(s.impact.mass, 4), s.geometry.name, s.k_hertz_source
(0.2259, 'plane', 'given')
>>> observer_point(s, 0.7, 45.0).round(4)
array([0.495, 0.   , 0.514])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import check_choice, check_positive, check_range
from ..constants import (
    PAPER_DENSITY,
    PAPER_K_HERTZ,
    PAPER_RADIUS,
    PULSES,
    STRIKES,
)
from ..core.contact import Impact, acceleration_pulse, hertz_stiffness
from ..core.geometry import CONFIGURATIONS, Geometry, geometry, geometry_class, observer_points
from ..core.limits import check_impact, check_sphere_mass
from ..core.materials import material
from ..core.medium import AIR, Medium
from ..errors import ParameterError, user_terms

#: Farthest observer in m: squared distances stay finite (:data:`acoustiviz.core.limits.LOG_LIMIT`).
MAX_DISTANCE = 1e145

__all__ = ["ImpactSetup", "impact_setup", "observer_point", "sphere_mass", "k_hertz_from"]

@dataclass(frozen=True)
class ImpactSetup:
    """One impact and everything around it.

    Attributes
    ----------
    impact : Impact
        Speed (m/s), K_HZ (N/m^1.5) and masses (kg).
    pulse : HalfSinePulse or SampledPulse
        Its acceleration pulse (m/s² against s).
    radius : float
        Sphere radius in m.
    medium : Medium
        The fluid.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its image sources.
    k_hertz_source : str
        Where K_HZ came from: ``"given"``, ``"Hertz, steel on steel"`` or ``"default (paper)"``.
    """

    impact: Impact
    pulse: object
    radius: float
    medium: Medium
    geometry: Geometry
    k_hertz_source: str


def _material(param: str, name: str):
    """The catalogue material ``name``; an unknown name is an error about ``param``."""
    try:
        return material(name)
    except ParameterError as exc:
        raise exc.renamed(param) from None


def k_hertz_from(radius: float, k_hertz=None, sphere_material=None, surface_material=None) -> tuple:
    """K_HZ in N/m^1.5 and where it came from: given, from the materials (paper eq 2), or the paper's.

    A given K_HZ excludes a surface material (which serves only to compute K_HZ); a sphere
    material alone still sets the density. Without K_HZ, a missing sphere material is steel and a
    missing surface is the sphere's material.
    """
    if k_hertz is not None:
        if surface_material is not None:
            raise ParameterError("k_hertz", "give either K_HZ or a surface material (from which K_HZ follows), "
                                            "not both")
        return check_positive("k_hertz", k_hertz, "N/m^1.5"), "given"
    if sphere_material is None and surface_material is None:
        return PAPER_K_HERTZ, "default (paper)"
    s_mat = _material("sphere_material", sphere_material or "steel")
    f_mat = _material("surface_material", surface_material) if surface_material else s_mat
    return hertz_stiffness(radius, s_mat, f_mat), f"Hertz, {s_mat.name} on {f_mat.name}"


def sphere_mass(radius: float, mass=None, density=None, sphere_material=None, *, names=None) -> float:
    """Sphere mass in kg: given, else density (given, the material's, or steel's 7800 kg/m³) × volume.

    ``names``: API parameter -> the option or scene key its errors name (default: the API parameter).
    """
    with user_terms(names or {}):
        return _sphere_mass(radius, mass, density, sphere_material)


def _sphere_mass(radius: float, mass, density, sphere_material) -> float:
    """The body of :func:`sphere_mass`; errors name the API parameters."""
    if mass is not None:
        if density is not None:
            raise ParameterError("mass", "give either the mass or the density, not both")
        return check_positive("mass", mass, "kg")
    if density is not None:
        rho = check_positive("density", density, "kg/m^3")
        # blame the setting farther from an ordinary sphere (the paper's steel ball)
        off_rho, off_a = abs(math.log10(rho / PAPER_DENSITY)), abs(math.log10(radius / PAPER_RADIUS))
        return check_sphere_mass(radius, rho, "density" if off_rho > off_a else "radius")
    if sphere_material is not None:
        rho = _material("sphere_material", sphere_material).density
    else:
        rho = PAPER_DENSITY
    return check_sphere_mass(radius, rho)


def impact_setup(*, radius: float, velocity: float, k_hertz=None, sphere_material=None, surface_material=None,
                 density=None, mass=None, pulse: str = "half-sine", c: float = AIR.c, rho: float = AIR.rho,
                 config: str = "free", wall_distance=None, strike: str = "floor", height=None,
                 partner_mass: float = math.inf, room=None, names=None) -> ImpactSetup:
    """Validate the settings of one impact and build its physics objects.

    Parameters
    ----------
    radius : float
        Sphere radius a in m.
    velocity : float
        Impact (approach) speed U0 in m/s.
    k_hertz : float, optional
        Hertz stiffness in N/m^1.5 (default: from the materials, else the paper's 5.6e8).
    sphere_material, surface_material : str, optional
        Names in the materials catalogue.
    density : float, optional
        Sphere density in kg/m³ (default: the material's, else 7800).
    mass : float, optional
        Sphere mass in kg (replaces the density).
    pulse : {"half-sine", "impulse-matched", "hertz"}
        The acceleration pulse.
    c, rho : float
        Speed of sound (m/s) and density (kg/m³) of the fluid.
    config : {"free", "plane", "wall-floor"}
        Reflecting surfaces.
    wall_distance : float, optional
        Wall-floor, floor strike: distance in m from the wall to the sphere's centre (default 0.05).
    strike : {"floor", "wall"}
        Wall-floor: the struck surface; a wall strike puts the sphere against the wall.
    height : float, optional
        Wall strike: height in m of the sphere's centre above the floor (default: the radius).
    partner_mass : float
        Mass in kg of the struck body (default infinite: an immovable wall, paper eq 3).
    room : dict, optional
        The settings of a shoebox room (:class:`acoustiviz.core.geometry.Room`: ``dimensions``,
        ``absorption``, ``source``, ``strike``, ``duration``, ...); replaces ``config`` and its settings.
    names : dict, optional
        API parameter -> the option or scene key its errors name (default: the API parameter).

    Returns
    -------
    ImpactSetup
    """
    with user_terms(names or {}):
        return _impact_setup(radius, velocity, k_hertz, sphere_material, surface_material, density, mass, pulse, c,
                             rho, config, wall_distance, strike, height, partner_mass, room)


def _impact_setup(radius, velocity, k_hertz, sphere_material, surface_material, density, mass, pulse, c, rho, config,
                  wall_distance, strike, height, partner_mass, room) -> ImpactSetup:
    """The body of :func:`impact_setup`; errors name the API parameters."""
    radius = check_positive("radius", radius, "m")
    velocity = check_positive("velocity", velocity, "m/s")
    check_choice("pulse", pulse, PULSES)
    if room is None:
        check_choice("config", config, CONFIGURATIONS)
        check_choice("strike", strike, STRIKES)
    medium = Medium(c=check_positive("c", c, "m/s"), rho=check_positive("rho", rho, "kg/m^3"))
    if sphere_material is not None:
        _material("sphere_material", sphere_material)  # an unknown name fails here, naming the catalogue
    k, source = k_hertz_from(radius, k_hertz, sphere_material, surface_material)
    m = sphere_mass(radius, mass, density, sphere_material)
    check_impact(velocity, k, m, partner_mass, radius=radius, c=medium.c, rho=medium.rho)
    if room is not None:  # the room's own settings (Room.from_settings validates them all)
        geom = geometry("room", radius, **{"sound_speed": medium.c, **room})
        _check_struck(geom)
    else:
        geom = geometry(config, radius, wall_distance=wall_distance, strike=strike, height=height)
    impact = Impact(velocity=velocity, k_hertz=k, mass=m, partner_mass=partner_mass)
    return ImpactSetup(impact, acceleration_pulse(impact, pulse), radius, medium, geom, source)


def _check_struck(room) -> None:
    """Refuse a room's sphere away from the surface it strikes: an impact needs the two in contact."""
    if room.touches_struck_surface:
        return
    ax, value = room.contact_coordinate
    name = "xyz"[ax]
    raise ParameterError("source", f"the sphere must touch the {room.strike} it strikes: {name} = {value:g} m "
                                   f"(its radius {room.radius:g} m from that surface), got {name} = "
                                   f"{room.source[ax]:g} m")


def observer_point(setup: ImpactSetup, distance: float, angle_deg: float, *, names=None) -> np.ndarray:
    """Observer at ``distance`` m from the sphere's centre and ``angle_deg`` degrees from its axis.

    The observer lies in the plane spanned by the acceleration axis and the horizontal direction
    away from any wall (+x); for the wall-floor corner, the plane through the centre normal to
    the wall, on the side away from it (:func:`acoustiviz.core.geometry.Geometry.observer_points`).

    ``names``: API parameter -> the option or scene key its errors name (default: the API parameter).

    Returns
    -------
    (3,) ndarray
        Position in m.
    """
    with user_terms(names or {}):
        return _observer_point(setup, distance, angle_deg)


def _observer_point(setup: ImpactSetup, distance: float, angle_deg: float) -> np.ndarray:
    """The body of :func:`observer_point`; errors name the API parameters."""
    check_range("distance", distance, setup.radius, MAX_DISTANCE, unit="m", low_open=True)
    limit = setup.geometry.polar_limit_deg
    theta = math.radians(check_range("angle_deg", angle_deg, 0.0, limit, unit="deg"))
    point = observer_points(setup.geometry, distance, theta)[0]
    if not bool(setup.geometry.in_fluid(point[None, :])[0]):
        raise ParameterError("angle_deg", "the observer would lie inside a wall or below the floor")
    return point


def room_settings(dimensions, *, absorption=None, source=None, strike="floor", order=None, tolerance_db=None,
                  duration=None, config=None, names=None, max_memory_mb=None) -> dict | None:
    """The settings of a room as given (text or numbers, for :class:`acoustiviz.core.geometry.Room` to check).

    Without ``dimensions`` there is no room (None), and a room setting given anyway is refused,
    naming it; so is a configuration other than the free field given with a room.

    Parameters
    ----------
    dimensions : str or sequence, optional
        ``LX,LY,LZ`` in m.
    absorption, source, strike, order, tolerance_db, duration
        The room's settings (:class:`~acoustiviz.core.geometry.Room`); None: its default.
    config : str, optional
        The configuration asked for besides the room.
    names : dict, optional
        Setting -> the option named in errors (default :data:`acoustiviz.app.names.ROOM_OPTIONS`).
    max_memory_mb : float, optional
        The memory budget in MB that caps the image order (default the room's).
    """
    from .names import ROOM_OPTIONS

    names = ROOM_OPTIONS if names is None else names
    room = names["dimensions"]
    if dimensions is None:
        given = {"absorption": absorption, "source": source, "order": order, "tolerance_db": tolerance_db}
        for key, val in given.items():
            if val is not None:
                raise ParameterError(names[key], f"only applies with {room} LX,LY,LZ")
        if strike != "floor":
            raise ParameterError(names["strike"], f"only applies with {room} LX,LY,LZ")
        return None
    if config is not None and geometry_class(config).reflecting and not geometry_class(config).enclosed:
        raise ParameterError(names.get("config", "--config"), f"give either {names.get('config', '--config')} or "
                                                              f"{room}, not both")
    out = {"dimensions": dimensions, "absorption": absorption, "source": source, "strike": strike, "order": order,
           "tolerance_db": tolerance_db, "duration": duration, "max_memory_mb": max_memory_mb}
    return {k: v for k, v in out.items() if v is not None}
