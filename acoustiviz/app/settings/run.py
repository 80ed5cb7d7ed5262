"""Settings of the command line as a whole (``--max-memory``) and of ``acoustiviz run`` (a scene into a folder)."""

from __future__ import annotations

from ...constants import MAX_MEMORY_MB
from .table import Setting

__all__ = ["MAX_MEMORY", "MEMORY_LIMIT", "RUN_OPTIONS"]

#: Every command's cap on its estimated memory and output size, in MB (checked by
#: :func:`acoustiviz.app.budget.outer_cap`; a scene's run also keeps under its ``grids.memory_limit_mb``).
MAX_MEMORY = Setting("max_memory_mb", "--max-memory", None, "float", None,
                     f"refuse work whose estimated memory or output size exceeds MB megabytes (default "
                     f"{MAX_MEMORY_MB:g}; a scene's run also keeps under its grids.memory_limit_mb)", "MB",
                     metavar="MB")

#: A scene's ``[grids]`` memory cap of its grid evaluations (the scene's own key for what ``--max-memory`` caps).
MEMORY_LIMIT = Setting("memory_limit_mb", None, "memory_limit_mb", "float", 256.0, "memory cap of grid evaluations",
                       "MiB", low=0.0, high=1e6, low_open=True, table="grids")

#: ``acoustiviz run``: the scene file, the output folder and what is printed.
RUN_OPTIONS = (
    Setting("scene", "SCENE", None, "str", None, "scene file (TOML)", metavar="SCENE", positional=True),
    Setting("out", "--out", None, "str", None, "output folder", metavar="DIR"),
    Setting("quiet", "--quiet", None, "bool", False, "no progress messages"),
    Setting("help_scene", "--help-scene", None, "bool", False, "print every scene key with unit, range and default"),
)
