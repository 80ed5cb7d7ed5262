"""Transient sound radiated by a rigid sphere under an impulsive acceleration (paper eqs 5-13).

A rigid sphere of radius ``a`` whose centre undergoes a velocity step radiates, at distance
``r`` and polar angle ``θ`` from the acceleration axis (paper eq 11)::

    h(t') = ρ c (a² cosθ / r²) [(1 - r/a) sin(l t') + (r/a) cos(l t')] exp(-l t'),

with ``t' = t - (r - a)/c >= 0`` and ``l = c/a``. Writing the bracket as
``Re[C exp(s t')]`` with ``C = r/a - i (1 - r/a)`` and ``s = l (-1 + i)`` separates the
observer (``P0 = ρ c a² cosθ / r²`` and ``C``) from time. The pressure for any acceleration
``A(t)`` (paper eqs 12-13) is therefore::

    p(r, θ, t) = P0 · Re[C · Y(t')],   Y(t') = ∫_0^{t'} exp(s (t' - ξ)) A(ξ) dξ,

and ``Y`` -- the *pulse response* -- is computed once per pulse and sphere, whatever the
number of observers. For the half-sine pulse ``Y`` has a closed form; for a sampled pulse it
is integrated exactly over the piecewise-linear acceleration; for the exact Hertz pulse it is
the exact solution of ``Y' = s Y + A`` over a piecewise-polynomial form of the closed-form pulse
(degree 10 on 76 pieces, error < 1e-13 of the peak), written as a Taylor series in each piece
(:func:`hertz_response_table`), and ``Y(τ) exp(s (t' - τ))`` after contact. None of the forms
ever builds ``exp(+l ξ)``, so all stay finite and accurate for any ``l τ``.

Times ``t`` are measured from the start of contact at the sphere, in s; distances in m;
pressures in Pa.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .._validate import ParameterError, check_points, check_positive
from ..constants import HERTZ_DURATION_CONSTANT
from .contact import HalfSinePulse, HertzPulse, SampledPulse, hertz_pulse_shape
from .medium import AIR, Medium

__all__ = [
    "sphere_pole",
    "radiation_coefficients",
    "impulse_response",
    "pulse_response",
    "pulse_response_function",
    "pressure",
    "sphere_pressure",
    "arrival_time",
    "hertz_shape_pieces",
    "hertz_response_table",
]


def sphere_pole(radius: float, medium: Medium = AIR) -> complex:
    """The complex pole ``s = (c/a)(-1 + i)`` of the rigid-sphere dipole response, in 1/s."""
    a = check_positive("radius", radius, "m")
    lam = medium.c / a
    return complex(-lam, lam)


def radiation_coefficients(distance, cos_theta, *, radius: float, medium: Medium = AIR):
    """Observer factors ``P0 = ρ c a² cosθ / r²`` (Pa·s/m) and ``C = r/a - i(1 - r/a)``.

    Parameters
    ----------
    distance : array_like
        Distance r from the sphere's centre in m (>= radius).
    cos_theta : array_like
        Cosine of the angle between the acceleration axis and the direction to the observer.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    P0 : ndarray
        Real amplitude in Pa per (m/s) of velocity step.
    C : ndarray
        Complex shape coefficient (dimensionless).
    """
    a = check_positive("radius", radius, "m")
    r = np.asarray(distance, dtype=float)
    if np.any(r < a * (1 - 1e-12)):
        raise ParameterError("distance", f"observer inside the sphere: need r >= radius = {a:g} m")
    ct = np.asarray(cos_theta, dtype=float)
    p0 = medium.rho * medium.c * a * a * ct / (r * r)
    ra = r / a
    return p0, ra - 1j * (1.0 - ra)


def arrival_time(distance, *, radius: float, medium: Medium = AIR):
    """Time ``(r - a)/c`` in s for sound to travel from the sphere's surface to distance r."""
    return (np.asarray(distance, dtype=float) - radius) / medium.c


