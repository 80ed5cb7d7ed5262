"""Cheaper radiation models than the exact closed form, with proven error bounds.

The exact pressure of a sphere (paper eqs 11-13) is the convolution
``p(t') = ∫_0^∞ h(ξ) A(t' - ξ) dξ`` with ``h(ξ) = P0 Re[C e^{sξ}]``, ``|h(ξ)| <= |P0||C| e^{-lξ}``,
``l = c/a`` and ``t' = t - (r - a)/c``. Expanding ``A(t' - ξ)`` about ``ξ = 0`` gives the
classical limits of a compact sphere (``l τ >> 1``: the pulse long against ``a/c``)::

    p ≈ ρ a³ cosθ / (2 r²) · [A(t') + ((r - a)/c) A'(t')]

* **near field** (incompressible flow): ``p_near = ρ a³ cosθ A(t') / (2 r²)``;
* **far field** (radiating dipole): ``p_far = ρ a³ cosθ A'(t') / (2 r c)``;
* **numerical convolution** of the sampled pulse with the sampled kernel, the textbook method
  (its error depends on the step; it has no cheap proven bound and serves as the baseline of
  the benchmark and the chart, not in the tolerance selection).

Error bounds (Pa), with ``|A|_∞``, ``L1 = sup|A'|``, ``L2 = sup|A''|`` (inside pieces) and
``J`` the sum of the jumps of ``A'`` (a half-sine has ``J = 2 A_max π/τ``; for a sampled,
piecewise-linear pulse ``J`` is its largest slope jump and ``L2 = 2 J / h_min``, since over a
window ``u`` its slope changes by at most ``J (1 + u/h_min)``). ``A`` must be continuous, as
the half-sine and Hertz pulses are::

    |p - p_near| <= |P0||C| L1 / l²
    |p - p_far|  <= |P0||C| (L2 / l³ + J / l²) + |M0| (|A|_∞ + L1 / l),   M0 = ρ a³ cosθ / (2 r²)

from ``|A(t'-ξ) - A(t')| <= L1 ξ``, ``|A(t'-ξ) - A(t') + ξ A'(t')| <= min(L2 ξ²/2 + J ξ, TV ξ)`` and
``∫ ξ^k e^{-lξ} dξ = k!/l^{k+1}``. They hold at every time, so they also bound the error of
peaks and (by Minkowski's inequality) of RMS values. For a sum over image sources the
bounds add.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import ParameterError, check_positive
from .contact import HalfSinePulse, SampledPulse
from .medium import AIR, Medium
from .radiation import arrival_time, impulse_response

__all__ = [
    "MODELS",
    "SELECTION_ORDER",
    "PulseBounds",
    "pulse_bounds",
    "pulse_derivative",
    "near_field_pressure",
    "far_field_pressure",
    "convolution_pressure",
    "near_field_bound",
    "far_field_bound",
    "choose_models",
    "window_metrics",
]

#: Model names; their index is the code stored in ``FieldMetrics.model``.
MODELS = ("exact", "near-field", "far-field")
#: Order in which a tolerance tries the models: cheapest first, exact last.
SELECTION_ORDER = ("near-field", "far-field", "exact")


class PulseBounds(tuple):
    """Sup norms of a pulse: ``(A_max, L1, L2, J, TV)``.

    ``A_max = sup|A|`` (m/s²), ``L1 = sup|A'|`` (m/s³), ``L2`` bounds ``|A''|`` (m/s⁴), ``J``
    the jumps of ``A'`` (m/s³) with ``|A'(t) - A'(t - u)| <= J + L2 u``, and ``TV`` the total
    variation of ``A'`` (m/s³), another bound of ``|A'(t) - A'(t - u)|``.
    """

    __slots__ = ()

    def __new__(cls, a_max, l1, l2, jumps, total_variation):  # noqa: D102
        vals = (a_max, l1, l2, jumps, total_variation)
        return super().__new__(cls, tuple(float(v) for v in vals))

    a_max = property(lambda self: self[0])
    l1 = property(lambda self: self[1])
    l2 = property(lambda self: self[2])
    jumps = property(lambda self: self[3])
    total_variation = property(lambda self: self[4])


def _check_pulse(pulse):
    if not isinstance(pulse, (HalfSinePulse, SampledPulse)):
        raise ParameterError("pulse", f"expected a HalfSinePulse or SampledPulse, got {type(pulse).__name__}")
    return pulse


def pulse_bounds(pulse) -> PulseBounds:
    """Sup norms of a pulse and its derivatives used by the error bounds.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        The acceleration pulse.

    Returns
    -------
    PulseBounds
        ``inf`` for ``L1`` (and the far-field terms) if the pulse is discontinuous (a sampled
        pulse that does not start and end at zero).
    """
    _check_pulse(pulse)
    if isinstance(pulse, HalfSinePulse):
        amp = abs(pulse.amplitude)
        w = math.pi / pulse.duration
        return PulseBounds(amp, amp * w, amp * w * w, 2 * amp * w, 4 * amp * w)
    acc = pulse.acceleration_samples
    slope = np.diff(acc) / np.diff(pulse.times)
    scale = np.max(np.abs(acc))
    if abs(acc[0]) > 1e-12 * scale or abs(acc[-1]) > 1e-12 * scale:
        return PulseBounds(scale, math.inf, math.inf, math.inf, math.inf)
    # A' is piecewise constant: over a window u it changes by at most J (1 + u / h_min), with
    # J the largest jump; so L2 = J / h_min plays the part of sup|A''|.
    jumps = np.abs(np.diff(np.r_[0.0, slope, 0.0]))
    jump = np.max(jumps)
    return PulseBounds(scale, np.max(np.abs(slope)), 2.0 * jump / np.min(np.diff(pulse.times)), jump, jumps.sum())


def pulse_derivative(pulse, t):
    """Right derivative ``A'(t)`` of the acceleration in m/s³ (zero outside the pulse)."""
    _check_pulse(pulse)
    t = np.asarray(t, dtype=float)
    if isinstance(pulse, HalfSinePulse):
        w = math.pi / pulse.duration
        inside = (t >= 0) & (t < pulse.duration)
        return np.where(inside, pulse.amplitude * w * np.cos(w * np.clip(t, 0, pulse.duration)), 0.0)
    xi = pulse.times
    slope = np.diff(pulse.acceleration_samples) / np.diff(xi)
    k = np.clip(np.searchsorted(xi, t, side="right") - 1, 0, slope.size - 1)
    return np.where((t >= 0) & (t < xi[-1]), slope[k], 0.0)


