"""Speed and verification figures of the forced damper (acoustiviz.dynamics.forced).

Usage::

    python benchmarks/bench_forced.py           # all tables
    python benchmarks/bench_forced.py --quick   # fewer frequencies, no Newmark steady states
    python benchmarks/bench_forced.py --attractors --write   # table 6 only, written to
                                                             # benchmarks/results/bench_forced_attractors.txt
    python benchmarks/bench_forced.py --quick --write         # all tables, also to results/bench_forced.txt

Tables printed:

1. Steady state of each solver at a few frequencies: regime, cycles to the Poincaré return
   (tolerance 1e-8), wall time, time per cycle, energy closure per measured cycle.
2. Masri-Caughey agreement: impact map (e = 0.5) and event solver (compliant contacts, against
   Masri-Caughey with the compliant restitution at its own impact speed), relative amplitude
   and impact-speed differences.
3. Linear limit: no-impact amplitude against |X| for the three solvers.
4. The Table 1 damper at F0 = 5 N, 3-7 Hz, 9 frequencies: sweep up with continuation, and
   independent runs serially and on a 2-process pool.
5. The noise in operation of that sweep (what ``acoustiviz forced`` adds by default): time per
   frequency to render the steady click train at 96 kHz (1 s lead-in + at least 1 s of whole
   periods + one trailing period) and take LAeq, LAFmax and LCpeak, against the dynamics' time.
6. Every attractor, Table 1 damper, F0 = 5 N, ``--freq 3:7:9`` with the default starts (what
   ``acoustiviz forced`` runs), against the single-start direct run of the code at ``--baseline``
   (a git revision, default the one before shooting came in), side by side in one run, each in
   its own process after its kernels are compiled: per frequency the cycles integrated, the
   Newton iterations, the attractors and the CPU seconds.
"""

from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np
from _timing import Tee

from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics._contact import free_restitution
from acoustiviz.dynamics.forced import Excitation, _params, frequency_response, steady_state
from acoustiviz.dynamics.periodic import masri_caughey

MC_MODEL = DamperModel(C=1.0, m=0.1)


def _timed(fn, *a, **k):
    t = time.perf_counter()
    out = fn(*a, **k)
    return out, time.perf_counter() - t


def table_solvers(quick):
    print("\n1. steady state per solver from the linear start (C = 1 N s/m, m = 0.1 kg, F0 = 2 N; Newton residual "
          "1e-8 m, m/s, Newmark 1e-3)")
    print(f"{'solver':>10} {'f Hz':>6} {'regime':>13} {'direct':>7} {'integr.':>8} {'time s':>8} {'ms/cycle':>9} "
          f"{'closure':>9}")
    solvers = ["event", "impact-map"] + ([] if quick else ["newmark"])
    for solver in solvers:
        for f in (5.1, 5.3):
            ex = Excitation(f, 2.0)
            steady_state(MC_MODEL, ex, solver=solver, max_cycles=18)  # compile / load the kernels
            r, dt = _timed(steady_state, MC_MODEL, ex, solver=solver,
                           tolerance=1e-3 if solver == "newmark" else 1e-8)
            n = r.cycles_integrated
            print(f"{solver:>10} {f:6.2f} {r.regime:>13} {r.cycles:7d} {n:8d} {dt:8.3f} {1e3 * dt / n:9.3f} "
                  f"{r.energy_closure:9.1e}")


def _mc_compliant(model, ex):
    e, s = 0.9, None
    for _ in range(40):
        s = [q for q in masri_caughey(model, ex, e) if q.valid][0]
        e_new = free_restitution(_params(model), s.approach_speed, 1e-12)[0]
        if abs(e_new - e) < 1e-13:
            break
        e = e_new
    return s, e


def _symmetric(r):
    if r.regime != "periodic-1" or r.impacts_per_cycle != 2:
        return False
    return abs(abs(r.impact_phases[1] - r.impact_phases[0]) - math.pi) < 1e-4