def impulse_response(t, distance, cos_theta, *, radius: float, medium: Medium = AIR):
    """Pressure in Pa per unit velocity step (m/s) of the sphere (paper eq 11).

    Parameters
    ----------
    t : array_like
        Time in s since the velocity step (the impulsive acceleration) at the sphere.
    distance, cos_theta : array_like
        Observer distance in m from the centre and cosine of its polar angle; broadcast with t.
    radius : float
        Sphere radius in m.
    medium : Medium
        The fluid.

    Returns
    -------
    ndarray
        ``h`` in Pa/(m/s), zero before the arrival time ``(r - a)/c``.

    Notes
    -----
    ``h(0+) = ρ c (a/r) cosθ`` (the plane-wave piston limit) and
    ``∫ h dt = ρ a³ cosθ / (2 r²)`` (the incompressible dipole).

    Examples
    --------
    On the axis of the paper's 19.05 mm radius sphere at 0.7 m in air the response is zero until
    the sound arrives, ``(r - a)/c`` = 1.984 ms later, then jumps to ``ρ c a / r`` = 11.25 Pa per
    m/s of velocity step:

    >>> a, r = 0.01905, 0.7
    >>> arrival = (r - a) / 343.2
    >>> np.round(impulse_response([arrival - 1e-6, arrival], r, 1.0, radius=a), 4)
    array([ 0.    , 11.2453])
    >>> round(1.204 * 343.2 * a / r, 4)
    11.2453
    """
    p0, cc = radiation_coefficients(distance, cos_theta, radius=radius, medium=medium)
    s = sphere_pole(radius, medium)
    tr = np.asarray(t, dtype=float) - arrival_time(distance, radius=radius, medium=medium)
    on = tr >= 0
    trc = np.where(on, tr, 0.0)
    return np.where(on, p0 * np.real(cc * np.exp(s * trc)), 0.0)


# --------------------------------------------------------------------------- pulse responses
def _phi12(z):
    """φ1(z) = (e^z - 1)/z and φ2(z) = (e^z - 1 - z)/z², accurate for every complex z, Re z <= 0."""
    z = np.asarray(z, dtype=complex)
    phi1 = np.empty_like(z)
    phi2 = np.empty_like(z)
    small = np.abs(z) < 0.25
    zl = z[~small]
    ez = np.exp(zl)
    phi1[~small] = (ez - 1.0) / zl
    phi2[~small] = (ez - 1.0 - zl) / (zl * zl)
    zs = z[small]
    # Taylor series: phi_k(z) = sum_j z^j / (j + k)!; 14 terms give < 1e-17 at |z| = 0.25
    t1 = np.zeros_like(zs)
    t2 = np.zeros_like(zs)
    for j in range(14, -1, -1):
        t1 = t1 * zs + 1.0 / math.factorial(j + 1)
        t2 = t2 * zs + 1.0 / math.factorial(j + 2)
    phi1[small] = t1
    phi2[small] = t2
    return phi1, phi2


def _half_sine_response(pulse: HalfSinePulse, s: complex, tr: np.ndarray) -> np.ndarray:
    tau = pulse.duration
    w = math.pi / tau
    den = s * s + w * w  # = w² - 2 i l², never zero
    y = np.zeros(tr.shape, dtype=complex)
    during = (tr >= 0) & (tr < tau)
    after = tr >= tau
    td = tr[during]
    y[during] = (-s * np.sin(w * td) - w * np.cos(w * td) + w * np.exp(s * td)) / den
    # after the contact both terms decay alike, e^{s t} = e^{s τ} e^{s (t - τ)}: one complex exp per sample
    y[after] = (w * (1.0 + np.exp(s * tau)) / den) * np.exp(s * (tr[after] - tau))
    return pulse.amplitude * y


