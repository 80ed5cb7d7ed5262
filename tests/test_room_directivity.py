"""Directivity, balloon and levels in a shoebox room, against independent references.

References: the free field and today's reflecting plane and wall-floor corner (a room whose other
walls lie beyond every arrival in the window), and the direct sum of the closed-form pressure of
every image sphere (:func:`acoustiviz.core.radiation.sphere_pressure`, one free sphere at a time,
times its reflection weight), refined to the continuous peak with a bounded Brent search.
"""

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from acoustiviz.cli import main
from acoustiviz.core.geometry import FreeField, ReflectingPlane, WallFloorCorner
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import sphere_pressure
from acoustiviz.core.reach import check_view_radius, circle_limit, view_limit
from acoustiviz.core.room_geometry import Room
from acoustiviz.errors import ParameterError
from acoustiviz.field import directivity

A = 0.01905  # the paper's sphere, m


def test_room_larger_than_any_arrival_equals_the_free_field(paper_pulse):
    """A sphere in the middle of a 1 km room: no wall's image arrives within 5 ms."""
    pulse = paper_pulse()
    room = Room(A, (1000.0, 1000.0, 1000.0), 0.0, (500.0, 500.0, 500.0), duration=0.005)
    assert room.polar_limit_deg == 180.0 and room.view_region().kind == "sphere"
    ang = np.radians(np.arange(0.0, 181.0, 30.0))
    d = directivity(pulse, room, 0.7, ang)
    assert d.metrics.window == pytest.approx(0.005 - (0.7 - A) / AIR.c, rel=1e-12)
    f = directivity(pulse, FreeField(A), 0.7, ang, window=d.metrics.window)
    peak = float(np.max(f.peak))
    np.testing.assert_allclose(d.peak, f.peak, rtol=0, atol=1e-12 * peak)
    np.testing.assert_allclose(d.rms, f.rms, rtol=0, atol=1e-12 * peak)
    # a weighted level from the band-limited signal: the same signal, so the same level
    from acoustiviz.app.views import directivity_metric

    lc_room = directivity_metric(d, "lcpeak", pulse, room, AIR)
    lc_free = directivity_metric(f, "lcpeak", pulse, FreeField(A), AIR)
    lobes = np.abs(np.degrees(ang) - 90.0) > 1.0  # the dipole's null at 90 deg is round-off in both
    np.testing.assert_allclose(lc_room[lobes], lc_free[lobes], rtol=0, atol=1e-9)  # dB
    assert np.all(np.isfinite(lc_room[lobes]))


@pytest.mark.parametrize("wall", [None, 0.05])
def test_large_room_with_the_sphere_on_its_floor_equals_the_plane_and_the_corner(wall, paper_pulse):
    """On the floor (and 5 cm from wall x0) of a 20 m room, within 4 ms: the plane's (corner's) images only."""
    pulse = paper_pulse()
    x = 10.0 if wall is None else wall
    room = Room(A, (20.0, 20.0, 20.0), 0.0, (x, 10.0, A), duration=0.004)
    assert room.polar_limit_deg == 90.0 and room.view_region().kind == "half"
    ang = np.radians(np.arange(0.0, 91.0, 15.0))
    d = directivity(pulse, room, 0.5, ang)
    ref = ReflectingPlane(A) if wall is None else WallFloorCorner(A, wall)
    c = directivity(pulse, ref, 0.5, ang, window=d.metrics.window)
    peak = float(np.max(c.peak))
    np.testing.assert_allclose(d.peak, c.peak, rtol=0, atol=1e-12 * peak)
    np.testing.assert_allclose(d.rms, c.rms, rtol=0, atol=1e-12 * peak)


def _image_sum(pulse, room, point, t):
    """Pressure in Pa at ``point`` and times ``t``: every image sphere's free field times its weight."""
    im = room.images()
    p = np.zeros(np.size(t))
    for pos, axis, w in zip(im.positions, im.axes, im.weights, strict=True):
        p += w * sphere_pressure(pulse, np.atleast_1d(t), point[None, :], radius=A, centre=pos, axis=axis)[0]
    return p


