"""Rerun every figure the README and the guide quote from the program, and check the text.

Usage::

    python docs/check_numbers.py --check            # exit 1 and list every quoted figure that differs
    python docs/check_numbers.py --update           # rewrite the quoted figures with what the program gives now
    python docs/check_numbers.py --check --only forced-table   # some entries only
    python docs/check_numbers.py --list             # the registry

The registry (:data:`REGISTRY`) has one entry per quoted figure or block: the file, a regular
expression whose named groups are the quoted text, and the function that produces that text by
running the program (the same command the text shows). Producers share their runs (each command
runs once). Timings are machine-dependent and are not re-timed here: the text quotes them from
the committed benchmark result files (``benchmarks/results/*.txt``, written by the benchmark
scripts with the machine and the date), and the check verifies that the text says what the file
says. To add a figure: write a producer returning ``{group: text}`` and append a :class:`Figure`.
"""

from __future__ import annotations

import argparse
import atexit
import contextlib
import functools
import io
import os
import re
import shutil
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TABLE1 = ["--M", "0.5", "--K", "500", "--C", "0.05", "--m", "0.0405", "--gap", "0.04", "--k-hertz", "5.6e8",
          "--c1", "20"]
#: Timings in the output of a command are replaced by this (they come from benchmark files only).
TIME = "[time]"


@dataclass(frozen=True)
class Figure:
    """One quoted figure (or block): ``pattern`` in ``file``; ``produce()`` gives each named group's text."""

    name: str
    file: str
    pattern: str
    produce: object
    command: str = ""


@functools.cache
def _workdir(name: str) -> Path:
    """A temporary folder kept for the whole check (commands that read what others wrote run in it)."""
    path = Path(tempfile.mkdtemp(prefix=f"numbers-{name}-"))
    atexit.register(shutil.rmtree, path, ignore_errors=True)
    return path


def _cli(argv, cwd=None) -> str:
    """Stdout of ``acoustiviz ARGV`` (status 0 required) run in ``cwd``, with timings replaced by :data:`TIME`.

    Run in ``cwd`` (a :func:`_workdir`), the relative paths of the command are printed as the text shows them.
    """
    from acoustiviz.cli import main

    buf = io.StringIO()
    with contextlib.chdir(cwd or os.getcwd()), contextlib.redirect_stdout(buf):
        rc = main(list(argv))
    if rc != 0:
        raise RuntimeError(f"acoustiviz {' '.join(argv)} exited with {rc}")
    text = buf.getvalue()
    text = re.sub(r"in \d+\.\d+ s\b", f"in {TIME} s", text)
    text = re.sub(r"; \d+\.\d+ s$", f"; {TIME} s", text, flags=re.M)
    text = re.sub(r"\(\d+\.\d+ s this run\)", f"({TIME} s this run)", text)
    return text


def _benchmark(name: str) -> str:
    """``benchmarks/results/NAME.txt``, written by ``python benchmarks/NAME.py ... --write``."""
    return (ROOT / "benchmarks" / "results" / f"{name}.txt").read_text(encoding="utf-8")


def _range(values, fmt: str, sep: str = "-") -> str:
    """``lo-hi`` of the formatted values (one value when both ends format alike)."""
    lo, hi = format(min(values), fmt), format(max(values), fmt)
    return lo if lo == hi else f"{lo}{sep}{hi}"


def _bound(x: float) -> str:
    """A bound on ``x`` to one significant figure, rounded up (2.2e-14 -> 3e-14; 6e-12 -> 6e-12)."""
    import math

    if x <= 0:
        return "0"
    e = math.floor(math.log10(x))
    d = math.ceil(round(x / 10**e, 9))
    if d == 10:
        d, e = 1, e + 1
    return f"{d}e{e:+03d}".replace("e+0", "e").replace("e-0", "e-").replace("e+", "e")


def _without_writes(text: str) -> str:
    """Drop the ``wrote PATH`` lines (temporary paths)."""
    return "".join(line for line in text.splitlines(keepends=True) if not line.startswith("wrote "))


# --------------------------------------------------------------------------- producers
FORCED_TABLE_ARGS = [*TABLE1, "--force", "5", "--freq", "3:7:9"]


@functools.cache
def forced_table() -> dict:
    """``acoustiviz forced ... --freq 3:7:9 --csv OUT.csv``: the console block of the guide, and its rows."""
    import csv

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "OUT.csv"
        text = _cli(["forced", *FORCED_TABLE_ARGS, "--csv", str(out)])
        with open(out, newline="") as fh:
            rows = list(csv.DictReader(fh))
    return {"output": _without_writes(text) + "wrote OUT.csv\n", "rows": rows}


def produce_forced_table() -> dict:
    """The console block of the 3-7 Hz table."""
    return {"output": forced_table()["output"]}


def produce_coexisting() -> dict:
    """How many frequencies have several attractors, and where the motion is chaotic."""
    rows = forced_table()["rows"]
    freqs = sorted({r["frequency_hz"] for r in rows}, key=float)
    several = [f for f in freqs if sum(r["frequency_hz"] == f for r in rows) > 1]
    chaotic = sorted({f"{float(r['frequency_hz']):g}" for r in rows if r["regime"] == "chaotic"}, key=float)
    return {"several": str(len(several)), "total": str(len(freqs)), "chaotic": ", ".join(chaotic)}


@functools.cache
def forced_5hz() -> dict:
    """The README's headline in operation: ``acoustiviz forced --force 5 --freq 5`` (Table 1 defaults)."""
    import csv

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "h.csv"
        _cli(["forced", *TABLE1, "--force", "5", "--freq", "5", "--csv", str(out)])
        with open(out, newline="") as fh:
            rows = list(csv.DictReader(fh))
    return {"rows": rows}


def produce_headline_forced() -> dict:
    """The README's 5 Hz figures: the worst case's amplitude and the loudest LCpeak."""
    rows = forced_5hz()["rows"]
    worst = max(rows, key=lambda r: float(r["amplitude_m"]))
    loud = max(rows, key=lambda r: float(r["lcpeak_db"]))
    regimes = sorted({r["regime"] for r in rows})
    return {
        "attractors": "one motion" if len(rows) == 1 else f"{len(rows)} coexisting motions",
        "regime": ", ".join(regimes),
        "red": f"{float(worst['reduction_db']):.1f}",
        "a0": f"{float(worst['amplitude_without_damper_m']):.2f}",
        "amp": f"{float(worst['amplitude_m']):.3f}",
        "err": f"{float(worst['amplitude_std_err_m']):.3f}",
        "lcpeak": f"{float(loud['lcpeak_db']):.1f}",
        "laeq": f"{float(loud['laeq_db']):.1f}",
    }


def _levels_line(text: str) -> dict:
    """The figures of a ``LZpeak ..., SEL(A) ... dB`` line, by name."""
    get = {key: re.search(rf"{key} (-?[\d.]+)", text).group(1)
           for key in ("LZpeak", "LCpeak", "LAFmax", "LASmax", "LAeq", "LZeq")}
    get["SEL"] = re.search(r"SEL (-?[\d.]+)", text).group(1)
    get["SELA"] = re.search(r"SEL\(A\) (-?[\d.]+)", text).group(1)
    return get


@functools.cache
def default_scene_levels() -> dict:
    """``acoustiviz run --out DIR`` on the default scene, its ``levels`` output: the printed lines and summary.md.

    The other outputs of the default scene do not change these figures (they are the damper run's
    levels at the listener, its sound power and the radiation efficiency of its loudest impact), so
    only ``[outputs.levels]`` is kept.
    """
    from acoustiviz.scene import shipped_scenes

    text = shipped_scenes()["default"]
    scene = text[:text.index("[outputs.")] + "[outputs.levels]\n"
    tmp = _workdir("scene")
    (tmp / "levels.toml").write_text(scene, encoding="utf-8")
    buf = io.StringIO()
    with contextlib.redirect_stderr(buf):
        out = _cli(["run", "levels.toml", "--out", "out"], cwd=tmp)
    progress = buf.getvalue() + out
    summary = (tmp / "out" / "summary.md").read_text(encoding="utf-8")
    figures = dict(re.findall(r"(\w+) = ([-\d.e+]+)", summary))
    get = _levels_line(re.search(r"LZpeak.*$", progress, re.M).group(0))
    get["impacts"] = re.search(r"levels of (\d+) impacts", progress).group(1)
    get["lw"] = figures["sound_power_level_db_re_1pw"]
    get["eff_pct"] = f"{100 * float(figures['loudest_impact_radiation_efficiency']):.2f}"
    return get


def produce_headline_damper() -> dict:
    """The README's figures of the 20 s damper run (the default scene's levels output)."""
    d = default_scene_levels()
    return {"impacts": d["impacts"], "peak": d["LZpeak"], "lcpeak": d["LCpeak"], "lafmax": d["LAFmax"],
            "laeq": d["LAeq"], "sela": d["SELA"], "lw": d["lw"], "eff": d["eff_pct"]}


