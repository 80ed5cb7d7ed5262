"""Conventions shared by the gallery scripts: one output folder, and a fast mode for CI."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["output_dir", "fast_mode"]


def output_dir() -> Path:
    """Folder the gallery writes into: ``$ACOUSTIVIZ_GALLERY_DIR`` or ``gallery/_output``."""
    out = Path(os.environ.get("ACOUSTIVIZ_GALLERY_DIR", "gallery/_output"))
    out.mkdir(parents=True, exist_ok=True)
    return out


def fast_mode() -> bool:
    """True when ``$ACOUSTIVIZ_FAST`` is set to a non-empty value other than 0 (the test suite)."""
    return os.environ.get("ACOUSTIVIZ_FAST", "") not in ("", "0")