def _knot_states(times: np.ndarray, acc: np.ndarray, s: complex) -> np.ndarray:
    """Y at every knot of a piecewise-linear pulse, by the exact first-order-hold recursion."""
    h = np.diff(times)
    z = s * h
    phi1, phi2 = _phi12(z)
    decay = np.exp(z)
    forcing = h * (acc[:-1] * phi1 + np.diff(acc) * phi2)
    y = np.empty(times.size, dtype=complex)
    y[0] = 0.0
    acc_y = 0j
    for k in range(h.size):  # sequential but only over the pulse's knots (~1e3)
        acc_y = decay[k] * acc_y + forcing[k]
        y[k + 1] = acc_y
    return y


def _sampled_response(pulse: SampledPulse, s: complex, yk: np.ndarray, tr: np.ndarray) -> np.ndarray:
    """``Y`` of a piecewise-linear pulse at ``tr`` (s), given its knot states ``yk`` (:func:`_knot_states`)."""
    xi = pulse.times
    acc = pulse.acceleration_samples
    y = np.zeros(tr.shape, dtype=complex)
    end = xi[-1]
    during = (tr >= 0) & (tr < end)
    after = tr >= end
    td = tr[during]
    k = np.minimum(np.maximum(np.searchsorted(xi, td, side="right") - 1, 0), xi.size - 2)  # np.clip, cheaper
    delta = td - xi[k]
    hk = xi[k + 1] - xi[k]
    slope = (acc[k + 1] - acc[k]) / hk
    phi1, phi2 = _phi12(s * delta)
    y[during] = np.exp(s * delta) * yk[k] + delta * (acc[k] * phi1 + slope * delta * phi2)
    y[after] = np.exp(s * (tr[after] - end)) * yk[-1]
    return y


#: Polynomial degree and number of the pieces of the exact Hertz pulse shape.
_HERTZ_DEGREE = 10
_HERTZ_PIECES = 64
#: The end pieces are graded geometrically (ratio, count) towards the θ^{3/2} behaviour at both ends.
_HERTZ_GRADING = 0.2
_HERTZ_GRADED = 6
#: Largest |s h| of a piece of the Taylor table and the number of Taylor terms kept.
_TAYLOR_STEP = 0.5
_TAYLOR_TERMS = 18  # 0.5**18 / 18! < 1e-21


@functools.lru_cache(maxsize=1)
def hertz_shape_pieces():
    """The exact Hertz pulse shape as polynomial pieces over the contact (a constant of nature).

    Returns
    -------
    breaks : (N + 1,) ndarray
        Piece boundaries as fractions of the contact duration: ``(1 - cos(π k/64))/2``, the
        end pieces cut again geometrically (ratio 0.2, 6 times) towards both ends.
    coef : (N, P + 1) ndarray
        Monomial coefficients of ``s(θ_c x)^{3/2}`` in the local variable ``u ∈ [0, 1]`` of each
        piece (Chebyshev interpolation of :func:`acoustiviz.core.pulses.hertz_pulse_shape` at
        ``P + 1`` points; error below 1e-13 of the peak).
    """
    deg = _HERTZ_DEGREE
    inner = 0.5 * (1.0 - np.cos(np.pi * np.arange(1, _HERTZ_PIECES) / _HERTZ_PIECES))
    graded = inner[0] * _HERTZ_GRADING ** np.arange(_HERTZ_GRADED, 0, -1)  # towards the s^{3/2} ends
    breaks = np.concatenate([[0.0], graded, inner, 1.0 - graded[::-1], [1.0]])
    n = breaks.size - 1
    cheb = np.polynomial.chebyshev
    coef = np.empty((n, deg + 1))
    for k in range(n):
        lo, h = breaks[k], breaks[k + 1] - breaks[k]
        c = cheb.chebinterpolate(
            lambda v, lo=lo, h=h: hertz_pulse_shape(HERTZ_DURATION_CONSTANT * (lo + h * (v + 1) / 2)), deg)
        poly = np.polynomial.Chebyshev(c, domain=[0.0, 1.0]).convert(kind=np.polynomial.Polynomial,
                                                                      domain=[0.0, 1.0], window=[0.0, 1.0])
        coef[k] = np.pad(poly.coef, (0, deg + 1 - poly.coef.size))
    breaks.setflags(write=False)
    coef.setflags(write=False)
    return breaks, coef


