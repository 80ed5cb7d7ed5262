"""Peak search of :func:`acoustiviz.field.peaks.fast_peaks` for many sources (a room's images): bounded chunks.

The coarse time grid ``t_k = d_min + k H`` of :mod:`acoustiviz.field._peak_kernels` is cut into
chunks of :data:`CHUNK_STEPS` samples. Before any sample is computed, each chunk gets a rigorous
bound on ``|p|`` over its samples and :data:`REACH` coarse steps either side (where its
candidates' brackets can reach)::

    |p(t)| <= Σ_j |a_j| |Y(t - d_j)| <= Σ_j |a_j| max_{u in the chunk's span - d_j} |Y(u)|,

in practice split as ``|Re[a_j Y]| <= |P0_j| ((r_j/a) |Yr - Yi| + |Yi|)`` (far from the sphere
``Yr - Yi``, the far field, is much smaller than ``|Y|``), with the maxima of ``|Yr - Yi|`` and
``|Yi|`` per coarse step of the pulse tabulated once (the fine samples plus half a fine step of
their slope, :func:`envelope`) and, after the pulse, the free decay ``|Y(T)| exp(Re(s) (u - T))``
summed for all decayed images as one running sum. The chunks are
searched in order of decreasing bound, each as a window of the windowed search (coarse samples,
candidates within the margin, refinement on the closed form, with the same tolerances), and the
search stops when no remaining bound exceeds both peaks found: a skipped chunk cannot hold a value
above them, so the peaks are those of the whole response (to the refinement's 1e-11 relative).
After the last chunk every image decays freely: the closed-form extremes, where their bound can
beat a peak found.

Each image's pulse is read from a table over the pulse only (not over the images' delay spread):
past its end, the image's decay enters the coarse samples as one complex running product for all
images of a chunk. Images whose decay fell below ``exp(-DECAY_CUT)`` of their amplitude before a
chunk are left out of it (below 1e-26 of their amplitude; the arrivals are sorted by delay).
Times in s, pressures in Pa.
"""

from __future__ import annotations

import math

import numpy as np

from ._kernels import _njit
from ._peak_kernels import NEAR, TAIL_STEPS, XTOL, _cubic_start, _decay_extremes
from ._peak_refine import _refine_bracket
from .exposure import _correlation_at, _exposure_sorted

#: Coarse samples per chunk.
CHUNK_STEPS = 16
#: Coarse steps beyond its samples over which a chunk's bound holds: a candidate's bracket reaches
#: ``2 NEAR + 1`` steps from its sample (a breakpoint within ``NEAR + 1`` steps, widened by ``NEAR``).
REACH = int(2 * NEAR) + 2
#: Width in coarse steps of the sliding maximum of ``|Y|`` that bounds one image in one chunk.
BOUND_WIDTH = CHUNK_STEPS + 2 * REACH + 2
#: An image whose free decay has fallen by ``exp(-DECAY_CUT)`` (1e-26) is left out of a chunk.
DECAY_CUT = 60.0
#: Relative allowance of the bounds for round-off (the refined values carry ~1e-11 of the Newton model).
BOUND_SLACK = 1e-9


def envelope(y: np.ndarray, fine: int, pad: int, h: float, slope: float, end: float, big_h: float) -> np.ndarray:
    """Sliding maxima of ``|Yr - Yi|`` and ``|Yi|`` over :data:`BOUND_WIDTH` coarse steps, from a peak table.

    An image's pressure is ``Re[a Y] = P0 [(r/a) (Yr - Yi) + Yi]`` (``a = P0 (r/a - i (1 - r/a))``):
    far from the sphere ``Yr - Yi`` (the far field) is much smaller than ``|Y|``, so the two are
    bounded apart.

    Parameters
    ----------
    y : (fine, ncol) complex ndarray
        ``Y`` in m/s at ``u = (k fine + r - pad) h`` (row ``r``, column ``k``), over the pulse.
    fine, pad : int
        Fine steps per coarse step and fine steps of zeros before ``u = 0``.
    h : float
        Fine step in s.
    slope : float
        ``max |Y'|`` in m/s² (``|(Yr - Yi)'| <= √2 max |Y'|``).
    end : float
        End of the pulse in s.
    big_h : float
        Coarse step in s.

    Returns
    -------
    (2, mend + BOUND_WIDTH - 1) ndarray
        Entry ``[0, q]``: an upper bound of ``|Yr - Yi|`` (m/s) for ``u`` in coarse steps
        ``q - BOUND_WIDTH + 1 .. q`` (step ``m`` is ``[m H, (m + 1) H]``) of the first
        ``mend = ceil(T/H) + 1`` steps; ``[1, q]`` of ``|Yi|``. Beyond them ``Y`` is the free decay.
    """
    flat = y.T.ravel()
    mend = int(math.ceil(end / big_h)) + 1
    w = BOUND_WIDTH
    out = np.empty((2, mend + w - 1))
    seg = flat[pad:pad + (mend + 1) * fine + 1]
    for row, (vals, lip) in enumerate(((seg.real - seg.imag, math.sqrt(2.0) * slope), (seg.imag, slope))):
        a = np.abs(vals)
        per = np.maximum(a[:mend * fine].reshape(mend, fine).max(axis=1), a[fine:(mend + 1) * fine:fine])
        per = per + 0.5 * h * lip  # between fine samples: at most half a step of the slope above them
        for q in range(out.shape[1]):
            out[row, q] = per[max(0, q - w + 1):min(mend, q + 1)].max()
    return out


