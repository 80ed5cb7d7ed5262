"""Driver of the forced impact damper (numba): flights, contacts, instantaneous impacts, sticking.

The flight (:mod:`._flight`, with the particular solution of the forcing), the contact
(:mod:`._contact`) and the status codes (:mod:`._status`) are those of free decay; what is proper
to forced operation is this driver: a run continued cycle by cycle (a contact may stay open
across the end of a call), the work of the forcing, and the sticking phase of the impact map.

Model: :class:`~acoustiviz.dynamics._records.Params` (SI).
Forcing vector ``fc``: ``[ω rad/s, P N, Q N, A_c m, A_s m]``: the main mass carries
``F(t) = P cos(ωt) + Q sin(ωt)`` and ``A_c cos(ωt) + A_s sin(ωt)`` is the particular solution.
State vector ``st`` (in/out, 8 floats): ``x, v, y, w`` (m, m/s), flag (0 flight, 1 in contact,
2 stuck), wall ±1, ``ξ = sqrt(δ)`` (m^0.5) and ``u = dδ/dt`` (m/s) of an unfinished contact. While
the flag is 1 the impact row ``n - 1`` is still open (its separation speed is NaN).
Impact rows: ``IMPACT_COLUMNS`` of :mod:`._status`.
Accumulators ``acc`` (added to): work of F on the main mass, dissipated by C, dissipated in
contacts (J), and the largest and smallest x reached (m).
``fcs`` is the forcing vector of the main and impact masses moving together (mass ``M + m``):
``[ω, P, Q, A_c, A_s, u_stick]`` with the particular solution of that oscillator and the speed
(m/s) below which instantaneous impacts turn into sticking (0 disables it).

Sticking (impact map only). A train of instantaneous impacts of restitution ``e`` against a wall
that the impact mass is pressed on shortens geometrically (a Zeno sequence). When the relative
speed after an impact falls below ``u_stick`` while the free relative acceleration presses the
impact mass on the wall, the last impact is made plastic and the two masses move together
(``(M + m) x'' + C x' + K x = F(t)``, closed form) while the wall pushes, i.e. while
``wall · x'' <= 0``. The release, where ``x''`` changes sign, is bracketed with a bound on
``|x''''|`` and located by Brent's method. After the release the relative gap opens as
``G'''(0) τ³/6`` (``G(0) = G'(0) = G''(0) = 0``); the flight is followed without contact test for
``τ_s = 2 G'''(0) / L4`` (``L4`` a bound on ``|x''''|``), over which ``G > 0`` is guaranteed, and
then scanned as usual.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from .._jit import helper, kernel, njit
from ._contact import N_STAGE_ROWS, N_WORK_ROWS, NY, contact, free_restitution_of, instant_impact
from ._flight import (
    _osc,
    brent,
    flight_coeffs,
    flight_energy,
    flight_minmax,
    flight_state,
    scan_forced,
)
from ._records import ContactStart
from ._status import STATUS_DIVERGED, STATUS_MAX_IMPACTS, STATUS_OK


@helper
def _jerk(tau, c):
    """Acceleration (m/s²) and its rate (m/s³) of the closed-form motion ``c`` at ``tau`` s.

    The rate is ``j_h - ω² v_p``: the free part's ``j_h = -2a a_h - (a² + ωd²) v_h`` and the
    particular part's ``-ω²`` times its velocity ``v_p``.
    """
    a, wd, om, ac, as_ = c[5], c[6], c[7], c[8], c[9]
    _, _, acc = flight_state(tau, c)
    xh, vh = _osc(c[1], c[2], tau, a, wd)
    ah = -2.0 * a * vh - (a * a + wd * wd) * xh
    jh = -2.0 * a * ah - (a * a + wd * wd) * vh
    t = c[0] + tau
    vp = om * (as_ * math.cos(om * t) - ac * math.sin(om * t))
    return acc, jh - om * om * vp


@helper
def _bound4(c, tau):
    """Bound on ``|x''''|`` (m/s⁴) of the motion ``c`` from ``tau`` on."""
    a, wd, om = c[5], c[6], c[7]
    x0, v0 = c[1], c[2]
    b = (v0 + a * x0) / wd
    r = math.sqrt(x0 * x0 + b * b)
    wn2 = a * a + wd * wd
    om2 = om * om
    return r * math.exp(-a * tau) * wn2 * wn2 + om2 * om2 * math.sqrt(c[8] * c[8] + c[9] * c[9])


@helper
def _release(c, tau_end, sw):
    """First ``tau`` in (0, tau_end] where ``sw x''`` turns >= 0 (the wall stops pushing): (found, tau)."""
    hmax = 0.25 * 2.0 * math.pi / max(c[6], c[7])
    hmin = 1e-10 * hmax
    ta = 0.0
    ga, gpa = _jerk(0.0, c)
    ga *= sw
    gpa *= sw
    if ga >= 0.0:
        return True, 0.0
    while ta < tau_end:
        h = min(hmax, tau_end - ta)
        # |g''| = |x''''| bounds the curvature of g = sw x''
        lb = _bound4(c, ta)
        while True:
            tb = ta + h
            gb, gpb = _jerk(tb, c)
            gb *= sw
            gpb *= sw
            mono = abs(gpa) > lb * h
            if gb >= 0.0:
                if mono or h <= hmin:
                    return True, brent(np.int64(3), ta, tb, sw * ga, sw * gb, c)
                h *= 0.5
                continue
            q = 0.5 * lb * h * h
            if mono or ga + gpa * h + q < 0.0 or gb - gpb * h + q < 0.0 or h <= hmin:
                break
            h *= 0.5
        ta = tb
        ga, gpa = gb, gpb
    return False, tau_end