def _split_pieces(breaks, coef, m: int):
    """Cut every polynomial piece into ``m`` equal ones (exact re-expansion of the monomials)."""
    if m == 1:
        return breaks, coef
    deg = coef.shape[1] - 1
    from math import comb

    n = coef.shape[0]
    new_breaks = (breaks[:-1, None] + np.diff(breaks)[:, None] * (np.arange(m) / m)[None, :]).reshape(-1)
    new_breaks = np.append(new_breaks, breaks[-1])
    out = np.empty((n, m, deg + 1))
    for i in range(m):
        # u = (i + v)/m: u^j = sum_l C(j, l) i^(j-l) v^l / m^j
        t = np.zeros((deg + 1, deg + 1))
        for j in range(deg + 1):
            for q in range(j + 1):
                t[j, q] = comb(j, q) * float(i) ** (j - q) / float(m) ** j
        out[:, i, :] = coef @ t
    return new_breaks, out.reshape(n * m, deg + 1)


def hertz_response_table(pulse: HertzPulse, s: complex, *, split: int = 1, rtol: float = 1e-19):
    """Exact ``Y`` of a Hertz pulse as a Taylor polynomial on each piece of the contact.

    ``Y' = s Y + A`` is solved exactly on each piece ``[t_k, t_k + h_k]`` of the piecewise
    polynomial pulse (:func:`hertz_shape_pieces`, pieces cut so that ``|s| h_k <= 0.5``): with
    ``u = (t - t_k)/h_k`` and ``Y = Σ β_m u^m``, ``(m + 1) β_{m+1} = h_k (s β_m + a_m)`` where
    ``a_m`` are the pulse's coefficients, and ``β_0 = Y(t_k)`` chains the pieces. 18 terms leave
    a truncation below 1e-21 of ``|Y|``.

    Parameters
    ----------
    pulse : HertzPulse
        The pulse.
    s : complex
        The sphere's pole (:func:`sphere_pole`) in 1/s.
    split : int
        Cut every piece into at least this many (shorter pieces need fewer terms).
    rtol : float
        Terms below ``rtol · max|Y|`` at the end of a piece's series are dropped.

    Returns
    -------
    knots : (K + 1,) ndarray
        Piece boundaries in s (``knots[-1]`` is the duration).
    table : (K, M) complex ndarray
        ``β_m`` of each piece in m/s (zero beyond each piece's own number of terms).
    terms : (K,) ndarray of int
        Number of terms kept in each piece.
    """
    breaks, coef = hertz_shape_pieces()
    return _response_table(breaks, coef, pulse.amplitude, pulse.duration, s, split, rtol)


def half_sine_shape_pieces(pieces: int = 16, degree: int = 12):
    """The half-sine ``sin(π x)``, ``0 <= x <= 1``, as polynomial pieces (Taylor series about each piece's start).

    Parameters
    ----------
    pieces : int
        Equal pieces.
    degree : int
        Polynomial degree: the truncation is below ``(π/pieces)^(degree+1)/(degree+1)!``
        (1e-19 by default).

    Returns
    -------
    breaks : (pieces + 1,) ndarray
        Piece boundaries as fractions of the duration.
    coef : (pieces, degree + 1) ndarray
        Monomial coefficients in the local variable ``u ∈ [0, 1]`` of each piece.
    """
    breaks = np.linspace(0.0, 1.0, pieces + 1)
    m = np.arange(degree + 1)
    scale = np.array([(np.pi / pieces) ** j / math.factorial(j) for j in m])
    coef = scale[None, :] * np.sin(np.pi * breaks[:-1, None] + 0.5 * np.pi * m[None, :])
    return breaks, coef


