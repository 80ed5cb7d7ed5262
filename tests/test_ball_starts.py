"""Where the balls of a cavity start (``--ball-start``, ``--ball-seed``) and their material (``--ball-material``).

The expected centres of the ``spaced``, ``low`` and ``high`` starts are worked out here from the
cavity's walls and the balls' radii; the radius of a brass ball and the ball-ball stiffness (paper
eq 2) from the catalogue's values read straight from ``materials.toml``. The command line, a scene
and the Python API build equal jobs and write the same files; bad values are refused naming the
option or scene key before any work.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import acoustiviz
import acoustiviz.dynamics
from acoustiviz.app.damper import DamperCavity, DamperJob, balls_model, damper_model, run
from acoustiviz.app.pipeline import damper_settings
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.damper import settings_from_args
from acoustiviz.dynamics import BallState, DamperModel, MultiBallModel
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

CATALOGUE = tomllib.loads((Path(acoustiviz.__file__).parent / "assets" / "materials.toml").read_text())

#: Absolute tolerance in m on a ball's centre (sums of a few lengths of centimetres).
POSITION_TOL = 1e-15
#: Absolute tolerance in m on a position read back from a CSV (written with 10 significant digits).
CSV_TOL = 1e-11

FILES = {"impacts_csv": "impacts.csv", "history_csv": "damper_history.csv", "png": "damper_history.png"}


def _centres(state: BallState, model: MultiBallModel) -> np.ndarray:
    """The balls' centres in m of one cavity of equal balls: reduced positions plus the offsets from the radius."""
    q, u = state.reduced(model)
    cav = model.cavities[0]
    n, r = cav.n_balls, cav.radii[0]
    assert np.all(u[1:] == 0.0)  # at rest
    return q[1:] + (2.0 * r * np.arange(n) + r - n * r)


def _clearances(y: np.ndarray, x: float, model: MultiBallModel) -> np.ndarray:
    """The N + 1 spaces in m between the walls and the balls of centres ``y``, main mass at ``x``."""
    cav = model.cavities[0]
    r, half = cav.radii[0], 0.5 * (cav.gap + 2.0 * cav.n_balls * cav.radii[0])
    return np.diff(np.concatenate([[x - half + r], y, [x + half - r]])) - np.concatenate([[0.0], [2.0 * r] *
                                                                                          (cav.n_balls - 1), [0.0]])


@pytest.mark.parametrize("n", [1, 2, 5])
@pytest.mark.parametrize("x", [0.0, 0.013])
@pytest.mark.parametrize("start", ["spaced", "low", "high"])
def test_each_start_places_the_balls_where_it_says(start, x, n):
    model = MultiBallModel.from_damper(DamperModel(gap=0.03), n)
    r, gap = model.cavities[0].radii[0], 0.03
    half = 0.5 * gap + n * r  # the cavity's half length
    i = np.arange(n)
    lowest = x - half + r + 2.0 * r * i  # every ball packed on wall-
    expected = {"low": lowest, "high": lowest + gap, "spaced": lowest + gap * (i + 1) / (n + 1)}[start]
    y = _centres(BallState(x=x, start=start), model)
    np.testing.assert_allclose(y, expected, rtol=0, atol=POSITION_TOL)
    gaps = _clearances(y, x, model)
    assert np.all(gaps >= -POSITION_TOL)
    assert math.isclose(gaps.sum(), gap, rel_tol=1e-12)


def test_the_default_start_is_the_spaced_one_bit_for_bit():
    model = MultiBallModel.from_damper(DamperModel(), 4)
    q_default, _ = BallState(x=0.002).reduced(model)
    q_spaced, _ = BallState(x=0.002, start="spaced").reduced(model)
    assert np.array_equal(q_default, q_spaced)


