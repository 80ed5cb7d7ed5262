"""CPU time of one design in operation, from scratch and warm-started (acoustiviz.sweep.operation).

Usage::

    python benchmarks/bench_operation.py           # the table
    python benchmarks/bench_operation.py --write   # also to benchmarks/results/operation.md
    python benchmarks/bench_operation.py --profile # only where a search from scratch spends its time
    python benchmarks/bench_operation.py --before /work/main  # also each design from scratch before/after,
                                                              # the "before" imported from that checkout
    python benchmarks/bench_operation.py --transient 1e-6,1e-7,1e-8  # the starts' transients at each rtol
                                                              # against the tight search, also on WIDE designs

Where the forcing cycles go (each tree in its own process): by phase (direct runs, shootings that
converged or failed, periodic measurements, non-periodic windows) and by how each start ends (a new
attractor, a known one measured again, or captured by a known one).

The Table 1 damper under F0 = 5 N over 3-7 Hz (9 frequencies, every attractor, the default
starts and sweep up): what ``acoustiviz forced --freq 3:7:9`` runs, with the checkpoint shootings
far from any return screened out (``Operation.options``). A small set of neighbouring
designs (impact masses 2.5 % apart around 40.5 g, and gaps 5 % apart around 40 mm) is evaluated
twice, each design from scratch and as one chain (the first from scratch, each next warm-started
from the attractors of the nearest design before it, :class:`acoustiviz.sweep.operation.WarmStart`).
The dynamics alone are timed (``levels=False``); the levels of the click trains are timed once
apart. Each line: CPU s from scratch and warm-started, the worst amplitude of each with its
standard error, and their difference in units of the combined standard error (periodic worst
cases have none: their difference is then given in µm).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

from _timing import RESULTS, Tee, results_header

from acoustiviz.sweep import SweepSpec
from acoustiviz.sweep.operation import Operation, WarmStart, evaluate_in_operation
from acoustiviz.sweep.spec import value_range

OPERATION = Operation(5.0, value_range(3.0, 7.0, 9), levels=False)
#: The warm-started searches compared: the linear start alone, and every own start, beside the nearest design's
#: attractors.
WARM = {"warm 1": replace(OPERATION, warm_radius=0.5, warm_starts=1),
        "warm all": replace(OPERATION, warm_radius=0.5, warm_starts=OPERATION.starts)}


def _cpu(f):
    c = time.process_time()
    out = f()
    return time.process_time() - c, out


def _difference(a: dict, b: dict) -> str:
    """``(b - a) / sqrt(se_a² + se_b²)`` of the worst amplitudes, or the difference in µm without errors."""
    d = b["worst_amplitude_m"] - a["worst_amplitude_m"]
    se = math.hypot(a["worst_amplitude_std_err_m"], b["worst_amplitude_std_err_m"])
    return f"{d / se:+7.2f} se" if se > 0 else f"{1e6 * d:+7.2f} um"


def _worst(r: dict) -> str:
    return (f"{r['cycles_integrated']:6d} {1e3 * r['worst_amplitude_m']:8.3f} "
            f"{1e3 * r['worst_amplitude_std_err_m']:5.3f} {r['worst_regime'][:8]:>8} {r['worst_frequency_hz']:4.1f}")


def table(specs) -> None:
    print(f"Table 1 damper, F0 = 5 N, {len(OPERATION.frequencies)} frequencies 3-7 Hz, {OPERATION.starts} starts, "
          f"sweep {OPERATION.sweep}, dynamics only. Warm: the nearest design before it in the chain (radius 0.5) "
          "seeds each frequency, with the linear start (warm 1) or every own start (warm all), no continuation.")
    print("CPU s; forcing cycles integrated (the cost without the machine's load); worst amplitude in mm, its "
          "standard error in mm, regime, frequency in Hz; difference to scratch in "
          "combined standard errors (se) or in um when both are periodic.")
    print(f"{'design':>14} | {'scratch s':>9} {'cycles, worst (scratch)':>36} |" + "".join(
        f" {name + ' s':>10} {'cycles, worst':>36} {'diff':>10} |" for name in WARM))
    tot = dict.fromkeys(["scratch", *WARM], 0.0)
    n = 0
    for label, spec in specs:
        caches = {name: WarmStart() for name in WARM}
        for d in spec.designs():
            ts, rs = _cpu(lambda d=d, s=spec: evaluate_in_operation(d, s.settings, OPERATION))
            line = f"{label + ' ' + (f'{1e3 * d.m:.1f} g' if label == 'm' else f'{1e3 * d.gap:.0f} mm'):>14} | " \
                   f"{ts:9.2f} {_worst(rs):>36} |"
            first = not len(caches["warm 1"])
            for name, op in WARM.items():
                tw, rw = _cpu(lambda d=d, s=spec, o=op, w=caches[name]: evaluate_in_operation(d, s.settings, o, warm=w))
                line += f" {tw:10.2f} {_worst(rw):>36} {_difference(rs, rw):>10} |"
                tot[name] += 0.0 if first else tw
            tot["scratch"] += 0.0 if first else ts
            n += 0 if first else 1
            print(line)
    print(f"mean CPU s per warm-started design ({n} designs): scratch {tot['scratch'] / n:.2f}, " + ", ".join(
        f"{name} {tot[name] / n:.2f}" for name in WARM))


def _designs(specs):
    for label, spec in specs:
        for d in spec.designs():
            yield {"m": f"m {1e3 * d.m:.1f} g", "gap": f"gap {1e3 * d.gap:.0f} mm"}.get(
                label, f"m {1e3 * d.m:.0f} g, gap {1e3 * d.gap:.0f} mm"), d, spec


def scratch_rows(specs) -> None:
    """One JSON line per design from scratch: its label, CPU s and the cells of its row (``--rows``)."""
    for name, d, spec in _designs(specs):
        t, r = _cpu(lambda d=d, s=spec: evaluate_in_operation(d, s.settings, OPERATION))
        keep = ("cycles_integrated", "worst_amplitude_m", "worst_amplitude_std_err_m", "worst_regime",
                "worst_frequency_hz", "attractors")
        print(json.dumps({"design": name, "cpu_s": t, **{k: r[k] for k in keep}}), flush=True)


#: Designs across the bounds the optimiser and the gallery use (gap 0.02-0.06 m, impact mass 0.02-0.08 kg).
WIDE = SweepSpec(gap=value_range(0.02, 0.06, 3), m=value_range(0.02, 0.08, 3))


def _rtol_rows(transient: str, wide: bool) -> list:
    """The rows of :func:`scratch_rows` with the transients at ``transient`` ("none": at the search's rtol)."""
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    cmd = [sys.executable, __file__, "--rows", "--transient-rtol", transient] + (["--wide"] if wide else [])
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return [json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")]


def transient_table(rtols: list, wide: bool) -> None:
    """Each design from scratch with the starts' transients at each of ``rtols`` against the tight search."""
    tight = _rtol_rows("none", wide)
    sides = {r: _rtol_rows(r, wide) for r in rtols}
    print("from scratch, the starts' transients at the search's rtol (tight) and at each transient rtol, each run "
          "in its own process: CPU s, cycles; worst amplitude mm, its standard error mm, regime; difference of the "
          "worst case to the tight search in se or um")
    print(f"{'design':>22} | {'tight s':>7} {'cycles, worst':>36} |" + "".join(
        f" {r + ' s':>9} {'cycles':>6} {'diff':>10} |" for r in rtols))
    for i, o in enumerate(tight):
        print(f"{o['design']:>22} | {o['cpu_s']:7.2f} {_worst(o):>36} |" + "".join(
            f" {sides[r][i]['cpu_s']:9.2f} {sides[r][i]['cycles_integrated']:6d} {_difference(o, sides[r][i]):>10} |"
            for r in rtols))
    n = len(tight)

    def worst(rows, unit):
        diffs = [_difference(o, r) for o, r in zip(tight, rows, strict=True)]
        return max((abs(float(d.split()[0])) for d in diffs if d.endswith(unit)), default=0.0)

    print(f"{'mean CPU s, cycles':>22} | {sum(o['cpu_s'] for o in tight) / n:7.2f} "
          f"{sum(o['cycles_integrated'] for o in tight) / n:6.0f} {'':>29} |" + "".join(
              f" {sum(r['cpu_s'] for r in sides[t]) / n:9.2f} {sum(r['cycles_integrated'] for r in sides[t]) / n:6.0f}"
              f" {'':>10} |" for t in rtols))
    print(f"{'largest |diff|':>22} | {'':>44} |" + "".join(
        f" {worst(sides[t], 'se'):7.2f} se {worst(sides[t], 'um'):7.2f} um {'':>4} |" for t in rtols))


def before_after(specs, before: str) -> None:
    """Each design from scratch with the package at ``before`` (a checkout, run apart) and with this one."""
    env = {**os.environ, "PYTHONPATH": before}
    proc = subprocess.run([sys.executable, __file__, "--rows"], env=env, capture_output=True, text=True, check=True)
    old = [json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")]
    print(f"from scratch, before ({before}) and after (this tree), each run in its own process: CPU s, cycles, "
          "worst amplitude mm, its standard error mm, regime, Hz, attractors found; difference in se or um")
    print(f"{'design':>14} | {'before s':>8} {'cycles, worst, attractors':>42} | {'after s':>8} "
          f"{'cycles, worst, attractors':>42} {'diff':>10}")
    tot = [0.0, 0.0, 0, 0]
    for o, (name, d, spec) in zip(old, _designs(specs), strict=True):
        t, r = _cpu(lambda d=d, s=spec: evaluate_in_operation(d, s.settings, OPERATION))
        print(f"{name:>14} | {o['cpu_s']:8.2f} {_worst(o):>36} {o['attractors']:5d} | {t:8.2f} {_worst(r):>36} "
              f"{r['attractors']:5d} {_difference(o, r):>10}")
        tot = [tot[0] + o["cpu_s"], tot[1] + t, tot[2] + o["cycles_integrated"], tot[3] + r["cycles_integrated"]]
    n = len(old)
    print(f"mean per design: before {tot[0] / n:.2f} CPU s, {tot[2] / n:.0f} cycles; after {tot[1] / n:.2f} CPU s, "
          f"{tot[3] / n:.0f} cycles")


#: Where the forcing cycles of a search go: phases (what integrates a cycle) and start outcomes.
PHASES = ("direct runs", "shooting, converged", "shooting, failed", "periodic measurements",
          "non-periodic windows")
OUTCOMES = ("new periodic orbit", "new non-periodic motion", "known orbit, measured again",
            "known non-periodic, measured again", "captured by a known orbit", "captured by a known non-periodic",
            "solver stopped")


def _instrumented():
    """Patch the search's internals to count cycles by phase and by start outcome; return the counters.

    Only names both trees have (``settle``, ``shoot``, ``measure_periodic``, ``measure_window``,
    ``_Runner.cycle``, and ``_Runner.cycles`` where the tree has it), so that the "before" process counts the
    same way: the cycles of shootings and measurements by the cycles their runners integrate, the direct runs
    as the rest of each start's cycles.
    """
    from acoustiviz.dynamics import _attractors as att
    from acoustiviz.dynamics import _forced_steady as fs
    from acoustiviz.dynamics._measure import same_motion

    phase = ["direct runs"]
    cycles = dict.fromkeys(PHASES, 0)
    starts = {k: [0, 0] for k in OUTCOMES}
    run_cycle = fs._Runner.cycle

    def cycle(self, *args):
        cycles[phase[-1]] += 1
        return run_cycle(self, *args)

    run_stretch = getattr(fs._Runner, "cycles", None)  # a stretch of cycles in one call, where the tree has it

    def stretch(self, *args, **kwargs):
        total, counted = self.total, cycles[phase[-1]]
        out = run_stretch(self, *args, **kwargs)
        cycles[phase[-1]] += self.total - total - (cycles[phase[-1]] - counted)  # less those counted by cycle
        return out

    def within(label, f):
        def g(*args, **kwargs):
            phase.append(label)
            try:
                return f(*args, **kwargs)
            finally:
                phase.pop()
        return g

    shoot = att.shoot

    def counted_shoot(pmap, *args, **kwargs):
        before = dict(cycles)
        phase.append("shooting, failed")
        try:
            out = shoot(pmap, *args, **kwargs)
        finally:
            phase.pop()
        if out.converged:
            moved = cycles["shooting, failed"] - before["shooting, failed"]
            cycles["shooting, failed"] -= moved
            cycles["shooting, converged"] += moved
        return out

    settle = att.settle

    def counted_settle(*args, **kwargs):
        counted = sum(cycles.values())
        o = settle(*args, **kwargs)
        counted = sum(cycles.values()) - counted
        used = o.steady.cycles_integrated if o.steady is not None else o.cycles
        cycles["direct runs"] += used - counted  # cycles run by the compiled direct run (none cycle by cycle)
        known = kwargs.get("known", ())
        if o.steady is None:
            key = "captured by a known orbit" if known[o.known].period else "captured by a known non-periodic"
        elif not o.steady.success:
            key = "solver stopped"
        else:
            again = any(same_motion(a, o.steady) for a in known)
            key = ("known orbit, measured again" if o.steady.period else "known non-periodic, measured again") \
                if again else ("new periodic orbit" if o.steady.period else "new non-periodic motion")
        starts[key][0] += 1
        starts[key][1] += used
        return o

    fs._Runner.cycle = cycle
    if run_stretch is not None:
        fs._Runner.cycles = stretch
    att.shoot = counted_shoot
    att.settle = counted_settle
    att.measure_periodic = within("periodic measurements", att.measure_periodic)
    att.measure_window = within("non-periodic windows", att.measure_window)
    return cycles, starts


def breakdown_rows(specs) -> None:
    """One JSON line: the cycles of every design from scratch by phase and by start outcome (``--breakdown``)."""
    cycles, starts = _instrumented()
    for _, d, spec in _designs(specs):
        evaluate_in_operation(d, spec.settings, OPERATION)
    print(json.dumps({"cycles": cycles, "starts": starts}), flush=True)


def breakdown(specs, before: str | None) -> None:
    """The cycles of the designs from scratch by phase and by start outcome, before and after, in their processes."""
    sides = {}
    for name, root in (("before", before), ("after", None)):
        if name == "before" and root is None:
            continue
        env = {**os.environ, "PYTHONPATH": root or str(Path(__file__).resolve().parents[1])}
        proc = subprocess.run([sys.executable, __file__, "--breakdown"], env=env, capture_output=True, text=True,
                              check=True)
        sides[name] = json.loads(proc.stdout.splitlines()[-1])
    n = sum(len(spec.designs()) for _, spec in specs)
    print(f"where the forcing cycles go, per design from scratch (mean of {n}); starts include the seeds "
          "continued from the neighbouring frequency. Direct runs: each start's cycles less those of its shootings "
          "and measurements (a measurement that finds a smaller period is left out of a start's cycles, so it shows "
          "here as fewer direct cycles).")
    print(f"{'phase':>40} |" + "".join(f" {name:>8}" for name in sides))
    for p in PHASES:
        print(f"{p:>40} |" + "".join(f" {s['cycles'].get(p, 0) / n:8.0f}" for s in sides.values()))
    print(f"{'start ends as':>40} |" + "".join(f" {name + ': starts, cycles':>24}" for name in sides))
    for k in OUTCOMES:
        print(f"{k:>40} |" + "".join(f" {s['starts'][k][0] / n:11.1f} {s['starts'][k][1] / n:12.0f}"
                                     for s in sides.values()))


def levels_cost(spec) -> None:
    d = spec.designs()[0]
    t, r = _cpu(lambda: evaluate_in_operation(d, spec.settings, Operation(5.0, OPERATION.frequencies)))
    print(f"with the levels of every attractor's click train at the listener (96 kHz): {t:.2f} CPU s for "
          f"design 0 (worst LCpeak {r['worst_lcpeak_db']:.1f} dB, LAeq {r['worst_laeq_db']:.1f} dB, "
          f"LAFmax {r['worst_lafmax_db']:.1f} dB)")


#: Where a search from scratch spends its time: label -> (module file, function) of pstats.
PROFILED = {"forced driver (run_cycles: stretches and single cycles)": ("_forced_direct.py", "run_cycles"),
            "direct runs of the starts": ("_attractors.py", "advance"),
            "shooting (Newton, Jacobians, Floquet)": ("_shooting.py", "shoot"),
            "  of which finite-difference Jacobians": ("_shooting.py", "_jacobian"),
            "non-periodic windows (batch means, Lyapunov)": ("_measure.py", "measure_window")}


def profile(spec) -> None:
    """Where one design's search from scratch spends its CPU time (cumulative, under cProfile)."""
    import cProfile
    import pstats

    d = spec.designs()[0]
    prof = cProfile.Profile()
    prof.runcall(evaluate_in_operation, d, spec.settings, OPERATION)
    st = pstats.Stats(prof).stats
    total = max(v[3] for v in st.values())
    print(f"profile of design 0 from scratch (cProfile, {total:.2f} s with its overhead):")
    for label, (fname, func) in PROFILED.items():
        hits = [(v[1], v[3]) for (f, _, name), v in st.items() if f.endswith(fname) and name == func]
        calls, cum = sum(h[0] for h in hits), sum(h[1] for h in hits)
        print(f"  {label:<54} {cum:6.2f} s {100 * cum / total:5.1f} %  ({calls} calls)")


def _write_markdown(header: str, body: str) -> None:
    """``results/operation.md``: the command line and the table, written atomically."""
    path = RESULTS / "operation.md"
    text = (f"# One design in operation: from scratch (before and after) and warm-started\n\n{header}\n\n```text\n"
            f"{body.strip()}\n```\n")
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)
    print(f"wrote {path}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="also write benchmarks/results/operation.md")
    ap.add_argument("--profile", action="store_true", help="only the profile of one design from scratch")
    ap.add_argument("--before", metavar="CHECKOUT", help="also each design from scratch with the package of "
                    "another checkout (its folder, run in a process of its own) beside this one")
    ap.add_argument("--transient", metavar="RTOLS", help="also each design from scratch with the starts' "
                    "transients at each of these comma-separated rtols beside the tight search (each in its own "
                    "process)")
    ap.add_argument("--wide", action="store_true", help="with --transient: also the designs across the bounds")
    ap.add_argument("--rows", action="store_true", help=argparse.SUPPRESS)  # the "before" side of --before
    ap.add_argument("--transient-rtol", help=argparse.SUPPRESS)  # the rows' transient rtol ("none": tight)
    ap.add_argument("--breakdown", action="store_true", help=argparse.SUPPRESS)  # one side of the cycles' breakdown
    args = ap.parse_args()
    masses = SweepSpec(m=value_range(0.0385, 0.0425, 5))
    gaps = SweepSpec(gap=value_range(0.038, 0.042, 3))
    evaluate_in_operation(masses.designs()[0], masses.settings, Operation(5.0, (3.0,), starts=1, max_cycles=18,
                                                                          levels=False))  # kernels loaded
    if args.transient_rtol is not None:  # this process's search with its transients at that rtol
        options = Operation.options
        rtol = None if args.transient_rtol == "none" else float(args.transient_rtol)
        Operation.options = lambda self: replace(options(self), transient_rtol=rtol)
    if args.rows:
        scratch_rows([("m", masses), ("gap", gaps)] + ([("wide", WIDE)] if args.wide else []))
        return
    if args.breakdown:
        breakdown_rows([("m", masses), ("gap", gaps)])
        return
    tee = Tee(sys.stdout)
    with contextlib.redirect_stdout(tee):
        if args.transient:
            transient_table(args.transient.split(","), args.wide)
        if args.before:
            before_after([("m", masses), ("gap", gaps)], args.before)
        breakdown([("m", masses), ("gap", gaps)], args.before)
        profile(masses)
        if not args.profile:
            table([("m", masses), ("gap", gaps)])
            levels_cost(masses)
    if args.write:
        command = " ".join(["python benchmarks/bench_operation.py", *(a for a in sys.argv[1:] if a != "--write")])
        _write_markdown(results_header(command), "".join(tee.parts))


if __name__ == "__main__":
    main()