def _geometry(distance, cos_theta, radius, medium):
    a = check_positive("radius", radius, "m")
    r = np.asarray(distance, dtype=float)
    if np.any(r < a * (1 - 1e-12)):
        raise ParameterError("distance", f"observer inside the sphere: need r >= radius = {a:g} m")
    return a, r, np.asarray(cos_theta, dtype=float)


def near_field_pressure(pulse, t, distance, cos_theta, *, radius: float, medium: Medium = AIR):
    """Incompressible near-field pressure ``ρ a³ cosθ A(t') / (2 r²)`` in Pa.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration of the sphere in m/s².
    t : array_like
        Time in s from the start of contact.
    distance, cos_theta : array_like
        Distance in m from the centre and cosine of the polar angle; broadcast with ``t``.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    ndarray
        Pressure in Pa (error bound: :func:`near_field_bound`).

    Notes
    -----
    Zeroth moment of paper eq 11: ``∫ h dt' = ρ a³ cosθ / (2 r²)``.
    """
    a, r, ct = _geometry(distance, cos_theta, radius, medium)
    tr = np.asarray(t, dtype=float) - arrival_time(r, radius=a, medium=medium)
    return medium.rho * a**3 * ct / (2 * r * r) * _check_pulse(pulse).acceleration(tr)


