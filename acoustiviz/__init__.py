"""acoustiviz: see and hear the noise of impact dampers.

The package is laid out in layers, each importing only from those below it:

``core``
    medium, materials, Hertz contact, rigid-sphere radiation, image sources (no grids, no files);
``dynamics``
    the impact damper (paper eq 15) and its solvers;
``field``
    pressure over points and grids; ``levels``: weighted levels, spectra and loudness;
``sweep``
    design sweeps and the design table;
``output``
    plots, pyvista renders, WAV files and other writers;
``app``
    the application layer that both front-ends call: ``scene`` files and the ``cli``.

``constants`` and ``errors`` are the one home of the package's facts and exceptions. Importing
the package imports only the light core and has no side effect.
"""

from .core.contact import (
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
from .core.materials import Material, catalogue, material
from .core.medium import AIR, Medium, air_at
from .core.radiation import impulse_response, pressure, pulse_response, sphere_pressure
from .errors import AccuracyWarning, ClippingWarning, ParameterError

__version__ = "0.1.0"

#: Names importable from ``acoustiviz`` that live in heavier modules, imported on first use.
_LAZY = {
    "configuration": "core.geometry",
    "images_free": "core.geometry",
    "images_plane": "core.geometry",
    "images_wall_floor": "core.geometry",
    "geometry": "core.geometry",
    "time_series": "field",
    "field_metrics": "field",
    "snapshots": "field",
    "directivity": "field",
    "spherical_grid": "field.grids",
    "planar_grid": "field.grids",
    "DamperModel": "dynamics",
    "InitialState": "dynamics",
    "simulate": "dynamics",
    "exact_maxima": "dynamics",
    "write_impact_table": "output.tables",
    "load_scene": "scene",
    "run_scene": "app.pipeline",
}


def __getattr__(name):
    """Import the lazily exported names (:data:`_LAZY`) on first access."""
    import importlib

    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'acoustiviz' has no attribute {name!r}")

__all__ = [
    "AIR",
    "AccuracyWarning",
    "ClippingWarning",
    "ParameterError",
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
