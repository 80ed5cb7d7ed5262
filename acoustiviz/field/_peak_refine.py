"""Refinement of :func:`acoustiviz.field.peaks.fast_peaks` on the closed form: ``p``, ``p'``, ``p''`` and Newton.

``p``, ``p'`` and ``p''`` come from the exact ``Y`` of :mod:`acoustiviz.field._kernels` (the
Hertz pulse's Taylor table differentiated term by term; the half-sine in closed form; a sampled
pulse over its piecewise-linear form, ``Y' = s Y + A``). A maximum is refined by safeguarded
Newton on ``p' = 0`` within a bracket split at the breakpoints where ``p''`` may jump. Times in s,
pressures in Pa.
"""

from __future__ import annotations

import math

import numpy as np

from ._kernels import _njit, _y_at


@_njit(cache=True)
def _y_d2(tr, kind, amp, tau, xi, acc, yk, tab, s):  # pragma: no cover - compiled
    """``Y``, ``Y'`` and ``Y''`` (m/s, m/s², m/s³) at one retarded time ``tr`` in s."""
    if tr < 0.0:
        return 0j, 0j, 0j
    end = tau if kind == 0 else xi[xi.size - 1]
    if tr >= end:
        if kind == 0:
            y = _y_at(tr, kind, amp, tau, xi, acc, yk, tab, s)
        elif kind == 1:
            y = np.exp(s * (tr - end)) * yk[yk.size - 1]
        else:
            y = np.exp(s * (tr - end)) * yk[0]
        return y, s * y, s * s * y
    if kind == 2:
        q = np.searchsorted(xi, tr, side="right") - 1
        q = min(max(q, 0), xi.size - 2)
        inv = acc[q]
        u = (tr - xi[q]) * inv
        nt = int(yk[1 + q].real)
        y = tab[q, nt - 1]
        d1 = 0j
        d2 = 0j
        for j in range(nt - 2, -1, -1):
            d2 = d2 * u + d1
            d1 = d1 * u + y
            y = y * u + tab[q, j]
        return y, d1 * inv, 2.0 * d2 * inv * inv
    y = _y_at(tr, kind, amp, tau, xi, acc, yk, tab, s)
    if kind == 0:
        w = math.pi / tau
        a0 = amp * math.sin(w * tr)
        a1 = amp * w * math.cos(w * tr)
    else:
        k = np.searchsorted(xi, tr, side="right") - 1
        k = min(max(k, 0), xi.size - 2)
        a1 = (acc[k + 1] - acc[k]) / (xi[k + 1] - xi[k])
        a0 = acc[k] + a1 * (tr - xi[k])
    y1 = s * y + a0
    return y, y1, s * y1 + a1


@_njit(cache=True)
def _p_d2(t, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab, s, lut):  # pragma: no cover - compiled
    """``p``, ``p'`` and ``p''`` (Pa, Pa/s, Pa/s²) at time ``t`` in s from the exact ``Y`` of every image."""
    p = 0.0
    p1 = 0.0
    p2 = 0.0
    end = xi[xi.size - 1]
    lscale = (lut.size - 1) / end if kind == 2 else 0.0
    for j in range(nimg):
        tr = t - delays[j]
        if kind == 2 and 0.0 <= tr < end:
            # Re[a_j Y] is a real polynomial on the piece: Horner with its first two derivatives.
            # The piece: lut[b] is the piece holding the start of bucket b, then a short scan
            b = min(int(tr * lscale), lut.size - 2)
            q = lut[b]
            qe = lut[b + 1]
            if qe - q > 8:
                q = q + np.searchsorted(xi[q : qe + 1], tr, side="right") - 1
            else:
                while q < qe and xi[q + 1] <= tr:
                    q += 1
            q = min(max(q, 0), xi.size - 2)
            inv = acc[q]
            u = (tr - xi[q]) * inv
            nt = int(yk[1 + q].real)
            ar = are[j]
            ai = aim[j]
            y = ar * tab[q, nt - 1].real - ai * tab[q, nt - 1].imag
            d1 = 0.0
            d2 = 0.0
            for m in range(nt - 2, -1, -1):
                d2 = d2 * u + d1
                d1 = d1 * u + y
                y = y * u + (ar * tab[q, m].real - ai * tab[q, m].imag)
            p += y
            p1 += d1 * inv
            p2 += 2.0 * d2 * inv * inv
        elif tr < 0.0:
            continue
        elif kind == 2 and tr >= end:
            # free decay: Re[a_j Y(T) e^{s x}], x = tr - T, and its derivatives, in real arithmetic
            x = tr - end
            e = math.exp(s.real * x)
            cs = e * math.cos(s.imag * x)
            sn = e * math.sin(s.imag * x)
            wr = are[j] * yk[0].real - aim[j] * yk[0].imag
            wi = are[j] * yk[0].imag + aim[j] * yk[0].real
            v0r = wr * cs - wi * sn
            v0i = wr * sn + wi * cs
            v1r = s.real * v0r - s.imag * v0i
            v1i = s.real * v0i + s.imag * v0r
            p += v0r
            p1 += v1r
            p2 += s.real * v1r - s.imag * v1i
        else:
            y, y1, y2 = _y_d2(tr, kind, amp, tau, xi, acc, yk, tab, s)
            p += are[j] * y.real - aim[j] * y.imag
            p1 += are[j] * y1.real - aim[j] * y1.imag
            p2 += are[j] * y2.real - aim[j] * y2.imag
    return p, p1, p2


