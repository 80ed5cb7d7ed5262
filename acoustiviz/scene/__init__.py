"""Scenes: one TOML file describing a situation and the outputs wanted from it.

A scene names the medium, the sphere and its contact, the geometry (free field, a reflecting
plane or a wall-floor corner), optionally an impact damper, listeners, grids, and an
``[outputs]`` table. Only the outputs named there are produced, and only the work they need is
done. Every key carries its unit in its name (``radius_m``, ``duration_s``, ``angle_deg``).

Loading validates everything before any work starts: a wrong type, a value out of range, an
unknown key (with a "did you mean"), a listener without a position, a listener inside the sphere or
behind a surface, or a grid too large for the memory cap raises :class:`SceneError`, whose
message names the file, the key path and the allowed range.

The schema is data (:data:`SCHEMA`), so the documentation (``acoustiviz run --help-scene``)
and the validator cannot drift apart.
"""

from __future__ import annotations

from .load import Scene, default_scene, load_scene, scene_from_dict, scene_from_text, shipped_scenes
from .schema import OUTPUT_KINDS, SCHEMA, schema_help
from .validate import SceneError, parse_range

__all__ = [
    "SceneError",
    "Scene",
    "SCHEMA",
    "OUTPUT_KINDS",
    "load_scene",
    "scene_from_dict",
    "scene_from_text",
    "default_scene",
    "shipped_scenes",
    "schema_help",
    "parse_range",
]