#: Constants of the forced driver's closed-form flights: decay rate ``a = C / 2M`` (1/s) and damped
#: angular frequency ``wd`` (rad/s) of the main oscillator, the same (``a_s``, ``wd_s``) of the two
#: masses moving together, the effective mass ``meff = m M / (m + M)`` (kg) and the speed below
#: which instantaneous impacts turn into sticking ``u_stick`` (m/s, 0 disables it).
Flights = namedtuple("Flights", ["a", "wd", "a_s", "wd_s", "meff", "u_stick"])


@njit(inline="always")
def _flights(prm, fcs):
    """The :data:`Flights` constants of the model ``prm`` (``fcs``: the forcing of the masses together)."""
    M, K, C, m = prm.M, prm.K, prm.C, prm.m
    meff = m * M / (m + M)
    a = C / (2.0 * M)
    wd = math.sqrt(K / M - a * a)
    a_s = C / (2.0 * (M + m))
    wd_s = math.sqrt(max(K / (M + m) - a_s * a_s, 0.0))
    u_stick = fcs[5] if wd_s > 0.0 else 0.0
    return Flights(a, wd, a_s, wd_s, meff, u_stick)


@njit(inline="always")
def _account(c, tau, fcv, c_main, acc, extrema):
    """Add the work of F and the dissipation by the dashpot ``c_main`` (N s/m) over ``tau`` s of the flight ``c``.

    Into ``acc[0:2]`` (J); with ``extrema`` the largest and smallest x (m) into ``acc[3:5]``.
    """
    wk, dc = flight_energy(c, tau, fcv, c_main)
    acc[0] += wk
    acc[1] += dc
    if extrema:
        flight_minmax(c, tau, acc)


@njit(inline="always")
def _stuck(prm, fl, fc, fcs, st, t, t1, acc, extrema):
    """Follow the masses stuck on wall ``st[5]`` (one oscillator of mass M + m) until the wall stops pushing.

    Then the first stretch of the flight in which the gap surely opens (module docstring).
    Returns ``(t, released)``: the time reached (s) and False when ``t1`` s came first.
    """
    C, hg = prm.C, prm.half_gap
    sw = st[5]
    cs = flight_coeffs(t, st[0], st[1], st[2], st[3], fl.a_s, fl.wd_s, fcs, hg)  # the two masses together
    found, tau = _release(cs, t1 - t, sw)
    _account(cs, tau, fcs, C, acc, extrema)
    x, v, _ = flight_state(tau, cs)
    st[0] = x
    st[1] = v
    st[2] = x + sw * hg
    st[3] = v
    if not found:
        return t, False
    t = t + tau
    st[4] = 0.0
    # the gap opens as G'''(0) tau^3 / 6: follow the flight unchecked while G > 0 is certain
    c = flight_coeffs(t, st[0], st[1], st[2], st[3], fl.a, fl.wd, fc, hg)
    _, jk = _jerk(0.0, c)
    ts = 2.0 * sw * jk / _bound4(c, 0.0) if sw * jk > 0.0 else 0.0
    ts = min(ts, t1 - t)
    if ts > 0.0:
        _account(c, ts, fc, C, acc, extrema)
        x, v, _ = flight_state(ts, c)
        st[0] = x
        st[1] = v
        st[2] = st[2] + st[3] * ts
        t = t + ts
    return t, True