@_njit(cache=True)
def _newton_max(sign, t0, lo, hi, xtol, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab,
                s, lut):  # pragma: no cover - compiled
    """Largest ``sign · p`` near ``t0`` in ``[lo, hi]``: safeguarded Newton on ``p' = 0``; (value, time)."""
    x = t0
    best = -np.inf
    tbest = t0
    for _ in range(40):
        p, p1, p2 = _p_d2(x, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
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


@_njit(cache=True)
def _newton_segment(sign, a, b, ga, gb, best, tbest, xtol, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk,
                    tab, s, lut):  # pragma: no cover - compiled
    """Maximum of ``sign · p`` on ``[a, b]`` where ``sign · p'`` decreases from ``ga > 0`` to ``gb < 0``."""
    x = a + ga * (b - a) / (ga - gb)  # Newton from the secant root, kept inside [a, b]
    for _ in range(60):
        p, p1, p2 = _p_d2(x, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
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


@_njit(cache=True)
def _refine_piece(sign, floor, lo, hi, pl, gl, cl, pr, gr, cr, xtol, nimg, delays, are, aim, kind, amp, tau, xi, acc,
                  yk, tab, s, lut):  # pragma: no cover - compiled
    """Largest ``sign · p`` on ``[lo, hi]``, an interval on which ``p`` is smooth: (value, time).

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
        a, fa, b, fb = lo, cl, hi, cr
        side = 0
        m = 0.5 * (lo + hi)
        gm = 0.0
        for _ in range(60):
            m = b - fb * (b - a) / (fb - fa)
            if not (a < m < b) and not (b < m < a):
                m = 0.5 * (a + b)
            pm, gm, cm = _p_d2(m, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
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
        if sign * gl > 0.0 and sign * gm < 0.0:
            best, tbest = _newton_segment(sign, lo, m, sign * gl, sign * gm, best, tbest, xtol, nimg, delays, are,
                                          aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
        if sign * gm > 0.0 and sign * gr < 0.0:
            best, tbest = _newton_segment(sign, m, hi, sign * gm, sign * gr, best, tbest, xtol, nimg, delays, are,
                                          aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
    elif sign * gl > 0.0 and sign * gr < 0.0:
        best, tbest = _newton_segment(sign, lo, hi, sign * gl, sign * gr, best, tbest, xtol, nimg, delays, are, aim,
                                      kind, amp, tau, xi, acc, yk, tab, s, lut)
    return best, tbest


@_njit(cache=True)
def _refine_bracket(sign, floor, t0, lo, hi, bps, xtol, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab,
                    s, lut):  # pragma: no cover - compiled
    """Largest ``sign · p`` on ``[lo, hi]`` near ``t0``, split at the breakpoints ``bps`` inside (sorted).

    Pieces that provably cannot beat ``floor`` (a value already reached) are not searched.
    """
    inside = 0
    for b in bps:
        if lo < b < hi:
            inside += 1
    if inside == 0:
        return _newton_max(sign, t0, lo, hi, xtol, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
    best = -np.inf
    tbest = t0
    a = lo
    pa, ga, ca = _p_d2(a, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
    for q in range(bps.size + 1):
        b = bps[q] if q < bps.size else hi
        if q < bps.size and not (lo < b < hi):
            continue
        pb, gb, cb = _p_d2(b, nimg, delays, are, aim, kind, amp, tau, xi, acc, yk, tab, s, lut)
        v, tv = _refine_piece(sign, max(floor, best), a, b, pa, ga, ca, pb, gb, cb, xtol, nimg, delays, are, aim,
                              kind, amp, tau, xi, acc, yk, tab, s, lut)
        if v > best:
            best = v
            tbest = tv
        a, pa, ga, ca = b, pb, gb, cb
    return best, tbest
