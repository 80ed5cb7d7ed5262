"""Ctrl-C on long commands: exit status 130 with one line, promptly, finished outputs kept, never a crash.

Each command runs in a subprocess (``python -m acoustiviz``) from a fresh folder, in a process group
of its own; SIGINT goes to that whole group, as Ctrl-C at a terminal does (worker processes
included). It is sent once the command has shown it is working (a line on stderr matching a marker), never after a fixed
sleep; the time-outs are hang detectors only. The time from the signal to the exit is bounded
generously (:data:`EXIT_WITHIN_S`) so that a loaded machine does not make a test fail.
"""

from __future__ import annotations

import contextlib
import csv
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from acoustiviz.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: Seconds allowed from SIGINT to the exit: "a second or two", with room for a loaded 2-core machine.
EXIT_WITHIN_S = 10.0
#: Hang detector: seconds a command may take to show it is working (a first compilation included).
READY_WITHIN_S = 300.0
INTERRUPTED = re.compile(r"^acoustiviz [a-z ]+: interrupted; finished outputs were kept$")


class Run:
    """A command line started in ``folder`` as ``child`` says (the ``interruptible`` fixture's keyword arguments);
    its stderr read line by line as it comes."""

    def __init__(self, argv, folder: Path, child: dict, python_options=()):
        self.proc = subprocess.Popen([sys.executable, *python_options, "-m", "acoustiviz", *argv], cwd=folder,
                                     stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     text=True, **child)
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
        os.killpg(self.proc.pid, signal.SIGINT)
        return self.interrupt_wait(t0, timeout)

    def interrupt_wait(self, t0: float, timeout: float = 120.0) -> float:
        """Wait for the exit after SIGINT sent at ``t0`` (monotonic s); return the seconds it took."""
        try:
            self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            pytest.fail(f"still running {timeout:g} s after SIGINT: {self.stderr()}")
        elapsed = time.monotonic() - t0
        self._reader.join(30)
        return elapsed

    def wait_until(self, ready, what: str, timeout: float = READY_WITHIN_S) -> None:
        """Poll ``ready()`` (a file written, ...) until it is true; a hang detector bounds the wait."""
        deadline = time.monotonic() + timeout
        while not ready():
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.kill()
                pytest.fail(f"never {what}: {self.stderr()}")
            time.sleep(0.05)

    def kill(self):
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.proc.pid, signal.SIGKILL)
        self.proc.wait()

    def stderr(self) -> str:
        return "\n".join(ln for ln in self.lines if ln is not None)


def assert_interrupted(run: Run, elapsed: float) -> None:
    """Exit 130 within :data:`EXIT_WITHIN_S` of the signal, the one-line message last, no traceback."""
    err = "\n".join(ln for ln in run.stderr().splitlines() if not ln.startswith("import time:"))  # -X importtime
    assert run.proc.returncode == 130, err
    assert "Traceback" not in err and "Fatal Python error" not in err, err
    assert INTERRUPTED.match(err.splitlines()[-1]), err
    assert sum(bool(INTERRUPTED.match(ln)) for ln in err.splitlines()) == 1, err
    assert elapsed < EXIT_WITHIN_S, f"exited {elapsed:.1f} s after SIGINT"


def interrupt_after(argv, folder: Path, marker: str, child: dict) -> Run:
    """Run ``argv`` in ``folder`` as ``child`` says, send SIGINT once stderr matches ``marker``; check the exit."""
    run = Run(argv, folder, child)
    run.wait_for(marker)
    elapsed = run.interrupt()
    assert_interrupted(run, elapsed)
    return run



#: ``python -m SHIM levels ...``: the command's work runs code from C (as an extension module's
#: initialisation does) and a Ctrl-C lands in it; CPython records that as an unhandled interrupt.
_FROM_C_SHIM = """\
import ctypes
import sys

import acoustiviz.cli.levels as levels


def run(args):
    print("working", file=sys.stderr, flush=True)
    if ctypes.pythonapi.PyRun_SimpleString(b"raise KeyboardInterrupt") != 0:
        raise KeyboardInterrupt


levels.run = run
from acoustiviz.cli import main

sys.exit(main())
"""