def half_sine_response_table(pulse: HalfSinePulse, s: complex, *, split: int = 1, rtol: float = 1e-19):
    """Exact ``Y`` of a half-sine pulse as a Taylor polynomial on each piece (as :func:`hertz_response_table`).

    The same representation as the exact Hertz pulse's (its closed form is
    :func:`pulse_response`), for kernels that evaluate ``Y`` and its derivatives by Horner.

    Parameters
    ----------
    pulse : HalfSinePulse
        The pulse.
    s : complex
        The sphere's pole in 1/s.
    split : int
        Cut every piece into at least this many.
    rtol : float
        Terms below ``rtol · max|Y|`` at the end of a piece's series are dropped.

    Returns
    -------
    knots, table, terms
        As :func:`hertz_response_table`.
    """
    breaks, coef = half_sine_shape_pieces()
    return _response_table(breaks, coef, pulse.amplitude, pulse.duration, s, split, rtol)


def sampled_response_table(pulse: SampledPulse, s: complex, *, split: int = 1, rtol: float = 1e-19):
    """Exact ``Y`` of a piecewise-linear pulse as a Taylor polynomial on each piece (as :func:`hertz_response_table`).

    Parameters
    ----------
    pulse : SampledPulse
        The pulse (linear between its samples).
    s : complex
        The sphere's pole in 1/s.
    split : int
        Cut every piece between two samples into at least this many.
    rtol : float
        Terms below ``rtol · max|Y|`` at the end of a piece's series are dropped.

    Returns
    -------
    knots, table, terms
        As :func:`hertz_response_table`.
    """
    t = np.asarray(pulse.times, dtype=float)
    a = np.asarray(pulse.acceleration_samples, dtype=float)
    coef = np.column_stack([a[:-1], np.diff(a)])  # A = a_k + (a_{k+1} - a_k) u on each piece
    return _response_table(t / t[-1], coef, 1.0, float(t[-1]), s, split, rtol)


def _response_table(breaks, coef, amp: float, tau: float, s: complex, split: int, rtol: float):
    """Taylor table of ``Y' = s Y + A`` on polynomial pieces of ``A / amp`` (fractions of ``tau``)."""
    hmax = float(np.max(np.diff(breaks))) * tau
    m = max(int(split), math.ceil(abs(s) * hmax / _TAYLOR_STEP))
    breaks, coef = _split_pieces(breaks, coef, m)
    knots = breaks * tau
    h = np.diff(knots)
    n, deg = coef.shape[0], coef.shape[1] - 1
    nt = _TAYLOR_TERMS
    hom = np.empty((n, nt), dtype=complex)  # Taylor terms of exp(s h u)
    par = np.zeros((n, nt), dtype=complex)  # of the particular solution with Y(t_k) = 0
    hom[:, 0] = 1.0
    for j in range(nt - 1):
        hom[:, j + 1] = h * s * hom[:, j] / (j + 1)
        force = amp * coef[:, j] if j <= deg else 0.0
        par[:, j + 1] = h * (s * par[:, j] + force) / (j + 1)
    grow = hom.sum(axis=1)
    drive = par.sum(axis=1)
    y = np.empty(n + 1, dtype=complex)
    y[0] = 0.0
    acc = 0j
    for k in range(n):  # sequential over the pieces (~1e2)
        acc = grow[k] * acc + drive[k]
        y[k + 1] = acc
    table = y[:-1, None] * hom + par
    big = np.abs(table) > rtol * max(float(np.abs(y).max()), 1e-300)
    terms = np.where(big.any(axis=1), nt - np.argmax(big[:, ::-1], axis=1), 1)
    table[np.arange(nt)[None, :] >= terms[:, None]] = 0.0
    keep = int(terms.max())
    return knots, np.ascontiguousarray(table[:, :keep]), terms.astype(np.int64)


