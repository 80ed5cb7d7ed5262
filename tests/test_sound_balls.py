"""The sound of several balls: every collision radiating from both its bodies (acoustiviz.sound.balls_sound)."""

import json

import numpy as np
import pytest

from acoustiviz.core.images import ImageSource
from acoustiviz.dynamics import BallState, DamperModel, MultiBallModel, simulate_balls
from acoustiviz.sound import BallClicks, CavityScene, ClickModel, ImpactSequence, ball_clicks, render, render_balls
from acoustiviz.sound.balls_sound import LEFT_OUT, render_clicks

#: Relative tolerance of two renderings of the same spheres by different routes (rounding of the distances only).
SAME = 1e-9
RADIUS = 0.01  # m, every sphere's radius in the free-field pair
GAP = 0.04  # m
PAIR = dict(k_hertz=2e9, mass=0.02, main_mass=0.02, mass_model="effective")  # two equal 20 g balls
SPEED = 1.3  # m/s, their approach speed
T0 = 1e-3  # s, the moment of contact


def _run(n_balls: int, duration: float, m: float = 0.0405):
    """A multi-ball run of the Table 1 damper with ``n_balls`` balls of ``m`` kg each, motion sampled at 10 kHz."""
    model = MultiBallModel.from_damper(DamperModel(m=m), n_balls)
    return simulate_balls(model, duration, initial=BallState(), t_eval=np.linspace(0.0, duration,
                                                                                   int(duration * 1e4) + 1))


def _free_pair():
    """Two equal spheres touching at the middle of a free-field cavity, pushed apart along the axis."""
    scene = CavityScene("free", radius=RADIUS, gap=GAP)
    n, mid = scene.axis, scene.geometry.centre + 0.5 * GAP * scene.axis
    lower, upper = mid - RADIUS * n, mid + RADIUS * n
    pulse = ClickModel(**PAIR).pulse_for(SPEED)
    clicks = BallClicks(np.array([T0, T0]), np.array([SPEED, SPEED]),
                        (scene.geometry.image_sources(ImageSource(lower, -n, 0, "ball1")),
                         scene.geometry.image_sources(ImageSource(upper, n, 0, "ball2"))),
                        (pulse, pulse), np.array([0, 0]), np.array([0, 0]))
    return scene, clicks, lower, upper


def _one_sphere(scene, listener, centre, axis_sign):
    """The one-ball rendering of a sphere at ``centre`` accelerated along ``axis_sign * n``, heard at ``listener``.

    The struck-wall sphere of ``render`` sits at the geometry's centre accelerating along +n: the listener is
    moved into its frame (and mirrored along n for a sphere accelerated along -n).
    """
    n = scene.axis
    d = np.asarray(listener) - centre
    if axis_sign < 0:
        d = d - 2.0 * (d @ n) * n
    seq = ImpactSequence([T0], [-1], [SPEED])
    return render(seq, scene, ClickModel(**PAIR), scene.geometry.centre + d, sample_rate=96000).pressure[0]


def _common(*rows):
    n = min(r.size for r in rows)
    for r in rows:
        assert np.all(r[n:] == 0.0) or np.max(np.abs(r[n:])) < SAME * np.max(np.abs(r))
    return [r[:n] for r in rows]


def test_one_ball_gives_exactly_the_single_ball_rendering():
    run = _run(1, 2.0)
    imp = run.impacts
    assert len(imp) > 10
    seq = ImpactSequence(imp.time, np.where(imp.first == "wall-", -1, 1), np.abs(imp.approach_velocity))
    scene, click, listener = CavityScene("plane", gap=0.04), ClickModel(), [0.495, 0.0, 0.514]
    today = render(seq, scene, click, listener)
    mine = render_balls(run, scene, click, listener)
    assert np.array_equal(mine.pressure, today.pressure)
    assert mine.internal_rate == today.internal_rate


