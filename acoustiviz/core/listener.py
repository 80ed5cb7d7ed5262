"""A listener: a named point in the scene where the sound is heard, rendered and levelled."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_points, label_problem

__all__ = ["Listener"]


@dataclass(frozen=True, eq=False)
class Listener:
    """A named listening position.

    Parameters
    ----------
    name : str
        Label that becomes part of file names: 1-64 letters, digits, ``_``, ``-``, ``.`` and inner
        spaces, starting with a letter, digit or ``_`` (the rule of
        :func:`acoustiviz._validate.label_problem`, the same as a scene's ``listeners[i].name``).
    position : (3,) array_like
        Position ``[x, y, z]`` in m in the scene frame (finite). Stored as a read-only float copy.

    Examples
    --------
    >>> ear = Listener("left", [0.7, 0.0, 0.0])
    >>> ear.name, ear.position.tolist()
    ('left', [0.7, 0.0, 0.0])
    >>> ear == Listener("left", (0.7, 0, 0))
    True
    >>> Listener("../x", [0, 0, 1])
    Traceback (most recent call last):
    ...
    acoustiviz.errors.ParameterError: name: may hold only letters, digits, '_', '-', '.' and inner spaces; got '../x'
    """

    name: str
    position: np.ndarray

    def __iter__(self):
        """Unpack as ``name, position``, as the ``(name, position)`` pairs of a scene's listeners.

        Examples
        --------
        >>> name, position = Listener("mic", [0.0, 0.0, 0.5])
        >>> name, float(position[2])
        ('mic', 0.5)
        """
        return iter((self.name, self.position))

    def __eq__(self, other):
        """Equal names and positions (a value, not an identity)."""
        if not isinstance(other, Listener):
            return NotImplemented
        return self.name == other.name and bool(np.array_equal(self.position, other.position))

    def __hash__(self):
        return hash((self.name, self.position.tobytes()))

    def __post_init__(self):
        problem = label_problem(self.name)
        if problem is not None:
            raise ParameterError("name", problem)
        points = check_points("position", self.position)
        if points.shape != (1, 3):
            raise ParameterError("position", f"expected one point [x, y, z] in m, got shape {np.shape(self.position)}")
        p = points[0].copy()
        p.flags.writeable = False
        object.__setattr__(self, "position", p)