@pytest.mark.slow
def test_rigid_room_directivity_near_the_source_is_the_sum_of_its_image_spheres(paper_pulse):
    pulse = paper_pulse()
    room = Room(A, (1.2, 1.0, 0.8), 0.0, (0.4, 0.45, A), duration=0.004)
    ang = np.radians([0.0, 30.0, 60.0, 90.0])
    d = directivity(pulse, room, 0.15, ang)
    fm = d.metrics
    m = int(round(fm.window / fm.sample_interval))
    for k, point in enumerate(d.points):
        t = fm.window_start[k] + fm.sample_interval * np.arange(m)
        p = _image_sum(pulse, room, point, t)
        scale = float(np.max(np.abs(p)))
        # the RMS over the same samples, and the continuous peak refined from the largest sample
        assert d.rms[k] == pytest.approx(math.sqrt(np.sum(p * p) / m), rel=1e-11)
        i = int(np.argmax(np.abs(p)))
        sign = math.copysign(1.0, p[i])
        res = minimize_scalar(lambda s, sg=sign, x=point: -sg * _image_sum(pulse, room, x, s)[0],
                              bounds=(t[max(i - 1, 0)], t[min(i + 1, m - 1)]), method="bounded",
                              options={"xatol": 1e-9 * fm.sample_interval})
        assert d.peak[k] == pytest.approx(max(scale, -res.fun), abs=1e-10 * scale)
    # the walls' images arrive in the window: the plane's images alone give another RMS, by far more
    # than the tolerance above (the direct click dominates this close to the sphere)
    plane = directivity(pulse, ReflectingPlane(A), 0.15, ang, window=fm.window)
    assert np.max(np.abs(d.rms / plane.rms - 1.0)) > 5e-4


def test_a_circle_or_balloon_that_leaves_the_room_is_refused_with_its_range(paper_pulse):
    pulse = paper_pulse()
    room = Room(A, (3.0, 2.5, 2.0), 0.3, (1.0, 1.0, A), duration=0.01)
    assert circle_limit(room) == pytest.approx(2.0 - A, rel=1e-12)  # the ceiling, straight up
    assert view_limit(room) == pytest.approx(1.0, rel=1e-12)  # walls x0 and y0 from the contact point
    with pytest.raises(ParameterError, match=r"distance: must lie in \(0.01905, 1.98095\] m .*got 2.5 m"):
        directivity(pulse, room, 2.5, [0.0])
    with pytest.raises(ParameterError, match=r"distance: the sound reaches the circle at .* after the room's window"):
        directivity(pulse, Room(A, (3.0, 2.5, 2.0), 0.3, (1.0, 1.0, A), duration=0.001), 1.5, [0.0])
    with pytest.raises(ParameterError, match=r"distance: must lie in \(0.040005, 1\] m for the measuring sphere"):
        check_view_radius(room, 1.2, 2.1 * A)
    # a sphere away from the struck surface: the whole circle and sphere, bounded by the nearest wall
    mid = Room(A, (3.0, 2.5, 2.0), 0.3, (1.0, 1.0, 0.8), duration=0.01)
    assert mid.polar_limit_deg == 180.0 and circle_limit(mid) == pytest.approx(0.8, rel=1e-12)
    assert view_limit(mid) == pytest.approx(0.8, rel=1e-12)


def test_radiated_energy_is_refused_in_a_room_saying_why():
    from acoustiviz.field.grids import spherical_grid_for

    room = Room(A, (3.0, 2.5, 2.0), 0.3, (1.0, 1.0, A), duration=0.01)
    assert room.enclosed and not ReflectingPlane(A).enclosed
    with pytest.raises(ParameterError, match="not defined in a room: its walls close the fluid"):
        spherical_grid_for(room, 0.5)


ROOM = ["--radius", "0.01905", "--velocity", "1.4", "--k-hertz", "5.6e8", "--density", "7800",
        "--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905", "--duration", "0.005"]


@pytest.mark.slow
def test_command_and_scene_write_the_same_directivity_bytes(tmp_path):
    from acoustiviz.app.pipeline import run_scene
    from acoustiviz.scene.load import scene_from_text

    assert main(["directivity", *ROOM, "--distance", "0.5", "--step", "30", "--csv", str(tmp_path / "cli.csv")]) == 0
    scene = scene_from_text("""
[sphere]
radius_m = 0.01905
density_kg_m3 = 7800.0
[impact]
velocity_m_s = 1.4
[contact]
k_hertz_n_m1_5 = 5.6e8
[geometry]
kind = "room"
room_m = [3.0, 2.5, 2.0]
absorption = 0.3
source_m = [1.0, 1.0, 0.01905]
window_s = 0.005
[[listeners]]
name = "up"
position_m = [1.0, 1.0, 0.51905]
[outputs.directivity]
step_deg = 30.0
""", "t.toml")
    run_scene(scene, tmp_path / "scene")
    cli = (tmp_path / "cli.csv").read_bytes()
    assert cli == (tmp_path / "scene" / "directivity.csv").read_bytes()
    assert cli.startswith(b"angle_deg,peak_pa,rms_pa,spl_db\n0,") and cli.count(b"\n") == 5  # 0 to 90 degrees