def test_head_on_pair_each_sphere_radiates_as_a_rigid_sphere():
    scene, clicks, lower, upper = _free_pair()
    n = scene.axis
    mid = 0.5 * (lower + upper)
    for listener in (mid + 0.3 * np.array([1.0, 0.0, 0.0]), mid + 0.3 * n):
        p_lo = render_clicks(clicks.take([0]), scene, ClickModel(**PAIR), listener, sample_rate=96000).pressure[0]
        p_hi = render_clicks(clicks.take([1]), scene, ClickModel(**PAIR), listener, sample_rate=96000).pressure[0]
        ref_lo, ref_hi = _one_sphere(scene, listener, lower, -1), _one_sphere(scene, listener, upper, +1)
        p_lo, p_hi, ref_lo, ref_hi = _common(p_lo, p_hi, ref_lo, ref_hi)
        scale = np.max(np.abs(ref_hi))
        np.testing.assert_allclose(p_lo, ref_lo, rtol=0, atol=SAME * scale)
        np.testing.assert_allclose(p_hi, ref_hi, rtol=0, atol=SAME * scale)


def test_head_on_pair_on_the_bisector_and_on_the_axis():
    """Mirror symmetry about the bisector: there the two spheres (pushed apart) sound alike and add; on the axis
    the near one pushes towards the listener and the far one away: opposite signs, the pair's dipoles cancel in
    the main (a longitudinal quadrupole: no net force)."""
    scene, clicks, lower, upper = _free_pair()
    n, mid = scene.axis, 0.5 * (lower + upper)
    click = ClickModel(**PAIR)
    bisector = mid + 0.3 * np.array([1.0, 0.0, 0.0])
    p_lo, p_hi, both = _common(*(render_clicks(c, scene, click, bisector, sample_rate=96000).pressure[0]
                                 for c in (clicks.take([0]), clicks.take([1]), clicks)))
    np.testing.assert_allclose(p_lo, p_hi, rtol=0, atol=SAME * np.max(np.abs(p_hi)))
    np.testing.assert_allclose(both, p_lo + p_hi, rtol=0, atol=SAME * np.max(np.abs(p_hi)))
    axis = mid + 0.3 * n
    p_lo, p_hi, both = _common(*(render_clicks(c, scene, click, axis, sample_rate=96000).pressure[0]
                                 for c in (clicks.take([0]), clicks.take([1]), clicks)))
    assert np.max(p_hi) > 0 > np.min(p_lo)  # first arrivals: compression ahead of the upper, rarefaction behind
    assert np.argmax(np.abs(p_hi)) < np.argmax(np.abs(p_lo))  # the near sphere is heard first
    assert p_hi[np.argmax(np.abs(p_hi))] > 0 > p_lo[np.argmax(np.abs(p_lo))]
    np.testing.assert_allclose(both, p_lo + p_hi, rtol=0, atol=SAME * np.max(np.abs(p_hi)))
    # the sum's net low-frequency content (∫p dt) cancels to the pair's 1/r² difference, far below each sphere's
    assert abs(both.sum()) < 0.5 * abs(p_hi.sum())


def test_ball_ball_contacts_are_two_touching_spheres_pushed_apart():
    run = _run(2, 2.0, m=0.02)
    scene = CavityScene("plane", gap=0.04, radius=0.0085)
    clicks = ball_clicks(run, scene, ClickModel(mass=0.02))
    pairs = np.flatnonzero(clicks.walls == 0)
    assert pairs.size >= 2 and pairs.size % 2 == 0
    r_ball = run.model.cavities[0].radii[0]
    for i in pairs[::2]:
        lo, hi = clicks.sources[i][0], clicks.sources[i + 1][0]
        assert clicks.collision[i] == clicks.collision[i + 1]
        np.testing.assert_allclose(hi.position - lo.position, 2 * r_ball * scene.axis, atol=1e-12)
        np.testing.assert_allclose(lo.axis, -scene.axis)
        np.testing.assert_allclose(hi.axis, scene.axis)
        assert clicks.pulses[i] == clicks.pulses[i + 1]  # equal balls: equal and opposite
        assert len(clicks.sources[i]) == 2  # the sphere and its image in the plane
    walls = clicks.walls[clicks.walls != 0]
    assert set(walls.tolist()) <= {-1, 1}
    assert clicks.describe()["left_out"] == list(LEFT_OUT)


