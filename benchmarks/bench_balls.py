"""Cost of the multi-ball damper solver (:func:`acoustiviz.dynamics.simulate_balls`).

Three tables, in CPU seconds of this process (``time.process_time``: the compiled kernel runs in it;
CPU time, unlike wall time, does not grow with the load of a shared machine), after one warm-up run
that compiles the kernel or loads it from numba's cache:

1. the column the brief asks for: 50 equal steel balls of the Table 1 impact mass in the Table 1
   damper (gap 4 cm, Figure 5 start), 20 s of motion;
2. side by side with an independent SciPy reference (``solve_ivp(method="DOP853")`` with an event on
   every pair, the equations written out again in ``_balls_reference.py``, tolerance 1e-13) over the
   first 20 collisions of 2, 3 and 5 balls, with the largest difference of their collision times;
3. cost against the number of collisions: 10 balls over longer and longer runs, and 2 to 50 balls over
   20 s (the cost per collision, and per collision and body).

Usage::

    python benchmarks/bench_balls.py            # writes benchmarks/results/balls.md
    python benchmarks/bench_balls.py --quick    # tables 2 and 3 on shorter runs, nothing written
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from _balls_reference import scipy_collisions
from _timing import results_header

from acoustiviz.dynamics import DamperModel, MultiBallModel, simulate_balls

RESULTS = Path(__file__).resolve().parent / "results" / "balls.md"
#: Heading of the hand-written reading of the tables, kept when the tables are written again.
READING = "## Reading"


def cpu(fn, *args, **kw):
    """``(result, CPU seconds)`` of one call."""
    t0 = time.process_time()
    out = fn(*args, **kw)
    return out, time.process_time() - t0


def column(n: int) -> MultiBallModel:
    """``n`` steel balls of the Table 1 impact mass in the Table 1 damper (gap 4 cm)."""
    return MultiBallModel.from_damper(DamperModel(), n)


def table_column(duration: float) -> list:
    r, s = cpu(simulate_balls, column(50), duration)
    return ["| balls | simulated s | collisions | CPU s | CPU ms per collision | energy closure |",
            "|---:|---:|---:|---:|---:|---:|",
            f"| 50 | {duration:g} | {len(r.impacts)} | {s:.2f} | {1e3 * s / max(len(r.impacts), 1):.3f} | "
            f"{r.energy.relative_closure_error:.1e} |"]


def table_scipy() -> list:
    rows = ["| balls | collisions | simulated s | SciPy CPU s | acoustiviz CPU s | ratio | max time difference s |",
            "|---:|---:|---:|---:|---:|---:|---:|"]
    for n in (2, 3, 5):
        model = column(n)
        ref, s_ref = cpu(scipy_collisions, model, 20)
        duration = ref[-1][0] + 1e-4
        reps = 20  # the compiled run is short: the mean of several
        t0 = time.process_time()
        for _ in range(reps):
            got = simulate_balls(model, duration)
        s_got = (time.process_time() - t0) / reps
        diff = np.max(np.abs(got.impacts.time[:20] - np.array([t for t, _ in ref])))
        rows.append(f"| {n} | {len(ref)} | {duration:.4f} | {s_ref:.2f} | {s_got:.2e} | {s_ref / s_got:.0f} | "
                    f"{diff:.1e} |")
    return rows


def table_linear(durations, counts, long: float) -> list:
    rows = ["| balls | simulated s | collisions | CPU s | CPU us per collision | CPU us per collision and body |",
            "|---:|---:|---:|---:|---:|---:|"]
    cases = [(10, d) for d in durations] + [(n, long) for n in counts if n != 10]
    for n, d in cases:
        r, s = cpu(simulate_balls, column(n), d)
        k = max(len(r.impacts), 1)
        rows.append(f"| {n} | {d:g} | {len(r.impacts)} | {s:.3f} | {1e6 * s / k:.1f} | {1e6 * s / k / (n + 1):.2f} |")
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter runs, nothing written")
    args = ap.parse_args(argv)
    simulate_balls(column(2), 0.05)  # compile or load the kernel
    parts = []
    if not args.quick:
        parts += ["## 50 balls, 20 s of the Table 1 damper", "", *table_column(20.0), ""]
    parts += ["## Against the SciPy reference (first 20 collisions)", "", *table_scipy(), ""]
    if args.quick:
        parts += ["## Cost against collisions", "", *table_linear((0.5, 1.0, 2.0), (2, 5), 2.0), ""]
    else:
        parts += ["## Cost against collisions", "", *table_linear((2.0, 5.0, 10.0, 20.0), (2, 5, 20, 50), 20.0), ""]
    text = "\n".join(parts)
    print(text)
    if not args.quick:
        old = RESULTS.read_text(encoding="utf-8") if RESULTS.exists() else ""
        reading = old[old.index(READING):] if READING in old else ""  # the hand-written reading is kept
        head = (f"# Multi-ball damper solver\n\n{results_header('python benchmarks/bench_balls.py')}\n\n"
                "CPU seconds of this process (numba kernel warm), from one run.\n\n")
        RESULTS.write_text(head + text + ("\n" + reading if reading else ""), encoding="utf-8")
        print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
