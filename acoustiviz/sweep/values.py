"""Values of a swept axis as typed: one value, ``start:stop:count`` (both ends included) or ``a,b,c``.

:func:`value_range` is the one range rule of every front-end (``acoustiviz sweep`` options and scene
keys), so the same range is the same grid and one run can resume another's folder.
"""

from __future__ import annotations

import math

from ..errors import ParameterError

__all__ = ["MAX_RANGE_COUNT", "value_range", "parse_start_stop_count", "parse_values"]

#: Most values a ``start:stop:count`` range may hold.
MAX_RANGE_COUNT = 10000


def value_range(start: float, stop: float, count: int) -> tuple[float, ...]:
    """``count`` evenly spaced values from ``start`` to ``stop``, both included: the one range rule.

    Value i is ``start + i (stop - start) / (count - 1)`` rounded to 15 significant digits of
    the larger end, so that decimal steps give decimal values (0.03, not 0.030000000000000002)
    and a residue of cancellation gives 0; the ends are ``start`` and ``stop`` exactly. Every
    front-end (``acoustiviz sweep`` options and scene keys) builds its grids with this rule, so
    the same range is the same grid -- and one run can resume another's folder.

    Parameters
    ----------
    start, stop : float
        First and last value (any unit).
    count : int
        Number of values (1 to :data:`MAX_RANGE_COUNT`; 1 gives ``(start,)`` and requires
        ``start == stop``; more require ``stop > start``: a range is given in increasing order,
        by every front-end).

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> value_range(0.02, 0.06, 5)
    (0.02, 0.03, 0.04, 0.05, 0.06)
    >>> value_range(-0.1, 0.2, 4)
    (-0.1, 0.0, 0.1, 0.2)
    """
    n = int(count)
    if n != count or not 1 <= n <= MAX_RANGE_COUNT:
        raise ParameterError("count", f"must be an integer in [1, {MAX_RANGE_COUNT}], got {count!r}")
    start, stop = float(start), float(stop)
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise ParameterError("count", f"a range needs finite ends, got {start!r}:{stop!r}")
    if n == 1:
        if start != stop:
            raise ParameterError("count", f"a range of 1 value needs start == stop, got {start:g}:{stop:g}")
        return (start,)
    if not stop > start:
        raise ParameterError("count", f"a range of {n} values needs stop > start (give it in increasing order), "
                                      f"got {start:g}:{stop:g}")
    scale = max(abs(start), abs(stop))
    digits = 14 - math.floor(math.log10(scale)) if scale > 0 else 0
    inner = (round(start + i * (stop - start) / (n - 1), digits) + 0.0 for i in range(1, n - 1))
    return (start, *inner, stop)


def parse_start_stop_count(name: str, text: str) -> tuple[float, ...]:
    """Parse ``start:stop:count`` (both ends included) with :func:`value_range`.

    Parameters
    ----------
    name : str
        The option or key, named by errors (e.g. ``"--gap"`` or ``"outputs.sweep.gap_m"``).
    text : str
        The range.

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> parse_start_stop_count("--m", "0.02:0.08:4")
    (0.02, 0.04, 0.06, 0.08)
    """
    s = str(text).strip()
    parts = s.split(":")
    if len(parts) != 3:
        raise ParameterError(name, f"a range is 'start:stop:count' (both ends included), got {s!r}")
    try:
        start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise ParameterError(name, f"a range is 'start:stop:count' with an integer count, got {s!r}") from None
    try:
        return value_range(start, stop, count)
    except ParameterError as exc:
        raise ParameterError(name, f"{exc.detail} (in {s!r})") from None


def parse_values(name: str, text, kind=float) -> tuple:
    """Parse ``start:stop:count`` (inclusive, :func:`parse_start_stop_count`), ``a,b,c`` or a single value.

    Parameters
    ----------
    name : str
        Name used in error messages (e.g. ``"--gap"``).
    text : str or number or sequence
        The specification.
    kind : type
        ``float`` for numbers, ``str`` for names (ranges are then refused).

    Returns
    -------
    tuple
        The values, in the given order.

    Examples
    --------
    >>> parse_values("--m", "0.02:0.08:4")
    (0.02, 0.04, 0.06, 0.08)
    >>> parse_values("--config", "plane,wall-floor", str)
    ('plane', 'wall-floor')
    """
    if isinstance(text, (list, tuple)):
        items = list(text)
    elif isinstance(text, (int, float)) and kind is float:
        items = [text]
    else:
        s = str(text).strip()
        if not s:
            raise ParameterError(name, "expected a value, start:stop:count or a comma-separated list")
        if ":" in s:
            if kind is not float:
                raise ParameterError(name, f"expected names separated by commas, got {s!r}")
            return parse_start_stop_count(name, s)
        items = [p.strip() for p in s.split(",")]
    if not items:
        raise ParameterError(name, "expected at least one value")
    if kind is float:
        out = []
        for it in items:
            try:
                v = float(it)
            except (TypeError, ValueError):
                raise ParameterError(name, f"expected a number, got {it!r}") from None
            if not math.isfinite(v):
                raise ParameterError(name, f"must be finite, got {it!r}")
            out.append(v)
        return tuple(out)
    return tuple(str(it) for it in items)
