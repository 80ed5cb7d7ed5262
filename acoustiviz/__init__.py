"""acoustiviz: see and hear the noise of impact dampers.

The package is laid out in layers, each importing only from those below it:

``core``
    medium, materials, Hertz contact, rigid-sphere radiation, image sources (no grids, no files);
``dynamics``
    the impact damper (paper eq 15) and its solvers;
``field``
    pressure over points and grids; ``levels``: weighted levels, spectra and loudness;
``sound``
    sound synthesis: impact trains rendered as calibrated pressure signals at listeners;
``output``
    sinks only: plots, pyvista renders, WAV, VTK and HTML files;
``sweep``
    design sweeps and the design table;
``app``
    the application layer that both front-ends call: ``scene`` files and the ``cli``.

``constants`` and ``errors`` are the one home of the package's facts and exceptions; ``files``
writes every file of the package atomically. Importing the package imports nothing else and has
no side effect: each name is imported on first use.
"""

__version__ = "0.1.0"

#: Every name importable from ``acoustiviz`` and its module, imported on first use (so that importing
#: the package, and ``acoustiviz --help``, loads no numpy).
_LAZY = {
    "HERTZ_DURATION_CONSTANT": "core.contact",
    "HalfSinePulse": "core.contact",
    "Impact": "core.contact",
    "SampledPulse": "core.contact",
    "acceleration_pulse": "core.contact",
    "contact_duration": "core.contact",
    "hertz_stiffness": "core.contact",
    "max_approach": "core.contact",
    "peak_acceleration": "core.contact",
    "restitution": "core.contact",
    "Material": "core.materials",
    "catalogue": "core.materials",
    "material": "core.materials",
    "AIR": "core.medium",
    "Medium": "core.medium",
    "air_at": "core.medium",
    "impulse_response": "core.radiation",
    "pressure": "core.radiation",
    "pulse_response": "core.radiation",
    "sphere_pressure": "core.radiation",
    "Signal": "core.signal",
    "Listener": "core.listener",
    "AccuracyWarning": "errors",
    "ClippingWarning": "errors",
    "ParameterError": "errors",
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


__all__ = list(_LAZY)


def __dir__():
    """The package's public names (:data:`__all__`), for ``dir()`` and tab completion."""
    return sorted(__all__)

