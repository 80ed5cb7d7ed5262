"""Peak search of :func:`acoustiviz.field.peaks.fast_peaks` for many sources (a room's images).

The search is that of :mod:`acoustiviz.field._peak_kernels` over one window holding every
arrival (coarse samples ``t_k = d_min + k H``, candidates within the margin, refinement on the
closed form, the free decay after the last pulse in closed form), with three changes that make
its cost ``O(n log n + n T/H + K)`` for ``n`` images and ``K`` coarse samples instead of
``O(n K)``:

1. **Pulse-only table.** Each image reads its pulse from a table over ``[-2 H, T + 3 H]`` only
   (at its delay rounded to the fine step, as before); past the table its free decay
   ``a_j Y(T) e^{s (t - d_j - T)}`` is the same for all images up to a factor, so the decays of
   all images are one complex sum carried from block to block of :data:`DECAY_BLOCK` samples
   (``e^{s H}`` per sample), added to the samples with the powers of ``e^{s H}``
   (:func:`_dense_samples`).
2. **Sorted arrivals.** The refinement evaluates ``p``, ``p'`` and ``p''`` from the images that
   have arrived and whose decay is above ``exp(-DECAY_CUT)`` of their amplitude (1e-26), found by
   bisection in the sorted delays, with the breakpoints (pulse starts and ends) near the bracket
   only.
3. **Local rounding bound.** The bound of the delays' rounding, ``h/2 max|Y'| Σ|a_j|``, sums the
   images sampled within one pulse and decay cut of each other (the largest such sum), not all
   images.

The peaks are those of the windowed search to the refinement's accuracy (about 1e-11 relative).
Times in s, pressures in Pa.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit as _njit
from ._arrivals import _arrival_order
from ._exposure_closed import _exposure_closed
from ._peak_kernels import (
    BLOCK,
    NEAR,
    TAIL_STEPS,
    XTOL,
    _best_candidate,
    _bracket,
    _breakpoint_candidate,
    _coarse_stats,
    _covered,
    _decay_extremes,
    _drop_candidate,
    _image_terms,
    _in_fluid,
    _scan,
)
from ._peak_refine import _refine_bracket
from .exposure import _correlation_at, _exposure_sorted

#: Coarse samples per block of the images' summed free decay.
DECAY_BLOCK = 16
#: An image whose free decay has fallen by ``exp(-DECAY_CUT)`` (1e-26) is left out of the refinement.
DECAY_CUT = 60.0
#: Coarse steps either side of a candidate within which its bracket (widened at breakpoints) lies.
REACH = int(2 * NEAR) + 2


@_njit
def _dense_samples(kk, coarse, nq, ar, ai, fine, pad, ytr, yti, zpast, qpr, qpi):  # pragma: no cover - compiled
    """Coarse samples ``0 .. kk`` of ``p`` (``coarse`` zeroed beyond, to whole blocks) from the sorted images.

    Image ``q`` lies ``nq[q]`` fine steps after ``dmin``; it reads its pulse from the table row of
    its fine residue and leaves it at sample ``kstar`` with value ``a_q zpast[residue]``, then
    decays by ``e^{s H}`` a sample. ``qpr + i qpi`` are the powers ``e^{s H m}``, ``m = 0..DECAY_BLOCK``.
    """
    ncol = ytr.shape[1]
    ytf = ytr.reshape(ytr.size)  # the tables' rows end to end; unsigned indices below: no wraparound test
    yif = yti.reshape(yti.size)
    c_len = DECAY_BLOCK
    nblk = kk // c_len + 1
    for k in range(nblk * c_len):
        coarse[k] = 0.0
    qc = complex(qpr[c_len], qpi[c_len])
    acc = 0j  # the decays of the images that left the table before the current block, at its start
    nxt = 0j  # those that leave it within the current block, at the next block's start
    blk = 0
    for q in range(nq.size):
        m = pad - nq[q]
        qs = m // fine
        rs = m - qs * fine
        a_r = ar[q]
        a_i = ai[q]
        k_first = max(0, -qs)
        k_past = ncol - qs
        k_stop = min(kk + 1, k_past)
        if k_first < k_stop:
            row = np.uint64(rs * ncol + qs + k_first)
            col = np.uint64(k_first)
            for k in range(k_stop - k_first):
                u = np.uint64(k)
                coarse[col + u] += a_r * ytf[row + u] - a_i * yif[row + u]
        if k_past > kk:
            continue
        e = complex(a_r, a_i) * zpast[rs]
        b = k_past // c_len
        while blk < b:  # the sorted images leave the table in order: close the blocks before this one
            _add_decay(coarse, np.uint64(blk * c_len), c_len, acc.real, acc.imag, qpr, qpi)
            acc = acc * qc + nxt
            nxt = 0j
            blk += 1
        off = k_past - b * c_len  # within the current block: from its own sample on
        _add_decay(coarse, np.uint64(k_past), c_len - off, e.real, e.imag, qpr, qpi)
        nxt += e * complex(qpr[c_len - off], qpi[c_len - off])
    while blk < nblk:
        _add_decay(coarse, np.uint64(blk * c_len), c_len, acc.real, acc.imag, qpr, qpi)
        acc = acc * qc + nxt
        nxt = 0j
        blk += 1


@_njit(inline="always")
def _add_decay(coarse, start, count, er, ei, qpr, qpi):  # pragma: no cover - compiled
    """``coarse[start + l] += Re((er + i ei) exp(s H l))`` for ``l < count`` (unsigned indices)."""
    for ll in range(count):
        u = np.uint64(ll)
        coarse[start + u] += er * qpr[u] - ei * qpi[u]


@_njit
def _breakpoints_near(ds, end, lo, hi, bps):  # pragma: no cover - compiled
    """The pulse starts and ends (sorted) of the sorted delays ``ds`` lying in ``[lo, hi]``, into ``bps``."""
    n = ds.size
    a = np.searchsorted(ds, lo)
    b = np.searchsorted(ds, lo - end)
    nb = 0
    while True:
        sa = ds[a] if a < n and ds[a] <= hi else np.inf
        sb = ds[b] + end if b < n and ds[b] + end <= hi else np.inf
        if sa == np.inf and sb == np.inf:
            break
        if sa <= sb:
            bps[nb] = sa
            a += 1
        else:
            bps[nb] = sb
            b += 1
        nb += 1
    return nb


@_njit
def _rounding_scale(ds, mag, span):  # pragma: no cover - compiled
    """Largest ``Σ |a_j|`` over the sorted delays within ``span`` s of each other (two pointers)."""
    best = 0.0
    run = 0.0
    lo = 0
    for q in range(ds.size):
        run += mag[q]
        while ds[q] - ds[lo] > span:
            run -= mag[lo]
            lo += 1
        best = max(best, run)
    return best * (1.0 + 1e-12)


@_njit
def _refine_side(side, best, tbest, nc, top, slack, reached, cand, t0, big_h, ds, ar, ai, end, cut, tp, bps,
                 done_lo, done_hi):  # pragma: no cover - compiled
    """Refine the candidates of one sign, best estimate first, while one can still beat the best value.

    As the windowed search (:func:`acoustiviz.field._peak_kernels._peaks_kernel`), with the
    images and breakpoints near each bracket only. Returns ``(best, tbest, refinements)``.
    """
    sign = 1.0 if side == 0 else -1.0
    xtol = XTOL * big_h
    dmin = ds[0]
    ndone = 0
    nref = 0
    while nc > 0:
        jb = _best_candidate(cand, side, nc)
        est = cand[side, 0, jb]
        if est + slack < best or est + slack < top - slack:
            break
        tk = cand[side, 2, jb]
        kb = int(cand[side, 3, jb])
        if not _covered(kb, t0, big_h, done_lo, done_hi, ndone):
            nbp = _breakpoints_near(ds, end, tk - REACH * big_h, tk + REACH * big_h, bps)
            bp = bps[:nbp]
            lo_b, hi_b = _bracket(kb, tk, t0, dmin, big_h, bp)
            j_lo = np.searchsorted(ds, lo_b - end - cut)
            j_hi = np.searchsorted(ds, hi_b, side="right")
            val, tv = _refine_bracket(sign, max(best, reached), cand[side, 1, jb], lo_b, hi_b, bp, xtol, j_hi - j_lo,
                                      ds[j_lo:j_hi], ar[j_lo:j_hi], ai[j_lo:j_hi], tp)
            done_lo[ndone] = lo_b
            done_hi[ndone] = hi_b
            ndone += 1
            nref += 1
            if val > best:
                best = val
                tbest = tv
        nc = _drop_candidate(cand, side, jb, nc)
    return best, tbest, nref


@_njit
def _after_last(t_end, best_s, tbest_s, ds, ar, ai, mag, tp):  # pragma: no cover - compiled
    """Extremes of the free decay of every image after ``t_end``, where their bound can beat a peak found."""
    end = tp.end
    yend = complex(tp.y0r, tp.y0i)
    s = complex(tp.sr, tp.si)
    yabs = abs(yend)
    bound = 0.0
    q = ds.size - 1
    while q >= 0:
        x = s.real * (t_end - ds[q] - end)
        if x < -DECAY_CUT:
            break
        bound += mag[q] * yabs * math.exp(x)
        q -= 1
    rest = 0.0
    for j in range(q + 1):
        rest += mag[j]
    bound = (bound + rest * yabs * math.exp(-DECAY_CUT)) * (1.0 + 1e-9)
    if bound <= min(best_s[0], best_s[1]):
        return
    j0 = q + 1
    thi, tphi, tlo, tplo = _decay_extremes(t_end, np.inf, t_end, ds.size - j0, ds[j0:], ar[j0:], ai[j0:], yend,
                                           end, s)
    if thi > best_s[0]:
        best_s[0] = thi
        tbest_s[0] = tphi
    if -tlo > best_s[1]:
        best_s[1] = -tlo
        tbest_s[1] = tplo


@_njit(inline="always")
def _pair_table(ctable):  # pragma: no cover - compiled
    """The correlation table's ``G ± H`` sums by column, (rows, 8), as :func:`_exposure_sorted` reads them."""
    ptab = np.empty((ctable.shape[0], 8))
    for q in range(ctable.shape[0]):
        g, dg, hh, dh = ctable[q, 0], ctable[q, 1], ctable[q, 2], ctable[q, 3]
        ptab[q, 0] = g.real + hh.real
        ptab[q, 1] = dg.real + dh.real
        ptab[q, 2] = g.imag - hh.imag
        ptab[q, 3] = dg.imag - dh.imag
        ptab[q, 4] = g.imag + hh.imag
        ptab[q, 5] = dg.imag + dh.imag
        ptab[q, 6] = g.real - hh.real
        ptab[q, 7] = dg.real - dh.real
    return ptab


