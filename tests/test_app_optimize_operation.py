"""The optimisation in operation: ``acoustiviz optimize --force``, a scene's ``in_operation`` and the API.

The same optimisation in operation is asked for three ways on a tiny budget (three designs, two
frequencies, two starts) and the files are compared byte for byte; the command line and the scene
build equal settings; objectives, constraints and options of free vibration are refused naming
what the user typed, before any work; a run resumes from its journal; a design that fails is a row
with its reason; a design's row does not depend on what its worker evaluated before, so two workers
give the rows of one; Ctrl-C keeps every finished evaluation (exit 130); and the chosen
design's confirmation holds the worst case of an independent ``forced`` run with twice the starts. An
optimisation over the number of balls evaluates whole numbers with finite dynamics columns, and a scene
searches the balls as the command line does.
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import time
import tomllib

import pytest

pytest.importorskip("optuna")

import acoustiviz.sweep.operation as operation_module  # noqa: E402
from acoustiviz.app.forced import run as run_forced  # noqa: E402
from acoustiviz.app.optimize import optimize_variables, run  # noqa: E402
from acoustiviz.app.scene_optimize import optimize_settings  # noqa: E402
from acoustiviz.app.settings.forced_job import ForcedJob  # noqa: E402
from acoustiviz.app.settings.optimize import OptimizeJob  # noqa: E402
from acoustiviz.cli import build_parser, main  # noqa: E402
from acoustiviz.cli.optimize import settings_from_args  # noqa: E402
from acoustiviz.dynamics import DamperModel  # noqa: E402
from acoustiviz.errors import ParameterError  # noqa: E402
from acoustiviz.scene import scene_from_dict  # noqa: E402
from acoustiviz.sweep import Operation  # noqa: E402
from acoustiviz.sweep.modes import InOperation  # noqa: E402
from acoustiviz.sweep.optimise import JOURNAL, read_journal, run_optimisation  # noqa: E402

FILES = ("evaluations.csv", "pareto.csv", "optimize.json", "pareto.png", "confirmation.csv")
FREQS = (6.5, 7.0)
SEARCH = dict(starts=2, max_cycles=18, noise_seconds=0.02)
#: Three designs of the impact mass in batches of two, under F0 = 5 N at two frequencies.
ARGV = ("optimize", "--gap", "0.04", "--m", "0.03:0.06", "--force", "5", "--freq", "6.5,7", "--starts", "2",
        "--max-cycles", "18", "--noise-seconds", "0.02", "--minimize", "worst_laeq_db", "--evaluations", "3",
        "--batch", "2", "--seed", "3", "--workers", "1")
SCENE = ('[damper]\nsolver = "event"\n[excitation]\nkind = "force"\namplitude = 5.0\nfrequencies_hz = "6.5,7"\n'
         'starts = 2\nmax_cycles = 18\n[outputs.optimize]\ngap_m = "0.04"\nmass_kg = "0.03:0.06"\n'
         'minimize = ["worst_laeq_db"]\nevaluations = 3\nbatch = 2\nseed = 3\nworkers = 1\nin_operation = true\n'
         'noise_seconds = 0.02\n')


def _operation(**kw) -> Operation:
    return Operation(5.0, FREQS, **{**SEARCH, **kw})


def _api_job(out, **kw) -> OptimizeJob:
    variables, fixed = optimize_variables({"gap": "0.04", "m": "0.03:0.06"})
    values = dict(minimize=("worst_laeq_db",), evaluations=3, batch=2, seed=3, workers=1, mode="operation",
                  operation=_operation(), out=None if out is None else str(out))
    values.update(kw)
    return OptimizeJob(variables, fixed, **values)


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def cli_folder(tmp_path_factory):
    """The folder of the command line's optimisation in operation."""
    out = tmp_path_factory.mktemp("cli")
    assert main([*ARGV, "--out", str(out)]) == 0
    return out


def test_every_front_end_writes_the_same_files(cli_folder, tmp_path, capsys):
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    written = run(_api_job(api)).write()
    assert sorted(p.name for p in written) == sorted(FILES)
    for name in FILES:
        mine = (cli_folder / name).read_bytes()
        assert len(mine) > 100
        assert (tmp_path / "scene" / "optimize" / name).read_bytes() == mine, f"the scene's {name} differs"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs"
    rows = _rows(cli_folder / "evaluations.csv")
    assert [int(r["evaluation"]) for r in rows] == [0, 1, 2]
    for r in rows:  # the operation columns, each design within its bounds and evaluated at the band's frequencies
        assert 0.03 <= float(r["mass_kg"]) <= 0.06 and float(r["gap_m"]) == 0.04
        assert r["success"] == "1" and float(r["worst_frequency_hz"]) in FREQS
        assert math.isfinite(float(r["worst_laeq_db"])) and float(r["worst_amplitude_m"]) > 0
    assert json.loads((cli_folder / "optimize.json").read_text())["operation"]["starts"] == 2


