"""Cost of several balls in operation (:mod:`acoustiviz.dynamics.balls_forced`).

Two tables, in CPU seconds of this process (``time.process_time``: the compiled kernels run in it), after
a warm-up that compiles them or loads them from numba's cache:

1. the forced multi-ball solver advanced cycle by cycle (:class:`~acoustiviz.dynamics.balls_forced.BallCycles`)
   from the linear start, 1 to 10 equal balls of the Table 1 impact mass in the Table 1 damper with
   C = 2 N s/m under 5 N at 5 Hz: CPU per forcing cycle and collisions per cycle;
2. one ball, the period-1 orbit at 4 Hz and 10 N with C = 5 N s/m: the single-ball ``forced`` (shooting)
   against the multi-ball path (direct run and multipliers by differences), their amplitudes and
   largest multiplier moduli, and their CPU.

Usage::

    python benchmarks/bench_balls_forced.py            # writes benchmarks/results/balls_forced.md
    python benchmarks/bench_balls_forced.py --quick    # fewer cycles, nothing written
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics.balls import MultiBallModel
from acoustiviz.dynamics.balls_forced import BallCycles, ball_attractors_at, ball_start_states, check_ball_settings
from acoustiviz.dynamics.forced import Excitation, attractors_at, check_settings

RESULTS = Path(__file__).resolve().parent / "results" / "balls_forced.md"


def per_cycle(n_balls: int, cycles: int) -> tuple:
    """``(CPU ms per cycle, collisions per cycle)`` of ``n_balls`` over ``cycles`` forcing cycles."""
    model = MultiBallModel.from_damper(DamperModel(C=2.0), n_balls)
    ex = Excitation(5.0, 5.0)
    run = BallCycles(model, ex, ball_start_states(model, ex, 1)[0], 1e-10)
    t0 = time.process_time()
    collisions = 0
    for _ in range(cycles):
        collisions += len(run.cycle()[3])
    return 1e3 * (time.process_time() - t0) / cycles, collisions / cycles


def one_ball() -> list:
    """The single-ball and multi-ball rows of table 2."""
    m, ex = DamperModel(C=5.0), Excitation(4.0, 10.0)
    rows = []
    t0 = time.process_time()
    (a,) = attractors_at(m, ex, check_settings(m, ex, starts=1, max_cycles=300)).attractors
    rows.append(("forced (one ball, shooting)", a, time.process_time() - t0))
    mb = MultiBallModel.from_damper(m, 1)
    t0 = time.process_time()
    (b,) = ball_attractors_at(mb, ex, check_ball_settings(mb, ex, starts=1, max_cycles=300)).attractors
    rows.append(("balls path (direct run, differences)", b, time.process_time() - t0))
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer cycles; nothing written")
    args = parser.parse_args(argv)
    cycles = 20 if args.quick else 200
    per_cycle(1, 2)  # warm-up: compile or load the kernels
    one_ball()
    lines = ["# Several balls in operation", "",
             "`python benchmarks/bench_balls_forced.py`: CPU seconds of this process (numba kernels warm). "
             "Figures from one run on the shared 2-core development machine.", "",
             f"## Cost per forcing cycle ({cycles} cycles from the linear start; C = 2 N s/m, 5 N at 5 Hz)", "",
             "| balls | CPU ms per cycle | collisions per cycle |", "|---:|---:|---:|"]
    for n in (1, 2, 5, 10):
        ms, col = per_cycle(n, cycles)
        lines.append(f"| {n} | {ms:.2f} | {col:.1f} |")
    lines += ["", "## One ball: the period-1 orbit at 4 Hz, 10 N, C = 5 N s/m", "",
              "| path | period | amplitude m | largest multiplier modulus | cycles integrated | CPU s |",
              "|---|---:|---:|---:|---:|---:|"]
    for name, a, cpu in one_ball():
        lines.append(f"| {name} | {a.period} | {a.amplitude:.12g} | {float(np.max(np.abs(a.floquet))):.6f} | "
                     f"{a.cycles_integrated} | {cpu:.3f} |")
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.quick:
        RESULTS.write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
