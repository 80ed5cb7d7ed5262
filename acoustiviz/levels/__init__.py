"""Levels: how loud an impact sounds to people and to standards, and how much of its energy becomes sound.

Pure functions of one :class:`~acoustiviz.core.signal.Signal` (pressure in Pa, its sample rate in
Hz, the time of its first sample in s), so they serve a computed waveform, a damper run at a
listener, a WAV read back with its calibration, a design of a sweep or a point of a directivity
alike. Nothing here writes files.

* :mod:`.weighted` -- LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL and SEL(A) (IEC 61672-1);
* :mod:`.transient` -- the same levels of a signal silent after its first samples, from those
  samples and the filters' exact free response (one click over 1 s);
* :mod:`.train` -- the same levels of a train of short sounds in a long silence, from the sounds
  alone and the filters' states carried exactly across the silences (a damper run's clicks);
* :mod:`.bands` -- 1/3-octave band Leq and LFmax (IEC 61260-1 filters);
* :mod:`.hearing` -- ISO 532-1 loudness (N5, Nmax) and DIN 45692 sharpness (optional mosqito);
* :mod:`.energy` -- sound energy of one impact (closed form and spherical-grid intensity),
  radiation efficiency, and the energy and sound power of a damper run.

The weighting and band filters are written from IEC 61672-1 and IEC 61260-1 (:mod:`._filters`,
named in one place by :mod:`._library`) and tested against the standards' tables and acceptance
limits and against PyOctaveBand.
"""

from __future__ import annotations

from .bands import BAND_LIMITS, BandLevels, band_energy_sum, third_octave_levels
from .energy import (
    RunEnergy,
    pulse_spectrum,
    radiated_energy_free,
    radiated_energy_grid,
    radiation_efficiency,
    radiation_resistance,
    run_energy,
    sound_power,
    surface_work_free,
)
from .hearing import Loudness, loudness, loudness_available
from .train import train_levels
from .transient import transient_levels
from .weighted import LEVEL_COLUMNS, METRICS, SoundLevels, level_db, metric_levels, sound_levels, weighted

__all__ = [
    "BAND_LIMITS",
    "LEVEL_COLUMNS",
    "METRICS",
    "BandLevels",
    "Loudness",
    "RunEnergy",
    "SoundLevels",
    "band_energy_sum",
    "level_db",
    "loudness",
    "loudness_available",
    "metric_levels",
    "pulse_spectrum",
    "radiated_energy_free",
    "radiated_energy_grid",
    "radiation_efficiency",
    "radiation_resistance",
    "run_energy",
    "sound_levels",
    "sound_power",
    "surface_work_free",
    "third_octave_levels",
    "train_levels",
    "transient_levels",
    "weighted",
]