def table_mc(quick):
    print("\n2. Masri-Caughey symmetric two-impacts-per-cycle motion (C = 1 N s/m, m = 0.1 kg, F0 = 2 N)")
    print(f"{'f Hz':>6} {'MC A mm':>10} {'map e=0.5':>10} {'dA map':>9} {'du map':>9} | {'e(u)':>7} "
          f"{'MC A mm':>10} {'event':>10} {'dA event':>9} {'du event':>9}")
    freqs = (4.9, 5.1, 5.3) if quick else (4.9, 5.0, 5.1, 5.2, 5.3, 5.4)
    for f in freqs:
        ex = Excitation(f, 2.0)
        r = steady_state(MC_MODEL, ex, solver="impact-map", restitution=0.5, tolerance=1e-10)
        s = min((q for q in masri_caughey(MC_MODEL, ex, 0.5) if q.valid),
                key=lambda q: abs(q.approach_speed - r.impact_speeds[0]))
        re_ = steady_state(MC_MODEL, ex, solver="event", tolerance=1e-10)
        sc, e = _mc_compliant(MC_MODEL, ex)
        right = (f"{re_.amplitude / sc.amplitude - 1:9.1e} {re_.impact_speeds[0] / sc.approach_speed - 1:9.1e}"
                 if _symmetric(re_) else f"  other motion: {re_.regime}, {re_.impacts_per_cycle:g} impacts/cycle")
        print(f"{f:6.2f} {1e3 * s.amplitude:10.5f} {1e3 * r.amplitude:10.5f} {r.amplitude / s.amplitude - 1:9.1e} "
              f"{r.impact_speeds[0] / s.approach_speed - 1:9.1e} | {e:7.4f} {1e3 * sc.amplitude:10.5f} "
              f"{1e3 * re_.amplitude:10.5f} {right}")
    print("   event against contact stiffness (5.1 Hz): the difference is first order in the contact time")
    for kh in (5.6e8, 5.6e10, 5.6e12):
        model = DamperModel(C=1.0, m=0.1, k_hertz=kh)
        ex = Excitation(5.1, 2.0)
        r = steady_state(model, ex, solver="event", tolerance=1e-10)
        sc, _ = _mc_compliant(model, ex)
        print(f"   K_HZ {kh:8.1e}: contact {np.mean(r.impact_durations):.2e} s, "
              f"dA {r.amplitude / sc.amplitude - 1:9.2e}")


def table_linear():
    print("\n3. linear limit (gap 10 m, C = 2 N s/m, F0 = 5 N, from rest; tolerance 1e-10)")
    model = DamperModel(C=2.0, gap=10.0)
    print(f"{'f Hz':>6} {'|X| mm':>10} {'event':>9} {'impact-map':>11} {'newmark':>9}")
    for f in (3.0, 5.0, 7.0):
        ex = Excitation(f, 5.0)
        w = 2 * math.pi * f
        ref = 5.0 / math.hypot(model.K - model.M * w * w, model.C * w)
        errs = []
        for solver in ("event", "impact-map", "newmark"):
            r = steady_state(model, ex, solver=solver, initial=(0, 0, 0, 0), tolerance=1e-10,
                             restitution=0.5 if solver == "impact-map" else None,
                             steps_per_cycle=4000 if solver == "newmark" else None)
            errs.append(r.amplitude / ref - 1)
        print(f"{f:6.2f} {1e3 * ref:10.5f} {errs[0]:9.1e} {errs[1]:11.1e} {errs[2]:9.1e}")


def table_sweep(quick):
    print("\n4. Table 1 damper, F0 = 5 N, 3-7 Hz")
    model = DamperModel()
    f = np.linspace(3, 7, 5 if quick else 9)
    up, t_up = _timed(frequency_response, model, f, 5.0, sweep="up")
    ind, t_ind = _timed(frequency_response, model, f, 5.0, sweep="independent")
    with ProcessPoolExecutor(2) as ex:
        par, t_par = _timed(frequency_response, model, f, 5.0, sweep="independent", executor=ex)
    print(f"   sweep up {t_up:.2f} s; independent serial {t_ind:.2f} s; independent on 2 processes {t_par:.2f} s "
          f"(same results: {bool(np.array_equal(ind.amplitude, par.amplitude))})")
    print(f"{'f Hz':>6} {'A mm':>9} {'alone mm':>9} {'red dB':>7} {'imp/cyc':>8} {'regime':>13} {'cycles':>7}")
    for r in up.primary:
        print(f"{r.excitation.frequency:6.2f} {1e3 * r.amplitude:9.3f} {1e3 * r.amplitude_without_damper:9.3f} "
              f"{r.reduction_db:7.2f} {r.impacts_per_cycle:8.3f} {r.regime:>13} {r.cycles:7d}")


def table_noise(quick):
    from acoustiviz.app.forced import operating_noise

    print("\n5. noise in operation, Table 1 damper, F0 = 5 N, sweep up (96 kHz, paper's listener)")
    model = DamperModel()
    f = np.linspace(3, 7, 5 if quick else 9)
    up, t_up = _timed(frequency_response, model, f, 5.0, sweep="up")
    operating_noise(up.primary[-1], seconds=0.1)  # load the filter library
    print(f"{'f Hz':>6} {'regime':>13} {'imp/cyc':>8} {'clicks':>7} {'T s':>6} {'time s':>7} "
          f"{'LAeq':>6} {'LAFmax':>7} {'LCpeak':>7}")
    total = 0.0
    for r in up.primary:
        nz, dt = _timed(operating_noise, r)
        total += dt
        print(f"{r.excitation.frequency:6.2f} {r.regime:>13} {r.impacts_per_cycle:8.3f} {nz.sequence.times.size:7d} "
              f"{nz.duration:6.3f} {dt:7.3f} {nz.laeq_db:6.1f} {nz.lafmax_db:7.1f} {nz.lcpeak_db:7.1f}")
    print(f"   dynamics (sweep up) {t_up:.2f} s; levels {total:.2f} s ({100 * total / t_up:.0f} % more)")


