"""A sweep in operation: ``acoustiviz sweep --force``, a scene's ``in_operation`` and the API, resumed, ranked.

The same tiny sweep (two impact masses under 5 N at 6.5 and 7 Hz, two starts, short runs and level
intervals) is asked for three ways and its files compared byte for byte; the command line and the scene
build equal jobs; an interrupted sweep resumes without evaluating a finished design again; a folder of
another mode or operation is refused; bad input names the option or scene key before any work; and
``acoustiviz design`` ranks the designs by an operation column in the column's sense.
"""

from __future__ import annotations

import math
import tomllib
from concurrent.futures import ThreadPoolExecutor

import pytest

import acoustiviz.sweep.operation as operation_module
from acoustiviz.app import design as design_app
from acoustiviz.app import sweep as sweep_app
from acoustiviz.app.design import DesignJob
from acoustiviz.app.settings.forced import FORCED
from acoustiviz.app.settings.sweep_job import SweepJob
from acoustiviz.app.sweep import sweep_settings
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.sweep import settings_from_args as sweep_from_args
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict
from acoustiviz.sweep import OPERATION_COLUMNS, FixedSettings, Operation, SweepMismatch, SweepSpec, load_sweep
from acoustiviz.sweep.in_operation import OPERATION_RANK, load_any_sweep, run_sweep_in_operation

MASSES, FREQS = (0.0405, 0.06), (6.5, 7.0)
SEARCH = dict(starts=2, max_cycles=18, noise_seconds=0.02)
ARGV = ("sweep", "--m", "0.0405,0.06", "--force", "5", "--freq", "6.5,7", "--starts", "2", "--max-cycles", "18",
        "--noise-seconds", "0.02", "--workers", "1", "--quiet")
#: duration_s (the free run's) does not apply in operation: the scene's sweep leaves it at the command line's default.
SCENE = ('[damper]\nsolver = "event"\n[excitation]\nkind = "force"\namplitude = 5.0\nfrequencies_hz = "6.5,7"\n'
         'starts = 2\nmax_cycles = 18\n[outputs.sweep]\nmass_kg = "0.0405,0.06"\ngap_m = "0.04"\nduration_s = 5.0\n'
         'workers = 1\nin_operation = true\nnoise_seconds = 0.02\n')
CAP = 256.0  # the scene's grids.memory_limit_mb by default


def _operation(**kw) -> Operation:
    return Operation(5.0, FREQS, **{**SEARCH, **kw})


def _api_job(out, **kw) -> SweepJob:
    kw = {"m": MASSES, "workers": 1, "operation": _operation(), **kw}
    return SweepJob(out=str(out), **kw)


def _scene(text: str):
    return scene_from_dict(tomllib.loads(text))


def test_every_front_end_writes_the_same_files(tmp_path, capsys):
    cli = tmp_path / "cli"
    assert main([*ARGV, "--out", str(cli / "sweep")]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert printed.startswith("sweep: 2 designs in") and "in operation: force amplitude 5 N" in printed
    choice = ["--rank-by", "min_reduction_db", "--choice", str(cli / "design_choice.txt")]
    assert main(["design", "--sweep", str(cli / "sweep"), *choice]) == 0, capsys.readouterr().err
    assert "ranked by min_reduction_db (largest first" in capsys.readouterr().out
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE + '[outputs.design_table]\nrank_by = "min_reduction_db"\n')
    scene = tmp_path / "scene"
    assert main(["run", str(toml), "--out", str(scene)]) == 0, capsys.readouterr().err
    assert not (scene / "design_table.png").exists()  # no damping inclination, no design table
    api = tmp_path / "api"
    result = sweep_app.run(_api_job(api / "sweep"))
    assert result.write() == []  # the rows are the product
    ranked = design_app.run(DesignJob(sweep=str(api / "sweep"), rank_by="min_reduction_db",
                                      choice="design_choice.txt")).write(api)
    assert [p.name for p in ranked] == ["design_choice.txt"]
    mine = (cli / "design_choice.txt").read_bytes()
    assert (scene / "design_choice.txt").read_bytes() == mine == (api / "design_choice.txt").read_bytes()
    header = (cli / "sweep" / "sweep.csv").read_text().splitlines()[0]
    assert header == ",".join(OPERATION_COLUMNS)
    for name in ("sweep.json", "sweep.csv"):
        mine = (cli / "sweep" / name).read_bytes()
        assert (scene / "sweep" / name).read_bytes() == mine, f"the scene's {name} differs from the command line's"
        assert (api / "sweep" / name).read_bytes() == mine, f"the API's {name} differs from the command line's"
    table = result.table
    assert len(table) == 2 and table.complete and table.operation == _operation()
    assert table["mass_kg"].tolist() == list(MASSES)
    assert set(table["worst_frequency_hz"][table["success"] == 1]) <= set(FREQS)


