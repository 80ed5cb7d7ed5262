"""The conformance-tested filter library behind the levels: phonometry, or PyOctaveBand before it.

phonometry (IEC 61672-1:2013 A/C/Z frequency weighting and F/S/I time weighting, IEC 61260-1:2014
fractional-octave filter banks) needs Python >= 3.13; on older interpreters the same filters ship
under its former name, PyOctaveBand 2.0.0. Both expose the three names used here with the same
signatures:

* ``weighting_filter(x, fs, curve)`` -- the A, C or Z frequency weighting of a signal;
* ``time_weighting(x, fs, mode)`` -- the exponentially averaged square (``"fast"``, ``"slow"``,
  ``"impulse"``);
* ``OctaveFilterBank(fs, fraction, order, limits)`` -- a fractional-octave bank with public
  ``freq``, ``nominal_freq``, ``sos`` and ``factor`` (per-band decimation factor) attributes;
* ``WeightingFilter(fs, curve)``, where present -- the weighting's second-order sections
  (``sos``), used only once they are shown to reproduce ``weighting_filter``
  (:func:`weighting_sos`), so a transient's levels can be run over its sound alone
  (:mod:`.transient`).

The library is imported on first use (it pulls in SciPy's signal module and, if present,
numba), so ``import acoustiviz`` stays light.
"""

from __future__ import annotations

import functools
from importlib import metadata
from types import SimpleNamespace

__all__ = ["library", "backend", "weighting_sos"]


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
                           OctaveFilterBank=lib.OctaveFilterBank,
                           WeightingFilter=getattr(lib, "WeightingFilter", None), name=f"{dist} {version}")


@functools.lru_cache(maxsize=16)
def weighting_sos(sample_rate: int, curve: str):
    """The second-order sections the library's ``weighting_filter(x, sample_rate, curve)`` runs, or ``None``.

    Taken from the library's ``WeightingFilter`` and accepted only if ``scipy.signal.sosfilt`` with
    them, from rest, reproduces the library's own ``weighting_filter`` on a probe signal (4096
    samples of seeded white noise) to 1e-12 of its largest value: so not where the library
    resamples internally (below 96 kHz) or where it has no such class.

    Parameters
    ----------
    sample_rate : int
        Sample rate in Hz.
    curve : {"A", "C"}
        The frequency weighting.

    Returns
    -------
    (n_sections, 6) ndarray or None
        The sections (``b0 b1 b2 a0 a1 a2``) at ``sample_rate``.
    """
    import numpy as np
    from scipy.signal import sosfilt

    lib = library()
    if lib.WeightingFilter is None:
        return None
    try:
        sos = np.array(lib.WeightingFilter(int(sample_rate), curve).sos, dtype=float)
    except Exception:  # pragma: no cover - a library whose class takes other arguments
        return None
    if sos.ndim != 2 or sos.shape[1] != 6 or sos.shape[0] == 0:
        return None
    probe = np.random.default_rng(61672).standard_normal(4096)
    ref = np.asarray(lib.weighting_filter(probe, int(sample_rate), curve), dtype=float)
    mine = sosfilt(sos, probe)
    if ref.shape != mine.shape or not np.max(np.abs(mine - ref)) <= 1e-12 * np.max(np.abs(ref)):
        return None
    return sos


def backend() -> str:
    """Name and version of the filter library in use, e.g. ``"PyOctaveBand 2.0.0"``."""
    return library().name
