"""Weighted levels of a train of short sounds in a long silence, without filtering the silence.

A damper run heard at a listener is a few hundred clicks of a few milliseconds each in 20 s: at
96 kHz some 10^5 samples of sound among 1.9 x 10^6. :func:`train_levels` gives the levels
:func:`~acoustiviz.levels.sound_levels` computes on the whole signal from the sound alone. The
signal is cut into blocks of ``B`` samples; only the blocks that hold sound are filtered, all at
once, from rest. The IEC 61672-1 weightings are linear with state ``s`` (the library's second-order
sections, :func:`.transient._system`: under zero input the output is ``c s`` and the next state
``Φ s``), so each block's true output is its output from rest plus the free response ``c Φ^n s_b``
of the state ``s_b`` it starts from, and the states follow

``s_{b+1} = Φ^{g_b} (Φ^B s_b + z_b)``

with ``z_b`` the block's final state from rest and ``g_b`` the silent samples before the next
block. Over a silence of ``g`` samples from state ``x`` the weighted signal is the free response,
whose energy is ``xᵀ G_g x`` (``G_g = Σ_{j<g} (Φ^j)ᵀ cᵀ c Φ^j``) and whose contribution to the
time-weighted square ``v[n] = β v[n-1] + α y[n]²`` (``β = 1 - α``) at its end is ``α xᵀ W_g x``
(``W_g = Σ_{j<g} β^{g-1-j} (Φ^j)ᵀ cᵀ c Φ^j``). ``Φ^g``, ``G_g`` and ``W_g`` come from tables of
powers of two built once per rate, weighting and time weighting (``G_{2a} = G_a + (Φ^a)ᵀ G_a Φ^a``,
``W_{2a} = β^a W_a + (Φ^a)ᵀ W_a Φ^a``) and walked bit by bit over every silence at once. So:

* exposure and equivalent levels (``sel``, ``sel-a``, ``lzeq``, ``laeq``) are exact: the energy of
  the blocks plus that of every silence;
* peaks (``lzpeak``; ``lcpeak``: in a silence ``|y| <= sqrt(xᵀ G_g x)``) and time-weighted maxima
  (``lafmax``, ``lasmax``: in a silence ``v <= v_0 + α xᵀ G_g x``) are exact once every silence's
  bound is below the maximum found (time-weighted: within :data:`~.transient.MAX_RELATIVE_GAP`);
  where one is not, the blocks after that sound are filtered too (1, 2, 4, ... of them) until it is.

Everything equals the levels of the whole signal up to round-off (1e-12 relative). Where the
library's weighting is not a cascade of sections at the rate (below 96 kHz), or the windows hold
more samples than the signal, the levels are those of :func:`~acoustiviz.levels.sound_levels` on the
whole signal (:func:`train_signal`).
"""

from __future__ import annotations

import functools

import numpy as np

from .._validate import ParameterError
from ..core.signal import Signal
from .transient import MAX_RELATIVE_GAP, _alpha, _system
from .weighted import METRICS, SoundLevels, _integer_rate, check_signal, level_db, sound_levels

__all__ = ["train_levels", "train_signal", "signal_levels", "MIN_BLOCK", "SPARSE_ABOVE"]

#: Largest fraction of samples holding sound for which :func:`signal_levels` works on the sound alone.
SPARSE_ABOVE = 0.25

#: Shortest block in samples (a window shorter than this is filtered in blocks of this length).
MIN_BLOCK = 256

_TIME_MODES = {"lafmax": "fast", "lasmax": "slow"}

#: Entries of the transition tables (dimensionless) and of the filter states (relative to the
#: train's largest sample) below this are set to zero: a silence of ``g`` samples decays a state
#: geometrically, and products of such numbers reach the subnormal range, where every operation on
#: them costs 20-100 times more on x86 processors. The levels move by less than 1e-100 relative.
FLUSH = 1e-100


@functools.lru_cache(maxsize=32)
def _tables(fs: int, curve: str, modes: tuple, nbits: int):
    """``Φ^{2^k}``, ``G_{2^k}`` and, per time weighting, ``W_{2^k}`` and ``β^{2^k}`` for ``k < nbits``."""
    _, phi, c = _system(fs, curve)
    cc = np.outer(c, c)
    p, g = [phi], [cc]
    betas = {m: 1.0 - _alpha(fs, m) for m in modes}
    w = {m: [cc] for m in modes}
    bpow = {m: [betas[m]] for m in modes}
    for _ in range(1, nbits):
        pk = p[-1]
        g.append(g[-1] + pk.T @ g[-1] @ pk)
        for m in modes:
            w[m].append(bpow[m][-1] * w[m][-1] + pk.T @ w[m][-1] @ pk)
            bpow[m].append(bpow[m][-1] ** 2)
        p.append(pk @ pk)
    sym = lambda a: _flush(0.5 * (a + np.swapaxes(a, 1, 2)))  # noqa: E731 - the Gramians are symmetric
    return (_flush(np.array(p)), sym(np.array(g)), {m: sym(np.array(w[m])) for m in modes},
            {m: _flush(np.array(bpow[m])) for m in modes})


