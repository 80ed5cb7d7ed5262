"""Off-screen renders: real pixels of the requested size, colour bars, geometry, animations, no leaks."""

import numpy as np
import pytest

from acoustiviz.errors import ParameterError
from acoustiviz.field.balloon import balloon_data
from acoustiviz.field.sections import animation_field, section_field, section_planes

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


def _split(kw, physics):
    """``kw`` split into the field's arguments (names in ``physics``) and the sink's."""
    return ({k: v for k, v in kw.items() if k in physics}, {k: v for k, v in kw.items() if k not in physics})


def _balloon(pulse, conf, path, **kw):
    """The balloon of ``conf`` (one or several) computed by the field layer, then rendered."""
    where, draw = _split({"n_theta": 8, **kw}, ("distance", "metric", "n_theta"))
    confs = [conf] if not isinstance(conf, list) else conf
    data = [balloon_data(pulse, c, **where) for c in confs]
    return render.render_balloon(data if isinstance(conf, list) else data[0], pulse, conf, path,
                                 **{"size": SIZE, **draw})


def _snapshot(pulse, conf, t, path, **kw):
    """The snapshot of ``conf`` at ``t`` evaluated by the field layer, then rendered."""
    where, draw = _split({"n_u": 41, **kw}, ("extent", "sections", "n_u", "planes"))
    return render.render_snapshot(section_field(pulse, conf, t, **where), pulse, conf, path, **{"size": SIZE, **draw})


# --------------------------------------------------------------------------- balloon
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
    grids = section_planes(corner, 0.2, sections=("xz", "yz", "xy"), n_u=11)
    for g in grids:
        assert np.all(corner.in_fluid(g.points) | (np.linalg.norm(g.points - corner.centre, axis=1) < A))
    assert min(g.points[:, 0].min() for g in grids) == pytest.approx(-0.05)  # clipped at the wall


# --------------------------------------------------------------------------- animation
def test_gif_animation_frames(pulse, corner, tmp_path):
    field = animation_field(pulse, corner, frames=5, n_u=31)
    out = render.render_animation(field, pulse, corner, tmp_path / "a.gif", size=(160, 120))
    with Image.open(out) as im:
        assert im.size == (160, 120)
        assert im.n_frames == 5
        frames = []
        for k in range(im.n_frames):
            im.seek(k)
            frames.append(np.asarray(im.convert("RGB")).astype(int))
    assert np.abs(frames[0] - frames[2]).mean() > 1.0


def test_mp4_is_optional(pulse, plane, tmp_path):
    field = animation_field(pulse, plane, frames=3, n_u=21)
    if render.mp4_available():
        out = render.render_animation(field, pulse, plane, tmp_path / "a.mp4", size=(160, 120))
        assert out.stat().st_size > 1000
    else:
        with pytest.raises(ParameterError, match="imageio-ffmpeg"):
            render.render_animation(field, pulse, plane, tmp_path / "a.mp4", size=(160, 120))
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
        render.render_animation(animation_field(pulse, plane, frames=2, n_u=11), pulse, plane, tmp_path / "x.png")


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

    grid = section_planes(plane, 0.1, n_u=12)

    def once(k):
        field = section_field(pulse, plane, 0.0002 + 1e-6 * k, planes=grid)
        render.render_snapshot(field, pulse, plane, tmp_path / "m.png", size=(96, 72))

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
            "from acoustiviz.field.balloon import balloon_data\n"
            "from acoustiviz.output.render import render_balloon\n"
            f"a = {A!r}\n"
            "imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * math.pi * a**3)\n"
            "pulse, plane = acceleration_pulse(imp, 'half-sine'), geometry('plane', a)\n"
            f"render_balloon(balloon_data(pulse, plane, n_theta=8), pulse, plane, sys.argv[1], size={SIZE!r})\n")
    out = tmp_path / "b.png"
    proc = subprocess.run([sys.executable, "-c", code, str(out)], env=env, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "bad X server" not in proc.stderr and "vtkXOpenGLRenderWindow" not in proc.stderr, proc.stderr
    _assert_real_picture(_img(out))
