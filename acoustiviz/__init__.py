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
]
