"""Evaluations per second of ``acoustiviz optimize`` on 1 and 2 workers of the local process pool.

The problem is the one of ``benchmarks/bench_optimisers.py`` (the quietest design with the damping
inclination in 0.004..0.006 m/s over gap and impact mass) with 5 s of motion per design, 64
evaluations in batches of 8 (``--quick``: 1 s and 32 evaluations). Each run starts in a fresh
temporary folder (nothing resumed); the pool's start-up and the kernels' warm-up are inside the
time. Printed side by side: wall time, evaluations per second, the time spent asking the optimiser
(in this process, between batches), and the speed-up of 2 workers over 1. The designs are the same
on both (the result does not depend on the workers), which the table also checks.

Run ``python benchmarks/bench_optimize.py`` (``--write`` keeps the table in
``benchmarks/results/bench_optimize.txt``).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time

from _timing import run_writing


def _problem(evaluations: int):
    from acoustiviz.sweep.modes import FreeVibration
    from acoustiviz.sweep.problem import Objective, Problem, parse_constraint, parse_variable

    return Problem((parse_variable("gap", "0.01:0.06"), parse_variable("m", "0.01:0.08")),
                   (Objective("max_spl_db", "min"),),
                   (parse_constraint("c", "inclination_two_maxima_m_s>=0.004"),
                    parse_constraint("c", "inclination_two_maxima_m_s<=0.006")),
                   evaluations=evaluations, seed=0, batch=8, columns=FreeVibration.objective_columns)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1 s of motion and 32 evaluations")
    args = parser.parse_args(argv)
    import acoustiviz.sweep.optimise as optimise
    from acoustiviz.sweep.modes import FreeVibration
    from acoustiviz.sweep.spec import FixedSettings

    duration, n = (1.0, 32) if args.quick else (5.0, 64)
    asking = {"s": 0.0}
    ask = optimise.ask_batch

    def timed_ask(*a):
        t0 = time.perf_counter()
        try:
            return ask(*a)
        finally:
            asking["s"] += time.perf_counter() - t0

    optimise.ask_batch = timed_ask
    results = {}
    for workers in (1, 2):
        asking["s"] = 0.0
        with tempfile.TemporaryDirectory() as folder:
            t0 = time.perf_counter()
            records = optimise.run_optimisation(_problem(n), FreeVibration(FixedSettings(duration=duration)),
                                                folder, workers=workers)
            results[workers] = (time.perf_counter() - t0, asking["s"], json.dumps(records))
    print(f"{n} evaluations of {duration:g} s of motion, batches of 8")
    print(f"{'workers':>8} {'wall (s)':>9} {'evaluations/s':>14} {'asking (s)':>11}")
    for workers, (wall, asked, _) in results.items():
        print(f"{workers:>8} {wall:>9.2f} {n / wall:>14.2f} {asked:>11.2f}")
    print(f"speed-up of 2 workers over 1: {results[1][0] / results[2][0]:.2f}x; "
          f"same designs and rows: {'yes' if results[1][2] == results[2][2] else 'NO'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_writing("bench_optimize", main))
