"""Rerun every figure the README and the guide quote from the program, and check the text.

Usage::

    python docs/numbers.py --check            # exit 1 and list every quoted figure that differs
    python docs/numbers.py --update           # rewrite the quoted figures with what the program gives now
    python docs/numbers.py --check --only forced-table   # some entries only
    python docs/numbers.py --list             # the registry

The registry (:data:`REGISTRY`) has one entry per quoted figure or block: the file, a regular
expression whose named groups are the quoted text, and the function that produces that text by
running the program (the same command the text shows). Producers share their runs (each command
runs once). Timings are machine-dependent and are not re-timed here: the text quotes them from
the committed benchmark result files (``benchmarks/results/*.txt``, written by the benchmark
scripts with the machine and the date), and the check verifies that the text says what the file
says. To add a figure: write a producer returning ``{group: text}`` and append a :class:`Figure`.
"""

from __future__ import annotations

import os
import sys

# run as a script, this file's folder comes first on sys.path, where this file would hide the
# standard library's ``numbers`` (which numpy imports): take the folder out first
_HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:] = [p for p in sys.path if os.path.abspath(p or os.curdir) != _HERE]

import argparse  # noqa: E402
import contextlib  # noqa: E402
import functools  # noqa: E402
import io  # noqa: E402
import re  # noqa: E402
import tempfile  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

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


def _cli(argv) -> str:
    """Stdout of ``acoustiviz ARGV`` (status 0 required), with timings replaced by :data:`TIME`."""
    from acoustiviz.cli import main

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rc = main(list(argv))
    if rc != 0:
        raise RuntimeError(f"acoustiviz {' '.join(argv)} exited with {rc}")
    text = buf.getvalue()
    text = re.sub(r"in \d+\.\d+ s\b", f"in {TIME} s", text)
    text = re.sub(r"; \d+\.\d+ s$", f"; {TIME} s", text, flags=re.M)
    return text


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


@functools.cache
def damper_levels() -> dict:
    """``acoustiviz auralize --wav damper.wav --levels``: the Table 1 damper's 20 s run at the paper's listener."""
    with tempfile.TemporaryDirectory() as tmp:
        text = _cli(["auralize", "--wav", str(Path(tmp) / "damper.wav"), "--levels"])
    get = {}
    m = re.search(r"impacts: (\d+)", text)
    get["impacts"] = m.group(1)
    for key in ("LZpeak", "LCpeak", "LAFmax", "LAeq"):
        get[key] = re.search(rf"{key} ([\d.]+)", text).group(1)
    get["SELA"] = re.search(r"SEL\(A\) ([\d.]+)", text).group(1)
    return get


def produce_headline_damper() -> dict:
    """The README's figures of the 20 s damper run."""
    d = damper_levels()
    return {"impacts": d["impacts"], "peak": d["LZpeak"], "lcpeak": d["LCpeak"], "lafmax": d["LAFmax"],
            "laeq": d["LAeq"], "sela": d["SELA"]}


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
REGISTRY = (
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
           r"reports them\): (?P<impacts>\d+) impacts, peak SPL\s+(?P<peak>[\d.]+) dB, LCpeak (?P<lcpeak>[\d.]+) dB, "
           r"LAFmax (?P<lafmax>[\d.]+) dB, LAeq (?P<laeq>[\d.]+) dB, SEL\(A\) (?P<sela>[\d.]+) dB",
           produce_headline_damper, "acoustiviz auralize --wav damper.wav --levels"),
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
            print(f"{f.name:26s} {f.file:28s} {f.command}")
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