def test_the_command_line_and_a_scene_build_equal_settings(tmp_path):
    from_cli = settings_from_args(build_parser().parse_args([*ARGV, "--out", str(tmp_path / "optimize")]))
    from_scene = optimize_settings(scene_from_dict(tomllib.loads(SCENE)), tmp_path)
    assert from_cli == from_scene == _api_job(tmp_path / "optimize")
    assert from_cli.mode == "operation" and from_cli.operation == _operation()
    # the search's solver and rtol are forced's defaults, not the free run's
    assert (from_cli.operation.solver, from_cli.operation.rtol) == ("event", 1e-10)


def test_the_confirmation_is_the_worst_case_of_forced_with_twice_the_starts(cli_folder, capsys):
    (best,) = _rows(cli_folder / "pareto.csv")
    (row,) = _rows(cli_folder / "confirmation.csv")
    assert row["evaluation"] == best["evaluation"] and float(row["m"]) == float(best["mass_kg"])
    assert float(row["worst_amplitude_m"]) == float(best["worst_amplitude_m"])
    assert row["worst_regime"] == best["worst_regime"]
    assert (int(row["starts"]), int(row["confirmation_starts"])) == (2, 4)
    # an independent forced run of the chosen damper with four starts: its largest amplitude
    model = DamperModel(m=float(best["mass_kg"]), gap=0.04)
    forced = run_forced(ForcedJob(model=model, frequencies=FREQS, amplitude=5.0, starts=4, max_cycles=18,
                                  noise=False))
    worst = max((r for r in forced.rows if math.isfinite(r["amplitude_m"])),
                key=lambda r: r["amplitude_m"])
    assert float(row["confirmed_worst_amplitude_m"]) == pytest.approx(worst["amplitude_m"], rel=1e-12)
    assert float(row["confirmed_worst_frequency_hz"]) == worst["frequency_hz"]
    a, b = float(row["worst_amplitude_m"]), float(row["confirmed_worst_amplitude_m"])
    ea, eb = float(row["worst_amplitude_std_err_m"]), float(row["confirmed_worst_amplitude_std_err_m"])
    expected = math.isclose(a, b, rel_tol=1e-6, abs_tol=1e-9) if ea == eb == 0 else abs(a - b) <= 2 * math.hypot(ea, eb)
    assert row["agree"] == ("true" if expected else "false")


def test_a_resumed_run_keeps_every_finished_evaluation_and_asks_the_same_designs(cli_folder, tmp_path):
    part = tmp_path / "part"
    run(_api_job(part, evaluations=2))  # stopped after the first batch
    journal = (part / "journal.jsonl").read_text().splitlines()
    assert len(journal) == 2
    resumed = run(_api_job(part))
    whole = [json.loads(line) for line in (cli_folder / "journal.jsonl").read_text().splitlines()]
    assert [r["params"] for r in resumed.records] == [w["params"] for w in whole]
    kept = [json.loads(line) for line in journal]
    assert [r["row"] for r in resumed.records[:2]] == [k["row"] for k in kept]  # not recomputed
    assert len((part / "journal.jsonl").read_text().splitlines()) == 3
    assert resumed.confirmation is not None and resumed.confirmation["confirmation_starts"] == 4


def test_a_folder_of_another_operation_is_refused(cli_folder):
    with pytest.raises(ParameterError, match=r"^--out: .*other settings"):
        _api_job(cli_folder, operation=_operation(starts=3), names={"out": "--out"})


def test_a_design_that_fails_is_a_row_with_its_reason(monkeypatch):
    real = operation_module.evaluate_in_operation

    def overflow_above_45_g(design, fixed, operation, **kw):
        if design.m > 0.045:
            raise FloatingPointError("overflow in the contact force")
        return real(design, fixed, operation, **kw)

    monkeypatch.setattr(operation_module, "evaluate_in_operation", overflow_above_45_g)  # forked workers inherit it
    result = run(_api_job(None, evaluations=4, batch=4, seed=1))
    rows = result.rows
    failed = [r for r in rows if r["mass_kg"] > 0.045]
    assert failed and len(failed) < len(rows)
    for r in failed:
        assert r["error"] == "FloatingPointError: overflow in the contact force" and r["success"] == 0
        assert r["feasible"] is False and math.isnan(r["worst_laeq_db"])
    assert all(not r["error"] for r in rows if r["mass_kg"] <= 0.045)