def test_ctrl_c_in_code_run_from_c_still_exits_130(tmp_path, interruptible):
    """``python -m`` kills its own process by SIGINT at exit once CPython has recorded an unhandled
    Ctrl-C, whatever status the command returns: the status must still be 130, not death by signal."""
    (tmp_path / "ctrl_c_from_c.py").write_text(_FROM_C_SHIM)
    proc = subprocess.run([sys.executable, "-m", "ctrl_c_from_c", "levels", "in.wav",
                           "--csv", "l.csv"], cwd=tmp_path,
                          stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120,
                          **interruptible(pythonpath=[tmp_path]))
    assert "working" in proc.stderr, proc.stderr
    assert proc.returncode == 130, proc.stderr
    assert INTERRUPTED.match(proc.stderr.strip().splitlines()[-1]), proc.stderr


#: ``python -m SHIM levels ...``: the Ctrl-C lands in a finaliser (``__del__``), where Python can only
#: print "Exception ignored in ..." and carry on.
_IN_FINALISER_SHIM = """\
import signal
import sys

import acoustiviz.cli.levels as levels


class Resource:
    def __del__(self):
        signal.raise_signal(signal.SIGINT)
        for _ in range(1000):  # the KeyboardInterrupt is raised here, inside the finaliser
            pass


def run(args):
    print("working", file=sys.stderr, flush=True)
    Resource()  # finalised at once
    for _ in range(10000):
        pass
    print("carried on", file=sys.stderr, flush=True)
    return 0


levels.run = run
from acoustiviz.cli import main

sys.exit(main())
"""


def test_ctrl_c_swallowed_by_a_finaliser_still_stops_the_command(tmp_path, interruptible):
    """A Ctrl-C raised inside a ``__del__`` cannot propagate (Python prints "Exception ignored in ..."
    and carries on): the command still ends with the one line and status 130, not 0."""
    (tmp_path / "ctrl_c_in_del.py").write_text(_IN_FINALISER_SHIM)
    proc = subprocess.run([sys.executable, "-m", "ctrl_c_in_del", "levels", "in.wav", "--csv", "l.csv"],
                          cwd=tmp_path, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                          timeout=120, **interruptible(pythonpath=[tmp_path]))
    assert "working" in proc.stderr, proc.stderr
    assert "Exception ignored" not in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
    assert proc.returncode == 130, proc.stderr
    assert INTERRUPTED.match(proc.stderr.strip().splitlines()[-1]), proc.stderr


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
def test_forced_interrupted_exits_130_and_never_segfaults(tmp_path, attempt, interruptible):
    """The hostile-user reproduction: Ctrl-C while the frequencies are computed, three times."""
    interrupt_after([*FORCED, "--csv", "o.csv"], tmp_path, r"^forced: .*\(\d+/40\)", interruptible())
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


@pytest.mark.slow
@pytest.mark.parametrize("freq, marker", [("3:7:40", r"^forced: .*\(\d+/40\)"),
                                          ("5.3:5.9:8", r"^forced: .*\(7/8\)"),
                                          ("5.3:5.9:8", r"^forced: 8 frequencies"),
                                          ("5.3:5.9:8", r"^forced: continuation round 1")],
                         ids=["first frequencies", "last frequencies", "first round done", "continuation"])
def test_forced_with_workers_cancels_them_and_exits(tmp_path, freq, marker, interruptible):
    """The workers ignore the Ctrl-C the terminal sends them too (a worker waiting for a task would
    die of it and break the pool under cancelled tasks: InvalidStateError and a hang); the parent
    cancels what is pending, stops them and exits, at any stage of the continuation."""
    argv = ["forced", "--force", "5", "--freq", freq, "--workers", "2", "--csv", "o.csv", "--png", "o.png"]
    run = interrupt_after(argv, tmp_path, marker, interruptible())
    assert not (tmp_path / "o.csv").exists() and not (tmp_path / "o.png").exists()
    with pytest.raises(ProcessLookupError):  # the whole group is gone: the workers were stopped
        os.killpg(run.proc.pid, 0)