# ---- docs/guide/hearing.md
@functools.cache
def damper_levels() -> dict:
    """``acoustiviz auralize --wav damper.wav --levels``: the Table 1 damper's 20 s run at the paper's listener.

    Run in a folder kept for the check: ``acoustiviz levels`` reads the WAV file afterwards.
    """
    import json

    tmp = _workdir("hearing")
    text = _cli(["auralize", "--wav", "damper.wav", "--levels"], cwd=tmp)
    get = _levels_line(re.search(r"LZpeak.*$", text, re.M).group(0))
    get["impacts"] = re.search(r"impacts: (\d+)", text).group(1)
    get["output"] = text
    get["sidecar"] = json.loads((tmp / "damper.json").read_text(encoding="utf-8"))
    return get


def produce_hearing_auralize() -> dict:
    """The console block of ``auralize --levels`` and the prose figures drawn from it."""
    d = damper_levels()
    return {"output": d["output"], "lcpeak": f"{float(d['LCpeak']):.0f}",
            "c_minus_a": f"{float(d['LCpeak']) - float(d['LAFmax']):.0f}",
            "f_minus_eq": f"{float(d['LAFmax']) - float(d['LAeq']):.0f}"}


SIDECAR_KEYS = ("subtype", "sample_rate_hz", "scale_pa_per_full_scale", "pressure_pa", "peak_pa", "peak_dbfs",
                "physical_peak_pa", "clipping")


def produce_hearing_sidecar() -> dict:
    """The keys of ``damper.json`` the guide shows, and how far band-limiting moved the peak."""
    import json
    import math

    side = damper_levels()["sidecar"]
    lines = "".join(f'"{k}": {json.dumps(side[k])},\n' for k in SIDECAR_KEYS)
    ratio = side["physical_peak_pa"][0] / side["peak_pa"][0]
    return {"json": lines, "pct": f"{100 * abs(ratio - 1):.2f}", "db": f"{abs(20 * math.log10(ratio)):.2f}"}


@functools.cache
def wav_levels() -> str:
    """``acoustiviz levels damper.wav --csv levels.csv`` on the file ``auralize`` wrote."""
    damper_levels()
    return _cli(["levels", "damper.wav", "--csv", "levels.csv"], cwd=_workdir("hearing"))


@functools.cache
def wav_levels_5s() -> str:
    """``acoustiviz levels damper.wav --csv first5s.csv --start 0 --stop 5 --loudness``."""
    damper_levels()
    return _cli(["levels", "damper.wav", "--csv", "first5s.csv", "--start", "0", "--stop", "5", "--loudness"],
                cwd=_workdir("hearing"))


def produce_hearing_wav_levels() -> dict:
    """The console block of ``acoustiviz levels`` on the whole file."""
    return {"output": wav_levels()}


def produce_hearing_wav_5s() -> dict:
    """The console block of the first 5 s with loudness, and its LAeq against the whole run's."""
    first = _levels_line(wav_levels_5s())
    whole = _levels_line(wav_levels())
    return {"output": wav_levels_5s(), "above": f"{float(first['LAeq']) - float(whole['LAeq']):.0f}"}


@functools.cache
def _gallery(script: str) -> dict:
    """``gallery/SCRIPT`` run in full mode: its printed text (without ``wrote`` lines) and its namespace."""
    import runpy

    tmp = _workdir("gallery")
    gallery = str(ROOT / "gallery")
    env = {k: os.environ.get(k) for k in ("ACOUSTIVIZ_GALLERY_DIR", "ACOUSTIVIZ_FAST")}
    os.environ["ACOUSTIVIZ_GALLERY_DIR"] = str(tmp)
    os.environ.pop("ACOUSTIVIZ_FAST", None)
    sys.path.insert(0, gallery)
    buf = io.StringIO()
    try:
        with contextlib.redirect_stdout(buf):
            ns = runpy.run_path(str(ROOT / "gallery" / script), run_name="__main__")
    finally:
        sys.path.remove(gallery)
        for k, v in env.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return {"text": _without_writes(buf.getvalue()), "namespace": ns}


def levels_gallery() -> dict:
    """``gallery/plot_14_levels.py`` (full mode): its printed design table and its results."""
    run = _gallery("plot_14_levels.py")
    return {"table": run["text"], "results": run["namespace"]["results"]}


def produce_hearing_designs() -> dict:
    """The two designs' table, and the prose comparing them (level differences, loudness)."""
    g = levels_gallery()
    (_, t1), (_, q) = g["results"].items()
    cols = ("lcpeak_db", "lafmax_db", "laeq_db", "sel_a_db")
    a, b = t1["report"].levels.rows()[0], q["report"].levels.rows()[0]
    diff = [round(a[c], 1) - round(b[c], 1) for c in cols]  # as the table shows them
    out = {"table": g["table"], "quieter_db": f"{sum(diff) / len(diff):.0f}",
           "eq_minus_z": f"{a['laeq_db'] - a['lzeq_db']:.0f}"}
    if t1["report"].loudness is not None:
        n1, n2 = t1["report"].loudness.rows()[0]["n5_sone"], q["report"].loudness.rows()[0]["n5_sone"]
        out["less_loud"] = f"{100 * (1 - round(n2, 2) / round(n1, 2)):.0f}"
    return out


def produce_hearing_energy() -> dict:
    """The radiation efficiency of each design's loudest impact and the Table 1 run's sound power."""
    (_, t1), (_, q) = levels_gallery()["results"].items()
    e1, e2 = t1["energy"], q["energy"]
    return {"eff1": f"{100 * e1.efficiency[e1.loudest]:.2f}", "eff2": f"{100 * e2.efficiency[e2.loudest]:.2f}",
            "lw": f"{e1.sound_power_level_db:.1f}"}


# ---- docs/guide/sweeps.md
SWEEP_ARGS = ["sweep", "--gap", "0.02:0.06:3", "--m", "0.02,0.0405,0.06", "--duration", "20", "--levels", "--out", "sw",
              "--workers", "2"]
DESIGN_ARGS = ["design", "--sweep", "sw", "--inclination", "0.005", "--tolerance", "0.003"]


@functools.cache
def sweep_run() -> str:
    """``acoustiviz sweep ... --out sw``: 9 designs of 20 s with levels (its time is :data:`TIME`)."""
    return _cli(SWEEP_ARGS, cwd=_workdir("sweeps"))


@functools.cache
def design_query(rank_by: str) -> str:
    """``acoustiviz design --sweep sw ... --rank-by RANK_BY`` on the sweep above."""
    sweep_run()
    return _cli([*DESIGN_ARGS, "--rank-by", rank_by], cwd=_workdir("sweeps"))


def produce_sweep_run() -> dict:
    """The console block of the sweep."""
    return {"output": sweep_run()}


def produce_design_lafmax() -> dict:
    """The console block of the query ranked by LAFmax."""
    return {"output": design_query("lafmax_db")}


def produce_design_max_spl() -> dict:
    """How far apart the same designs are by the paper's measure (``--rank-by max_spl_db``)."""
    text = design_query("max_spl_db")
    return {"spread": re.search(r"the quietest is ([\d.]+) dB quieter", text).group(1)}


def produce_sweep_refused() -> dict:
    """The one-line refusal of a sweep directory made with other settings (``--gap 0.02:0.06:4``)."""
    from acoustiviz.cli import main

    sweep_run()
    args = [*SWEEP_ARGS]
    args[args.index("0.02:0.06:3")] = "0.02:0.06:4"
    buf = io.StringIO()
    quiet = contextlib.redirect_stdout(io.StringIO())
    with contextlib.chdir(_workdir("sweeps")), contextlib.redirect_stderr(buf), quiet:
        try:
            rc = main(args)
        except SystemExit as exc:
            rc = exc.code
    if rc != 2:
        raise RuntimeError(f"acoustiviz {' '.join(args)} exited with {rc}, not 2")
    return {"error": buf.getvalue().strip().splitlines()[-1]}


# ---- docs/guide/speed_accuracy.md and the README's field timing: the benchmark result files
def _e(x: float, digits: int = 1) -> str:
    """``x`` in the guide's short scientific form: 1.1e8, 2.8e6, 6e-12."""
    m, e = f"{x:.{digits}e}".split("e")
    return f"{m}e{int(e)}"


def _rows(text: str, head: str) -> list:
    """The whitespace-split rows of the table under the line starting ``head`` (after its dashes)."""
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.strip().startswith(head))
    out = []
    for line in lines[i + 2:]:  # to a blank line or a note (a line of another length)
        row = line.split()
        if not row or out and len(row) not in (len(out[0]), len(out[0]) + 1):
            break
        out.append(row)
    return out