def test_a_design_s_row_does_not_depend_on_what_its_worker_evaluated_before():
    _, fixed = optimize_variables({"gap": "0.04", "m": "0.03:0.06"})
    mode = InOperation(fixed, _operation(starts=1))
    design = {"gap": 0.04, "m": 0.05}
    first = mode(1, design)
    mode(0, {"gap": 0.04, "m": 0.0405})
    again = mode(1, design)
    assert json.dumps(first, sort_keys=True) == json.dumps(again, sort_keys=True)
    assert first["warm_from"] == -1


def test_two_workers_give_the_result_of_one(tmp_path):
    job = _api_job(None, evaluations=4, batch=4)
    one = run_optimisation(job.problem, job.evaluator(), tmp_path / "one", workers=1)
    two = run_optimisation(job.problem, job.evaluator(), tmp_path / "two", workers=2)
    assert [r["evaluation"] for r in two] == [0, 1, 2, 3]
    assert json.dumps(one) == json.dumps(two)  # the same designs and rows, in evaluation order (NaN included)


def test_ctrl_c_keeps_every_finished_evaluation(tmp_path, interruptible):
    out = tmp_path / "o"
    argv = [sys.executable, "-m", "acoustiviz", *ARGV[:-8], "--evaluations", "5000", "--batch", "2", "--workers", "1",
            "--out", str(out)]
    # as a terminal starts the command, in a clean environment, in a process group of its own
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **interruptible())
    journal = out / JOURNAL
    deadline = time.monotonic() + 300  # a hang detector only: the trigger is the journal's second line
    while time.monotonic() < deadline and proc.poll() is None:
        if journal.exists() and journal.read_text().count("\n") >= 2:
            break
        time.sleep(0.05)
    assert proc.poll() is None, proc.stderr.read()
    os.killpg(proc.pid, signal.SIGINT)  # parent and workers alike, as a terminal's Ctrl-C
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err[-2000:]
    kept = read_journal(journal)
    assert f"optimize: stopped; {len(kept)} of 5000 evaluations kept" in err
    assert len(kept) >= 2 and sorted(kept) == list(range(len(kept)))
    assert all(r["row"]["error"] == "" for r in kept.values())
    assert not (out / "confirmation.csv").exists()


OP = ("--gap", "0.01:0.06", "--force", "5", "--freq", "6.5,7")