@_njit(inline="always")
def _sorted_sources(x0, x1, x2, spos, saxis, rho, c, radius, delays, are, aim, count, key, order, ds, ar, ai,
                    mag):  # pragma: no cover - compiled
    """Every image seen from ``(x0, x1, x2)`` (m), sorted by arrival (a bucket sort, :mod:`._arrivals`).

    Into ``ds`` the delays in s, ``ar + i ai`` the weights and ``mag`` their moduli in Pa·s/m;
    ``delays``, ``are``, ``aim``, ``key``, ``order`` (the image count) and ``count`` (one more)
    are work space.
    """
    nimg = spos.shape[0]
    _image_terms(x0, x1, x2, spos, saxis, rho, c, radius, delays, are, aim)
    _arrival_order(delays, count, key, order)
    for q in range(nimg):
        j = order[q]
        ds[q] = delays[j]
        ar[q] = are[j]
        ai[q] = aim[j]
        mag[q] = math.sqrt(are[j] ** 2 + aim[j] ** 2)


@_njit(inline="always")
def _cusp_candidates(side, nc, ds, end, dmin, big_h, kk, coarse, cand):  # pragma: no cover - compiled
    """Add the pulse starts and ends (s) of every image as candidates of one sign; return the new count.

    A feature narrower than ``H`` may sit at such a breakpoint: its coarse neighbours bound it.
    """
    for q in range(2 * ds.size):
        b = ds[q // 2] + (end if q % 2 else 0.0)
        nc = _breakpoint_candidate(side, nc, b, int((b - dmin) / big_h), kk, coarse, cand)
    return nc


@_njit(inline="always")
def _decay_factors(yend, s, ncol, fine, pad, h, big_h, end):  # pragma: no cover - compiled
    """``Y`` in m/s just past the table by fine residue, and ``exp(s H m)`` for ``m <= DECAY_BLOCK`` (re, im)."""
    zpast = np.empty(fine, np.complex128)
    for r in range(fine):
        zpast[r] = yend * np.exp(s * ((ncol * fine + r - pad) * h - end))
    qpr = np.empty(DECAY_BLOCK + 1)
    qpi = np.empty(DECAY_BLOCK + 1)
    for m in range(DECAY_BLOCK + 1):
        z = np.exp(s * big_h * m)
        qpr[m] = z.real
        qpi[m] = z.imag
    return zpast, qpr, qpi


@_njit(nogil=True)
def _dense_kernel(res, pts, src, smp, tp, corr, closed):  # pragma: no cover - compiled
    """:func:`acoustiviz.field._peak_kernels._peaks_kernel` over one window (module notes); same columns.

    ``src``, ``smp``, ``tp`` and ``corr`` are the records :func:`~._peak_kernels._peaks_kernel` takes
    (:class:`~._common.PeakSources`, :class:`~._common.PeakSampling`, :class:`~._common.TaylorPulse`,
    :class:`~._common.PeakCorrelations`). The exposure of the half-sine pulse (``closed.lag_terms``
    not empty) sums its close pairs in closed form (:func:`._exposure_closed._exposure_closed`, with
    the tables of :class:`._exposure_closed.ClosedPairs`), of other pulses from the correlation table.
    """
    spos, saxis, centre, ppt, pnm, radius, rho, c = src
    big_h, fine, pad, ytr, yti, slope, margin, cusps = smp
    do_exp, ctau, cs, cstep, ctable, cyend, m_g, m_h = corr
    lag_terms, ts, tw = closed
    end = tp.end
    yend = complex(tp.y0r, tp.y0i)
    s = complex(tp.sr, tp.si)
    n = pts.shape[0]
    nimg = spos.shape[0]
    h = big_h / fine
    cut = DECAY_CUT / -s.real
    ncol = ytr.shape[1]
    delays = np.empty(nimg)
    are = np.empty(nimg)
    aim = np.empty(nimg)
    ds = np.empty(nimg)
    ar = np.empty(nimg)
    ai = np.empty(nimg)
    mag = np.empty(nimg)
    count = np.empty(nimg + 1, np.int64)
    key = np.empty(nimg, np.int64)
    order = np.empty(nimg, np.int64)
    nq = np.empty(nimg, np.int64)
    bps = np.empty(2 * nimg + 2)
    best_s = np.empty(2)
    tbest_s = np.empty(2)
    zpast, qpr, qpi = _decay_factors(yend, s, ncol, fine, pad, h, big_h, end)
    coarse = np.empty(0)
    bmax = np.empty(0)
    bmin = np.empty(0)
    cand = np.empty((2, 4, 0))
    done_lo = np.empty(0)
    done_hi = np.empty(0)
    tol = 1e-12 * radius
    g0 = 0j
    h0 = 0j
    ptab = _pair_table(ctable)
    if do_exp:
        g0, h0 = _correlation_at(0.0, ctau, cs, cstep, ctable, cyend, m_g, m_h)
    for i in range(n):
        x0 = pts[i, 0]
        x1 = pts[i, 1]
        x2 = pts[i, 2]
        if not _in_fluid(x0, x1, x2, centre, radius, tol, ppt, pnm):
            for col in range(5):
                res[i, col] = np.nan
            res[i, 5] = 0.0
            continue
        _sorted_sources(x0, x1, x2, spos, saxis, rho, c, radius, delays, are, aim, count, key, order, ds, ar, ai,
                        mag)
        if do_exp:
            if lag_terms.size:
                res[i, 4] = _exposure_closed(ds, ar, ai, ctau, cs, lag_terms, cyend, m_g, m_h, ts, tw)
            else:
                res[i, 4] = _exposure_sorted(ds, ar, ai, ctau, cs, cstep, ptab, cyend, m_g, m_h, g0, h0)
        else:
            res[i, 4] = np.nan
        dmin = ds[0]
        for q in range(nimg):
            nq[q] = int(round((ds[q] - dmin) / h))
        # one window from the first arrival to TAIL_STEPS after the last pulse (t_k = dmin + k H, k <= kk)
        kk = int(math.ceil((ds[nimg - 1] - dmin + end) / big_h)) + 1 + TAIL_STEPS
        need = kk + DECAY_BLOCK + BLOCK + 2
        if coarse.size < need:
            coarse = np.empty(need)
            bmax = np.empty(need // BLOCK + 2)
            bmin = np.empty(need // BLOCK + 2)
            cand = np.empty((2, 4, need + 2 * nimg + 2))
            done_lo = np.empty(need + 2 * nimg + 2)
            done_hi = np.empty(need + 2 * nimg + 2)
        _dense_samples(kk, coarse, nq, ar, ai, fine, pad, ytr, yti, zpast, qpr, qpi)
        nb, cmax, cmin, jump = _coarse_stats(coarse, kk, bmax, bmin)
        vmax = max(cmax, -cmin)
        rounding = 0.5 * h * slope * _rounding_scale(ds, mag, end + cut + 4.0 * big_h)
        slack = margin * vmax + rounding
        nc0, top0, nc1, top1 = _scan(coarse, kk, nb, bmax, bmin, cmax - 2.0 * slack - 0.125 * jump,
                                     -cmin - 2.0 * slack - 0.125 * jump, dmin, big_h, cand)
        nref = 0
        for side in range(2):
            nc, top = (nc0, top0) if side == 0 else (nc1, top1)
            if cusps:  # a feature narrower than H may sit at a breakpoint: its coarse neighbours bound it
                nc = _cusp_candidates(side, nc, ds, end, dmin, big_h, kk, coarse, cand)
            reached = (cmax if side == 0 else -cmin) - rounding
            best, tbest, nr = _refine_side(side, 0.0, dmin, nc, top, slack, reached, cand, dmin, big_h, ds, ar, ai,
                                           end, cut, tp, bps, done_lo, done_hi)
            best_s[side] = best  # p = 0 before the first arrival
            tbest_s[side] = tbest
            nref += nr
        _after_last(dmin + (kk - 1) * big_h, best_s, tbest_s, ds, ar, ai, mag, tp)
        for side in range(2):
            res[i, side] = (1.0 if side == 0 else -1.0) * best_s[side]
            res[i, 2 + side] = tbest_s[side]
        res[i, 5] = nref

