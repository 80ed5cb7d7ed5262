"""The ``acoustiviz render`` command: the interface of the issue, image sizes and error handling."""

import numpy as np
import pytest

from acoustiviz.cli import main

pytest.importorskip("pyvista")
Image = pytest.importorskip("PIL.Image")

SMALL = ["--size", "200x150"]


def _size(path):
    with Image.open(path) as im:
        return im.size


def _pixels(path):
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB")).astype(int)


def test_balloon_wall_floor(tmp_path, capsys):
    out = tmp_path / "b.png"
    assert main(["render", "balloon", "--config", "wall-floor", "--wall-distance", "0.05", *SMALL,
                 "--resolution", "8", "--png", str(out)]) == 0
    assert _size(out) == (200, 150)
    assert _pixels(out).std() > 10
    assert f"wrote {out}" in capsys.readouterr().out


def test_snapshot_plane_at_one_ms(tmp_path):
    out = tmp_path / "s.png"
    assert main(["render", "snapshot", "--config", "plane", "--time", "0.001", *SMALL, "--resolution", "41",
                 "--png", str(out)]) == 0
    assert _size(out) == (200, 150)
    img = _pixels(out)
    assert img.std() > 10 and len(np.unique(img.reshape(-1, 3), axis=0)) > 100


def test_snapshot_several_times_and_sections(tmp_path):
    out = tmp_path / "s.png"
    assert main(["render", "snapshot", "--config", "free", "--time", "0.0003", "0.0006", "--sections", "xz,xy",
                 "--extent", "0.3", "--size", "300x150", "--resolution", "31", "--png", str(out)]) == 0
    assert _size(out) == (300, 150)


def test_animation_plane_gif(tmp_path):
    out = tmp_path / "a.gif"
    assert main(["render", "animation", "--config", "plane", "--frames", "4", "--fps", "8", "--size", "160x120",
                 "--resolution", "31", "--gif", str(out)]) == 0
    with Image.open(out) as im:
        assert im.size == (160, 120) and im.n_frames == 4


def test_default_size_is_1200x900(tmp_path):
    from acoustiviz.cli import build_parser

    args = build_parser().parse_args(["render", "balloon", "--png", str(tmp_path / "x.png")])
    assert args.size == "1200x900" and args.metric == "peak" and args.distance == 0.7
    args = build_parser().parse_args(["render", "animation", "--gif", "x.gif"])
    assert args.frames == 48 and args.fps == 12.0


