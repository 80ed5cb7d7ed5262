"""The optimisation job: one settings object, one run and one writer for the command line, scenes and the API.

The same optimisation is asked for three ways (``acoustiviz optimize``, a scene's ``[outputs.optimize]``
and :class:`~acoustiviz.app.settings.optimize.OptimizeJob` built in Python) on a tiny budget and the
files are compared byte for byte; the command line and the scene build equal settings; a run resumes
from its journal; a design that fails is a row with its reason; the Pareto front of two objectives
is checked against a brute-force non-dominated filter of the evaluations; and bad input is one line
naming the option before any work.
"""

from __future__ import annotations

import csv
import json
import math
import re
import tomllib

import pytest

pytest.importorskip("optuna")

from acoustiviz.app.impacts import room_settings  # noqa: E402
from acoustiviz.app.optimize import optimize_variables, run  # noqa: E402
from acoustiviz.app.scene_optimize import optimize_settings  # noqa: E402
from acoustiviz.app.settings.optimize import OptimizeJob  # noqa: E402
from acoustiviz.app.sweep import with_room  # noqa: E402
from acoustiviz.cli import build_parser, main  # noqa: E402
from acoustiviz.cli.optimize import settings_from_args  # noqa: E402
from acoustiviz.errors import ParameterError, SceneError  # noqa: E402
from acoustiviz.scene import scene_from_dict  # noqa: E402

FILES = ("evaluations.csv", "pareto.csv", "optimize.json", "pareto.png")
BAND = ("inclination_two_maxima_m_s>=0.002", "inclination_two_maxima_m_s<=0.008")
#: A tiny problem: 0.3 s of motion per design, 6 evaluations in batches of 4 (one batch and a partial one).
ARGV = ("--gap", "0.01:0.06", "--m", "0.01:0.08", "--minimize", "max_spl_db", "--constraint", BAND[0],
        "--constraint", BAND[1], "--evaluations", "6", "--batch", "4", "--seed", "3", "--duration", "0.3",
        "--workers", "1")
SCENE = ('[outputs.optimize]\ngap_m = "0.01:0.06"\nmass_kg = "0.01:0.08"\nminimize = ["max_spl_db"]\n'
         f'constraints = ["{BAND[0]}", "{BAND[1]}"]\nevaluations = 6\nbatch = 4\nseed = 3\nduration_s = 0.3\n'
         'workers = 1\n')


def _api_job(out, duration=0.3, **kw) -> OptimizeJob:
    variables, fixed = optimize_variables({"gap": "0.01:0.06", "m": "0.01:0.08", "duration": duration})
    values = dict(minimize=("max_spl_db",), constraints=BAND, evaluations=6, batch=4, seed=3, out=str(out),
                  workers=1)
    values.update(kw)
    return OptimizeJob(variables, fixed, **values)


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_every_front_end_writes_the_same_files(tmp_path, capsys):
    assert main(["optimize", *ARGV, "--out", str(tmp_path / "cli")]) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    assert "optimize: 6 designs evaluated" in out and ("best design" in out or "no evaluated design" in out)
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    written = run(_api_job(api)).write()
    assert sorted(p.name for p in written) == sorted(FILES)
    for name in FILES:
        mine = (tmp_path / "cli" / name).read_bytes()
        assert len(mine) > 100
        assert (tmp_path / "scene" / "optimize" / name).read_bytes() == mine, f"the scene's {name} differs"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs"
    rows = _rows(tmp_path / "cli" / "evaluations.csv")
    assert [int(r["evaluation"]) for r in rows] == list(range(6))
    for r in rows:  # every design within the bounds, feasible exactly when it meets the band
        assert 0.01 <= float(r["gap_m"]) <= 0.06 and 0.01 <= float(r["mass_kg"]) <= 0.08
        inc = float(r["inclination_two_maxima_m_s"])
        assert (r["feasible"] == "true") == (0.002 <= inc <= 0.008 and not r["error"])


