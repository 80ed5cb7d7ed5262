"""Several cavities on the main mass: a scene's ``[[damper.cavities]]`` and the damper job's ``cavities``.

A two-cavity scene and the same :class:`~acoustiviz.app.damper.DamperJob` built in Python make equal
settings and write the same files byte for byte; the impact table names each cavity's bodies with its
number and the history has every cavity's balls; bad cavities, badly placed cavities and listeners inside
one are refused before any work, naming the scene key or the API parameter; the sound of several
cavities is the same from a scene and the API.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest

import acoustiviz.dynamics
from acoustiviz.app.damper import DamperCavity, DamperJob, balls_model, damper_model, run
from acoustiviz.app.pipeline import damper_settings
from acoustiviz.cli import main
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

FILES = {"impacts_csv": "impacts.csv", "history_csv": "damper_history.csv", "png": "damper_history.png"}

#: Two cavities: two balls of 20 g in 3 cm of travel, and one ball of [damper]'s mass in 5 cm.
SCENE = ('[damper]\nduration_s = 0.5\nsolver = "event"\n[contact]\nk_hertz_n_m1_5 = 5.6e8\n'
         "[[damper.cavities]]\ngap_m = 0.03\nballs = 2\nimpact_mass_kg = 0.02\n"
         "contact_damping_ball_n_s_m = 10.0\n"
         "[[damper.cavities]]\ngap_m = 0.05\n"
         "[outputs.impact_table]\n[outputs.damper_history]\n")

#: The same two cavities in the Python API.
CAVITIES = (DamperCavity(gap=0.03, balls=2, m=0.02, c1_ball=10.0), DamperCavity(gap=0.05))


@pytest.fixture
def no_simulation(monkeypatch):
    """Fail a test that simulates the damper."""
    def refuse(*args, **kwargs):
        raise AssertionError("the damper was simulated")

    monkeypatch.setattr(acoustiviz.dynamics, "simulate", refuse)
    monkeypatch.setattr(acoustiviz.dynamics, "simulate_balls", refuse)


def test_two_cavities_from_a_scene_and_the_api_write_the_same_files(tmp_path, capsys):
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    job = DamperJob(damper_model(), duration=0.5, cavities=CAVITIES, **FILES)
    assert [p.name for p in run(job).write(api)] == list(FILES.values())
    for name in FILES.values():
        mine = (tmp_path / "scene" / name).read_bytes()
        assert len(mine) > 100
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the scene's"
    rows = (api / FILES["impacts_csv"]).read_text().splitlines()
    assert rows[0].split(",")[:3] == ["time_s", "first", "second"]
    bodies = {tuple(r.split(",")[1:3]) for r in rows[1:]}
    first = {("c1:wall-", "c1:ball1"), ("c1:ball1", "c1:ball2"), ("c1:ball2", "c1:wall+")}
    second = {("c2:wall-", "c2:ball1"), ("c2:ball1", "c2:wall+")}
    assert bodies <= first | second  # a body meets only the bodies of its own cavity
    assert bodies & first and bodies & second and ("c1:ball1", "c1:ball2") in bodies
    history = (api / FILES["history_csv"]).read_text().splitlines()[0]
    assert history == "time_s,x_m,v_m_s,c1_y1_m,c1_y2_m,c2_y1_m,c1_w1_m_s,c1_w2_m_s,c2_w1_m_s"


def test_a_scene_and_the_api_build_the_same_job(tmp_path):
    from_scene = damper_settings(scene_from_dict(tomllib.loads(SCENE)), tmp_path)
    api = DamperJob(damper_model(), duration=0.5, max_memory_mb=256.0, cavities=CAVITIES,
                    **{k: str(tmp_path / v) for k, v in FILES.items()})
    assert from_scene == api
    assert from_scene.total_balls() == 3


def test_each_cavity_takes_the_values_it_leaves_out_from_the_model():
    model = damper_model(gap=0.04, m=0.05, c1=30.0)
    multi = balls_model(DamperJob(model, duration=0.5, cavities=CAVITIES))
    one, two = multi.cavities
    assert (one.gap, one.masses, one.c_ball) == (0.03, (0.02, 0.02), 10.0)
    assert (two.gap, two.masses, two.c_wall) == (0.05, (0.05,), 30.0)
    assert one.k_wall == two.k_wall == model.k_hertz
    assert (multi.M, multi.K, multi.C) == (model.M, model.K, model.C)


def test_a_scene_without_cavities_builds_the_one_cavity_job(tmp_path):
    scene = scene_from_dict(tomllib.loads(SCENE.split("[[damper.cavities]]")[0] + "[outputs.impact_table]\n"))
    job = damper_settings(scene, tmp_path)
    assert job.cavities == () and job.balls == 1


def test_a_bad_cavity_is_refused_naming_its_key(tmp_path, capsys, no_simulation):
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE.replace("gap_m = 0.05", "gap_m = -0.05"))
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "damper.cavities[1].gap_m: " in err and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("text, key", [("[damper.cavities]\ngap_m = 0.05\n", "damper.cavities"),
                                       ("[[damper.cavities]]\nballs = 0\n", "damper.cavities[0].balls"),
                                       ("[[damper.cavities]]\nwidth_m = 0.1\n", "damper.cavities[0].width_m")])
def test_a_malformed_cavity_is_refused_naming_its_key(text, key, tmp_path, capsys, no_simulation):
    toml = tmp_path / "scene.toml"
    toml.write_text("[damper]\nduration_s = 0.5\n" + text + "[outputs.impact_table]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    assert f"{key}: " in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("kwargs, name", [({"cavities": (DamperCavity(gap=-1.0),)}, "cavities[0].gap"),
                                          ({"cavities": (DamperCavity(), DamperCavity(m=0.0))}, "cavities[1].m"),
                                          ({"cavities": (DamperCavity(m=1e-9),)}, "cavities[0].m"),
                                          ({"cavities": CAVITIES, "balls": 2}, "balls"),
                                          ({"cavities": CAVITIES, "solver": "newmark"}, "solver")])
def test_the_api_refuses_a_bad_cavity_naming_its_parameter(kwargs, name, no_simulation):
    with pytest.raises(ParameterError) as info:
        DamperJob(damper_model(), duration=0.5, **kwargs)
    assert info.value.name == name


def test_a_cavity_whose_contacts_cannot_be_followed_is_refused_naming_its_key(tmp_path, capsys, no_simulation):
    # a ball far lighter than the main mass: in its record's range, below what the solver can follow
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE.replace("gap_m = 0.05", "gap_m = 0.05\nimpact_mass_kg = 1e-9"))
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    assert "damper.cavities[1].impact_mass_kg: " in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("where, message", [("[0.0, 0.0, 0.0]", "cavity 2 overlaps cavity 1"),
                                            ("[0.0, 0.0, -0.5]", "cavity 2's balls would leave the fluid"),
                                            ("[0.1, 0.2]", "3 numbers")])
@pytest.mark.parametrize("output", ["wav", "levels", "spectrum"])
def test_a_cavity_placed_badly_is_refused_before_any_work(output, where, message, tmp_path, capsys, no_simulation):
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE.replace("gap_m = 0.05\n", f"gap_m = 0.05\nposition_m = {where}\n")
                    + f"[outputs.{output}]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "damper.cavities[1].position_m: " in err
    assert message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_a_listener_inside_a_cavity_placed_away_is_refused(tmp_path, capsys, no_simulation):
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE.replace("gap_m = 0.05\n", "gap_m = 0.05\nposition_m = [0.5, 0.0, 0.0]\n")
                    + "[[listeners]]\nname = \"in\"\nposition_m = [0.5, 0.0, 0.04]\n[outputs.levels]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "listeners: " in err and "inside cavity 2" in err
    assert not (tmp_path / "out").exists()


def test_the_sound_of_several_cavities_from_a_scene_and_the_api_is_the_same(tmp_path, capsys):
    """The scene's WAV of two cavities (the second placed by hand) and the API's job write the same file."""
    from acoustiviz.app.auralize import run as run_auralize
    from acoustiviz.app.pipeline import wav_settings

    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE.replace("gap_m = 0.05\n", "gap_m = 0.05\nposition_m = [0.0, 0.3, 0.0]\n")
                    + "[outputs.wav]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 0, capsys.readouterr().err
    (wav,) = (tmp_path / "out").glob("*.wav")
    side = json.loads(wav.with_suffix(".json").read_text())
    assert side["balls"]["cavity_offsets_m"] == [[0.0, 0.0, 0.0], [0.0, 0.3, 0.0]]
    assert side["damper"]["cavities"] == 2 and side["damper"]["balls"] == 3
    assert side["balls"]["ball_ball_contacts"] > 0 and "cavity_placement" in side["balls"]
    scene = scene_from_dict(tomllib.loads(toml.read_text()))
    (tmp_path / "api").mkdir()
    job = wav_settings(scene, tmp_path / "api", damper_settings(scene))
    assert job.damper.cavities[1].position == (0.0, 0.3, 0.0)
    written = [Path(p) for p in run_auralize(job).write()]
    api = [p for p in written if p.suffix == ".wav"]
    assert len(api) == 1 and api[0].read_bytes() == wav.read_bytes()


def test_the_levels_of_several_cavities_hear_each_from_its_place(tmp_path, capsys):
    """A scene's levels: the second cavity moved from under the listener to 3 m away makes them quieter."""
    import csv

    laeq = {}
    for y in (0.3, 3.0):
        toml = tmp_path / f"scene_{y:g}.toml"
        toml.write_text(SCENE.replace("gap_m = 0.05\n", f"gap_m = 0.05\nposition_m = [0.0, {-y}, 0.0]\n")
                        + '[[listeners]]\nname = "above"\nposition_m = [0.0, -0.3, 0.15]\n[outputs.levels]\n')
        out = tmp_path / f"out_{y:g}"
        assert main(["run", str(toml), "--out", str(out)]) == 0, capsys.readouterr().err
        with open(out / "levels.csv", newline="") as f:
            (row,) = list(csv.DictReader(f))
        laeq[y] = float(row["laeq_db"])
    assert laeq[3.0] < laeq[0.3] - 1.0