@pytest.mark.slow
@pytest.mark.parametrize("attempt", range(3))
def test_a_second_ctrl_c_changes_nothing(tmp_path, attempt, interruptible):
    """Ctrl-C pressed twice: the second lands in the cleanup or the message, or after the exit;
    whichever, one line, status 130, the workers stopped."""
    run = Run(["forced", "--force", "5", "--freq", "3:7:40", "--workers", "2", "--csv", "o.csv"], tmp_path,
              interruptible())
    run.wait_for(r"^forced: .*\(\d+/40\)")
    t0 = time.monotonic()
    os.killpg(run.proc.pid, signal.SIGINT)
    with contextlib.suppress(ProcessLookupError):
        os.killpg(run.proc.pid, signal.SIGINT)
    assert_interrupted(run, run.interrupt_wait(t0))
    with pytest.raises(ProcessLookupError):
        os.killpg(run.proc.pid, 0)


def _rows(path: Path) -> list[dict]:
    if not path.is_file():
        return []
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.mark.slow
@pytest.mark.parametrize("attempt", range(2))
def test_sweep_with_workers_keeps_finished_rows(tmp_path, attempt, interruptible):
    """Ctrl-C once a design is journalled: exit 130, the rows written stay, each one whole."""
    table = tmp_path / "s" / "sweep.csv"
    run = Run(["sweep", "--out", "s", "--gap", "0.01:0.05:60", "--workers", "2"], tmp_path, interruptible())
    run.wait_until(lambda: len(_rows(table)) >= 1, "wrote a row")
    assert_interrupted(run, run.interrupt())
    rows = _rows(table)
    assert 1 <= len(rows) < 60
    assert all(r["design_id"] not in ("", None) and None not in r.values() for r in rows)
    assert "sweep: stopped;" in run.stderr()
    with pytest.raises(ProcessLookupError):
        os.killpg(run.proc.pid, 0)


# ------------------------------------------------------------------ executor addresses
BAD_EXECUTORS = ["dask://host:abc", "dask://:", "dask://[::1:8786", "dask://host:0", "dask://host:65536",
                 "dask://host", "dask://", "dask:/host:8786", "dask://a b:8786"]


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _one_line_naming_executor(rc, err):
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and "Traceback" not in err, err
    assert ": error: --executor" in lines[0] and "dask://HOST:PORT" in lines[0], err


@pytest.mark.parametrize("address", BAD_EXECUTORS)
def test_malformed_dask_address_is_refused_before_any_file(here, capsys, address):
    assert main(["sweep", "--out", "s", "--executor", address, "--quiet"]) == 2
    _one_line_naming_executor(2, capsys.readouterr().err)
    assert list(here.iterdir()) == []  # no sweep.json, no folder
    assert main(["forced", "--force", "5", "--freq", "4", "--executor", address, "--csv", "o.csv"]) == 2
    _one_line_naming_executor(2, capsys.readouterr().err)
    assert list(here.iterdir()) == []


@pytest.mark.parametrize("url, address", [("dask://localhost:8786", "tcp://localhost:8786"),
                                          ("dask://10.1.2.3:1", "tcp://10.1.2.3:1"),
                                          ("dask://[::1]:65535", "tcp://[::1]:65535"),
                                          ("dask://tls://sched.example.org:8786", "tls://sched.example.org:8786")])
def test_well_formed_dask_address_is_parsed_without_connecting(url, address):
    from acoustiviz.sweep.execute import check_executor_form, dask_address

    assert dask_address(url) == address
    check_executor_form(url)


# ------------------------------------------------------------------ long compiled runs in batches
def _newmark_run(monkeypatch, chunk, initial=None):
    import acoustiviz.dynamics._newmark as nm
    from acoustiviz.dynamics import DamperModel, simulate

    monkeypatch.setattr(nm, "NEWMARK_CHUNK_STEPS", chunk)
    return simulate(DamperModel(), 1.0, solver="newmark", initial=initial, t_eval=np.linspace(0.0, 1.0, 501))