BASELINE = "acad2ed"
_OLD = r"""
import json, sys, time
import numpy as np
from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics.forced import Excitation, steady_state
m = DamperModel()
steady_state(m, Excitation(5.0, 5.0), max_cycles=18)  # compile / load the kernels
state, out = None, []
for f in np.linspace(3, 7, 9):
    c0 = time.process_time()
    r = steady_state(m, Excitation(float(f), 5.0), initial=state)
    out.append([float(f), r.cycles + r.measured_cycles, r.regime, time.process_time() - c0, r.amplitude])
    state = r.final_state if r.success else None
print(json.dumps(out))
"""


def table_attractors(baseline=BASELINE, write=False):
    """Table 6 (module docstring); with ``write`` also to benchmarks/results/bench_forced_attractors.txt."""
    import json
    import os
    import platform
    import subprocess
    import sys
    import tempfile
    from datetime import UTC, datetime
    from pathlib import Path

    from acoustiviz.constants import FORCED_MAX_CYCLES, FORCED_RTOL, FORCED_STARTS, FORCED_TOLERANCE
    from acoustiviz.dynamics.forced import attractor_response

    lines = []

    def say(text=""):
        print(text)
        lines.append(text)

    root = Path(__file__).resolve().parent.parent
    with tempfile.TemporaryDirectory() as tmp:
        tree = subprocess.run(["git", "-C", str(root), "archive", baseline, "acoustiviz"], capture_output=True,
                              check=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=tree, check=True)
        env = {**os.environ, "PYTHONPATH": tmp}
        old = json.loads(subprocess.run([sys.executable, "-c", _OLD], capture_output=True, text=True, env=env,
                                        cwd=tmp, check=True).stdout)
    model = DamperModel()
    f = np.linspace(3, 7, 9)
    attractor_response(model, [5.0], 5.0, starts=1, max_cycles=18)  # compile / load the kernels
    c0 = time.process_time()
    resp = attractor_response(model, f, 5.0)
    total = time.process_time() - c0
    now = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    say(f"6. every attractor, Table 1 damper, F0 = 5 N, --freq 3:7:9 ({now}; {platform.machine()}, "
        f"{platform.python_implementation()} {platform.python_version()}, {os.cpu_count()} cores)")
    say(f"   new: {FORCED_STARTS} starts, tolerance {FORCED_TOLERANCE:g} m and m/s, rtol {FORCED_RTOL:g}, "
        f"max cycles {FORCED_MAX_CYCLES}, sweep up, {resp.rounds} continuation rounds; "
        f"old ({baseline}): one start, sweep up, max cycles 2000")
    say(f"{'f Hz':>5} | {'old cycles':>10} {'old CPU s':>9} {'old regime':>13} | {'cycles':>7} {'Newton it':>9} "
        f"{'CPU s':>6} {'attractors':>10}  regimes")
    for (fo, cyc, reg, cpu, _), fa in zip(old, resp.per_frequency, strict=True):
        regs = ", ".join(f"{a.regime} {1e3 * a.amplitude:.2f} mm" for a in fa.attractors)
        say(f"{fo:5.2f} | {cyc:10d} {cpu:9.2f} {reg:>13} | {fa.cycles_integrated:7d} {fa.newton_iterations:9d} "
            f"{fa.cpu_s:6.2f} {len(fa.attractors):10d}  {regs}")
    old_total = sum(o[3] for o in old)
    say(f"total | {sum(o[1] for o in old):10d} {old_total:9.2f} {'':>13} | "
        f"{sum(fa.cycles_integrated for fa in resp.per_frequency):7d} "
        f"{sum(fa.newton_iterations for fa in resp.per_frequency):9d} {total:6.2f}")
    say(f"CPU ratio old / new: {old_total / total:.2f}")
    if write:
        from acoustiviz.files import write_text_atomic

        path = root / "benchmarks" / "results" / "bench_forced_attractors.txt"
        write_text_atomic(path, "\n".join(lines) + "\n")
        print(f"wrote {path.relative_to(root)}")


def main(argv=None):
    """Print the tables (module docstring); ``--write`` keeps them in benchmarks/results/."""
    import contextlib
    import sys
    from pathlib import Path

    args = list(sys.argv[1:] if argv is None else argv)
    if "--write" in args and "--attractors" not in args:
        tee = Tee(sys.stdout)
        with contextlib.redirect_stdout(tee):
            _main(args)
        from acoustiviz.files import write_text_atomic

        path = Path(__file__).resolve().parent / "results" / "bench_forced.txt"
        write_text_atomic(path, "".join(tee.parts).lstrip("\n"))
        print(f"wrote {path}")
        return
    _main(args)


def _main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--attractors", action="store_true", help="table 6 only")
    p.add_argument("--baseline", default=BASELINE, help="git revision of the single-start run (table 6)")
    p.add_argument("--write", action="store_true", help="write table 6 to benchmarks/results/")
    a = p.parse_args(argv)
    if a.attractors:
        table_attractors(a.baseline, a.write)
        return
    table_solvers(a.quick)
    table_mc(a.quick)
    table_linear()
    table_sweep(a.quick)
    table_noise(a.quick)
    table_attractors(a.baseline, a.write)


if __name__ == "__main__":
    main()
