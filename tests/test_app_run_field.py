"""The field of a damper run: its levels on a grid of listeners and its waveform, from every front end.

The same short run is evaluated three ways (``acoustiviz auralize --grid ...``, a scene's
``[outputs.run_field]`` and a :class:`~acoustiviz.app.run_field.RunFieldJob` built in Python) and the files
are compared byte for byte; the command line and the scene build equal jobs. The grid's levels are those of
its points heard as listeners by the levels job, mirror-symmetric where the geometry is, and the waveform's
energy is the unweighted level of the run; a grid beyond the memory cap is refused naming the cap.
"""

from __future__ import annotations

import csv
import dataclasses

import numpy as np
import pytest
from test_app_auralize import LISTENER, SHORT, _api_job, _argv, _scene

from acoustiviz.app.auralize import run as run_sound
from acoustiviz.app.pipeline import damper_settings, run_scene
from acoustiviz.app.run_field import RunFieldJob, run
from acoustiviz.app.scene_run_field import run_field_settings
from acoustiviz.app.settings.run_field import RUN_FIELD, scene_files
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.auralize import field_settings_from_args, settings_from_args
from acoustiviz.core.listener import Listener
from acoustiviz.errors import ParameterError
from acoustiviz.levels import LEVEL_COLUMNS
from acoustiviz.scene import scene_from_dict

#: The grid's and the waveform's files, as a scene names them.
FILES = {"grid_csv": "run_directivity.csv", "grid_png": "run_directivity.png",
         "waveform_csv": "run_waveform.csv", "waveform_png": "run_waveform.png", "snapshot_png": "run_snapshot.png",
         "snapshot_vtk": "run_snapshot.vtu"}
#: The snapshot's instant in s (a click sounding) and plane, as options and as scene keys.
SNAP = {"snapshot_time": 0.0108, "grid_extent": 0.3}
SNAP_ARGV = ["--snapshot-time", "0.0108", "--grid-extent", "0.3"]
SNAP_KEYS = {"snapshot_time_s": 0.0108, "extent_m": 0.3, "vtk": True}
#: A short arc of directions: five points from -80 to +80 degrees at 0.5 m.
ARC = {"grid": "directivity", "grid_points": 5, "grid_arc": 80.0, "grid_distance": 0.5}
#: The same, as options and as scene keys.
ARC_ARGV = ["--grid", "directivity", "--grid-points", "5", "--grid-arc", "80", "--grid-distance", "0.5"]
ARC_KEYS = {"grid": "directivity", "points": 5, "arc_deg": 80.0, "distance_m": 0.5}


def _rows(path) -> list:
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def test_every_front_end_writes_the_same_files(tmp_path, monkeypatch, capsys):
    cli, scene_out, api = tmp_path / "cli", tmp_path / "scene", tmp_path / "api"
    for folder in (cli, api):
        folder.mkdir()
    monkeypatch.chdir(cli)
    files = [x for k, v in FILES.items() for x in (f"--{k.replace('_', '-')}", v)]
    assert main(_argv(SHORT, "wav_listener1.wav", [LISTENER], [*ARC_ARGV, *SNAP_ARGV, *files])) == 0, \
        capsys.readouterr().err
    out = capsys.readouterr().out
    assert "directivity: 5 of 5 grid point(s) heard" in out and "wrote run_waveform.png" in out
    scene = scene_from_dict(_scene(SHORT, ["listener1"], [LISTENER],
                                   {"wav": {}, "run_field": {**ARC_KEYS, **SNAP_KEYS, "waveform": True}}))
    run_scene(scene, scene_out)
    job = RunFieldJob(_api_job(SHORT, ["listener1"], [LISTENER], ()), **ARC, **SNAP, **FILES)
    result = run(job)
    written = result.write(api)
    assert [p.name for p in written] == [*FILES.values(), "run_snapshot_geometry.vtu"]
    for name in (*FILES.values(), "run_snapshot_geometry.vtu"):
        mine = (cli / name).read_bytes()
        assert len(mine) > 200
        assert (scene_out / name).read_bytes() == mine, f"the scene's {name} differs from the command line's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the command line's"
    rows = _rows(cli / FILES["grid_csv"])
    assert [float(r["angle_deg"]) for r in rows] == [-80.0, -40.0, 0.0, 40.0, 80.0]
    assert all(float(r["laeq_db"]) > 40.0 for r in rows)
    assert np.nanmax(np.abs(result.snapshot)) > 0.01