def test_the_command_line_and_a_scene_build_equal_settings(tmp_path):
    args = build_parser().parse_args(["optimize", *ARGV, "--out", str(tmp_path / "optimize")])
    from_cli = settings_from_args(args)
    from_scene = optimize_settings(scene_from_dict(tomllib.loads(SCENE)), tmp_path)
    assert from_cli == from_scene
    assert from_cli.out == from_scene.out == str(tmp_path / "optimize")
    assert [v.name for v in from_cli.problem.searched] == ["gap", "m"]


def test_the_same_seed_gives_the_same_designs_and_another_seed_others(tmp_path):
    a = run(_api_job(tmp_path / "a"))
    b = run(_api_job(tmp_path / "b"))
    c = run(_api_job(tmp_path / "c", seed=4))
    assert [r["params"] for r in a.records] == [r["params"] for r in b.records]
    assert [r["params"] for r in a.records] != [r["params"] for r in c.records]


def test_a_resumed_run_keeps_every_finished_evaluation_and_asks_the_same_designs(tmp_path):
    whole = run(_api_job(tmp_path / "whole"))
    part = tmp_path / "part"
    run(_api_job(part, evaluations=5))  # stopped after 5 evaluations: one inside the second batch
    journal = (part / "journal.jsonl").read_text().splitlines()
    assert len(journal) == 5
    # a kill in the middle of writing the next line leaves a torn line, which is dropped
    with open(part / "journal.jsonl", "a") as fh:
        fh.write('{"evaluation": 5, "par')
    # a larger budget continues the same run: the designs of a batch depend only on those before it
    resumed = run(_api_job(part), progress=None)
    assert [r["params"] for r in resumed.records] == [r["params"] for r in whole.records]
    kept = [json.loads(line) for line in journal]
    assert [r["row"] for r in resumed.records[:5]] == [k["row"] for k in kept]  # not recomputed
    assert len((part / "journal.jsonl").read_text().splitlines()) == 6


def test_a_folder_of_another_optimisation_is_refused(tmp_path):
    run(_api_job(tmp_path, evaluations=1)).write()
    with pytest.raises(ParameterError, match=r"^--out: .*other settings"):
        _api_job(tmp_path, evaluations=2, seed=4, names={"out": "--out"})


def test_a_design_that_fails_is_a_row_with_its_reason(tmp_path, monkeypatch):
    import acoustiviz.sweep.evaluate as evaluate

    real = evaluate.evaluate_design

    def overflow_beyond_4_cm(design, settings):
        if design.gap > 0.04:
            raise FloatingPointError("overflow in the contact force")
        return real(design, settings)

    monkeypatch.setattr(evaluate, "evaluate_design", overflow_beyond_4_cm)  # the forked workers inherit it
    rows = run(_api_job(tmp_path, evaluations=8, batch=8)).rows
    failed = [r for r in rows if r["gap_m"] > 0.04]
    assert failed and len(failed) < len(rows)
    for r in failed:
        assert r["error"] == "FloatingPointError: overflow in the contact force"
        assert r["feasible"] is False and r["pareto"] is False and math.isnan(r["max_spl_db"]) and r["success"] == 0
    assert all(not r["error"] for r in rows if r["gap_m"] <= 0.04)


def test_constraints_decide_feasibility_and_an_infeasible_run_says_so(tmp_path, capsys):
    assert main(["optimize", "--gap", "0.01:0.06", "--minimize", "max_spl_db", "--constraint", "max_spl_db<=0",
                 "--evaluations", "3", "--duration", "0.3", "--workers", "1", "--out", str(tmp_path)]) == 0
    assert "no evaluated design is feasible" in capsys.readouterr().out
    rows = _rows(tmp_path / "evaluations.csv")
    assert all(r["feasible"] == "false" for r in rows) and len(_rows(tmp_path / "pareto.csv")) == 0


def test_two_objectives_give_the_brute_force_non_dominated_designs(tmp_path):
    job = _api_job(tmp_path, minimize=("max_spl_db",), maximize=("inclination_two_maxima_m_s",), constraints=(),
                   evaluations=12, duration=1.0)
    result = run(job)
    rows = [r for r in result.rows if r["feasible"]]
    pts = [(r["max_spl_db"], -r["inclination_two_maxima_m_s"]) for r in rows]
    expected = [r["evaluation"] for r, p in zip(rows, pts, strict=True)
                if not any(q[0] <= p[0] and q[1] <= p[1] and q != p for q in pts)]
    assert [r["evaluation"] for r in result.best()] == expected
    assert len(rows) >= 6 and len(expected) >= 1
    result.write()
    assert [int(r["evaluation"]) for r in _rows(tmp_path / "pareto.csv")] == expected