@pytest.mark.parametrize("extra, option, reason", [
    (["--distance", "2.5"], "--distance", "must lie in (0.01905, 1.98095] m"),
    (["--distance", "1.9"], "--distance", "after the room's window of 0.005 s"),
])
def test_command_refuses_a_circle_that_does_not_fit(extra, option, reason, tmp_path, capsys):
    assert main(["directivity", *ROOM, *extra, "--csv", str(tmp_path / "d.csv")]) == 2
    err = capsys.readouterr().err
    assert f"{option}: " in err and reason in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "d.csv").exists()


def test_room_options_need_the_room_and_the_room_needs_a_window(capsys):
    assert main(["directivity", "--duration", "0.01"]) == 2
    assert "--duration: only applies with --room" in capsys.readouterr().err
    assert main(["directivity", "--room", "3,2.5,2"]) == 2
    assert "--duration: required with --room" in capsys.readouterr().err
    assert main(["render", "balloon", *ROOM, "--distance", "1.2", "--png", "b.png"]) == 2
    assert "--distance: must lie in (0.040005, 1] m" in capsys.readouterr().err


def test_scene_refuses_what_does_not_fit_at_load_time():
    from acoustiviz.errors import SceneError
    from acoustiviz.scene.load import scene_from_text

    base = """
[geometry]
kind = "room"
room_m = [3.0, 2.5, 2.0]
absorption = 0.3
source_m = [1.0, 1.0, 0.01905]
window_s = 0.01
[[listeners]]
name = "l"
position_m = [{x}, 1.0, 1.0]
"""
    with pytest.raises(SceneError, match=r"listeners\[0\].position_m: the directivity's circle .* must lie in"):
        scene_from_text(base.format(x=2.9) + "[outputs.directivity]\n", "t.toml")
    # the balloon's sphere is its job's check, made before the run's first output
    from acoustiviz.app.render_job import balloon_settings

    balloon = scene_from_text(base.format(x=1.5) + "[grids.sphere]\ndistance_m = 1.5\n[outputs.balloon]\n", "t.toml")
    with pytest.raises(ParameterError, match=r"grids.sphere.distance_m: must lie in \(0.040005, 1\] m"):
        balloon_settings(balloon)
    # a sweep takes the scene's room: its designs are built in it
    from acoustiviz.app.sweep import scene_sweep_spec

    spec = scene_sweep_spec(scene_from_text(base.format(x=1.5) + "[outputs.sweep]\n", "t.toml"))
    assert spec.config == ("room",) and dict(spec.settings.room)["dimensions"] == (3.0, 2.5, 2.0)


@pytest.mark.slow
def test_forced_noise_in_a_room_is_the_same_from_the_command_and_the_scene(tmp_path):
    import csv

    from acoustiviz.app.pipeline import run_scene
    from acoustiviz.scene.load import scene_from_text

    room = ["--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905", "--duration", "0.05"]
    assert main(["forced", "--force", "5", "--freq", "5:5:1", "--noise-seconds", "0.2", *room,
                 "--listener", "1.5,1,0.5", "--csv", str(tmp_path / "cli.csv")]) in (0, 1)
    scene = scene_from_text("""
[geometry]
kind = "room"
room_m = [3.0, 2.5, 2.0]
absorption = 0.3
source_m = [1.0, 1.0, 0.01905]
window_s = 0.05
[excitation]
kind = "force"
amplitude = 5.0
frequencies_hz = "5:5:1"
[[listeners]]
name = "l"
position_m = [1.5, 1.0, 0.5]
[outputs.operating_noise]
seconds = 0.2
""", "t.toml")
    run_scene(scene, tmp_path / "scene")
    with open(tmp_path / "cli.csv", newline="") as fh:
        cli = next(csv.DictReader(fh))
    with open(tmp_path / "scene" / "operating_noise.csv", newline="") as fh:
        sc = next(csv.DictReader(fh))
    for col in ("laeq_db", "lcpeak_db", "lafmax_db"):
        assert float(cli[col]) == pytest.approx(float(sc[col]), abs=1e-9), col


def test_forced_in_a_room_needs_its_listener(capsys):
    assert main(["forced", "--force", "5", "--freq", "5:5:1", "--room", "3,2.5,2", "--duration", "0.05"]) == 2
    assert "--listener: required with --room" in capsys.readouterr().err
    assert main(["forced", "--force", "5", "--freq", "5:5:1", "--duration", "0.05"]) == 2
    assert "--duration: only applies with --room" in capsys.readouterr().err


