"""Settings of one impact heard at one observer: ``acoustiviz waveform`` and ``acoustiviz directivity``.

The same records build the scene's ``[outputs.directivity]`` keys and the room window
``configuration.window_s``; a waveform's sampling is a command-line setting (a scene tabulates
at the default).
"""

from __future__ import annotations

import dataclasses
import math

from ...constants import (
    CONFIGURATIONS,
    DEFAULT_AIR_DENSITY,
    DEFAULT_SOUND_SPEED,
    DEFAULT_WALL_DISTANCE,
    DIRECTIVITY_METRICS,
    PAPER_ANGLE_DEG,
    PAPER_DENSITY,
    PAPER_DISTANCE,
    PAPER_K_HERTZ,
    PAPER_RADIUS,
    PAPER_VELOCITY,
    PULSES,
    STRIKES,
)
from .base import Settings
from .table import Setting
from .vocabulary import ALIASES, MEMORY

__all__ = ["IMPACT_GROUPS", "IMPACT", "OBSERVER", "WAVEFORM", "DIRECTIVITY", "WaveformSettings", "DirectivitySettings",
           "MIN_SAMPLES_PER_DURATION", "ImpactJob"]

#: Fewest time samples per contact duration a waveform is drawn or tabulated with.
MIN_SAMPLES_PER_DURATION = 200

#: The impact, its medium and its surroundings as the commands of one impact take them: ``(--help group, records)``.
IMPACT_GROUPS = (
    ("impact (SI units)", (
        Setting("radius", "--radius", "radius_m", "float", PAPER_RADIUS, "sphere radius", "m", low=0.0, high=1.0,
                low_open=True, table="sphere"),
        Setting("velocity", "--velocity", "velocity_m_s", "float", PAPER_VELOCITY,
                "impact (approach) speed of the single impact", "m/s", low=0.0, high=1e3, low_open=True,
                table="impact", metavar="M/S"),
        Setting("k_hertz", "--k-hertz", None, "float", None,
                f"Hertz contact stiffness in N/m^1.5 (default {PAPER_K_HERTZ:g}, or from --material/--surface when "
                "given)", "N/m^1.5", low=0.0, high=1e14, low_open=True, metavar="N/M^1.5"),
        Setting("material", "--material", "material", "str", None,
                "sphere material from the catalogue (sets density and, with --surface, K_HZ)", metavar="NAME",
                table="sphere", scene_doc="sphere material from the catalogue (sets density; with contact.surface, "
                "K_HZ)"),
        Setting("surface", "--surface", "surface", "str", None,
                "surface material from the catalogue (default: same as --material, else steel)", metavar="NAME",
                table="contact",
                scene_doc="surface material from the catalogue (K_HZ from sphere and surface materials)"),
        Setting("density", "--density", "density_kg_m3", "float", None,
                f"sphere density (default {PAPER_DENSITY:g} or the material's)", "kg/m^3", low=0.0, high=1e5,
                low_open=True, table="sphere", metavar="KG/M^3"),
        Setting("mass", "--mass", "mass_kg", "float", None, "sphere mass; replaces the density", "kg", low=0.0,
                high=1e4, low_open=True, table="sphere", metavar="KG"),
        Setting("pulse", "--pulse", "pulse", "str", "half-sine",
                "acceleration pulse: the paper's peak-matched half-sine, an impulse-matched half-sine, or the exact "
                "Hertz pulse", choices=PULSES, table="contact", scene_doc="acceleration pulse"),
    )),
    ("medium", (
        Setting("c", "--c", "c_m_s", "float", DEFAULT_SOUND_SPEED, "speed of sound in the fluid",
                "m/s", low=1.0, high=1e5, table="medium", metavar="M/S"),
        Setting("rho", "--rho", "rho_kg_m3", "float", DEFAULT_AIR_DENSITY,
                "density of the fluid", "kg/m^3", low=1e-3, high=1e5, table="medium",
                metavar="KG/M^3"),
    )),
    ("configuration", (
        Setting("config", "--config", None, "str", "free",
                "free field, a reflecting plane (floor), or a wall-floor corner", choices=CONFIGURATIONS),
        Setting("wall_distance", "--wall-distance", "wall_distance_m", "float", None,
                f"wall-floor only: distance in m from the wall to the sphere's centre (default "
                f"{DEFAULT_WALL_DISTANCE:g})", "m", low=0.0, high=100.0, low_open=True,
                scene_default=DEFAULT_WALL_DISTANCE, table="configuration"),
        Setting("strike", "--strike", None, "str", "floor",
                "wall-floor only: the struck surface; 'wall' puts the sphere against the wall, accelerating along +x",
                choices=STRIKES),
        Setting("height", "--height", "height_m", "float", None,
                "wall strike only: height in m of the sphere's centre above the floor (default: the radius, a ball in "
                "the corner)", "m", low=0.0, high=100.0, low_open=True, table="configuration"),
    )),
)

