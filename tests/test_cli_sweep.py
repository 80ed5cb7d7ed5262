"""The ``sweep`` and ``design`` commands: outputs, killing and resuming, the Dask address, errors."""

import csv
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from acoustiviz.cli import main
from acoustiviz.sweep import CSV_COLUMNS, design, load_sweep

SWEEP = ["sweep", "--gap", "0.02:0.06:3", "--m", "0.02:0.08:2", "--duration", "1", "--workers", "1", "--quiet"]


def rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


@pytest.fixture(scope="module")
def done(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep")
    assert main([*SWEEP, "--out", str(out)]) == 0
    return out


@pytest.mark.slow
def test_outputs_and_columns(done, capsys):
    r = rows(done / "sweep.csv")
    assert tuple(r[0][: len(CSV_COLUMNS)]) == CSV_COLUMNS
    assert len(r) == 1 + 6
    assert sorted((float(x[0]), float(x[1])) for x in r[1:]) == [
        (g, m) for g in (0.02, 0.04, 0.06) for m in (0.02, 0.08)]
    for name in ("design_table.csv", "inclination_map.png", "max_spl_map.png", "sweep.json"):
        assert (done / name).stat().st_size > 0, name
    assert rows(done / "design_table.csv")[0][:7] == [
        "inclination_m_s", "band_low_m_s", "band_high_m_s", "n_designs", "min_max_spl_db", "max_max_spl_db",
        "decrease_db"]


@pytest.mark.slow
def test_rerun_of_a_finished_sweep_computes_nothing(done, capsys):
    before = (done / "sweep.csv").read_bytes()
    assert main([*SWEEP[:-1], "--out", str(done)]) == 0  # with the progress output
    err = capsys.readouterr().err
    assert "nothing to compute" in err
    assert (done / "sweep.csv").read_bytes() == before


def test_design_command_answers_from_the_sweep(done, capsys):
    table = load_sweep(done)
    e = float(table["inclination_two_maxima_m_s"][2])
    assert main(["design", "--sweep", str(done), "--inclination", repr(e), "--tolerance", "0.002", "--table"]) == 0
    out = capsys.readouterr().out
    ref = design(table, e, 0.002)
    assert f"max SPL {ref.quietest['max_spl_db']:.2f} dB" in out
    assert f"{ref.saving_db:.2f} dB quieter" in out
    assert "design table" in out


@pytest.mark.parametrize("argv, option", [
    (["design", "--inclination", "nan", "--tolerance", "0.0001"], "--inclination"),
    (["design", "--inclination", "0.008", "--tolerance", "-1"], "--tolerance"),
])
def test_design_command_errors_name_the_option(done, capsys, argv, option):
    assert main([argv[0], "--sweep", str(done), *argv[1:]]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz design: error: {option}") and "\n" not in err


def test_design_command_needs_a_sweep_directory(tmp_path, capsys):
    assert main(["design", "--sweep", str(tmp_path / "none"), "--inclination", "0.008"]) == 2
    assert "--sweep" in capsys.readouterr().err


@pytest.mark.parametrize("extra, option", [
    (["--gap", "0.02:0.06"], "--gap"),
    (["--m", "-0.01"], "--m"),
    (["--angle", "100"], "--angle"),
    (["--radius", "big"], "--radius"),
    (["--executor", "threads"], "--executor"),
    (["--workers", "0"], "--workers"),
    (["--config", "room"], "--config"),
    (["--material", "cheese"], "--material"),
    (["--m", "0.04", "--mass-ratio", "0.1"], "--m"),
    (["--distance", "0.01"], "--distance"),
    (["--density", "7800"], "--density"),  # a density sets the radius only with --radius mass
    (["--gap", "0:1:20000"], "--gap"),
])
def test_bad_values_exit_2_naming_the_option(tmp_path, capsys, extra, option):
    assert main(["sweep", "--out", str(tmp_path / "x"), "--duration", "1", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz sweep: error: {option}"), err
    assert "\n" not in err
    assert not (tmp_path / "x" / "sweep.csv").exists()


@pytest.mark.slow
def test_other_settings_refused_then_overwritten(done, tmp_path, capsys):
    out = tmp_path / "o"
    assert main([*SWEEP, "--out", str(out)]) == 0
    assert main([*SWEEP, "--out", str(out), "--c1", "10"]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "different settings" in err and "--overwrite" in err
    assert main([*SWEEP, "--out", str(out), "--c1", "10", "--overwrite"]) == 0
    assert {float(r[9]) for r in rows(out / "sweep.csv")[1:]} == {10.0}


#: The child process: ``acoustiviz sweep`` whose designs from number GATE_AFTER on wait until the
#: file GATE exists, so the sweep cannot end before the test has signalled it, however fast or slow
#: the machine (the workers are forked, so they share the waiting evaluation).
_CHILD = """
import os, sys, time
import acoustiviz.sweep.evaluate as ev
gate, after, real = sys.argv[1], int(sys.argv[2]), ev.evaluate_design
def gated(d, settings):
    if d.design_id >= after:
        t0 = time.monotonic()
        while not os.path.exists(gate) and time.monotonic() - t0 < 120:
            time.sleep(0.01)
    return real(d, settings)
ev.evaluate_design = gated
from acoustiviz.cli import main
sys.exit(main(sys.argv[3:]))
"""
SLOW = ["sweep", "--gap", "0.02:0.06:6", "--m", "0.02:0.08:5", "--duration", "20", "--spl-fastest", "0",
        "--workers", "1"]


def _start(out, gate_after, child: dict):
    """Start the sweep as ``child`` says (the ``interruptible`` fixture's keyword arguments: a new session)."""
    gate = out.parent / f"{out.name}.gate"
    cmd = [sys.executable, "-c", _CHILD, str(gate), str(gate_after), *SLOW, "--out", str(out)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **child)
    return proc, gate


def _wait_rows(path, n, proc, timeout=120.0):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if path.exists() and path.read_bytes().count(b"\n") >= 1 + n:
            return
        if proc.poll() is not None:
            raise AssertionError(f"sweep ended early: {proc.stderr.read()[-2000:]}")
        time.sleep(0.005)
    raise AssertionError("no rows appeared")


@pytest.mark.slow
def test_killed_sweep_resumes_without_recomputing(tmp_path, capsys, interruptible):
    out = tmp_path / "k"
    proc, gate = _start(out, 3, interruptible())
    _wait_rows(out / "sweep.csv", 3, proc)  # designs 0-2 are written, design 3 waits at the gate
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)
    proc.stdout.close()
    proc.stderr.close()
    kept = (out / "sweep.csv").read_text()
    kept_lines = kept.splitlines(keepends=True)
    complete = [ln for ln in kept_lines if ln.endswith("\n")]
    n_kept = len(complete) - 1
    assert n_kept == 3
    argv = [*SLOW, "--out", str(out)]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert f"{n_kept} of 30 designs done before, {30 - n_kept} to compute" in err
    final = (out / "sweep.csv").read_text().splitlines(keepends=True)
    assert final[: len(complete)] == complete  # finished rows untouched
    assert len(final) == 31
    ids = [int(r[7]) for r in csv.reader(final[1:])]
    assert sorted(ids) == list(range(30))  # each design exactly once


@pytest.mark.parametrize("inherited", [signal.SIG_DFL, signal.SIG_IGN], ids=["sigint-default", "sigint-ignored"])
@pytest.mark.slow
def test_ctrl_c_keeps_finished_rows(tmp_path, inherited, interruptible):
    """Ctrl-C stops the sweep with status 130 and keeps the finished rows -- also when the process
    inherited SIGINT ignored (a background job), because the sweep sets the disposition itself."""
    import threading

    out = tmp_path / "c"
    # e.g. SIG_IGN: what a background job of a non-interactive shell inherits
    proc, gate = _start(out, 2, interruptible(sigint=inherited))
    try:
        _wait_rows(out / "sweep.csv", 2, proc)  # designs 0-1 written, design 2 waits at the gate
    except BaseException:
        gate.touch()
        os.killpg(proc.pid, signal.SIGKILL)
        raise
    # never leave the child waiting at the gate, even if the test fails; started only now, so a slow start
    # (kernels compiled under load) cannot open the gate before the Ctrl-C
    watchdog = threading.Timer(60.0, gate.touch)
    watchdog.start()
    try:
        os.killpg(proc.pid, signal.SIGINT)  # parent and worker alike, as a terminal's Ctrl-C
        lines = []
        for line in proc.stderr:  # the parent reports that it stopped before design 2 can finish
            lines.append(line)
            if line.startswith("sweep: stopped"):
                break
    finally:
        gate.touch()
        watchdog.cancel()
    proc.wait(timeout=120)  # its little output fits the pipes
    err = "".join(lines) + proc.stderr.read()
    proc.stdout.close()
    proc.stderr.close()
    assert proc.returncode == 130, err[-2000:]
    assert "sweep: stopped; 2 of 30 designs kept" in err
    assert "finished outputs were kept" in err
    assert len(rows(out / "sweep.csv")) - 1 == 2
    assert (out / "sweep.csv").read_text().endswith("\n")
    assert sorted(load_sweep(out)["design_id"]) == [0, 1]


@pytest.mark.slow
def test_dask_scheduler_address(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp://",
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        address = cluster.scheduler_address.removeprefix("tcp://")
        out = tmp_path / "dask"
        argv = ["sweep", "--gap", "0.03,0.05", "--m", "0.04", "--duration", "1", "--out", str(out), "--quiet"]
        assert main([*argv, "--executor", f"dask://{address}"]) == 0
    table = load_sweep(out)
    assert len(table) == 2
    local = tmp_path / "local"
    assert main([*argv[:-3], "--out", str(local), "--workers", "1", "--quiet"]) == 0
    ref = load_sweep(local)
    for c in CSV_COLUMNS:
        np.testing.assert_array_equal(table[c], ref[c])



def test_sweep_over_listener_configuration_and_velocity(tmp_path, capsys):
    out = tmp_path / "multi"
    argv = ["sweep", "--config", "plane,wall-floor", "--v0", "1,2", "--angle", "30:60:2", "--distance", "0.5",
            "--material", "steel", "--radius", "mass", "--duration", "0.5", "--workers", "1", "--out", str(out),
            "--quiet"]
    assert main(argv) == 0
    assert "maps skipped" in capsys.readouterr().out
    table = load_sweep(out)
    assert len(table) == 8
    assert sorted(set(table["config"])) == ["plane", "wall-floor"]
    assert sorted(set(table["v0_m_s"])) == [1.0, 2.0]
    np.testing.assert_allclose(sorted(set(table["angle_deg"])), [30.0, 60.0])
    # radius from the mass and steel's density; K_HZ from the materials at that radius
    from acoustiviz.core.contact import hertz_stiffness
    from acoustiviz.core.materials import material

    st = material("steel")
    a = (3 * 0.0405 / (4 * np.pi * st.density)) ** (1 / 3)
    np.testing.assert_allclose(table["radius_m"], a, rtol=1e-12)  # cube root: < 5e-15 apart
    np.testing.assert_allclose(table["k_hertz_n_m1_5"], hertz_stiffness(a, st, st), rtol=1e-12)
    assert not (out / "inclination_map.png").exists()


@pytest.mark.slow
def test_design_without_candidates_names_the_nearest(tmp_path, capsys):
    # the issue's own pair of commands on a small sweep: a target outside every design's reach
    # is answered (exit 0), not refused
    from acoustiviz.cli import main

    out = tmp_path / "S"
    assert main(["sweep", "--gap", "0.03:0.04:2", "--m", "0.03:0.04:2", "--duration", "1", "--out", str(out),
                 "--quiet"]) == 0
    capsys.readouterr()
    assert main(["design", "--sweep", str(out), "--inclination", "5", "--tolerance", "0.001"]) == 0
    text = capsys.readouterr().out
    assert "no design" in text and "nearest designs" in text and text.count("m = ") == 3


def test_one_set_of_defaults():
    """The sweep's damper defaults are every front-end's: Table 1, the Figure 5 start, DEFAULT_RTOL."""
    from acoustiviz import constants
    from acoustiviz.cli import build_parser
    from acoustiviz.cli.sweep import spec_from_args
    from acoustiviz.sweep import FixedSettings

    spec = spec_from_args(build_parser().parse_args(["sweep", "--out", "x"]))
    assert spec.settings == FixedSettings()
    assert spec.settings.rtol == constants.DEFAULT_RTOL
    assert (spec.settings.M, spec.settings.K, spec.settings.C) == tuple(constants.TABLE1_PARAMETERS[k] for k in "MKC")
    assert (spec.gap, spec.m, spec.v0, spec.c1) == ((constants.PAPER_GAP,), (constants.TABLE1_PARAMETERS["m"],),
                                                    (constants.PAPER_V0,), (constants.TABLE1_PARAMETERS["c1"],))
