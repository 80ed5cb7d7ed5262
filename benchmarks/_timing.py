"""Timing helper shared by the benchmark scripts (run them from anywhere: ``python benchmarks/bench_*.py``)."""

from __future__ import annotations

import math
import time


def best_of(f, repeat: int):
    """Call ``f`` ``repeat`` times; return (the shortest wall time in s, the last result)."""
    best, out = math.inf, None
    for _ in range(max(1, int(repeat))):
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
    return best, out
