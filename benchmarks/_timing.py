"""Timing helpers shared by the benchmark scripts (run them from anywhere: ``python benchmarks/bench_*.py``).

:func:`run_writing` gives a benchmark its ``--write`` option: the printed output is also saved to
``benchmarks/results/<name>.txt`` under a header line naming the command, the date and the machine
(CPU model, cores, Python). The guide quotes its timings from those files (``docs/check_numbers.py``
checks that the text says what the file says).
"""

from __future__ import annotations

import contextlib
import math
import os
import platform
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"


def best_of(f, repeat: int, clock=time.perf_counter):
    """Call ``f`` ``repeat`` times; return (the shortest time on ``clock`` in s, the last result).

    The default clock is the wall clock.
    """
    best, out = math.inf, None
    for _ in range(max(1, int(repeat))):
        t0 = clock()
        out = f()
        best = min(best, clock() - t0)
    return best, out


def cpu_best_of(f, repeat: int):
    """Call ``f`` ``repeat`` times; return (the shortest CPU time of this process in s, the last result).

    CPU time is steadier than wall time on a machine shared with other work (and counts every
    thread of this process).
    """
    return best_of(f, repeat, clock=time.process_time)


def machine() -> str:
    """The CPU model (``/proc/cpuinfo``, else the platform's name), logical cores and the Python running."""
    model = ""
    with contextlib.suppress(OSError):
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            model = next((line.split(":", 1)[1].strip() for line in fh if line.startswith("model name")), "")
    model = model or platform.processor() or platform.machine()
    return (f"{model}, {os.cpu_count()} cores, {platform.machine()}, "
            f"{platform.python_implementation()} {platform.python_version()}")


def results_header(command: str) -> str:
    """``$ COMMAND (date UTC; machine)``: the first line of a results file."""
    return f"$ {command} ({datetime.now(UTC).strftime('%Y-%m-%d %H:%M UTC')}; {machine()})"


class Tee:
    """Write to a stream and keep a copy."""

    def __init__(self, out):
        self.out, self.parts = out, []

    def write(self, text):
        self.parts.append(text)
        return self.out.write(text)

    def flush(self):
        self.out.flush()


def run_writing(name: str, main, argv=None) -> int:
    """Run ``main(argv)``; with ``--write`` among the arguments also keep its output in results/NAME.txt.

    ``--write`` is taken out of the arguments before ``main`` sees them. The file starts with
    :func:`results_header` (the command without ``--write``) and has the printed lines, less those
    starting ``wrote `` (paths of this machine); it is written atomically.
    """
    args = list(sys.argv[1:] if argv is None else argv)
    if "--write" not in args:
        return main(args)
    args = [a for a in args if a != "--write"]
    header = results_header(" ".join(["python", f"benchmarks/{name}.py", *args]))
    print(header)
    tee = Tee(sys.stdout)
    with contextlib.redirect_stdout(tee):
        status = main(args)
    if status:
        return status
    body = "".join(tee.parts).strip("\n").splitlines()
    text = "\n".join([header, *(line for line in body if not line.startswith("wrote "))]) + "\n"
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"{name}.txt"
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)
    print(f"wrote {path}")
    return 0
