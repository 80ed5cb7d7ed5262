"""Steps per compliant contact against its accuracy: a work-precision study of the contact's step control.

Usage::

    python benchmarks/bench_contact_steps.py                      # the table
    python benchmarks/bench_contact_steps.py --write              # also results/bench_contact_steps.txt
    python benchmarks/bench_contact_steps.py --png                # also results/bench_contact_steps.png
    python benchmarks/bench_contact_steps.py --before /work/main  # also the step control of that checkout
    python benchmarks/bench_contact_steps.py --before DIR --label pi  # its rows named "pi"

One contact (``acoustiviz.dynamics._contact.contact``, DOP853 in the regularised time σ) is run to
its end at rtol 1e-6 ... 1e-13 for each case: free contacts of the two masses alone (the contact of
``free_restitution``) at approach speeds 0.01-3 m/s, impact masses 10, 40.5 and 100 g and contact
damping c1 0 and 20 N s/m (the main mass 0.5 kg, Table 1's Hertz stiffness), and contacts of the
Table 1 damper forced at 5 Hz by 5 N, starting at either wall with the main mass moving. Each tree
runs in its own process with numba's compilation off (``NUMBA_DISABLE_JIT=1``), so that the steps can
be counted by wrapping the module's step and error norm: the same operations as the compiled
kernel's (to the rounding of the library's powers and roots), and counts that do not depend on the
machine's load.

Errors are against the contact at rtol 1e-14 of this tree (its restitution is checked against
SciPy's DOP853 on the same σ-equations at rtol 1e-13, printed first): the largest over the cases of
the restitution's error (relative to the approach speed), the relative errors of the duration and
the impulse, the end state's error (x, v, sqrt(δ), u, each over its Hertz scale: ``_contact_begin``'s
tolerances at rtol 1) and that of the energies (dissipated in the contact and by C, the work of the
forcing: relative to the larger of the value and the Hertz energy scale). Steps per contact: those
the step control tried (rejected included), the rejected ones, the full steps of the root searches
of the peak force and of the contact's end (and of the main mass's turns, none here), and all; each
costs 12 stages.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
from pathlib import Path

os.environ["NUMBA_DISABLE_JIT"] = "1"  # before acoustiviz imports numba: the steps are counted in Python

import numpy as np  # noqa: E402
from _timing import RESULTS, run_writing  # noqa: E402

RTOLS = (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13)
REFERENCE_RTOL = 1e-14
#: Table 1 (kg, N/m, N s/m, m, N/m^1.5): the main mass, spring and dashpot, half the gap, the Hertz stiffness.
M, K, C, HALF_GAP, K_HERTZ = 0.5, 500.0, 0.05, 0.02, 5.6e8
FORCING = (2.0 * math.pi * 5.0, 5.0, 0.0)  # ω rad/s, P N, Q N


def cases() -> list[tuple]:
    """``(label, parameter vector, forcing or None, start)``: ``start`` = (tc s, wall, x m, v m/s, ξ, u m/s)."""
    out = []
    for m in (0.01, 0.0405, 0.1):
        for c1 in (0.0, 20.0):
            for u0 in (0.01, 0.1, 1.0, 3.0):
                p = [M, 0.0, 0.0, m, HALF_GAP, K_HERTZ, c1, 0.0]
                out.append((f"free m={m} c1={c1} u0={u0}", p, None, (0.0, 1.0, 0.0, 0.0, 0.0, u0)))
    p = [M, K, C, 0.0405, HALF_GAP, K_HERTZ, 20.0, 0.0]
    for tc, sw, x, v, u0 in ((0.013, 1.0, 0.003, 0.1, 0.05), (0.071, -1.0, -0.002, -0.3, 0.5),
                             (0.15, 1.0, 0.001, 0.6, 2.0), (0.117, -1.0, 0.004, 0.2, 0.01)):
        out.append((f"forced u0={u0}", p, list(FORCING), (tc, sw, x, v, 0.0, u0)))
    return out


def run_cases(rtols) -> dict:
    """End states and step counts of every case at each rtol with the acoustiviz imported here."""
    from acoustiviz.dynamics import _contact as mod
    from acoustiviz.dynamics._records import ContactStart, params_record

    counts = {"tried": 0, "rejected": 0, "all": 0, "peak": 0}
    error_norm, dop_step, root_in_step = mod._dop_error, mod._dop_step, mod._root_in_step

    def counted_error(*args):
        err = error_norm(*args)
        counts["tried"] += 1
        counts["rejected"] += not (err <= 1.0)
        return err

    def counted_step(*args):
        counts["all"] += 1
        return dop_step(*args)

    def counted_root(kind, *args):  # kind 3: the peak force's search (its steps counted apart)
        before = counts["all"]
        out = root_in_step(kind, *args)
        counts["peak"] += (counts["all"] - before) if kind == 3 else 0
        return out

    mod._dop_error, mod._dop_step, mod._root_in_step = counted_error, counted_step, counted_root
    out = {}
    for rtol in rtols:
        rows = []
        for _, p, fc, start in cases():
            n = mod.NY if fc is None else mod.NY + 1
            work, kst = np.zeros((mod.N_WORK_ROWS, n)), np.zeros((mod.N_STAGE_ROWS, n))
            for key in counts:
                counts[key] = 0
            r = mod.contact(params_record(np.array(p)), None if fc is None else np.array(fc), ContactStart(*start),
                            math.inf, rtol, None, np.int64(0), None, 0.0, 0.0, work, kst, None, None)
            assert r.ended and r.status == 0
            rows.append({"y": [float(v) for v in r.y], "peak": r.peak, **counts})
        out[repr(rtol)] = rows
    return out


def scales() -> list[np.ndarray]:
    """Each case's Hertz scale of every state component (``_contact_begin``'s tolerances at rtol 1)."""
    from acoustiviz.dynamics import _contact as mod
    from acoustiviz.dynamics._records import ContactStart, params_record

    out = []
    for _, p, fc, start in cases():
        n = mod.NY if fc is None else mod.NY + 1
        y, atol = np.zeros(n), np.zeros(n)
        mod._contact_begin(params_record(np.array(p)), ContactStart(*start), 1.0, y, atol)
        out.append(atol)
    return out


def scipy_check(reference: list) -> float:
    """Largest difference of the free contacts' restitution between the reference and SciPy's DOP853 (rtol 1e-13)."""
    from scipy.integrate import solve_ivp

    worst = 0.0
    for (_, p, fc, start), ref in zip(cases(), reference, strict=True):
        if fc is not None:
            continue
        m, kh, c1 = p[3], p[5], p[6]
        meff, u0 = m * M / (m + M), start[5]

        def rhs(_s, z, meff=meff, kh=kh, c1=c1):  # z = (t, ξ, u): dt/dσ = ξ, dξ/dσ = u/2, du/dσ = -ξ F / m_eff
            f = kh * z[1] ** 3 + c1 * z[2]
            return (z[1], 0.5 * z[2], -z[1] * f / meff)

        def parted(_s, z):
            return z[1]

        parted.terminal, parted.direction = True, -1
        amax = (1.25 * meff * u0 * u0 / kh) ** 0.4
        s_end = 20.0 * amax / u0 / math.sqrt(amax)
        sol = solve_ivp(rhs, (0.0, s_end), (0.0, 0.0, u0), method="DOP853", rtol=1e-13,
                        atol=(1e-30, 1e-13 * math.sqrt(amax), 1e-13 * u0), events=parted, first_step=1e-3 * s_end / 20)
        e_scipy = -sol.y_events[0][0][2] / u0
        worst = max(worst, abs(e_scipy - (-ref["y"][4] / u0)))
    return worst


def errors(rows: list, reference: list, scale: list) -> tuple:
    """Largest errors over the cases: restitution, duration, impulse, end state, energies (module docstring)."""
    de = dd = dj = ds = dw = 0.0
    for (_, _, _, start), row, ref, sc in zip(cases(), rows, reference, scale, strict=True):
        y, yr = np.array(row["y"]), np.array(ref["y"])
        de = max(de, abs(y[4] - yr[4]) / start[5])
        dd = max(dd, abs(y[0] / yr[0] - 1.0))
        dj = max(dj, abs(y[5] / yr[5] - 1.0))
        ds = max(ds, float(np.max(np.abs(y[1:5] - yr[1:5]) / sc[1:5])))
        dw = max(dw, float(np.max(np.abs(y[6:] - yr[6:]) / np.maximum(np.abs(yr[6:]), sc[6:]))))
    return de, dd, dj, ds, dw


def in_tree(tree: str | None, rtols) -> dict:
    """:func:`run_cases` in a process importing acoustiviz from ``tree`` (None: this one)."""
    env = dict(os.environ, PYTHONPATH=str(Path(tree or Path(__file__).resolve().parents[1]).resolve()))
    cmd = [sys.executable, __file__, "--worker", json.dumps(list(rtols))]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def draw(lines: dict, path: Path) -> None:
    """Restitution error against DOP853 steps per contact (all of them), one line per step control."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.0, 4.0))
    ax = fig.add_subplot()
    for name, pts in lines.items():
        steps, errs, rtols = zip(*pts, strict=True)
        ax.loglog(steps, errs, "o-", label=name)
        for s, e, r in zip(steps, errs, rtols, strict=True):
            ax.annotate(f"{r:g}", (s, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("DOP853 steps per contact (tried + root searches)")
    ax.set_ylabel("largest restitution error")
    ax.set_title("One compliant contact: work against precision (labels: rtol)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", help="a checkout whose step control is compared (its acoustiviz imported)")
    ap.add_argument("--label", default="before", help="the name of the --before checkout's rows")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--png", action="store_true", help="also draw results/bench_contact_steps.png")
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(run_cases(json.loads(args.worker))))
        return 0
    reference = in_tree(None, [REFERENCE_RTOL])[repr(REFERENCE_RTOL)]
    scale = scales()
    n = len(cases())
    print(f"{n} contacts ({sum(c[2] is None for c in cases())} free, {sum(c[2] is not None for c in cases())} "
          f"forced); reference rtol {REFERENCE_RTOL:g}, its restitution against SciPy DOP853 at rtol 1e-13: "
          f"{scipy_check(reference):.1e}")
    print("Per contact (mean over the cases): steps tried, of them rejected, full steps of the root searches of the "
          "peak force and of the end, all steps; largest errors over the cases.")
    print(f"{'tree':>8} {'rtol':>7} | {'tried':>6} {'rej':>5} {'peak':>5} {'end':>5} {'all':>6} | {'restitution':>11} "
          f"{'duration':>9} {'impulse':>9} {'end state':>9} {'energies':>9}")
    trees = {args.label[:8]: args.before, "this": None} if args.before else {"this": None}
    lines = {}
    for name, tree in trees.items():
        res = in_tree(tree, RTOLS)
        pts = []
        for rtol in RTOLS:
            rows = res[repr(rtol)]
            tried, rej, peak, allst = (sum(r[k] for r in rows) / n for k in ("tried", "rejected", "peak", "all"))
            de, dd, dj, ds, dw = errors(rows, reference, scale)
            end = allst - tried - peak
            print(f"{name:>8} {rtol:7.0e} | {tried:6.2f} {rej:5.2f} {peak:5.2f} {end:5.2f} {allst:6.2f} | {de:11.1e} "
                  f"{dd:9.1e} {dj:9.1e} {ds:9.1e} {dw:9.1e}")
            pts.append((allst, de, rtol))
        lines[name] = pts
    if args.png:
        path = RESULTS / "bench_contact_steps.png"
        draw(lines, path)
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(run_writing("bench_contact_steps", main))
