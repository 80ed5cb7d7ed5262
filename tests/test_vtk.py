"""acoustiviz.output.vtk: fields read back by pyvista and meshio equal the field evaluator's values."""


import numpy as np
import pytest

from acoustiviz.app.impacts import impact_setup
from acoustiviz.cli import main
from acoustiviz.errors import ParameterError
from acoustiviz.field import field_metrics, snapshots, time_series
from acoustiviz.field.balloon import balloon_data
from acoustiviz.field.sections import animation_field, section_field
from acoustiviz.output.vtk import geometry_path, write_animation_vtk, write_balloon_vtk, write_snapshot_vtk

pv = pytest.importorskip("pyvista")
meshio = pytest.importorskip("meshio")

P_REF = 20e-6  # Pa, the reference pressure of every level (independent of the package's constant)


def _setup(config="plane", **kw):
    return impact_setup(radius=0.01905, velocity=1.4, config=config, **kw)


def _pressure_names(mesh):
    return sorted(n for n in mesh.point_data.keys() if n.startswith("pressure_pa"))


def test_cli_interface_of_the_issue(tmp_path, monkeypatch, capsys):
    """``render snapshot --config plane --time 0.001 --png S.png --vtk S.vtu``: the evaluator's values."""
    monkeypatch.chdir(tmp_path)
    assert main(["render", "snapshot", "--config", "plane", "--time", "0.001", "--size", "200x150",
                 "--resolution", "41", "--png", "S.png", "--vtk", "S.vtu"]) == 0
    out = capsys.readouterr().out
    assert "wrote S.vtu" in out and "wrote S_geometry.vtu" in out and "wrote S.png" in out
    mesh = pv.read("S.vtu")
    assert _pressure_names(mesh) == ["pressure_pa_t0000"]
    np.testing.assert_array_equal(mesh.field_data["time_s"], [0.001])
    s = _setup()
    expected = snapshots(s.pulse, [0.001], np.asarray(mesh.points), s.geometry, medium=s.medium)[0]
    got = mesh.point_data["pressure_pa_t0000"]
    assert np.isfinite(got).sum() > 500 and np.nanmax(np.abs(got)) > 0.1  # a real field, not zeros
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=0, equal_nan=True)
    # every point of the section lies in the plane y = 0 and above the floor
    assert np.all(np.abs(mesh.points[:, 1]) < 1e-12) and mesh.points[:, 2].min() >= 0.0
    # meshio reads the same points and values
    m = meshio.read("S.vtu")
    np.testing.assert_array_equal(m.points, mesh.points)
    np.testing.assert_array_equal(m.point_data["pressure_pa_t0000"], got)
    np.testing.assert_array_equal(m.field_data["time_s"], [0.001])
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left behind


def test_several_times_agree_with_the_time_series(tmp_path):
    """Each pressure array matches a second route through the evaluator: the time series at that time."""
    s = _setup("wall-floor", wall_distance=0.05)
    times = [0.4e-3, 0.8e-3, 1.2e-3]
    field = section_field(s.pulse, s.geometry, times, medium=s.medium, sections=("xz", "xy"), n_u=31)
    data, geo = write_snapshot_vtk(field, s.geometry, tmp_path / "s.vtu")
    mesh = pv.read(data)
    assert _pressure_names(mesh) == [f"pressure_pa_t{k:04d}" for k in range(3)]
    np.testing.assert_allclose(mesh.field_data["time_s"], times, rtol=0, atol=0)
    assert set(np.unique(mesh.point_data["section"])) == {0, 1}
    rng = np.random.default_rng(1)
    pts = np.asarray(mesh.points)
    inside = np.isfinite(mesh.point_data["pressure_pa_t0000"])
    pick = rng.choice(np.flatnonzero(inside), 12, replace=False)
    for k, t in enumerate(times):
        ref = np.array([time_series(s.pulse, [t], [pts[i]], s.geometry, medium=s.medium)[0, 0] for i in pick])
        got = mesh.point_data[f"pressure_pa_t{k:04d}"][pick]
        scale = np.max(np.abs(mesh.point_data[f"pressure_pa_t{k:04d}"][inside]))
        np.testing.assert_allclose(got, ref, rtol=1e-9, atol=1e-9 * scale)
    # points inside the sphere carry NaN, and only those
    r = np.linalg.norm(pts - s.geometry.centre, axis=1)
    np.testing.assert_array_equal(~inside, r < s.geometry.radius)


