"""Off-screen renders: real pixels of the requested size, colour bars, geometry, animations, no leaks."""

import numpy as np
import pytest

from acoustiviz.core.geometry import geometry
from acoustiviz.errors import ParameterError
from acoustiviz.field import snapshots

pv = pytest.importorskip("pyvista")
render = pytest.importorskip("acoustiviz.output.render")
Image = pytest.importorskip("PIL.Image")

A = 0.01905
SIZE = (200, 150)


@pytest.fixture(scope="module")
def pulse(half_sine_pulse):
    return half_sine_pulse


@pytest.fixture(scope="module")
def plane(plane_geometry):
    return plane_geometry


@pytest.fixture(scope="module")
def corner(wall_floor_geometry):
    return wall_floor_geometry


def _img(path):
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB")).astype(int)


def _assert_real_picture(img, size=SIZE):
    assert img.shape == (size[1], size[0], 3)
    assert img.std() > 10.0
    colours = np.unique(img.reshape(-1, 3), axis=0)
    assert len(colours) > 100


def _balloon(pulse, conf, path, **kw):
    kw = {"size": SIZE, "n_theta": 8, **kw}
    return render.render_balloon(pulse, conf, path, **kw)


def _snapshot(pulse, conf, t, path, **kw):
    kw = {"size": SIZE, "n_u": 41, **kw}
    return render.render_snapshot(pulse, conf, t, path, **kw)


# --------------------------------------------------------------------------- balloon
def test_balloon_data_closes_the_region_and_peaks_on_the_axis(pulse, plane, corner):
    d = render.balloon_data(pulse, plane, n_theta=8)
    nt, nph, _ = d.directions.shape
    assert (nt, nph) == (8 + 2, 16 + 1)
    np.testing.assert_allclose(np.linalg.norm(d.directions, axis=-1), 1.0, atol=1e-12)
    np.testing.assert_allclose(d.directions[-1] @ [0, 0, 1], 1.0)  # the pole
    np.testing.assert_allclose(d.directions[0] @ [0, 0, 1], 0.0, atol=1e-12)  # the rim on the floor
    assert np.all(np.isfinite(d.level))
    assert d.level[-1].mean() == pytest.approx(d.max_level, abs=0.5)  # loudest along the normal
    assert d.level[-1].mean() - d.level[0].mean() > 15.0  # quiet at grazing
    assert d.mean_level < d.max_level
    q = render.balloon_data(pulse, corner, n_theta=6)
    assert np.all(q.directions[..., 0] >= -1e-12) and np.all(q.directions[..., 2] >= -1e-12)
    assert q.grid.region == "quarter" and q.label == "peak SPL (dB re 20 µPa)"


