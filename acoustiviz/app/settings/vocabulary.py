"""The words of values that several jobs share: the memory cap's records, the alias table, the derived names.

A job's vocabulary (:meth:`~acoustiviz.app.settings.base.Settings.names_for`) is made from records; these are
the records and aliases the jobs' ``BUILT_FROM`` and ``ALIASES`` take from one place.
"""

from __future__ import annotations

import dataclasses

from .run import MAX_MEMORY, MEMORY_LIMIT

__all__ = ["MEMORY", "ALIASES", "DERIVED", "OUTPUT_TABLES"]

#: The memory cap as every job names it: ``--max-memory`` on the command line, ``grids.memory_limit_mb`` in a
#: scene (the scene's record, under the API name ``max_memory_mb``).
MEMORY = (MAX_MEMORY, dataclasses.replace(MEMORY_LIMIT, name="max_memory_mb"))

#: API parameter -> the record it is spelled as, by the group of values it belongs to. ``room``: the window is
#: the waveform's ``--duration``, the sound speed the medium's ``--c``; ``sweep``: the sweep's and the design
#: table's parameters; ``memory``: the physics' name of the memory cap; ``room_sound``: the
#: :class:`~acoustiviz.sound.RoomSound` parameters as ``acoustiviz auralize`` and ``[outputs.wav]`` name them.
ALIASES = {
    "damper": {"v": "v0"},
    "impact": {"sphere_material": "material", "surface_material": "surface"},
    "room": {"dimensions": "room", "strike": "room_strike", "order": "image_order", "duration": "window",
             "sound_speed": "c"},
    "sweep": {"angle": "angle_deg", "radius_mode": "radius", "width": "band_width"},
    "memory": {"memory_limit": "max_memory_mb"},
    "room_sound": {"late_tail": "late_tail", "seed": "tail_seed", "decay": "tail_decay", "transition": "transition",
                   "band_centres": "absorption_bands", "band_absorption": "absorption_bands"},
}

#: Derived values with no record of their own -> their option (``"cli"``) or scene key (``"scene"``): the
#: listeners a scene lists (each one's distance and angle), and a sweep's folder and radius choice in a scene.
DERIVED = {
    "cli": {"listeners": "--listener"},
    "scene": {"listeners": "listeners", **{k: "listeners" for k in ("distance", "angle", "angle_deg")},
              "out": "outputs.sweep"},
}

#: A scene's files have no key of their own: a job's file setting -> the ``[outputs.*]`` table that asks for it.
OUTPUT_TABLES = {
    "damper": {"impacts_csv": "outputs.impact_table", "history_csv": "outputs.damper_history",
               "png": "outputs.damper_history"},
    "waveform": {"csv": "outputs.waveform", "png": "outputs.waveform"},
    "directivity": {"csv": "outputs.directivity", "png": "outputs.directivity"},
    "level_map": {k: "outputs.level_map" for k in ("png", "csv", "vtk")},
    "design_table": {"sweep": "outputs.sweep", "png": "outputs.design_table", "choice": "outputs.design_table"},
    # the impacts a scene's WAV files render are those of its [damper] run
    "wav": {"wav_files": "outputs.wav", "impacts": "damper"},
}
