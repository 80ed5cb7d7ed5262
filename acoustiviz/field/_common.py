"""Shared helpers of the field evaluator: defaults, argument checks, memory chunking, time steps."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._validate import ParameterError, check_positive, check_range
from ..constants import P_REF
from ..core.contact import HalfSinePulse, HertzPulse, SampledPulse
from ..core.geometry import Geometry
from ..core.medium import AIR, Medium
from ..core.radiation import (
    _knot_states,
    half_sine_response_table,
    hertz_response_table,
    sampled_response_table,
    sphere_pole,
)

__all__ = ["DEFAULT_CUTOFF", "DEFAULT_MEMORY_LIMIT", "P_REF", "MODEL_NAMES", "decay_time", "default_sample_interval"]

#: Relative size of the decaying tail below which a sphere's response is dropped.
DEFAULT_CUTOFF = 1e-10
#: Default cap on the evaluator's working memory, in bytes (256 MiB).
DEFAULT_MEMORY_LIMIT = 256 * 2**20
#: Model names when no tolerance is given: the exact closed form serves every point.
MODEL_NAMES = ("exact",)
#: Pieces of the exact Hertz pulse's Taylor table cut this many times for the kernels, and the
#: size (relative to max|Y|) below which its terms are dropped: ~9 terms per sample, error < 1e-13.
_HERTZ_SPLIT = 4
_HERTZ_RTOL = 1e-15
#: Largest number of points handled per chunk (keeps the geometry arrays in cache).
_MAX_CHUNK = 65536


def check_pulse(pulse):
    if not isinstance(pulse, (HalfSinePulse, SampledPulse)):
        raise ParameterError("pulse", f"expected a HalfSinePulse or SampledPulse, got {type(pulse).__name__}")
    return pulse


def check_geometry(geometry):
    if not isinstance(geometry, Geometry):
        raise ParameterError("geometry", f"expected a Geometry (acoustiviz.core.geometry), got "
                                         f"{type(geometry).__name__}")
    return geometry


class PulseArrays(NamedTuple):
    """A pulse flattened for the field kernels (a record the JIT reads by attribute).

    Attributes
    ----------
    kind : int
        0: the half-sine in closed form; 1: a piecewise-linear pulse with its exact knot states;
        2: ``Y`` as Taylor polynomials per piece (the exact Hertz pulse, or any pulse with ``taylor``).
    amp : float
        Half-sine amplitude in m/s² (kind 0; 0 otherwise).
    tau : float
        Pulse duration in s.
    xi : (k,) ndarray
        Knot times in s (kind 1 and 2; unused by kind 0).
    acc : (k,) or (k - 1,) ndarray
        Kind 1: acceleration at the knots in m/s²; kind 2: inverse piece lengths in 1/s.
    yk : ndarray of complex
        Kind 1: ``Y`` at the knots in m/s; kind 2: ``Y`` at the pulse's end in m/s, then the terms
        per piece (as the real part).
    tab : (k - 1, terms) ndarray of complex
        Kind 2: Taylor coefficients of ``Y`` in m/s per piece, in ``u = (t' - xi[q]) acc[q]``.
    s : complex
        The sphere's pole ``(c/a)(-1 + i)`` in 1/s.
    """

    kind: int
    amp: float
    tau: float
    xi: np.ndarray
    acc: np.ndarray
    yk: np.ndarray
    tab: np.ndarray
    s: complex


class ImageArrays(NamedTuple):
    """Every image source seen from a block of points, for the field kernels (read by attribute).

    Row ``i`` is a point, column ``j`` an image (:func:`acoustiviz.field.sources.chunk_geometry`);
    image ``j`` adds ``p0[i, j] Re[(cre + i cim)[i, j] Y(t - delay[i, j])]`` to the pressure in Pa.

    Attributes
    ----------
    delay : (n, nimg) ndarray
        Retardation ``(r - a)/c`` in s.
    p0 : (n, nimg) ndarray
        Scale in Pa·s/m (0 for a point outside the fluid).
    cre, cim : (n, nimg) ndarray
        Real and imaginary parts of the radiation coefficient (dimensionless).
    """

    delay: np.ndarray
    p0: np.ndarray
    cre: np.ndarray
    cim: np.ndarray


class PeakSources(NamedTuple):
    """The sphere, its images and the fluid, as :func:`~acoustiviz.field._peak_kernels._peaks_kernel` reads them.

    Attributes
    ----------
    spos : (nimg, 3) ndarray
        Image centres in m.
    saxis : (nimg, 3) ndarray
        Image acceleration axes with the reflection weight folded in (dimensionless).
    centre : (3,) ndarray
        The sphere's centre in m.
    ppt, pnm : (planes, 3) ndarray
        A point (m) and the unit normal into the fluid of each reflecting plane.
    radius : float
        Sphere radius in m.
    rho : float
        Fluid density in kg/m³.
    c : float
        Speed of sound in m/s.
    """

    spos: np.ndarray
    saxis: np.ndarray
    centre: np.ndarray
    ppt: np.ndarray
    pnm: np.ndarray
    radius: float
    rho: float
    c: float


class PeakSampling(NamedTuple):
    """The tabulated pulse and the margins, as :func:`~acoustiviz.field._peak_kernels._peaks_kernel` reads them.

    Attributes
    ----------
    big_h : float
        Coarse time step H in s.
    fine : int
        Fine steps per coarse step.
    pad : int
        Fine steps of zeros before ``Y``'s start.
    ytr, yti : (fine, K) ndarray
        ``Y`` in m/s by fine residue (row) and coarse step (column), real and imaginary parts.
    slope : float
        ``max |Y'|`` in m/s², for the bound of the delays' rounding to the fine step.
    margin : float
        Relative margin (of the largest coarse ``|p|``) within which candidates are refined.
    cusps : bool
        Whether ``p'`` may jump at a pulse's start or end (the pulse's acceleration is not zero there).
    """

    big_h: float
    fine: int
    pad: int
    ytr: np.ndarray
    yti: np.ndarray
    slope: float
    margin: float
    cusps: bool


class PeakCorrelations(NamedTuple):
    """The pulse correlations of the exposure (:class:`acoustiviz.field.exposure.PulseCorrelations`), by attribute.

    Attributes
    ----------
    on : bool
        Whether the exposure is computed (else its column is NaN and the rest unused).
    tau : float
        Pulse length in s.
    s : complex
        The sphere's pole in 1/s.
    step : float
        Lag spacing of ``table`` in s.
    table : (nodes, 4) complex ndarray
        ``G``, ``step G'``, ``H``, ``step H'`` at the lags, in (m/s)²·s.
    y_end : complex
        ``Y(T)`` in m/s.
    m_g, m_h : complex
        ``∫ Y(u) exp(s u) du`` and ``∫ Y(u) exp(s̄ u) du`` in m.
    """

    on: bool
    tau: float
    s: complex
    step: float
    table: np.ndarray
    y_end: complex
    m_g: complex
    m_h: complex


def pulse_args(pulse, radius: float, medium: Medium, *, taylor: bool = False) -> PulseArrays:
    """Flatten a pulse into the kernels' :class:`PulseArrays` (``taylor``: every pulse as a Taylor table, kind 2)."""
    s = sphere_pole(radius, medium)
    notab = np.zeros((1, 1), complex)
    if isinstance(pulse, HertzPulse):
        table = hertz_response_table
    elif taylor:  # the other pulses as the Hertz pulse: Horner instead of exp/sin/cos
        table = half_sine_response_table if isinstance(pulse, HalfSinePulse) else sampled_response_table
    else:
        table = None
    if table is not None:  # knots, 1/piece length, Y at the end and terms per piece, Taylor table
        knots, tab, terms = table(pulse, s, split=_HERTZ_SPLIT, rtol=_HERTZ_RTOL)
        return PulseArrays(
            2, 0.0, float(knots[-1]), knots, 1.0 / np.diff(knots), np.array([tab[-1].sum(), *terms]), tab, s
        )
    if isinstance(pulse, HalfSinePulse):
        empty = np.zeros(2)
        amp, tau = float(pulse.amplitude), float(pulse.duration)
        return PulseArrays(0, amp, tau, empty, empty, np.zeros(2, complex), notab, s)
    xi = np.ascontiguousarray(pulse.times, dtype=float)
    acc = np.ascontiguousarray(pulse.acceleration_samples, dtype=float)
    return PulseArrays(1, 0.0, float(xi[-1]), xi, acc, _knot_states(xi, acc, s), notab, s)


def decay_time(radius: float, *, medium: Medium = AIR, cutoff: float = DEFAULT_CUTOFF) -> float:
    """Time in s after the pulse ends over which a sphere's response is kept.

    The response after the pulse decays like ``exp(-c t/a)``; it is kept until that factor
    falls to ``cutoff``: ``(a/c) ln(1/cutoff)``.

    Parameters
    ----------
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.
    cutoff : float
        Relative amplitude, in (0, 1).

    Returns
    -------
    float
        Tail length in s.
    """
    a = check_positive("radius", radius, "m")
    c = check_range("cutoff", cutoff, 0.0, 1.0, low_open=True, high_open=True)
    return a / medium.c * math.log(1.0 / c)



def default_sample_interval(pulse, radius: float, *, medium: Medium = AIR, samples: int = 64) -> float:
    """A sample interval in s resolving both the pulse and the sphere's decay time.

    ``min(T, a/c) / samples``: ``samples`` points per pulse length ``T`` or per decay time
    ``a/c`` of the sphere, whichever is shorter.
    """
    a = check_positive("radius", radius, "m")
    if int(samples) < 4:
        raise ParameterError("samples", f"must be >= 4, got {samples}")
    return min(check_pulse(pulse).duration, a / medium.c) / int(samples)


def uniform_step(t: np.ndarray):
    """Return the step of a uniform grid, or None if ``t`` is not uniform (to 1e-9 of a step)."""
    if t.size < 2:
        return None
    dt = (t[-1] - t[0]) / (t.size - 1)
    if not dt > 0:
        return None
    if np.max(np.abs(t - (t[0] + dt * np.arange(t.size)))) > 1e-9 * dt:
        return None
    return float(dt)


def chunk_size(bytes_per_point: float, fixed: float, memory_limit: float, name="memory_limit") -> int:
    room = memory_limit - fixed
    if room < bytes_per_point:
        raise ParameterError(
            name,
            f"{memory_limit:.4g} B is too small: the results and fixed buffers need {fixed:.4g} B, plus "
            f"{bytes_per_point:.4g} B per point of a chunk",
        )
    return int(max(1, min(_MAX_CHUNK, room // bytes_per_point)))


def geometry_bytes(nimg: int) -> int:
    # delay, p0, c (complex), r, ct, ra + per-source temporaries (d (n,3), r, ct) and the mask
    return 8 * (nimg * 9 + 12)


def check_inputs(pulse, geometry, medium) -> None:
    """Check that ``pulse``, ``geometry`` and ``medium`` are a pulse, a geometry and a medium."""
    check_pulse(pulse)
    check_geometry(geometry)
    if not isinstance(medium, Medium):
        raise ParameterError("medium", f"expected a Medium, got {type(medium).__name__}")


def prepare(pulse, geometry, medium, cutoff):
    """Check the arguments; return the kernels' :class:`PulseArrays` and the kept tail in s."""
    check_inputs(pulse, geometry, medium)
    tail = decay_time(geometry.radius, medium=medium, cutoff=cutoff)
    return pulse_args(pulse, geometry.radius, medium), tail

