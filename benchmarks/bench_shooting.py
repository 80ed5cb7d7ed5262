"""Where the shootings of a design's search in operation spend their forcing cycles (acoustiviz.dynamics._shooting).

Usage::

    python benchmarks/bench_shooting.py          # the counts
    python benchmarks/bench_shooting.py --ulp    # also: every converged orbit point moved by one ulp
    python benchmarks/bench_shooting.py --write  # also to benchmarks/results/bench_shooting.txt

The designs and the operation of ``bench_operation.py`` (the Table 1 damper and its neighbours, F0 = 5 N,
9 frequencies 3-7 Hz, every attractor), each from scratch. Each shooting (:func:`shoot`) is counted by
phase, through the cycles its map integrates: the first evaluation of ``P^n`` at the start point, the
forward-difference Jacobians of the Newton steps (4 n cycles each), the line-search trials, and apart
the central-difference Jacobians of the Floquet multipliers of new orbits (8 n cycles each). Solves
are split into those that converged and those that failed (after ``SHOOT_MAX_ITERATIONS`` steps, or
on a step that could not reduce the residual or left the cavity).

``--ulp`` runs the designs again with the point of every converged shooting moved by one unit in the
last place (:func:`numpy.nextafter`) and compares the attractors and worst cases: how far the search
depends on the last bits of the orbits it converges to (the periodic orbits seed the neighbouring
frequencies, and a seeded start that turns chaotic amplifies its start's last bit).
"""

from __future__ import annotations

import argparse
import collections
import sys
from dataclasses import replace

import numpy as np
from _timing import run_writing
from bench_operation import OPERATION, _designs, _difference, _worst

from acoustiviz.dynamics import _attractors as att
from acoustiviz.dynamics import _shooting as sh
from acoustiviz.sweep import SweepSpec
from acoustiviz.sweep.operation import Operation, evaluate_in_operation
from acoustiviz.sweep.spec import value_range

#: The designs of ``bench_operation.py``: impact masses 2.5 % apart around 40.5 g, gaps 5 % apart around 40 mm.
SPECS = [("m", SweepSpec(m=value_range(0.0385, 0.0425, 5))), ("gap", SweepSpec(gap=value_range(0.038, 0.042, 3)))]
PHASES = ("first evaluation", "Jacobians", "line-search trials")


class _Counter:
    """Counts every shooting's cycles by phase while installed (wraps the names the search calls)."""

    def __init__(self):
        self.solves = []  # one dict per shooting
        self.multipliers = [0, 0]  # calls, cycles
        self.phase = None
        self.current = None

    def install(self):
        shoot, jacobian, with_multipliers = att.shoot, sh._jacobian, att.with_multipliers
        call = sh.PoincareMap.__call__

        def counted_call(pmap, s, n):
            before = pmap.cycles
            out = call(pmap, s, n)
            if self.current is not None:
                self.current[self.phase] += pmap.cycles - before
                if self.phase == "first evaluation":
                    self.phase = "line-search trials"
            return out

        def counted_jacobian(*args, **kwargs):
            if self.current is None:  # the multipliers' Jacobian, counted by its caller
                return jacobian(*args, **kwargs)
            self.phase = "Jacobians"
            self.current["jacobians"] += 1
            try:
                return jacobian(*args, **kwargs)
            finally:
                self.phase = "line-search trials"

        def counted_shoot(pmap, s0, n, *args, **kwargs):
            self.current = dict.fromkeys(PHASES, 0) | {"jacobians": 0, "n": n}
            self.phase = "first evaluation"
            try:
                out = shoot(pmap, s0, n, *args, **kwargs)
            finally:
                rec, self.current, self.phase = self.current, None, None
            rec.update(converged=out.converged, steps=out.iterations)
            self.solves.append(rec)
            return out

        def counted_multipliers(pmap, shot, n, *args, **kwargs):
            before = pmap.cycles
            out = with_multipliers(pmap, shot, n, *args, **kwargs)
            self.multipliers[0] += 1
            self.multipliers[1] += pmap.cycles - before
            return out

        sh.PoincareMap.__call__ = counted_call
        sh._jacobian = counted_jacobian
        att.shoot = counted_shoot
        att.with_multipliers = counted_multipliers


