"""Closed-form flight of the impact damper between contacts (numba), free decay and forced.

Between contacts the impact mass flies at constant velocity, ``y(τ) = y0 + w0 τ``, and the main
mass is a damped linear oscillator driven by the external force
``F(t) = P cos(ωt) + Q sin(ωt)`` (paper eq 15 without the contact force)::

    M x'' + C x' + K x = F(t),    x(τ) = x_h(τ) + x_p(t0 + τ),

with the particular (steady) solution ``x_p(t) = A_c cos(ωt) + A_s sin(ωt)`` and the free part

    x_h(τ) = e^{-aτ} (x_h0 cos ωd τ + (v_h0 + a x_h0) / ωd sin ωd τ),   a = C / 2M,
    ωd = sqrt(K/M - a²).

Free decay is the zero-forcing limit (``A_c = A_s = 0``): ``x = x_h`` exactly, and one flight
representation (the coefficient vector ``c`` below) serves both. What does not carry over is the
search for the next contact: without forcing the main-mass acceleration is a damped sinusoid whose
zeros are known in closed form, which makes the scan exact (:func:`scan_unforced`); with forcing
they are not, and :func:`scan_forced` brackets with a bound on ``|x''|`` instead. Likewise the
extrema of x are closed-form only without forcing (:func:`free_extrema` against
:func:`flight_minmax`).

Flight coefficients ``c`` (a tuple of 11 floats): ``t0`` (s, start of the flight), ``x_h0`` (m), ``v_h0``
(m/s) (free part at ``t0``), ``y0`` (m), ``w0`` (m/s), ``a`` (1/s), ``ωd`` (rad/s), ``ω``
(rad/s), ``A_c``, ``A_s`` (m), half the gap ``d/2`` (m). Times ``τ`` are measured from ``t0``.
Forcing vector ``fc``: None (free decay; numba compiles that case without the forcing terms) or
``[ω rad/s, P N, Q N, A_c m, A_s m, ...]``.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import helper

_EPS = 2.220446049250313e-16
_GX, _GW = (np.ascontiguousarray(q) for q in np.polynomial.legendre.leggauss(12))


@helper
def _osc_decay(x0, v0, tau, a, wd):
    """Free damped oscillator after ``tau`` s: displacement (m), velocity (m/s) and ``e^{-aτ}``.

    ``x(τ) = e^{-aτ} (x0 cos ωd τ + b sin ωd τ)`` with ``b = (v0 + a x0) / ωd`` (m). The decay
    factor is returned for the callers that need it at the same ``τ`` (the bound of
    :func:`scan_forced`), so that it is not computed twice.
    """
    e = math.exp(-a * tau)
    c = math.cos(wd * tau)
    s = math.sin(wd * tau)
    b = (v0 + a * x0) / wd
    x = e * (x0 * c + b * s)
    v = e * ((b * wd - a * x0) * c - (x0 * wd + a * b) * s)
    return x, v, e


@helper
def _osc(x0, v0, tau, a, wd):
    """Free damped oscillator after ``tau`` s: displacement (m) and velocity (m/s) (:func:`_osc_decay`)."""
    x, v, _ = _osc_decay(x0, v0, tau, a, wd)
    return x, v


@helper
def flight_coeffs(t0, x, v, y, w, a, wd, fc, hg):
    """The flight coefficients ``c`` (module docstring) of a flight from ``t0`` s, as a tuple.

    ``x, v, y, w`` (m, m/s) is the state at ``t0``; ``a`` (1/s) and ``wd`` (rad/s) describe the
    free oscillator (of the main mass, or of both masses when stuck together); ``fc`` the
    forcing (None: free decay, then ``x_h0 = x`` and ``v_h0 = v`` exactly); ``hg`` = d/2 in m.
    A tuple, not an array: passed by value, it costs no reference counting in the hot calls.
    """
    if fc is None:
        return (t0, x, v, y, w, a, wd, 0.0, 0.0, 0.0, hg)
    om, ac, as_ = fc[0], fc[3], fc[4]
    cs = math.cos(om * t0)
    sn = math.sin(om * t0)
    return (t0, x - (ac * cs + as_ * sn), v - om * (as_ * cs - ac * sn), y, w, a, wd, om, ac, as_, hg)


@helper
def _state_parts(tau, c):
    """:func:`flight_state` at ``tau`` s with the values it shares with other terms at ``t0 + tau``.

    Returns ``x, v, acc, e, cs, sn``: the state (m, m/s, m/s²), the decay factor ``e^{-aτ}`` of
    the free part, and ``cos ωt``, ``sin ωt`` of the forcing (1 and 0 without forcing, not
    evaluated then).
    """
    a, wd = c[5], c[6]
    xh, vh, e = _osc_decay(c[1], c[2], tau, a, wd)
    ah = -2.0 * a * vh - (a * a + wd * wd) * xh
    ac, as_ = c[8], c[9]
    if ac == 0.0 and as_ == 0.0:
        return xh, vh, ah, e, 1.0, 0.0
    om = c[7]
    t = c[0] + tau
    cs = math.cos(om * t)
    sn = math.sin(om * t)
    xp = ac * cs + as_ * sn
    vp = om * (as_ * cs - ac * sn)
    return xh + xp, vh + vp, ah - om * om * xp, e, cs, sn


@helper
def flight_state(tau, c):
    """Main-mass displacement (m), velocity (m/s) and acceleration (m/s²) at ``t0 + tau``.

    ``x = x_h + x_p`` (module docstring); ``x_h'' = -2a x_h' - (a² + ωd²) x_h`` and
    ``x_p'' = -ω² x_p``. Without forcing (``A_c = A_s = 0``) only the free part is evaluated.
    """
    x, v, acc, _, _, _ = _state_parts(tau, c)
    return x, v, acc


@helper
def _fval(kind, tau, c):
    """Flight functions of ``tau`` (s) whose roots are sought.

    0 -> main-mass velocity x' (m/s), 1 -> d/2 - z (m), 2 -> z + d/2 (m), 3 -> acceleration x''
    (m/s²), 4 -> relative velocity z' = w0 - x' (m/s), with ``z = y0 + w0 τ - x``.
    """
    x, v, acc = flight_state(tau, c)
    if kind == 0:
        return v
    if kind == 4:
        return c[4] - v
    if kind == 3:
        return acc
    z = c[3] + c[4] * tau - x
    if kind == 1:
        return c[10] - z
    return z + c[10]


@helper
def brent(kind, xa, xb, fa, fb, c):
    """Brent's root in s of the flight function ``kind`` (:func:`_fval`) bracketed by ``[xa, xb]``.

    Tolerance ``1e-18 s + 4 eps |τ|`` (Brent, *Algorithms for Minimization without Derivatives*,
    1973, ch. 4; the form of SciPy's ``brentq``).
    """
    xpre, xcur, fpre, fcur = xa, xb, fa, fb
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    xblk = 0.0
    fblk = 0.0
    spre = 0.0
    scur = 0.0
    for _ in range(200):
        if fpre != 0.0 and fcur != 0.0 and ((fpre < 0.0) != (fcur < 0.0)):
            xblk = xpre
            fblk = fpre
            spre = xcur - xpre
            scur = spre
        if abs(fblk) < abs(fcur):
            xpre = xcur
            xcur = xblk
            xblk = xpre
            fpre = fcur
            fcur = fblk
            fblk = fpre
        delta = 0.5 * (1e-18 + 4.0 * _EPS * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre = scur
                scur = stry
            else:
                spre = sbis
                scur = sbis
        else:
            spre = sbis
            scur = sbis
        xpre = xcur
        fpre = fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = _fval(kind, xcur, c)
    return xcur


# ------------------------------------------------------------------ free decay (no forcing)
@helper
def _first_acc_zero(c):
    """First time > 0 in s where the acceleration of the unforced flight ``c`` vanishes.

    ``x''`` is ``e^{-aτ}(p2 cos ωd τ + q2 sin ωd τ)``, zero at ``ωd τ = atan2(q2, p2) + π/2 + kπ``.
    """
    a, wd = c[5], c[6]
    p0 = c[1]
    q0 = (c[2] + a * p0) / wd
    p1 = -a * p0 + wd * q0
    q1 = -a * q0 - wd * p0
    p2 = -a * p1 + wd * q1
    q2 = -a * q1 - wd * p1
    phi = math.atan2(q2, p2)
    th = phi + 0.5 * math.pi
    k = math.ceil(-th / math.pi)
    th = th + k * math.pi
    if th <= 0.0:
        th += math.pi
    return th / wd


@helper
def record_extremum(ext, n_ext, t, x, kind):
    """Append an extremum of the main-mass displacement (time s, x m, +1 max / -1 min) to ``ext``.

    ``n_ext[0]`` counts every extremum found, also those beyond the capacity of ``ext`` (the
    caller compares the count with the capacity).
    """
    k = n_ext[0]
    if k < ext.shape[0]:
        ext[k, 0] = t
        ext[k, 1] = x
        ext[k, 2] = kind
    n_ext[0] = k + 1


@helper
def free_extrema(c, tau_end, ext, n_ext):
    """Record the extrema of the unforced main mass ``c`` in ``(0, tau_end]`` (times from ``t0``).

    The velocity of the damped oscillator is ``e^{-a τ} (p cos ωd τ + q sin ωd τ)``, so its zeros
    are ``ωd τ = atan2(q, p) + π/2 + kπ`` exactly; one Newton step on the closed-form velocity
    polishes each. At a zero the acceleration is ``-K x / M``: a maximum where ``x > 0``.
    """
    x0, v0, a, wd, t0 = c[1], c[2], c[5], c[6], c[0]
    if wd <= 0.0 or tau_end <= 0.0:
        return
    q0 = (v0 + a * x0) / wd
    p1 = -a * x0 + wd * q0
    q1 = -a * q0 - wd * x0
    if p1 == 0.0 and q1 == 0.0:
        return  # at rest
    th = math.atan2(q1, p1) + 0.5 * math.pi
    th = th + math.ceil(-th / math.pi) * math.pi
    if th <= 0.0:
        th += math.pi
    w2 = a * a + wd * wd
    while th / wd <= tau_end:
        tau = th / wd
        x, v = _osc(x0, v0, tau, a, wd)
        acc = -w2 * x - 2.0 * a * v
        if acc != 0.0:
            tn = tau - v / acc
            if 0.0 < tn <= tau_end and abs(tn - tau) < 1e-6 / wd:
                tau = tn
                x, v = _osc(x0, v0, tau, a, wd)
        if x != 0.0:
            record_extremum(ext, n_ext, t0 + tau, x, 1.0 if x > 0.0 else -1.0)
        th += math.pi


@helper
def scan_unforced(c, tau_end):
    """First contact of an unforced flight ``c`` within ``(0, tau_end]``: (found, tau s, wall ±1).

    Between consecutive zeros of the main-mass acceleration (:func:`_first_acc_zero`, spaced
    π/ωd) ``dz/dt`` is monotone, so ``z`` has at most one extremum there, found by Brent's method
    on ``dz/dt``; on each monotone piece a wall crossing is bracketed exactly. No contact can be
    missed, however short the excursion.
    """
    half = math.pi / c[6]
    tz = _first_acc_zero(c)
    ta = 0.0
    while ta < tau_end:
        tb = min(tz, tau_end)
        if tb > ta:
            da = _fval(np.int64(4), ta, c)
            db = _fval(np.int64(4), tb, c)
            npc = 2
            pmid = tb  # the monotone pieces [ta, pmid] and, if z' changes sign, [pmid, tb]
            if (da < 0.0) != (db < 0.0) and da != 0.0 and db != 0.0:
                pmid = brent(np.int64(4), ta, tb, da, db, c)
                npc = 3
            for i in range(npc - 1):
                p = ta if i == 0 else pmid
                q = pmid if i == 0 else tb
                hup = _fval(np.int64(1), p, c)
                huq = _fval(np.int64(1), q, c)
                if huq < hup:  # z increasing: only wall +1 can be reached
                    if hup <= 0.0:
                        return True, p, 1.0
                    if huq <= 0.0:
                        return True, brent(np.int64(1), p, q, hup, huq, c), 1.0
                else:
                    hlp = _fval(np.int64(2), p, c)
                    hlq = _fval(np.int64(2), q, c)
                    if hlq < hlp:
                        if hlp <= 0.0:
                            return True, p, -1.0
                        if hlq <= 0.0:
                            return True, brent(np.int64(2), p, q, hlp, hlq, c), -1.0
        ta = tb
        tz += half
    return False, tau_end, 0.0


# ------------------------------------------------------------------ forced flight
@helper
def _gaps(tau, c):
    """Gap functions ``d/2 - z``, ``z + d/2`` (m), relative velocity ``z'`` (m/s) and ``e^{-aτ}`` at ``tau`` s."""
    x, v, _, e, _, _ = _state_parts(tau, c)
    z = c[3] + c[4] * tau - x
    return c[10] - z, z + c[10], c[4] - v, e


#: Slots (a power of two) of the table of rejected trial points of a forced scan (:func:`scan_forced`); a slot
#: holds a time and the four values of :func:`_gaps` there, in a flat array with one scratch word at the end.
_MEMO_SLOTS = 64
# the slot: the two halves of the time's bit pattern folded into 32 bits, then Fibonacci hashing on 32 bits
# (a product below 2^64, so that no unsigned product wraps) whose top 6 bits (64 slots) are kept
_MEMO_LOW = np.uint64(0xFFFFFFFF)
_MEMO_HALF = np.uint64(32)
_MEMO_HASH = np.uint64(0x9E3779B1)
_MEMO_SHIFT = np.uint64(26)  # 32 - log2(_MEMO_SLOTS)


@helper
def _memo_new():
    """An empty table (:data:`_MEMO_SLOTS`): every time NaN, which equals no time."""
    memo = np.empty(5 * _MEMO_SLOTS + 1)
    for k in range(_MEMO_SLOTS):
        memo[5 * k] = math.nan
    return memo


@helper
def _memo_slot(memo, bits, tau):
    """First word of the slot of ``tau`` s in ``memo`` (``bits`` its uint64 view)."""
    memo[5 * _MEMO_SLOTS] = tau
    b = bits[5 * _MEMO_SLOTS]
    f = (b >> _MEMO_HALF) ^ (b & _MEMO_LOW)
    return 5 * np.int64(((f * _MEMO_HASH) & _MEMO_LOW) >> _MEMO_SHIFT)


@helper
def _trial(tau, c, memo, bits):
    """:func:`_gaps` at ``tau`` s, from ``memo`` when ``tau`` was tried before; and the slot of ``tau``.

    A time comes back only as the same bit pattern, whose values are then bit for bit those that
    evaluating it again gives.
    """
    k = _memo_slot(memo, bits, tau)
    if memo[k] == tau:
        return memo[k + 1], memo[k + 2], memo[k + 3], memo[k + 4], k
    gp, gm, dz, e = _gaps(tau, c)
    return gp, gm, dz, e, k


@helper
def _remember(memo, k, tau, gp, gm, dz, e):
    """Keep the values of the rejected trial point ``tau`` s in its slot ``k`` of ``memo``."""
    memo[k] = tau
    memo[k + 1] = gp
    memo[k + 2] = gm
    memo[k + 3] = dz
    memo[k + 4] = e


@helper
def scan_forced(c, tau_end):
    """First contact of a forced flight ``c`` within ``[0, tau_end]``: (found, tau in s, wall ±1).

    Exact bracketing with a bound ``L`` on ``|d²z/dt²| = |d²x/dt²|`` (free part
    ``R e^{-a t} ω_n²`` plus particular part ``ω² |A|``). A step ``[t_a, t_a + h]`` is accepted when
    either ``|dz/dt(t_a)| > L h`` (``z`` monotone: at most one wall crossing, bracketed by the
    signs at both ends and found by Brent's method) or the Taylor bound
    ``g(t_a) + g'(t_a) s - L s²/2`` keeps both gap functions ``g`` positive; otherwise the step is
    halved. Only a grazing shorter than ``1e-10`` of the step cap (a penetration below
    ``L h²/2``, ~1e-20 m) can go unnoticed. The bound takes the ``e^{-a t_a}`` that the state at
    ``t_a`` was evaluated with.

    Each step starts again from the cap, so its halvings often fall on times that an earlier step
    tried and rejected (a step ``s`` accepted from ``t_p`` last rejected ``t_p + 2s``, which the step
    from ``t_a = t_p + s`` tries again as ``t_a + s``): the values of rejected times are kept in a
    small hash table and taken again when the same time comes back.
    """
    a, wd, om, hg = c[5], c[6], c[7], c[10]
    x0, v0 = c[1], c[2]
    b = (v0 + a * x0) / wd
    r = math.sqrt(x0 * x0 + b * b)
    wn2 = a * a + wd * wd
    lp = om * om * math.sqrt(c[8] * c[8] + c[9] * c[9])
    hmax = 0.25 * 2.0 * math.pi / max(wd, om)
    hmin = 1e-10 * hmax
    ta = 0.0
    x, v, _, ea, _, _ = _state_parts(0.0, c)  # ea = e^{-a ta}, reused by the bound
    z = c[3] - x
    gpa = hg - z
    gma = z + hg
    dza = c[4] - v
    if gpa <= 0.0 and dza > 0.0:
        return True, 0.0, 1.0
    if gma <= 0.0 and dza < 0.0:
        return True, 0.0, -1.0
    memo = _memo_new()
    bits = memo.view(np.uint64)
    while ta < tau_end:
        h = min(hmax, tau_end - ta)
        lb = r * ea * wn2 + lp
        while True:
            tb = ta + h
            gpb, gmb, dzb, eb, slot = _trial(tb, c, memo, bits)
            if abs(dza) > lb * h:  # monotone z
                if dza > 0.0 and gpb <= 0.0:
                    return True, brent(np.int64(1), ta, tb, gpa, gpb, c), 1.0
                if dza < 0.0 and gmb <= 0.0:
                    return True, brent(np.int64(2), ta, tb, gma, gmb, c), -1.0
                break
            q = 0.5 * lb * h * h
            okp = (gpa > 0.0 and gpa - dza * h - q > 0.0) or (gpb > 0.0 and gpb + dzb * h - q > 0.0)
            okm = (gma > 0.0 and gma + dza * h - q > 0.0) or (gmb > 0.0 and gmb - dzb * h - q > 0.0)
            if okp and okm:
                break
            if h <= hmin:
                if gpb <= 0.0:
                    return True, brent(np.int64(1), ta, tb, gpa, gpb, c) if gpa > 0.0 else ta, 1.0
                if gmb <= 0.0:
                    return True, brent(np.int64(2), ta, tb, gma, gmb, c) if gma > 0.0 else ta, -1.0
                break
            _remember(memo, slot, tb, gpb, gmb, dzb, eb)
            h *= 0.5
        ta = tb
        gpa, gma, dza, ea = gpb, gmb, dzb, eb
    return False, tau_end, 0.0


@helper
def flight_energy(c, tau, fc, cdamp):
    """Work of F on the main mass and energy dissipated by C (J) over ``[0, tau]`` of a flight.

    ``∫ F x' dt`` and ``∫ C x'² dt`` by Gauss-Legendre quadrature (12 nodes) on pieces no longer
    than a quarter period: the integrands are smooth sums of exponentials and sinusoids,
    integrated to round-off. ``cdamp`` is C in N s/m; ``c`` is made by :func:`flight_coeffs` with
    this ``fc`` (so ``c[7]`` is ``fc[0]``): the force takes the cosine and sine of ``ωt`` that the
    particular solution evaluates at each node.
    """
    om, pc, ps = fc[0], fc[1], fc[2]
    free = c[8] == 0.0 and c[9] == 0.0  # no particular part: ωt's cosine and sine are not evaluated
    hq = 0.25 * 2.0 * math.pi / max(c[6], om)
    npc = max(int(math.ceil(tau / hq)), 1)
    h = tau / npc
    work = 0.0
    diss = 0.0
    for k in range(npc):
        mid = (k + 0.5) * h
        for j in range(_GX.shape[0]):
            s = mid + 0.5 * h * _GX[j]
            _, v, _, _, cs, sn = _state_parts(s, c)
            if free:
                t = c[0] + s
                cs = math.cos(om * t)
                sn = math.sin(om * t)
            f = pc * cs + ps * sn
            work += 0.5 * h * _GW[j] * f * v
            diss += 0.5 * h * _GW[j] * cdamp * v * v
    return work, diss


@helper
def flight_minmax(c, tau, acc):
    """Update ``acc[3]``/``acc[4]`` with the largest/smallest x (m) of a flight over ``[0, tau]``.

    Zeros of the main-mass velocity are bracketed on 64 samples per period and located by Brent's
    method; the flight ends are included.
    """
    om = c[7]
    hs = 2.0 * math.pi / max(c[6], om) / 64.0
    ns = max(int(math.ceil(tau / hs)), 1)
    h = tau / ns
    x, va, _ = flight_state(0.0, c)
    acc[3] = max(acc[3], x)
    acc[4] = min(acc[4], x)
    ta = 0.0
    for k in range(1, ns + 1):
        tb = k * h
        x, vb, _ = flight_state(tb, c)
        acc[3] = max(acc[3], x)
        acc[4] = min(acc[4], x)
        if (va > 0.0) != (vb > 0.0) and va != 0.0 and vb != 0.0:
            tr = brent(np.int64(0), ta, tb, va, vb, c)
            x, _, _ = flight_state(tr, c)
            acc[3] = max(acc[3], x)
            acc[4] = min(acc[4], x)
        ta = tb
        va = vb