def test_a_random_start_is_reproducible_with_its_seed_and_differs_between_seeds():
    model = MultiBallModel.from_damper(DamperModel(gap=0.04), 4)
    first = _centres(BallState(start="random", seed=11), model)
    assert np.array_equal(first, _centres(BallState(start="random", seed=11), model))
    other = _centres(BallState(start="random", seed=12), model)
    assert not np.allclose(first, other)
    for y in (first, other):
        gaps = _clearances(y, 0.0, model)
        assert np.all(gaps >= -POSITION_TOL) and math.isclose(gaps.sum(), 0.04, rel_tol=1e-12)
        assert np.all(gaps > 0.0)  # uniform cuts fall on no wall or ball


def test_a_random_run_is_reproducible_with_its_seed():
    job = DamperJob(damper_model(), duration=0.3, balls=3, ball_start="random", ball_seed=5)
    again = run(DamperJob(damper_model(), duration=0.3, balls=3, ball_start="random", ball_seed=5))
    first = run(job)
    assert np.array_equal(first.result.y, again.result.y)
    other = run(DamperJob(damper_model(), duration=0.3, balls=3, ball_start="random", ball_seed=6))
    assert not np.array_equal(first.result.y[:, 0], other.result.y[:, 0])


def test_brass_balls_have_the_radius_and_stiffness_of_brass_spheres_of_their_mass():
    brass = CATALOGUE["brass"]
    m = 0.0405
    radius = (3.0 * m / (4.0 * math.pi * brass["density"])) ** (1.0 / 3.0)
    e_star = brass["E"] / (2.0 * (1.0 - brass["nu"] ** 2))  # two equal spheres
    k_ball = 4.0 / 3.0 * e_star * math.sqrt(radius / 2.0)  # paper eq 2, relative radius a/2
    cav = balls_model(DamperJob(damper_model(m=m), balls=3, ball_material="brass")).cavities[0]
    assert cav.radii == pytest.approx((radius,) * 3, rel=1e-12)
    assert cav.k_ball == pytest.approx((k_ball,) * 2, rel=1e-12)
    steel = (3.0 * m / (4.0 * math.pi * CATALOGUE["steel"]["density"])) ** (1.0 / 3.0)
    assert balls_model(DamperJob(damper_model(m=m), balls=3)).cavities[0].radii[0] == pytest.approx(steel, rel=1e-12)


SCENE = ('[damper]\nduration_s = 0.5\nsolver = "event"\nballs = 3\nball_start = "random"\nball_seed = 7\n'
         'ball_material = "brass"\n[contact]\nk_hertz_n_m1_5 = 5.6e8\n[outputs.impact_table]\n'
         "[outputs.damper_history]\n")
ARGV = ("damper", "--duration", "0.5", "--solver", "event", "--balls", "3", "--ball-start", "random",
        "--ball-seed", "7", "--ball-material", "brass")


def _options(prefix="") -> list:
    return ["--impacts-csv", f"{prefix}impacts.csv", "--history-csv", f"{prefix}damper_history.csv",
            "--png", f"{prefix}damper_history.png"]


def test_the_command_line_a_scene_and_the_api_write_the_same_files(tmp_path, monkeypatch, capsys):
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main([*ARGV, *_options()]) == 0, capsys.readouterr().err
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    job = DamperJob(damper_model(), duration=0.5, balls=3, ball_start="random", ball_seed=7, ball_material="brass",
                    **FILES)
    run(job).write(api)
    for name in FILES.values():
        mine = (cli / name).read_bytes()
        assert len(mine) > 100
        assert (tmp_path / "scene" / name).read_bytes() == mine, f"the scene's {name} differs from the CLI's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"


def test_the_command_line_and_a_scene_build_equal_jobs(tmp_path):
    argv = [*ARGV, "--max-memory", "256", *_options(f"{tmp_path}/")]
    from_cli = settings_from_args(build_parser().parse_args(argv))
    from_scene = damper_settings(scene_from_dict(tomllib.loads(SCENE)), tmp_path)
    assert from_cli == from_scene
    assert (from_cli.ball_start, from_cli.ball_seed, from_cli.ball_material) == ("random", 7, "brass")


