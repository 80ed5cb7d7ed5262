"""The errors and warnings acoustiviz raises: one public home for each.

Every public function checks its inputs before doing any work and raises :class:`ParameterError`
naming the parameter as the caller spelt it (``"radius"`` in the API, ``"--radius"`` on the
command line, ``"sphere.radius_m"`` in a scene), with the offending value and the allowed range.
A front-end that renames a parameter does so with :meth:`ParameterError.renamed` (around a whole
block, :func:`user_terms`), never by taking the message apart.

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

import contextlib
from collections.abc import Mapping

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

    Examples
    --------
    A negative impact speed is refused when the impact is built, naming the parameter; the error
    is a ``ValueError``:

    >>> from acoustiviz import Impact
    >>> try:
    ...     Impact(velocity=-1.4, k_hertz=5.6e8, mass=0.2259)
    ... except ValueError as err:
    ...     print(type(err).__name__, "|", err.name, "|", err.detail)
    ParameterError | velocity | must be > 0 m/s, got -1.4 m/s
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
    """A method is used near the limit where its error stops being small (e.g. a coarse time step).

    Examples
    --------
    A Newmark step of 1/10 of the shortest possible contact of the paper's Table 1 damper
    (0.184 ms) resolves each contact by a handful of steps only, and says so:

    >>> import warnings
    >>> from acoustiviz.dynamics import simulate
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     _ = simulate(duration=0.02, solver="newmark", dt=1.84e-5)
    >>> [w.category.__name__ for w in caught]
    ['AccuracyWarning']
    >>> print(str(caught[0].message).split(":")[0])
    Newmark step 1.84e-05 s is coarser than 1/20 of the shortest contact (0.000184 s)
    """


class ClippingWarning(UserWarning):
    """Samples of an audio file were clipped at full scale.

    Examples
    --------
    A 2 Pa peak written as 24-bit PCM with 1 Pa at full scale is 6.02 dB over and clipped:

    >>> import tempfile, warnings
    >>> from pathlib import Path
    >>> from acoustiviz import Signal
    >>> from acoustiviz.output.audio import write_wav
    >>> with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     info = write_wav(Path(folder) / "click.wav", Signal([0.0, 2.0, -0.5], 48000), subtype="PCM_24",
    ...                      scale=1.0)
    >>> [w.category.__name__ for w in caught], info["clipped_samples"], round(info["over_full_scale_db"], 2)
    (['ClippingWarning'], 1, 6.02)
    """


@contextlib.contextmanager
def user_terms(names: Mapping[str, str]):
    """Re-raise a :class:`ParameterError` about a parameter of ``names`` under the user's name.

    Parameters
    ----------
    names : mapping of str to str
        API parameter name -> the option or scene key the user gave.
    """
    try:
        yield
    except ParameterError as exc:
        if exc.name in names and names[exc.name] != exc.name:
            raise exc.renamed(names[exc.name]) from None
        raise
