"""The filters behind the levels: IEC 61672-1 weightings and IEC 61260-1 bands (:mod:`._filters`).

One place names the filters the level functions run, so they can be swapped as a whole:

* ``weighting_filter(x, fs, curve)`` -- the A, C or Z frequency weighting of a signal;
* ``time_weighting(x, fs, mode)`` -- the exponentially averaged square (``"fast"``, ``"slow"``,
  ``"impulse"``);
* ``OctaveFilterBank(fs, fraction, order, limits)`` -- a fractional-octave bank with public
  ``freq``, ``nominal_freq``, ``sos`` and ``factor`` (per-band decimation factor) attributes;
* ``WeightingFilter(fs, curve)`` -- the weighting's second-order sections (``sos``) and the
  oversampling factor they run at (:func:`weighting_sos`), so a transient's levels can be run over
  its sound alone (:mod:`.transient`).

They are written from the standards' formulas with SciPy (:mod:`._filters`) and checked against
the standards' tables and acceptance limits and, where installed, against PyOctaveBand
(``tests/test_levels_filters.py``). SciPy's signal module is imported on first use, so
``import acoustiviz`` stays light.
"""

from __future__ import annotations

import functools
from types import SimpleNamespace

__all__ = ["library", "backend", "weighting_sos"]


@functools.lru_cache(maxsize=1)
def library() -> SimpleNamespace:
    """The filters: ``weighting_filter``, ``time_weighting``, ``OctaveFilterBank``, ``WeightingFilter`` and ``name``.

    Returns
    -------
    types.SimpleNamespace
        The callables and ``name`` (``"acoustiviz IEC 61672-1/61260-1 filters"``).
    """
    from . import _filters as lib

    return SimpleNamespace(weighting_filter=lib.weighting_filter, time_weighting=lib.time_weighting,
                           OctaveFilterBank=lib.OctaveFilterBank, WeightingFilter=lib.WeightingFilter,
                           name=lib.NAME)


@functools.lru_cache(maxsize=16)
def weighting_sos(sample_rate: int, curve: str):
    """The second-order sections ``weighting_filter(x, sample_rate, curve)`` runs at the rate, or ``None``.

    ``None`` where the weighting oversamples the signal (below 96 kHz): there the weighted signal
    is not a cascade of sections at ``sample_rate``.

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
    wf = library().WeightingFilter(int(sample_rate), curve)
    return wf.sos.copy() if wf.oversample == 1 else None


def backend() -> str:
    """Name of the filters in use, ``"acoustiviz IEC 61672-1/61260-1 filters"``."""
    return library().name