def test_the_command_line_and_a_scene_build_equal_jobs(tmp_path):
    from_cli = sweep_from_args(build_parser().parse_args([*ARGV, "--out", str(tmp_path / "sweep"),
                                                          "--max-memory", str(CAP)]))
    from_scene = sweep_settings(_scene(SCENE), tmp_path)
    assert from_cli == from_scene == _api_job(tmp_path / "sweep", max_memory_mb=CAP)
    assert from_cli.operation == _operation()
    # the search's defaults are those of acoustiviz forced's records
    defaults = {s.name: s.default for s in FORCED}
    op = from_cli.operation
    assert (op.sweep, op.solver, op.tolerance, op.rtol) == tuple(defaults[k] for k in ("sweep", "solver",
                                                                                        "tolerance", "rtol"))
    assert from_cli.names["frequencies"] == "--freq" and from_scene.names["frequencies"] == "excitation.frequencies_hz"


def _counting(monkeypatch, stop_after=None):
    """Count the designs evaluated (in this process); raise KeyboardInterrupt at evaluation ``stop_after``."""
    seen = []
    real = operation_module.evaluate_in_operation_or_fail

    def counted(design, *args, **kwargs):
        if stop_after is not None and len(seen) == stop_after:
            raise KeyboardInterrupt
        seen.append(design.design_id)
        return real(design, *args, **kwargs)

    monkeypatch.setattr(operation_module, "evaluate_in_operation_or_fail", counted)
    return seen


def test_an_interrupted_sweep_resumes_without_repeating_a_design(tmp_path, monkeypatch):
    spec = SweepSpec(m=MASSES + (0.08,))
    seen = _counting(monkeypatch, stop_after=2)
    with ThreadPoolExecutor(1) as ex, pytest.raises(KeyboardInterrupt):
        run_sweep_in_operation(spec, _operation(), tmp_path, executor=ex, chain=1)
    assert seen == [0, 1]
    kept = load_any_sweep(tmp_path)
    assert sorted(kept["design_id"].tolist()) == [0, 1]  # the finished rows are kept
    monkeypatch.undo()
    seen = _counting(monkeypatch)
    with ThreadPoolExecutor(1) as ex:
        table = run_sweep_in_operation(spec, _operation(), tmp_path, executor=ex, chain=1)
    assert seen == [2] and len(table) == 3 and table.complete
    for c in ("worst_laeq_db", "worst_amplitude_m", "cycles_integrated"):  # the kept rows as they were
        assert table[c][:2].tolist() == pytest.approx(kept[c].tolist(), nan_ok=True)
    with ThreadPoolExecutor(1) as ex:  # finished: nothing to evaluate
        run_sweep_in_operation(spec, _operation(), tmp_path, executor=ex, chain=1)
    assert seen == [2]
    lines = (tmp_path / "sweep.csv").read_text().splitlines()
    assert [line.split(",")[0] for line in lines[1:]] == ["0", "1", "2"]


