"""Values typed as text on the command line: a point ``X,Y,Z`` and an image size ``WxH``."""

from __future__ import annotations

from ...errors import ParameterError
from .base import check_size

__all__ = ["parse_point", "parse_size"]


def parse_point(text: str, name: str = "--listener"):
    """``"x,y,z"`` in m -> a (3,) float array; a :class:`ParameterError` naming ``name`` otherwise.

    Examples
    --------
    >>> parse_point("0.495, 0, 0.514").tolist()
    [0.495, 0.0, 0.514]
    """
    import numpy as np

    try:
        xyz = np.array([float(v) for v in str(text).split(",")])
    except ValueError:
        xyz = np.empty(0)
    if xyz.shape != (3,) or not np.all(np.isfinite(xyz)):
        raise ParameterError(name, f"expected three finite coordinates X,Y,Z in m, got {text!r}")
    return xyz


def parse_size(text: str, name: str = "size") -> tuple:
    """``"1200x900"`` -> ``(1200, 900)``, each side checked (:func:`check_size`); a ParameterError naming ``name``.

    Examples
    --------
    >>> parse_size("800x600")
    (800, 600)
    """
    parts = str(text).lower().replace("\u00d7", "x").split("x")
    try:
        if len(parts) != 2:
            raise ValueError
        w, h = int(parts[0]), int(parts[1])
    except ValueError:
        raise ParameterError(name, f"expected WIDTHxHEIGHT in pixels, e.g. 1200x900, got {text!r}") from None
    return check_size((w, h), name)