def test_geometry_file(tmp_path):
    s = _setup("wall-floor", wall_distance=0.05)
    field = section_field(s.pulse, s.geometry, 1e-3, medium=s.medium, n_u=21)
    _, geo = write_snapshot_vtk(field, s.geometry, tmp_path / "f.vtkhdf")
    assert geo == tmp_path / "f_geometry.vtu" == geometry_path(tmp_path / "f.vtkhdf")
    g = pv.read(geo)
    part = g.cell_data["part"]
    assert sorted(np.unique(part)) == [0, 1, 2]
    geometry = s.geometry
    sphere = g.extract_cells(np.flatnonzero(part == 0))
    np.testing.assert_allclose(np.linalg.norm(sphere.points - geometry.centre, axis=1), geometry.radius, rtol=1e-6)
    floor = g.extract_cells(np.flatnonzero(part == 1))
    wall = g.extract_cells(np.flatnonzero(part == 2))
    np.testing.assert_allclose(floor.points[:, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(wall.points[:, 0], -0.05, atol=1e-12)
    # the planes span the data: the section file's points lie within the floor's x-range
    data = pv.read(tmp_path / "f.vtkhdf")
    assert floor.bounds[0] <= data.bounds[0] + 1e-12 and floor.bounds[1] >= data.bounds[1] - 1e-12
    np.testing.assert_allclose(g.field_data["sphere_radius_m"], [geometry.radius])


@pytest.mark.parametrize("suffix", [".vtu", ".vtkhdf"])
def test_balloon_metrics_on_the_measuring_sphere(tmp_path, suffix):
    s = _setup()
    balloon = balloon_data(s.pulse, s.geometry, medium=s.medium, distance=0.5, n_theta=8)
    data, _ = write_balloon_vtk(balloon, s.geometry, tmp_path / f"b{suffix}")
    mesh = pv.read(data)
    pts = np.asarray(mesh.points)
    geometry = s.geometry
    np.testing.assert_allclose(np.linalg.norm(pts - geometry.contact_point, axis=1), 0.5, rtol=1e-12)
    assert pts[:, 2].min() >= -1e-12  # the half space above the floor
    fm = field_metrics(s.pulse, pts, geometry, medium=s.medium)
    for name, ref in [("peak_pa", fm.peak), ("rms_pa", fm.rms), ("peak_positive_pa", fm.peak_positive),
                      ("peak_negative_pa", fm.peak_negative), ("exposure_pa2s", fm.exposure)]:
        np.testing.assert_allclose(mesh.point_data[name], ref, rtol=1e-12, atol=0)
    # the levels follow from the pressures by their definitions
    np.testing.assert_allclose(mesh.point_data["peak_spl_db"], 20 * np.log10(mesh.point_data["peak_pa"] / P_REF),
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(mesh.point_data["sel_db"],
                               10 * np.log10(mesh.point_data["exposure_pa2s"] / (P_REF**2 * 1.0)), rtol=0, atol=1e-9)
    np.testing.assert_allclose(mesh.point_data["rms_pa"] ** 2 * mesh.field_data["window_s"][0],
                               mesh.point_data["exposure_pa2s"], rtol=1e-9)
    # the far field of a sphere on a plane is loudest along the normal: compare top and grazing rings
    up = mesh.point_data["direction"][:, 2]
    assert mesh.point_data["peak_pa"][up > 0.9].min() > mesh.point_data["peak_pa"][up < 0.2].max()
    if suffix == ".vtu":
        m = meshio.read(data)
        np.testing.assert_array_equal(m.point_data["peak_spl_db"], mesh.point_data["peak_spl_db"])


def test_animation_frames(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["render", "animation", "--config", "free", "--frames", "5", "--resolution", "21",
                 "--vtk", "a.vtu"]) == 0
    mesh = pv.read("a.vtu")
    t = mesh.field_data["time_s"]
    assert len(_pressure_names(mesh)) == 5 == t.size and np.all(np.diff(t) > 0)
    s = _setup("free")
    ref = snapshots(s.pulse, t, np.asarray(mesh.points), s.geometry, medium=s.medium)
    for k in range(5):
        got = mesh.point_data[f"pressure_pa_t{k:04d}"]
        scale = np.nanmax(np.abs(ref[k]))
        np.testing.assert_allclose(got, ref[k], rtol=0, atol=1e-8 * scale, equal_nan=True)
    assert not (tmp_path / "a.gif").exists()


@pytest.mark.slow
def test_scene_requests_vtk(tmp_path):
    from acoustiviz import load_scene, run_scene

    scene = tmp_path / "s.toml"
    scene.write_text('[configuration]\nkind = "plane"\n\n[grids.plane]\nresolution = 24\n\n[grids.sphere]\n'
                     'n_theta = 6\n\n[outputs.snapshot]\ntimes_s = [0.0005]\nsize_px = [160, 120]\nvtk = true\n\n'
                     '[outputs.balloon]\nsize_px = [160, 120]\nvtk = true\n', encoding="utf-8")
    run_scene(load_scene(scene), tmp_path / "out", force=True)
    names = {p.name for p in (tmp_path / "out").iterdir()}
    assert {"snapshot.vtu", "snapshot_geometry.vtu", "balloon.vtu", "balloon_geometry.vtu"} <= names
    assert _pressure_names(pv.read(tmp_path / "out" / "snapshot.vtu")) == ["pressure_pa_t0000"]
    assert "snapshot.vtu" in (tmp_path / "out" / "summary.md").read_text(encoding="utf-8")


@pytest.mark.parametrize(("argv", "option"), [
    (["snapshot", "--vtk", "x.vtk"], "--vtk"),
    (["balloon", "--html", "x.png"], "--html"),
    (["balloon"], "--png"),
])
def test_bad_outputs_exit_2(tmp_path, monkeypatch, capsys, argv, option):
    monkeypatch.chdir(tmp_path)
    assert main(["render", *argv]) == 2
    err = capsys.readouterr().err
    assert option in err and len(err.strip().splitlines()) == 1
    assert not list(tmp_path.iterdir())


def test_write_refuses_other_suffix(tmp_path):
    s = _setup()
    field = animation_field(s.pulse, s.geometry, medium=s.medium, frames=2, n_u=11)
    with pytest.raises(ValueError, match="vtu"):
        write_animation_vtk(field, s.geometry, tmp_path / "a.vtk")
    assert not list(tmp_path.iterdir())


def test_a_balloon_without_its_metrics_is_refused_not_evaluated(tmp_path):
    # a level of its own carries no field metrics: the writer says where they come from, computes nothing
    s = _setup()
    flat = balloon_data(s.pulse, s.geometry, medium=s.medium, distance=0.5, n_theta=6, metric="flat",
                        levels=(lambda pts: np.full(len(pts), 80.0), "flat (dB re 20 µPa)"))
    with pytest.raises(ParameterError, match="balloon_metrics") as exc:
        write_balloon_vtk(flat, s.geometry, tmp_path / "b.vtu")
    assert exc.value.name == "data"
    assert not list(tmp_path.iterdir())


def test_a_vtu_is_written_by_python_and_reads_back_as_pyvista_writes_it(tmp_path):
    import pyvista as pv

    from acoustiviz.output.vtk import _save

    mesh = pv.Sphere().cast_to_unstructured_grid()
    mesh.point_data["p"] = np.arange(mesh.n_points, dtype=float)
    mesh.field_data["r"] = np.array([0.5])
    ours = _save(mesh, tmp_path / "ours.vtu")
    mesh.save(str(tmp_path / "theirs.vtu"))
    # the same mesh and arrays (not the same bytes: the zlib level of pyvista's writer differs between releases)
    back, theirs = pv.read(ours), pv.read(tmp_path / "theirs.vtu")
    np.testing.assert_array_equal(back.points, theirs.points)
    np.testing.assert_array_equal(back.cells, theirs.cells)
    np.testing.assert_array_equal(back.celltypes, theirs.celltypes)
    for data in ("point_data", "cell_data", "field_data"):
        assert list(getattr(back, data)) == list(getattr(theirs, data))
        for name in getattr(back, data):
            np.testing.assert_array_equal(getattr(back, data)[name], getattr(theirs, data)[name])
    np.testing.assert_array_equal(back.point_data["p"], mesh.point_data["p"])


def test_a_vtkhdf_without_room_is_refused_before_vtk_writes(tmp_path, monkeypatch):
    import errno
    import shutil
    from collections import namedtuple

    import pyvista as pv

    import acoustiviz.output.vtk as vtk

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage(1 << 30, (1 << 30) - 4096, 4096))
    mesh = pv.Sphere().cast_to_unstructured_grid()
    with pytest.raises(OSError) as info:
        vtk._save(mesh, tmp_path / "m.vtkhdf")
    assert info.value.errno == errno.ENOSPC and info.value.filename == str(tmp_path / "m.vtkhdf")
    assert list(tmp_path.iterdir()) == []
