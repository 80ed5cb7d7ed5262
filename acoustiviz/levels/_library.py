"""The conformance-tested filter library behind the levels: phonometry, or PyOctaveBand before it.

phonometry (IEC 61672-1:2013 A/C/Z frequency weighting and F/S/I time weighting, IEC 61260-1:2014
fractional-octave filter banks) needs Python >= 3.13; on older interpreters the same filters ship
under its former name, PyOctaveBand 2.0.0. Both expose the three names used here with the same
signatures:

* ``weighting_filter(x, fs, curve)`` -- the A, C or Z frequency weighting of a signal;
* ``time_weighting(x, fs, mode)`` -- the exponentially averaged square (``"fast"``, ``"slow"``,
  ``"impulse"``);
* ``OctaveFilterBank(fs, fraction, order, limits)`` -- a fractional-octave bank with public
  ``freq``, ``nominal_freq``, ``sos`` and ``factor`` (per-band decimation factor) attributes.

The library is imported on first use (it pulls in SciPy's signal module and, if present,
numba), so ``import acoustiviz`` stays light.
"""

from __future__ import annotations

import functools
from importlib import metadata
from types import SimpleNamespace

__all__ = ["library", "backend"]


@functools.lru_cache(maxsize=1)
def library() -> SimpleNamespace:
    """The filter library: ``weighting_filter``, ``time_weighting``, ``OctaveFilterBank`` and ``name``.

    Returns
    -------
    types.SimpleNamespace
        The three callables and ``name`` (distribution and version, e.g. ``"PyOctaveBand 2.0.0"``).
    """
    try:
        import phonometry as lib

        dist = "phonometry"
    except ImportError:
        import pyoctaveband as lib

        dist = "PyOctaveBand"
    try:
        version = metadata.version(dist)
    except metadata.PackageNotFoundError:  # pragma: no cover - a source checkout
        version = getattr(lib, "__version__", "?")
    return SimpleNamespace(weighting_filter=lib.weighting_filter, time_weighting=lib.time_weighting,
                           OctaveFilterBank=lib.OctaveFilterBank, name=f"{dist} {version}")


def backend() -> str:
    """Name and version of the filter library in use, e.g. ``"PyOctaveBand 2.0.0"``."""
    return library().name