def test_several_balls_radiate_each_with_its_own_radius():
    from acoustiviz.core.materials import material, sphere_radius

    m = 0.0081
    run = _run(5, 0.5, m=m)
    r_ball = sphere_radius(m, material("steel").density)  # a 8.1 g steel ball: about 6.3 mm
    assert 0.006 < r_ball < 0.0065
    scene, listener = CavityScene("plane", gap=0.04), [0.495, 0.0, 0.514]  # the scene's sphere: 19.05 mm
    clicks = ball_clicks(run, scene, ClickModel(mass=m))
    np.testing.assert_allclose(clicks.sources[int(np.flatnonzero(clicks.walls == -1)[0])][0].position,
                               [0.0, 0.0, r_ball], rtol=1e-12)  # ball 1 rests on the floor
    np.testing.assert_allclose(clicks.radii, r_ball, rtol=1e-12)
    assert clicks.describe()["sphere_radii_m"] == pytest.approx([r_ball])
    k = int(np.flatnonzero(clicks.walls == -1)[0])  # a ball on the struck wall: as one ball of that radius
    one = render_clicks(clicks.take([k]), scene, ClickModel(mass=m), listener).pressure[0]
    seq = ImpactSequence([clicks.times[k]], [-1], [clicks.velocities[k]])
    small = CavityScene("plane", gap=0.04, radius=r_ball)
    alone = render(seq, small, ClickModel(mass=m), listener, oversampling=None).pressure[0]
    a, b = _common(one, alone)
    np.testing.assert_allclose(a, b, rtol=0, atol=SAME * np.max(np.abs(b)))
    big = render(seq, scene, ClickModel(mass=m), listener).pressure[0]
    assert np.max(np.abs(big)) > 2 * np.max(np.abs(alone))  # the 19 mm sphere would be far louder


def test_a_multi_ball_run_is_the_sum_of_its_collisions():
    run = _run(3, 1.0, m=0.0135)
    scene, click, listener = CavityScene("plane", gap=0.04), ClickModel(mass=0.0135), [0.495, 0.0, 0.514]
    clicks = ball_clicks(run, scene, click)
    whole = render_clicks(clicks, scene, click, listener)
    L = int(round(whole.internal_rate / whole.sample_rate))
    total = np.zeros(whole.n_samples)
    rows = np.unique(clicks.collision)
    assert rows.size == len(run.impacts) > 20
    for k in rows:
        part = render_clicks(clicks.take(clicks.collision == k), scene, click, listener, oversampling=L).pressure[0]
        assert part.size <= total.size
        total[:part.size] += part
    np.testing.assert_allclose(whole.pressure[0], total, rtol=0, atol=1e-12 * np.max(np.abs(total)))