def test_a_snapshot_is_symmetric_about_the_axis_and_refused_outside_the_run(tmp_path, monkeypatch, capsys):
    """One ball on a plane: the snapshot at (x, z) equals that at (-x, z); an instant after the run is refused."""
    result = run(RunFieldJob(_api_job(SHORT, ["listener1"], [LISTENER], ()), snapshot_time=0.0108,
                             grid_points=21, grid_extent=0.3, snapshot_png="s.png"))
    img = result.snapshot_grid.image(result.snapshot)
    np.testing.assert_allclose(img, img[:, ::-1], rtol=0, atol=1e-9 * np.nanmax(np.abs(img)))
    assert np.nanmax(np.abs(img)) > 0.01 and np.isnan(img).any()  # the points in the cavity are blank
    monkeypatch.chdir(tmp_path)
    argv = ["auralize", "--duration", "0.1", "--wav", "a.wav", "--snapshot-time", "0.2", "--snapshot-png", "s.png"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "--snapshot-time" in err and "outside the run" in err and "[0, 0.1] s" in err
    assert main(["auralize", "--duration", "0.1", "--wav", "a.wav", "--snapshot-png", "s.png"]) == 2
    assert "--snapshot-png" in capsys.readouterr().err and not list(tmp_path.iterdir())


def test_the_command_line_and_a_scene_build_equal_jobs(tmp_path):
    argv = _argv(SHORT, str(tmp_path / "wav_listener1.wav"), [LISTENER],
                 ["--grid", "map", "--grid-points", "7", "--grid-extent", "0.3", "--grid-section", "xy",
                  "--grid-csv", str(tmp_path / "run_map.csv"), "--grid-png", str(tmp_path / "run_map.png")])
    args = build_parser().parse_args(argv)
    from_cli = field_settings_from_args(args, settings_from_args(args))
    scene = scene_from_dict(_scene(SHORT, ["listener1"], [LISTENER],
                                   {"wav": {}, "run_field": {"grid": "map", "points": 7, "extent_m": 0.3,
                                                             "section": "xy"}}))
    from_scene = run_field_settings(scene, tmp_path, damper_settings(scene))
    assert from_cli == from_scene
    assert from_cli.names["grid_points"] == "--grid-points"
    assert from_scene.names["grid_points"] == "outputs.run_field.points"
    other = scene_from_dict(_scene(SHORT, ["listener1"], [LISTENER],
                                   {"wav": {}, "run_field": {"grid": "map", "points": 8, "extent_m": 0.3,
                                                             "section": "xy"}}))
    assert run_field_settings(other, tmp_path, damper_settings(other)) != from_cli
    without = build_parser().parse_args(_argv(SHORT, str(tmp_path / "a.wav"), [LISTENER]))
    assert field_settings_from_args(without, settings_from_args(without)) is None


def test_a_grid_equals_its_points_given_as_listeners():
    """The grid's levels are the levels job's at the same points heard as listeners, to 1e-9 dB."""
    result = run(RunFieldJob(_api_job(SHORT, ["listener1"], [LISTENER], ()), **ARC))
    names = [f"p{i}" for i in range(len(result.points))]
    listeners = _api_job(SHORT, names, [tuple(p) for p in result.points], (), levels=True)
    heard = run_sound(listeners, damper=result.sound.damper).levels.report.levels
    for c in LEVEL_COLUMNS:
        np.testing.assert_allclose(result.levels[c], getattr(heard, c), rtol=0, atol=1e-9, err_msg=c)
    assert result.sample_rate == heard.sample_rate == 96000.0


@pytest.mark.parametrize("config", ["plane", "free"])
def test_one_balls_directivity_is_symmetric_about_its_axis(config):
    """One ball's run on a plane (and in free field): the levels at +theta and -theta from the axis agree."""
    data = _scene(SHORT, ["listener1"], [LISTENER], {"run_field": {**ARC_KEYS, "points": 7, "arc_deg": 90.0}})
    data["configuration"] = {"kind": config}
    scene = scene_from_dict(data)
    result = run(run_field_settings(scene, None, damper_settings(scene)))
    assert result.heard.all() and len(result.sound.sequence) > 2
    for c in LEVEL_COLUMNS:
        v = result.levels[c]
        np.testing.assert_allclose(v, v[::-1], rtol=0, atol=1e-6, err_msg=c)
        assert np.ptp(v) > 0.5, c  # the levels do change with the angle: the check above is not vacuous


def test_two_identical_cavities_map_is_symmetric_about_their_mid_plane():
    """Two equal cavities at x = -0.1 m and +0.1 m on one main mass: the map at (x, z) equals that at (-x, z)."""
    data = _scene(SHORT, ["listener1"], [(0.0, 0.3, 0.3)],
                  {"run_field": {"grid": "map", "points": 13, "extent_m": 0.3, "section": "xz"}})
    data["damper"]["cavities"] = [{"gap_m": 0.04, "position_m": [x, 0.0, 0.0]} for x in (-0.1, 0.1)]
    scene = scene_from_dict(data)
    result = run(run_field_settings(scene, None, damper_settings(scene)))
    grid = result.grid
    assert grid.n_u == 13 and np.allclose(grid.points[:, 0] + grid.image(grid.points[:, 0])[:, ::-1].ravel(), 0.0)
    assert 0 < result.heard.sum() < len(result.points)  # the two columns of balls are not listeners
    for c in LEVEL_COLUMNS:
        img = grid.image(result.levels[c])
        np.testing.assert_allclose(img, img[:, ::-1], rtol=0, atol=1e-6, err_msg=c)
        assert np.nanmax(img) - np.nanmin(img) > 1.0, c
    # the snapshot of every collision, 0.4 ms after the first contact, too
    first = float(result.sound.sequence.times[0])
    job = result.settings
    snap = run(RunFieldJob(job.sound, grid_points=13, grid_extent=0.3, snapshot_time=first + 4e-4),
               sound=result.sound)
    img = snap.snapshot_grid.image(snap.snapshot)
    np.testing.assert_allclose(img, img[:, ::-1], rtol=0, atol=1e-9 * np.nanmax(np.abs(img)))
    assert np.nanmax(np.abs(img)) > 0.01


def test_the_waveforms_energy_is_the_runs_unweighted_level(tmp_path, monkeypatch, capsys):
    """The RMS of the waveform CSV, in dB re 20 uPa, is the LZeq the levels job writes for the same run."""
    monkeypatch.chdir(tmp_path)
    argv = _argv({**SHORT, "rate": 96000}, "a.wav", [LISTENER],
                 ["--levels-csv", "levels.csv", "--waveform-csv", "w.csv"])
    assert main(argv) == 0, capsys.readouterr().err
    data = np.loadtxt(tmp_path / "w.csv", delimiter=",", skiprows=1)
    with open(tmp_path / "w.csv", encoding="utf-8") as f:
        assert f.readline().strip() == "time_s,p_listener1_pa"
    t, p = data[:, 0], data[:, 1]
    assert np.allclose(np.diff(t), 1 / 96000)
    rms_db = 10 * np.log10(np.mean(p ** 2) / 20e-6 ** 2)
    (row,) = _rows(tmp_path / "levels.csv")
    assert rms_db == pytest.approx(float(row["lzeq_db"]), abs=1e-3)
    assert np.max(np.abs(p)) > 0.1


def test_a_grid_point_beyond_the_memory_cap_is_refused_naming_it(tmp_path, monkeypatch, capsys):
    """One point's signal at 96 kHz over the run must fit the cap (the points are evaluated in groups that fit)."""
    monkeypatch.chdir(tmp_path)
    argv = ["auralize", "--duration", "2", "--wav", "a.wav", "--grid", "map", "--grid-points", "60",
            "--grid-csv", "m.csv", "--max-memory", "5"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "--duration" in err and "--max-memory" in err and "1 point(s)" in err and len(err.strip().splitlines()) == 1
    assert not list(tmp_path.iterdir())
    data = _scene({**SHORT, "duration": 2.0}, ["listener1"], [LISTENER],
                  {"run_field": {"grid": "map", "points": 60}})
    data["grids"] = {"memory_limit_mb": 5}
    scene = scene_from_dict(data)
    with pytest.raises(ParameterError, match=r"^damper\.duration_s: .*grids\.memory_limit_mb"):
        run_field_settings(scene, None, damper_settings(scene))


def test_the_levels_do_not_depend_on_the_grouping_of_the_points():
    """A cap that takes one point at a time gives the levels of one rendering of every point, bit for bit.

    The run ends 0.5 ms after its first click ends, so the sound of the far points outlasts it: each point
    rendered alone is shorter than the whole grid's rendering until it is rendered again to that length.
    """
    sound = _api_job({**SHORT, "duration": 0.0107}, ["listener1"], [LISTENER], ())
    whole = run(RunFieldJob(sound, grid="map", grid_points=6, grid_extent=0.4))
    small = dataclasses.replace(sound, max_memory_mb=0.05)  # one point of the 10.7 ms run at 96 kHz: 0.04 MB
    one_by_one = run(RunFieldJob(small, grid="map", grid_points=6, grid_extent=0.4), sound=whole.sound)
    assert whole.heard.sum() > 10
    for c in LEVEL_COLUMNS:
        np.testing.assert_array_equal(one_by_one.levels[c], whole.levels[c], err_msg=c)


def test_grid_files_without_a_grid_are_refused(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["auralize", "--duration", "0.1", "--wav", "a.wav", "--grid-csv", "g.csv"]) == 2
    err = capsys.readouterr().err
    assert "--grid-csv" in err and "--grid" in err
    scene = scene_from_dict(_scene(SHORT, ["listener1"], [LISTENER], {"run_field": {}}))
    with pytest.raises(ParameterError, match="^outputs.run_field"):
        run_field_settings(scene, None, damper_settings(scene))


def _draw(rng) -> dict:
    """Random valid run-field settings from the records: API name -> value."""
    records = {s.name: s for s in RUN_FIELD}
    values = {"grid": str(rng.choice(["directivity", "map"])),
              "grid_section": str(rng.choice(records["grid_section"].choices)),
              "grid_points": int(rng.integers(2, 12)),
              "grid_distance": float(rng.uniform(0.2, 3.0)), "grid_arc": float(rng.uniform(1.0, 90.0)),
              "grid_extent": float(rng.uniform(0.1, 1.0))}
    if rng.integers(2):
        values["snapshot_time"] = float(rng.uniform(0.0, SHORT["duration"]))
    return values


@pytest.mark.parametrize("seed", range(6))
def test_random_settings_build_equal_jobs(seed, tmp_path):
    values = _draw(np.random.default_rng(seed))
    records = {s.name: s for s in RUN_FIELD}
    argv = [x for k, v in values.items() for x in (records[k].option, f"{v!r}" if isinstance(v, float) else str(v))]
    files = scene_files(values["grid"], False, "snapshot_time" in values, "snapshot_time" in values)
    argv += [x for k, name in files.items() for x in (records[k].option, str(tmp_path / name))]
    args = build_parser().parse_args(_argv(SHORT, str(tmp_path / "wav_listener1.wav"), [LISTENER], argv))
    from_cli = field_settings_from_args(args, settings_from_args(args))
    keys = {records[k].key: v for k, v in values.items()} | {"vtk": "snapshot_time" in values}
    scene = scene_from_dict(_scene(SHORT, ["listener1"], [LISTENER], {"wav": {}, "run_field": keys}))
    from_scene = run_field_settings(scene, tmp_path, damper_settings(scene))
    from_api = RunFieldJob(_api_job(SHORT, ["listener1"], [LISTENER], ()), **values,
                           **{k: str(tmp_path / name) for k, name in files.items()})
    assert from_cli == from_scene == from_api, values


def test_one_balls_free_field_directivity_is_the_same_at_every_azimuth():
    """Free field: the arc's levels (in the xz-plane) are those of the same arc turned 60 degrees about the axis."""
    data = _scene(SHORT, ["listener1"], [LISTENER], {"run_field": {**ARC_KEYS, "points": 7, "arc_deg": 150.0}})
    data["configuration"] = {"kind": "free"}
    scene = scene_from_dict(data)
    result = run(run_field_settings(scene, None, damper_settings(scene)))
    centre = np.asarray(result.settings.sound.cavity.geometry.centre)
    d = result.points - centre
    phi = np.radians(60.0)
    turned = centre + np.stack([d[:, 0] * np.cos(phi), d[:, 0] * np.sin(phi), d[:, 2]], axis=1)
    listeners = tuple(Listener(f"p{i}", tuple(p)) for i, p in enumerate(turned))
    job = dataclasses.replace(result.settings.sound, listeners=listeners, levels=True)
    heard = run_sound(job, damper=result.sound.damper).levels.report.levels
    for c in LEVEL_COLUMNS:
        np.testing.assert_allclose(getattr(heard, c), result.levels[c], rtol=0, atol=1e-6, err_msg=c)
        assert np.ptp(result.levels[c]) > 0.5, c


@pytest.mark.slow
def test_ctrl_c_during_the_grid_keeps_the_wav(tmp_path, interruptible):
    """Interrupted while the grid is evaluated: exit 130, the WAV already written is kept, no grid file."""
    from test_cli_interrupt import interrupt_after

    argv = ["auralize", "--duration", "20", "--wav", "a.wav", "--grid", "directivity", "--grid-points", "19",
            "--max-memory", "2048", "--grid-csv", "m.csv"]
    interrupt_after(argv, tmp_path, r"^directivity: the run's .* rendered at each grid point", interruptible())
    assert (tmp_path / "a.wav").exists() and (tmp_path / "a.json").exists()
    assert not (tmp_path / "m.csv").exists()


def test_the_arc_turns_about_the_acceleration_axis_of_a_wall_strike():
    """A wall strike accelerates along +x: the arc's 0 degree point lies on +x, at the distance asked for."""
    from acoustiviz.app.settings.run_field import grid_points

    data = _scene(SHORT, ["listener1"], [(0.5, 0.0, 0.3)], {"run_field": {**ARC_KEYS, "points": 3, "arc_deg": 90.0}})
    data["configuration"] = {"kind": "wall-floor", "strike": "wall"}
    scene = scene_from_dict(data)
    job = run_field_settings(scene, None, damper_settings(scene))
    points, angle, _ = grid_points(job)
    d = points - np.asarray(job.sound.cavity.geometry.centre)
    np.testing.assert_allclose(d, [[0.0, 0.0, -0.5], [0.5, 0.0, 0.0], [0.0, 0.0, 0.5]], atol=1e-15)
    np.testing.assert_allclose(np.degrees(angle), [-90.0, 0.0, 90.0])
    data["outputs"]["run_field"]["vtk"] = True
    with pytest.raises(ParameterError, match="^outputs.run_field.vtk: needs outputs.run_field.snapshot_time_s"):
        scene = scene_from_dict(data)
        run_field_settings(scene, None, damper_settings(scene))