def test_sweep_in_a_room_beyond_every_arrival_equals_the_plane_and_round_trips():
    from acoustiviz.app.sweep import sweep_spec
    from acoustiviz.sweep.evaluate import evaluate_design
    from acoustiviz.sweep.spec import SweepSpec

    room = {"dimensions": (1000.0, 1000.0, 1000.0), "source": (500.0, 500.0, A), "duration": 0.005}
    common = dict(gap=0.04, m=0.0405, duration=2.0, distance=0.7, angle_deg=45.0)
    in_room = sweep_spec(config="room", room=room, **common)
    plane = sweep_spec(config="plane", **common)
    (d_room,), (d_plane,) = in_room.designs(), plane.designs()
    assert d_room.geometry(in_room.settings).dimensions == (1000.0, 1000.0, 1000.0)
    r, p = evaluate_design(d_room, in_room.settings), evaluate_design(d_plane, plane.settings)
    assert r.n_impacts == p.n_impacts > 0 and r.inclination_two_maxima == p.inclination_two_maxima
    assert r.max_spl_db == pytest.approx(p.max_spl_db, abs=1e-9)  # dB: the floor's image alone arrives
    assert SweepSpec.from_dict(in_room.to_dict()) == in_room
    assert "room" not in plane.to_dict()["settings"]  # sweeps without a room are stored as before
    with pytest.raises(ParameterError, match="config: must be one of 'free', 'plane', 'wall-floor', got 'room'"):
        sweep_spec(config="room", **common)  # a room without its settings
    with pytest.raises(ParameterError, match=r"angle: must be <= 1.5708 rad \(90 deg\) with the room"):
        sweep_spec(config="room", room=room, **{**common, "angle_deg": 120.0})


def test_sweep_command_in_a_room(tmp_path, capsys):
    import csv

    room = ["--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905"]
    assert main(["sweep", "--room", "3,2.5,2", "--out", str(tmp_path / "y")]) == 2
    assert "--room-window: required: surface x0 is rigid" in capsys.readouterr().err
    assert main(["sweep", "--room-window", "0.01", "--out", str(tmp_path / "z")]) == 2
    assert "--room-window: only applies with --room" in capsys.readouterr().err
    out = tmp_path / "s"
    assert main(["sweep", *room, "--room-window", "0.01", "--duration", "1", "--distance", "0.5", "--angle", "30",
                 "--out", str(out), "--quiet", "--workers", "1"]) == 0
    with open(out / "sweep.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 1 and rows[0]["config"] == "room" and float(rows[0]["max_spl_db"]) > 0


def test_map_command_in_a_room_lies_on_the_plane_through_the_sphere_inside_the_walls(tmp_path):
    import csv

    out = tmp_path / "m.csv"
    assert main(["map", *ROOM, "--extent", "5", "--resolution", "16", "--csv", str(out)]) == 0
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    x, y, z = (np.array([float(r[k]) for r in rows]) for k in ("x_m", "y_m", "z_m"))
    assert np.all(y == 1.0)  # the vertical plane through the sphere's centre
    assert x.min() == 0.0 and x.max() == 3.0 and z.min() == 0.0 and z.max() == 2.0  # cut at the walls and ceiling


@pytest.mark.parametrize("metric", ["peak", "sel"])
def test_balloon_in_a_room_beyond_every_arrival_equals_the_plane(metric, paper_pulse):
    from acoustiviz.field.balloon import balloon_data

    pulse = paper_pulse()
    room = Room(A, (1000.0, 1000.0, 1000.0), 0.0, (500.0, 500.0, A), duration=0.004)
    b_room = balloon_data(pulse, room, distance=0.5, metric=metric, n_theta=6)
    assert b_room.grid.region == "half"
    plane = ReflectingPlane(A)
    b_plane = balloon_data(pulse, plane, distance=0.5, metric=metric, n_theta=6)
    # the same directions about the contact point
    np.testing.assert_allclose(b_room.directions, b_plane.directions, rtol=0, atol=1e-15)
    if metric == "peak":  # the peak lies in both windows: equal to round-off
        np.testing.assert_allclose(b_room.level, b_plane.level, rtol=0, atol=1e-9)
    else:  # both windows hold the whole click of both spheres: the sampled exposures agree
        np.testing.assert_allclose(b_room.level, b_plane.level, rtol=0, atol=1e-6)