@functools.cache
def bench_field() -> dict:
    """Figures of ``benchmarks/results/bench_field.txt`` (``python benchmarks/bench_field.py --write``)."""
    text = _benchmark("bench_field")
    pulses = [r for r in _rows(text, "config ") if len(r) == 9]  # config pulse metrics_s points/s x s x err err
    hertz = [r for r in pulses if r[1] == "hertz"]
    sampled = [r for r in pulses if r[1] == "hertz-1025-linear"]
    expo = _rows(text, "pulse  setup s  exposure s")
    fast = {r[0]: r for r in _rows(text, "pulse  setup s  peak+SEL s")}
    n_fast = int(re.search(r"fast_peaks\), wall-floor corner, ([\d,]+) points", text).group(1).replace(",", ""))
    scaling = _rows(text, "points samples/pt")
    mem = re.search(r"peak memory of field_metrics on [\d,]+ points .*?: ([\d.]+) MiB", text).group(1)
    hz, hs = fast["hertz"], fast["half-sine"]
    missed = sum(int(r[-1]) for r in fast.values())
    differ = sum(int(r[-2]) for r in fast.values())
    fm_s = float(hz[9].rstrip("*"))
    return {
        "table": text,
        "rate": _range([float(r[3]) for r in scaling], ".1e").replace("e+0", "e").replace("e+", "e"),
        "speedup": _range([float(r[6]) for r in scaling], ".0f"),
        "hertz_cost": _range([float(r[4]) for r in hertz], ".2f"),
        "hertz_pct": _range([100 * (float(r[4]) - 1) for r in hertz], ".0f"),
        "hertz_err": _bound(max(float(x) for r in hertz for x in r[7:9])),
        "sampled_cost": _range([float(r[4]) for r in sampled], ".0f"),
        "sampled_err": _e(max(float(x) for r in sampled for x in r[7:9]), 0),
        "sampled_err_lo": _e(min(float(x) for r in sampled for x in r[7:9]), 0),
        "sel_rate": _range([float(r[3]) for r in expo], ".1e").replace("e+0", "e").replace("e+", "e"),
        "n_fast": _e(n_fast, 0),
        "fp_s": f"{float(hz[2]):.1f}", "fp_total": f"{float(hz[3]):.1f}", "hs_s": f"{float(hs[2]):.1f}",
        "fp_x": f"{fm_s / float(hz[3]):.0f}",
        "fp_err": _e(float(hz[6]), 0), "fp_err_bound": _bound(float(hz[6])),
        "sel_err": _e(float(hz[8]), 1),
        "missed": "no peak" if missed == 0 else f"{missed} peak{'s' * (missed > 1)}",
        "differ": "none differ" if differ == 0 else f"{differ} differ",
        "mem": mem,
    }


def produce_bench_field() -> dict:
    """The field evaluator's figures, as its results file has them."""
    return bench_field()


@functools.cache
def bench_dynamics() -> dict:
    """Figures of ``benchmarks/results/bench_dynamics.txt`` and of the ``--full`` run's ``bench_dynamics.csv``.

    ``python benchmarks/bench_dynamics.py --write`` writes the first (3 s), ``--full`` the second (20 s).
    """
    import csv

    text = _benchmark("bench_dynamics")
    rows = _rows(text, "solver      setting")
    default = next(r for r in rows if r[-1] == "(default)")
    newmark = [r for r in rows if r[0] == "newmark"]
    imap = [r for r in rows if r[0] == "impact-map"]
    ivp = re.findall(r"vs scipy DOP853 .*?first 40: \|dt\| ([\d.e+-]+) s, du/u ([\d.e+-]+)", text)
    with open(ROOT / "benchmarks" / "results" / "bench_dynamics.csv", newline="") as fh:
        full = list(csv.DictReader(fh))
    from acoustiviz.constants import DEFAULT_RTOL

    row20 = next(r for r in full if r["solver"] == "event" and r["setting"] == f"rtol={DEFAULT_RTOL:g}")
    speedup = float(default[-2].rstrip("x"))
    agree = max(int(r[8]) for r in newmark)
    map_agree = int(imap[0][8])
    return {
        "table": text,
        "impacts": default[3], "ms": f"{float(default[2]):.1f}", "du": default[4].replace("e-0", "e-"),
        "dt": default[5].replace("e-0", "e-"), "speedup": f"{round(speedup, -2):.0f}",
        "impacts20": row20["n_impacts"], "ms20": f"{1e3 * float(row20['time_s']):.1f}",
        "ivp_du": ivp[0][1] if ivp else "",
        "newmark_agree": str(agree),
        "map_agree": "the first one only" if map_agree == 1 else f"the first {map_agree} only",
    }


def produce_bench_dynamics() -> dict:
    """The damper solvers' figures, as the results files have them."""
    return bench_dynamics()


@functools.cache
def bench_levels() -> dict:
    """Figures of ``benchmarks/results/bench_levels.txt`` (``python benchmarks/bench_levels.py --quick --write``)."""
    text = _benchmark("bench_levels")
    wl = re.search(r"weighted levels \(8 levels\)\s+([\d.]+)", text).group(1)
    bands = re.search(r"1/3-octave bands \(30\)\s+([\d.]+)", text).group(1)
    changes = [abs(float(r[2])) for r in _rows(text, "level       96 kHz")]
    sw = float(re.search(r"\(rel\. diff\. ([\d.e+-]+)\)", text).group(1))
    grid = {(r[0], r[1]): r for r in _rows(text, "config n_theta")}
    free = max(float(r[4]) for k, r in grid.items() if k[0] == "free" and k[1] != "4")
    plane = max(float(r[4]) for k, r in grid.items() if k[0] == "plane" and r[4] != "-")
    corner = max(float(r[4]) for k, r in grid.items() if k[0] == "wall-floor" and r[4] != "-")
    return {"table": text, "wl": f"{float(wl):.2f}", "bands": f"{float(bands):.1f}",
            "dmax": f"{max(changes):.3f}", "sw": _bound(sw), "free": _bound(max(free, sw)),
            "plane": _bound(plane), "corner": f"{100 * corner:.1f}"}


def produce_bench_levels() -> dict:
    """The levels' figures, as the results file has them."""
    return bench_levels()


@functools.cache
def bench_audio() -> dict:
    """Figures of ``benchmarks/results/bench_audio.txt`` (``python benchmarks/bench_audio.py --write``)."""
    rows = _rows(_benchmark("bench_audio"), "rate (Hz)")
    hs = next(r for r in rows if r[:3] == ["48000", "half-sine", "mono"])
    hz = next(r for r in rows if r[:3] == ["48000", "hertz", "mono"])
    return {"hs": f"{float(hs[4]):.2f}", "hertz": f"{float(hz[4]):.2f}",
            "xrt": _range([float(r[5]) for r in rows], ".0f")}


def produce_bench_audio() -> dict:
    """The auralisation's figures, as the results file has them."""
    return bench_audio()


@functools.cache
def bench_forced() -> dict:
    """Figures of ``benchmarks/results/bench_forced_attractors.txt`` (written by benchmarks/bench_forced.py)."""
    text = (ROOT / "benchmarks" / "results" / "bench_forced_attractors.txt").read_text()
    total = re.search(r"^total \|\s+(\d+)\s+([\d.]+)\s+\|\s+(\d+)\s+(\d+)\s+([\d.]+)", text, re.M)
    head = re.search(r"--freq 3:7:9 \((.*?);", text)
    return {"old_cpu": total.group(2), "new_cpu": total.group(5), "old_cycles": total.group(1),
            "new_cycles": total.group(3), "newton": total.group(4), "date": head.group(1), "table": text}


def produce_bench_forced_quote() -> dict:
    """The CPU times the guide quotes from the benchmark file."""
    b = bench_forced()
    return {"new_cpu": b["new_cpu"], "old_cpu": b["old_cpu"], "date": b["date"]}


@functools.cache
def bench_forced_all() -> str:
    """``benchmarks/results/bench_forced.txt`` (``python benchmarks/bench_forced.py --quick --write``)."""
    return (ROOT / "benchmarks" / "results" / "bench_forced.txt").read_text()


def produce_bench_forced_all() -> dict:
    """Every table of the forced benchmark as its results file has it."""
    return {"table": bench_forced_all()}


def produce_bench_forced_table() -> dict:
    """The benchmark table the guide shows, as the file has it."""
    return {"table": bench_forced()["table"]}