def test_the_spaced_start_writes_the_files_of_the_default(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    base = ("damper", "--duration", "0.5", "--balls", "3")
    assert main([*base, *_options("a_")]) == 0, capsys.readouterr().err
    assert main([*base, "--ball-start", "spaced", "--ball-material", "steel", *_options("b_")]) == 0
    for name in FILES.values():
        assert (tmp_path / f"a_{name}").read_bytes() == (tmp_path / f"b_{name}").read_bytes()


def test_a_cavity_of_a_scene_takes_its_own_material(tmp_path):
    scene = ('[damper]\nduration_s = 0.5\nsolver = "event"\nball_material = "glass"\n'
             '[[damper.cavities]]\nballs = 2\nmaterial = "brass"\n[[damper.cavities]]\nballs = 2\n')
    job = damper_settings(scene_from_dict(tomllib.loads(scene)), tmp_path)
    assert job == DamperJob(damper_model(), duration=0.5, ball_material="glass", max_memory_mb=job.max_memory_mb,
                            cavities=(DamperCavity(balls=2, material="brass"), DamperCavity(balls=2)))
    first, second = balls_model(job).cavities
    m = damper_model().m
    for cav, name in ((first, "brass"), (second, "glass")):
        radius = (3.0 * m / (4.0 * math.pi * CATALOGUE[name]["density"])) ** (1.0 / 3.0)
        assert cav.radii == pytest.approx((radius, radius), rel=1e-12)


@pytest.fixture
def no_simulation(monkeypatch):
    """Fail a test that simulates the damper."""
    def refuse(*args, **kwargs):
        raise AssertionError("the damper was simulated")

    monkeypatch.setattr(acoustiviz.dynamics, "simulate", refuse)
    monkeypatch.setattr(acoustiviz.dynamics, "simulate_balls", refuse)


@pytest.mark.parametrize("extra, option, words", [
    (("--balls", "2", "--ball-start", "middle"), "--ball-start", "spaced"),
    (("--balls", "2", "--ball-material", "unobtainium"), "--ball-material", "brass"),
    (("--balls", "2", "--ball-seed", "-1"), "--ball-seed", ""),
    (("--ball-start", "low"), "--ball-start", "--balls above 1"),
    (("--ball-material", "brass"), "--ball-material", "--balls above 1"),
])
def test_bad_values_are_refused_naming_the_option(extra, option, words, tmp_path, monkeypatch, capsys, no_simulation):
    monkeypatch.chdir(tmp_path)
    try:
        status = main(["damper", "--duration", "1", *extra, "--impacts-csv", "i.csv"])
    except SystemExit as stop:  # argparse refuses a choice it does not know itself
        status = stop.code
    err = capsys.readouterr().err.strip()
    assert status == 2
    assert err.startswith(f"acoustiviz damper: error: {option}") or f"argument {option}" in err
    assert words in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("text, key, words", [
    ('[damper]\nballs = 2\nball_start = "middle"\n', "damper.ball_start", "random"),
    ('[damper]\nballs = 2\nball_material = "cheese"\n', "damper.ball_material", "steel"),
    ('[[damper.cavities]]\nballs = 2\n[[damper.cavities]]\nmaterial = "cheese"\n', "damper.cavities[1].material",
     "brass"),
])
def test_a_scene_refuses_bad_values_naming_the_key(text, key, words, tmp_path, capsys, no_simulation):
    toml = tmp_path / "scene.toml"
    toml.write_text(text + "[outputs.impact_table]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert key in err and words in err
    assert not (tmp_path / "out").exists()


def test_the_api_refuses_an_unknown_start_and_material_naming_the_field(no_simulation):
    with pytest.raises(ParameterError, match="ball_start"):
        DamperJob(damper_model(), balls=2, ball_start="middle")
    with pytest.raises(ParameterError, match=r"cavities\[0\]\.material.*brass"):
        DamperJob(damper_model(), cavities=(DamperCavity(balls=2, material="cheese"),))
    with pytest.raises(ParameterError, match="start"):
        BallState(start="middle")


#: Two brass balls under a forced run, as the command line, a scene and the API give them.
FORCED_ARGV = ("forced", "--C", "5", "--force", "10", "--freq", "4", "--balls", "2", "--ball-material", "brass",
               "--starts", "1", "--no-noise", "--max-memory", "256")
FORCED_SCENE = ('[damper]\ndamping_n_s_m = 5.0\nballs = 2\nball_material = "brass"\n[excitation]\namplitude = 10.0\n'
                'frequencies_hz = "4"\nstarts = 1\n[outputs.frequency_response]\n')


def test_forced_balls_take_their_material_from_every_front_end():
    from acoustiviz.app.forced import ForcedJob, forced_settings
    from acoustiviz.cli.forced import settings_from_args as forced_from_args

    from_cli = forced_from_args(build_parser().parse_args(list(FORCED_ARGV)))
    from_scene = forced_settings(scene_from_dict(tomllib.loads(FORCED_SCENE)))
    api = ForcedJob(damper_model(C=5.0), frequencies=(4.0,), kind="force", amplitude=10.0, starts=1, noise=False,
                    balls=2, ball_material="brass", max_memory_mb=256.0)
    assert from_cli == from_scene == api
    radius = (3.0 * damper_model().m / (4.0 * math.pi * CATALOGUE["brass"]["density"])) ** (1.0 / 3.0)
    assert api.ball_model().cavities[0].radii == pytest.approx((radius, radius), rel=1e-12)


def test_forced_refuses_an_unknown_material_naming_the_option(tmp_path, monkeypatch, capsys, no_simulation):
    monkeypatch.chdir(tmp_path)
    argv = [*FORCED_ARGV[:-2], "--csv", "f.csv"]
    argv[argv.index("brass")] = "cheese"
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "--ball-material" in err and "steel" in err
    assert list(tmp_path.iterdir()) == []


def test_each_cavity_of_a_scene_takes_its_own_start(tmp_path):
    scene = ('[damper]\nduration_s = 0.05\nsolver = "event"\nball_start = "high"\n'
             '[[damper.cavities]]\nballs = 2\ngap_m = 0.03\nstart = "low"\n[[damper.cavities]]\ngap_m = 0.05\n'
             '[outputs.damper_history]\n')
    job = damper_settings(scene_from_dict(tomllib.loads(scene)), tmp_path)
    assert job.cavities == (DamperCavity(balls=2, gap=0.03, start="low"), DamperCavity(gap=0.05))
    written = run(job).write()
    history = next(p for p in written if p.suffix == ".csv").read_text().splitlines()
    header, first = history[0].split(","), [float(v) for v in history[1].split(",")]
    row = dict(zip(header, first, strict=True))
    assert row["time_s"] == 0.0 and row["x_m"] == 0.0
    r = (3.0 * damper_model().m / (4.0 * math.pi * CATALOGUE["steel"]["density"])) ** (1.0 / 3.0)
    low = -0.5 * (0.03 + 4.0 * r) + r  # the first cavity's balls packed on its wall-
    assert row["c1_y1_m"] == pytest.approx(low, abs=CSV_TOL)
    assert row["c1_y2_m"] == pytest.approx(low + 2.0 * r, abs=CSV_TOL)
    assert row["c2_y1_m"] == pytest.approx(0.5 * 0.05, abs=CSV_TOL)  # the second's on its wall+ (the job's)


def test_a_bad_cavity_start_is_refused_naming_its_key(tmp_path, capsys, no_simulation):
    toml = tmp_path / "scene.toml"
    toml.write_text('[[damper.cavities]]\nballs = 2\nstart = "middle"\n[outputs.impact_table]\n')
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "damper.cavities[0].start" in err and "random" in err