@njit(inline="always")
def _in_contact(prm, fc, st, t, t1, rtol, impacts, n, acc, extrema, work, kst):
    """Integrate the open contact (impact row ``n - 1``) until the bodies part or ``t1`` s.

    Updates ``st`` and the row (duration s, peak force N, impulse N s, energy lost J; the
    separation speed m/s when it ends) and ``acc``. Returns ``(t, status)``.
    """
    hg = prm.half_gap
    sw = st[5]
    r = contact(prm, fc, ContactStart(t, sw, st[0], st[1], st[6], st[7]), t1, rtol, None, np.int64(0), None,
                0.0, 0.0, work, kst, None, None)
    yc = r.y
    acc[0] += yc[8]
    acc[1] += yc[7]
    acc[2] += yc[6]
    if extrema:
        acc[3] = max(acc[3], st[0], yc[1])
        acc[4] = min(acc[4], st[0], yc[1])
    row = n - 1
    impacts[row, 4] += yc[0]
    impacts[row, 5] = max(impacts[row, 5], r.peak)
    impacts[row, 6] += yc[5]
    impacts[row, 7] += yc[6]
    xi = max(yc[3], 0.0)
    st[0] = yc[1]
    st[1] = yc[2]
    st[2] = yc[1] + sw * (hg + xi * xi)
    st[3] = yc[2] + sw * yc[4]
    st[6] = xi
    st[7] = yc[4]
    t = t + yc[0]
    if r.status != STATUS_OK:
        return t, r.status
    if r.ended:
        st[4] = 0.0
        impacts[row, 3] = -yc[4]
        st[2] = st[0] + sw * hg
    else:
        t = t1
    return t, r.status


@njit(inline="always")
def _fly(prm, fl, fc, st, t, t1, acc, extrema):
    """Free flight from ``t`` s to the next contact or ``t1`` s; ``st``, ``acc`` updated.

    Returns ``(t, found, sw)``: the time reached (s), whether a contact starts there and its wall.
    """
    c = flight_coeffs(t, st[0], st[1], st[2], st[3], fl.a, fl.wd, fc, prm.half_gap)
    found, tau, sw = scan_forced(c, t1 - t)
    if found and t + tau >= t1:
        found = False
        tau = t1 - t
    _account(c, tau, fc, prm.C, acc, extrema)
    x, v, _ = flight_state(tau, c)
    st[0] = x
    st[1] = v
    st[2] = st[2] + st[3] * tau
    return t + tau if found else t1, found, sw


@njit(inline="always")
def _instant(prm, fl, fc, st, t, sw, u0, restitution, rtol, impacts, n, acc):
    """Apply an instantaneous impact at ``t`` s on wall ``sw`` (approach ``u0`` m/s) into row ``n``.

    Restitution ``restitution`` (>= 0) or, below -1.5, that of the compliant contact of the two
    masses alone at this speed; a Zeno train on a wall that presses ends in sticking (module
    docstring). Returns the next free row.
    """
    M, K, C, m, hg = prm.M, prm.K, prm.C, prm.m, prm.half_gap
    e = restitution
    dur = 0.0
    peak = 0.0
    if restitution < 0.0:  # the compliant contact's restitution at this speed
        e, dur, peak = free_restitution_of(prm, u0, rtol)
    st[1], st[3], lost = instant_impact(prm, sw, u0, e, st[1], st[3], dur, peak, impacts[n])
    st[2] = st[0] + sw * hg
    acc[2] += lost
    n += 1
    # a Zeno train of impacts on a wall that presses: stick (module docstring)
    press = sw * (fc[1] * math.cos(fc[0] * t) + fc[2] * math.sin(fc[0] * t) - K * st[0] - C * st[1]) / M
    if e * u0 < fl.u_stick and press <= 0.0:
        vc = (M * st[1] + m * st[3]) / (M + m)
        eu = e * u0
        extra = 0.5 * fl.meff * (eu * eu)  # the last rebound made plastic
        acc[2] += extra
        impacts[n - 1, 3] = 0.0
        impacts[n - 1, 6] = fl.meff * u0
        impacts[n - 1, 7] = lost + extra
        st[1] = vc
        st[3] = vc
        st[4] = 2.0
        st[5] = sw
    return n


@njit(inline="always")
def _open_contact(prm, st, sw, u0, impacts, n):
    """Open a compliant contact on wall ``sw`` (approach ``u0`` m/s) in row ``n``; return the next free row."""
    for k in range(3, 8):
        impacts[n, k] = 0.0
    impacts[n, 3] = math.nan
    st[4] = 1.0
    st[5] = sw
    st[6] = math.sqrt(max(sw * (st[2] - st[0]) - prm.half_gap, 0.0))
    st[7] = u0
    return n + 1