def _run_designs() -> list:
    return [evaluate_in_operation(d, spec.settings, OPERATION) for _, d, spec in _designs(SPECS)]


def counts() -> list:
    """The table of the shootings' cycles per design (mean over the designs); the designs' results."""
    c = _Counter()
    c.install()
    results = _run_designs()
    nd = len(results)
    total = sum(r["cycles_integrated"] for r in results)
    print(f"shootings of a search from scratch, per design (mean of {nd}); {total / nd:.0f} forcing cycles per "
          "design in all")
    print(f"{'':>34} | {'converged':>10} {'failed':>10}")
    groups = {k: [s for s in c.solves if s["converged"] == k] for k in (True, False)}

    def row(label, f, fmt="10.1f"):
        print(f"{label:>34} | " + " ".join(f"{f(groups[k]) / nd:{fmt}}" for k in (True, False)))

    row("solves", len)
    row("Newton steps", lambda g: sum(s["steps"] for s in g))
    row("Jacobians", lambda g: sum(s["jacobians"] for s in g))
    for p in PHASES:
        row(f"cycles: {p}", lambda g, p=p: sum(s[p] for s in g), "10.0f")
    spent = {k: sum(sum(s[p] for p in PHASES) for s in g) for k, g in groups.items()}
    row("cycles in all", lambda g: sum(sum(s[p] for p in PHASES) for s in g), "10.0f")
    print(f"{'share of all cycles':>34} | " + " ".join(f"{100 * spent[k] / total:9.1f}%" for k in (True, False)))
    print(f"{'Floquet multipliers (new orbits)':>34} | {c.multipliers[0] / nd:.1f} Jacobians, "
          f"{c.multipliers[1] / nd:.0f} cycles ({100 * c.multipliers[1] / total:.1f} %)")
    for k in (True, False):
        hist = collections.Counter(s["steps"] for s in groups[k])
        print(f"{'Newton steps: solves (' + ('converged' if k else 'failed') + ')':>34} | "
              + ", ".join(f"{n}: {hist[n]}" for n in sorted(hist)) + f"  (all {nd} designs)")
    capped = sum(1 for s in groups[False] if s["steps"] >= sh.SHOOT_MAX_ITERATIONS)
    print(f"{'failed after the last step allowed':>34} | {capped} of {len(groups[False])} (all designs)")
    return results


def one_ulp(plain: list) -> None:
    """The designs again with every converged orbit point moved by one ulp, beside ``plain``."""
    shoot = att.shoot

    def moved(*args, **kwargs):
        out = shoot(*args, **kwargs)
        return replace(out, point=np.nextafter(out.point, np.inf)) if out.converged else out

    att.shoot = moved
    try:
        after = _run_designs()
    finally:
        att.shoot = shoot
    print("every converged orbit point moved by one ulp: cycles, worst amplitude mm, its standard error mm, "
          "regime, Hz, attractors found; difference in se or um")
    for (name, _, _), a, b in zip(_designs(SPECS), plain, after, strict=True):
        print(f"{name:>14} | {_worst(a):>36} {a['attractors']:3d} | {_worst(b):>36} {b['attractors']:3d} "
              f"{_difference(a, b):>10}")


def main(argv) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ulp", action="store_true", help="also every converged orbit point moved by one ulp")
    args = ap.parse_args(argv)
    spec = SPECS[0][1]
    evaluate_in_operation(spec.designs()[0], spec.settings, Operation(5.0, (3.0,), starts=1, max_cycles=18,
                                                                      levels=False))  # kernels loaded
    plain = counts()
    if args.ulp:
        one_ulp(plain)
    return 0


if __name__ == "__main__":
    sys.exit(run_writing("bench_shooting", main))