def far_field_pressure(pulse, t, distance, cos_theta, *, radius: float, medium: Medium = AIR):
    """Radiating compact-dipole pressure ``ρ a³ cosθ A'(t') / (2 r c)`` in Pa.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration of the sphere in m/s².
    t : array_like
        Time in s from the start of contact.
    distance, cos_theta : array_like
        Distance in m from the centre and cosine of the polar angle; broadcast with ``t``.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    ndarray
        Pressure in Pa (error bound: :func:`far_field_bound`).

    Notes
    -----
    First moment of paper eq 11, ``∫ t' h dt' = ρ a³ cosθ (a - r) / (2 c r²)``, at ``r >> a``.
    """
    a, r, ct = _geometry(distance, cos_theta, radius, medium)
    tr = np.asarray(t, dtype=float) - arrival_time(r, radius=a, medium=medium)
    return medium.rho * a**3 * ct / (2 * r * medium.c) * pulse_derivative(pulse, tr)


def convolution_pressure(pulse, t, distance, cos_theta, *, radius: float, medium: Medium = AIR, step=None):
    """Pressure in Pa by direct numerical convolution of the sampled pulse and kernel (eq 12).

    The acceleration and the impulse response (paper eq 11) are sampled every ``step`` s and
    convolved with the trapezoidal rule (by FFT); the result is interpolated linearly to ``t``.
    This is the straightforward method: all N samples of every observer, O(N log N) each.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration of the sphere in m/s².
    t : (m,) array_like
        Times in s.
    distance, cos_theta : float
        One observer: distance in m from the centre, cosine of the polar angle.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.
    step : float, optional
        Sampling step in s (default ``min(T, a/c) / 64``).

    Returns
    -------
    (m,) ndarray
        Pressure in Pa; the error is O((step · c/a)²).
    """
    a, r, ct = _geometry(distance, cos_theta, radius, medium)
    if r.ndim or ct.ndim:
        raise ParameterError("distance", "convolution_pressure takes one observer (scalars)")
    dt = min(pulse.duration, a / medium.c) / 64 if step is None else check_positive("step", step, "s")
    tr = np.asarray(t, dtype=float) - arrival_time(r, radius=a, medium=medium)
    top = max(float(np.max(tr)), 0.0)
    n = int(math.ceil(top / dt)) + 2
    grid = np.arange(n) * dt
    acc = pulse.acceleration(grid)
    h = impulse_response(grid + arrival_time(r, radius=a, medium=medium), r, ct, radius=a, medium=medium)
    h[0] *= 0.5  # trapezoid; the other end term carries A(0) = 0 for continuous pulses
    from scipy.signal import fftconvolve

    conv = fftconvolve(acc, h)[:n] * dt
    return np.interp(tr, grid, conv, left=0.0)


def near_field_bound(pulse, p0, c_shape, *, radius: float, medium: Medium = AIR):
    """Proven bound in Pa on ``|p - p_near|`` at all times: ``|P0||C| L1 (a/c)²``.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        The acceleration pulse.
    p0, c_shape : array_like
        ``P0`` (Pa·s/m) and ``C`` from :func:`acoustiviz.core.radiation.radiation_coefficients`.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    ndarray
        Bound in Pa, shaped like ``p0``.
    """
    b = pulse_bounds(pulse)
    inv_l = check_positive("radius", radius, "m") / medium.c
    with np.errstate(invalid="ignore"):
        return np.abs(p0) * np.abs(c_shape) * b.l1 * inv_l**2


