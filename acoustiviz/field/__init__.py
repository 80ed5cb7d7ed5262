"""Pressure of a sphere and its images over many points: time series, peaks, RMS, SPL, snapshots.

Every image source ``j`` (see :mod:`acoustiviz.core.images`) is a rigid sphere radiating in free
field; at an observer ``x`` its pressure is (paper eqs 12-14)::

    p_j(x, t) = P0_j Re[C_j Y(t - d_j)],   d_j = (|x - x_j| - a)/c,

with ``P0_j = ρ c a² cosθ_j / r_j²`` and ``C_j = r_j/a - i(1 - r_j/a)`` from
:func:`acoustiviz.core.radiation.radiation_coefficients`, and ``Y`` the observer-independent
pulse response of :func:`acoustiviz.core.radiation.pulse_response`. The evaluator

* computes each point only inside its own retarded window: ``Y(t') = 0`` for ``t' < 0``, and
  after the pulse (length ``T``) ``Y(t') = exp(s (t' - T)) Y(T)`` decays like
  ``exp(-c (t' - T)/a)``; it is dropped once that factor is below ``cutoff`` (default 1e-10,
  i.e. ``23 a/c`` after the pulse), so the neglected pressure is below
  ``cutoff · |P0||C| max|Y|`` for each image;
* on a uniform time grid advances ``exp(i ω t')`` and ``exp(s t')`` by one complex multiply per
  sample (a numba kernel), the closed form being re-entered exactly at the start of each
  interval; the exact Hertz pulse is evaluated per sample from the Taylor polynomials of ``Y``
  on the pieces of :func:`acoustiviz.core.radiation.hertz_response_table` (no interpolation;
  about the half-sine's cost), a sampled pulse exactly over its piecewise-linear form;
* reports the peaks of the continuous pressure: each point's extreme samples are refined by a
  bounded Brent search on the closed form (:func:`field_metrics`, ``refine``); the exposure of
  the whole response needs no time grid at all (:func:`exposure`, from correlations of ``Y`` at
  the image delays);
* processes the points in chunks so that its working memory stays under ``memory_limit``
  bytes (default 256 MiB); peak and RMS metrics reduce each point's series on the fly and never
  hold the series of all points.

Modules: :mod:`.sources` (image-source geometry), :mod:`.evaluate` (time series, snapshots),
:mod:`.metrics` (peak, RMS, exposure on a time grid), :mod:`.exposure` (exposure without one),
:mod:`.peaks` (peaks and exposure without a time loop),
:mod:`.directivity`, :mod:`.grids` (observer grids) and the numba kernels in :mod:`._kernels`.
Times are in s from the start of contact, points in m, pressures in Pa. The package imports only
the physics core and never plots or writes files.
"""

from __future__ import annotations

from ..core.medium import AIR  # noqa: F401 - kept importable as acoustiviz.field.AIR
from ._common import (
    DEFAULT_CUTOFF,
    DEFAULT_MEMORY_LIMIT,
    MODEL_NAMES,  # noqa: F401
    P_REF,
    decay_time,
    default_sample_interval,
)
from .directivity import Directivity, circle_points, directivity
from .evaluate import iter_time_series, snapshots, time_series
from .exposure import PulseCorrelations, exposure, pulse_correlations
from .metrics import FieldMetrics, field_metrics, spl_db
from .peaks import PeakExposure, PeakTable, fast_peaks, peak_table
from .sources import arrival_windows, image_geometry, source_geometry, waveform_span, waveform_spans

__all__ = [
    "DEFAULT_CUTOFF",
    "DEFAULT_MEMORY_LIMIT",
    "P_REF",
    "FieldMetrics",
    "image_geometry",
    "source_geometry",
    "decay_time",
    "arrival_windows",
    "waveform_span",
    "waveform_spans",
    "default_sample_interval",
    "time_series",
    "iter_time_series",
    "field_metrics",
    "fast_peaks",
    "peak_table",
    "PeakExposure",
    "PeakTable",
    "exposure",
    "pulse_correlations",
    "PulseCorrelations",
    "snapshots",
    "spl_db",
    "Directivity",
    "circle_points",
    "directivity",
]
