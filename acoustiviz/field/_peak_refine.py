"""Refinement of :func:`acoustiviz.field.peaks.fast_peaks` on the closed form: ``p``, ``p'``, ``p''`` and Newton.

``p``, ``p'`` and ``p''`` come from the exact ``Y`` of :mod:`acoustiviz.field._kernels` (the
Hertz pulse's Taylor table differentiated term by term; the half-sine in closed form; a sampled
pulse over its piecewise-linear form, ``Y' = s Y + A``). A maximum is refined by safeguarded
Newton on ``p' = 0`` within a bracket split at the breakpoints where ``p''`` may jump. Times in s,
pressures in Pa.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._jit import njit as _njit
from ._common import pulse_args

#: Buckets of the piece look-up table over the pulse.
LUT_BUCKETS = 4096


class TaylorPulse(NamedTuple):
    """The pulse response ``Y`` as Taylor polynomials per piece, as :func:`_p_d2` reads it (by attribute).

    Attributes
    ----------
    knots : (k,) ndarray
        Piece starts in s (the last: the pulse's end).
    inv : (k - 1,) ndarray
        Inverse piece lengths in 1/s.
    nts : (k - 1,) ndarray of int64
        Terms per piece.
    tab_r, tab_i : (k - 1, terms) ndarray
        Real and imaginary Taylor coefficients in m/s, in ``u = (t' - knots[q]) inv[q]``.
    lut : (LUT_BUCKETS + 1,) ndarray of int64
        The piece holding the start of each of :data:`LUT_BUCKETS` equal buckets of ``[0, end]``.
    lscale : float
        Buckets per s.
    end : float
        The pulse's end in s.
    y0r, y0i : float
        ``Y(end)`` in m/s, real and imaginary parts.
    sr, si : float
        The sphere's pole ``s`` in 1/s, real and imaginary parts.
    """

    knots: np.ndarray
    inv: np.ndarray
    nts: np.ndarray
    tab_r: np.ndarray
    tab_i: np.ndarray
    lut: np.ndarray
    lscale: float
    end: float
    y0r: float
    y0i: float
    sr: float
    si: float


def taylor_pulse(pulse, radius: float, medium) -> TaylorPulse:
    """The pulse response ``Y`` as :func:`_p_d2` reads it: its Taylor table and a piece look-up table.

    Parameters
    ----------
    pulse : HalfSinePulse, HertzPulse or SampledPulse
        Acceleration pulse (m/s²) starting at t = 0.
    radius : float
        Sphere radius in m.
    medium : Medium
        The fluid.

    Returns
    -------
    TaylorPulse
        Its piece starts in s, their inverse lengths in 1/s, terms per piece, the real and
        imaginary Taylor coefficients in m/s, the piece look-up table over ``[0, end]`` with its
        buckets per s, the pulse's end in s, ``Y(end)`` in m/s and the pole in 1/s.
    """
    pa = pulse_args(pulse, radius, medium, taylor=True)
    knots, inv, yk, tab, s = pa.xi, pa.acc, pa.yk, pa.tab, pa.s
    end = float(knots[-1])
    lut = np.searchsorted(knots, np.linspace(0.0, end, LUT_BUCKETS + 1), side="right") - 1
    lut = np.clip(lut, 0, knots.size - 2).astype(np.int64)
    nts = yk[1:].real.astype(np.int64)
    y_end = complex(yk[0])
    return TaylorPulse(np.ascontiguousarray(knots, dtype=float), np.ascontiguousarray(inv, dtype=float), nts,
                       np.ascontiguousarray(tab.real), np.ascontiguousarray(tab.imag), lut, LUT_BUCKETS / end, end,
                       y_end.real, y_end.imag, float(s.real), float(s.imag))


@_njit
def _p_d2(t, nimg, delays, are, aim, tp):  # pragma: no cover - compiled
    """``p``, ``p'`` and ``p''`` (Pa, Pa/s, Pa/s²) at time ``t`` in s from the exact ``Y`` of every image.

    ``tp`` (:class:`TaylorPulse`, from :func:`taylor_pulse`) holds ``Y`` as the Taylor table of
    :func:`acoustiviz.field._common.pulse_args` with ``taylor=True``:
    on piece ``q`` (``knots[q] <= t' < knots[q + 1]``, ``inv[q] = 1/(knots[q + 1] - knots[q])``),
    ``Y = Σ_m (tab_r + i tab_i)[q, m] u^m`` with ``u = (t' - knots[q]) inv[q]`` and ``nts[q]`` terms;
    ``lut[b]`` is the piece holding the start of bucket ``b`` of ``lscale`` buckets per second of
    ``[0, end]``; after ``end`` the free decay ``Y(end) exp(s (t' - end))``, ``Y(end) = y0r + i y0i``
    and ``s = sr + i si``.
    """
    knots, inv, nts, tab_r, tab_i, lut = tp.knots, tp.inv, tp.nts, tp.tab_r, tp.tab_i, tp.lut
    lscale, end, y0r, y0i, sr, si = tp.lscale, tp.end, tp.y0r, tp.y0i, tp.sr, tp.si
    p = 0.0
    p1 = 0.0
    p2 = 0.0
    last = lut.size - 2
    for j in range(nimg):
        tr = t - delays[j]
        if tr < 0.0:
            continue
        ar = are[j]
        ai = aim[j]
        if tr < end:
            # Re[a_j Y] is a real polynomial on the piece: Horner with its first two derivatives
            q = lut[min(int(tr * lscale), last)]
            while knots[q + 1] <= tr:
                q += 1
            h = inv[q]
            u = (tr - knots[q]) * h
            nt = nts[q]
            y = ar * tab_r[q, nt - 1] - ai * tab_i[q, nt - 1]
            d1 = 0.0
            d2 = 0.0
            for m in range(nt - 2, -1, -1):
                d2 = d2 * u + d1
                d1 = d1 * u + y
                y = y * u + (ar * tab_r[q, m] - ai * tab_i[q, m])
            p += y
            p1 += d1 * h
            p2 += 2.0 * d2 * h * h
        else:
            # free decay: Re[a_j Y(T) e^{s x}], x = tr - T, and its derivatives, in real arithmetic
            x = tr - end
            e = math.exp(sr * x)
            cs = e * math.cos(si * x)
            sn = e * math.sin(si * x)
            wr = ar * y0r - ai * y0i
            wi = ar * y0i + ai * y0r
            v0r = wr * cs - wi * sn
            v0i = wr * sn + wi * cs
            v1r = sr * v0r - si * v0i
            v1i = sr * v0i + si * v0r
            p += v0r
            p1 += v1r
            p2 += sr * v1r - si * v1i
    return p, p1, p2


@_njit(inline="always")  # inlined: called per candidate, a call costs more than the body
def _newton_max(sign, t0, lo, hi, xtol, nimg, delays, are, aim, tp):  # pragma: no cover - compiled
    """Largest ``sign · p`` near ``t0`` in ``[lo, hi]``: safeguarded Newton on ``p' = 0``; (value, time)."""
    x = t0
    best = -np.inf
    tbest = t0
    for _ in range(40):
        p, p1, p2 = _p_d2(x, nimg, delays, are, aim, tp)
        v = sign * p
        g = sign * p1
        gp = sign * p2
        if v > best:
            best = v
            tbest = x
        if gp < 0.0:
            step = -g / gp
        else:
            step = 0.25 * (hi - lo) if g > 0.0 else -0.25 * (hi - lo)
        if abs(step) < xtol:
            if gp < 0.0:
                model = v - 0.5 * g * g / gp  # the Newton model's maximum, O(step³) from the true one
                if model > best:
                    best = model
                    tbest = x + step
            break
        if g > 0.0:
            lo = max(lo, x)
        else:
            hi = min(hi, x)
        if hi - lo < xtol:
            break
        xn = x + step
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        x = xn
    return best, tbest


@_njit
def _newton_segment(sign, a, b, ga, gb, best, tbest, xtol, nimg, delays, are, aim, tp):  # pragma: no cover - compiled
    """Maximum of ``sign · p`` on ``[a, b]`` where ``sign · p'`` decreases from ``ga > 0`` to ``gb < 0``."""
    x = a + ga * (b - a) / (ga - gb)  # Newton from the secant root, kept inside [a, b]
    for _ in range(60):
        p, p1, p2 = _p_d2(x, nimg, delays, are, aim, tp)
        v = sign * p
        g = sign * p1
        gp = sign * p2
        if v > best:
            best = v
            tbest = x
        if g > 0.0:
            a = x
        else:
            b = x
        step = -g / gp if gp < 0.0 else 0.5 * (a + b) - x
        if abs(step) < xtol and gp < 0.0:
            model = v - 0.5 * g * g / gp
            if model > best:
                best = model
                tbest = x + step
            break
        if b - a < xtol:
            break
        xn = x + step
        x = xn if a < xn < b else 0.5 * (a + b)
    return best, tbest


@_njit(inline="always")
def _inflection(sign, best, tbest, lo, hi, cl, cr, xtol, nimg, delays, are, aim, tp):  # pragma: no cover - compiled
    """Zero of ``p''`` in ``[lo, hi]`` (s) by the Illinois method, ``p''`` being ``cl`` and ``cr`` at the ends.

    Returns ``(m, p'(m), best, tbest)``: the zero in s, ``p'`` there in Pa/s, and the largest
    ``sign · p`` in Pa met on the way (``best``, at ``tbest``) or the one passed in.
    """
    a, fa, b, fb = lo, cl, hi, cr
    side = 0
    m = 0.5 * (lo + hi)
    gm = 0.0
    for _ in range(60):
        m = b - fb * (b - a) / (fb - fa)
        if not (a < m < b) and not (b < m < a):
            m = 0.5 * (a + b)
        pm, gm, cm = _p_d2(m, nimg, delays, are, aim, tp)
        if sign * pm > best:
            best = sign * pm
            tbest = m
        if cm * fb < 0.0:
            a, fa = b, fb
            side = 0
        else:
            fa = 0.5 * fa if side == 1 else fa
            side = 1
        b, fb = m, cm
        if abs(b - a) < xtol or cm == 0.0:
            break
    return m, gm, best, tbest


@_njit
def _refine_piece(sign, floor, lo, hi, pl, gl, cl, pr, gr, cr, xtol, nimg, delays, are, aim,
                  tp):  # pragma: no cover - compiled
    """Largest ``sign · p`` on ``[lo, hi]``, an interval on which ``p`` is smooth: (value in Pa, time in s).

    ``pl, gl, cl`` and ``pr, gr, cr`` are ``p, p', p''`` at the ends. ``p''`` is assumed to change
    sign at most once on the interval (its zero is found by the Illinois method and splits it), so
    that ``p'`` is monotone on each part and has at most one zero there: a maximum, found by
    safeguarded Newton, when ``p'`` goes from + to -. When ``sign · p`` is concave at both ends (so
    on the whole interval) and the meeting point of its end tangents is below ``floor`` (a value
    already reached elsewhere), no point of the interval can beat ``floor``: nothing is evaluated.
    """
    best, tbest = (sign * pl, lo) if sign * pl >= sign * pr else (sign * pr, hi)
    if not hi > lo:
        return best, tbest
    fa, ga, fb, gb = sign * pl, sign * gl, sign * pr, sign * gr
    if sign * cl < 0.0 and sign * cr < 0.0 and ga > 0.0 and gb < 0.0:
        if fa + ga * (fb - fa - gb * (hi - lo)) / (ga - gb) < floor:
            return best, tbest
    if cl * cr < 0.0 and gl * gr > 0.0:  # p' may cross zero twice: split at the zero of p'' (Illinois)
        m, gm, best, tbest = _inflection(sign, best, tbest, lo, hi, cl, cr, xtol, nimg, delays, are, aim, tp)
        if sign * gl > 0.0 and sign * gm < 0.0:
            best, tbest = _newton_segment(sign, lo, m, sign * gl, sign * gm, best, tbest, xtol, nimg, delays, are,
                                          aim, tp)
        if sign * gm > 0.0 and sign * gr < 0.0:
            best, tbest = _newton_segment(sign, m, hi, sign * gm, sign * gr, best, tbest, xtol, nimg, delays, are,
                                          aim, tp)
    elif sign * gl > 0.0 and sign * gr < 0.0:
        best, tbest = _newton_segment(sign, lo, hi, sign * gl, sign * gr, best, tbest, xtol, nimg, delays, are, aim, tp)
    return best, tbest


@_njit(inline="always")  # inlined: called per candidate, a call costs more than the body
def _refine_bracket(sign, floor, t0, lo, hi, bps, xtol, nimg, delays, are, aim, tp):  # pragma: no cover - compiled
    """Largest ``sign · p`` on ``[lo, hi]`` near ``t0``, split at the breakpoints ``bps`` inside (sorted).

    Pieces that provably cannot beat ``floor`` (a value already reached) are not searched.
    """
    inside = 0
    for b in bps:
        if lo < b < hi:
            inside += 1
    if inside == 0:
        return _newton_max(sign, t0, lo, hi, xtol, nimg, delays, are, aim, tp)
    best = -np.inf
    tbest = t0
    a = lo
    pa, ga, ca = _p_d2(a, nimg, delays, are, aim, tp)
    for q in range(bps.size + 1):
        b = bps[q] if q < bps.size else hi
        if q < bps.size and not (lo < b < hi):
            continue
        pb, gb, cb = _p_d2(b, nimg, delays, are, aim, tp)
        v, tv = _refine_piece(sign, max(floor, best), a, b, pa, ga, ca, pb, gb, cb, xtol, nimg, delays, are, aim, tp)
        if v > best:
            best = v
            tbest = tv
        a, pa, ga, ca = b, pb, gb, cb
    return best, tbest
