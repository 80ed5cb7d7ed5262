"""Sound exposure ``∫ p² dt`` of every point without a time loop: correlations of ``Y`` at the image delays.

With ``a_j = P0_j C_j`` (Pa·s/m) and delays ``d_j`` (:func:`acoustiviz.field.sources.source_geometry`)
the pressure is ``p(t) = Σ_j Re[a_j Y(t - d_j)]`` (paper eqs 12-14), and since
``Re u Re v = ½ Re[u v + u v̄]`` its exposure over the whole response is a small sum over pairs of
images::

    ∫ p² dt = ½ Σ_j Re[a_j² G(0) + |a_j|² H(0)] + Σ_{j<k} Re[a_m a_n G(Δ) + a_m ā_n H(Δ)],

with ``(m, n)`` the pair ordered so that ``Δ = d_m - d_n >= 0`` and the observer-independent
correlations of the pulse response ``G(Δ) = ∫ Y(u) Y(u + Δ) du`` and ``H(Δ) = ∫ Y(u) Ȳ(u + Δ) du``.
For ``Δ >= T`` (no overlap with the pulse) ``Y(u + Δ) = Y(T) exp(s (u + Δ - T))`` makes them
exponentials in closed form; on ``[0, T]`` they are computed once per pulse by Gauss-Legendre
quadrature of the exact ``Y`` (:func:`acoustiviz.core.radiation.pulse_response`) over the pieces
where ``Y`` is smooth, and stored as piecewise Chebyshev series. A point then costs a few
series evaluations per pair of images: no time grid, no sampling error.

With many images (a room's) the pairs further apart than ``T`` are summed at once: their
correlations are one damped exponential ``exp(s Δ)``, so that, the arrivals sorted, a running sum
carried from one arrival to the next holds all of them (:func:`_exposure_sorted`); only the pairs
arriving within ``T`` of each other read the table. The cost is ``O(n)`` (the arrivals are sorted
by buckets, :mod:`acoustiviz.field._arrivals`) plus those close pairs instead of ``O(n²)``, and
the result the same sum. For the half-sine pulse the close pairs are running sums too
(:mod:`acoustiviz.field._exposure_closed`: ``G`` and ``H`` on ``[0, T]`` are sums of
exponentials in the lag there), and a point costs ``O(n)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._jit import njit as _njit
from .._validate import check_points
from ..core.contact import HalfSinePulse
from ..core.geometry import Geometry
from ..core.medium import AIR, Medium
from ..core.radiation import hertz_shape_pieces, pulse_response_function
from ._arrivals import _arrival_order
from ._common import DEFAULT_MEMORY_LIMIT, check_geometry, check_pulse, pulse_args
from ._exposure_closed import EPOCH, _exposure_closed, closed_tables, half_sine_lag_terms
from .sources import chunk_geometry

__all__ = ["PulseCorrelations", "pulse_correlations", "exposure"]

#: Chebyshev panels over [0, T] (at least; one per 2/|s| for long pulses) and their degree;
#: Gauss-Legendre nodes per smooth piece of Y.
_PANELS = 24
_DEGREE = 16
_GAUSS = 16
#: The evaluation table: cubic Hermite nodes at spacing ``_HERMITE_STEP / |s|`` (interpolation
#: error below ``(|s| h)^4 / 384`` of ``G``'s scale: 2.6e-11), at least 64 and at most 2^18 of them.
_HERMITE_STEP = 0.01
_HERMITE_NODES = (64, 2**18)


@dataclass(frozen=True)
class PulseCorrelations:
    """``G(Δ)`` and ``H(Δ)`` of one pulse and sphere (see the module notes).

    Attributes
    ----------
    duration : float
        Pulse length T in s.
    pole : complex
        The sphere's pole s in 1/s.
    g_coef, h_coef : (panels, degree + 1) complex ndarray
        Chebyshev coefficients on the equal panels of ``[0, T]``, in (m/s)²·s.
    y_end : complex
        ``Y(T)`` in m/s.
    m_g, m_h : complex
        ``∫ Y(u) exp(s u) du`` and ``∫ Y(u) exp(s̄ u) du`` over ``u >= 0``, in m.
    step : float
        Spacing in s of the evaluation table's lags ``0, step, ..., T``.
    table : (nodes, 4) complex ndarray
        ``G``, ``step · G'``, ``H`` and ``step · H'`` at those lags, from the Chebyshev series, for
        cubic Hermite interpolation (what the kernels evaluate; a few multiply-adds per lag).
    lag_terms : (12,) or (0,) complex ndarray
        The half-sine pulse only (kind 0, ``Y`` a sum of three exponentials on ``[0, T]``): ``G``
        and ``H`` on ``[0, T]`` as sums of exponentials in the lag
        (:func:`acoustiviz.field._exposure_closed.half_sine_lag_terms`),
        with which a room's exposure sums its close pairs as running sums
        (:func:`acoustiviz.field._exposure_closed._exposure_closed`); empty for other pulses.
    """

    duration: float
    pole: complex
    g_coef: np.ndarray
    h_coef: np.ndarray
    y_end: complex
    m_g: complex
    m_h: complex
    step: float
    table: np.ndarray
    lag_terms: np.ndarray = field(default_factory=lambda: np.zeros(0, complex))

    def __call__(self, lag):
        """``G`` and ``H`` at lags ``lag >= 0`` in s, in (m/s)²·s."""
        lag = np.atleast_1d(np.asarray(lag, dtype=float))
        g = np.empty(lag.shape, complex)
        h = np.empty(lag.shape, complex)
        for i, d in enumerate(lag.ravel()):
            g.flat[i], h.flat[i] = _correlation_at(d, self.duration, self.pole, self.step, self.table,
                                                   self.y_end, self.m_g, self.m_h)
        return g, h

    def series(self, lag):
        """``G`` and ``H`` at lags ``0 <= lag <= T`` in s from the Chebyshev series (the table's source)."""
        lag = np.atleast_1d(np.asarray(lag, dtype=float))
        return _chebyshev_at(self.g_coef, self.duration, lag), _chebyshev_at(self.h_coef, self.duration, lag)


def _chebyshev_at(coef: np.ndarray, tau: float, lag: np.ndarray, derivative: bool = False) -> np.ndarray:
    """A piecewise Chebyshev series on the equal panels of ``[0, tau]`` (or its derivative) at ``lag``."""
    npan = coef.shape[0]
    pos = np.clip(lag / tau * npan, 0.0, npan)
    p = np.minimum(pos.astype(np.int64), npan - 1)
    x = 2.0 * (pos - p) - 1.0
    out = np.empty(lag.shape, complex)
    cheb = np.polynomial.chebyshev
    for q in np.unique(p):
        sel = p == q
        c = cheb.chebder(coef[q]) * (2.0 * npan / tau) if derivative else coef[q]
        out[sel] = cheb.chebval(x[sel], c)
    return out


def _smooth_breaks(pulse, s: complex, knots: np.ndarray) -> np.ndarray:
    """Points of ``[0, T]`` between which ``Y`` is smooth and well resolved by Gauss-Legendre."""
    tau = pulse.duration
    n = int(min(max(32, math.ceil(abs(s) * tau)), 4000))
    uniform = np.linspace(0.0, tau, n + 1)
    return np.unique(np.concatenate([uniform, knots]))


def _gauss_on(breaks: np.ndarray, x: np.ndarray, w: np.ndarray):
    """Gauss-Legendre nodes ``x`` and weights ``w`` of [-1, 1] on every interval between consecutive ``breaks``."""
    lo, hi = breaks[:-1, None], breaks[1:, None]
    half = 0.5 * (hi - lo)
    return (lo + half * (x[None, :] + 1.0)).ravel(), (half * w[None, :]).ravel()


def pulse_correlations(pulse, radius: float, *, medium: Medium = AIR) -> PulseCorrelations:
    """The correlations ``G`` and ``H`` of the pulse response of one pulse and sphere.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse (m/s²) starting at t = 0.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    PulseCorrelations

    Notes
    -----
    On ``[0, T]``: ``G(Δ) = ∫_0^T Y(u) Y(u + Δ) du + Y(T)² exp(s Δ)/(-2 s)`` (and likewise ``H``
    with ``Ȳ`` and ``-(s + s̄)``), the integral by Gauss-Legendre (16 nodes) on the pieces between
    the pulse's own knots, their shifts by ``-Δ`` and a grid of ``|s| T`` steps, with the exact
    ``Y`` of :func:`acoustiviz.core.radiation.pulse_response` (vectorised, nothing to compile),
    evaluated at the Chebyshev points of 24 panels (more for pulses longer than ``48/|s|``) of
    degree 16; then tabulated with the derivatives of the series for cubic Hermite interpolation
    (nodes ``0.01/|s|`` apart).
    """
    check_pulse(pulse)
    pa = pulse_args(pulse, radius, medium)
    kind, xi, s = pa.kind, pa.xi, pa.s
    tau = float(pulse.duration)

    y_of = pulse_response_function(pulse, radius=radius, medium=medium)  # the pulse's tables once

    def y_at(u):
        return y_of(np.asarray(u, dtype=float).ravel())

    if kind == 0:
        knots = np.array([0.0, tau])
    elif kind == 2:  # the exact pulse's polynomial pieces (Y is smooth inside each; its Taylor knots are finer)
        knots = hertz_shape_pieces()[0] * tau
    else:
        knots = np.asarray(xi, dtype=float)
    base = _smooth_breaks(pulse, s, knots)
    y_end = complex(y_at(np.array([tau]))[0])
    gx, gw = np.polynomial.legendre.leggauss(_GAUSS)
    xg, wg = _gauss_on(base, gx, gw)
    yg = y_at(xg)
    sb = s.conjugate()
    m_g = complex(np.sum(wg * yg * np.exp(s * xg)) + y_end * np.exp(s * tau) / (-2.0 * s))
    m_h = complex(np.sum(wg * yg * np.exp(sb * xg)) + y_end * np.exp(sb * tau) / (-(s + sb)))
    cheb = np.cos(np.pi * (np.arange(_DEGREE + 1) + 0.5) / (_DEGREE + 1))  # Chebyshev points of [-1, 1]
    panels = max(_PANELS, int(math.ceil(abs(s) * tau / 2.0)))
    width = tau / panels
    g_coef = np.empty((panels, _DEGREE + 1), complex)
    h_coef = np.empty((panels, _DEGREE + 1), complex)
    for p in range(panels):
        lags = (p + 0.5 * (cheb + 1.0)) * width
        gv = np.empty(lags.size, complex)
        hv = np.empty(lags.size, complex)
        for i, lag in enumerate(lags):
            cuts = np.concatenate([base, base - lag])
            cuts = np.unique(cuts[(cuts >= 0.0) & (cuts <= tau)])
            x, w = _gauss_on(cuts, gx, gw)
            y0 = y_at(x)
            y1 = y_at(x + lag)
            gv[i] = np.sum(w * y0 * y1) + y_end**2 * np.exp(s * lag) / (-2.0 * s)
            hv[i] = np.sum(w * y0 * np.conj(y1)) + y_end * np.conj(y_end) * np.exp(sb * lag) / (-(s + sb))
        for vals, out in ((gv, g_coef), (hv, h_coef)):
            out[p] = np.polynomial.chebyshev.chebfit(cheb, vals.real, _DEGREE) + \
                1j * np.polynomial.chebyshev.chebfit(cheb, vals.imag, _DEGREE)
    nodes = int(min(max(math.ceil(abs(s) * tau / _HERMITE_STEP), _HERMITE_NODES[0]), _HERMITE_NODES[1]))
    step = tau / nodes
    lag = np.arange(nodes + 1) * step
    table = np.empty((nodes + 1, 4), complex)
    table[:, 0] = _chebyshev_at(g_coef, tau, lag)
    table[:, 1] = step * _chebyshev_at(g_coef, tau, lag, derivative=True)
    table[:, 2] = _chebyshev_at(h_coef, tau, lag)
    table[:, 3] = step * _chebyshev_at(h_coef, tau, lag, derivative=True)
    closed = kind == 0 and isinstance(pulse, HalfSinePulse)
    terms = half_sine_lag_terms(pa.amp, tau, s) if closed else np.zeros(0, complex)
    return PulseCorrelations(tau, s, g_coef, h_coef, y_end, m_g, m_h, step, table, terms)


@_njit
def _correlation_at(lag, tau, s, step, table, y_end, m_g, m_h):  # pragma: no cover - compiled
    """``G(lag)`` and ``H(lag)`` for one lag >= 0 in s (cubic Hermite on the table, closed form after T)."""
    if lag >= tau:
        e = y_end * np.exp(s * (lag - tau))
        return e * m_g, np.conj(e) * m_h
    x = lag / step
    i = min(int(x), table.shape[0] - 2)
    t = x - i
    u = 1.0 - t
    h00 = (1.0 + 2.0 * t) * u * u
    h10 = t * u * u
    h01 = t * t * (3.0 - 2.0 * t)
    h11 = -t * t * u
    g = h00 * table[i, 0] + h10 * table[i, 1] + h01 * table[i + 1, 0] + h11 * table[i + 1, 1]
    h = h00 * table[i, 2] + h10 * table[i, 3] + h01 * table[i + 1, 2] + h11 * table[i + 1, 3]
    return g, h


@_njit(inline="always")
def _exposure_pairs(delays, are, aim, tau, s, step, table, y_end, m_g, m_h, g0, h0):  # pragma: no cover
    """``∫ p² dt`` in Pa²·s at one point from every pair of its images (the module notes' sum).

    ``delays`` (s) and ``are``, ``aim`` (Pa·s/m) are one point's images; ``g0``, ``h0`` the
    correlations at lag 0 (:func:`_correlation_at`), the rest the pulse correlations'.
    """
    nimg = delays.size
    total = 0.0
    for j in range(nimg):
        aj = complex(are[j], aim[j])
        total += 0.5 * (aj * aj * g0 + (are[j] ** 2 + aim[j] ** 2) * h0).real
        for k in range(j + 1, nimg):
            ak = complex(are[k], aim[k])
            lag = delays[j] - delays[k]
            if lag >= 0.0:
                g, h = _correlation_at(lag, tau, s, step, table, y_end, m_g, m_h)
                total += (aj * ak * g + aj * np.conj(ak) * h).real
            else:
                g, h = _correlation_at(-lag, tau, s, step, table, y_end, m_g, m_h)
                total += (aj * ak * g + ak * np.conj(aj) * h).real
    return total


@_njit
def _exposure_kernel(out, delays, are, aim, tau, s, step, table, y_end, m_g, m_h):  # pragma: no cover
    g0, h0 = _correlation_at(0.0, tau, s, step, table, y_end, m_g, m_h)
    for i in range(delays.shape[0]):
        out[i] = _exposure_pairs(delays[i], are[i], aim[i], tau, s, step, table, y_end, m_g, m_h, g0, h0)


#: Above this many sources (a room's images) the exposure sorts the arrivals and sums the pairs
#: further apart than the pulse in closed form, as one running sum (:func:`_exposure_sorted`).
PAIRS_ABOVE = 64
#: Bytes of working memory per point and source of :func:`exposure` (delays, amplitudes, shape
#: coefficients, distances and temporaries), for its chunk under the evaluator's memory cap.
_BYTES_PER_SOURCE = 96


def pair_table(table: np.ndarray) -> np.ndarray:
    """The correlation table recombined for real pair sums: ``Re G ± Re H`` and ``Im G ∓ Im H``.

    Parameters
    ----------
    table : (nodes, 4) complex ndarray
        ``G``, ``step G'``, ``H``, ``step H'`` at the lags (:attr:`PulseCorrelations.table`).

    Returns
    -------
    (nodes, 8) ndarray
        ``Re(G + H)``, ``Im(G - H)``, ``Im(G + H)``, ``Re(G - H)``, each followed by ``step``
        times its derivative, in (m/s)²·s: for a pair ``j`` before ``k``,
        ``Re[a_k a_j G + a_k ā_j H] = a_k' (a_j' A - a_j'' B₋) - a_k'' (a_j'' D + a_j' B₊)``
        (``'`` and ``''`` the real and imaginary parts).
    """
    g, dg, hh, dh = table[:, 0], table[:, 1], table[:, 2], table[:, 3]
    out = np.empty((table.shape[0], 8))
    for col, (v, dv) in enumerate(((g.real + hh.real, dg.real + dh.real), (g.imag - hh.imag, dg.imag - dh.imag),
                                   (g.imag + hh.imag, dg.imag + dh.imag), (g.real - hh.real, dg.real - dh.real))):
        out[:, 2 * col] = v
        out[:, 2 * col + 1] = dv
    return out


@_njit
def _exposure_sorted(ds, ar, ai, tau, s, step, ptab, y_end, m_g, m_h, g0, h0):  # pragma: no cover - compiled
    """``∫ p² dt`` of one point from its sources sorted by arrival (``ds`` ascending), in O(n + close pairs).

    A pair ``j`` before ``k`` with lag ``Δ = d_k - d_j >= T`` correlates in closed form,
    ``G(Δ) = Y(T) e^{s(Δ - T)} m_g`` and ``H(Δ) = conj(Y(T) e^{s(Δ - T)}) m_h``, so that all of them
    together give ``Re[a_k (Y(T) m_g S_k + conj(Y(T)) m_h conj(S_k))]`` with
    ``S_k = Σ_{d_j <= d_k - T} a_j e^{s (d_k - d_j - T)}``, carried from one arrival to the next
    (every factor ``|e^{s x}| <= 1``, ``x >= 0``: no growth of round-off). The pairs closer than
    ``T`` read the tabulated correlations (:func:`pair_table` of :attr:`PulseCorrelations.table`,
    cubic Hermite as :func:`_correlation_at`).
    """
    n = ds.size
    cg = y_end * m_g
    ch = np.conj(y_end) * m_h
    inv = 1.0 / step
    last = ptab.shape[0] - 2  # lags below T = (rows - 1) step read a row and the next
    # S_k = e_k B with e_k = e^{s (d_k - r)} for a reference r moved forward by whole epochs of
    # EPOCH/|Re s| (so |e_k| >= e^{-EPOCH}) and B = Σ a_j e^{-sT} e^{s (r - d_j)}: one exponential
    # per source, the rest products (|e^{s(r - d_j)}| <= e^{EPOCH} for the sources added)
    span = EPOCH / -s.real
    q_epoch = np.exp(s * span)
    fall = np.exp(-s * tau)
    qpow = np.empty(48, np.complex128)  # q_epoch^m (below 1e-300 past 43 epochs: zero)
    qpow[0] = 1.0
    for m in range(1, 48):
        qpow[m] = qpow[m - 1] * q_epoch
    eks = np.empty(n, np.complex128)
    epochs = np.empty(n, np.int64)
    total = 0.0
    ref = ds[0]
    epoch = 0
    bsum = 0j
    first = 0  # the earliest source not yet in S
    for k in range(n):
        dk = ds[k]
        akr = ar[k]
        aki = ai[k]
        ak = complex(akr, aki)
        total += 0.5 * (ak * ak * g0 + (akr * akr + aki * aki) * h0).real
        while dk - ref > span:  # a new epoch: B follows the reference
            ref += span
            epoch += 1
            bsum *= q_epoch
        ek = np.exp(s * (dk - ref))
        eks[k] = ek
        epochs[k] = epoch
        while first < k and ds[first] <= dk - tau:  # e^{s (r - d_j)} = q_epoch^(epochs since j) / e_j
            m = epoch - epochs[first]
            if m < 48:
                bsum += complex(ar[first], ai[first]) * fall * qpow[m] / eks[first]
            first += 1
        acc = ek * bsum
        total += (ak * (cg * acc + ch * np.conj(acc))).real
        close = 0.0
        for j in range(first, k):  # closer than the pulse (lag < T): the table, row below the lag
            x = (dk - ds[j]) * inv
            i = min(int(x), last)
            t = x - i
            u = 1.0 - t
            h00 = (1.0 + 2.0 * t) * u * u
            h10 = t * u * u
            h01 = t * t * (3.0 - 2.0 * t)
            h11 = -t * t * u
            row = ptab[i]
            nxt = ptab[i + 1]
            va = h00 * row[0] + h10 * row[1] + h01 * nxt[0] + h11 * nxt[1]
            vbm = h00 * row[2] + h10 * row[3] + h01 * nxt[2] + h11 * nxt[3]
            vbp = h00 * row[4] + h10 * row[5] + h01 * nxt[4] + h11 * nxt[5]
            vd = h00 * row[6] + h10 * row[7] + h01 * nxt[6] + h11 * nxt[7]
            close += akr * (ar[j] * va - ai[j] * vbm) - aki * (ai[j] * vd + ar[j] * vbp)
        total += close
    return total


@_njit
def _exposure_points(out, pts, inside, spos, saxis, radius, rho, c, tau, s, step, table, y_end, m_g, m_h,
                     ptab, lag_terms):  # pragma: no cover - compiled
    """:func:`_exposure_sorted` at each point, the geometry of every source computed there (no (n, k) arrays).

    Points outside the fluid (``inside``: in the sphere or behind a wall) get NaN.
    """
    g0, h0 = _correlation_at(0.0, tau, s, step, table, y_end, m_g, m_h)
    ts, tw = closed_tables(tau, s)
    nimg = spos.shape[0]
    delays = np.empty(nimg)
    are = np.empty(nimg)
    aim = np.empty(nimg)
    count = np.empty(nimg + 1, np.int64)
    key = np.empty(nimg, np.int64)
    order = np.empty(nimg, np.int64)
    for i in range(pts.shape[0]):
        if inside[i]:
            out[i] = np.nan
            continue
        for j in range(nimg):  # paper eqs 12-14, as acoustiviz.field.sources.image_geometry
            d0 = pts[i, 0] - spos[j, 0]
            d1 = pts[i, 1] - spos[j, 1]
            d2 = pts[i, 2] - spos[j, 2]
            r = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            p0 = rho * c * radius * radius * (d0 * saxis[j, 0] + d1 * saxis[j, 1] + d2 * saxis[j, 2]) / (r * r * r)
            delays[j] = (r - radius) / c
            are[j] = p0 * r / radius
            aim[j] = -p0 * (1.0 - r / radius)
        _arrival_order(delays, count, key, order)
        if lag_terms.size:  # the half-sine: close pairs in closed form
            out[i] = _exposure_closed(delays[order], are[order], aim[order], tau, s, lag_terms, y_end, m_g, m_h, ts,
                                      tw)
        else:
            out[i] = _exposure_sorted(delays[order], are[order], aim[order], tau, s, step, ptab, y_end, m_g, m_h, g0,
                                      h0)


def exposure(pulse, points, geometry: Geometry, *, medium: Medium = AIR, correlations=None,
             chunk: int = 65536) -> np.ndarray:
    """Sound exposure ``∫ p² dt`` in Pa²·s of the whole response at each point, without a time loop.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    points : (n, 3) array_like
        Observer positions in m; points outside the fluid get NaN.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    correlations : PulseCorrelations, optional
        Those of ``pulse`` and the sphere (:func:`pulse_correlations`), to reuse between calls.
    chunk : int
        Points per block, at most (fewer when the block's geometry would exceed the evaluator's
        256 MiB working memory, :data:`acoustiviz.field._common.DEFAULT_MEMORY_LIMIT`).

    Returns
    -------
    (n,) ndarray
        Exposure in Pa²·s over all time (the SEL is ``10 log10(E / (20 µPa)² / 1 s)``).

    Notes
    -----
    Paper eqs 12-14 squared and integrated in closed form over time (module notes); the only
    approximations are the quadrature and Chebyshev series of ``G`` and ``H`` (relative error
    about 1e-12).
    """
    check_pulse(pulse)
    check_geometry(geometry)
    pts = check_points("points", points)
    corr = pulse_correlations(pulse, geometry.radius, medium=medium) if correlations is None else correlations
    out = np.empty(pts.shape[0])
    imgs = geometry.images()
    if len(imgs) > PAIRS_ABOVE:  # many sources: the geometry in the kernel, the pairs over sorted arrivals
        inside = ~geometry.in_fluid(pts)
        spos = np.ascontiguousarray(imgs.positions, dtype=float)
        saxis = np.ascontiguousarray(imgs.weighted_axes, dtype=float)
        ptab = pair_table(corr.table)
        for lo in range(0, pts.shape[0], max(1, int(chunk))):
            hi = min(lo + max(1, int(chunk)), pts.shape[0])
            _exposure_points(out[lo:hi], np.ascontiguousarray(pts[lo:hi]), inside[lo:hi], spos, saxis,
                             float(geometry.radius),
                             float(medium.rho), float(medium.c), corr.duration, corr.pole, corr.step, corr.table,
                             corr.y_end, corr.m_g, corr.m_h, ptab,
                             np.ascontiguousarray(corr.lag_terms, dtype=complex))
        return out
    # points per block: at most ``chunk``, and within the evaluator's memory cap
    step = max(1, min(int(chunk), DEFAULT_MEMORY_LIMIT // (_BYTES_PER_SOURCE * len(imgs))))
    for lo in range(0, pts.shape[0], step):
        hi = min(lo + step, pts.shape[0])
        delay, p0, cre, cim, inside = chunk_geometry(pts[lo:hi], geometry, medium)
        res = np.empty(hi - lo)
        _exposure_kernel(res, delay, p0 * cre, p0 * cim, corr.duration, corr.pole, corr.step, corr.table, corr.y_end,
                         corr.m_g, corr.m_h)
        res[inside] = np.nan
        out[lo:hi] = res
    return out
