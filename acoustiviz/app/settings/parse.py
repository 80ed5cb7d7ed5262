"""Values typed as text on the command line or in a scene: a point ``X,Y,Z``, an image size ``WxH``, frequencies."""

from __future__ import annotations

from ...errors import ParameterError
from .base import parse_size  # the one reading of WxH, beside the check of a size

__all__ = ["parse_point", "parse_size", "parse_frequencies", "check_frequencies"]


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


def parse_frequencies(text, name: str = "--freq"):
    """Forcing frequencies in Hz, sorted: the one reading of ``--freq`` and of ``excitation.frequencies_hz``.

    ``text`` is ``START:STOP:COUNT`` (both ends included, the one range rule of
    :func:`acoustiviz.sweep.spec.parse_values`), a comma list ``F1,F2,...`` or one value, checked by
    :func:`check_frequencies`. Errors are :class:`ParameterError` naming ``name``.

    Examples
    --------
    >>> parse_frequencies("3:7:5").tolist()
    [3.0, 4.0, 5.0, 6.0, 7.0]
    >>> parse_frequencies("5.5, 4.5").tolist()
    [4.5, 5.5]
    """
    from ...sweep.spec import parse_values

    return check_frequencies(parse_values(name, text), name, text)


def check_frequencies(values, name: str = "frequencies", text=None):
    """Forcing frequencies in Hz as a sorted float array: 1 to ``MAX_FREQUENCIES``, each in range, none repeated.

    The ranges are those of :data:`~acoustiviz.app.settings.forced.FREQUENCIES`; ``text`` (default: the
    values) is what the user typed, quoted in the error about a repeated frequency. Errors are
    :class:`ParameterError` naming ``name``.
    """
    import numpy as np

    from .forced import FREQUENCIES, MAX_FREQUENCIES

    values = tuple(values) if not isinstance(values, (str, bytes)) and np.ndim(values) == 1 else (values,)
    if not 1 <= len(values) <= MAX_FREQUENCIES:
        raise ParameterError(name, f"expected 1 to {MAX_FREQUENCIES} frequencies, got {len(values)}")
    f = np.array([FREQUENCIES.check(v, name) for v in values], dtype=float)
    if np.unique(f).size != f.size:
        raise ParameterError(name, f"duplicate frequencies in {text if text is not None else list(values)!r}")
    return np.sort(f)
