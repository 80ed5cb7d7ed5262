"""Audio sinks: calibrated WAV files and their JSON sidecars, written atomically.

The signals come from :mod:`acoustiviz.sound` (impact trains rendered at listeners, in Pa);
this package only writes them.

Calibration
-----------
Files meant for listening are normalised ``"PCM_24"`` with one scale (Pa per full scale) shared by
all files of a run (:func:`shared_scale`), the run's peak 1 dB below full scale; the application
layer writes them by default. :func:`write_wav` also writes float32 (``subtype="FLOAT"``), by
default in pascals: a sample value 1.0 is 1 Pa (94 dB SPL). Nothing is clipped
silently: a PCM sample beyond full scale raises a :class:`ClippingWarning` saying by how many dB
and is recorded in the sidecar. A JSON sidecar (``OUT.json`` beside ``OUT.wav``) records the
scale, rate, subtype, listeners, scene, pulse, modelling choices, impact count and peak SPL.

All quantities are SI (s, m, kg, m/s, Pa, Hz) unless a name says otherwise (``_db``).
"""

from __future__ import annotations

from ...errors import ClippingWarning
from .wav import SUBTYPES, shared_scale, sidecar_path, write_sidecar, write_wav

__all__ = [
    "SUBTYPES",
    "ClippingWarning",
    "shared_scale",
    "write_wav",
    "write_sidecar",
    "sidecar_path",
]
