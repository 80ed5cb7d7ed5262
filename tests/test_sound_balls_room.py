"""Several balls in a room: every sphere with the room's images of its own place (acoustiviz.sound.balls_room)."""

import numpy as np
import pytest

from acoustiviz.dynamics import BallState, DamperModel, MultiBallModel, simulate_balls
from acoustiviz.levels.weighted import sound_levels
from acoustiviz.sound import ClickModel, ball_clicks, render_balls
from acoustiviz.sound.balls_room import POSITION_STEP
from acoustiviz.sound.balls_sound import column_scene, render_clicks
from acoustiviz.sound.sources import cavity

M = 0.02  # kg, each ball
RADIUS = 0.0085  # m, the scene's sphere (several balls radiate with their own radius)
DIMS = "3,2.5,2"  # m
SOURCE = (1.5, 1.2)  # m, where the cavity stands on the floor
LISTENER = np.array([0.7, 0.3, 0.8])  # m from the struck ball's contact point
#: Two renderings of the same spheres, one through the room's exact images, one through free-field or plane
#: sources: only the rounding of the distances differs.
SAME = 1e-9
#: The fractional-delay trains of a room's images are accurate to about 1e-4 of each image's click.
TRAINS = 2e-3


@pytest.fixture(scope="module")
def run():
    model = MultiBallModel.from_damper(DamperModel(m=M), 2)
    return simulate_balls(model, 0.3, initial=BallState(), t_eval=np.linspace(0.0, 0.3, 3001))


def _room(**room):
    return cavity("room", RADIUS, 0.04, room={"dimensions": DIMS, "source": f"{SOURCE[0]},{SOURCE[1]},{RADIUS}",
                                              **room})


def _at(scene, listener=LISTENER):
    """``listener`` (relative to the struck ball's contact point) in the scene's frame, m."""
    return np.asarray(scene.geometry.contact_point, dtype=float) + listener


def test_a_room_of_image_order_zero_sounds_as_free_field(run):
    room, free = _room(absorption="0.3", order=0), cavity("free", RADIUS, 0.04)
    click = ClickModel(mass=M)
    a = render_balls(run, room, click, _at(room)).pressure[0]
    b = render_balls(run, free, click, _at(free)).pressure[0]
    n = min(a.size, b.size)
    assert np.max(np.abs(b)) > 0.0 and np.all(np.isfinite(a))
    np.testing.assert_allclose(a[:n], b[:n], rtol=0, atol=SAME * np.max(np.abs(b)))


def test_each_click_is_heard_as_on_a_rigid_floor_until_the_walls_answer(run):
    """A rigid floor and order 4 (129 images, summed through trains): each click equals its plane rendering until
    the first image in another surface arrives (causality), and differs after it."""
    column = run.model.cavities[0]
    room = column_scene(_room(absorption="0.3,0.3,0.3,0.3,0,0.3", order=4), column)
    plane = column_scene(cavity("plane", RADIUS, 0.04), column)
    click = ClickModel(mass=M)
    pts_room, pts_plane = _at(room), _at(plane)
    in_room, on_plane = ball_clicks(run, room, click), ball_clicks(run, plane, click)
    assert len(in_room) == len(on_plane) > 10
    shift = np.asarray(room.geometry.contact_point) - np.asarray(plane.geometry.contact_point)
    for k in np.unique(in_room.collision)[:4]:
        one_room, one_plane = in_room.take(in_room.collision == k), on_plane.take(on_plane.collision == k)
        a = render_clicks(one_room, room, click, pts_room, oversampling=16).pressure[0]
        b = render_clicks(one_plane, plane, click, pts_plane, oversampling=16).pressure[0]
        # the first arrival in a surface other than the floor, over this collision's spheres
        first_wall = np.inf
        for srcs in one_room.sources:
            real = srcs[0]
            for ax in (0, 1):
                for wall in (0.0, (3.0, 2.5)[ax]):
                    image = real.position.copy()
                    image[ax] = 2 * wall - image[ax]
                    first_wall = min(first_wall, np.linalg.norm(pts_room - image))
            image = real.position.copy()
            image[2] = 2 * 2.0 - image[2]
            first_wall = min(first_wall, np.linalg.norm(pts_room - image))
        # its arrival, less the click's radius over c and the interpolator's reach (16 samples at 48 kHz)
        t_wall = float(one_room.times[0]) + (first_wall - 0.05) / room.medium.c - 16 / 48000
        n = int(t_wall * 48000)
        a, b = (np.pad(x, (0, max(a.size, b.size, n) - x.size)) for x in (a, b))
        peak = np.max(np.abs(b))
        assert np.all(np.isfinite(a)) and peak > 0.0
        np.testing.assert_allclose(a[:n], b[:n], rtol=0, atol=TRAINS * peak)
        assert np.max(np.abs(a[n:] - b[n:])) > 10 * TRAINS * peak  # the walls answer after
    assert np.allclose(shift[:2], SOURCE)