def _flush(a: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """``a`` with entries below :data:`FLUSH` ``x scale`` set to zero (no subnormal numbers downstream)."""
    a[np.abs(a) < FLUSH * scale] = 0.0
    return a


@functools.lru_cache(maxsize=32)
def _free_rows(fs: int, curve: str, length: int) -> np.ndarray:
    """``(d, length)``: column ``n`` is ``c Φ^n``, the output ``n`` samples on from each basis state."""
    from scipy.signal import sosfilt

    sos = _system(fs, curve)[0]
    n_sec = sos.shape[0]
    d = 2 * n_sec
    zi = np.eye(d).reshape(d, n_sec, 2).transpose(1, 0, 2)
    y, _ = sosfilt(sos, np.zeros((d, length)), axis=-1, zi=zi)
    return y


def _rows(x: np.ndarray, m: np.ndarray) -> np.ndarray:
    """``x_k m`` for every row ``x_k`` of ``x`` (a stack of small products: no multi-threaded BLAS call)."""
    return (x[:, None, :] @ m[None])[:, 0]


def _powers(p: np.ndarray, gaps: np.ndarray) -> np.ndarray:
    """``Φ^g`` for every ``g`` of ``gaps`` from the table ``p[k] = Φ^{2^k}``, ``(len(gaps), d, d)``."""
    d = p.shape[1]
    out = np.broadcast_to(np.eye(d), (gaps.size, d, d)).copy()
    for k in range(p.shape[0]):
        sel = np.flatnonzero((gaps >> k) & 1)
        if sel.size:
            out[sel] = p[k] @ out[sel]
    return out


def _affine_scan(a: np.ndarray, u: np.ndarray, scale: float) -> np.ndarray:
    """``x_{k+1} = a_k x_k + u_k`` from ``x_0 = 0``: ``(x_1, ..., x_n)`` by prefix doubling (log2 n batched steps)."""
    a, u = a.copy(), u.copy()
    shift = 1
    while shift < a.shape[0]:  # after the step, (a_k, u_k) maps x_{k+1-2 shift} to x_{k+1}
        u[shift:] = _flush((a[shift:] @ u[:-shift, :, None])[:, :, 0] + u[shift:], scale)
        a[shift:] = _flush(a[shift:] @ a[:-shift])
        shift *= 2
    return u


def _silences(tables, x: np.ndarray, gaps: np.ndarray):
    """Energy ``xᵀ G_g x`` and per time weighting ``xᵀ W_g x`` of the free response from each ``x`` over its ``g``."""
    p, g, w, bpow = tables
    x = x.copy()
    energy = np.zeros(gaps.size)
    disc = {m: np.zeros(gaps.size) for m in w}
    for k in range(p.shape[0]):
        sel = np.flatnonzero((gaps >> k) & 1)
        if not sel.size:
            continue
        xs = x[sel]
        energy[sel] += np.sum(_rows(xs, g[k]) * xs, axis=1)
        for m in w:
            disc[m][sel] = bpow[m][k] * disc[m][sel] + np.sum(_rows(xs, w[m][k]) * xs, axis=1)
        x[sel] = _rows(xs, p[k].T)
    return np.maximum(energy, 0.0), {m: np.maximum(v, 0.0) for m, v in disc.items()}


def _weighted_blocks(fs: int, curve: str, xb: np.ndarray, gaps: np.ndarray, modes: tuple, nbits: int):
    """The weighted blocks (true outputs), and the energy and discounted energies of the silence after each."""
    from scipy.signal import sosfilt

    sos = _system(fs, curve)[0]
    nb, blk = xb.shape
    d = 2 * sos.shape[0]
    y0, zf = sosfilt(sos, xb, axis=-1, zi=np.zeros((sos.shape[0], nb, 2)))
    z = zf.transpose(1, 0, 2).reshape(nb, d)
    tables = _tables(fs, curve, modes, nbits)
    pb = _powers(tables[0], np.array([blk]))[0]
    m = _powers(tables[0], gaps[:-1])  # across each silence between blocks
    scale = float(np.max(np.abs(xb))) if xb.size else 0.0
    s = np.zeros((nb, d))
    s[1:] = _affine_scan(_flush(m @ pb), _flush((m @ z[:-1, :, None])[:, :, 0], scale), scale)
    y = y0 + _rows(s, _free_rows(fs, curve, blk))
    energy, disc = _silences(tables, _rows(s, pb.T) + z, gaps)
    return y, energy, disc


def train_signal(starts, windows, n_samples: int) -> np.ndarray:
    """The whole signal of a train: ``p[n] = Σ_k windows[k, n - starts[k]]`` for ``0 <= n < n_samples``.

    Parameters
    ----------
    starts : (k,) array_like of int
        First sample of each window (samples before 0 or from ``n_samples`` on are not part of the signal).
    windows : (k, N) array_like
        The sounds in Pa.
    n_samples : int
        Length of the signal in samples.

    Returns
    -------
    (n_samples,) ndarray
    """
    st, win = _check_train(starts, windows)
    n = int(n_samples)
    idx = st[:, None] + np.arange(win.shape[1])[None, :]
    ok = (idx >= 0) & (idx < n)
    return np.bincount(idx[ok], weights=win[ok], minlength=n)[:n]


def _check_train(starts, windows):
    win = np.asarray(windows, dtype=float)
    if win.ndim != 2 or win.shape[1] < 1:
        raise ParameterError("windows", f"expected (n_windows, n) samples in Pa, got shape {win.shape}")
    if not np.all(np.isfinite(win)):
        raise ParameterError("windows", "pressure samples must be finite")
    st = np.asarray(starts)
    if st.shape != (win.shape[0],) or (st.size and not np.all(st == np.round(st))):
        raise ParameterError("starts", f"expected {win.shape[0]} whole sample indices, got {st!r}")
    return st.astype(np.int64), win


def train_levels(starts, windows, sample_rate: float, n_samples: int, metrics, *, first_sample: int = 0) -> dict:
    """Levels over ``[first_sample, n_samples)`` of a train of windows in silence, as :func:`sound_levels` gives them.

    Parameters
    ----------
    starts : (k,) array_like of int
        First sample of each window; windows may overlap, samples outside ``[0, n_samples)`` are
        not part of the signal (:func:`train_signal`).
    windows : (k, N) array_like
        The sounds in Pa.
    sample_rate : float
        Sample rate in Hz (whole Hz).
    n_samples : int
        Length of the signal in samples (>= 2): the interval is ``n_samples / sample_rate`` s from sample 0.
    metrics : sequence of str
        Keys of :data:`METRICS`.
    first_sample : int
        First sample of the interval, ``0 <= first_sample <= n_samples - 2``: the filters run from
        sample 0 (the sound before it is heard through their memory), the peaks, maxima and
        energies are taken from it on (``sound_levels(Signal(...), start=first_sample / sample_rate)``).

    Returns
    -------
    dict
        Metric -> level in dB re 20 µPa (exposure levels re (20 µPa)²·s), a float: equal to
        ``getattr(sound_levels(Signal(train_signal(...), sample_rate)), METRICS[metric])[0]`` up to round-off
        (time-weighted maxima: within :data:`~.transient.MAX_RELATIVE_GAP`); ``-inf`` for silence.

    Examples
    --------
    >>> fs = 96000
    >>> click = np.sin(np.pi * np.arange(48) / 48) ** 2
    >>> starts, windows = [1000, 50000, 50030], np.stack([click, -click, 0.5 * click])
    >>> fast = train_levels(starts, windows, fs, fs, ["laeq", "lcpeak", "lafmax"])
    >>> full = sound_levels(Signal(train_signal(starts, windows, fs), fs))
    >>> [bool(abs(fast[m] - getattr(full, METRICS[m])[0]) < 1e-6) for m in ("laeq", "lcpeak", "lafmax")]
    [True, True, True]
    """
    st, win = _check_train(starts, windows)
    fs = _integer_rate(sample_rate)
    n = int(n_samples)
    if n != n_samples or n < 2:
        raise ParameterError("n_samples", f"must be a whole number of samples >= 2, got {n_samples!r}")
    first = int(first_sample)
    if first != first_sample or not 0 <= first <= n - 2:
        raise ParameterError("first_sample", f"must be a whole sample in [0, {n - 2}], got {first_sample!r}")
    names = list(metrics)
    for m in names:
        if m not in METRICS:
            raise ParameterError("metrics", f"each must be one of {', '.join(METRICS)}, got {m!r}")
    modes = tuple(sorted({_TIME_MODES[m] for m in names if m in _TIME_MODES}))
    curves = ({"A"} if {"lafmax", "lasmax", "laeq", "sel-a"} & set(names) else set()) | \
        ({"C"} if "lcpeak" in names else set())
    dense = any(_system(fs, c) is None for c in curves) or any(_alpha(fs, m) is None for m in modes)
    if dense or win.size >= n:  # below 96 kHz, or more window samples than signal: filter the signal
        full = sound_levels(Signal(train_signal(st, win, n), fs), start=first / fs)
        return {m: float(getattr(full, METRICS[m])[0]) for m in names}
    keep = (st + win.shape[1] > 0) & (st < n)  # windows with a sample in [0, n)
    st, win = st[keep], win[keep]
    blk = max(win.shape[1], MIN_BLOCK)
    extra = np.array([first] if first else [], dtype=np.int64)  # a block starts at the interval, or holds it
    reach = 1
    while True:
        starts, xb = _blocks(np.r_[st, extra], np.r_[win, np.zeros((extra.size, win.shape[1]))], n, blk)
        out, flagged = _levels_of_blocks(xb, starts, fs, n, names, curves, modes, first)
        if not flagged.size:
            return out
        ends = starts[flagged] + blk
        extra = np.union1d(extra, (ends[:, None] + blk * np.arange(reach)[None, :]).ravel())
        extra = extra[extra < n]
        reach *= 2


def signal_levels(signal: Signal, *, start=None, stop=None) -> SoundLevels:
    """:func:`~acoustiviz.levels.sound_levels` of signals that are mostly exact silence, from their sound alone.

    A damper run rendered at 96 kHz is a few hundred clicks among two million zero samples. Each
    channel's samples up to ``stop`` are cut into windows of :data:`MIN_BLOCK` samples, those
    holding a nonzero sample are kept, and :func:`train_levels` gives the levels of the train they
    make (the filters' states carried across the silences in closed form). The filters are causal
    and start from rest at sample 0, so the levels over ``[start, stop)`` do not depend on the
    samples after ``stop``. Where the rate is below 96 kHz or more than :data:`SPARSE_ABOVE` of a
    channel's samples are nonzero, the levels are those of :func:`~acoustiviz.levels.sound_levels`
    on the whole signal.

    Parameters
    ----------
    signal : Signal
        Sound pressure in Pa, one or more channels, at a whole number of Hz.
    start, stop : float, optional
        The interval in s on the signal's time axis, as for :func:`~acoustiviz.levels.sound_levels`.

    Returns
    -------
    SoundLevels
        Equal to ``sound_levels(signal, start=start, stop=stop)`` up to round-off
        (time-weighted maxima: within :data:`~.transient.MAX_RELATIVE_GAP`, 4.3e-6 dB).
    """
    from ._library import library

    p = check_signal(signal).as_channels()
    fs = _integer_rate(signal.sample_rate)
    win = signal.interval(start, stop)
    n = win.stop
    blk = MIN_BLOCK
    held = [np.unique(np.flatnonzero(row[:n]) // blk) for row in p]
    if _system(fs, "A") is None or _system(fs, "C") is None \
            or any(h.size * blk > SPARSE_ABOVE * n for h in held):
        return sound_levels(signal, start=start, stop=stop)
    padded = np.concatenate([p[:, :n], np.zeros((p.shape[0], blk))], axis=1)
    names = list(METRICS)
    rows = []
    for row, h in zip(padded, held, strict=True):
        starts = h * blk
        rows.append(train_levels(starts, row[starts[:, None] + np.arange(blk)[None, :]], fs, n, names,
                                 first_sample=win.start)
                    if h.size else dict.fromkeys(names, -np.inf))
    cols = {METRICS[m]: np.array([r[m] for r in rows]) for m in names}
    return SoundLevels(**cols, sample_rate=float(fs), start=signal.start + win.start / fs, stop=signal.start + n / fs,
                       library=library().name)


def _blocks(st, win, n, blk):
    """Blocks of ``blk`` samples that hold every window: their first samples and ``(n_blocks, blk)`` samples.

    A block starts at the first window not already held by the previous blocks, and a window
    reaching past its block brings in the next blocks, so each window lies in consecutive blocks.
    Blocks from ``n`` on are left out.
    """
    width = win.shape[1]
    first = np.maximum(st, 0)  # a window before sample 0 loses its head
    order = np.argsort(first, kind="stable")
    chains, begin, end = [], None, None
    for s0, s1 in zip(first[order].tolist(), (st[order] + width).tolist(), strict=True):
        if begin is not None and s0 < end:
            if s1 > end:
                end += blk * -(-(s1 - end) // blk)
            continue
        if begin is not None:
            chains.append((begin, end))
        begin, end = s0, s0 + blk * -(-(s1 - s0) // blk)
    if begin is None:
        return np.zeros(0, dtype=np.int64), np.zeros((0, blk))
    chains.append((begin, end))
    c0 = np.array([c[0] for c in chains])
    c1 = np.minimum(np.array([c[1] for c in chains]), c0 + blk * -(-(n - c0) // blk))  # no block from n on
    offset = np.r_[0, np.cumsum(c1 - c0)]
    flat = np.zeros(int(offset[-1]) + width)
    chain = np.searchsorted(c0, first, side="right") - 1
    base = offset[chain] + first - c0[chain]
    for k in range(st.size):
        cut = int(first[k] - st[k])
        flat[base[k]:base[k] + width - cut] += win[k, cut:]
    starts = np.concatenate([np.arange(a, b, blk) for a, b in zip(c0.tolist(), c1.tolist(), strict=True)])
    return starts, flat[:starts.size * blk].reshape(starts.size, blk)


def _levels_of_blocks(xb, starts, fs, n, names, curves, modes, first=0):
    """The levels from the blocks (and the silences between), and the blocks whose silence bound fails."""
    if starts.size == 0:
        return {m: -np.inf for m in names}, np.zeros(0, dtype=np.int64)
    nb, blk = xb.shape
    idx = starts[:, None] + np.arange(blk)[None, :]
    inside = ((idx >= first) & (idx < n)).reshape(-1)  # the blocks' samples in [first, n)
    gaps = np.maximum(np.r_[starts[1:], n] - (starts + blk), 0)
    # the silence after each block, from the interval on (a block starts at first or holds it)
    gaps_in = np.where(starts + blk >= first, gaps, 0)
    nbits = max(1, int(n).bit_length())
    seconds = (n - first) / fs
    out, bad = {}, np.zeros(nb, dtype=bool)
    weighted = {c: _weighted_blocks(fs, c, xb, gaps, modes if c == "A" else (), nbits) for c in curves}
    for m in names:
        if m == "lzpeak":
            out[m] = float(level_db(np.max(np.abs(xb.reshape(-1)[inside])) ** 2))
        elif m in ("sel", "lzeq"):
            x = xb.reshape(-1)[inside]
            e = float(np.einsum("i,i->", x, x)) / fs
            out[m] = float(level_db(e if m == "sel" else e / seconds))
        elif m in ("sel-a", "laeq"):
            y, energy, _ = weighted["A"]
            y = y.reshape(-1)[inside]
            e = (float(np.einsum("i,i->", y, y)) + float(np.sum(energy[gaps_in > 0]))) / fs
            out[m] = float(level_db(e if m == "sel-a" else e / seconds))
        elif m == "lcpeak":
            y, energy, _ = weighted["C"]
            top = float(np.max(np.abs(y.reshape(-1)[inside])))
            bad |= (gaps_in > 0) & (energy > top * top)
            out[m] = float(level_db(top * top))
        else:
            mode = _TIME_MODES[m]
            top, v_end = _time_weighted(fs, mode, weighted["A"], gaps, inside)
            bad |= (gaps_in > 0) & (v_end + _alpha(fs, mode) * weighted["A"][1] > top * (1.0 + MAX_RELATIVE_GAP))
            out[m] = float(level_db(top))
    return out, np.flatnonzero(bad)


def _time_weighted(fs, mode, weighted_a, gaps, inside):
    """Largest ``mode``-time-weighted mean square (Pa²) over the blocks' samples ``inside``, and each block's last."""
    from scipy.signal import lfilter

    y, _, disc = weighted_a
    a = _alpha(fs, mode)
    beta = 1.0 - a
    nb, blk = y.shape
    v0 = lfilter([a], [1.0, -beta], y * y, axis=-1)  # from rest in each block
    decay = beta ** np.arange(1, blk + 1)
    across = beta ** gaps.astype(float)
    # v entering block b+1: the previous block's end decayed across the silence, plus the silence's own
    v_in = _affine_scan((across[:-1] * decay[-1])[:, None, None],
                        (across[:-1] * v0[:-1, -1] + a * disc[mode][:-1])[:, None], 0.0)[:, 0]
    v = v0 + np.r_[0.0, v_in][:, None] * decay[None, :]
    return float(np.max(v.reshape(-1)[inside])), v[:, -1]