def _hertz_response(knots: np.ndarray, terms: np.ndarray, yend: complex, s: complex, tr: np.ndarray) -> np.ndarray:
    """``Y`` at ``tr`` (s) from :func:`hertz_response_table`: ``knots``, the table transposed, ``Y`` at the end."""
    end = knots[-1]
    y = np.zeros(tr.shape, dtype=complex)
    during = (tr >= 0) & (tr < end)
    after = tr >= end
    td = tr[during]
    k = np.minimum(np.maximum(np.searchsorted(knots, td, side="right") - 1, 0), knots.size - 2)  # np.clip, cheaper
    u = (td - knots[k]) / (knots[k + 1] - knots[k])
    acc = terms[-1].take(k)
    for j in range(terms.shape[0] - 2, -1, -1):  # Horner, one coefficient row gathered per term
        acc *= u
        acc += terms[j].take(k)
    y[during] = acc
    y[after] = np.exp(s * (tr[after] - end)) * yend
    return y


def pulse_response(pulse, t_ret, *, radius: float, medium: Medium = AIR):
    """Observer-independent response ``Y(t') = ∫_0^{t'} exp(s (t' - ξ)) A(ξ) dξ`` in m/s.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        The sphere's acceleration pulse, starting at t = 0.
    t_ret : array_like
        Retarded time ``t' = t - (r - a)/c`` in s (any shape).
    radius : float
        Sphere radius in m.
    medium : Medium
        The fluid.

    Returns
    -------
    ndarray of complex
        ``Y`` shaped like ``t_ret``; zero for ``t' < 0``. The pressure at an observer is
        ``P0 Re[C Y]`` (see :func:`radiation_coefficients`).

    Notes
    -----
    Half-sine: closed form of paper eq 13 for both intervals (during and after contact).
    Exact Hertz (:class:`~acoustiviz.core.pulses.HertzPulse`): exact solution over a piecewise
    polynomial form of the closed-form pulse, error below 1e-12 of the peak
    (:func:`hertz_response_table`). Sampled: exact integral of the kernel over a piecewise-linear acceleration
    (first-order hold), using φ-functions evaluated by series near zero.

    Examples
    --------
    The paper's Figure 2 pulse (peak 9800 m/s², 525.6 µs) on its 19.05 mm radius sphere lasts
    about ten sphere time constants ``a/c``, so during contact ``Y`` follows the acceleration
    quasi-statically, ``|Y| ≈ A(t') / |s|`` with ``|s| = sqrt(2) c/a``; it is zero before
    ``t' = 0`` and has all but decayed two contact lengths later:

    >>> from acoustiviz.core.contact import HalfSinePulse
    >>> a, pulse = 0.01905, HalfSinePulse(9800.0, 525.6e-6)
    >>> y = pulse_response(pulse, [-1e-4, 262.8e-6, 1051.2e-6], radius=a)
    >>> np.round(np.abs(y), 4)  # m/s
    array([0.    , 0.3846, 0.    ])
    >>> round(9800.0 / (math.sqrt(2.0) * 343.2 / a), 4)
    0.3847
    """
    return pulse_response_function(pulse, radius=radius, medium=medium)(t_ret)


def pulse_response_function(pulse, *, radius: float, medium: Medium = AIR):
    """:func:`pulse_response` as a function ``f(t_ret)`` of the retarded time in s, the pulse's tables built once.

    For evaluating ``Y`` (m/s) of one pulse and sphere (radius in m) many times, e.g. in a search for
    an extreme: a sampled pulse's knot states and the Hertz pulse's Taylor table are computed once.

    >>> from acoustiviz.core.contact import HalfSinePulse
    >>> pulse = HalfSinePulse(9800.0, 525.6e-6)
    >>> bool(pulse_response_function(pulse, radius=0.01905)(3e-4) == pulse_response(pulse, 3e-4, radius=0.01905))
    True
    """
    s = sphere_pole(radius, medium)
    if isinstance(pulse, HalfSinePulse):
        evaluate = functools.partial(_half_sine_response, pulse, s)
    elif isinstance(pulse, HertzPulse):
        knots, table, _ = hertz_response_table(pulse, s)
        evaluate = functools.partial(_hertz_response, knots, np.ascontiguousarray(table.T), table[-1].sum(), s)
    elif isinstance(pulse, SampledPulse):
        yk = _knot_states(pulse.times, pulse.acceleration_samples, s)
        evaluate = functools.partial(_sampled_response, pulse, s, yk)
    else:
        raise ParameterError("pulse", f"expected a HalfSinePulse or SampledPulse, got {type(pulse).__name__}")
    return lambda t_ret: evaluate(np.asarray(t_ret, dtype=float))


