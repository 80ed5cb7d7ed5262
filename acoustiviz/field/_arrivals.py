"""The image sources seen from one point, sorted by arrival: a bucket sort of the delays.

A room's images seen from a point arrive over ``[d_min, d_max]`` (about 0.2 s at order 10 in a
6 x 4 x 3 m room); their delays are spread by :func:`_arrival_order` into as many equal buckets
as there are images (a counting pass and a prefix sum) and each bucket's few delays are put in
order by insertion. The result is the order of a stable sort (equal delays keep their image
order); the cost is ``O(n + Σ b²)`` for buckets of ``b`` delays instead of a comparison sort's
``O(n log n)``, with no recursion. The images' density of arrivals grows as ``t²``, so the late
buckets hold a few delays each and the early ones none or one.
"""

from __future__ import annotations

import numpy as np

from .._jit import njit as _njit


@_njit(inline="always")
def _arrival_order(delays, count, key, order):  # pragma: no cover - compiled
    """Indices of ``delays`` in ascending order (stable) into ``order``.

    ``count`` (at least ``n + 1`` integers) and ``key`` (``n``) are work space.
    """
    n = delays.size
    dmin = delays[0]
    dmax = delays[0]
    for j in range(1, n):
        d = delays[j]
        if d < dmin:
            dmin = d
        if d > dmax:
            dmax = d
    for b in range(n + 1):
        count[b] = 0
    scale = 0.0
    if dmax > dmin:
        scale = n / (dmax - dmin)
    for j in range(n):  # bucket b holds the delays in [dmin + b w, dmin + (b + 1) w), w = (dmax - dmin)/n
        b = min(int((delays[j] - dmin) * scale), n - 1)
        key[j] = b
        count[b + 1] += 1
    for b in range(n):
        count[b + 1] += count[b]
    for j in range(n):  # by bucket, in image order within each bucket
        b = key[j]
        order[count[b]] = j
        count[b] += 1
    for q in range(1, n):  # insertion within the buckets (a delay never moves past its bucket)
        oj = order[q]
        d = delays[oj]
        p = q - 1
        while p >= 0 and delays[order[p]] > d:
            order[p + 1] = order[p]
            p -= 1
        order[p + 1] = oj


def arrival_order(delays: np.ndarray) -> np.ndarray:
    """Indices that sort ``delays`` (s) ascending, equal delays in their given order (as a stable argsort)."""
    d = np.ascontiguousarray(delays, dtype=float)
    n = d.size
    order = np.empty(n, np.int64)
    if n:
        _arrival_order(d, np.empty(n + 1, np.int64), np.empty(n, np.int64), order)
    return order