@njit(inline="always")
def advance_inline(prm, fc, fcs, st, t0, t1, restitution, rtol, impacts, n, max_impacts, acc, extrema):
    """Advance the forced damper from ``t0`` to ``t1`` s (state ``st`` updated in place).

    The body of :func:`advance`, inlined into the kernels that run it (:mod:`._forced_direct`), so that
    its code is compiled once per kernel and not again when a kernel links another.

    ``restitution = None`` integrates compliant contacts (event solver); ``restitution >= 0``
    applies instantaneous impacts with that coefficient (impact map; ``restitution`` > 1 is
    refused upstream); ``restitution = -2`` applies instantaneous impacts with the restitution
    of the compliant contact of the two masses alone at each approach speed. New impact rows are
    written from row ``n``. ``extrema`` tracks the largest and smallest x in ``acc[3:5]``.
    ``st[4] = 2`` marks the impact mass stuck on wall ``st[5]`` (impact map, module docstring).

    numba compiles one version per type of ``restitution``: with None the instantaneous impacts,
    the sticking phase and the compliant contact of the masses alone (the impact map's pieces)
    are left out, so the event solver does not compile code it never runs.

    Parameters
    ----------
    prm : Params
        The model (:class:`~acoustiviz.dynamics._records.Params`, SI).
    fc, fcs : ndarray
        Forcing vectors of the main mass and of the two masses together (module docstring).
    st : ndarray
        State (module docstring), updated in place.
    t0, t1 : float
        Start and end (s).
    restitution : float or None
        As above.
    rtol : float
        Relative tolerance of the compliant contacts.
    impacts, n, max_impacts : ndarray, int, int
        Impact rows, the first free row and the row limit.
    acc : ndarray
        Accumulators (module docstring), added to.
    extrema : bool
        Track the largest and smallest x in ``acc[3:5]``.

    Returns
    -------
    tuple of int
        ``(n, status)``: ``n`` the next free impact row and ``status`` (``STATUS_OK``, ``STATUS_MAX_IMPACTS``,
        ``STATUS_STEP_UNDERFLOW`` or ``STATUS_DIVERGED``).
    """
    fl = _flights(prm, fcs)
    work = np.zeros((N_WORK_ROWS, NY + 1))  # forced contact state: NY + the work of F
    kst = np.zeros((N_STAGE_ROWS, NY + 1))
    t = t0
    status = STATUS_OK
    while t < t1:
        if restitution is not None and st[4] > 1.5:  # stuck on wall st[5] (impact map): one oscillator
            # of mass M + m until the wall stops pushing
            t, released = _stuck(prm, fl, fc, fcs, st, t, t1, acc, extrema)
            if not released:
                break
            continue
        if st[4] > 0.5:  # inside a contact: integrate it
            t, stc = _in_contact(prm, fc, st, t, t1, rtol, impacts, n, acc, extrema, work, kst)
            if stc != STATUS_OK:
                return (n, stc)
            continue
        t, found, sw = _fly(prm, fl, fc, st, t, t1, acc, extrema)
        if not (math.isfinite(st[0]) and math.isfinite(st[1])):
            return (n, STATUS_DIVERGED)
        if not found:
            break
        if n >= max_impacts:
            return (n, STATUS_MAX_IMPACTS)
        u0 = sw * (st[3] - st[1])
        if restitution is not None and u0 <= 0.0:  # resting on a wall: instantaneous impacts cannot follow
            return (n, STATUS_MAX_IMPACTS)
        impacts[n, 0] = t
        impacts[n, 1] = sw
        impacts[n, 2] = u0
        if restitution is None:  # compliant contact
            n = _open_contact(prm, st, sw, u0, impacts, n)
        else:  # instantaneous impact
            n = _instant(prm, fl, fc, st, t, sw, u0, restitution, rtol, impacts, n, acc)
    return (n, status)


@kernel
def advance(prm, fc, fcs, st, t0, t1, restitution, rtol, impacts, n, max_impacts, acc, extrema):
    """:func:`advance_inline` called from Python (one forcing period or any span; same parameters and returns).

    The search runs the driver through :func:`._forced_direct.run_cycles` instead, one compiled kernel.
    """
    return advance_inline(prm, fc, fcs, st, t0, t1, restitution, rtol, impacts, n, max_impacts, acc, extrema)