#: Every record of :data:`IMPACT_GROUPS`.
IMPACT = tuple(s for _, records in IMPACT_GROUPS for s in records)

#: The one observer of ``acoustiviz waveform`` (and the distance of ``directivity``): no range of their own, the
#: observer must lie in the fluid (:func:`acoustiviz.app.impacts.observer_point`).
OBSERVER = (
    Setting("distance", "--distance", None, "float", PAPER_DISTANCE, "observer distance in m from the sphere's centre",
            "m"),
    Setting("angle_deg", "--angle", None, "float", PAPER_ANGLE_DEG,
            "observer angle in degrees from the acceleration axis (the surface normal)", "deg", metavar="DEG"),
)

WAVEFORM = (
    Setting("samples_per_duration", "--samples-per-duration", None, "int", 400,
            "time samples per contact duration", low=MIN_SAMPLES_PER_DURATION, high=math.inf),
    Setting("window", "--duration", "window_s", "float", None,
            "with --room (required): the window from the start of contact that the waveform and its images "
            "reach", "s",
            low=0.0, high=1e4, low_open=True, table="configuration"),
)

DIRECTIVITY = (
    Setting("step_deg", "--step", "step_deg", "float", 5.0, "angle step", "deg", low=0.0,
            high=90.0, low_open=True, table="outputs.directivity"),
    Setting("metric", "--metric", "metric", "str", "peak-spl",
            "level shown against angle besides peak, RMS and SPL: peak-spl (none, max|p|), rms (RMS level over the "
            "window), or a weighted level computed from the impact's pressure at each angle, band-limited at 96 kHz: "
            "lcpeak, lafmax, laeq (over 1 s from the first arrival), sel-a, lzpeak, lasmax, lzeq, sel",
            choices=tuple(DIRECTIVITY_METRICS), table="outputs.directivity"),
)


@dataclasses.dataclass(frozen=True)
class WaveformSettings(Settings):
    """How a waveform is tabulated: its sampling and, in a room, its window in s."""

    TABLE = WAVEFORM
    samples_per_duration: int = 400
    window: float | None = None


@dataclasses.dataclass(frozen=True)
class DirectivitySettings(Settings):
    """The angles of a directivity and the further level shown against them."""

    TABLE = DIRECTIVITY
    step_deg: float = 5.0
    metric: str = "peak-spl"


@dataclasses.dataclass(frozen=True, kw_only=True)
class ImpactJob(Settings):
    """The base of the jobs of one impact (waveform, directivity, map, render): the impact, its fluid and surroundings.

    Its fields are keyword-only, and so are its subclasses' (``WaveformJob(impact=..., pulses=..., ...)``);
    each subclass adds its pulse or pulses, its sampling and its files.

    Attributes
    ----------
    impact : acoustiviz.core.contact.Impact
        Speed (m/s), K_HZ (N/m^1.5) and masses (kg) of the impact.
    medium : acoustiviz.core.medium.Medium
        The fluid.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its image sources (in a room, its window in s ends the job's sound).
    max_memory_mb : float, optional
        Cap in MB on the working memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).
    k_hertz_source : str
        Where K_HZ came from (reported; not compared).
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name
        (not compared; default: the API names).
    """

    BUILT_FROM = MEMORY  # the memory cap of every impact job
    ALIASES = ALIASES["memory"]

    impact: object
    medium: object
    geometry: object
    max_memory_mb: float | None = None
    k_hertz_source: str = dataclasses.field(default="given", compare=False)
    names: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)

    @property
    def window(self) -> float | None:
        """In a room, the window in s from the start of contact the job's sound covers; None elsewhere."""
        return getattr(self.geometry, "duration", None)

    @property
    def in_room(self) -> bool:
        """True when the geometry is a room (its image model is reported, its peaks are the window's)."""
        return getattr(self.geometry, "image_order", None) is not None

    def _name(self, api: str) -> str:
        """The option or scene key of API parameter ``api`` (itself without one)."""
        return self.names.get(api, api)
