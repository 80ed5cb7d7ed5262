"""The damper job: one settings object, one run and one writer for the command line, scenes and the API.

The same damper run is asked for three ways (``acoustiviz damper``, a scene's ``[outputs.impact_table]``
and ``[outputs.damper_history]``, and :class:`~acoustiviz.app.damper.DamperJob` built in Python) and the
files are compared byte for byte; the command line and the scene must build equal settings objects; the
settings refuse bad input before any work, naming the front end's option or key; a scene runs its damper
once for every output that wants it.
"""

from __future__ import annotations

import tomllib

import pytest

import acoustiviz.app.damper
import acoustiviz.dynamics
from acoustiviz.app.damper import DamperJob, damper_model, run
from acoustiviz.app.pipeline import damper_settings
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.damper import settings_from_args
from acoustiviz.dynamics import InitialState
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

#: The files of the job, as the scene names them.
FILES = {"impacts_csv": "impacts.csv", "history_csv": "damper_history.csv", "png": "damper_history.png"}

#: A short run of the paper's damper (Table 1, Figure 5 start) with the event solver: the scene states
#: the contact stiffness and the solver, which it otherwise takes from the sphere's material and "auto".
SCENE = ('[damper]\nduration_s = 1.0\nsolver = "event"\n[contact]\nk_hertz_n_m1_5 = 5.6e8\n'
         '[outputs.impact_table]\n[outputs.damper_history]\n')
ARGV = ("damper", "--duration", "1", "--solver", "event")


def _options(folder=None) -> list:
    prefix = "" if folder is None else f"{folder}/"
    return ["--impacts-csv", prefix + FILES["impacts_csv"], "--history-csv", prefix + FILES["history_csv"],
            "--png", prefix + FILES["png"]]