def _newmark_arrays(r) -> dict:
    imp, ext = r.impacts, r.extrema
    out = {k: np.asarray(getattr(r, k)) for k in ("t", "x", "v", "y", "w", "dissipated_main", "dissipated_contact",
                                                    "final_state")}
    out.update({f"impacts.{k}": np.asarray(getattr(imp, k)) for k in ("time", "wall", "approach_velocity",
                                                                       "separation_velocity", "duration",
                                                                       "peak_force", "impulse", "energy_lost")})
    out.update({f"extrema.{k}": np.asarray(v) for k, v in vars(ext).items() if isinstance(v, np.ndarray)})
    out["t_end"] = np.asarray(r.t_end)
    return out


@pytest.mark.parametrize("moving_start", [False, True])
def test_newmark_in_batches_is_one_run_bit_for_bit(monkeypatch, moving_start):
    """The free-decay Newmark run is cut into batches of steps (so Ctrl-C is handled between them);
    with a prime batch length, whose cuts fall inside contacts too, every array is the one of a
    single call, bit for bit."""
    from acoustiviz.dynamics import DamperModel, InitialState

    gap = DamperModel().gap
    initial = InitialState(x=0.001, v=1.0, y=0.001 + 0.49 * gap, w=-0.5) if moving_start else None
    whole = _newmark_arrays(_newmark_run(monkeypatch, 1 << 40, initial))
    cut = _newmark_arrays(_newmark_run(monkeypatch, 9973, initial))
    assert whole["impacts.time"].size > 10
    for key, ref in whole.items():
        assert np.array_equal(cut[key], ref, equal_nan=True), key


@pytest.mark.slow
@pytest.mark.parametrize("attempt", range(2))
def test_long_newmark_run_says_so_and_stops_at_ctrl_c(tmp_path, attempt, interruptible):
    interrupt_after(["damper", "--solver", "newmark", "--duration", "10000", "--impacts-csv", "i.csv"],
                    tmp_path, r"^newmark: .* steps .* a long run", interruptible())
    assert not (tmp_path / "i.csv").exists()


LONG_COMMANDS = {
    "render balloon": (["render", "balloon", "--resolution", "512", "--metric", "lafmax", "--png", "b.png"],
                       r"^balloon: .* a long computation"),
    "map": (["map", "--resolution", "2000", "--csv", "m.csv", "--png", "m.png"], r"^map: .* a long computation"),
    "auralize": (["auralize", "--solver", "newmark", "--duration", "1000", "--wav", "a.wav"],
                 r"^newmark: .* a long run"),
    "run": (["run", str(ROOT / "assets" / "scenes" / "default.toml"), "--out", "r"], r"^\[3/\d+\] "),
}


@pytest.mark.slow
@pytest.mark.parametrize("attempt", range(2))
@pytest.mark.parametrize("command", list(LONG_COMMANDS))
def test_long_command_stops_at_ctrl_c(tmp_path, command, attempt, interruptible):
    argv, marker = LONG_COMMANDS[command]
    interrupt_after(argv, tmp_path, marker, interruptible())
    for name in ("b.png", "m.csv", "m.png", "a.wav"):
        assert not (tmp_path / name).exists(), name  # nothing half-written
    if command == "run":  # the steps finished before the interrupt keep their files
        assert {"waveform_paper.csv", "directivity.csv"} <= {p.name for p in (tmp_path / "r").iterdir()}