# --------------------------------------------------------------------------- the registry
FORCED_CMD = "acoustiviz forced " + " ".join(FORCED_TABLE_ARGS) + " --csv OUT.csv"
FIELD_CMD = "python benchmarks/bench_field.py --write"
DYNAMICS_CMD = "python benchmarks/bench_dynamics.py --write"
LEVELS_CMD = "python benchmarks/bench_levels.py --quick --write"
SWEEP_CMD = "acoustiviz " + " ".join(SWEEP_ARGS)
DESIGN_CMD = "acoustiviz " + " ".join(DESIGN_ARGS) + " --rank-by lafmax_db"
AURALIZE_CMD = "acoustiviz auralize --wav damper.wav --levels"
WAV_5S_CMD = "acoustiviz levels damper.wav --csv first5s.csv --start 0 --stop 5 --loudness"
def produce_bench_sweep_levels() -> dict:
    """The extra cost of a design's levels in a sweep, from ``bench_sweep.txt``.

    Rounded to 10 ms and to a whole factor: the text says "about"; the file has the measured times.
    """
    text = _benchmark("bench_sweep")
    m = re.search(r"one design alone, serial .*?: ([\d.]+) ms without levels, ([\d.]+) ms with", text)
    base, lev = float(m.group(1)), float(m.group(2))
    return {"ms": f"{10 * round((lev - base) / 10):d}", "times": f"{round(lev / base):d}"}


@functools.cache
def bench_room_wav() -> dict:
    """Section 4 of ``benchmarks/results/bench_room.txt``: the room's WAV against free field."""
    text = _benchmark("bench_room")
    exact = re.search(r"exact images: order (\d+) \(([\d,]+) images\)", text)
    ratios = {name: [float(x) for x in re.findall(pattern + r"\s+[\d.]+\s+([\d.]+)$", text, re.M)]
              for name, pattern in (("exact", r"(?:exact images: order \d+ \([\d,]+ images\)|"
                                             r"--room 6,4,3 --absorption 0\.1)"),
                                    ("tail", r"(?:--late-tail(?: --absorption-bands \(6 bands\))?: order \d+ "
                                             r"\(\d+ images\)|--late-tail)"))}
    transition = re.search(r"tail: neglected energy [-\d.]+ dB, transition ([\d.]+) ms", text).group(1)
    return {"order": exact.group(1), "mimages": f"{int(exact.group(2).replace(',', '')) / 1e6:.1f}",
            "transition": transition,
            "lo": f"{min(ratios['tail']):.1f}", "hi": f"{max(ratios['tail']):.1f}",
            "ex_lo": f"{10 * round(min(ratios['exact']) / 10):d}",
            "ex_hi": f"{10 * round(max(ratios['exact']) / 10):d}"}


def bench_room_field() -> dict:
    """Section 3 of ``benchmarks/results/bench_room.txt``: a room point's peak and SEL, per receiver, on all cores."""
    text = _benchmark("bench_room")
    per = float(re.search(r"^fast_peaks, peak \+ SEL in one pass\s+[\d.]+\s+([\d.]+)$", text, re.M).group(1))
    threads = re.search(r"receivers on (\d+) threads?", text).group(1)
    return {"ms": f"{per:.1g}", "cores": {"1": "one core", "2": "two cores"}.get(threads, f"{threads} cores")}


def produce_bench_startup() -> dict:
    """The README main job's CPU time, cold (empty kernel cache) and warm, from ``bench_startup.txt``.

    Rounded to the second below 20 s and to 5 s above: the text says "about"; the file has the
    measured seconds.
    """
    text = _benchmark("bench_startup")
    cold = float(re.search(r"^run cold\s+[\d.]+\s+([\d.]+)", text, re.M).group(1))
    warm = float(re.search(r"^run warm\s+[\d.]+\s+([\d.]+)", text, re.M).group(1))

    def about(x):
        return f"{round(x):d}" if x < 20.0 else f"{5 * round(x / 5):d}"

    return {"cold": about(cold), "warm": about(warm)}


_WORDS = ("no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine")


def _operation_sections() -> tuple[list, list, list]:
    """``benchmarks/results/operation.md``: the transient table's rows, its rtols, and the before/after rows.

    Transient rows: (design, tight CPU s, cycles, [(CPU s, diff, unit) per rtol], tight regime); before/after rows:
    (design, before CPU s, before worst mm, its se mm, before regime, after CPU s, after worst mm, after regime).
    """
    text = (ROOT / "benchmarks" / "results" / "operation.md").read_text(encoding="utf-8")
    head = re.search(r"^\s+design \| tight s .*$", text, re.M)
    rtols = re.findall(r"\|\s+([\d.e-]+) s cycles\s+diff", head.group(0))
    transient = []
    for line in text[head.end():].splitlines()[1:]:
        if line.strip().startswith("mean CPU s"):
            break
        cells = [c.strip() for c in line.split("|")]
        tight = cells[1].split()
        sides = [(float(c.split()[0]), float(c.split()[2]), c.split()[3]) for c in cells[2:2 + len(rtols)]]
        transient.append((cells[0], float(tight[0]), int(tight[1]), sides, tight[4]))
    before_after = re.findall(
        r"^\s+(.+?) \|\s+([\d.]+)\s+\d+\s+([\d.]+) ([\d.]+)\s+(\w+)\s+[\d.]+\s+\d+ \|\s+([\d.]+)\s+\d+\s+([\d.]+) "
        r"[\d.]+\s+(\w+)\s+[\d.]+\s+\d+\s+[-+\d.]+ (?:se|um)$", text, re.M)
    return transient, rtols, before_after


#: The command that writes ``benchmarks/results/operation.md``.
OPERATION_BENCH_CMD = ("python benchmarks/bench_operation.py --before CHECKOUT --transient 1.1e-10,1e-9,1e-8,1e-7,1e-6 "
                       "--wide --write")


def produce_operation_cost() -> dict:
    """The guide's cost of a design's search in operation, from ``benchmarks/results/operation.md``.

    ``python benchmarks/bench_operation.py --before CHECKOUT --transient 1.1e-10,1e-9,1e-8,1e-7,1e-6 --wide
    --write``: the small grid's mean CPU s (the "after" side), the Table 1 design's (m 40.5 g), the range over
    every design of the transient table and their mean cycles; per transient rtol the CPU saved against the
    tight search and the largest worst-case move in standard errors; the 42.5 g design before and after.
    """
    transient, rtols, rows = _operation_sections()
    after = {r[0]: r for r in rows}
    tight = [t[1] for t in transient]
    mean = sum(tight) / len(tight)

    def saved(rtol):
        k = rtols.index(rtol)
        return f"{100 * (1 - sum(t[3][k][0] for t in transient) / sum(tight)):.0f}"

    def largest(rtol):
        k = rtols.index(rtol)
        return max(abs(t[3][k][1]) for t in transient if t[3][k][2] == "se")

    loose = ("1e-8", "1e-7", "1e-6")
    k11 = rtols.index("1.1e-10")
    turned = sum(1 for t in transient if t[4] == "periodic" and t[3][k11][2] == "se")  # the other side chaotic
    m425 = after["m 42.5 g"]
    return {"design": f"{sum(float(r[5]) for r in rows) / len(rows):.1f}",
            "table1": f"{float(after['m 40.5 g'][5]):.1f}",
            "lo": f"{min(tight):.1f}", "hi": f"{max(tight):.1f}",
            "cycles": f"{1000 * round(sum(t[2] for t in transient) / len(transient) / 1000):,}".replace(",", " "),
            "s8": saved("1e-8"), "s7": saved("1e-7"), "s6": saved("1e-6"), "tight": f"{mean:.2f}",
            "mlo": f"{min(largest(r) for r in loose):.0f}", "mhi": f"{max(largest(r) for r in loose):.0f}",
            "d11": f"{largest('1.1e-10'):.1f}", "turned": _WORDS[turned],
            "before": f"{float(m425[2]):.1f}", "before_se": f"{float(m425[3]):.1f}", "after": f"{float(m425[6]):.1f}"}


def produce_contact_steps() -> dict:
    """Steps per contact at rtol 1e-10 (``python benchmarks/bench_contact_steps.py --write``), to whole steps."""
    row = re.search(r"^\s+this\s+1e-10 \|\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)",
                    _benchmark("bench_contact_steps"), re.M)
    tried, rej, peak, end = (round(float(x)) for x in row.groups())
    return {"tried": str(tried), "rej": str(rej), "end": str(end), "peak": _WORDS[peak]}


#: The libraries of the comparison in operation: the guide's group suffix -> the results file's name.
OPERATION_LIBRARIES = {"acv": "acoustiviz optimize (optuna TPE, penalty)", "plain": "optuna TPE (constraint not told)",
                       "cf": "optuna TPE (constraints_func)", "pymoo": "pymoo NSGA-II",
                       "scipy": "scipy differential_evolution"}