@pytest.mark.parametrize(("argv", "message"), [
    (("--gap", "0.01:0.06", "--minimize", "loudness"), r"--minimize: unknown column 'loudness'"),
    (("--gap", "0.06:0.01", "--minimize", "max_spl_db"), r"--gap: needs LO < HI"),
    (("--gap", "0.01:x", "--minimize", "max_spl_db"), r"--gap: expected .*non-number"),
    (("--gap", "0.01:20", "--minimize", "max_spl_db"), r"--gap: "),
    (("--gap", "0.01:0.06", "--minimize", "max_spl_db", "--evaluations", "0"), r"--evaluations: "),
    (("--gap", "0.01:0.06", "--minimize", "max_spl_db", "--executor", "spark://h:1"), r"--executor: "),
    (("--gap", "0.01:0.06", "--minimize", "max_spl_db", "--constraint", "max_spl_db<100"), r"--constraint: "),
    (("--gap", "0.01:0.06", "--minimize", "lafmax_db"), r"--minimize: .*--levels"),
    (("--minimize", "max_spl_db",), r"--gap: no variable to search"),
])
def test_bad_input_is_one_line_naming_the_option_before_any_work(argv, message, tmp_path, capsys):
    assert main(["optimize", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert re.search(message, err), err
    assert not (tmp_path / "o").exists()


#: The sweep's room (absorbing walls, a 5 ms window) on the command line and as a scene's configuration.
ROOM_ARGV = ("--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905", "--room-window", "0.005")
ROOM_SCENE = ('[configuration]\nkind = "room"\nroom_m = [3.0, 2.5, 2.0]\nabsorption = [0.3]\n'
              'source_m = [1.0, 1.0, 0.01905]\nwindow_s = 0.005\n')
#: Two designs in the room: enough to compare the front ends.
ROOM_BUDGET = ("--evaluations", "2", "--batch", "2")


def test_an_optimisation_in_a_room_is_the_same_from_every_front_end(tmp_path, capsys):
    argv = ["optimize", *ARGV, *ROOM_BUDGET, *ROOM_ARGV, "--out"]
    from_cli = settings_from_args(build_parser().parse_args([*argv, str(tmp_path / "scene" / "optimize")]))
    scene_text = ROOM_SCENE + SCENE.replace("evaluations = 6\nbatch = 4", "evaluations = 2\nbatch = 2")
    from_scene = optimize_settings(scene_from_dict(tomllib.loads(scene_text)), tmp_path / "scene")
    assert from_cli.fixed.room is not None
    assert from_cli == from_scene
    assert main([*argv, str(tmp_path / "cli")]) == 0, capsys.readouterr().err
    toml = tmp_path / "scene.toml"
    toml.write_text(scene_text)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    room = room_settings("3,2.5,2", absorption="0.3", source="1,1,0.01905", duration=0.005)
    variables, fixed = optimize_variables(with_room({"gap": "0.01:0.06", "m": "0.01:0.08", "duration": 0.3}, room))
    api = tmp_path / "api"
    run(OptimizeJob(variables, fixed, minimize=("max_spl_db",), constraints=BAND, evaluations=2, batch=2, seed=3,
                    out=str(api), workers=1)).write()
    for name in FILES:
        mine = (tmp_path / "cli" / name).read_bytes()
        assert (tmp_path / "scene" / "optimize" / name).read_bytes() == mine, f"the scene's {name} differs"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs"
    room = dict(json.loads((api / "optimize.json").read_text())["fixed"]["room"])  # the numbers, typed or listed
    assert room["dimensions"] == [3.0, 2.5, 2.0] and room["absorption"] == [0.3] and room["duration"] == 0.005
    rows = _rows(api / "evaluations.csv")
    assert len(rows) == 2 and all(r["config"] == "room" and not r["error"] for r in rows)


@pytest.mark.parametrize(("argv", "message"), [
    (("--room", "3,2.5"), r"error: --room: "),
    (("--room", "3,2.5,2", "--absorption", "1.5", "--room-window", "0.005"), r"error: --absorption: "),
    (("--room", "3,2.5,2", "--source", "9,1,0.01905", "--room-window", "0.005"), r"error: --source: "),
    (("--room-window", "0.005",), r"error: --room-window: only applies with --room"),
    (("--absorption", "0.3",), r"error: --absorption: only applies with --room"),
    (("--room", "3,2.5,2", "--config", "plane", "--room-window", "0.005"), r"error: --config: "),
])
def test_a_bad_room_option_is_one_line_naming_it(argv, message, tmp_path, capsys):
    assert main(["optimize", "--gap", "0.01:0.06", "--minimize", "max_spl_db", *argv,
                 "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert re.search(message, err), err
    assert not (tmp_path / "o").exists()


def test_in_operation_the_room_reaches_the_designs_as_in_free_vibration(tmp_path):
    # a sweep in operation takes a room, so an optimisation in operation does: the same room from both front ends
    argv = ["optimize", "--gap", "0.04", "--m", "0.03:0.06", "--force", "5", "--freq", "6.5,7", "--starts", "2",
            "--minimize", "worst_laeq_db", "--evaluations", "3", "--workers", "1", *ROOM_ARGV,
            "--out", str(tmp_path / "optimize")]
    from_cli = settings_from_args(build_parser().parse_args(argv))
    scene = ROOM_SCENE + ('[damper]\nsolver = "event"\n[excitation]\nkind = "force"\namplitude = 5.0\n'
                          'frequencies_hz = "6.5,7"\nstarts = 2\n[outputs.optimize]\ngap_m = "0.04"\n'
                          'mass_kg = "0.03:0.06"\nminimize = ["worst_laeq_db"]\nevaluations = 3\nworkers = 1\n'
                          'in_operation = true\n')
    from_scene = optimize_settings(scene_from_dict(tomllib.loads(scene)), tmp_path)
    assert from_cli.mode == from_scene.mode == "operation"
    assert dict(from_cli.fixed.room)["dimensions"] == (3.0, 2.5, 2.0)
    assert from_cli == from_scene


def _balls_job(out, evaluations=4, **given) -> OptimizeJob:
    """A tiny search over the number of balls 1 to 3 and the fill (0.2 s of motion per design)."""
    variables, fixed = optimize_variables({"balls": "1:3", "fill": "0.2:0.6", "duration": 0.2, **given})
    return OptimizeJob(variables, fixed, minimize=("max_spl_db",), evaluations=evaluations, batch=2, seed=1,
                       out=str(out), workers=1)


def test_an_optimisation_over_the_balls_evaluates_whole_numbers_and_resumes(tmp_path):
    job = _balls_job(tmp_path / "whole")
    (balls,) = [v for v in job.variables if v.name == "balls"]
    assert (balls.kind, balls.low, balls.high) == ("int", 1, 3)
    assert json.loads(json.dumps(job.document()))["variables"][-2:] == [
        {"name": "balls", "kind": "int", "low": 1, "high": 3}, {"name": "fill", "kind": "float", "low": 0.2,
                                                               "high": 0.6}]
    assert "gap" not in {v.name for v in job.variables}  # the fill sets the gap
    whole = run(job)
    whole.write()
    asked = [r["params"]["balls"] for r in whole.records]
    assert all(type(n) is int and 1 <= n <= 3 for n in asked)
    rows = _rows(tmp_path / "whole" / FILES[0])
    assert [int(r["balls"]) for r in rows] == asked
    assert all(0.2 <= float(r["fill"]) <= 0.6 and r["error"] == "" for r in rows)
    part = tmp_path / "part"
    run(_balls_job(part, evaluations=3))  # stopped inside the second batch
    resumed = run(_balls_job(part), progress=None)
    resumed.write()
    assert [r["params"] for r in resumed.records] == [r["params"] for r in whole.records]
    assert (part / FILES[0]).read_bytes() == (tmp_path / "whole" / FILES[0]).read_bytes()


@pytest.mark.parametrize("argv, message", [
    (["--balls", "1.5:3"], "--balls: must be whole numbers"),
    (["--balls", "log:1:3"], "--balls: a whole number takes"),
])
def test_bad_balls_are_one_line_naming_the_option(argv, message, tmp_path, capsys):
    status = main(["optimize", *argv, "--minimize", "max_spl_db", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert status == 2 and message in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("objective", [["--minimize", "worst_laeq_db"], ["--maximize", "worst_lcpeak_db"],
                                       ["--minimize", "worst_amplitude_m", "--constraint", "worst_lafmax_db<=90"]])
def test_a_level_objective_in_operation_is_accepted_with_several_balls(objective, tmp_path):
    argv = ["optimize", "--balls", "1:3", "--force", "5", "--freq", "6.5,7", *objective, "--out", str(tmp_path / "o")]
    job = settings_from_args(build_parser().parse_args(argv))  # validated: several balls are heard in operation
    assert [v.name for v in job.problem.searched] == ["balls"] and job.operation is not None
    columns = [item.column for item in (*job.problem.objectives, *job.problem.constraints)]
    assert set(columns) & {"worst_laeq_db", "worst_lcpeak_db", "worst_lafmax_db"}
    assert not (tmp_path / "o").exists()


#: An optimisation over the balls and their fill at equal total mass, on the command line and in a scene.
BALLS_ARGV = ("--balls", "1:3", "--fill", "0.2:0.8", "--m", "0.0405", "--equal-total-mass", "--k-hertz-ball", "1e9",
              "--minimize", "max_spl_db", "--evaluations", "6", "--batch", "4", "--duration", "0.3", "--workers", "1")
BALLS_SCENE = ('[damper]\nk_hertz_ball_n_m1_5 = 1e9\n[outputs.optimize]\nballs = "1:3"\nfill = "0.2:0.8"\n'
               'mass_kg = "0.0405"\nequal_total_mass = true\nminimize = ["max_spl_db"]\nevaluations = 6\nbatch = 4\n'
               'duration_s = 0.3\nworkers = 1\n')


def test_a_scene_searches_the_balls_and_the_fill_as_the_command_line(tmp_path):
    args = build_parser().parse_args(["optimize", *BALLS_ARGV, "--out", str(tmp_path / "optimize")])
    from_cli = settings_from_args(args)
    from_scene = optimize_settings(scene_from_dict(tomllib.loads(BALLS_SCENE)), tmp_path)
    assert from_cli == from_scene
    assert from_cli.fixed == from_scene.fixed and from_scene.fixed.equal_total_mass
    assert from_scene.fixed.k_hertz_ball == 1e9
    searched = {v.name: v for v in from_scene.problem.searched}
    assert sorted(searched) == ["balls", "fill"]
    assert (searched["balls"].kind, searched["balls"].low, searched["balls"].high) == ("int", 1, 3)
    assert from_scene.names["balls"] == "outputs.optimize.balls" and from_cli.names["balls"] == "--balls"


@pytest.mark.parametrize("key, value, message", [
    ("balls", '"1.5:3"', "outputs.optimize.balls: must be whole numbers"),
    ("balls", '"log:1:3"', "outputs.optimize.balls: a whole number takes"),
    ("fill", '"0.2:1.5"', "outputs.optimize.fill:"),
])
def test_a_scene_s_bad_balls_or_fill_are_refused_naming_the_key(key, value, message, tmp_path):
    text = BALLS_SCENE.replace(f'{key} = "{"1:3" if key == "balls" else "0.2:0.8"}"', f"{key} = {value}")
    with pytest.raises((ParameterError, SceneError), match=re.escape(message)):
        optimize_settings(scene_from_dict(tomllib.loads(text)), tmp_path)


def test_a_scene_with_both_gap_and_fill_is_refused_naming_both(tmp_path):
    text = BALLS_SCENE.replace('fill = "0.2:0.8"\n', 'fill = "0.2:0.8"\ngap_m = "0.04"\n')
    with pytest.raises(SceneError, match=r"outputs\.optimize\.fill: give either outputs\.optimize\.gap_m"):
        scene_from_dict(tomllib.loads(text))