def test_balloon_free_field_is_a_symmetric_dipole(pulse):
    d = render.balloon_data(pulse, geometry("free", A), n_theta=8, distance=1.0)
    lev = d.level.mean(axis=1)  # rows: cos θ from -1 to 1
    np.testing.assert_allclose(lev, lev[::-1], atol=0.3)
    assert lev[0] - lev[len(lev) // 2] > 10.0


def test_balloon_png_has_the_size_and_real_content(pulse, plane, corner, tmp_path):
    out = _balloon(pulse, corner, tmp_path / "corner.png")
    assert out == tmp_path / "corner.png"
    _assert_real_picture(_img(out))
    assert [p.name for p in tmp_path.iterdir()] == ["corner.png"]  # no temporary left behind


@pytest.mark.slow
def test_balloons_differ_between_configurations(pulse, plane, corner, tmp_path):
    a = _img(_balloon(pulse, plane, tmp_path / "plane.png"))
    b = _img(_balloon(pulse, corner, tmp_path / "corner.png"))
    c = _img(_balloon(pulse, plane, tmp_path / "rms.png", metric="rms"))
    assert np.abs(a - b).mean() > 5.0
    assert np.abs(a - c).max() > 30  # another metric, another colour bar label and colours


def test_balloon_colour_bar_is_drawn_at_the_right(pulse, plane, tmp_path):
    with_bar = _img(_balloon(pulse, plane, tmp_path / "bar.png", size=(400, 300)))
    without = _img(_balloon(pulse, plane, tmp_path / "nobar.png", size=(400, 300), show_scalar_bar=False))
    changed = np.abs(with_bar - without).sum(axis=2) > 30
    cols = np.nonzero(changed.any(axis=0))[0]
    assert changed.sum() > 500
    assert cols.min() > 0.7 * 400  # only the right-hand strip changes
    # the bar is a gradient: many distinct colours along one column of it
    assert max(len(np.unique(with_bar[:, c], axis=0)) for c in cols) > 40


def test_two_balloons_side_by_side(pulse, plane, corner, tmp_path):
    img = _img(_balloon(pulse, [plane, corner], tmp_path / "pair.png", size=(400, 150)))
    _assert_real_picture(img, (400, 150))
    left, right = img[:, :200], img[:, 200:]
    assert left.std() > 10 and right.std() > 10


# --------------------------------------------------------------------------- snapshots
def test_snapshot_has_the_size_and_changes_with_time(pulse, plane, tmp_path):
    early = _img(_snapshot(pulse, plane, 0.0004, tmp_path / "early.png", extent=0.3))
    late = _img(_snapshot(pulse, plane, 0.0008, tmp_path / "late.png", extent=0.3))
    _assert_real_picture(early)
    _assert_real_picture(late)
    assert np.abs(early - late).mean() > 2.0


def test_snapshot_uses_a_diverging_map_centred_on_zero(pulse, plane, tmp_path):
    # before the sound arrives the plane is at p = 0 (centre of RdBu_r, near white), then red and blue
    img = _img(_snapshot(pulse, plane, 0.0006, tmp_path / "s.png", extent=0.3, size=(300, 225)))
    red = (img[..., 0] > img[..., 2] + 60).sum()
    blue = (img[..., 2] > img[..., 0] + 60).sum()
    assert red > 100 and blue > 100


def test_snapshot_series_and_planes(pulse, corner, tmp_path):
    img = _img(_snapshot(pulse, corner, [0.0003, 0.0006], tmp_path / "series.png", size=(300, 150),
                         sections=("xz", "xy")))
    _assert_real_picture(img, (300, 150))
    grids = render.section_planes(corner, 0.2, sections=("xz", "yz", "xy"), n_u=11)
    for g in grids:
        assert np.all(corner.in_fluid(g.points) | (np.linalg.norm(g.points - corner.centre, axis=1) < A))
    assert min(g.points[:, 0].min() for g in grids) == pytest.approx(-0.05)  # clipped at the wall


def test_frames_evaluate_only_inside_the_arrival_windows(pulse, corner):
    grid = render.section_planes(corner, 0.25, n_u=31)[0]
    times = np.array([0.0002, 0.0005, 0.0009])
    got = render.frame_fields(pulse, corner, times, grid.points)
    ref = snapshots(pulse, times, grid.points, corner)
    ok = np.isfinite(ref)
    np.testing.assert_array_equal(np.isfinite(got), ok)
    np.testing.assert_allclose(got[ok], ref[ok], rtol=0, atol=1e-9 * np.abs(ref[ok]).max())
    assert (got[0][ok[0]] == 0).mean() > 0.5  # most points are still silent early on


# --------------------------------------------------------------------------- animation
def test_gif_animation_frames(pulse, corner, tmp_path):
    out = render.render_animation(pulse, corner, tmp_path / "a.gif", frames=5, size=(160, 120), n_u=31)
    with Image.open(out) as im:
        assert im.size == (160, 120)
        assert im.n_frames == 5
        frames = []
        for k in range(im.n_frames):
            im.seek(k)
            frames.append(np.asarray(im.convert("RGB")).astype(int))
    assert np.abs(frames[0] - frames[2]).mean() > 1.0


def test_mp4_is_optional(pulse, plane, tmp_path):
    if render.mp4_available():
        out = render.render_animation(pulse, plane, tmp_path / "a.mp4", frames=3, size=(160, 120), n_u=21)
        assert out.stat().st_size > 1000
    else:
        with pytest.raises(ParameterError, match="imageio-ffmpeg"):
            render.render_animation(pulse, plane, tmp_path / "a.mp4", frames=3, size=(160, 120))
    assert not list(tmp_path.glob(".*"))


# --------------------------------------------------------------------------- errors and resources
@pytest.mark.parametrize(
    ("kwargs", "name"),
    [({"size": (10, 10)}, "size"), ({"size": (200.5, 100)}, "size"), ({"metric": "loud"}, "metric"),
     ({"db_range": 0}, "db_range"), ({"distance": 0.01}, "distance"), ({"opacity": 2}, "opacity")],
)
def test_bad_balloon_input_names_the_parameter(pulse, plane, tmp_path, kwargs, name):
    with pytest.raises(ParameterError) as exc:
        _balloon(pulse, plane, tmp_path / "x.png", **kwargs)
    assert exc.value.name == name
    assert not list(tmp_path.iterdir())


def test_bad_paths_and_times(pulse, plane, tmp_path):
    with pytest.raises(ParameterError, match="path"):
        _balloon(pulse, plane, tmp_path / "x.jpg")
    with pytest.raises(ParameterError, match="time"):
        _snapshot(pulse, plane, -1.0, tmp_path / "x.png")
    with pytest.raises(ParameterError, match="path"):
        render.render_animation(pulse, plane, tmp_path / "x.png")


def test_missing_back_end_is_a_clear_error(pulse, plane, tmp_path, monkeypatch):
    def broken(*args, **kwargs):
        raise OSError("no OpenGL")

    monkeypatch.setattr(pv, "Plotter", broken)
    with pytest.raises(RuntimeError, match="off-screen rendering back-end"):
        _balloon(pulse, plane, tmp_path / "x.png")
    assert not list(tmp_path.iterdir())


def test_blank_render_is_a_clear_error(pulse, plane, tmp_path, monkeypatch):
    monkeypatch.setattr(pv.Plotter, "screenshot", lambda self, *a, **k: np.zeros((150, 200, 3), np.uint8))
    with pytest.raises(RuntimeError, match="apt-get install"):
        _snapshot(pulse, plane, 0.0005, tmp_path / "x.png")


def _rss_bytes():
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * 4096


@pytest.mark.skipif(not hasattr(__import__("os"), "sysconf"), reason="needs /proc")
@pytest.mark.slow
def test_memory_does_not_grow_over_50_renders(pulse, plane, tmp_path):
    from pyvista.plotting import plotter as _plotter_module

    grid = render.section_planes(plane, 0.1, n_u=12)

    def once(k):
        render.render_snapshot(pulse, plane, 0.0002 + 1e-6 * k, tmp_path / "m.png", planes=grid, size=(96, 72))

    for k in range(8):  # warm up: fonts, shaders, numba caches
        once(k)
    n_plotters = len(_plotter_module._ALL_PLOTTERS)
    before = _rss_bytes()
    for k in range(50):
        once(k)
    grown = _rss_bytes() - before
    assert len(_plotter_module._ALL_PLOTTERS) == n_plotters
    assert grown < 25 * 2**20, f"RSS grew by {grown / 2**20:.1f} MiB over 50 renders"


@pytest.mark.skipif(not __import__("sys").platform.startswith("linux"), reason="X/EGL choice is Linux's")
@pytest.mark.slow
def test_headless_render_is_quiet(tmp_path):
    # without a display, the render opens VTK's off-screen window directly: no X warning on stderr
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "VTK_DEFAULT_OPENGL_WINDOW")}
    env["PYTHONPATH"] = os.pathsep.join([str(root), env.get("PYTHONPATH", "")])
    code = ("import math, sys\n"
            "from acoustiviz import Impact, acceleration_pulse\n"
            "from acoustiviz.core.geometry import geometry\n"
            "from acoustiviz.output.render import render_balloon\n"
            f"a = {A!r}\n"
            "imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * math.pi * a**3)\n"
            "render_balloon(acceleration_pulse(imp, 'half-sine'), geometry('plane', a), sys.argv[1],\n"
            f"               size={SIZE!r}, n_theta=8)\n")
    out = tmp_path / "b.png"
    proc = subprocess.run([sys.executable, "-c", code, str(out)], env=env, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "bad X server" not in proc.stderr and "vtkXOpenGLRenderWindow" not in proc.stderr, proc.stderr
    _assert_real_picture(_img(out))
