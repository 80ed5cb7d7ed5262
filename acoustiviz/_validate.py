"""Argument checks shared by the whole package.

Every public function checks its inputs *before* doing any work and raises
:class:`acoustiviz.errors.ParameterError` (a :class:`ValueError`) whose message names the
parameter, the offending value and the allowed range. The command-line layer
turns these into a one-line message and exit status 2.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .errors import ParameterError

if TYPE_CHECKING:
    import numpy as np

__all__ = [
    "ParameterError",
    "check_finite",
    "check_positive",
    "check_nonnegative",
    "check_range",
    "check_choice",
    "check_points",
    "label_problem",
    "LABEL_MAX",
]


def _as_float(name: str, value) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"expected a number, got {value!r}") from None
    return out


def check_finite(name: str, value) -> float:
    """Return ``value`` as a float, raising if it is not a finite number."""
    v = _as_float(name, value)
    if not math.isfinite(v):
        raise ParameterError(name, f"must be a finite number, got {value!r}")
    return v


def check_positive(name: str, value, unit: str = "") -> float:
    """Return ``value`` as a float, raising unless it is finite and > 0."""
    v = check_finite(name, value)
    if not v > 0:
        u = f" {unit}" if unit else ""
        raise ParameterError(name, f"must be > 0{u}, got {v:g}{u}")
    return v


def check_nonnegative(name: str, value, unit: str = "") -> float:
    """Return ``value`` as a float, raising unless it is finite and >= 0."""
    v = check_finite(name, value)
    if not v >= 0:
        u = f" {unit}" if unit else ""
        raise ParameterError(name, f"must be >= 0{u}, got {v:g}{u}")
    return v


def check_range(
    name: str,
    value,
    low: float = -math.inf,
    high: float = math.inf,
    *,
    unit: str = "",
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """Return ``value`` as a float, raising unless it lies in the given interval."""
    v = check_finite(name, value)
    ok_low = v > low if low_open else v >= low
    ok_high = v < high if high_open else v <= high
    if not (ok_low and ok_high):
        u = f" {unit}" if unit else ""
        lb = "(" if low_open else "["
        hb = ")" if high_open else "]"
        raise ParameterError(name, f"must lie in {lb}{low:g}, {high:g}{hb}{u}, got {v:g}{u}")
    return v


def check_choice(name: str, value, choices) -> str:
    """Return ``value`` unless it is not one of ``choices``."""
    if value not in choices:
        allowed = ", ".join(repr(c) for c in choices)
        raise ParameterError(name, f"must be one of {allowed}, got {value!r}")
    return value


def check_points(name: str, points) -> np.ndarray:
    """Return ``points`` as a float ``(n, 3)`` array (a single point becomes ``(1, 3)``)."""
    import numpy as np  # here, so that the command line's parsers and --help load no numpy

    try:
        p = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, "expected an (n, 3) array of coordinates in m") from None
    if p.ndim == 1:
        p = p[None, :]
    if p.ndim != 2 or p.shape[1] != 3:
        raise ParameterError(name, f"expected an (n, 3) array of coordinates in m, got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ParameterError(name, "coordinates must be finite")
    return p


#: Longest label (a listener's name, ...) that becomes part of a file name, in characters.
LABEL_MAX = 64
#: Device names Windows reserves (with any extension); refused everywhere so that a scene is portable.
_RESERVED = frozenset({"con", "prn", "aux", "nul", *(f"com{i}" for i in range(10)), *(f"lpt{i}" for i in range(10))})


def label_problem(label) -> str | None:
    """Why ``label`` cannot become part of a file name inside an output folder, or None if it can.

    A label is 1 to :data:`LABEL_MAX` letters, digits, ``_``, ``-`` and ``.`` (inner spaces
    allowed), starts with a letter, digit or ``_`` and ends without a dot or space. So it holds no
    path separator, no ``..``, no NUL or control character and no character a file system
    refuses, and it is not a device name Windows reserves (``CON``, ``NUL``, ``COM1``, ...): a
    name taken from someone else's input can never choose a folder or a device.

    Examples
    --------
    >>> label_problem("left") is None
    True
    >>> label_problem("../../victim/data")
    "may hold only letters, digits, '_', '-', '.' and inner spaces; got '../../victim/data'"
    """
    if not isinstance(label, str) or not label:
        return f"expected a non-empty name, got {label!r}"
    if len(label) > LABEL_MAX:
        return f"at most {LABEL_MAX} characters, got {len(label)}"
    if not all(ch.isalnum() or ch in "_-. " for ch in label) or not label.isprintable():
        return f"may hold only letters, digits, '_', '-', '.' and inner spaces; got {label!r}"
    if not (label[0].isalnum() or label[0] == "_") or label[-1] in ". ":
        return f"must start with a letter, digit or '_' and not end with '.' or a space; got {label!r}"
    if label.split(".")[0].strip().lower() in _RESERVED:
        return f"{label!r} is a device name on Windows; choose another"
    return None