def far_field_bound(pulse, p0, c_shape, *, radius: float, medium: Medium = AIR):
    """Proven bound in Pa on ``|p - p_far|``: ``|P0||C|(L2/l³ + J/l²) + |M0|(|A|_∞ + L1/l)``.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        The acceleration pulse.
    p0, c_shape : array_like
        ``P0`` (Pa·s/m) and ``C`` from :func:`acoustiviz.core.radiation.radiation_coefficients`.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    ndarray
        Bound in Pa, shaped like ``p0``.

    Notes
    -----
    ``M0 = ρ a³ cosθ/(2r²) = P0 a/(2c)``.
    """
    b = pulse_bounds(pulse)
    inv_l = check_positive("radius", radius, "m") / medium.c
    p0 = np.abs(p0)
    with np.errstate(invalid="ignore"):
        local = min(b.l2 * inv_l**3 + b.jumps * inv_l**2, b.total_variation * inv_l**2)
        rem = p0 * np.abs(c_shape) * local
        return rem + 0.5 * p0 * inv_l * (b.a_max + b.l1 * inv_l)


def choose_models(pulse, delay, p0, c_shape, tolerance: float, *, radius: float, medium: Medium = AIR):
    """Per point, the code (index in :data:`MODELS`) of the cheapest model within ``tolerance``.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        The acceleration pulse.
    delay, p0, c_shape : (n, k) array_like
        Per point and image source: delay (s), ``P0`` and ``C`` (see
        :func:`acoustiviz.field.source_geometry`).
    tolerance : float
        Absolute error allowed in Pa; the bounds of all images add.
    radius : float
        Sphere radius in m.
    medium : Medium
        The fluid.

    Returns
    -------
    (n,) ndarray of uint8
        Model codes; NaN rows (points outside the fluid) get the exact model.
    """
    tol = check_positive("tolerance", tolerance, "Pa")
    out = np.zeros(np.shape(p0)[0], dtype=np.uint8)
    chosen = np.zeros(out.size, dtype=bool)
    bounds = {"near-field": near_field_bound, "far-field": far_field_bound}
    for name in SELECTION_ORDER:
        if name == "exact":
            break
        err = np.sum(bounds[name](pulse, p0, c_shape, radius=radius, medium=medium), axis=1)
        ok = (err <= tol) & ~chosen
        out[ok] = MODELS.index(name)
        chosen |= ok
    return out


def window_metrics(name, pulse, delay, p0, t0, dt, m, *, radius, medium=AIR, max_bytes=2**24):
    """Max, min and Σp² of a cheap model over the grids ``t0[i] + k dt``, k < m.

    Parameters
    ----------
    name : {"near-field", "far-field"}
        The model.
    pulse : HalfSinePulse or SampledPulse
        The acceleration pulse.
    delay, p0 : (n, k) ndarray
        Delays in s and ``P0`` in Pa·s/m per point and image.
    t0 : (n,) ndarray
        Start of each point's grid in s.
    dt : float
        Step in s.
    m : int
        Samples per point.
    radius : float
        Sphere radius in m.
    medium : Medium
        The fluid.
    max_bytes : int
        Working memory for the sample blocks, in bytes.

    Returns
    -------
    (n, 3) ndarray
        Largest and smallest pressure in Pa and the sum of squares in Pa².
    """
    n = delay.shape[0]
    res = np.zeros((n, 3))
    rows = max(1, int(max_bytes // (8 * 4 * max(m, 1))))
    k = np.arange(m) * dt
    fac = 0.5 * radius / medium.c  # M0 = P0 a/(2c)
    for lo in range(0, n, rows):
        hi = min(lo + rows, n)
        p = np.zeros((hi - lo, m))
        for j in range(delay.shape[1]):
            tr = t0[lo:hi, None] + k[None, :] - delay[lo:hi, j : j + 1]
            if name == "near-field":
                p += (fac * p0[lo:hi, j : j + 1]) * pulse.acceleration(tr)
            elif name == "far-field":
                r = delay[lo:hi, j : j + 1] * medium.c + radius
                p += (fac * p0[lo:hi, j : j + 1] * r / medium.c) * pulse_derivative(pulse, tr)
            else:
                raise ParameterError("model", f"unknown cheap model {name!r}")
        res[lo:hi, 0] = np.maximum(p.max(axis=1), 0.0)
        res[lo:hi, 1] = np.minimum(p.min(axis=1), 0.0)
        res[lo:hi, 2] = np.einsum("ij,ij->i", p, p)
    return res