def test_a_sweep_resumed_in_another_mode_or_operation_is_refused(tmp_path, monkeypatch):
    with ThreadPoolExecutor(1) as ex:
        run_sweep_in_operation(SweepSpec(m=MASSES), _operation(), tmp_path / "op", executor=ex)
    seen = _counting(monkeypatch)
    with pytest.raises(SweepMismatch, match="different settings"):
        SweepJob(m=MASSES, out=str(tmp_path / "op"), workers=1)
    with pytest.raises(SweepMismatch, match="different settings.*operation.starts"):
        _api_job(tmp_path / "op", operation=_operation(starts=3))
    free = dict(m=(0.04,), settings=FixedSettings(duration=0.2), workers=1)
    sweep_app.run(SweepJob(out=str(tmp_path / "free"), **free))
    with pytest.raises(SweepMismatch, match=r"different settings \(operation: None there"):  # free, in operation
        _api_job(tmp_path / "free", **free)
    assert seen == []
    with pytest.raises(ParameterError, match="columns"):  # the free-vibration reader refuses its rows
        load_sweep(tmp_path / "op")


def _no_work(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("a design ran")

    monkeypatch.setattr(operation_module, "evaluate_chain", refuse)


@pytest.mark.parametrize("extra, option", [
    (["--force", "5", "--base", "0.01", "--freq", "5"], "--base"),
    (["--force", "5"], "--freq"),
    (["--starts", "2"], "--starts"),
    (["--force", "-1", "--freq", "5"], "--force"),
    (["--force", "5", "--freq", "5,5"], "--freq"),
    (["--force", "5", "--freq", "5", "--starts", "0"], "--starts"),
    (["--force", "5", "--freq", "5", "--rtol", "1e-15"], "--rtol"),
    (["--force", "5", "--freq", "5", "--noise-seconds", "61"], "--noise-seconds"),
    (["--force", "5", "--freq", "5", "--max-cycles", "10000000"], "--max-cycles"),
    (["--force", "5", "--freq", "5", "--duration", "5"], "--duration"),  # the free run's alone
    (["--force", "5", "--freq", "5", "--levels"], "--levels"),
    (["--force", "5", "--freq", "5", "--max-cycles", "1000000", "--max-memory", "1"], "--max-cycles"),
])
def test_the_command_refuses_bad_input_before_any_work(tmp_path, capsys, monkeypatch, extra, option):
    _no_work(monkeypatch)
    assert main(["sweep", "--out", str(tmp_path / "x"), "--workers", "1", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz sweep: error: {option}") and "\n" not in err, err
    assert not (tmp_path / "x").exists()


def test_a_scene_in_operation_names_its_keys(tmp_path):
    heavy = SCENE.replace("max_cycles = 18", "max_cycles = 1000000") + "[grids]\nmemory_limit_mb = 1.0\n"
    with pytest.raises(ParameterError) as exc:  # over the memory cap
        sweep_settings(_scene(heavy), tmp_path)
    assert exc.value.name == "excitation.max_cycles"
    with pytest.raises(ParameterError) as exc:
        sweep_settings(_scene(SCENE.replace("noise_seconds = 0.02", "noise_seconds = 61.0")), tmp_path)
    assert exc.value.name == "outputs.sweep.noise_seconds"


def test_design_ranks_a_sweep_in_operation(tmp_path, capsys):
    with ThreadPoolExecutor(1) as ex:
        table = run_sweep_in_operation(SweepSpec(m=MASSES + (0.08,)), _operation(), tmp_path, executor=ex)
    for column in ("worst_laeq_db", "min_reduction_db"):
        assert main(["design", "--sweep", str(tmp_path), "--rank-by", column]) == 0, capsys.readouterr().err
        printed = capsys.readouterr().out
        assert "sweep in operation" in printed and f"ranked by {column}" in printed
        ok = [i for i in range(len(table)) if table["success"][i] == 1 and math.isfinite(table[column][i])]
        best = (min if OPERATION_RANK[column] > 0 else max)(ok, key=lambda i: table[column][i])
        assert f"best: design {table['design_id'][best]} " in printed
    result = design_app.run(DesignJob(sweep=str(tmp_path), rank_by="worst_laeq_db"))
    values = [table["worst_laeq_db"][i] for i in result.ranking]
    assert values == sorted(values)
    assert main(["design", "--sweep", str(tmp_path), "--rank-by", "max_spl_db"]) == 2
    assert capsys.readouterr().err.startswith("acoustiviz design: error: --rank-by")
    assert main(["design", "--sweep", str(tmp_path), "--rank-by", "worst_laeq_db", "--inclination", "0.008"]) == 2
    assert capsys.readouterr().err.startswith("acoustiviz design: error: --inclination")


def test_a_failed_design_is_a_row_with_its_reason(tmp_path, monkeypatch, capsys):
    real = operation_module.evaluate_in_operation

    def failing(design, *args, **kwargs):
        if design.design_id == 1:
            raise FloatingPointError("overflow in the contact")
        return real(design, *args, **kwargs)

    monkeypatch.setattr(operation_module, "evaluate_in_operation", failing)
    with ThreadPoolExecutor(1) as ex:
        job = _api_job(tmp_path, executor="process")
        table = run_sweep_in_operation(job.spec, job.operation, tmp_path, executor=ex)
    assert table["success"].tolist() == [1, 0] and table.failed.tolist() == [False, True]
    assert table["error"][1] == "FloatingPointError: overflow in the contact"
    assert math.isnan(table["worst_laeq_db"][1]) and table["worst_regime"][1] == ""
    result = sweep_app.SweepResult(job, table, (), 0.0)
    assert "failed designs: 1 (design_id 1;" in "\n".join(sweep_app.sweep_summary(result))


_CHILD = """
import pathlib, sys, time
import acoustiviz.sweep.operation as op
gate, after = pathlib.Path(sys.argv[1]), int(sys.argv[2])
real = op.evaluate_in_operation_or_fail
def gated(design, *args, **kwargs):
    while design.design_id >= after and not gate.exists():
        time.sleep(0.01)
    return real(design, *args, **kwargs)
op.evaluate_in_operation_or_fail = gated
from acoustiviz.cli import main
sys.exit(main(sys.argv[3:]))
"""
#: Nine designs: a first chain of eight (OPERATION_CHAIN) and a second of one, which waits at the gate.
NINE = ["sweep", "--m", "0.03:0.07:9", "--force", "5", "--freq", "6.5,7", "--starts", "2", "--max-cycles", "18",
        "--noise-seconds", "0.02", "--workers", "1", "--quiet"]


@pytest.mark.slow
def test_ctrl_c_keeps_the_finished_chains_and_the_same_command_resumes(tmp_path, capsys, interruptible):
    import os
    import signal
    import subprocess
    import sys
    import threading
    import time

    from acoustiviz.sweep.in_operation import OPERATION_CHAIN

    assert OPERATION_CHAIN == 8
    out, gate = tmp_path / "c", tmp_path / "gate"
    proc = subprocess.Popen([sys.executable, "-c", _CHILD, str(gate), "8", *NINE, "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **interruptible())
    watchdog = threading.Timer(300.0, gate.touch)  # a hang detector: never leave the child waiting
    watchdog.start()
    try:
        t0 = time.monotonic()
        while not ((out / "sweep.csv").exists() and (out / "sweep.csv").read_bytes().count(b"\n") >= 9):
            assert proc.poll() is None, proc.stderr.read()[-2000:]
            assert time.monotonic() - t0 < 300.0, "the first chain's rows never appeared"
            time.sleep(0.01)
        os.killpg(proc.pid, signal.SIGINT)  # parent and worker alike, as a terminal's Ctrl-C
        err = proc.communicate(timeout=120)[1]
    finally:
        gate.touch()
        watchdog.cancel()
    assert proc.returncode == 130, err[-2000:]
    assert "sweep: stopped; 8 of 9 designs kept" in err
    kept = (out / "sweep.csv").read_text()
    assert main([*NINE, "--out", str(out)]) == 0
    assert "8 of 9 designs done before, 1 to compute" in capsys.readouterr().err
    final = (out / "sweep.csv").read_text()
    assert final.startswith(kept) and final.count("\n") == 10
    assert load_any_sweep(out)["design_id"].tolist() == list(range(9))
