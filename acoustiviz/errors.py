"""The errors and warnings acoustiviz raises: one public home for each.

Every public function checks its inputs before doing any work and raises :class:`ParameterError`
naming the parameter as the caller spelt it (``"radius"`` in the API, ``"--radius"`` on the
command line, ``"sphere.radius_m"`` in a scene), with the offending value and the allowed range.
A front-end that renames a parameter does so with :meth:`ParameterError.renamed`, never by
taking the message apart.

Examples
--------
>>> from acoustiviz import ParameterError
>>> err = ParameterError("radius", "must be > 0 m, got -1 m")
>>> err.name, err.detail
('radius', 'must be > 0 m, got -1 m')
>>> str(err.renamed("--radius"))
'--radius: must be > 0 m, got -1 m'
"""

from __future__ import annotations

__all__ = ["ParameterError", "SceneError", "AccuracyWarning", "ClippingWarning"]


class ParameterError(ValueError):
    """A parameter is outside its allowed range.

    Parameters
    ----------
    name : str
        The parameter as the caller spells it (``"radius"``, ``"--radius"``, ``"sphere.radius_m"``).
    detail : str
        What is wrong and what is allowed, without the name.

    Attributes
    ----------
    name : str
        The failing parameter.
    detail : str
        What is wrong and what is allowed.
    """

    def __init__(self, name: str, detail: str):
        self.name = name
        self.detail = detail
        super().__init__(f"{name}: {detail}")

    def __reduce__(self):  # keep (name, detail) across process pools
        return (type(self), (self.name, self.detail))

    def renamed(self, name: str) -> ParameterError:
        """The same error under the name a front-end's user gave (an option or a scene key)."""
        return ParameterError(name, self.detail)


class SceneError(ParameterError):
    """A scene is invalid; the message names the file, the key path and what is allowed.

    Attributes
    ----------
    source : str
        The scene file.
    name : str
        The key path (``"sphere.radius_m"``).
    detail : str
        What is wrong and what is allowed.
    """

    def __init__(self, source: str, key: str, detail: str):
        super().__init__(key, detail)
        self.source = source
        self.args = (f"{source}: {key}: {detail}",)

    def __str__(self) -> str:
        return self.args[0]

    def __reduce__(self):
        return (type(self), (self.source, self.name, self.detail))

    @property
    def key(self) -> str:
        """The key path (same as :attr:`name`)."""
        return self.name


class AccuracyWarning(UserWarning):
    """A method is used near the limit where its error stops being small (e.g. a coarse time step)."""


class ClippingWarning(UserWarning):
    """Samples of an audio file were clipped at full scale."""