@pytest.mark.parametrize("size", ["1200", "12x9", "axb", "1200x900x3", "9000x900", "0x0"])
def test_bad_size_exits_2_naming_size(tmp_path, capsys, size):
    out = tmp_path / "x.png"
    assert main(["render", "balloon", "--size", size, "--png", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--size" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


@pytest.mark.parametrize(
    ("argv", "option"),
    [
        (["balloon", "--metric", "rms", "--db-range", "-3", "--png", "x.png"], "--db-range"),
        (["balloon", "--distance", "0.02", "--png", "x.png"], "--distance"),
        (["balloon", "--opacity", "0", "--png", "x.png"], "--opacity"),
        (["balloon", "--resolution", "2", "--png", "x.png"], "--resolution"),
        (["snapshot", "--time", "-0.1", "--png", "x.png"], "--time"),
        (["snapshot", "--extent", "0.01", "--png", "x.png"], "--extent"),
        (["snapshot", "--sections", "xz,ab", "--png", "x.png"], "--sections"),
        (["snapshot", "--config", "plane", "--wall-distance", "0.1", "--png", "x.png"], "--wall-distance"),
        (["animation", "--frames", "1", "--gif", "x.gif"], "--frames"),
        (["animation", "--fps", "0", "--gif", "x.gif"], "--fps"),
        (["animation", "--config", "plane"], "--gif"),
        (["animation", "--gif", "x.png"], "--gif"),
    ],
)
def test_bad_options_exit_2_naming_the_option(tmp_path, capsys, monkeypatch, argv, option):
    monkeypatch.chdir(tmp_path)
    assert main(["render", *argv]) == 2
    err = capsys.readouterr().err
    assert option in err and len(err.strip().splitlines()) == 1
    assert not list(tmp_path.iterdir())


def test_mp4_needs_a_writer(tmp_path, capsys):
    from acoustiviz.output.render import mp4_available

    out = tmp_path / "a.mp4"
    code = main(["render", "animation", "--config", "plane", "--frames", "2", "--size", "160x120",
                 "--resolution", "21", "--mp4", str(out)])
    if mp4_available():
        assert code == 0 and out.stat().st_size > 1000
    else:
        assert code == 2 and "imageio-ffmpeg" in capsys.readouterr().err


def test_render_without_a_view(capsys):
    assert main(["render"]) == 2
    assert "balloon, snapshot or animation" in capsys.readouterr().err


def test_balloon_of_a_weighted_level(tmp_path, capsys):
    """A weighted balloon (LCpeak) from the command line: the C-weighted peak of a click lies within
    the C weighting's effect of its unweighted peak SPL, point by point, and the VTK file carries it."""
    import numpy as np
    import pyvista

    from acoustiviz.cli import main

    base = ["render", "balloon", "--config", "plane", "--resolution", "4", "--size", "200x150"]
    assert main([*base, "--metric", "lcpeak", "--png", str(tmp_path / "c.png"), "--vtk", str(tmp_path / "c.vtu")]) == 0
    assert main([*base, "--metric", "peak", "--vtk", str(tmp_path / "p.vtu")]) == 0
    assert (tmp_path / "c.png").stat().st_size > 1000
    c = pyvista.read(tmp_path / "c.vtu")
    p = pyvista.read(tmp_path / "p.vtu")
    lc, peak = np.asarray(c.point_data["lcpeak_db"]), np.asarray(c.point_data["peak_spl_db"])
    np.testing.assert_allclose(peak, np.asarray(p.point_data["peak_spl_db"]))
    assert np.all(np.isfinite(lc))
    assert np.all(lc <= peak + 0.1) and np.all(lc >= peak - 2.0)
    assert not np.allclose(lc, peak)


def _count_snapshot_evaluations(monkeypatch):
    """Wrap the field evaluator wherever a loaded module holds it; return the list of its calls (points each)."""
    import sys

    import acoustiviz.field.evaluate as evaluate

    original = evaluate.snapshots
    calls = []

    def counted(pulse, times, points, *args, **kwargs):
        calls.append(np.asarray(points).shape[0])
        return original(pulse, times, points, *args, **kwargs)

    for name, module in list(sys.modules.items()):
        if name.startswith("acoustiviz") and getattr(module, "snapshots", None) is original:
            monkeypatch.setattr(module, "snapshots", counted)
    return calls


def test_snapshot_png_vtk_and_html_evaluate_the_field_once(tmp_path, monkeypatch):
    calls = _count_snapshot_evaluations(monkeypatch)
    paths = [tmp_path / "s.png", tmp_path / "s.vtu", tmp_path / "s.html"]
    assert main(["render", "snapshot", "--config", "plane", "--time", "0.0005", *SMALL, "--resolution", "21",
                 "--png", str(paths[0]), "--vtk", str(paths[1]), "--html", str(paths[2])]) == 0
    assert all(p.stat().st_size > 0 for p in paths)
    assert len(calls) == 1  # one section, one evaluation for the three files


def test_balloon_png_vtk_and_html_evaluate_the_metrics_once(tmp_path, monkeypatch):
    import sys

    import acoustiviz.field.metrics as metrics

    original = metrics.field_metrics
    calls = []

    def counted(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    for name, module in list(sys.modules.items()):
        if name.startswith("acoustiviz") and getattr(module, "field_metrics", None) is original:
            monkeypatch.setattr(module, "field_metrics", counted)
    paths = [tmp_path / "b.png", tmp_path / "b.vtu", tmp_path / "b.html"]
    assert main(["render", "balloon", "--config", "plane", *SMALL, "--resolution", "8", "--png", str(paths[0]),
                 "--vtk", str(paths[1]), "--html", str(paths[2])]) == 0
    assert all(p.stat().st_size > 0 for p in paths)
    assert len(calls) == 1


def test_balloon_vtk_in_a_room_holds_the_levels_drawn(tmp_path, half_sine_pulse):
    import pyvista as pv

    from acoustiviz.core.room_geometry import Room
    from acoustiviz.field.balloon import balloon_data
    from acoustiviz.field.directivity import room_window
    from acoustiviz.output.vtk import write_balloon_vtk

    a = 0.01905
    pulse = half_sine_pulse
    room = Room(a, (3.0, 2.5, 2.0), 0.1, (1.0, 1.0, a), duration=0.02)
    data = balloon_data(pulse, room, distance=0.5, metric="peak", n_theta=6)
    path, _ = write_balloon_vtk(data, room, tmp_path / "b.vtu", geometry_file=False)
    mesh = pv.read(path)
    pts = data.anchor + data.distance * data.directions.reshape(-1, 3)
    # the file's window is the room's (ending by its duration), and its peak SPL the balloon's level
    assert mesh.field_data["window_s"][0] == pytest.approx(room_window(room, np.vstack([pts, data.grid.points])),
                                                           rel=1e-12)
    np.testing.assert_allclose(mesh.point_data["peak_spl_db"], data.level.reshape(-1), rtol=0, atol=1e-9)


def test_animation_gif_and_vtk_evaluate_the_frames_once(tmp_path, monkeypatch):
    import acoustiviz.field.sections as sections

    original = sections.frame_fields
    calls = []

    def counted(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(sections, "frame_fields", counted)
    paths = [tmp_path / "a.gif", tmp_path / "a.vtu"]
    assert main(["render", "animation", "--config", "plane", "--frames", "3", "--fps", "8", "--size", "160x120",
                 "--resolution", "21", "--gif", str(paths[0]), "--vtk", str(paths[1])]) == 0
    assert all(p.stat().st_size > 0 for p in paths)
    assert len(calls) == 1  # one section, its frames evaluated once for both files


def test_a_shared_animation_field_is_left_as_computed(tmp_path, half_sine_pulse, plane_geometry):
    import pyvista as pv

    from acoustiviz.field.sections import animation_field
    from acoustiviz.output.render import render_animation
    from acoustiviz.output.vtk import write_animation_vtk

    field = animation_field(half_sine_pulse, plane_geometry, frames=4, n_u=21)
    before = [p.copy() for p in field.pressures]
    assert not any(p.flags.writeable for p in field.pressures)
    render_animation(field, half_sine_pulse, plane_geometry, tmp_path / "a.gif", size=(160, 120))
    write_animation_vtk(field, plane_geometry, tmp_path / "a.vtu", geometry_file=False)
    for now, then in zip(field.pressures, before, strict=True):
        np.testing.assert_array_equal(now, then)  # the GIF drew every frame without writing into the field
    data = pv.read(tmp_path / "a.vtu")
    for k in range(4):
        np.testing.assert_array_equal(data.point_data[f"pressure_pa_t{k:04d}"], before[0][k])