@pytest.mark.parametrize(("argv", "message"), [
    ((*OP, "--minimize", "max_spl_db"), r"--minimize: unknown column 'max_spl_db'"),
    ((*OP, "--minimize", "worst_laeq_db", "--constraint", "inclination_two_maxima_m_s>=0.004"),
     r"--constraint: unknown column 'inclination_two_maxima_m_s'"),
    ((*OP, "--minimize", "worst_laeq_db", "--duration", "1"), r"--duration: applies only to a sweep of free"),
    ((*OP, "--minimize", "worst_laeq_db", "--levels"), r"--levels: applies only to a sweep of free"),
    ((*OP, "--minimize", "worst_laeq_db", "--v0", "1:2"), r"--v0: applies only to a sweep of free"),
    (("--gap", "0.01:0.06", "--force", "5", "--minimize", "worst_laeq_db"), r"--freq: is required"),
    (("--gap", "0.01:0.06", "--minimize", "worst_laeq_db"), r"--minimize: unknown column 'worst_laeq_db'"),
    (("--gap", "0.01:0.06", "--starts", "2", "--minimize", "max_spl_db"), r"--starts: applies only"),
    (("--gap", "0.01:0.06", "--mode", "operation", "--minimize", "worst_laeq_db"), r"--mode: operation needs"),
    ((*OP, "--minimize", "worst_laeq_db", "--starts", "0"), r"--starts: "),
])
def test_bad_input_is_one_line_naming_the_option_before_any_work(argv, message, tmp_path, capsys):
    assert main(["optimize", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert re.search(message, err), err
    assert not (tmp_path / "o").exists()


def test_a_scene_naming_a_free_vibration_column_in_operation_is_refused(tmp_path):
    text = SCENE.replace('minimize = ["worst_laeq_db"]', 'minimize = ["max_spl_db"]')
    with pytest.raises(ParameterError, match=r"outputs\.optimize\.minimize: unknown column 'max_spl_db'"):
        optimize_settings(scene_from_dict(tomllib.loads(text)), tmp_path)


#: A room with absorbing walls around the designs' sphere (the images within a 5 ms window).
ROOM_ARGV = ("--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905", "--room-window", "0.005")


@pytest.mark.slow
def test_in_a_room_every_design_is_heard_with_its_reflections(cli_folder, tmp_path, capsys):
    # two designs asked in one batch, before any result is told: the designs of the plane run's first batch
    budget = ("--evaluations", "2", "--batch", "2")
    argv = [*ARGV[:ARGV.index("--evaluations")], *budget, *ARGV[ARGV.index("--seed"):], *ROOM_ARGV]
    assert main([*argv, "--out", str(tmp_path / "cli")]) == 0, capsys.readouterr().err
    from acoustiviz.app.impacts import room_settings
    from acoustiviz.app.sweep import with_room

    room = room_settings("3,2.5,2", absorption="0.3", source="1,1,0.01905", duration=0.005)
    variables, fixed = optimize_variables(with_room({"gap": "0.04", "m": "0.03:0.06"}, room))
    api = tmp_path / "api"
    written = run(OptimizeJob(variables, fixed, minimize=("worst_laeq_db",), evaluations=2, batch=2, seed=3,
                              workers=1, mode="operation", operation=_operation(), out=str(api))).write()
    assert sorted(p.name for p in written) == sorted(FILES)
    for name in FILES:
        assert (api / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), f"the API's {name} differs"
    in_room = _rows(api / "evaluations.csv")
    on_plane = _rows(cli_folder / "evaluations.csv")[:2]
    assert len(in_room) == 2
    for r, p in zip(in_room, on_plane, strict=True):
        assert (r["config"], p["config"]) == ("room", "plane")
        assert r["success"] == "1" and not r["error"] and r["mass_kg"] == p["mass_kg"]
        levels = [float(r[c]) for c in ("worst_lcpeak_db", "worst_laeq_db", "worst_lafmax_db")]
        assert all(math.isfinite(v) and v > 0 for v in levels), r
        # the walls send sound back, never motion: the same attractors, a louder average level
        for c in ("worst_amplitude_m", "min_reduction_db", "worst_frequency_hz", "worst_regime"):
            assert r[c] == p[c], c
        assert float(r["worst_laeq_db"]) > float(p["worst_laeq_db"])


#: An optimisation in operation over the number of balls, 1 to 3, under F0 = 5 N at two frequencies.
BALLS_ARGV = ("optimize", "--gap", "0.04", "--balls", "1:3", "--force", "5", "--freq", "6.5,7", "--starts", "2",
              "--max-cycles", "18", "--noise-seconds", "0.02", "--minimize", "worst_amplitude_m", "--evaluations", "3",
              "--batch", "3", "--seed", "1", "--workers", "1")


def test_an_optimisation_over_the_balls_in_operation_evaluates_whole_numbers(tmp_path, capsys):
    out = tmp_path / "balls"
    assert main([*BALLS_ARGV, "--out", str(out)]) == 0, capsys.readouterr().err
    rows = _rows(out / "evaluations.csv")
    assert len(rows) == 3 and any(r["balls"] != "1" for r in rows)
    for r in rows:
        assert r["balls"] in ("1", "2", "3") and r["success"] == "1", r
        assert 0.0 < float(r["fill"]) < 1.0
        for c in ("worst_amplitude_m", "min_reduction_db", "mean_reduction_db", "chaotic_fraction"):
            assert math.isfinite(float(r[c])), (c, r)
        for c in ("worst_lcpeak_db", "worst_laeq_db", "worst_lafmax_db"):  # several balls heard in operation too
            assert not math.isnan(float(r[c])), (c, r)
    (best,) = _rows(out / "pareto.csv")
    (row,) = _rows(out / "confirmation.csv")
    assert row["evaluation"] == best["evaluation"] and row["balls"] == best["balls"]
    assert math.isfinite(float(row["confirmed_worst_amplitude_m"])) and int(row["confirmation_starts"]) == 4


def test_a_scene_in_operation_searches_the_balls_as_the_command_line(tmp_path):
    scene = SCENE.replace('mass_kg = "0.03:0.06"\n', 'mass_kg = "0.0405"\nballs = "1:3"\n') \
        .replace('minimize = ["worst_laeq_db"]\nevaluations = 3\nbatch = 2\nseed = 3\n',
                 'minimize = ["worst_amplitude_m"]\nevaluations = 3\nbatch = 3\nseed = 1\n')
    from_cli = settings_from_args(build_parser().parse_args([*BALLS_ARGV, "--out", str(tmp_path / "optimize")]))
    from_scene = optimize_settings(scene_from_dict(tomllib.loads(scene)), tmp_path)
    assert from_cli == from_scene and from_cli.operation == from_scene.operation
    assert [v.name for v in from_scene.problem.searched] == ["balls"]
    assert from_scene.evaluator().columns == from_cli.evaluator().columns
    assert "balls" in from_scene.evaluator().columns
    # a level objective with several balls is accepted, the same from a scene as from the command line
    levels = optimize_settings(scene_from_dict(tomllib.loads(scene.replace("worst_amplitude_m", "worst_laeq_db"))),
                               tmp_path)
    argv = [a if a != "worst_amplitude_m" else "worst_laeq_db" for a in BALLS_ARGV]
    assert levels == settings_from_args(build_parser().parse_args([*argv, "--out", str(tmp_path / "optimize")]))
    assert [o.column for o in levels.problem.objectives] == ["worst_laeq_db"]