# ------------------------------------------------------------------ a long signal in a room
def test_long_shell_convolution_is_the_direct_one(monkeypatch):
    """The image orders' shell weights of a long signal: past the direct limit the far orders are
    convolved by FFT, the orders that may be chosen exactly; both match the direct convolution."""
    import acoustiviz.core.reverberation as rv

    rng = np.random.default_rng(7)
    a = np.concatenate([rng.uniform(0.5, 2.0, 2500), np.zeros(500)])  # trailing zeros: underflowed powers
    b = 2.0 ** -np.arange(3000.0) * rng.uniform(0.5, 2.0, 3000)
    ref = np.convolve(a, b)[:3000]
    assert np.array_equal(rv._convolve_head(a, b, 3000), ref)  # below the limit: np.convolve itself
    monkeypatch.setattr(rv, "_DIRECT_PRODUCTS", 2500 * 1100)  # the trailing zeros left out: direct
    np.testing.assert_allclose(rv._convolve_head(a, b, 3000), ref, rtol=1e-14, atol=0.0)
    monkeypatch.setattr(rv, "_DIRECT_PRODUCTS", 1000)  # by FFT beyond the exact orders
    monkeypatch.setattr(rv, "_EXACT_ORDERS", 300)
    fast = rv._convolve_head(a, b, 3000)
    np.testing.assert_allclose(fast[:300], ref[:300], rtol=1e-14, atol=0.0)
    np.testing.assert_allclose(fast, ref, rtol=1e-9, atol=1e-12 * ref.max())
    assert np.all(fast >= 0.0)