def produce_optimisers_operation() -> dict:
    """The guide's table of the libraries in operation (``python benchmarks/bench_optimisers.py --mode operation``).

    Per library: the mean over the seeds of each run's best ``min_reduction_db`` in (a), the runs
    within the tolerance of the reference, and the mean hypervolume in (b) as a share of the reference's.
    """
    _, text = _optimisers()
    runs = _by_library(_md_rows(text, "| library | seed | best min_reduction_db"))
    two = {r[0]: r for r in _md_rows(text, "| library | mean hypervolume")}
    out = {"distinct": re.search(r"(\d+) distinct designs evaluated in all", text).group(1),
           "ref_a": re.search(r"best feasible value of every evaluation = (-?[\d.]+) dB", text).group(1),
           "ref_b": re.search(r"front of every evaluation = ([\d.]+) dB²", text).group(1),
           "grid_a": re.search(r"grid alone = (-?[\d.]+) dB;", text).group(1),
           "grid_b": re.search(r"grid alone = ([\d.]+) dB²", text).group(1)}
    for key, name in OPERATION_LIBRARIES.items():
        rows = runs[name]
        out[f"a_{key}"] = f"{sum(float(r[2]) for r in rows) / len(rows):.2f}"
        out[f"n_{key}"] = f"{sum(r[6] == 'yes' for r in rows)} of {len(rows)}"
        if key != "scipy":
            out[f"b_{key}"] = two[name][2]
    return out

# --------------------------------------------------------------------------- several balls (docs/guide/balls.md)
def _md_rows(text: str, head: str) -> list:
    """Cells of the rows of the Markdown table whose header line starts with ``head``."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(head))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip("|").split("|")])
    return rows


def produce_bench_balls() -> dict:
    """Figures of ``benchmarks/results/balls.md`` (``python benchmarks/bench_balls.py``)."""
    text = (ROOT / "benchmarks" / "results" / "balls.md").read_text(encoding="utf-8")
    big = _md_rows(text, "| balls | simulated s | collisions | CPU s | CPU ms")[0]
    ref = _md_rows(text, "| balls | collisions | simulated s | SciPy")
    cost = _md_rows(text, "| balls | simulated s | collisions | CPU s | CPU us")
    diffs = {r[0]: float(r[6]) for r in ref}
    return {"ratio": _range([float(r[5]) for r in ref], ".0f"),
            "dt2": _bound(diffs["2"]), "dt35": _bound(max(v for k, v in diffs.items() if k != "2")),
            "per_body": _range([float(r[5]) for r in cost], ".0f"),
            "n_big": big[0], "collisions_big": big[2], "cpu_big": big[3]}


@functools.cache
def produce_one_ball() -> dict:
    """One ball in ``simulate_balls`` against the single-ball event solver: 20 s of Table 1, every impact."""
    import numpy as np

    from acoustiviz.dynamics import DamperModel, MultiBallModel, simulate, simulate_balls

    model = DamperModel()
    a = simulate(model, 20.0).impacts
    b = simulate_balls(MultiBallModel.from_damper(model, 1), 20.0).impacts
    names = ("time", "approach_velocity", "separation_velocity", "peak_force", "impulse", "energy_lost")
    same = len(a) == len(b) and all(np.array_equal(getattr(a, k), getattr(b, k)) for k in names)
    return {"n": str(len(a)), "same": "equal" if same else "not equal"}


@functools.cache
def produce_balls_gallery() -> dict:
    """``gallery/plot_17_balls.py``: its printed tables, and the prose of the guide drawn from its results."""
    run = _gallery("plot_17_balls.py")
    res = run["namespace"]["results"]
    op = run["namespace"]["operating"]
    best = max(res, key=lambda n: res[n]["reduction"])
    worst = [r["reduction_db"] for r in op.values()]
    free, _, operating = run["text"].partition("in operation:")
    return {"table": free, "operating_table": "in operation:" + operating,
            **{f"{key}{n}": f"{op[n][key + '_db']:.1f}" for n in op for key in ("lcpeak", "laeq", "reduction")},
            "drop2": f"{op[1]['laeq_db'] - op[2]['laeq_db']:.1f}",
            "drop5": f"{op[1]['laeq_db'] - op[5]['laeq_db']:.1f}",
            "cop1": f"{op[1]['collisions_per_cycle']:.1f}", "cop5": f"{op[5]['collisions_per_cycle']:.1f}",
            "spread": f"{max(worst) - min(worst):.1f}",
            "resonance": f"{run['namespace']['resonance']:.2f}",
            "red1": f"{100 * res[1]['reduction']:.0f}", "red_best": f"{100 * res[best]['reduction']:.0f}",
            "best": str(best), "red10": f"{100 * res[10]['reduction']:.0f}",
            "settle1": f"{res[1]['settling']:.1f}", "settle_best": f"{res[best]['settling']:.1f}",
            "settle10": f"{res[10]['settling']:.1f}",
            "f1": f"{res[1]['peak_force']:.0f}", "f2": f"{res[2]['peak_force']:.0f}",
            "f10": f"{res[10]['peak_force']:.0f}", "med1": f"{res[1]['median_force']:.0f}",
            "med10": f"{res[10]['median_force']:.0f}",
            "c1": str(res[1]["collisions"]), "c10": str(res[10]["collisions"])}


BALLS_CMD = "python gallery/plot_17_balls.py"


def produce_choose_damper() -> dict:
    """``gallery/plot_18_choose_damper.py``: its printed text, and the guide's comparison drawn from its results."""
    run = _gallery("plot_18_choose_damper.py")
    ns = run["namespace"]
    chosen, t1, other = ns["chosen"], ns["paper"][ns["REFERENCE"]], list(ns["paper"].values())[1]
    x, y = ns["X"], ns["Y"]
    return {"text": run["text"], "m": f"{1e3 * chosen['mass_kg']:.1f}", "gap": f"{100 * chosen['gap_m']:.2f}",
            "red": f"{chosen[y]:.2f}", "t1_red": f"{t1[y]:.2f}", "dlcpeak": f"{t1[x] - chosen[x]:.1f}",
            "dlaeq": f"{t1['worst_laeq_db'] - chosen['worst_laeq_db']:.1f}", "other_red": f"{other[y]:.2f}"}


CHOOSE_CMD = "python gallery/plot_18_choose_damper.py"
#: The gallery's optimisation in operation on the command line (the job ``plot_18_choose_damper.py`` builds).
CHOOSE_ARGS = ["optimize", "--gap", "0.02:0.06", "--m", "0.02:0.08", "--force", "5", "--freq", "4.5:5.5:5", "--starts",
               "2", "--max-cycles", "200", "--noise-seconds", "0.2", "--maximize", "min_reduction_db", "--minimize",
               "worst_lcpeak_db", "--evaluations", "20", "--batch", "10", "--workers", "2", "--out", "opt"]


def produce_choose_damper_cli() -> dict:
    """The console block of the gallery's optimisation in operation, run on the command line."""
    return {"output": _cli(CHOOSE_ARGS, cwd=_workdir("optimize"))}


# --------------------------------------------------------------------------- optimisers (docs/guide/optimize.md)
def _optimisers() -> tuple[str, str]:
    """``benchmarks/results/optimisers.md`` cut into its free-vibration part and its part in operation."""
    text = (ROOT / "benchmarks" / "results" / "optimisers.md").read_text(encoding="utf-8")
    free, _, operation = text.partition("## In operation")
    return free, operation


def _by_library(rows) -> dict:
    """``{library: [row, ...]}`` of a table whose first cell names the library."""
    out = {}
    for row in rows:
        out.setdefault(row[0], []).append(row)
    return out


def produce_optimisers_free() -> dict:
    """The guide's table of the libraries in free vibration (``python benchmarks/bench_optimisers.py``)."""
    free, _ = _optimisers()
    ref = float(re.search(r"grid = ([\d.]+) dB", free).group(1))
    by = _by_library(_md_rows(free, "| library | seed | best value found (dB)"))

    def passed(name):
        return f"{sum(r[4] == 'yes' for r in by[name])} of {len(by[name])}"

    acv, scipy = "acoustiviz optimize (optuna TPE, penalty)", "scipy differential_evolution"
    above = _range([float(r[2]) - ref for r in by[acv]], ".3f", "–")
    return {"ref": f"{ref:.3f}", "acv": passed(acv), "acv_above": above,
            "optuna": passed("optuna TPE"), "pymoo": passed("pymoo NSGA-II"), "scipy": passed(scipy),
            "scipy_n": _range([int(r[3]) for r in by[scipy]], "d", "–")}

