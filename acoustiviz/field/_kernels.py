"""Numba kernels of the field evaluator: one sphere's pressure added onto a uniform time grid.

The kernels take a pulse flattened by :func:`acoustiviz.field._common.pulse_args` into one
:class:`~acoustiviz.field._common.PulseArrays` record, read by attribute (``kind`` 0: the
half-sine in closed form; 1: a piecewise-linear pulse with its exact knot states; 2: the exact
Hertz pulse as Taylor polynomials of ``Y`` per piece, from
:func:`acoustiviz.core.radiation.hertz_response_table`) and the geometry of
:func:`acoustiviz.field.sources.source_geometry`. Times in s, pressures in Pa.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit as _njit

#: 1/k! for k = 0..17, for the Taylor series of the φ-functions
_INV_FACT = np.array([1.0 / math.factorial(k) for k in range(18)])


@_njit
def _phi12_scalar(z):  # pragma: no cover - compiled
    """φ1(z) = (e^z - 1)/z and φ2(z) = (e^z - 1 - z)/z² for one complex z with Re z <= 0."""
    if abs(z) < 0.25:
        t1 = 0j
        t2 = 0j
        for j in range(14, -1, -1):  # 15 terms: < 1e-17 at |z| = 0.25
            t1 = t1 * z + _INV_FACT[j + 1]
            t2 = t2 * z + _INV_FACT[j + 2]
        return t1, t2
    ez = np.exp(z)
    return (ez - 1.0) / z, (ez - 1.0 - z) / (z * z)


@_njit
def _y_sampled(tr, xi, acc, yk, s):  # pragma: no cover - compiled
    """Exact pulse response of a piecewise-linear pulse at one retarded time (complex m/s)."""
    if tr < 0.0:
        return 0j
    nk = xi.size
    end = xi[nk - 1]
    if tr >= end:
        return np.exp(s * (tr - end)) * yk[nk - 1]
    k = np.searchsorted(xi, tr, side="right") - 1
    if k < 0:
        k = 0
    if k > nk - 2:
        k = nk - 2
    delta = tr - xi[k]
    slope = (acc[k + 1] - acc[k]) / (xi[k + 1] - xi[k])
    p1, p2 = _phi12_scalar(s * delta)
    return np.exp(s * delta) * yk[k] + delta * (acc[k] * p1 + slope * delta * p2)


@_njit(inline="always")
def _acc_taylor(buf, k0, kt, t0, dt, delay, p0, cre, cim, pa):  # pragma: no cover - compiled
    """Add a kind-2 pulse's pressure ``p0 Re[(cre + i cim) Y]`` in Pa on samples ``k0 <= k < kt``.

    ``Y`` is a Taylor polynomial on each piece between the knots ``xi`` (``yk[1 + q]`` terms).
    """
    if kt <= k0:
        return
    xi = pa.xi
    tab = pa.tab
    q = np.searchsorted(xi, t0 + k0 * dt - delay, side="right") - 1
    q = min(max(q, 0), xi.size - 2)
    k = k0
    while k < kt:
        kend = kt if q == xi.size - 2 else min(kt, int(math.ceil((delay + xi[q + 1] - t0) / dt)))
        nt = int(pa.yk[1 + q].real)
        base = t0 - delay - xi[q]
        inv = pa.acc[q]
        kk = k
        while kk + 1 < kend:  # two samples at a time: four independent Horner chains
            u = (base + kk * dt) * inv  # u may leave [0, 1] by rounding: the polynomial is smooth there
            v = u + dt * inv
            ar = br = tab[q, nt - 1].real
            ai = bi = tab[q, nt - 1].imag
            for j in range(nt - 2, -1, -1):
                cr = tab[q, j].real
                ci = tab[q, j].imag
                ar = ar * u + cr
                ai = ai * u + ci
                br = br * v + cr
                bi = bi * v + ci
            buf[kk] += p0 * (cre * ar - cim * ai)
            buf[kk + 1] += p0 * (cre * br - cim * bi)
            kk += 2
        if kk < kend:
            u = (base + kk * dt) * inv
            ar = tab[q, nt - 1].real
            ai = tab[q, nt - 1].imag
            for j in range(nt - 2, -1, -1):
                ar = ar * u + tab[q, j].real
                ai = ai * u + tab[q, j].imag
            buf[kk] += p0 * (cre * ar - cim * ai)
        k = max(k, kend)
        q += 1


@_njit
def _accumulate(buf, t0, dt, delay, p0, cre, cim, pa, tail):  # pragma: no cover - compiled
    """Add one sphere's pressure in Pa to ``buf[k]`` at ``t0 + k dt`` (s); return the touched index range.

    ``delay`` (s), ``p0`` (Pa·s/m) and ``cre + i cim`` are one image's retardation, scale and
    radiation coefficient (:func:`acoustiviz.field.sources.chunk_geometry`); ``pa`` the pulse
    (:class:`acoustiviz.field._common.PulseArrays`); after the pulse the free decay is kept for
    ``tail`` s. Returns ``(k0, ke)``: samples ``k0 <= k < ke`` were touched.
    """
    m = buf.size
    s = pa.s
    end = pa.tau if pa.kind == 0 else pa.xi[pa.xi.size - 1]
    k0 = max(int(math.ceil((delay - t0) / dt)), 0)
    if k0 >= m:
        return m, m
    kt = int(math.ceil((delay + end - t0) / dt))
    kt = min(max(kt, k0), m)
    ke = int(math.ceil((delay + end + tail - t0) / dt))
    ke = min(max(ke, kt), m)
    dF = np.exp(s * dt)
    if pa.kind == 0:  # half-sine: exp(i w t') and exp(s t') advance by one complex multiply per sample
        w = math.pi / pa.tau
        coef = pa.amp / (s * s + w * w)
        if kt > k0:
            tr = t0 + k0 * dt - delay
            e = np.exp(1j * w * tr)
            de = np.exp(1j * w * dt)
            f = np.exp(s * tr)
            for k in range(k0, kt):
                y = coef * (-s * e.imag - w * e.real + w * f)
                buf[k] += p0 * (cre * y.real - cim * y.imag)
                e *= de
                f *= dF
        yend = coef * w * (1.0 + np.exp(s * pa.tau))
    elif pa.kind == 1:
        for k in range(k0, kt):
            y = _y_sampled(t0 + k * dt - delay, pa.xi, pa.acc, pa.yk, s)
            buf[k] += p0 * (cre * y.real - cim * y.imag)
        yend = pa.yk[pa.yk.size - 1]
    else:  # exact Hertz pulse: Taylor polynomial of Y on each piece between the knots
        _acc_taylor(buf, k0, kt, t0, dt, delay, p0, cre, cim, pa)
        yend = pa.yk[0]
    if ke > kt:
        g = yend * np.exp(s * (t0 + kt * dt - delay - end))
        for k in range(kt, ke):
            buf[k] += p0 * (cre * g.real - cim * g.imag)
            g *= dF
    return k0, ke


@_njit
def _series_kernel(out, t0, dt, img, pa, tail):  # pragma: no cover - compiled
    """Add into ``out[i, k]`` the pressure in Pa at point ``i`` and time ``t0[i] + k dt`` (s).

    ``img`` holds every image seen from each point (:class:`acoustiviz.field._common.ImageArrays`),
    ``pa`` the pulse (:class:`acoustiviz.field._common.PulseArrays`), ``tail`` the kept decay in s.
    """
    n, nimg = img.delay.shape
    for i in range(n):
        for j in range(nimg):
            _accumulate(out[i], t0[i], dt, img.delay[i, j], img.p0[i, j], img.cre[i, j], img.cim[i, j], pa, tail)


@_njit
def _y_at(tr, pa):  # pragma: no cover - compiled
    """Exact pulse response ``Y`` in m/s at one retarded time ``tr`` in s (``pa``: :class:`PulseArrays`)."""
    if tr < 0.0:
        return 0j
    if pa.kind == 0:
        s = pa.s
        tau = pa.tau
        w = math.pi / tau
        coef = pa.amp / (s * s + w * w)
        if tr < tau:
            return coef * (-s * math.sin(w * tr) - w * math.cos(w * tr) + w * np.exp(s * tr))
        return coef * w * (np.exp(s * (tr - tau)) + np.exp(s * tr))
    if pa.kind == 1:
        return _y_sampled(tr, pa.xi, pa.acc, pa.yk, pa.s)
    xi = pa.xi
    end = xi[xi.size - 1]
    if tr >= end:
        return np.exp(pa.s * (tr - end)) * pa.yk[0]
    q = np.searchsorted(xi, tr, side="right") - 1
    q = min(max(q, 0), xi.size - 2)
    u = (tr - xi[q]) * pa.acc[q]
    nt = int(pa.yk[1 + q].real)
    y = pa.tab[q, nt - 1]
    for j in range(nt - 2, -1, -1):
        y = y * u + pa.tab[q, j]
    return y


@_njit
def _p_at(t, img, i, pa):  # pragma: no cover - compiled
    """Pressure in Pa at time ``t`` in s of all images of point ``i`` of ``img`` (no tail cut)."""
    total = 0.0
    for j in range(img.delay.shape[1]):
        if img.p0[i, j] != 0.0:
            y = _y_at(t - img.delay[i, j], pa)
            total += img.p0[i, j] * (img.cre[i, j] * y.real - img.cim[i, j] * y.imag)
    return total


@_njit(inline="always")
def _brent_step(xf, nfc, fulc, fx, fnfc, ffulc, e, rat, a, b, xm, tol1, tol2):  # pragma: no cover - compiled
    """One step choice of Brent's minimiser (SciPy's ``fminbound``): parabolic if acceptable, else golden.

    Returns the updated ``(e, rat)``: the step before last and the step to take.
    """
    golden = True
    if abs(e) > tol1:
        golden = False
        r = (xf - nfc) * (fx - ffulc)
        q = (xf - fulc) * (fx - fnfc)
        p = (xf - fulc) * q - (xf - nfc) * r
        q = 2.0 * (q - r)
        if q > 0.0:
            p = -p
        q = abs(q)
        r = e
        e = rat
        if abs(p) < abs(0.5 * q * r) and p > q * (a - xf) and p < q * (b - xf):
            rat = p / q
            x = xf + rat
            if (x - a) < tol2 or (b - x) < tol2:
                rat = tol1 if xm >= xf else -tol1
        else:
            golden = True
    if golden:
        e = (a - xf) if xf >= xm else (b - xf)
        rat = 0.5 * (3.0 - math.sqrt(5.0)) * e
    return e, rat


@_njit
def _refine(sign, tk, dt, lo, hi, img, i, pa):  # pragma: no cover - compiled
    """Largest ``sign · p`` in Pa at point ``i`` of ``img`` on ``[max(lo, tk - dt), min(hi, tk + dt)]`` (s).

    By Brent's method: a bounded Brent search (golden section with parabolic steps, the algorithm of SciPy's
    ``fminbound``) in the local variable ``x = (t - tk)/dt`` to ``|Δx| < 1e-9``; returns the
    refined value, never below the sample ``sign · p(tk)``.
    """
    a = max(lo - tk, -dt) / dt
    b = min(hi - tk, dt) / dt
    best = sign * _p_at(tk, img, i, pa)
    if not b > a:
        return best
    sqrt_eps = 1.4901161193847656e-08
    xatol = 1e-9
    fulc = a + 0.5 * (3.0 - math.sqrt(5.0)) * (b - a)
    nfc = fulc
    xf = fulc
    rat = 0.0
    e = 0.0
    x = xf
    fx = -sign * _p_at(tk + x * dt, img, i, pa)
    ffulc = fx
    fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = sqrt_eps * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    for _ in range(200):
        if abs(xf - xm) <= tol2 - 0.5 * (b - a):
            break
        e, rat = _brent_step(xf, nfc, fulc, fx, fnfc, ffulc, e, rat, a, b, xm, tol1, tol2)
        step = max(abs(rat), tol1)
        x = xf + (step if rat >= 0.0 else -step)
        fu = -sign * _p_at(tk + x * dt, img, i, pa)
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = sqrt_eps * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
    return max(best, -fx)


@_njit
def _metrics_kernel(res, buf, t0, dt, img, pa, tail, refine):  # pragma: no cover - compiled
    """Per point ``i``: ``res[i] = (max p, min p, Σ p²)`` (Pa, Pa, Pa²) over its grid ``t0[i] + k dt``, k < buf.size.

    ``buf`` is a zeroed scratch row, left zeroed; the other arguments as :func:`_series_kernel`.
    With ``refine`` the extremes are refined between the samples (:func:`_refine`) inside
    ``[t0[i], t0[i] + (m - 1) dt]``.
    """
    n, nimg = img.delay.shape
    m = buf.size
    for i in range(n):
        lo = m
        hi = 0
        for j in range(nimg):
            a, b = _accumulate(buf, t0[i], dt, img.delay[i, j], img.p0[i, j], img.cre[i, j], img.cim[i, j], pa, tail)
            if b > a:
                lo = min(lo, a)
                hi = max(hi, b)
        pmax = 0.0
        pmin = 0.0
        kmax = -1
        kmin = -1
        ssq = 0.0
        for k in range(lo, hi):
            v = buf[k]
            if v > pmax:
                pmax = v
                kmax = k
            if v < pmin:
                pmin = v
                kmin = k
            ssq += v * v
            buf[k] = 0.0
        if refine:
            wlo = t0[i]
            whi = t0[i] + (m - 1) * dt
            if kmax >= 0:
                pmax = _refine(1.0, t0[i] + kmax * dt, dt, wlo, whi, img, i, pa)
            if kmin >= 0:
                pmin = -_refine(-1.0, t0[i] + kmin * dt, dt, wlo, whi, img, i, pa)
        res[i, 0] = pmax
        res[i, 1] = pmin
        res[i, 2] = ssq

