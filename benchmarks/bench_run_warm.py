"""The README's main job warm, ``acoustiviz run --out DIR`` on the default scene, side by side with earlier commits.

CPU seconds (user + system of the child, ``resource.getrusage(RUSAGE_CHILDREN)``) of the job with
the numba cache filled, each tree with a cache of its own: one run per tree fills it (not counted),
then ``--repeats`` rounds run every tree once in turn, so a change in the machine's load falls on
all of them alike; the table gives each tree's median and its ratio to each baseline, with the
issue 24 target (warm run <= 0.6 x commit 4a6bf44). The trees are extracted with ``git archive``
and run through ``PYTHONPATH`` with the same interpreter and packages, their bytecode written first;
the child is the probe of :mod:`bench_startup` (the console script's ``main()`` in-process).

This is the warm row of ``bench_startup.py`` measured several times over: that benchmark runs the
job once per tree, and on a machine shared with other work one run can be off by a second.

Usage::

    python benchmarks/bench_run_warm.py                          # against 4a6bf44, 3 rounds
    python benchmarks/bench_run_warm.py --baseline 4a6bf44 main --repeats 5 --write
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import run_writing  # noqa: E402
from bench_startup import BASELINE, ROOT, TARGETS, _fresh, _precompile, baseline_tree, cpu_run  # noqa: E402


def measure(trees: dict, works: dict, repeats: int) -> dict:
    """{tree: [CPU s of each counted run]}: a cache-filling run each, then ``repeats`` rounds in turn."""
    def run(t, cache):
        out = works[t] / "out"
        shutil.rmtree(out, ignore_errors=True)  # a new folder each time, as the README's first run
        return cpu_run(trees[t], ["run", "--out", str(out)], cache, works[t])

    for t in trees:
        run(t, _fresh(works[t] / "cache"))
    samples = {t: [] for t in trees}
    for _ in range(repeats):
        for t in trees:
            samples[t].append(run(t, works[t] / "cache"))
    return samples


def table(samples: dict, baselines: list) -> str:
    """One row per tree: median and each run (CPU s), ratios of the median to each baseline's."""
    med = {t: statistics.median(v) for t, v in samples.items()}
    lines = ["acoustiviz run --out DIR (default scene), warm numba cache: CPU seconds (user + system), "
             "median of alternated runs", ""]
    head = f"{'tree':<12}{'median s':>10}  {'runs s':<26}" + "".join(f"{'/ ' + b:>12}" for b in baselines)
    lines.append(head)
    for t, v in samples.items():
        runs = " ".join(f"{x:.2f}" for x in v)
        lines.append(f"{t:<12}{med[t]:>10.2f}  {runs:<26}" + "".join(f"{med[t] / med[b]:>12.3f}" for b in baselines))
    if BASELINE in med:
        ratio = med["now"] / med[BASELINE]
        target = TARGETS["run warm"]
        lines += ["", f"target (issue 24): now / {BASELINE} <= {target:g}: {ratio:.3f} "
                      f"({'ok' if ratio <= target else 'MISS'}; {target * med[BASELINE]:.2f} s)"]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    """Run the benchmark and print the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", nargs="+", default=[BASELINE], help=f"commits to compare with (default {BASELINE})")
    ap.add_argument("--repeats", type=int, default=3, help="alternated rounds counted (median)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_run_warm_") as tmp:
        tmp = Path(tmp)
        trees = {b: baseline_tree(b, tmp / f"tree_{i}") for i, b in enumerate(args.baseline)}
        trees["now"] = ROOT
        works = {t: tmp / f"work_{i}" for i, t in enumerate(trees)}
        for t, tree in trees.items():
            works[t].mkdir()
            _precompile(tree)
        samples = measure(trees, works, max(1, args.repeats))
    print(table(samples, args.baseline), end="")
    return 0


if __name__ == "__main__":
    sys.exit(run_writing("bench_run_warm", main))