def pressure(pulse, t, distance, cos_theta, *, radius: float, medium: Medium = AIR):
    """Pressure in Pa radiated by a sphere with acceleration ``pulse`` (paper eqs 12-13).

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration of the sphere along its axis, starting at t = 0, in m/s².
    t : array_like
        Time in s from the start of contact.
    distance, cos_theta : array_like
        Observer distance in m from the sphere's centre and cosine of its angle from the
        acceleration axis. ``t``, ``distance`` and ``cos_theta`` broadcast together.
    radius : float
        Sphere radius in m.
    medium : Medium
        The fluid (default: air at 20 °C).

    Returns
    -------
    ndarray
        Pressure in Pa, zero before the arrival time ``(r - a)/c``.

    Examples
    --------
    >>> from acoustiviz.core.contact import Impact, acceleration_pulse
    >>> imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=0.2244)
    >>> pulse = acceleration_pulse(imp, "half-sine")
    >>> t = np.linspace(0, 3e-3, 7)
    >>> pressure(pulse, t, 0.7, np.cos(np.pi / 4), radius=0.01905).shape
    (7,)
    """
    p0, cc = radiation_coefficients(distance, cos_theta, radius=radius, medium=medium)
    tr = np.asarray(t, dtype=float) - arrival_time(distance, radius=radius, medium=medium)
    y = pulse_response(pulse, tr, radius=radius, medium=medium)
    return p0 * np.real(cc * y)


def sphere_pressure(pulse, t, points, *, radius: float, centre=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
                    medium: Medium = AIR):
    """Pressure in Pa at many points and times from one sphere in free field.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²), starting at t = 0.
    t : (m,) array_like
        Times in s from the start of contact.
    points : (n, 3) array_like
        Observer positions in m.
    radius : float
        Sphere radius in m.
    centre : (3,) array_like
        Position of the sphere's centre in m.
    axis : (3,) array_like
        Direction of the acceleration (normalised here).
    medium : Medium
        The fluid.

    Returns
    -------
    (n, m) ndarray
        Pressure in Pa.

    Examples
    --------
    The paper's Figure 2 impact in free field: the sphere radiates as a dipole, loudest along its
    acceleration axis and silent at right angles to it (0.7 m from the centre):

    >>> from acoustiviz.core.contact import Impact, acceleration_pulse
    >>> a = 0.01905
    >>> pulse = acceleration_pulse(Impact(1.4, 5.6e8, 7800.0 * 4.0 / 3.0 * math.pi * a**3))
    >>> points = [[0.0, 0.0, 0.7], [0.7, 0.0, 0.0]]  # on the axis, at 90°
    >>> p = sphere_pressure(pulse, np.linspace(0.0, 4e-3, 4001), points, radius=a)
    >>> np.round(np.abs(p).max(axis=1), 4)  # peak |p| in Pa
    array([0.9422, 0.    ])
    """
    pts = check_points("points", points)
    c0 = np.asarray(centre, dtype=float).reshape(3)
    ax = np.asarray(axis, dtype=float).reshape(3)
    norm = np.linalg.norm(ax)
    if not norm > 0:
        raise ParameterError("axis", "must be a non-zero vector")
    ax = ax / norm
    d = pts - c0
    r = np.linalg.norm(d, axis=1)
    if np.any(r < radius * (1 - 1e-12)):
        raise ParameterError("points", f"a point lies inside the sphere (radius {radius:g} m)")
    ct = (d @ ax) / r
    tt = np.atleast_1d(np.asarray(t, dtype=float))
    return pressure(pulse, tt[None, :], r[:, None], ct[:, None], radius=radius, medium=medium)
