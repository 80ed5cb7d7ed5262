"""Several balls in operation through the forced job: ``forced --balls N``, a scene's ``[[damper.cavities]]``, the API.

The same multi-ball damper in operation is asked for three ways and the files compared byte for byte; the
command line and the scene build equal settings objects, with and without the noise in operation; ``--balls 1``
is today's single-ball job; bad input is refused before any work, naming the option or scene key.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import tomllib

import pytest

import acoustiviz.app.forced as job_module
import acoustiviz.dynamics.balls_forced as balls_forced
from acoustiviz.app.damper import damper_model
from acoustiviz.app.forced import BALL_CSV_COLUMNS, FORCED_CSV_COLUMNS, ForcedJob, forced_settings, run
from acoustiviz.app.settings.damper_job import DamperCavity
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.forced import settings_from_args
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

#: Two balls on a damper with a stable period-1 motion (4 Hz, 10 N, C = 5 N s/m): one frequency, one start.
ARGV = ("--C", "5", "--force", "10", "--freq", "4", "--balls", "2", "--k-hertz-ball", "3e8", "--c1-ball", "15",
        "--starts", "1", "--max-cycles", "40", "--sweep", "independent", "--no-noise")
SCENE = """
[damper]
damping_n_s_m = 5.0
balls = 2
k_hertz_ball_n_m1_5 = 3e8
contact_damping_ball_n_s_m = 15.0
[excitation]
amplitude = 10.0
frequencies_hz = "4"
starts = 1
max_cycles = 40
sweep = "independent"
[outputs.frequency_response]
"""
API = dict(frequencies=(4.0,), kind="force", amplitude=10.0, starts=1, max_cycles=40, sweep="independent",
           noise=False, balls=2, k_hertz_ball=3e8, c1_ball=15.0)
CAVITIES = """
[[damper.cavities]]
gap_m = 0.03
balls = 2
impact_mass_kg = 0.02
[[damper.cavities]]
gap_m = 0.05
"""


def _no_work(monkeypatch):
    """Make any search for attractors fail the test: bad input must be refused before it."""
    def refuse(*args, **kwargs):
        raise AssertionError("the attractors were computed")

    monkeypatch.setattr(job_module, "attractor_response", refuse)
    monkeypatch.setattr(balls_forced, "ball_attractor_response", refuse)


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_every_front_end_writes_the_same_files(tmp_path, monkeypatch, capsys):
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main(["forced", *ARGV, "--csv", "f.csv", "--png", "f.png"]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert "2 balls in 1 cavity: attractors reached by simulation" in printed
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene"), "--quiet"]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    result = run(ForcedJob(damper_model(C=5.0), **API, csv="f.csv", png="f.png",
                           response_png="frequency_response.png"))
    result.write(api)
    for name in ("f.csv", "f.png"):
        assert len((cli / name).read_bytes()) > 100
        assert (api / name).read_bytes() == (cli / name).read_bytes(), f"the API's {name} differs from the CLI's"
    scene = tmp_path / "scene"
    assert (scene / "frequency_response.csv").read_bytes() == (cli / "f.csv").read_bytes()
    assert (scene / "frequency_response.png").read_bytes() == (api / "frequency_response.png").read_bytes()
    (row,) = _rows(cli / "f.csv")
    assert tuple(row) == FORCED_CSV_COLUMNS + BALL_CSV_COLUMNS
    assert row["balls"] == "2" and row["cavities"] == "1" and row["stable"] == "true"
    total = float(row["wall_impacts_per_cycle"]) + float(row["ball_collisions_per_cycle"])
    assert total == pytest.approx(float(row["impacts_per_cycle"]))


def test_the_command_line_and_a_scene_build_equal_settings(tmp_path):
    from_cli = settings_from_args(build_parser().parse_args(["forced", *ARGV, "--max-memory", "256"]))
    from_scene = forced_settings(scene_from_dict(tomllib.loads(SCENE)))
    assert from_cli == from_scene == ForcedJob(damper_model(C=5.0), **API, max_memory_mb=256.0)
    assert from_cli.several_balls and from_cli.ball_model().n_balls == 2
    assert from_cli.names["balls"] == "--balls" and from_scene.names["balls"] == "damper.balls"


#: The same job with its noise in operation at an ear: the command line, the scene, the API.
NOISE_ARGV = (*ARGV[:-1], "--noise-seconds", "0.2", "--listener", "0.495,0,0.514")
NOISE_SCENE = SCENE + """[outputs.operating_noise]
seconds = 0.2
[[listeners]]
name = "ear"
position_m = [0.495, 0.0, 0.514]
"""
NOISE_API = {**API, "noise": True, "noise_seconds": 0.2, "listener": (0.495, 0.0, 0.514)}


def test_the_noise_of_two_balls_is_the_same_from_every_front_end(tmp_path, monkeypatch, capsys):
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main(["forced", *NOISE_ARGV, "--wav", "f.wav", "--csv", "f.csv"]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert "noise in operation at (0.495,0,0.514) m" in printed and "LCpeak" in printed
    toml = tmp_path / "scene.toml"
    toml.write_text(NOISE_SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene"), "--quiet"]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    job = ForcedJob(damper_model(C=5.0), **NOISE_API, wav="f.wav", csv="f.csv", noise_csv="operating_noise.csv")
    run(job).write(api)
    scene = tmp_path / "scene"
    for name, theirs in (("f.wav", "operating_noise_ear.wav"), ("f.csv", "frequency_response.csv")):
        mine = (cli / name).read_bytes()
        assert len(mine) > 1000
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"
        assert (scene / theirs).read_bytes() == mine, f"the scene's {theirs} differs from the CLI's {name}"
    assert (scene / "operating_noise.csv").read_bytes() == (api / "operating_noise.csv").read_bytes()
    sidecars = [json.loads(path.read_text()) for path in (cli / "f.json", scene / "operating_noise_ear.json")]
    assert sidecars[0].pop("file") == "f.wav" and sidecars[1].pop("file") == "operating_noise_ear.wav"
    assert sidecars[0] == sidecars[1]
    (row,) = _rows(cli / "f.csv")
    assert row["balls"] == "2" and float(row["lcpeak_db"]) > float(row["laeq_db"]) > 0
    assert "lcpeak" in row["worst_case"]


def test_the_command_line_and_a_scene_build_equal_settings_with_the_noise():
    from_cli = settings_from_args(build_parser().parse_args(["forced", *NOISE_ARGV, "--max-memory", "256"]))
    from_scene = forced_settings(scene_from_dict(tomllib.loads(NOISE_SCENE)))
    assert from_cli == from_scene == ForcedJob(damper_model(C=5.0), **NOISE_API, max_memory_mb=256.0)
    assert from_cli.noise and from_cli.several_balls


def test_a_scene_with_several_cavities_runs_them(tmp_path):
    scene = scene_from_dict(tomllib.loads(SCENE.replace("balls = 2\n", "") + CAVITIES))
    job = forced_settings(scene)
    assert job.cavities == (DamperCavity(gap=0.03, balls=2, m=0.02), DamperCavity(gap=0.05))
    assert job == ForcedJob(damper_model(C=5.0), **{**API, "balls": 1}, cavities=job.cavities, max_memory_mb=256.0)
    result = run(job)
    (row,) = result.rows
    assert row["balls"] == 3 and row["cavities"] == 2 and result.success
    assert result.steady_states[0].poincare.shape[1] == 2 + 2 * 3


def test_worker_processes_write_the_same_table(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    argv = ["forced", *ARGV[:5], "4,4.5", *ARGV[6:]]  # two frequencies
    assert main([*argv, "--csv", "one.csv"]) == 0
    assert main([*argv, "--workers", "2", "--csv", "two.csv"]) == 0, capsys.readouterr().err
    capsys.readouterr()
    assert (tmp_path / "one.csv").read_bytes() == (tmp_path / "two.csv").read_bytes()


def test_one_ball_keeps_the_single_ball_job(tmp_path, monkeypatch, capsys):
    base = ("--force", "5", "--freq", "6.5", "--starts", "1", "--solver", "impact-map", "--max-cycles", "40",
            "--sweep", "independent", "--no-noise")
    monkeypatch.chdir(tmp_path)
    assert main(["forced", *base, "--csv", "a.csv"]) == 0
    assert main(["forced", *base, "--balls", "1", "--csv", "b.csv"]) == 0
    capsys.readouterr()
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    assert tuple(_rows(tmp_path / "b.csv")[0]) == FORCED_CSV_COLUMNS


@pytest.mark.parametrize("extra, option", [
    (["--balls", "2", "--listener", "0,0,0.03"], "--listener"),  # the listener inside the column of balls
    (["--balls", "2", "--no-noise", "--solver", "impact-map"], "--solver"),
    (["--balls", "0"], "--balls"),
    (["--balls", "2", "--no-noise", "--k-hertz-ball", "-1"], "--k-hertz-ball"),
    (["--balls", "2", "--no-noise", "--c1-ball", "-1"], "--c1-ball"),
    (["--balls", "2", "--no-noise", "--C", "100"], "--C"),  # overdamped: no closed-form flight
    # the section points of 1000 balls over a million cycles exceed the memory cap
    (["--balls", "1000", "--no-noise", "--max-cycles", "1000000", "--max-memory", "2048"], "--max-cycles"),
])
def test_bad_options_are_refused_before_any_work_naming_the_option(extra, option, tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    monkeypatch.chdir(tmp_path)
    assert main(["forced", "--force", "5", "--freq", "4", "--csv", "f.csv", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz forced: error: {option}") and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_bad_scene_settings_are_refused_naming_the_scene_key(monkeypatch):
    _no_work(monkeypatch)
    names = forced_settings(scene_from_dict(tomllib.loads(SCENE))).names
    job = dict(model=damper_model(C=5.0), **API, names=names)
    cases = [(dict(noise=True, listener=(0.0, 0.0, 0.03)), r"^listeners: .*inside"),
             (dict(balls=0), r"^damper\.balls: "),
             (dict(balls=2, cavities=(DamperCavity(),)), r"^damper\.balls: .*leave balls at 1"),
             (dict(balls=1, cavities=(DamperCavity(gap=-0.01),)), r"^damper\.cavities\[0\]\.gap_m: "),
             (dict(solver="newmark"), r"^excitation\.solver: ")]
    for change, message in cases:
        with pytest.raises(ParameterError, match=message):
            ForcedJob(**{**job, **change})


def test_a_bad_scene_is_refused_before_the_run_folder_is_made(tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE + "[outputs.operating_noise]\n[[listeners]]\nname = \"ear\"\nposition_m = [0, 0, 0.05]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "listeners: listener (0, 0, 0.05) m is inside" in err, err
    assert not (tmp_path / "out").exists()


def test_the_settings_keep_their_types_when_replaced():
    job = ForcedJob(damper_model(C=5.0), **API)
    assert dataclasses.replace(job, balls=3).ball_model().n_balls == 3


def test_the_noise_of_several_cavities_is_heard_from_each_place():
    placed = CAVITIES.replace("gap_m = 0.05\n", "gap_m = 0.05\nposition_m = [0.2, 0, 0]\n")
    noise = '[outputs.operating_noise]\nseconds = 0.2\n[[listeners]]\nname = "ear"\nposition_m = [0.495, 0.0, 0.514]\n'
    scene = scene_from_dict(tomllib.loads(SCENE.replace("balls = 2\n", "") + placed + noise))
    job = forced_settings(scene)
    assert job.noise and job.cavities[1].position == (0.2, 0.0, 0.0)
    result = run(job)
    (noise,) = result.noises
    balls = noise.rendering["balls"]
    assert balls["cavity_offsets_m"][1] == [0.2, 0.0, 0.0] and balls["ball_wall_contacts"] > 0
    (row,) = result.rows
    assert row["laeq_db"] == noise.laeq_db and row["lcpeak_db"] > row["laeq_db"] > 0
