"""acoustiviz: see and hear the noise of impact dampers.

The physics core (``medium``, ``materials``, ``contact``, ``radiation``, ``images``,
``dynamics``) knows nothing of grids, plots or files; ``field`` and ``grids`` evaluate it over
points; ``plot``, ``render``, ``audio``, ``scene`` and ``cli`` sit on top. Importing the package
has no side effects and imports only the light core.
"""

from .contact import (
    HERTZ_DURATION_CONSTANT,
    HalfSinePulse,
    Impact,
    SampledPulse,
    acceleration_pulse,
    contact_duration,
    hertz_stiffness,
    max_approach,
    peak_acceleration,
    restitution,
)
from .materials import Material, catalogue, material
from .medium import AIR, Medium, air_at
from .radiation import impulse_response, pressure, pulse_response, sphere_pressure

__version__ = "0.1.0"

#: Names importable from ``acoustiviz`` that live in heavier modules, imported on first use.
_LAZY = {
    "configuration": "images",
    "images_free": "images",
    "images_plane": "images",
    "images_wall_floor": "images",
    "time_series": "field",
    "field_metrics": "field",
    "snapshots": "field",
    "directivity": "field",
    "spherical_grid": "grids",
    "planar_grid": "grids",
    "DamperModel": "dynamics",
    "InitialState": "dynamics",
    "simulate": "dynamics",
    "load_scene": "scene",
    "run_scene": "pipeline",
}


def __getattr__(name):
    """Import the lazily exported names (:data:`_LAZY`) on first access."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'acoustiviz' has no attribute {name!r}")

__all__ = [
    "AIR",
    "HERTZ_DURATION_CONSTANT",
    "HalfSinePulse",
    "Impact",
    "Material",
    "Medium",
    "SampledPulse",
    "acceleration_pulse",
    "air_at",
    "catalogue",
    "contact_duration",
    "hertz_stiffness",
    "impulse_response",
    "material",
    "max_approach",
    "peak_acceleration",
    "pressure",
    "pulse_response",
    "restitution",
    "sphere_pressure",
    *_LAZY,
]