def test_a_five_ball_scene_writes_a_calibrated_wav(tmp_path, capsys):
    soundfile = pytest.importorskip("soundfile")
    from acoustiviz.cli import main

    toml = tmp_path / "scene.toml"
    toml.write_text("[damper]\nballs = 5\nimpact_mass_kg = 0.0081\nduration_s = 1.0\n[outputs.wav]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 0, capsys.readouterr().err
    (wav,) = (tmp_path / "out").glob("*.wav")
    data, rate = soundfile.read(wav, always_2d=True)
    side = json.loads(wav.with_suffix(".json").read_text())
    assert rate == side["sample_rate_hz"] == 48000
    assert np.all(np.isfinite(data)) and np.max(np.abs(data)) > 0.01
    pascal = data * side["scale_pa_per_full_scale"]
    assert np.max(np.abs(pascal)) == pytest.approx(side["peak_pa"][0], rel=1e-4)
    assert side["balls"]["ball_ball_contacts"] > 0 and side["balls"]["left_out"] == list(LEFT_OUT)
    assert side["damper"]["balls"] == 5


def test_auralize_balls_from_the_command_line_and_a_scene_are_equal_jobs(tmp_path):
    import tomllib

    from acoustiviz.app.pipeline import damper_settings
    from acoustiviz.app.scene_wav import wav_settings
    from acoustiviz.cli import build_parser
    from acoustiviz.cli.auralize import settings_from_args
    from acoustiviz.scene import scene_from_dict

    argv = ["auralize", "--balls", "3", "--m", "0.0135", "--duration", "1", "--wav", str(tmp_path / "wav_paper.wav")]
    from_cli = settings_from_args(build_parser().parse_args(argv))
    scene = scene_from_dict(tomllib.loads("[damper]\nballs = 3\nimpact_mass_kg = 0.0135\nduration_s = 1.0\n"
                                          "[outputs.wav]\n"))
    from_scene = wav_settings(scene, tmp_path, damper_settings(scene))
    # the two front ends' default solver and memory cap differ (as for one ball): the balls and the model agree
    for job in (from_cli.damper, from_scene.damper):
        assert (job.balls, job.k_hertz_ball, job.c1_ball) == (3, None, None)
    assert from_cli.damper.model == from_scene.damper.model
    assert from_cli.click == from_scene.click


def test_auralize_refuses_several_balls_with_given_impacts(tmp_path, capsys):
    from acoustiviz.cli import main

    (tmp_path / "i.csv").write_text("time_s,wall,approach_velocity_m_s\n0.1,-1,1.0\n")
    status = main(["auralize", "--balls", "2", "--impacts", str(tmp_path / "i.csv"), "--wav",
                   str(tmp_path / "o.wav")])
    assert status == 2
    assert "--balls" in capsys.readouterr().err
    assert not (tmp_path / "o.wav").exists()


def test_several_balls_sound_the_same_from_the_command_line_and_a_scene(tmp_path, monkeypatch, capsys):
    from acoustiviz.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["auralize", "--balls", "3", "--m", "0.0135", "--duration", "1", "--listener", "0.495,0,0.514",
                 "--wav", "cli.wav"]) == 0
    capsys.readouterr()
    toml = tmp_path / "scene.toml"
    toml.write_text('[damper]\nballs = 3\nimpact_mass_kg = 0.0135\nduration_s = 1.0\nsolver = "event"\n'
                    '[[listeners]]\nname = "listener1"\nposition_m = [0.495, 0.0, 0.514]\n'
                    "[outputs.wav]\n[outputs.levels]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    (wav,) = (tmp_path / "scene").glob("*.wav")
    assert wav.read_bytes() == (tmp_path / "cli.wav").read_bytes()
    # the API: the same job built from the library's objects
    from acoustiviz.app.auralize import run
    from acoustiviz.app.damper import DamperJob, damper_model
    from acoustiviz.app.settings.auralize import AuralizeJob
    from acoustiviz.constants import PAPER_RADIUS
    from acoustiviz.core.listener import Listener
    from acoustiviz.dynamics import InitialState
    from acoustiviz.sound.sources import cavity

    model = damper_model(m=0.0135)
    job = AuralizeJob(model, cavity("plane", PAPER_RADIUS, model.gap), ClickModel(mass=0.0135),
                      (Listener("listener1", (0.495, 0.0, 0.514)),), ("api.wav",), 1.0,
                      DamperJob(model, InitialState(), 1.0, "event", balls=3))
    run(job).write(tmp_path)
    assert (tmp_path / "api.wav").read_bytes() == wav.read_bytes()
    assert (tmp_path / "scene" / "levels.csv").read_text().count("\n") == 2  # header and the one listener


#: Inside the column of five 8.1 g balls on a plane (about z = 6 mm to 97 mm on the axis), beyond the one
#: 19.05 mm sphere's cavity (z up to 78 mm): a listener the single-ball check lets through.
IN_COLUMN = (0.0, 0.0, 0.09)


def test_a_listener_inside_the_column_of_balls_is_refused():
    from acoustiviz.errors import ParameterError
    from acoustiviz.sound import check_listeners
    from acoustiviz.sound.balls_sound import column_scene

    run = _run(5, 0.05, m=0.0081)
    cav = run.model.cavities[0]
    scene = CavityScene("plane", gap=0.04)
    check_listeners(IN_COLUMN, scene)  # the one sphere's cavity ends below it
    r = cav.radii[0]
    assert cav.span == pytest.approx(0.04 + 8 * r)  # first to last centre: the travel and 4 diameters
    with pytest.raises(ParameterError, match="^listeners.*inside the column of 5 balls"):
        render_balls(run, scene, ClickModel(mass=0.0081), IN_COLUMN)
    with pytest.raises(ParameterError, match="^--listener"):
        check_listeners(IN_COLUMN, column_scene(scene, cav), name="--listener", column=cav)
    top = r + cav.span + r  # just above the last ball's top: in the fluid
    check_listeners((0.0, 0.0, top * 1.001), column_scene(scene, cav), column=cav)


def test_auralize_and_a_scene_refuse_a_listener_inside_the_column(tmp_path, capsys):
    from acoustiviz.cli import main

    listener = ",".join(str(v) for v in IN_COLUMN)
    status = main(["auralize", "--balls", "5", "--m", "0.0081", "--duration", "0.1", "--listener", listener,
                   "--wav", str(tmp_path / "o.wav")])
    err = capsys.readouterr().err
    assert status == 2 and "--listener" in err and "column of 5 balls" in err
    assert not (tmp_path / "o.wav").exists()
    toml = tmp_path / "scene.toml"
    toml.write_text("[damper]\nballs = 5\nimpact_mass_kg = 0.0081\nduration_s = 0.1\n"
                    f"[[listeners]]\nname = \"in\"\nposition_m = {list(IN_COLUMN)}\n[outputs.wav]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "listeners" in err and "column of 5 balls" in err
    assert not list((tmp_path / "out").glob("*.wav"))
    toml.write_text(toml.read_text().replace("[outputs.wav]", "[outputs.levels]"))  # the levels alone: refused too
    assert main(["run", str(toml), "--out", str(tmp_path / "levels")]) == 2
    err = capsys.readouterr().err
    assert "column of 5 balls" in err and "simulating" not in err  # refused before the run starts
    assert not list((tmp_path / "levels").glob("*.csv"))


def test_the_summaries_count_every_collision_of_several_balls(tmp_path, capsys):
    import csv
    import re

    from acoustiviz.cli import main

    toml = tmp_path / "scene.toml"
    toml.write_text("[damper]\nballs = 3\nimpact_mass_kg = 0.0135\nduration_s = 0.5\n[outputs.wav]\n"
                    "[outputs.impact_table]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    (table,) = (tmp_path / "out").glob("*.csv")
    with table.open() as f:
        rows = list(csv.DictReader(f))
    on_wall = sum(r["first"] == "wall-" or r["second"] == "wall+" for r in rows)
    assert 0 < on_wall < len(rows)
    line = next(ln for ln in out.splitlines() if ".wav" in ln)
    assert f"impacts={len(rows)}," in line
    assert f"ball_wall={on_wall}, ball_ball={len(rows) - on_wall}," in line
    assert main(["auralize", "--balls", "3", "--m", "0.0135", "--duration", "0.5", "--wav",
                 str(tmp_path / "a.wav")]) == 0
    out = capsys.readouterr().out
    assert re.search(rf"^impacts: {len(rows)} \({on_wall} ball-wall: \d+ on wall -1, \d+ on wall \+1; "
                     rf"{len(rows) - on_wall} ball-ball\)", out, re.M)
    assert "sphere radius 7.43 mm (each ball its own" in out  # 13.5 g of steel


def _twin_run(duration: float = 0.5):
    """Two identical cavities of one ball each on the Table 1 main mass, started identically."""
    from acoustiviz.dynamics import equal_balls

    d = DamperModel()
    cav = equal_balls(1, d.m, d.gap, d.k_hertz, d.c1)
    model = MultiBallModel((cav, cav), d.M, d.K, d.C)
    return simulate_balls(model, duration, initial=BallState(), t_eval=np.linspace(0.0, duration,
                                                                                   int(duration * 1e4) + 1))


def _of_cavity(run, clicks, ic: int):
    """The clicks of cavity ``ic`` (1-based) alone."""
    mine = np.array([str(run.impacts.first[k]).startswith(f"c{ic}:") for k in clicks.collision])
    return clicks.take(mine)


def test_two_identical_cavities_heard_from_equidistant_listener_are_twice_one():
    run = _twin_run()
    t1 = run.impacts.time[np.char.startswith(run.impacts.first.astype(str), "c1:")]
    t2 = run.impacts.time[np.char.startswith(run.impacts.first.astype(str), "c2:")]
    np.testing.assert_allclose(t1, t2, rtol=0, atol=1e-12)  # the clicks coincide in time
    scene, click = CavityScene("plane", gap=DamperModel().gap), ClickModel()
    clicks = ball_clicks(run, scene, click)
    (c1, c2) = (np.asarray(s[0].position) for s in (_of_cavity(run, clicks, 1).sources[0],
                                                    _of_cavity(run, clicks, 2).sources[0]))
    # two balls in all: each radiates with its own radius, on the floor; by default a cavity's length (gap + 2r)
    # plus a diameter apart, along the floor
    r = run.model.cavities[0].radii[0]
    assert r < scene.radius and set(clicks.radii) == {r}
    np.testing.assert_allclose(c2 - c1, [DamperModel().gap + 4 * r, 0.0, 0.0], rtol=1e-12)
    assert c1[2] == pytest.approx(r, rel=1e-12) and c2[2] == pytest.approx(r, rel=1e-12)
    listener = 0.5 * (c1 + c2) + np.array([0.0, 0.6, 0.5])  # equidistant from both
    both = render_clicks(clicks, scene, click, listener).pressure[0]
    one = render_clicks(_of_cavity(run, clicks, 1), scene, click, listener).pressure[0]
    n = min(both.size, one.size)
    np.testing.assert_allclose(both[:n], 2.0 * one[:n], rtol=0, atol=1e-9 * np.max(np.abs(both)))
    gain = 20 * np.log10(np.max(np.abs(both)) / np.max(np.abs(one)))
    assert gain == pytest.approx(20 * np.log10(2.0), abs=1e-6)  # +6.02 dB
    side = render_balls(run, scene, click, listener).describe()["balls"]
    assert np.allclose(side["cavity_offsets_m"][1], c2 - c1) and "cavity_placement" in side


def test_a_listener_on_the_line_of_two_cavities_hears_two_arrivals():
    run = _twin_run(0.05)
    scene, click, lift = CavityScene("free", gap=DamperModel().gap), ClickModel(), 0.5
    clicks = ball_clicks(run, scene, click, positions=[None, [0.0, 0.0, lift]])  # the second above the first
    listener = np.asarray(scene.geometry.centre) + np.array([0.0, 0.0, 1.5])  # on their common axis
    fs = 96000
    onsets = []
    for ic in (1, 2):
        p = render_clicks(_of_cavity(run, clicks, ic), scene, click, listener, sample_rate=fs).pressure[0]
        onsets.append(np.flatnonzero(np.abs(p) > 1e-3 * np.max(np.abs(p)))[0])
    assert (onsets[0] - onsets[1]) / fs == pytest.approx(lift / scene.medium.c, abs=1.5 / fs)
    whole = render_balls(run, scene, click, listener, positions=[None, [0.0, 0.0, lift]], sample_rate=fs)
    assert np.all(np.isfinite(whole.pressure))


@pytest.mark.parametrize("positions, match", [([None, [0.0, 0.0, 0.0]], r"^positions\[1\]: cavity 2 overlaps"),
                                              ([None, [0.0, 0.0, -0.1]], r"^positions\[1\]: cavity 2's balls would "
                                                                          "leave the fluid"),
                                              ([None, [0.1, "a", 0.0]], r"^positions\[1\]: expected three"),
                                              ([None], r"^positions\[1\]: one position per cavity")])
def test_cavities_out_of_the_fluid_or_overlapping_are_refused(positions, match):
    from acoustiviz.errors import ParameterError
    from acoustiviz.sound.balls_sound import cavity_places

    model = _twin_run(0.01).model
    with pytest.raises(ParameterError, match=match):
        cavity_places(model, CavityScene("plane", gap=DamperModel().gap), positions)