def test_every_front_end_writes_the_same_files(tmp_path, monkeypatch, capsys):
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main([*ARGV, *_options()]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert [line for line in printed.splitlines() if line.startswith("wrote ")] \
        == [f"wrote {FILES[k]}" for k in ("impacts_csv", "history_csv", "png")]
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    written = run(DamperJob(damper_model(), duration=1.0, **FILES)).write(api)
    assert [p.name for p in written] == list(FILES.values())
    for name in FILES.values():
        mine = (cli / name).read_bytes()
        assert len(mine) > 100
        assert (tmp_path / "scene" / name).read_bytes() == mine, f"the scene's {name} differs from the CLI's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"


@pytest.mark.parametrize("solver", ["event", "auto"])
def test_the_command_line_and_a_scene_build_equal_settings(solver, tmp_path):
    # the scene's memory cap (grids.memory_limit_mb) defaults to 256 MB, the command line's to --max-memory's
    argv = ["damper", "--duration", "1", "--solver", solver, "--max-memory", "256", *_options(tmp_path)]
    from_cli = settings_from_args(build_parser().parse_args(argv))
    scene = scene_from_dict(tomllib.loads(SCENE.replace('"event"', f'"{solver}"')))
    from_scene = damper_settings(scene, tmp_path)
    assert from_cli == from_scene
    assert from_cli.solver == solver and from_cli.initial == InitialState(x=0.0, v=2.0)
    assert from_cli.files() == {k: str(tmp_path / v) for k, v in FILES.items()}
    # without files: the checks made before the run folder exists
    assert damper_settings(scene).files() == {}


def test_a_scene_writes_only_the_files_of_the_outputs_it_asks_for(tmp_path):
    scene = scene_from_dict(tomllib.loads(SCENE.replace("[outputs.damper_history]\n", "")))
    assert damper_settings(scene, tmp_path).files() == {"impacts_csv": str(tmp_path / "impacts.csv")}


@pytest.fixture
def no_simulation(monkeypatch):
    """Fail a test that simulates the damper."""
    def refuse(*args, **kwargs):
        raise AssertionError("the damper was simulated")

    monkeypatch.setattr(acoustiviz.dynamics, "simulate", refuse)


def test_a_run_too_big_for_the_memory_cap_is_refused_before_any_work(tmp_path, monkeypatch, capsys, no_simulation):
    monkeypatch.chdir(tmp_path)
    # Table 1's main period is 0.199 s, 200 samples of 128 B each: 20 s of motion needs about 2.6 MB
    assert main([*ARGV[:1], "--duration", "20", "--max-memory", "1", *_options()]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("acoustiviz damper: error: --duration: ") and "--max-memory" in err
    assert len(err.splitlines()) == 1
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE.replace("duration_s = 1.0", "duration_s = 20.0") + "[grids]\nmemory_limit_mb = 1.0\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "damper.duration_s: " in err and "grids.memory_limit_mb" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]  # nothing written, not even the folder


def test_a_tolerance_outside_the_solvers_range_names_the_option_or_key(tmp_path, capsys, no_simulation):
    # the event solver's tolerance reaches 0.5 at most, whatever the option's whole range
    assert main([*ARGV, "--rtol", "0.9"]) == 2
    assert capsys.readouterr().err.startswith("acoustiviz damper: error: --rtol: ")
    with pytest.raises(ParameterError, match=r"^rtol: "):
        DamperJob(damper_model(), duration=1.0, rtol=0.9)
    with pytest.raises(ParameterError, match=r"^--rtol: "):
        DamperJob(damper_model(), duration=1.0, rtol=0.9, names={"rtol": "--rtol"})


def test_the_api_checks_the_model_and_the_start_against_the_records(no_simulation):
    with pytest.raises(ParameterError, match=r"^damper.gap_m: .*\(0, 10\] m"):
        DamperJob(damper_model(gap=20.0), duration=1.0, names={"gap": "damper.gap_m"})
    with pytest.raises(ParameterError, match=r"^v0: "):
        DamperJob(damper_model(), InitialState(v=5e3), duration=1.0)
    with pytest.raises(ParameterError, match=r"^duration: "):
        DamperJob(damper_model(), duration=-1.0)


def test_two_files_of_one_name_are_refused(tmp_path, capsys, no_simulation):
    same = str(tmp_path / "x.csv")
    assert main([*ARGV, "--impacts-csv", same, "--history-csv", same]) == 2
    err = capsys.readouterr().err
    assert err.startswith("acoustiviz damper: error: --history-csv: names the same file as --impacts-csv")
    assert not (tmp_path / "x.csv").exists()


def test_a_scene_runs_its_damper_once_for_every_output(tmp_path, monkeypatch):
    from acoustiviz.app.pipeline import run_scene

    calls = []
    real = acoustiviz.app.damper.run

    def counted(settings):
        calls.append(settings)
        return real(settings)

    monkeypatch.setattr(acoustiviz.app.damper, "run", counted)
    products = run_scene(scene_from_dict(tomllib.loads(SCENE)), tmp_path / "out")
    assert len(calls) == 1
    assert sorted(p.path.name for p in products) == sorted([*FILES.values(), "summary.md"])
    table = next(p for p in products if p.path.name == "impacts.csv")
    history = next(p for p in products if p.path.name == "damper_history.png")
    assert table.figures["impacts"] == history.figures["impacts"] != "0"


#: The same short run with three balls in the cavity, as the scene and the command line give it.
BALLS_SCENE = SCENE.replace('solver = "event"\n', 'solver = "event"\nballs = 3\nk_hertz_ball_n_m1_5 = 2e9\n'
                            'contact_damping_ball_n_s_m = 10.0\n')
BALLS_ARGV = (*ARGV, "--balls", "3", "--k-hertz-ball", "2e9", "--c1-ball", "10")


def test_several_balls_write_the_same_files_from_every_front_end(tmp_path, monkeypatch, capsys):
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main([*BALLS_ARGV, *_options()]) == 0, capsys.readouterr().err
    capsys.readouterr()
    toml = tmp_path / "scene.toml"
    toml.write_text(BALLS_SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    job = DamperJob(damper_model(), duration=1.0, balls=3, k_hertz_ball=2e9, c1_ball=10.0, **FILES)
    assert [p.name for p in run(job).write(api)] == list(FILES.values())
    for name in FILES.values():
        mine = (cli / name).read_bytes()
        assert (tmp_path / "scene" / name).read_bytes() == mine, f"the scene's {name} differs from the CLI's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"
    rows = (cli / FILES["impacts_csv"]).read_text().splitlines()
    assert rows[0].split(",")[:3] == ["time_s", "first", "second"]
    bodies = {tuple(r.split(",")[1:3]) for r in rows[1:]}
    assert bodies <= {("wall-", "ball1"), ("ball1", "ball2"), ("ball2", "ball3"), ("ball3", "wall+")}
    assert ("ball1", "ball2") in bodies and ("wall-", "ball1") in bodies
    history = (cli / FILES["history_csv"]).read_text().splitlines()[0]
    assert history == "time_s,x_m,v_m_s,y1_m,y2_m,y3_m,w1_m_s,w2_m_s,w3_m_s"


def test_several_balls_from_the_command_line_and_a_scene_are_equal_settings(tmp_path):
    argv = ["damper", "--duration", "1", "--solver", "event", "--balls", "3", "--k-hertz-ball", "2e9", "--c1-ball",
            "10", "--max-memory", "256", *_options(tmp_path)]
    from_cli = settings_from_args(build_parser().parse_args(argv))
    from_scene = damper_settings(scene_from_dict(tomllib.loads(BALLS_SCENE)), tmp_path)
    assert from_cli == from_scene
    assert (from_cli.balls, from_cli.k_hertz_ball, from_cli.c1_ball) == (3, 2e9, 10.0)


def test_one_ball_is_the_default_and_the_single_ball_run(tmp_path):
    from_cli = settings_from_args(build_parser().parse_args(list(ARGV)))
    assert (from_cli.balls, from_cli.k_hertz_ball, from_cli.c1_ball) == (1, None, None)
    assert from_cli == DamperJob(damper_model(), duration=1.0, solver="event")


@pytest.mark.parametrize("extra, option", [(("--balls", "0"), "--balls"), (("--balls", "2.5"), "--balls"),
                                           (("--balls", "2", "--solver", "newmark"), "--solver"),
                                           (("--balls", "2", "--k-hertz-ball", "-1"), "--k-hertz-ball"),
                                           (("--balls", "2", "--c1-ball", "-1"), "--c1-ball")])
def test_bad_balls_are_refused_naming_the_option(extra, option, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    try:
        status = main([*ARGV, *extra, "--impacts-csv", "i.csv"])
    except SystemExit as stop:  # argparse refuses a value that is not a number itself
        status = stop.code
    err = capsys.readouterr().err.strip()
    assert status == 2
    assert err.startswith(f"acoustiviz damper: error: {option}") or f"argument {option}" in err
    assert list(tmp_path.iterdir()) == []


def test_a_scene_refuses_a_late_tail_for_several_balls_in_a_room_before_any_work(tmp_path, capsys, no_simulation):
    toml = tmp_path / "scene.toml"
    toml.write_text('[configuration]\nkind = "room"\nroom_m = [3.0, 2.5, 2.0]\nabsorption = [0.3]\n'
                    "[damper]\nballs = 2\n[outputs.wav]\nlate_tail = true\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "outputs.wav.late_tail: " in err and "several balls (2) in a room" in err
    assert not (tmp_path / "out").exists()