REGISTRY = (
    Figure("rooms-wav-images", "docs/guide/rooms.md",
           r"A reverberant room needs many images for -60 dB\s+\(order (?P<order>\d+), (?P<mimages>[\d.]+) million "
           r"images, in the 6 x 4 x 3 m room", bench_room_wav, "python benchmarks/bench_room.py"),
    Figure("rooms-wav-transition", "docs/guide/rooms.md",
           r"once per contact duration of the shortest click \((?P<transition>[\d.]+) ms in",
           bench_room_wav, "python benchmarks/bench_room.py"),
    Figure("rooms-wav-speed", "docs/guide/rooms.md",
           r"takes (?P<lo>[\d.]+) to (?P<hi>[\d.]+) times as long as\s+in free field .*?instead of about "
           r"(?P<ex_lo>\d+) to (?P<ex_hi>\d+) times", bench_room_wav, "python benchmarks/bench_room.py"),
    Figure("rooms-map-cost", "docs/guide/rooms.md",
           r"about (?P<ms>[\d.]+) ms per point on (?P<cores>one core|two cores|\d+ cores) at order 10",
           bench_room_field, "python benchmarks/bench_room.py"),
    Figure("sweep-levels-cost", "docs/guide/sweeps.md",
           r"It costs about (?P<ms>\d+) ms more per 20 s design, (?P<times>\d+) times the\s+motion alone",
           produce_bench_sweep_levels, "python benchmarks/bench_sweep.py"),
    Figure("readme-startup", "README.md",
           r"on a 2-core machine about (?P<cold>\d+) s of CPU the first time, most of it\s+compiling the numba "
           r"kernels once per installation, then (?P<warm>\d+) s; measured by `benchmarks/bench_startup\.py`",
           produce_bench_startup, "python benchmarks/bench_startup.py"),
    Figure("forced-table", "docs/guide/operation.md",
           r"```console\n\$ " + re.escape(FORCED_CMD) + r"\n(?P<output>.*?)```", produce_forced_table, FORCED_CMD),
    Figure("forced-coexisting", "docs/guide/operation.md",
           r"several attractors coexist at (?P<several>\d+) of the (?P<total>\d+) frequencies; the motion is chaotic "
           r"at (?P<chaotic>[\d., ]+) Hz", produce_coexisting, FORCED_CMD),
    Figure("readme-forced-coexisting", "README.md",
           r"several motions coexist at (?P<several>\d+) of the (?P<total>\d+) frequencies", produce_coexisting,
           FORCED_CMD),
    Figure("readme-headline-forced", "README.md",
           r"Driven by\s+5 N at 5 Hz, next to the structure's 5\.03 Hz resonance, the starts find\s+"
           r"(?P<attractors>[^(]+?) \((?P<regime>[a-z, -]+)\); it cuts the\s+vibration amplitude by "
           r"(?P<red>[\d.]+) dB \((?P<a0>[\d.]+) m to "
           r"(?P<amp>[\d.]+) ± (?P<err>[\d.]+) m\) while its clicks reach LCpeak (?P<lcpeak>[\d.]+) dB and\s+LAeq "
           r"(?P<laeq>[\d.]+) dB", produce_headline_forced,
           "acoustiviz forced --force 5 --freq 5 (Table 1 damper)"),
    Figure("readme-headline-damper", "README.md",
           r"prints them\):\s+(?P<impacts>\d+) impacts, peak SPL\s+(?P<peak>[\d.]+) dB, LCpeak (?P<lcpeak>[\d.]+) "
           r"dB, LAFmax (?P<lafmax>[\d.]+) dB, LAeq (?P<laeq>[\d.]+) dB, SEL\(A\) (?P<sela>[\d.]+) dB,\s+sound power\s+"
           r"(?P<lw>[\d.]+) dB re 1 pW, its loudest impact turning (?P<eff>[\d.]+) % of the energy",
           produce_headline_damper, "acoustiviz run --out DIR (default scene, its levels output)"),
    Figure("operation-cost", "docs/guide/operation.md",
           r"a search from scratch takes about (?P<design>[\d.]+) CPU s a design, (?P<table1>[\d.]+) s for Table 1\s+"
           r"itself, and (?P<lo>[\d.]+) to (?P<hi>[\d.]+) s across gaps of 20-60 mm and impact masses of 20-80 g; "
           r"some (?P<cycles>[\d ]+) forcing\s+cycles a design", produce_operation_cost, OPERATION_BENCH_CMD),
    Figure("operation-transients", "docs/guide/operation.md",
           r"1e-8, 1e-7 and 1e-6 save about (?P<s8>\d+) %, (?P<s7>\d+) % and (?P<s6>\d+) % of the CPU time "
           r"\((?P<tight>[\d.]+) CPU s a design at 1e-10\).*?by up to (?P<mlo>\d+) to (?P<mhi>\d+) standard errors\. "
           r"Transients at\s+1\.1e-10, a tenth looser, move worst cases as much: by up to (?P<d11>[\d.]+) standard "
           r"errors, turning (?P<turned>\w+)\s+periodic worst cases chaotic", produce_operation_cost,
           OPERATION_BENCH_CMD),
    Figure("operation-rounding", "docs/guide/operation.md",
           r"a chaotic worst case of\s+(?P<before>[\d.]+) ± (?P<before_se>[\d.]+) mm with the forcing evaluated by a "
           r"sine and cosine at every stage,\s+and a periodic orbit of (?P<after>[\d.]+) mm", produce_operation_cost,
           OPERATION_BENCH_CMD),
    Figure("operation-contact-steps", "docs/guide/operation.md",
           r"each is some (?P<tried>\d+) DOP853 steps in the regularised time with about (?P<rej>\d+)\s+rejected, "
           r"plus about (?P<end>\d+) full steps locating its end and (?P<peak>\w+) locating its peak force",
           produce_contact_steps, "python benchmarks/bench_contact_steps.py --write"),
    Figure("bench-forced-quote", "docs/guide/operation.md",
           r"took (?P<new_cpu>[\d.]+) s of CPU against (?P<old_cpu>[\d.]+) s for the single start of before "
           r"\((?P<date>[^)]*)\)", produce_bench_forced_quote,
           "python benchmarks/bench_forced.py --attractors --write"),
    Figure("bench-forced-row", "docs/guide/speed_accuracy.md",
           r"6 starts each, in (?P<new_cpu>[\d.]+) s of CPU against (?P<old_cpu>[\d.]+) s for one start",
           produce_bench_forced_quote, "python benchmarks/bench_forced.py --attractors --write"),
    Figure("bench-forced-tables", "docs/guide/speed_accuracy.md",
           r"with the machine and the date\):\n\n```text\n(?P<table>.*?)```", produce_bench_forced_all,
           "python benchmarks/bench_forced.py --quick --write"),
    Figure("bench-forced-table", "docs/guide/operation.md",
           r"```text\n(?P<table>6\. every attractor.*?)```", produce_bench_forced_table,
           "python benchmarks/bench_forced.py --attractors --write"),
    # docs/guide/hearing.md
    Figure("hearing-auralize", "docs/guide/hearing.md",
           r"```console\n\$ acoustiviz auralize --wav damper\.wav --levels\n(?P<output>.*?)```",
           produce_hearing_auralize, AURALIZE_CMD),
    Figure("hearing-auralize-prose", "docs/guide/hearing.md",
           r"loudest part \(LCpeak (?P<lcpeak>\d+) dB\) while the A-weighted, 125 ms-averaged LAFmax is "
           r"(?P<c_minus_a>\d+) dB lower, and\s+the average over the run \(LAeq\) another (?P<f_minus_eq>\d+) dB lower",
           produce_hearing_auralize, AURALIZE_CMD),
    Figure("hearing-sidecar", "docs/guide/hearing.md", r"```json\n(?P<json>.*?)```", produce_hearing_sidecar,
           AURALIZE_CMD),
    Figure("hearing-band-limit", "docs/guide/hearing.md",
           r"peak, here by (?P<pct>[\d.]+) % \((?P<db>[\d.]+) dB\)", produce_hearing_sidecar, AURALIZE_CMD),
    Figure("hearing-wav-levels", "docs/guide/hearing.md",
           r"```console\n\$ acoustiviz levels damper\.wav --csv levels\.csv\n(?P<output>.*?)```",
           produce_hearing_wav_levels, "acoustiviz levels damper.wav --csv levels.csv"),
    Figure("hearing-wav-5s", "docs/guide/hearing.md",
           r"```console\n\$ acoustiviz levels damper\.wav --csv first5s\.csv --start 0 --stop 5 --loudness\n"
           r"(?P<output>.*?)```", produce_hearing_wav_5s, WAV_5S_CMD),
    Figure("hearing-wav-5s-prose", "docs/guide/hearing.md",
           r"LAeq is (?P<above>\d+) dB above that of the whole run", produce_hearing_wav_5s, WAV_5S_CMD),
    Figure("hearing-designs", "docs/guide/hearing.md", r"```text\n(?P<table>design .*?)```",
           produce_hearing_designs, "python gallery/plot_14_levels.py"),
    Figure("hearing-designs-prose", "docs/guide/hearing.md",
           r"\(LAeq is (?P<eq_minus_z>\d+) dB above LZeq\); the quieter\s+design is about (?P<quieter_db>\d+) dB "
           r"quieter by every level and (?P<less_loud>\d+) % less loud", produce_hearing_designs,
           "python gallery/plot_14_levels.py"),
    Figure("hearing-energy", "docs/guide/hearing.md",
           r"the loudest impact turns (?P<eff1>[\d.]+) %\s+of the energy it destroys into sound \((?P<eff2>[\d.]+) % "
           r"for the quieter design\), and the run radiates a sound\s+power level of (?P<lw>[\d.]+) dB re 1 pW",
           produce_hearing_energy, "python gallery/plot_14_levels.py"),
    # docs/guide/sweeps.md
    Figure("sweeps-sweep", "docs/guide/sweeps.md",
           r"```console\n\$ " + re.escape(SWEEP_CMD) + r"\n(?P<output>.*?)```", produce_sweep_run, SWEEP_CMD),
    Figure("sweeps-design", "docs/guide/sweeps.md",
           r"```console\n\$ " + re.escape(DESIGN_CMD) + r"\n(?P<output>.*?)```", produce_design_lafmax, DESIGN_CMD),
    Figure("sweeps-design-max-spl", "docs/guide/sweeps.md",
           r"ranked by the paper's measure differ by (?P<spread>[\d.]+) dB", produce_design_max_spl,
           "acoustiviz " + " ".join(DESIGN_ARGS)),
    Figure("sweeps-refused", "docs/guide/sweeps.md", r"```text\n  (?P<error>acoustiviz sweep: error: --out: [^\n]*)\n",
           produce_sweep_refused, "acoustiviz sweep --gap 0.02:0.06:4 ... --out sw"),
    # the benchmark result files: the README's field timing and docs/guide/speed_accuracy.md
    Figure("readme-field-timing", "README.md",
           r"at (?P<n_fast>1e\d) points of a\s+wall-floor corner in (?P<fp_s>[\d.-]+) s of one core with the exact "
           r"Hertz pulse, within (?P<fp_err_bound>[\de.-]+) of the peak", produce_bench_field, FIELD_CMD),
    Figure("bench-field-row", "docs/guide/speed_accuracy.md",
           r"\| `python benchmarks/bench_field\.py \[--quick\]` \| (?P<rate>[\d.e-]+) point-samples/s per core "
           r"for peaks/RMS, (?P<speedup>[\d-]+)× a per-point convolution; the exact Hertz pulse at "
           r"(?P<hertz_cost>[\d.-]+)× the half-sine's cost with errors ≤ (?P<hertz_err>[\de.-]+) "
           r"\(the former sampled pulse: (?P<sampled_cost>[\d-]+)× the cost, errors (?P<sampled_err>[\de.-]+)\); "
           r"SEL of 1e6 points without a time grid at (?P<sel_rate>[\de.-]+) points/s, peaks and SEL of "
           r"(?P<n_fast>1e\d) corner points in (?P<fp_s>[\d.-]+) s with the exact Hertz pulse "
           r"\((?P<fp_total>[\d.]+) s with its setup; `field\.fast_peaks`, (?P<fp_x>\d+)× `field_metrics`, "
           r"(?P<missed>no peak|\d+ peaks?) missed against a second search\); 1e6 points in (?P<mem>[\d.]+) MiB",
           produce_bench_field, FIELD_CMD),
    Figure("bench-field-table", "docs/guide/speed_accuracy.md",
           r"all images summed; one thread\.\n\n```text\n(?P<table>.*?)```", produce_bench_field, FIELD_CMD),
    Figure("bench-field-prose", "docs/guide/speed_accuracy.md",
           r"to rounding, and `field_metrics` costs (?P<hertz_pct>[\d-]+) % more\s+with it; the former pulse sampled "
           r"at 1025 points and interpolated linearly cost (?P<sampled_cost>[\d-]+)× as much\s+for errors of "
           r"(?P<sampled_err_lo>[\de.-]+) to (?P<sampled_err>[\de.-]+) of the peak", produce_bench_field, FIELD_CMD),
    Figure("bench-field-fast-peaks", "docs/guide/speed_accuracy.md",
           r"the exposure of (?P<n_fast>1e\d) corner\s+points in (?P<fp_s>[\d.-]+) s of one core with the exact Hertz "
           r"pulse \((?P<fp_total>[\d.]+) s with the setup of its\s+tables; (?P<hs_s>[\d.-]+) s for the half-sine\), "
           r"(?P<fp_x>\d+) times faster than `field_metrics`, which it matches to\s+(?P<fp_err>[\de.-]+) of the peak"
           r".*?no time grid, (?P<sel_err>[\de.-]+) from the quadrature reference.*?closed form: "
           r"(?P<differ>none differ|\d+ differ)\.", produce_bench_field, FIELD_CMD),
    Figure("bench-dynamics-row", "docs/guide/speed_accuracy.md",
           r"event solver at its default tolerance: 3 s of Table 1 \((?P<impacts>\d+) impacts\) in (?P<ms>[\d.]+) ms, "
           r"first 40 impacts within (?P<du>[\de.-]+) \(speed\) and (?P<dt>[\de.-]+) s \(time\), about "
           r"(?P<speedup>\d+)× the paper's Newmark at 1e-7 s; 20 s \((?P<impacts20>\d+) impacts\) in "
           r"(?P<ms20>[\d.]+) ms", produce_bench_dynamics, DYNAMICS_CMD + "; --full for 20 s"),
    Figure("bench-dynamics-table", "docs/guide/speed_accuracy.md",
           r"then times\nevery solver setting:\n\n```text\n(?P<table>.*?)```", produce_bench_dynamics, DYNAMICS_CMD),
    Figure("bench-dynamics-prose", "docs/guide/speed_accuracy.md",
           r"confirm there \(du/u (?P<ivp_du>[\de.+-]+) over the first 40\)\.\s+Newmark\s+agrees with the reference "
           r"on at most the first (?P<newmark_agree>\d+) impacts even at a step of 1e-7 s, and the impact\s+map "
           r"\(instantaneous\s+impacts\) on (?P<map_agree>the first [\w ]+ only)\.", produce_bench_dynamics,
           DYNAMICS_CMD),
    Figure("bench-levels-row", "docs/guide/speed_accuracy.md",
           r"20 s at 96 kHz: 8 weighted levels in (?P<wl>[\d.]+) s, 30 bands in (?P<bands>[\d.]+) s; a 48 kHz "
           r"rendering moves each level by ≤ (?P<dmax>[\d.]+) dB; radiated energy by closed form and surface "
           r"work within (?P<sw>[\de.-]+)", produce_bench_levels, LEVELS_CMD),
    Figure("bench-levels-table", "docs/guide/speed_accuracy.md",
           r"\{doc\}`hearing`\):\n\n```text\n(?P<table>.*?)```", produce_bench_levels, LEVELS_CMD),
    Figure("bench-levels-prose", "docs/guide/speed_accuracy.md",
           r"128-direction grid\s+within (?P<free>[\de.-]+)\)\. On the plane the grid has converged to "
           r"(?P<plane>[\de.-]+) at 128 directions; in the corner the\s+quick run's two resolutions still differ by "
           r"(?P<corner>[\d.]+) %.*?A 48 kHz rendering is good to (?P<dmax>[\d.]+) dB for every level",
           produce_bench_levels, LEVELS_CMD),
    Figure("bench-audio-row", "docs/guide/speed_accuracy.md",
           r"20 s of a Table 1 run at 48 kHz in (?P<hs>[\d.]+) s \(half-sine, mono; (?P<hertz>[\d.]+) s with the exact "
           r"Hertz pulse\), (?P<xrt>[\d-]+)× real time", produce_bench_audio,
           "python benchmarks/bench_audio.py --write"),
    # docs/guide/balls.md
    Figure("balls-bench", "docs/guide/balls.md",
           r"the compiled solver is (?P<ratio>[\d-]+) times faster on the first 20 collisions,\s+and the collision "
           r"times of the two agree within (?P<dt2>[\de.-]+) s \(2 balls\) and (?P<dt35>[\de.-]+) s \(3 and 5 balls\)"
           r".*?(?P<per_body>[\d-]+) us of CPU per collision and body\. (?P<n_big>\d+) balls\s+over 20 s of the Table 1"
           r" damper make (?P<collisions_big>\d+) collisions in (?P<cpu_big>[\d.]+) s of CPU", produce_bench_balls,
           "python benchmarks/bench_balls.py"),
    Figure("balls-one-ball", "docs/guide/balls.md",
           r"over 20 s of Table 1 the (?P<n>\d+) impacts' times, speeds, peak forces, impulses and energies\s+lost are "
           r"(?P<same>equal|not equal)", produce_one_ball, "simulate_balls (1 ball) against simulate, 20 s of Table 1"),
    Figure("balls-table", "docs/guide/balls.md",
           r"```text\n(?P<table>\d+ s of the Table 1 structure, 40\.5 g.*?)```", produce_balls_gallery, BALLS_CMD),
    Figure("balls-vibration", "docs/guide/balls.md",
           r"the RMS reduction rises from (?P<red1>\d+) % with one\s+ball to (?P<red_best>\d+) % with (?P<best>\d+) "
           r"\(settling in (?P<settle_best>[\d.]+) s instead of (?P<settle1>[\d.]+) s\), then falls back to "
           r"(?P<red10>\d+) %\s+with 10 \(settling in (?P<settle10>[\d.]+) s\)", produce_balls_gallery, BALLS_CMD),
    Figure("balls-forces", "docs/guide/balls.md",
           r"force rises from (?P<f1>\d+) N with one ball to (?P<f2>\d+) N with two,.*?many balls \((?P<f10>\d+) N "
           r"with 10\); the median peak force falls from (?P<med1>\d+) N to (?P<med10>\d+) N, but\s+the collisions "
           r"multiply, from (?P<c1>\d+) to (?P<c10>\d+)\.", produce_balls_gallery, BALLS_CMD),
    Figure("balls-operating-table", "docs/guide/balls.md",
           r"```text\n(?P<operating_table>in operation: 5 N at .*?)```", produce_balls_gallery, BALLS_CMD),
    Figure("balls-operating", "docs/guide/balls.md",
           (r"around its resonance with the balls on it \((?P<resonance>[\d.]+) Hz\).*?"
            r"LCpeak from (?P<lcpeak1>[\d.]+) dB with one ball to (?P<lcpeak2>[\d.]+), (?P<lcpeak3>[\d.]+) and "
            r"(?P<lcpeak5>[\d.]+) dB with 2, 3 and 5, and LAeq from (?P<laeq1>[\d.]+) dB to (?P<laeq2>[\d.]+), "
            r"(?P<laeq3>[\d.]+) and (?P<laeq5>[\d.]+) dB, while the collisions per cycle multiply \((?P<cop1>[\d.]+) "
            r"to (?P<cop5>[\d.]+)\)\. The worst vibration reduction over the band hardly depends on N "
            r"\((?P<reduction1>[\d.-]+), (?P<reduction2>[\d.-]+), (?P<reduction3>[\d.-]+) and (?P<reduction5>[\d.-]+) "
            r"dB\).*?within (?P<spread>[\d.]+) dB.*?the model finds it falling by (?P<drop2>[\d.]+) dB \(LAeq\) from "
            r"one ball to two and (?P<drop5>[\d.]+) dB to five").replace(" ", r"\s+"),
           produce_balls_gallery, BALLS_CMD),
    Figure("choose-damper-cli", "docs/guide/optimize.md",
           r"```console\n\$ " + r"(?: \\\n\s*| )".join(re.escape(a) for a in ["acoustiviz", *CHOOSE_ARGS])
           + r"\n(?P<output>.*?)```", produce_choose_damper_cli, "acoustiviz " + " ".join(CHOOSE_ARGS)),
    Figure("choose-damper-text", "docs/guide/optimize.md",
           r"```text\n(?P<text>\d+ designs evaluated in operation at .*?)```", produce_choose_damper, CHOOSE_CMD),
    Figure("choose-damper-prose", "docs/guide/optimize.md",
           (r"The chosen design \(m = (?P<m>[\d.]+) g, d = (?P<gap>[\d.]+) cm\) keeps Table 1's worst-case reduction "
            r"\((?P<red>[\d.-]+) dB against (?P<t1_red>[\d.-]+) dB\) with a worst LCpeak (?P<dlcpeak>[\d.-]+) dB and "
            r"a worst LAeq (?P<dlaeq>[\d.-]+) dB lower;.*?is the worst of the three in operation "
            r"\((?P<other_red>[\d.-]+) dB\)").replace(" ", r"\s+"), produce_choose_damper, CHOOSE_CMD),
    Figure("optimisers-free", "docs/guide/optimize.md",
           r"900 designs, (?P<ref>[\d.]+) dB;.*?\| Optuna TPE, constraints as a graded penalty "
           r"\(what `optimize` runs\) \| (?P<acv>\d+ of \d+) \((?P<acv_above>[\d.–]+) dB above\) \|\n"
           r"\| Optuna TPE, its own constraint handling \| (?P<optuna>\d+ of \d+) \|\n"
           r"\| pymoo NSGA-II, constraints as `G <= 0` \| (?P<pymoo>\d+ of \d+) \|\n"
           r"\| scipy `differential_evolution` with a `NonlinearConstraint` \| (?P<scipy>\d+ of \d+), with "
           r"(?P<scipy_n>[\d–]+) evaluations \|", produce_optimisers_free, "python benchmarks/bench_optimisers.py"),
    Figure("optimisers-operation", "docs/guide/optimize.md",
           r"\((?P<distinct>\d+) designs in all, a 6 × 6 grid included;\s+best `min_reduction_db` "
           r"(?P<ref_a>-?[\d.]+) dB,\s+front hypervolume (?P<ref_b>[\d.]+) dB²; the grid alone:\s+"
           r"(?P<grid_a>-?[\d.]+) dB and (?P<grid_b>[\d.]+) dB²\).*?"
           r"\| Optuna TPE, graded penalty \(what `optimize` runs\) \| (?P<a_acv>-?[\d.]+) dB \| (?P<n_acv>\d+ of \d+) "
           r"\| (?P<b_acv>\d+ %) \|\n"
           r"\| Optuna TPE, constraint not told \| (?P<a_plain>-?[\d.]+) dB \| (?P<n_plain>\d+ of \d+) "
           r"\| (?P<b_plain>\d+ %) \|\n"
           r"\| Optuna TPE, its `constraints_func` \| (?P<a_cf>-?[\d.]+) dB \| (?P<n_cf>\d+ of \d+) "
           r"\| (?P<b_cf>\d+ %) \|\n"
           r"\| pymoo NSGA-II, constraint as `G <= 0` \| (?P<a_pymoo>-?[\d.]+) dB \| (?P<n_pymoo>\d+ of \d+) "
           r"\| (?P<b_pymoo>\d+ %) \|\n"
           r"\| scipy `differential_evolution`, `NonlinearConstraint` \| (?P<a_scipy>-?[\d.]+) dB "
           r"\| (?P<n_scipy>\d+ of \d+) \|",
           produce_optimisers_operation, "python benchmarks/bench_optimisers.py --mode operation"),
)