def test_a_reverberant_room_is_louder_than_free_field(run):
    room, free = _room(absorption="0.2", duration=0.4), cavity("free", RADIUS, 0.04)
    click = ClickModel(mass=M)
    wet = render_balls(run, room, click, _at(room))
    dry = render_balls(run, free, click, _at(free))
    assert np.all(np.isfinite(wet.pressure)) and wet.describe()["balls"]["room"]["sphere_groups"] > 2
    assert wet.describe()["balls"]["room"]["position_step_m"] == POSITION_STEP
    n = max(wet.n_samples, dry.n_samples)
    pad = [np.pad(r.pressure, ((0, 0), (0, n - r.n_samples))) for r in (wet, dry)]
    from acoustiviz.core.signal import Signal

    la_wet, la_dry = (float(sound_levels(Signal(p, 48000)).laeq_db[0]) for p in pad)
    assert np.isfinite(la_wet) and la_wet > la_dry + 1.0


def test_two_balls_in_a_room_sound_the_same_from_the_command_line_a_scene_and_the_api(tmp_path, monkeypatch, capsys):
    import json

    from acoustiviz.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["auralize", "--balls", "2", "--m", "0.02", "--duration", "0.3", "--room", DIMS, "--absorption", "0.3",
                 "--listener", "2.2,1.5,0.8", "--wav", "cli.wav"]) == 0, capsys.readouterr().err
    capsys.readouterr()
    toml = tmp_path / "scene.toml"
    toml.write_text('[configuration]\nkind = "room"\nroom_m = [3.0, 2.5, 2.0]\nabsorption = [0.3]\n'
                    '[damper]\nballs = 2\nimpact_mass_kg = 0.02\nduration_s = 0.3\nsolver = "event"\n'
                    '[[listeners]]\nname = "listener1"\nposition_m = [2.2, 1.5, 0.8]\n[outputs.wav]\n')
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    (wav,) = (tmp_path / "scene").glob("*.wav")
    assert wav.read_bytes() == (tmp_path / "cli.wav").read_bytes()
    side = json.loads(wav.with_suffix(".json").read_text())
    assert side["balls"]["room"]["sphere_groups"] > 2 and side["balls"]["ball_ball_contacts"] > 0
    # the API: the same job built from the library's objects
    from acoustiviz.app.auralize import run
    from acoustiviz.app.damper import DamperJob, damper_model
    from acoustiviz.app.settings.auralize import AuralizeJob
    from acoustiviz.constants import PAPER_RADIUS
    from acoustiviz.core.listener import Listener
    from acoustiviz.dynamics import InitialState

    model = damper_model(m=M)
    room = cavity("room", PAPER_RADIUS, model.gap, room={"dimensions": DIMS, "absorption": "0.3"})
    job = AuralizeJob(model, room, ClickModel(mass=M), (Listener("listener1", (2.2, 1.5, 0.8)),), ("api.wav",), 0.3,
                      DamperJob(model, InitialState(), 0.3, "event", balls=2))
    run(job).write(tmp_path)
    assert (tmp_path / "api.wav").read_bytes() == wav.read_bytes()


def test_auralize_refuses_a_late_tail_for_several_balls_in_a_room(tmp_path, capsys):
    from acoustiviz.cli import main

    assert main(["auralize", "--balls", "2", "--m", "0.02", "--duration", "0.3", "--room", DIMS, "--absorption", "0.3",
                 "--late-tail", "--listener", "2.2,1.5,0.8", "--wav", str(tmp_path / "x.wav")]) == 2
    err = capsys.readouterr().err
    assert "--late-tail: " in err and len(err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
