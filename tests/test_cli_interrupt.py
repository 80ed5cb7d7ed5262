"""Ctrl-C on long commands: exit status 130 with one line, promptly, finished outputs kept, never a crash.

Each command runs in a subprocess (``python -m acoustiviz``) from a fresh folder. SIGINT is sent
once the command has shown it is working (a line on stderr matching a marker), never after a fixed
sleep; the time-outs are hang detectors only. The time from the signal to the exit is bounded
generously (:data:`EXIT_WITHIN_S`) so that a loaded machine does not make a test fail.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from acoustiviz.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: Seconds allowed from SIGINT to the exit: "a second or two", with room for a loaded 2-core machine.
EXIT_WITHIN_S = 10.0
#: Hang detector: seconds a command may take to show it is working (a first compilation included).
READY_WITHIN_S = 300.0
INTERRUPTED = re.compile(r"^acoustiviz [a-z ]+: interrupted; finished outputs were kept$")


def _env() -> dict:
    """The environment of the subprocess: this tree first on the path, no inherited numba or plotting switch."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "PYTHON", "MPL"))}
    env.update(PYTHONPATH=str(ROOT), MPLBACKEND="Agg", PYTHONFAULTHANDLER="1")
    return env


class Run:
    """A command line started in ``folder``; its stderr read line by line as it comes."""

    def __init__(self, argv, folder: Path):
        self.proc = subprocess.Popen([sys.executable, "-m", "acoustiviz", *argv], cwd=folder, env=_env(),
                                     stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     text=True)
        self.lines: list[str] = []
        self._cond = threading.Condition()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        for line in self.proc.stderr:
            with self._cond:
                self.lines.append(line.rstrip("\n"))
                self._cond.notify_all()
        with self._cond:
            self.lines.append(None)  # end of stderr
            self._cond.notify_all()

    def wait_for(self, marker: str, timeout: float = READY_WITHIN_S) -> None:
        """Wait until a line of stderr matches ``marker`` (a regular expression)."""
        pattern = re.compile(marker)
        deadline = time.monotonic() + timeout
        with self._cond:
            while not any(ln is not None and pattern.search(ln) for ln in self.lines):
                left = deadline - time.monotonic()
                if None in self.lines or left <= 0:
                    self.kill()
                    pytest.fail(f"no line matching {marker!r} on stderr: {self.stderr()}")
                self._cond.wait(left)

    def interrupt(self, timeout: float = 120.0) -> float:
        """Send SIGINT; return the seconds until the process exited (killed and failed if it hangs)."""
        t0 = time.monotonic()
        self.proc.send_signal(signal.SIGINT)
        try:
            self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            pytest.fail(f"still running {timeout:g} s after SIGINT: {self.stderr()}")
        elapsed = time.monotonic() - t0
        self._reader.join(30)
        return elapsed

    def kill(self):
        self.proc.kill()
        self.proc.wait()

    def stderr(self) -> str:
        return "\n".join(ln for ln in self.lines if ln is not None)


def assert_interrupted(run: Run, elapsed: float) -> None:
    """Exit 130 within :data:`EXIT_WITHIN_S` of the signal, the one-line message last, no traceback."""
    err = run.stderr()
    assert run.proc.returncode == 130, err
    assert "Traceback" not in err and "Fatal Python error" not in err, err
    assert INTERRUPTED.match(err.splitlines()[-1]), err
    assert sum(bool(INTERRUPTED.match(ln)) for ln in err.splitlines()) == 1, err
    assert elapsed < EXIT_WITHIN_S, f"exited {elapsed:.1f} s after SIGINT"


def interrupt_after(argv, folder: Path, marker: str) -> Run:
    """Run ``argv`` in ``folder``, send SIGINT once stderr matches ``marker``; check the exit."""
    run = Run(argv, folder)
    run.wait_for(marker)
    elapsed = run.interrupt()
    assert_interrupted(run, elapsed)
    return run


FORCED = ["forced", "--force", "5", "--freq", "3:7:40"]


# ------------------------------------------------------------------ compiled kernels and Ctrl-C
def _namedtuple_returns() -> list[str]:
    """The compiled entry kernels of acoustiviz (callable from Python) whose return type holds a namedtuple."""
    from numba.core import types
    from numba.core.registry import CPUDispatcher

    def holds_namedtuple(t) -> bool:
        if isinstance(t, types.BaseNamedTuple):
            return True
        return isinstance(t, types.BaseTuple) and any(holds_namedtuple(u) for u in t.types)

    found = []
    for name, mod in list(sys.modules.items()):
        if not name.startswith("acoustiviz."):
            continue
        for attr, obj in list(vars(mod).items()):
            if not isinstance(obj, CPUDispatcher) or obj.targetoptions.get("no_cpython_wrapper"):
                continue
            for sig in obj.nopython_signatures:
                if holds_namedtuple(sig.return_type):
                    found.append(f"{name}.{attr} -> {sig.return_type}")
    return found


def test_no_kernel_called_from_python_returns_a_namedtuple():
    """numba boxes a returned namedtuple by calling its Python class: a Ctrl-C pending there raises
    KeyboardInterrupt, and numba then calls a NULL object (a segmentation fault, exit 139). Every
    solver is run once so that its kernels are compiled (or loaded), then every entry kernel's
    return types are inspected."""
    from acoustiviz.dynamics import DamperModel, simulate
    from acoustiviz.dynamics._forced_steady import simulate_cycles
    from acoustiviz.dynamics.forced import Excitation

    model = DamperModel()
    for solver in ("event", "impact-map", "newmark"):
        simulate(model, 0.05, solver=solver)
        simulate_cycles(model, Excitation(4.0, 5.0), 1, solver=solver, restitution=0.6 if solver == "impact-map"
                        else None)
    assert _namedtuple_returns() == []


@pytest.mark.slow
@pytest.mark.parametrize("attempt", range(3))
def test_forced_interrupted_exits_130_and_never_segfaults(tmp_path, attempt):
    """The hostile-user reproduction: Ctrl-C while the frequencies are computed, three times."""
    interrupt_after([*FORCED, "--csv", "o.csv"], tmp_path, r"^forced: .*\(\d+/40\)")
    assert not (tmp_path / "o.csv").exists()  # the table is written at the end: nothing half-written


def test_keyboard_interrupt_is_one_line_and_130(capsys, monkeypatch):
    """In-process: a KeyboardInterrupt from the work becomes the one-line message and status 130."""
    import acoustiviz.cli.waveform as waveform

    def stop(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(waveform, "run", stop)
    assert main(["waveform"]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and INTERRUPTED.match(err[0]), err
