"""Cost of several balls in operation (:mod:`acoustiviz.dynamics.balls_forced`).

Two tables, in CPU seconds of this process (``time.process_time``: the compiled kernels run in it), after
a warm-up that compiles them or loads them from numba's cache:

1. the forced multi-ball solver advanced cycle by cycle (:class:`~acoustiviz.dynamics.balls_forced.BallCycles`)
   from the linear start, 1 to 10 equal balls of the Table 1 impact mass in the Table 1 damper with
   C = 2 N s/m under 5 N at 5 Hz: CPU per forcing cycle and collisions per cycle;
2. one ball, the period-1 orbit at 4 Hz and 10 N with C = 5 N s/m: the single-ball ``forced`` (shooting)
   against the multi-ball path (direct run and multipliers by differences), their amplitudes and
   largest multiplier moduli, and their CPU.

With ``--before DIR`` (a tree of the package, e.g. ``git archive`` of an earlier commit) the same
measurements of that tree run in a subprocess (``PYTHONPATH=DIR``) in the same run, and each table gets
its figures beside this tree's.

Usage::

    python benchmarks/bench_balls_forced.py            # writes benchmarks/results/balls_forced.md
    python benchmarks/bench_balls_forced.py --quick    # fewer cycles, nothing written
    python benchmarks/bench_balls_forced.py --before /tmp/old   # and the old tree's figures beside
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics.balls import MultiBallModel
from acoustiviz.dynamics.balls_forced import BallCycles, ball_attractors_at, ball_start_states, check_ball_settings
from acoustiviz.dynamics.forced import Excitation, attractors_at, check_settings

RESULTS = Path(__file__).resolve().parent / "results" / "balls_forced.md"
#: Numbers of balls of the per-cycle table.
BALLS = (1, 2, 5, 10)


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


def measure(cycles: int) -> dict:
    """Both tables' figures of the package imported here (kernels warmed first), as plain numbers."""
    per_cycle(1, 2)  # warm-up: compile or load the kernels
    one_ball()
    costs = {n: per_cycle(n, cycles) for n in BALLS}
    orbits = [(name, a.period, a.amplitude, float(np.max(np.abs(a.floquet))), a.cycles_integrated, cpu)
              for name, a, cpu in one_ball()]
    return {"costs": costs, "orbits": orbits}


def measure_before(tree: Path, cycles: int) -> dict:
    """:func:`measure` of the package in ``tree``, run in a subprocess that imports it."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--json", "--cycles", str(cycles)],
                         env=env, cwd=tree, capture_output=True, text=True, check=True).stdout
    got = json.loads(out.strip().splitlines()[-1])
    return {"costs": {int(n): tuple(v) for n, v in got["costs"].items()}, "orbits": got["orbits"]}


def report(now: dict, cycles: int, before: dict | None = None, label: str = "") -> str:
    """The Markdown text of the results, with the figures of ``before`` beside when given."""
    lines = ["# Several balls in operation", "",
             "`python benchmarks/bench_balls_forced.py`: CPU seconds of this process (numba kernels warm). "
             "Figures from one run on the shared 2-core development machine.", ""]
    if before is not None:
        lines += [f"Before: {label} (run in a subprocess of the same run, `--before`); after: this tree. A lone "
                  "contact (exactly one pair touching from its start to its end) is integrated by the single-ball "
                  "contact kernel in sqrt(delta) time, under forcing too; before, forcing sent every contact "
                  "through the general physical-time path.", ""]
    lines += [f"## Cost per forcing cycle ({cycles} cycles from the linear start; C = 2 N s/m, 5 N at 5 Hz)", ""]
    if before is None:
        lines += ["| balls | CPU ms per cycle | collisions per cycle |", "|---:|---:|---:|"]
        lines += [f"| {n} | {ms:.2f} | {col:.1f} |" for n, (ms, col) in now["costs"].items()]
    else:
        lines += ["| balls | CPU ms per cycle before | CPU ms per cycle after | speed-up | collisions per cycle "
                  "before | after |", "|---:|---:|---:|---:|---:|---:|"]
        for n, (ms, col) in now["costs"].items():
            ms0, col0 = before["costs"][n]
            lines.append(f"| {n} | {ms0:.2f} | {ms:.2f} | {ms0 / ms:.1f}x | {col0:.1f} | {col:.1f} |")
    lines += ["", "## One ball: the period-1 orbit at 4 Hz, 10 N, C = 5 N s/m", "",
              "| path | period | amplitude m | largest multiplier modulus | cycles integrated | CPU s |",
              "|---|---:|---:|---:|---:|---:|"]
    runs = [("", now)] if before is None else [(" (before)", before), (" (after)", now)]
    for tag, res in runs:
        for name, period, amp, top, ncyc, cpu in res["orbits"]:
            lines.append(f"| {name}{tag} | {period} | {amp:.12g} | {top:.6f} | {ncyc} | {cpu:.3f} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer cycles; nothing written")
    parser.add_argument("--before", type=Path, help="a tree of the package to measure beside this one")
    parser.add_argument("--label", default="", help="what the --before tree is (for the text)")
    parser.add_argument("--cycles", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)  # the --before subprocess
    args = parser.parse_args(argv)
    cycles = args.cycles or (20 if args.quick else 200)
    if args.json:
        print(json.dumps(measure(cycles)))
        return
    before = None if args.before is None else measure_before(args.before.resolve(), cycles)
    text = report(measure(cycles), cycles, before, args.label or str(args.before))
    print(text)
    if not args.quick:
        RESULTS.write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