@_njit(cache=True)
def _chunk_bounds(ds, ar, ai, dmin, big_h, nch, env, yabs, sr, end):  # pragma: no cover - compiled
    """Bound of ``|p|`` over each chunk's span (module notes) from the sorted delays and amplitudes."""
    c_len = CHUNK_STEPS
    w = BOUND_WIDTH
    mend = env.shape[1] - w + 1
    end_steps = REACH + 1 + mend
    ub = np.zeros(nch)
    dec = np.zeros(nch)
    tail = math.sqrt(2.0) * yabs
    for q in range(ds.size):
        kj = int((ds[q] - dmin) / big_h)
        mf = abs(ar[q])  # P0 r/a
        mi = abs(ar[q] - ai[q])  # P0
        c_lo = max(0, -((w - kj - REACH - 2) // c_len))
        c_dec = -((-(kj + end_steps)) // c_len)  # the first chunk after the pulse's steps
        for c in range(c_lo, min(c_dec, nch)):
            e = c * c_len - REACH - 1 - kj + w - 1
            ub[c] += mf * env[0, e] + mi * env[1, e]
        if c_dec < nch:
            dec[c_dec] += (mf * tail + mi * yabs) * math.exp(sr * ((c_dec * c_len - REACH - 1 - kj) * big_h - end))
    run = 0.0
    fall = math.exp(sr * c_len * big_h)
    for c in range(nch):
        run = run * fall + dec[c]
        ub[c] = (ub[c] + run) * (1.0 + BOUND_SLACK)
    return ub


@_njit(cache=True)
def _decay_starts(nq, ar, ai, pad, fine, ncol, zpast, qstep, nch, accs, kstar):  # pragma: no cover - compiled
    """The free decay of the images past the table, summed at the first sample of every chunk.

    Image ``q`` (sorted, ``nq[q]`` fine steps after ``dmin``) leaves the table at coarse sample
    ``kstar[q]`` with value ``a_q Y(u)``, ``u`` depending on its fine residue only (``zpast``);
    from there it decays by ``e^{s H}`` a step. ``accs[c]`` is the sum of every image that left the
    table before chunk ``c``'s first sample ``c C - 2``, at that sample.
    """
    c_len = CHUNK_STEPS
    for q in range(nq.size):
        m = pad - nq[q]
        qs = m // fine
        kstar[q] = ncol - qs
    qpow = np.empty(c_len + 1, np.complex128)
    qpow[0] = 1.0
    for m in range(c_len):
        qpow[m + 1] = qpow[m] * qstep
    qc = qpow[c_len]
    acc = 0j
    ptr = 0
    for c in range(nch):
        k0 = c * c_len - 2
        if c > 0:
            acc *= qc
        while ptr < nq.size and kstar[ptr] < k0:
            m = pad - nq[ptr]
            rs = m - (m // fine) * fine
            acc += complex(ar[ptr], ai[ptr]) * zpast[rs] * qpow[k0 - kstar[ptr]]  # 1 <= k0 - kstar <= C
            ptr += 1
        accs[c] = acc


@_njit(cache=True)
def _chunk_samples(k0, nl, coarse, ev, acc0, j_lo, j_hi, nq, ar, ai, fine, pad, ytr, yti, zpast,
                   qstep):  # pragma: no cover - compiled
    """Coarse samples ``k0 .. k0 + nl - 1`` of ``p``, in ``coarse``.

    The images ``j_lo .. j_hi - 1`` (sorted) read their pulse from the table at their delay rounded
    to the fine step (``nq`` fine steps after ``dmin``); past the table each one's free decay joins
    one running product ``e^{s H}``, started at ``acc0`` (the images decayed before ``k0``).
    """
    ncol = ytr.shape[1]
    for q in range(nl):
        coarse[q] = 0.0
        ev[q] = 0j
    ev[0] = acc0
    for q in range(j_lo, j_hi):
        m = pad - nq[q]
        qs = m // fine
        rs = m - qs * fine
        a_r = ar[q]
        a_i = ai[q]
        l_first = max(0, -qs - k0)
        l_past = ncol - qs - k0  # the first sample after the table
        for ll in range(l_first, min(nl, l_past)):
            col = qs + k0 + ll
            coarse[ll] += a_r * ytr[rs, col] - a_i * yti[rs, col]
        if 0 <= l_past < nl:
            ev[l_past] += complex(a_r, a_i) * zpast[rs]
    acc = 0j
    for ll in range(nl):
        acc = acc * qstep + ev[ll]
        coarse[ll] += acc.real


@_njit(cache=True)
def _chunk_breakpoints(ds, end, lo, hi, bps):  # pragma: no cover - compiled
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


@_njit(cache=True)
def _chunk_search(c, ubc, best_s, tbest_s, ds, nq, ar, ai, cum, dmin, big_h, fine, pad, ytr, yti, slope,  # noqa: C901 - one compiled kernel
                  margin, tp, cusps, s, qstep, zpast, accs, kstar, coarse, ev, cand, done_lo, done_hi,
                  bps):  # pragma: no cover
    """Search chunk ``c`` as a window of the windowed search; updates ``best_s``, ``tbest_s``; returns refinements."""
    end = tp[7]
    yend = complex(tp[8], tp[9])
    h = big_h / fine
    c_len = CHUNK_STEPS
    k0 = c * c_len - 2
    nl = c_len + 5
    t0 = dmin + k0 * big_h
    t_hi = t0 + (nl - 1) * big_h
    cut = DECAY_CUT / -s.real
    j_lo = np.searchsorted(ds, t0 - REACH * big_h - end - cut)
    j_tab = np.searchsorted(kstar, k0)  # the first image still in the table at k0
    j_hi = np.searchsorted(ds, t_hi, side="right")
    j_far = np.searchsorted(ds, t_hi + REACH * big_h, side="right")
    _chunk_samples(k0, nl, coarse, ev, accs[c], j_tab, j_hi, nq, ar, ai, fine, pad, ytr, yti, zpast, qstep)
    scale = cum[j_hi] - cum[j_lo]  # Σ |a_j| of the images sampled: the rounding bound's
    cmax = 0.0
    cmin = 0.0
    jump = 0.0
    for ll in range(nl):
        cmax = max(cmax, coarse[ll])
        cmin = min(cmin, coarse[ll])
        if ll > 0:
            jump = max(jump, abs(coarse[ll] - coarse[ll - 1]))
    vmax = max(cmax, -cmin)
    slack = margin * vmax + 0.5 * h * slope * scale
    if not ((ubc > best_s[0] and cmax + slack >= best_s[0]) or (ubc > best_s[1] and -cmin + slack >= best_s[1])):
        return 0  # no coarse sample comes within the slack of a peak found: no candidate would be refined
    nbp = _chunk_breakpoints(ds, end, t0 - REACH * big_h, t_hi + REACH * big_h, bps)
    bp = bps[:nbp]
    sub_d = ds[j_lo:j_far]
    sub_r = ar[j_lo:j_far]
    sub_i = ai[j_lo:j_far]
    nsub = j_far - j_lo
    xtol = XTOL * big_h
    nref = 0
    for side in range(2):
        sign = 1.0 if side == 0 else -1.0
        best = best_s[side]
        if ubc <= best:
            continue  # nothing here can beat this side's peak
        tbest = tbest_s[side]
        floor = (cmax if side == 0 else -cmin) - 2.0 * slack - 0.125 * jump
        nc = 0
        top = -np.inf
        for ll in range(2, c_len + 2):  # this chunk's own samples; the two either side are neighbours
            v0 = sign * coarse[ll]
            if v0 < floor or v0 <= 0.0:
                continue
            vm = sign * coarse[ll - 1]
            vp = sign * coarse[ll + 1]
            if v0 >= vm and v0 >= vp:
                den = vm - 2.0 * v0 + vp
                xs = 0.5 * (vm - vp) / den if den < 0.0 else 0.0
                est = v0 - 0.25 * (vm - vp) * xs
                cand[0, nc] = est
                cand[1, nc] = t0 + (ll + _cubic_start(coarse, ll, nl - 1, xs)) * big_h
                cand[2, nc] = t0 + ll * big_h
                cand[3, nc] = -1.0
                nc += 1
                top = max(top, est)
        if cusps:  # a feature narrower than H may sit at a breakpoint: its coarse neighbours bound it
            for b in bp:
                k = int(math.floor((b - t0) / big_h))
                if 2 <= k < c_len + 2:
                    est = max(sign * coarse[k], sign * coarse[k + 1])
                    if est > 0.0:
                        cand[0, nc] = est
                        cand[1, nc] = b
                        cand[2, nc] = b
                        cand[3, nc] = k
                        nc += 1
        ndone = 0
        reached = (cmax if side == 0 else -cmin) - 0.5 * h * slope * scale
        while nc > 0:  # best estimate first, while one can still beat the best refined value
            jb = 0
            for q in range(1, nc):
                if cand[0, q] > cand[0, jb]:
                    jb = q
            est = cand[0, jb]
            if est + slack < best or est + slack < top - slack:
                break
            tk = cand[2, jb]
            kb = int(cand[3, jb])
            covered = False
            if kb >= 0:
                ta = t0 + kb * big_h - 1e-9 * big_h
                tz = t0 + (kb + 1) * big_h + 1e-9 * big_h
                for q in range(ndone):
                    if done_lo[q] <= ta and tz <= done_hi[q]:
                        covered = True
                        break
            if not covered:
                lo_b = max(dmin, tk - big_h)
                hi_b = tk + big_h
                if kb >= 0:
                    lo_b = t0 + kb * big_h
                    hi_b = t0 + (kb + 1) * big_h
                else:
                    for b in bp:
                        if abs(b - tk) < (NEAR + 1.0) * big_h:
                            lo_b = max(dmin, min(lo_b, b - NEAR * big_h))
                            hi_b = max(hi_b, b + NEAR * big_h)
                val, tv = _refine_bracket(sign, max(best, reached), cand[1, jb], lo_b, hi_b, bp, xtol, nsub, sub_d,
                                          sub_r, sub_i, tp)
                done_lo[ndone] = lo_b
                done_hi[ndone] = hi_b
                ndone += 1
                nref += 1
                if val > best:
                    best = val
                    tbest = tv
            nc -= 1
            for f in range(4):
                cand[f, jb] = cand[f, nc]
        best_s[side] = best
        tbest_s[side] = tbest
    return nref


@_njit(cache=True)
def _after_last(t_end, best_s, tbest_s, ds, ar, ai, mag, tp):  # pragma: no cover - compiled
    """Extremes of the free decay of every image after ``t_end``, where their bound can beat a peak found."""
    end = tp[7]
    yend = complex(tp[8], tp[9])
    s = complex(tp[10], tp[11])
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
    bound = (bound + rest * yabs * math.exp(-DECAY_CUT)) * (1.0 + BOUND_SLACK)
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


@_njit(cache=True)
def _bound_kernel(res, pts, spos, saxis, centre, ppt, pnm, radius, rho, c, big_h, fine, pad, ytr, yti, slope,  # noqa: C901 - one compiled kernel
                  margin, tp, do_exp, cusps, env, ctau, cs, cstep, ctable, cyend, m_g, m_h):  # pragma: no cover
    """:func:`acoustiviz.field._peak_kernels._peaks_kernel` by bounded chunks (module notes); same columns."""
    end = tp[7]
    yend = complex(tp[8], tp[9])
    s = complex(tp[10], tp[11])
    yabs = abs(yend)
    qstep = np.exp(s * big_h)
    n = pts.shape[0]
    nimg = spos.shape[0]
    h = big_h / fine
    delays = np.empty(nimg)
    are = np.empty(nimg)
    aim = np.empty(nimg)
    ds = np.empty(nimg)
    ar = np.empty(nimg)
    ai = np.empty(nimg)
    mag = np.empty(nimg)
    cum = np.empty(nimg + 1)
    nq = np.empty(nimg, np.int64)
    nl = CHUNK_STEPS + 5
    coarse = np.empty(nl)
    ev = np.empty(nl, np.complex128)
    cand = np.empty((4, CHUNK_STEPS + 2 * nimg + 2))
    done_lo = np.empty(CHUNK_STEPS + 2 * nimg + 2)
    done_hi = np.empty(CHUNK_STEPS + 2 * nimg + 2)
    kstar = np.empty(nimg, np.int64)
    # Y just past the table, by fine residue: where each image's decay starts
    zpast = np.empty(fine, np.complex128)
    ncol = ytr.shape[1]
    for r in range(fine):
        zpast[r] = yend * np.exp(s * ((ncol * fine + r - pad) * h - end))
    bps = np.empty(2 * nimg + 2)
    best_s = np.empty(2)
    tbest_s = np.empty(2)
    tol = 1e-12 * radius
    g0 = 0j
    h0 = 0j
    if do_exp:
        g0, h0 = _correlation_at(0.0, ctau, cs, cstep, ctable, cyend, m_g, m_h)
    for i in range(n):
        x0 = pts[i, 0]
        x1 = pts[i, 1]
        x2 = pts[i, 2]
        dc = math.sqrt((x0 - centre[0]) ** 2 + (x1 - centre[1]) ** 2 + (x2 - centre[2]) ** 2)
        ok = dc >= radius - tol
        for q in range(ppt.shape[0]):
            if (x0 - ppt[q, 0]) * pnm[q, 0] + (x1 - ppt[q, 1]) * pnm[q, 1] + (x2 - ppt[q, 2]) * pnm[q, 2] < -tol:
                ok = False
        if not ok:
            for col in range(5):
                res[i, col] = np.nan
            res[i, 5] = 0.0
            continue
        for j in range(nimg):
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
        order = np.argsort(delays)
        if do_exp:
            res[i, 4] = _exposure_sorted(order, delays, are, aim, ctau, cs, cstep, ctable, cyend, m_g, m_h, g0, h0)
        else:
            res[i, 4] = np.nan
        for q in range(nimg):
            j = order[q]
            ds[q] = delays[j]
            ar[q] = are[j]
            ai[q] = aim[j]
            mag[q] = math.sqrt(are[j] ** 2 + aim[j] ** 2)
        dmin = ds[0]
        cum[0] = 0.0
        for q in range(nimg):
            cum[q + 1] = cum[q] + mag[q]
        for q in range(nimg):
            nq[q] = int(round((ds[q] - dmin) / h))
        kmax = int(math.ceil((ds[nimg - 1] - dmin + end) / big_h)) + 1 + TAIL_STEPS
        nch = kmax // CHUNK_STEPS + 1
        ub = _chunk_bounds(ds, ar, ai, dmin, big_h, nch, env, yabs, s.real, end)
        accs = np.empty(nch, np.complex128)
        _decay_starts(nq, ar, ai, pad, fine, ncol, zpast, qstep, nch, accs, kstar)
        best_s[0] = best_s[1] = 0.0  # p = 0 before the first arrival
        tbest_s[0] = tbest_s[1] = dmin
        # the chunk of the largest bound first (it sets the peaks to beat), then the others by bound
        first = np.argmax(ub)
        nref = _chunk_search(first, ub[first], best_s, tbest_s, ds, nq, ar, ai, cum, dmin, big_h, fine, pad, ytr,
                             yti, slope, margin, tp, cusps, s, qstep, zpast, accs, kstar, coarse, ev, cand, done_lo, done_hi, bps)
        ub[first] = 0.0
        floor = min(best_s[0], best_s[1])
        m = 0
        for cc in range(nch):
            if ub[cc] > floor:
                m += 1
        if m > 0:
            left = np.empty(m, np.int64)
            m = 0
            for cc in range(nch):
                if ub[cc] > floor:
                    left[m] = cc
                    m += 1
            rank = np.argsort(-ub[left])
            for q in range(m):
                cc = left[rank[q]]
                if ub[cc] <= min(best_s[0], best_s[1]):
                    break
                nref += _chunk_search(cc, ub[cc], best_s, tbest_s, ds, nq, ar, ai, cum, dmin, big_h, fine, pad, ytr,
                                      yti, slope, margin, tp, cusps, s, qstep, zpast, accs, kstar, coarse, ev, cand, done_lo, done_hi, bps)
        _after_last(dmin + (nch * CHUNK_STEPS - 1) * big_h, best_s, tbest_s, ds, ar, ai, mag, tp)
        for side in range(2):
            res[i, side] = (1.0 if side == 0 else -1.0) * best_s[side]
            res[i, 2 + side] = tbest_s[side]
        res[i, 5] = nref
