"""The exposure of a room's half-sine impact in closed form: the close pairs of arrivals as running sums.

On ``[0, T]`` the half-sine pulse's response ``Y`` is a sum of three exponentials
(:func:`acoustiviz.field._kernels._y_at`), so its correlations ``G(Δ) = ∫ Y(u) Y(u + Δ) du`` and
``H(Δ) = ∫ Y(u) Ȳ(u + Δ) du`` (:mod:`acoustiviz.field.exposure`) are, for ``0 <= Δ <= T``, sums of
``e^{sΔ}``, ``e^{s̄Δ}``, ``e^{s(T - Δ)}``, ``e^{±iwΔ}`` and ``Δ e^{±iwΔ}`` (``w = π/T``):
:func:`half_sine_lag_terms`. A point's pairs of arrivals closer than ``T`` then sum as running
sums over its sorted arrivals (:func:`_exposure_closed`): ``O(n)`` for ``n`` images however many
arrivals fall within ``T`` of each other (at order 10 in a 6 x 4 x 3 m room about ten per
arrival), with no table and no interpolation (1e-14 of the exact pair sum). Times in s.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._jit import njit as _njit

#: The running sums keep their reference time within this many decay times ``1/|Re s|`` of the
#: latest arrival (:func:`acoustiviz.field.exposure._exposure_sorted` and :func:`_exposure_closed`).
EPOCH = 16.0


def _lag_exponentials(c1, l1, y1_end, s1, c2, l2, y2_end, s2, tau: float) -> dict:
    """``∫ Y1(u) Y2(u + Δ) du`` over ``u >= 0`` for ``0 <= Δ <= T`` as ``Σ (C + D Δ) exp(κ Δ)``.

    ``Yi(u) = Σ_p ci_p exp(li_p u)`` on ``[0, T]`` and ``yi_end exp(si (u - T))`` after (``T = tau``).
    Returns ``{κ: [C, D]}`` (s, units of ``Y1 Y2`` times s and times 1) from the three pieces
    ``u + Δ <= T``, ``u <= T < u + Δ`` and ``T < u``, each an integral of exponentials.
    """
    out: dict = {}

    def add(kappa, c, d=0j):
        e = out.setdefault(complex(kappa), [0j, 0j])
        e[0] += c
        e[1] += d

    for cp, lp in zip(c1, l1, strict=True):
        for cq, lq in zip(c2, l2, strict=True):
            mu = lp + lq
            if mu == 0:  # ∫_0^{T-Δ} e^{lq Δ} du
                add(lq, cp * cq * tau, -cp * cq)
            else:
                add(-lp, cp * cq * np.exp(mu * tau) / mu)
                add(lq, -cp * cq / mu)
        f = cp * y2_end * np.exp(lp * tau) / (lp + s2)
        add(s2, f)
        add(-lp, -f)
    add(s2, y1_end * y2_end / -(s1 + s2))
    return out


def half_sine_lag_terms(amp: float, tau: float, s: complex) -> np.ndarray:
    """``G`` and ``H`` of the half-sine pulse on ``0 <= Δ <= T`` as sums of exponentials in the lag.

    Parameters
    ----------
    amp : float
        Pulse amplitude in m/s².
    tau : float
        Pulse length T in s.
    s : complex
        The sphere's pole in 1/s.

    Returns
    -------
    (12,) complex ndarray
        With ``w = π/T``: ``G(Δ) = g_s e^{sΔ} + g_m e^{s(T-Δ)} + (g_+ + g'_+ Δ) e^{iwΔ} + (g_- + g'_- Δ) e^{-iwΔ}``
        and ``H(Δ) = h_s e^{s̄Δ} + h_m e^{s(T-Δ)} + (h_+ + h'_+ Δ) e^{iwΔ} + (h_- + h'_- Δ) e^{-iwΔ}``,
        in the order ``g_s, h_s, g_m, h_m, g_+, g'_+, g_-, g'_-, h_+, h'_+, h_-, h'_-``
        ((m/s)²·s, and (m/s)² for the primed ones).

    Notes
    -----
    On ``[0, T]`` the half-sine's ``Y = A/(s² + w²) (-s sin wu - w cos wu + w e^{su})``
    (:func:`acoustiviz.field._kernels._y_at`) is a sum of ``e^{±iwu}`` and ``e^{su}``, and after
    ``T`` it decays as ``Y(T) e^{s(u - T)}``: each piece of ``∫ Y(u) Y(u + Δ) du`` is an integral
    of exponentials (:func:`_lag_exponentials`); the pairs ``e^{iwu} e^{-iw(u + Δ)}`` integrate to
    ``(T - Δ) e^{∓iwΔ}``. The terms in ``e^{-sΔ}`` are carried as ``e^{s(T - Δ)}`` (bounded by 1).
    """
    w = math.pi / tau
    coef = amp / (s * s + w * w)
    lam = [1j * w, -1j * w, s]
    c = [coef * (-s / 2j - w / 2.0), coef * (s / 2j - w / 2.0), coef * w]
    y_end = coef * w * (1.0 + np.exp(s * tau))
    g = _lag_exponentials(c, lam, y_end, s, c, lam, y_end, s, tau)
    h = _lag_exponentials(c, lam, y_end, s, [np.conj(x) for x in c], [np.conj(x) for x in lam], np.conj(y_end),
                          np.conj(s), tau)
    fall = np.exp(-s * tau)
    out = np.array([g[s][0], h[np.conj(s)][0], g[-s][0] * fall, h[-s][0] * fall,
                    *g[1j * w], *g[-1j * w], *h[1j * w], *h[-1j * w]], dtype=complex)
    assert set(g) == {s, -s, 1j * w, -1j * w} and set(h) == {np.conj(s), -s, 1j * w, -1j * w}
    assert g[s][1] == 0 and h[np.conj(s)][1] == 0 and g[-s][1] == 0 and h[-s][1] == 0
    return out


#: Steps per epoch (and per period ``2T`` of ``e^{-iwΔ}``) of the exponential tables of
#: :func:`_exposure_closed`; within a step ``e^{z}`` is a Taylor polynomial of degree :data:`EXP_DEGREE`
#: (``|z| <= 2π/EXP_STEPS``, 0.0031, and ``16/EXP_STEPS`` times ``√2``, 0.011: the next term below 1e-17).
EXP_STEPS = 2048
EXP_DEGREE = 6


class ClosedPairs(NamedTuple):
    """The half-sine's closed-form close pairs, as :func:`acoustiviz.field._peak_dense._dense_kernel` reads them.

    Attributes
    ----------
    lag_terms : (k,) complex ndarray
        The exponential terms of the pulse correlations in the lag on ``[0, T]``
        (:attr:`acoustiviz.field.exposure.PulseCorrelations.lag_terms`); empty for other pulses,
        whose close pairs read the correlation table.
    ts, tw : (EXP_STEPS + 1,) complex ndarray
        The tables of :func:`closed_tables` (unused when ``lag_terms`` is empty).
    """

    lag_terms: np.ndarray
    ts: np.ndarray
    tw: np.ndarray


@_njit
def closed_tables(tau, s):  # pragma: no cover - compiled
    """The tables of :func:`_exp_step`, once per pulse and sphere (complex, ``EXP_STEPS + 1`` each).

    ``e^{s m δ}`` (``δ``: the epoch ``EPOCH/|Re s|`` over :data:`EXP_STEPS`) and ``e^{-iw m δ'}``
    (``δ' = 2T/EXP_STEPS``, ``w = π/T``).
    """
    span = EPOCH / -s.real
    w = math.pi / tau
    ts = np.empty(EXP_STEPS + 1, np.complex128)
    tw = np.empty(EXP_STEPS + 1, np.complex128)
    for m in range(EXP_STEPS + 1):
        ts[m] = np.exp(s * (m * (span / EXP_STEPS)))
        tw[m] = np.exp(-1j * w * (m * (2.0 * tau / EXP_STEPS)))
    return ts, tw


@_njit(inline="always")
def _exp_step(x, step, inv_step, table, rate):  # pragma: no cover - compiled
    """``e^{rate x}`` for ``0 <= x <= EXP_STEPS step`` from ``table[m] = e^{rate m step}`` and a Taylor polynomial.

    In real arithmetic (Horner, degree :data:`EXP_DEGREE`); ``inv_step = 1/step`` (a product is
    cheaper than a quotient; ``x`` then lies within a rounding of the step ``m`` it is read from).
    """
    m = min(int(x * inv_step), EXP_STEPS)
    r = x - m * step
    zr = rate.real * r
    zi = rate.imag * r
    pr = 1.0
    pi = 0.0
    for q in range(EXP_DEGREE, 0, -1):
        c = 1.0 / q
        nr = 1.0 + (zr * pr - zi * pi) * c
        pi = (zr * pi + zi * pr) * c
        pr = nr
    e = table[m]
    return complex(e.real * pr - e.imag * pi, e.real * pi + e.imag * pr)


#: :func:`_exposure_closed` recomputes its window sums from their terms after this many arrivals
#: (or when the latest is more than :data:`REBASE_PULSES` pulse lengths past their reference time).
REBUILD = 32
REBASE_PULSES = 2.0


@_njit(inline="always")
def _late_pairs(j, m, ar, ai, eks, invs, epochs, upto, fall_t, q_back, g_m, h_m):  # pragma: no cover - compiled
    """The ``e^{s(T - Δ)}`` terms of the pairs of arrival ``j`` with the later ``j < q <= m`` (all within T).

    ``Σ_q a_q e^{s(d_j + T - d_q)} = e^{s(d_j + T - d_m)} U_m - e^{sT} U_j`` with
    ``U_k = Σ_{q <= k} a_q e^{s(d_k - d_q)}`` (``upto``), ``e^{s(d_j - d_m)}`` from the arrivals'
    ``e^{s(d - ref)}`` (``eks``), their inverses and the epochs between them (``q_back`` each).
    """
    if m <= j:
        return 0.0
    aj = complex(ar[j], ai[j])
    grow = eks[j] * invs[m]
    for _ in range(epochs[m] - epochs[j]):
        grow *= q_back
    inner = fall_t * (grow * upto[m] - upto[j])
    return ((g_m * aj + h_m * np.conj(aj)) * inner).real


@_njit(fastmath={"contract", "arcp"})
def _exposure_closed(ds, ar, ai, tau, s, terms, y_end, m_g, m_h, ts, tw):  # pragma: no cover - compiled
    """``∫ p² dt`` of one point from its sources sorted by arrival, the half-sine pulse: ``O(n)``, no table.

    As :func:`_exposure_sorted`, the pairs further apart than ``T`` by one running sum; the pairs
    closer than ``T`` with ``G`` and ``H`` on ``[0, T]`` as sums of exponentials in the lag
    (``terms``, :func:`half_sine_lag_terms`), each summed over the window of arrivals within ``T``
    of the later one:

    - ``e^{sΔ}``, ``e^{s̄Δ}``: ``P_k = Σ_{window} a_j e^{s(d_k - d_j)}`` is the running sum over all
      earlier arrivals less ``e^{sT}`` times the far one (both decaying: no growth of round-off);
    - ``e^{s(T - Δ)}`` (largest at the window's far end) is summed from the earlier arrival's side,
      ``Σ_{d_j <= d_k < d_j + T} a_k e^{s(d_j + T - d_k)}``, when it leaves the window: the running
      sum over all arrivals at the last one inside, times its decay to ``d_j + T``, less
      ``e^{sT}`` times the running sum at ``d_j`` (again decaying terms only);
    - ``e^{±iwΔ}`` and ``Δ e^{±iwΔ}`` (``w = π/T``, modulus one): window sums of ``a_j e^{∓iw(d_j - r)}``
      and ``(d_j - r)`` times them, an arrival added as it comes and taken off as it leaves,
      recomputed from their terms every :data:`REBUILD` arrivals, with the reference time ``r``
      moved to the latest arrival then.

    Each arrival costs a few dozen multiplications, however many arrivals lie within ``T`` of it:
    its two exponentials are read from ``ts`` and ``tw`` (:func:`closed_tables`) and a short
    Taylor polynomial (:func:`_exp_step`).
    """
    n = ds.size
    w = math.pi / tau
    fall_t = np.exp(s * tau)  # e^{sT}
    g_s, h_s, g_m, h_m = terms[0], terms[1], terms[2], terms[3]
    g_p, gd_p, g_n, gd_n = terms[4], terms[5], terms[6], terms[7]
    h_p, hd_p, h_n, hd_n = terms[8], terms[9], terms[10], terms[11]
    g0 = g_s + g_m * fall_t + g_p + g_n
    h0 = h_s + h_m * fall_t + h_p + h_n
    cg = y_end * m_g
    ch = np.conj(y_end) * m_h
    # the running sums' reference moves by whole epochs of EPOCH/|Re s| (as _exposure_sorted)
    span = EPOCH / -s.real
    q_epoch = np.exp(s * span)
    q_back = 1.0 / q_epoch
    fall = np.exp(-s * tau)
    qpow = np.empty(48, np.complex128)
    qpow[0] = 1.0
    for m in range(1, 48):
        qpow[m] = qpow[m - 1] * q_epoch
    step_s = span / EXP_STEPS
    period = 2.0 * tau
    step_w = period / EXP_STEPS
    inv_s = 1.0 / step_s
    inv_w = 1.0 / step_w
    inv_period = 1.0 / period
    eks = np.empty(n, np.complex128)  # e^{s (d_k - ref_k)}
    invs = np.empty(n, np.complex128)  # its inverse
    epochs = np.empty(n, np.int64)
    upto = np.empty(n, np.complex128)  # Σ_{j <= k} a_j e^{s (d_k - d_j)}
    osc = np.empty(n, np.complex128)  # e^{-iw (d_k - d0)}
    total = 0.0
    ref = ds[0]
    epoch = 0
    bsum = 0j  # far sum (as _exposure_sorted)
    asum = 0j  # all earlier arrivals: Σ a_j e^{-s (d_j - ref)}
    first = 0
    # window sums of the oscillating terms, about the reference time rr
    rr = ds[0]
    qp = 0j
    qm = 0j
    rp = 0j
    rm = 0j
    since = 0
    for k in range(n):
        dk = ds[k]
        akr = ar[k]
        aki = ai[k]
        ak = complex(akr, aki)
        total += 0.5 * (ak * ak * g0 + (akr * akr + aki * aki) * h0).real
        while dk - ref > span:
            ref += span
            epoch += 1
            bsum *= q_epoch
            asum *= q_epoch
        ek = _exp_step(dk - ref, step_s, inv_s, ts, s)
        inv = complex(ek.real, -ek.imag) * (1.0 / (ek.real * ek.real + ek.imag * ek.imag))  # |ek| >= e^-16
        eks[k] = ek
        invs[k] = inv
        epochs[k] = epoch
        x = dk - ds[0]
        ok = _exp_step(x - period * math.floor(x * inv_period), step_w, inv_w, tw, -1j * w)  # e^{-iwx}, period 2T
        osc[k] = ok
        while first < k and ds[first] <= dk - tau:  # leaves the window: far from here on
            j = first
            m = epoch - epochs[j]
            aj = complex(ar[j], ai[j])
            if m < 48:
                bsum += aj * fall * qpow[m] * invs[j]
            # its e^{s(T - Δ)} pairs with the arrivals j < q <= k - 1 (all within T after it)
            total += _late_pairs(j, k - 1, ar, ai, eks, invs, epochs, upto, fall_t, q_back, g_m, h_m)
            xp = aj * osc[j]
            xm = aj * np.conj(osc[j])
            qp -= xp
            qm -= xm
            rp -= (ds[j] - rr) * xp
            rm -= (ds[j] - rr) * xm
            first += 1
        if since >= REBUILD or dk - rr > REBASE_PULSES * tau:  # the window sums afresh, about dk
            rr = dk
            qp = 0j
            qm = 0j
            rp = 0j
            rm = 0j
            for j in range(first, k):
                aj = complex(ar[j], ai[j])
                xp = aj * osc[j]
                xm = aj * np.conj(osc[j])
                qp += xp
                qm += xm
                rp += (ds[j] - rr) * xp
                rm += (ds[j] - rr) * xm
            since = 0
        # far pairs (Δ >= T)
        acc = ek * bsum
        total += (ak * (cg * acc + ch * np.conj(acc))).real
        # close pairs, e^{sΔ} and e^{s̄Δ}: all earlier arrivals less the far ones
        allk = ek * asum
        near = allk - fall_t * acc
        close = g_s * near + h_s * np.conj(near)
        # close pairs, e^{±iwΔ} and Δ e^{±iwΔ}
        tk = dk - rr
        u0p = np.conj(ok) * qp
        u1p = np.conj(ok) * (tk * qp - rp)
        u0m = ok * qm
        u1m = ok * (tk * qm - rm)
        close += g_p * u0p + gd_p * u1p + g_n * u0m + gd_n * u1m
        close += h_p * np.conj(u0m) + hd_p * np.conj(u1m) + h_n * np.conj(u0p) + hd_n * np.conj(u1p)
        total += (ak * close).real
        # k joins the sums
        upto[k] = allk + ak
        asum += ak * inv
        xp = ak * ok
        xm = ak * np.conj(ok)
        qp += xp
        qm += xm
        rp += (dk - rr) * xp
        rm += (dk - rr) * xm
        since += 1
    for j in range(first, n):  # the arrivals still in the window at the end: pairs up to the last
        total += _late_pairs(j, n - 1, ar, ai, eks, invs, epochs, upto, fall_t, q_back, g_m, h_m)
    return total
