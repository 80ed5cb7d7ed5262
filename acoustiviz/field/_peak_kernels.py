"""Numba kernels of :func:`acoustiviz.field.peaks.fast_peaks`: geometry, exposure, coarse pass and candidates.

The candidates are refined on the closed form by :mod:`acoustiviz.field._peak_refine`. Times in
s, pressures in Pa.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit as _njit
from ._peak_refine import _refine_bracket
from .exposure import _correlation_at, _exposure_pairs

#: Newton stops when its step is below this fraction of the coarse step; the value is then that of
#: the quadratic model, O(step³ p''') from the maximum (about 1e-11 relative at 12 samples per a/c).
XTOL = 2e-3
#: Coarse steps sampled after the last pulse ends (about 2 a/c at 12 per a/c): the free decay's
#: bound beyond them is mostly below the peaks, so its closed-form extremes are rarely needed.
TAIL_STEPS = 24
#: A coarse candidate within NEAR + 1 coarse steps of a pulse's start or end has its bracket
#: widened to NEAR steps either side of it (split there, each side searched).
NEAR = 2.0
#: Arrival windows closer than this many coarse steps are merged (sampled across the gap).
GAP_STEPS = 8
#: Coarse samples per block of :func:`_coarse_stats` (its unrolling assumes eight).
BLOCK = 8


@_njit
def _cubic_start(coarse, k, kk, xs):  # pragma: no cover - compiled
    """Offset (in coarse steps, within ±1) of the maximum of the cubic through 4 coarse samples near ``k``.

    The samples ``k-1, k, k+1`` and ``k+2`` (``k-2`` when the parabola's vertex ``xs`` is left of
    ``k``); two Newton steps on the cubic's derivative from ``xs``. Only a start for the Newton
    iteration on the closed form: any value in ``[-1, 1]`` is safe.
    """
    f0 = coarse[k]
    fm = coarse[k - 1] if k > 0 else 0.0
    fp = coarse[k + 1]
    b = 0.5 * (fp - fm)
    c = 0.5 * (fp - 2.0 * f0 + fm)
    if xs >= 0.0:
        if k + 2 > kk:
            return xs
        d = (coarse[k + 2] - (f0 + 2.0 * b + 4.0 * c)) / 6.0
    else:
        f2 = coarse[k - 2] if k >= 2 else 0.0
        d = ((f0 - 2.0 * b + 4.0 * c) - f2) / 6.0
    x = xs
    for _ in range(2):
        dd = 2.0 * c + 6.0 * d * x
        if dd == 0.0:
            return xs
        x = x - (b + 2.0 * c * x + d * (3.0 * x * x - 1.0)) / dd
    if not (-1.0 < x < 1.0):
        return xs
    return x


@_njit
def _coarse_stats(coarse, kk, bmax, bmin):  # pragma: no cover - compiled
    """Largest and smallest of ``coarse[0..kk]``, the largest step between neighbours, and block extremes.

    Blocks of :data:`BLOCK` samples (``coarse`` is zero-padded to whole blocks, so its length must
    be at least ``kk + BLOCK``): ``bmax[b]`` and ``bmin[b]`` bound the samples of block ``b`` for
    :func:`_scan`. Unrolled by eight for instruction-level parallelism. Returns
    ``(blocks, max, min, jump)`` with ``max >= 0 >= min``.
    """
    nb = (kk + BLOCK) // BLOCK
    for k in range(kk + 1, nb * BLOCK):
        coarse[k] = 0.0
    jump = 0.0
    prev = 0.0
    cmax = 0.0
    cmin = 0.0
    for b in range(nb):
        k = BLOCK * b
        x0 = coarse[k]
        x1 = coarse[k + 1]
        x2 = coarse[k + 2]
        x3 = coarse[k + 3]
        x4 = coarse[k + 4]
        x5 = coarse[k + 5]
        x6 = coarse[k + 6]
        x7 = coarse[k + 7]
        mx = max(max(max(x0, x1), max(x2, x3)), max(max(x4, x5), max(x6, x7)))
        mn = min(min(min(x0, x1), min(x2, x3)), min(min(x4, x5), min(x6, x7)))
        j0 = max(max(abs(x0 - prev), abs(x1 - x0)), max(abs(x2 - x1), abs(x3 - x2)))
        j1 = max(max(abs(x4 - x3), abs(x5 - x4)), max(abs(x6 - x5), abs(x7 - x6)))
        prev = x7
        bmax[b] = mx
        bmin[b] = mn
        cmax = max(cmax, mx)
        cmin = min(cmin, mn)
        jump = max(jump, max(j0, j1))
    return nb, cmax, cmin, jump


@_njit
def _scan(coarse, kk, nb, bmax, bmin, floor_p, floor_n, dmin, big_h, cand):  # pragma: no cover - compiled
    """Coarse local maxima of ``p`` (above ``floor_p``) and of ``-p`` (above ``floor_n``), in one pass.

    Only the blocks of :func:`_coarse_stats` reaching a floor are read. Each maximum of sign
    ``side`` (0: ``p``, 1: ``-p``) gets in ``cand[side, :, n]`` its parabolic estimate, its Newton
    start, its sample time and ``-1`` (no breakpoint); returns the counts and the largest
    estimate of each sign.
    """
    n0 = 0
    n1 = 0
    top0 = -np.inf
    top1 = -np.inf
    for blk in range(nb):
        if bmax[blk] < floor_p and -bmin[blk] < floor_n:
            continue
        for k in range(BLOCK * blk, min(BLOCK * blk + BLOCK, kk)):
            c0 = coarse[k]
            if c0 >= floor_p or -c0 >= floor_n:
                for sign in (1.0, -1.0):
                    v0 = sign * c0
                    if v0 < (floor_p if sign > 0.0 else floor_n):
                        continue
                    vm = sign * coarse[k - 1] if k > 0 else 0.0
                    vp = sign * coarse[k + 1]
                    if v0 >= vm and v0 >= vp and v0 > 0.0:
                        den = vm - 2.0 * v0 + vp
                        xs = 0.5 * (vm - vp) / den if den < 0.0 else 0.0
                        est = v0 - 0.25 * (vm - vp) * xs
                        x = dmin + (k + _cubic_start(coarse, k, kk, xs)) * big_h
                        side = 0 if sign > 0.0 else 1
                        q = n0 if side == 0 else n1
                        cand[side, 0, q] = est
                        cand[side, 1, q] = x
                        cand[side, 2, q] = dmin + k * big_h
                        cand[side, 3, q] = -1.0
                        if side == 0:
                            n0 += 1
                            top0 = max(top0, est)
                        else:
                            n1 += 1
                            top1 = max(top1, est)
    return n0, top0, n1, top1


@_njit
def _decay_extremes(t_a, t_b, arrived, nimg, delays, are, aim, yend, end, s):  # pragma: no cover - compiled
    """Largest and smallest ``p`` on ``[t_a, t_b]`` where the images that arrived by ``arrived`` decay freely.

    There ``p(t_a + v) = Re[b e^{s v}]`` (the later images are silent); its extremes are among the
    ends and the first stationary points (each later one ``exp(-π)`` smaller). ``t_b`` may be
    infinite. Returns ``(hi, t_hi, lo, t_lo)``.
    """
    b = 0j
    for j in range(nimg):
        if delays[j] <= arrived:
            b += complex(are[j], aim[j]) * yend * np.exp(s * (t_a - delays[j] - end))
    hi = lo = b.real
    thi = tlo = t_a
    if b == 0j:
        return hi, thi, lo, tlo
    w = s.imag
    if math.isfinite(t_b):
        val = (b * np.exp(s * (t_b - t_a))).real
        if val > hi:
            hi = val
            thi = t_b
        if val < lo:
            lo = val
            tlo = t_b
    # p'(v) = Re[b s e^{s v}] = 0 where arg(b s) + Im(s) v = π/2 (mod π)
    bs = b * s
    v0 = ((0.5 * math.pi - math.atan2(bs.imag, bs.real)) % math.pi) / w
    for q in range(2):
        v = v0 + q * math.pi / w
        if not t_a + v < t_b:
            break
        val = (b * np.exp(s * v)).real
        if val > hi:
            hi = val
            thi = t_a + v
        if val < lo:
            lo = val
            tlo = t_a + v
    return hi, thi, lo, tlo


@_njit(inline="always")
def _windows(delays, order, dmin, dmax, end, big_h, seg_a, seg_b):  # pragma: no cover - compiled
    """Coarse-step ranges holding each image's pulse and TAIL_STEPS after it, merged where they meet.

    Fills ``seg_a``, ``seg_b`` (first and last coarse sample, from ``dmin``) and returns their
    number; ``order`` is work space (the images by arrival). Between the windows every image that
    has arrived decays freely.
    """
    nimg = delays.size
    if dmax - dmin <= end + (TAIL_STEPS + GAP_STEPS) * big_h:  # they all meet: one window
        seg_a[0] = 0
        seg_b[0] = int(math.ceil((dmax - dmin + end) / big_h)) + 1 + TAIL_STEPS
        return 1
    for j in range(nimg):
        order[j] = j
    for j in range(1, nimg):  # insertion sort of the few images by arrival
        oj = order[j]
        q = j - 1
        while q >= 0 and delays[order[q]] > delays[oj]:
            order[q + 1] = order[q]
            q -= 1
        order[q + 1] = oj
    nseg = 0
    for q in range(nimg):
        d = delays[order[q]] - dmin
        ka = int(math.floor(d / big_h))
        kb = int(math.ceil((d + end) / big_h)) + 1 + TAIL_STEPS
        if nseg > 0 and ka <= seg_b[nseg - 1] + GAP_STEPS:
            seg_b[nseg - 1] = max(seg_b[nseg - 1], kb)
        else:
            seg_a[nseg] = max(ka, 0)
            seg_b[nseg] = kb
            nseg += 1
    return nseg


@_njit(inline="always")
def _in_fluid(x0, x1, x2, centre, radius, tol, ppt, pnm):  # pragma: no cover - compiled
    """Whether the point ``(x0, x1, x2)`` (m) is outside the sphere and in front of every plane ``(ppt, pnm)``."""
    dc = math.sqrt((x0 - centre[0]) ** 2 + (x1 - centre[1]) ** 2 + (x2 - centre[2]) ** 2)
    ok = dc >= radius - tol
    for q in range(ppt.shape[0]):
        if (x0 - ppt[q, 0]) * pnm[q, 0] + (x1 - ppt[q, 1]) * pnm[q, 1] + (x2 - ppt[q, 2]) * pnm[q, 2] < -tol:
            ok = False
    return ok


@_njit(inline="always")
def _image_terms(x0, x1, x2, spos, saxis, rho, c, radius, delays, are, aim):  # pragma: no cover - compiled
    """Each image seen from ``(x0, x1, x2)`` (m), in image order (paper eqs 12-14).

    Into ``delays`` its delay ``(r - a)/c`` in s, into ``are + i aim`` its weight
    ``P0 (r/a) - i P0 (1 - r/a)`` in Pa·s/m.
    """
    for j in range(spos.shape[0]):
        d0 = x0 - spos[j, 0]
        d1 = x1 - spos[j, 1]
        d2 = x2 - spos[j, 2]
        r = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        ct = (d0 * saxis[j, 0] + d1 * saxis[j, 1] + d2 * saxis[j, 2]) / r
        p0 = rho * c * radius * radius * ct / (r * r)
        ra = r / radius
        delays[j] = (r - radius) / c
        are[j] = p0 * ra
        aim[j] = -p0 * (1.0 - ra)


@_njit(inline="always")
def _exposure(delays, are, aim, corr, g0, h0):  # pragma: no cover - compiled
    """``∫ p² dt`` in Pa²·s from the pairs of images and the pulse correlations (module ``exposure``)."""
    _, tau, cs, step, table, yend, m_g, m_h = corr
    return _exposure_pairs(delays, are, aim, tau, cs, step, table, yend, m_g, m_h, g0, h0)


@_njit(inline="always")
def _window_samples(ka, kk, t0, smp, delays, are, aim, qs, rs, coarse):  # pragma: no cover - compiled
    """Coarse samples ``0 .. kk`` of ``p`` (Pa) over the window from coarse step ``ka`` (``t0`` s) into ``coarse``.

    Each image that has arrived by the window's end adds its weight ``are + i aim`` (Pa·s/m) times
    a contiguous run of its residue table row ``rs`` from column ``qs + ka``.
    """
    ytr, yti, t_last = smp.ytr, smp.yti, t0 + kk * smp.big_h
    for k in range(kk + 1):
        coarse[k] = 0.0
    for j in range(delays.size):  # contiguous runs of one residue table per image
        if delays[j] > t_last:
            continue  # silent in this window
        seg_r = ytr[rs[j], qs[j] + ka : qs[j] + ka + kk + 1]
        seg_i = yti[rs[j], qs[j] + ka : qs[j] + ka + kk + 1]
        ar = are[j]
        ai = aim[j]
        for k in range(kk + 1):
            coarse[k] += ar * seg_r[k] - ai * seg_i[k]


@_njit(inline="always")
def _covered(kb, t0, big_h, done_lo, done_hi, ndone):  # pragma: no cover - compiled
    """Whether coarse step ``kb`` (``[t0 + kb H, t0 + (kb + 1) H]``, s) lies in a bracket already searched.

    A breakpoint's feature lies between the coarse samples ``kb`` and ``kb + 1``; ``done_lo[:ndone]``,
    ``done_hi[:ndone]`` are the brackets searched (split at the breakpoints), s; ``kb < 0`` is never covered.
    """
    if kb < 0:
        return False
    ta = t0 + kb * big_h - 1e-9 * big_h
    tz = t0 + (kb + 1) * big_h + 1e-9 * big_h
    for q in range(ndone):
        if done_lo[q] <= ta and tz <= done_hi[q]:
            return True
    return False


@_njit(inline="always")
def _breakpoint_candidate(side, nc, b, k, kk, coarse, cand):  # pragma: no cover - compiled
    """Add a candidate of sign ``side`` at breakpoint ``b`` s between coarse samples ``k`` and ``k + 1``.

    A feature narrower than the coarse step may sit at a pulse's start or end: the larger of its two
    coarse neighbours (Pa, signed by ``side``) bounds it. Added only for ``0 < k < kk`` and a positive
    estimate; returns the new number of candidates.
    """
    sign = 1.0 if side == 0 else -1.0
    if 0 < k < kk:
        est = max(sign * coarse[k], sign * coarse[k + 1])
        if est > 0.0:
            cand[side, 0, nc] = est
            cand[side, 1, nc] = b
            cand[side, 2, nc] = b
            cand[side, 3, nc] = k
            nc += 1
    return nc


@_njit(inline="always")
def _best_candidate(cand, side, nc):  # pragma: no cover - compiled
    """Index of the candidate of sign ``side`` with the largest estimate among the first ``nc``."""
    jb = 0
    for q in range(1, nc):
        if cand[side, 0, q] > cand[side, 0, jb]:
            jb = q
    return jb


@_njit(inline="always")
def _bracket(kb, tk, t0, dmin, big_h, bps):  # pragma: no cover - compiled
    """The bracket ``(lo, hi)`` in s refined for a candidate at ``tk`` s (coarse step ``kb``, or -1).

    One coarse step either side, or a breakpoint's coarse neighbours; p is only C¹ at a pulse's
    start or end: maxima on either side of one may be closer than a coarse step (the samples then
    show one hump), so near a breakpoint of ``bps`` (s) both sides are searched out to
    :data:`NEAR` coarse steps from it. Never before ``dmin``, the first arrival.
    """
    lo_b = max(dmin, tk - big_h)
    hi_b = tk + big_h
    if kb >= 0:
        lo_b = t0 + kb * big_h
        hi_b = t0 + (kb + 1) * big_h
    else:
        for b in bps:
            if abs(b - tk) < (NEAR + 1.0) * big_h:
                lo_b = max(dmin, min(lo_b, b - NEAR * big_h))
                hi_b = max(hi_b, b + NEAR * big_h)
    return lo_b, hi_b


@_njit(inline="always")
def _drop_candidate(cand, side, jb, nc):  # pragma: no cover - compiled
    """Remove candidate ``jb`` of sign ``side`` (the last of ``nc`` takes its place); return the new count."""
    nc -= 1
    for f in range(4):
        cand[side, f, jb] = cand[side, f, nc]
    return nc


# allocates nothing: compiled without reference counts, which would otherwise be updated for each of its
# array arguments at every call of this inner loop (figures: benchmarks/results/design_timings.md)
@_njit(_nrt=False)
def _refine_side(side, nc, top, slack, reached, t0, dmin, big_h, tp, delays, are, aim, bps, cand, done,
                 found):  # pragma: no cover - compiled
    """Refine the candidates of one sign, best estimate first, while one can still beat the best value.

    ``top`` is the largest coarse estimate and ``slack`` (Pa) the margin within which an estimate
    may still beat it or the best value; ``reached`` (Pa) a value ``p`` surely reaches (pieces
    that cannot beat it are not searched). ``done`` (2, m) is work space for the brackets
    searched (s); ``found`` (2, 2) holds the best value of each sign (Pa) and its time (s),
    updated. Returns the number of brackets refined.
    """
    sign = 1.0 if side == 0 else -1.0
    best = found[0, side]
    tbest = found[1, side]
    xtol = XTOL * big_h
    ndone = 0
    nref = 0
    while nc > 0:
        jb = _best_candidate(cand, side, nc)
        est = cand[side, 0, jb]
        if est + slack < best or est + slack < top - slack:
            break
        kb = int(cand[side, 3, jb])
        if not _covered(kb, t0, big_h, done[0], done[1], ndone):
            lo_b, hi_b = _bracket(kb, cand[side, 2, jb], t0, dmin, big_h, bps)
            val, tv = _refine_bracket(sign, max(best, reached), cand[side, 1, jb], lo_b, hi_b, bps, xtol,
                                      delays.size, delays, are, aim, tp)
            done[0, ndone] = lo_b
            done[1, ndone] = hi_b
            ndone += 1
            nref += 1
            if val > best:
                best = val
                tbest = tv
        nc = _drop_candidate(cand, side, jb, nc)
    found[0, side] = best
    found[1, side] = tbest
    return nref


@_njit(inline="always")
def _after_window(t_end, t_next, dmin, scale, tp, delays, are, aim, found):  # pragma: no cover - compiled
    """The free decay's extremes between ``t_end`` and ``t_next`` s (or for ever), where they can beat a peak found.

    ``scale`` is ``Σ|a_j|`` in Pa·s/m; ``found`` (2, 2) the best value of each sign (Pa) and its
    time (s), updated.
    """
    # the bound Σ|a_j| |Y(T)| e^{Re(s)(t_end - d_j - T)}, first from the latest arrival (which decays least)
    floor = min(found[0, 0], found[0, 1])
    end, sr, yend = tp.end, tp.sr, complex(tp.y0r, tp.y0i)
    yabs = abs(yend)
    last = dmin
    for j in range(delays.size):
        if delays[j] <= t_end:
            last = max(last, delays[j])
    if not scale * yabs * math.exp(sr * (t_end - last - end)) > floor:
        return
    bound = 0.0
    for j in range(delays.size):
        if delays[j] <= t_end:
            bound += math.sqrt(are[j] ** 2 + aim[j] ** 2) * yabs * math.exp(sr * (t_end - delays[j] - end))
    if not bound > floor:
        return
    thi, tphi, tlo, tplo = _decay_extremes(t_end, t_next, t_end, delays.size, delays, are, aim,
                                           yend, end, complex(sr, tp.si))
    if thi > found[0, 0]:
        found[0, 0] = thi
        found[1, 0] = tphi
    if -tlo > found[0, 1]:
        found[0, 1] = -tlo
        found[1, 1] = tplo


# allocates nothing: compiled without reference counts, as _refine_side
@_njit(_nrt=False)
def _search_window(ka, kk, dmin, scale, smp, tp, delays, are, aim, qs, rs, bps, coarse, bmax, bmin, cand, done,
                   found):  # pragma: no cover - compiled
    """Coarse pass, candidates and refinement of both signs over one window of arrivals; returns the refinements.

    The window holds the coarse samples ``t_k = dmin + (ka + k) H``, ``k = 0 .. kk``; the best
    values found (``found``) are updated.
    """
    big_h, fine, slope, margin, cusps = smp.big_h, smp.fine, smp.slope, smp.margin, smp.cusps
    h = big_h / fine
    t0 = dmin + ka * big_h
    _window_samples(ka, kk, t0, smp, delays, are, aim, qs, rs, coarse)
    nb, cmax, cmin, jump = _coarse_stats(coarse, kk, bmax, bmin)
    vmax = max(cmax, -cmin)
    slack = margin * vmax + 0.5 * h * slope * scale
    # a coarse local maximum's parabolic estimate exceeds it by at most 1/8 of its larger step,
    # so samples below these floors cannot come within the slack of the best estimate
    nc0, top0, nc1, top1 = _scan(coarse, kk, nb, bmax, bmin, cmax - 2.0 * slack - 0.125 * jump,
                                 -cmin - 2.0 * slack - 0.125 * jump, t0, big_h, cand)
    nref = 0
    for side in range(2):
        nc, top = (nc0, top0) if side == 0 else (nc1, top1)
        for b in bps:  # a feature narrower than H may sit at a breakpoint: its coarse neighbours bound it
            k = int((b - t0) / big_h) if cusps else -1  # none where the pulse starts and ends at A = 0
            nc = _breakpoint_candidate(side, nc, b, k, kk, coarse, cand)
        # pieces that cannot beat the largest coarse sample less the rounding bound (a value that p
        # reaches) are not searched
        reached = (cmax if side == 0 else -cmin) - 0.5 * h * slope * scale
        nref += _refine_side(side, nc, top, slack, reached, t0, dmin, big_h, tp, delays, are, aim, bps, cand, done,
                             found)
    return nref


@_njit(inline="always")
def _arrivals(smp, tp, delays, qs, rs, bps, order, seg_a, seg_b):  # pragma: no cover - compiled
    """First arrival ``dmin`` in s and the number of windows of arrivals (``seg_a``, ``seg_b``).

    Sorts the breakpoints into ``bps`` and sets each image's table column and residue row
    (``qs``, ``rs``) from its delay rounded to the fine step.
    """
    big_h, fine, pad, end = smp.big_h, smp.fine, smp.pad, tp.end
    nimg = delays.size
    h = big_h / fine
    dmin = delays[0]
    dmax = delays[0]
    for j in range(1, nimg):
        dmin = min(dmin, delays[j])
        dmax = max(dmax, delays[j])
    for j in range(nimg):  # where p'' may jump or have a cusp: the start and end of each pulse
        bps[2 * j] = delays[j]
        bps[2 * j + 1] = delays[j] + end
    for j in range(1, 2 * nimg):  # insertion sort of the few breakpoints
        b = bps[j]
        q = j - 1
        while q >= 0 and bps[q] > b:
            bps[q + 1] = bps[q]
            q -= 1
        bps[q + 1] = b
    for j in range(nimg):
        m = pad - int(round((delays[j] - dmin) / h))
        qs[j] = m // fine
        rs[j] = m - qs[j] * fine
    return dmin, _windows(delays, order, dmin, dmax, end, big_h, seg_a, seg_b)


@_njit(nogil=True)
def _peaks_kernel(res, pts, src, smp, tp, corr):  # pragma: no cover - compiled
    """Peaks, their times and the exposure of the pressure at each point, into ``res`` (module notes).

    At each point the coarse pass runs over each window of arrivals (``t_k = dmin + k H``);
    between windows and after the last, every image that has arrived decays freely: extremes in
    closed form.

    Parameters
    ----------
    res : (n, 6) ndarray
        Output rows: largest ``p`` (Pa), smallest ``p`` (Pa, <= 0), their times (s), exposure
        ``∫ p² dt`` (Pa²·s; NaN without ``corr.on``) and the number of brackets refined; NaN
        (and 0 refinements) for a point outside the fluid.
    pts : (n, 3) ndarray
        Observer positions in m.
    src : acoustiviz.field._common.PeakSources
        The sphere, its images and the fluid.
    smp : acoustiviz.field._common.PeakSampling
        The tabulated pulse (:class:`acoustiviz.field.peaks.PeakTable`) and the margin.
    tp : TaylorPulse
        ``Y`` for the refinement (:func:`acoustiviz.field._peak_refine.taylor_pulse`).
    corr : acoustiviz.field._common.PeakCorrelations
        The pulse correlations of the exposure.
    """
    spos, saxis, centre, ppt, pnm, radius, rho, c = src
    big_h = smp.big_h
    nimg = spos.shape[0]
    ncol = smp.ytr.shape[1]
    delays = np.empty(nimg)
    are = np.empty(nimg)
    aim = np.empty(nimg)
    qs = np.empty(nimg, np.int64)
    rs = np.empty(nimg, np.int64)
    coarse = np.empty(ncol + 2 + BLOCK)
    bmax = np.empty((ncol + 2 + BLOCK) // BLOCK + 1)
    bmin = np.empty((ncol + 2 + BLOCK) // BLOCK + 1)
    # candidates of each sign: estimate, Newton start, time, breakpoint's coarse index (or -1)
    cand = np.empty((2, 4, ncol + 2 + 2 * nimg))
    done = np.empty((2, ncol + 2 + 2 * nimg))
    bps = np.empty(2 * nimg)
    order = np.empty(nimg, np.int64)
    seg_a = np.empty(nimg, np.int64)
    seg_b = np.empty(nimg, np.int64)
    found = np.empty((2, 2))
    tol = 1e-12 * radius
    g0 = 0j
    h0 = 0j
    if corr.on:
        g0, h0 = _correlation_at(0.0, corr.tau, corr.s, corr.step, corr.table, corr.y_end, corr.m_g, corr.m_h)
    for i in range(pts.shape[0]):
        x0 = pts[i, 0]
        x1 = pts[i, 1]
        x2 = pts[i, 2]
        if not _in_fluid(x0, x1, x2, centre, radius, tol, ppt, pnm):
            for col in range(5):
                res[i, col] = np.nan
            res[i, 5] = 0.0
            continue
        _image_terms(x0, x1, x2, spos, saxis, rho, c, radius, delays, are, aim)
        res[i, 4] = _exposure(delays, are, aim, corr, g0, h0) if corr.on else np.nan
        scale = 0.0
        for j in range(nimg):
            scale += math.sqrt(are[j] ** 2 + aim[j] ** 2)
        dmin, nseg = _arrivals(smp, tp, delays, qs, rs, bps, order, seg_a, seg_b)
        found[0, :] = 0.0  # p = 0 before the first arrival
        found[1, :] = dmin
        nref = 0
        for sg in range(nseg):
            nref += _search_window(seg_a[sg], seg_b[sg] - seg_a[sg], dmin, scale, smp, tp, delays, are, aim, qs, rs,
                                   bps, coarse, bmax, bmin, cand, done, found)
            # after the window: the free decay of every image arrived so far, up to the next window (or
            # for ever), in closed form where its bound can beat a peak found
            t_end = dmin + seg_a[sg] * big_h + (seg_b[sg] - seg_a[sg] - 1) * big_h
            t_next = dmin + seg_a[sg + 1] * big_h if sg + 1 < nseg else np.inf
            _after_window(t_end, t_next, dmin, scale, tp, delays, are, aim, found)
        res[i, 0] = found[0, 0]
        res[i, 1] = -found[0, 1]
        res[i, 2] = found[1, 0]
        res[i, 3] = found[1, 1]
        res[i, 5] = nref