@pytest.mark.slow
@pytest.mark.parametrize("absorption", [[], ["--absorption", "0.3"]], ids=["rigid", "absorbing"])
def test_long_waveform_in_a_room_answers_at_once(tmp_path, absorption, interruptible):
    """10000 s in a room asked image orders in the millions, convolved directly (hours, deaf to Ctrl-C):
    the command now answers (here: refused by the memory budget, naming an option) well within the
    hang detector, leaving no file."""
    proc = subprocess.run([sys.executable, "-m", "acoustiviz", "waveform", "--room", "6,4,3", *absorption,
                           "--duration", "10000", "--listener", "3,2,1.5", "--csv", "o.csv"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=240, **interruptible())
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1 and ": error: --" in lines[0], proc.stderr
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ every command, early and later
#: One invocation of every command, long enough to be running when its marker shows, and the module
#: whose import (``python -X importtime`` prints one line as each module is imported) marks the
#: command at work: its kernels' compiled code being loaded or compiled, its signal read.
EVERY_COMMAND = {
    "run": (["run", "--out", "r"], "numba"),
    "waveform": (["waveform", "--samples-per-duration", "20000", "--csv", "w.csv"], "numba"),
    "directivity": (["directivity", "--step", "0.5", "--csv", "d.csv"], "numba"),
    "map": (["map", "--resolution", "301", "--csv", "m.csv"], "numba"),
    "damper": (["damper", "--duration", "100", "--impacts-csv", "i.csv"], "numba"),
    "forced": ([*FORCED, "--csv", "f.csv"], "numba"),
    "sweep": (["sweep", "--out", "s", "--gap", "0.01:0.05:20", "--workers", "1"], "numba"),
    "optimize": (["optimize", "--out", "o", "--gap", "0.01:0.06", "--minimize", "max_spl_db", "--evaluations", "500",
                  "--workers", "1"], "numba"),
    "design": (["design", "--sweep", "SWEEP", "--inclination", "0.005", "--tolerance", "0.01"], "numba"),
    "render balloon": (["render", "balloon", "--resolution", "64", "--png", "b.png"], "numba"),
    "render snapshot": (["render", "snapshot", "--resolution", "401", "--png", "s.png"], "numba"),
    "render animation": (["render", "animation", "--frames", "40", "--resolution", "101", "--gif", "a.gif"],
                         "numba"),
    "auralize": (["auralize", "--duration", "5", "--wav", "a.wav"], "numba"),
    "levels": (["levels", "t.wav", "--csv", "l.csv", "--pa-per-fs", "1", "--loudness"], "scipy"),
}
#: The first module the command line imports for its parser: a Ctrl-C then lands in its imports.
PARSER_MODULE = "acoustiviz.app.settings.table"


@pytest.fixture(scope="module")
def sweep_folder(tmp_path_factory):
    """A finished sweep of two designs (what ``design`` reads)."""
    folder = tmp_path_factory.mktemp("sweep") / "sw"
    assert main(["sweep", "--gap", "0.03,0.04", "--m", "0.04", "--duration", "0.5", "--quiet", "--out",
                 str(folder)]) == 0
    return folder


def _inputs(folder: Path, argv: list, sweep: Path) -> list:
    """Write what ``argv`` reads into ``folder`` (a 30 s WAV); return ``argv`` with the sweep's folder."""
    if "t.wav" in argv:
        from scipy.io import wavfile

        t = np.arange(30 * 48000) / 48000.0
        wavfile.write(folder / "t.wav", 48000, (0.1 * np.sin(2 * np.pi * 1000.0 * t)).astype(np.float32))
    return [str(sweep) if a == "SWEEP" else a for a in argv]


def _imported(module: str) -> str:
    """The ``-X importtime`` line of ``module`` (printed once it is imported)."""
    return r"\|\s+" + re.escape(module) + "$"


@pytest.fixture
def command_argv(request, tmp_path):
    """The invocation of ``request.param`` with its inputs in ``tmp_path`` (the sweep only for design)."""
    argv, marker = EVERY_COMMAND[request.param]
    sweep = request.getfixturevalue("sweep_folder") if "SWEEP" in argv else None
    return _inputs(tmp_path, argv, sweep), marker


def _interrupt_at_import(argv, folder: Path, module: str, child: dict) -> Run:
    run = Run(argv, folder, child, python_options=("-X", "importtime"))
    run.wait_for(_imported(module))
    assert_interrupted(run, run.interrupt())
    return run


@pytest.mark.slow
@pytest.mark.parametrize("attempt", range(2))
@pytest.mark.parametrize("command_argv", list(EVERY_COMMAND), indirect=True)
def test_ctrl_c_while_the_command_line_imports_exits_130(tmp_path, command_argv, attempt, interruptible):
    """Ctrl-C very early, while the parser's modules are imported: one line, status 130 (not a
    traceback, not death by SIGINT), nothing written."""
    argv, _ = command_argv
    before = sorted(p.name for p in tmp_path.iterdir())
    _interrupt_at_import(argv, tmp_path, PARSER_MODULE, interruptible())
    assert sorted(p.name for p in tmp_path.iterdir()) == before


@pytest.mark.slow
@pytest.mark.parametrize("attempt", range(2))
@pytest.mark.parametrize("command_argv", list(EVERY_COMMAND), indirect=True)
def test_ctrl_c_while_the_command_works_exits_130(tmp_path, command_argv, attempt, interruptible):
    """Ctrl-C later, once the command has started its work (its compiled kernels or its signal
    reader being loaded): one line, status 130, and no output half-written."""
    argv, marker = command_argv
    _interrupt_at_import(argv, tmp_path, marker, interruptible())
    for name in ("w.csv", "d.csv", "m.csv", "i.csv", "f.csv", "b.png", "s.png", "a.gif", "a.wav", "l.csv"):
        assert not (tmp_path / name).exists(), name


def test_an_interrupt_python_wrapped_in_another_exception_still_exits_130(monkeypatch, capsys):
    """A Ctrl-C in a dataclass field's ``__set_name__`` reaches the command as a RuntimeError caused by it."""
    import acoustiviz.cli as cli

    def class_built_under_ctrl_c(argv, standalone):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise RuntimeError("Error calling __set_name__ on 'Field' instance 'names'") from exc

    monkeypatch.setattr(cli, "_command", class_built_under_ctrl_c)
    assert cli._main(["map"]) == 130
    assert "acoustiviz map: interrupted" in capsys.readouterr().err


def test_an_error_not_caused_by_an_interrupt_is_not_taken_for_one(monkeypatch):
    import acoustiviz.cli as cli

    def fails(argv, standalone):
        raise RuntimeError("a defect")

    monkeypatch.setattr(cli, "_command", fails)
    with pytest.raises(RuntimeError, match="a defect"):
        cli._main(["map"])