def _spans(fig: Figure, text: str):
    matches = list(re.finditer(fig.pattern, text, flags=re.S))
    if len(matches) != 1:
        raise LookupError(f"{fig.name}: the pattern matches {len(matches)} times in {fig.file} (expected once)")
    return matches[0]


def check(figures) -> list:
    """``(name, group, quoted, produced)`` of every quoted figure that differs (groups the pattern names)."""
    bad = []
    for fig in figures:
        m = _spans(fig, (ROOT / fig.file).read_text(encoding="utf-8"))
        for group, value in fig.produce().items():
            if group in m.re.groupindex and m.group(group) != value:
                bad.append((fig.name, group, m.group(group), value))
    return bad


def update(figures) -> list:
    """Rewrite the quoted figures; return the names of the files changed."""
    changed = []
    for fig in figures:
        path = ROOT / fig.file
        text = path.read_text(encoding="utf-8")
        m = _spans(fig, text)
        values = fig.produce()
        edits = sorted(((m.start(g), m.end(g), v) for g, v in values.items() if g in m.re.groupindex), reverse=True)
        new = text
        for a, b, v in edits:
            new = new[:a] + v + new[b:]
        if new != text:
            tmp = path.with_suffix(path.suffix + ".tmp")
            tmp.write_text(new, encoding="utf-8")
            tmp.replace(path)
            changed.append(fig.file)
    return changed


def main(argv=None) -> int:
    """Command line (module docstring); returns the exit status."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--check", action="store_true", help="exit 1 when a quoted figure differs")
    g.add_argument("--update", action="store_true", help="rewrite the quoted figures")
    g.add_argument("--list", action="store_true", help="list the registry")
    p.add_argument("--only", nargs="+", metavar="NAME", help="entries to run (default all)")
    a = p.parse_args(argv)
    figs = [f for f in REGISTRY if not a.only or f.name in a.only]
    if a.only and len(figs) != len(set(a.only)):
        p.error(f"--only: unknown names; known: {', '.join(f.name for f in REGISTRY)}")
    if a.list:
        for f in REGISTRY:
            print(f"{f.name:28s} {f.file:30s} {f.command}")
        return 0
    if a.update:
        changed = update(figs)
        print("updated " + (", ".join(sorted(set(changed))) if changed else "nothing"))
        return 0
    bad = check(figs)
    for name, group, quoted, produced in bad:
        print(f"{name}: {group}: the text says {quoted!r}, the program gives {produced!r}")
    print(f"{len(figs)} entries checked, {len(bad)} figures differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
