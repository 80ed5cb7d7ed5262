"""Level maps (acoustiviz.app.maps): peaks and SEL against the sampled-and-refined field metrics,
blank points, symmetry, spreading loss, files and input checks."""

import math

import numpy as np
import pytest

from acoustiviz.app.impacts import impact_setup
from acoustiviz.app.maps import (
    CLI_NAMES,
    MAP_CSV_COLUMNS,
    MAP_SETTINGS,
    level_map,
    map_grid,
    map_on_grid,
    plan_map,
    write_map_csv,
    write_map_outputs,
)
from acoustiviz.constants import P_REF
from acoustiviz.errors import ParameterError
from acoustiviz.field import field_metrics, time_series
from acoustiviz.field.grids import planar_grid

#: Peaks: both paths refine the continuous pressure (fast_peaks to ~1e-11, field_metrics' Brent
#: search to ~1e-12 relative). SEL: field_metrics sums 64 samples per min(T, a/c).
PEAK_RTOL = 1e-8
SEL_ATOL_DB = 1e-6
#: 20 log10(2): the far-field fall of a level per doubling of distance (pressure ~ 1/r).
DOUBLING_DB = 20.0 * math.log10(2.0)


def _setup(config, pulse="half-sine", **kw):
    return impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config=config, pulse=pulse,
                        **kw)


CASES = [("free", "half-sine", {}), ("plane", "hertz", {}), ("wall-floor", "half-sine", {"wall_distance": 0.05}),
         ("wall-floor", "impulse-matched", {"strike": "wall", "height": 0.08})]


@pytest.mark.parametrize(("config", "pulse", "kw"), CASES)
@pytest.mark.slow
def test_peaks_and_sel_equal_the_refined_field_metrics(config, pulse, kw):
    s = _setup(config, pulse, **kw)
    for plane in ("vertical", "horizontal"):
        height = None if plane == "vertical" else 0.06
        m = level_map(s.pulse, s.geometry, medium=s.medium, plane=plane, height=height, extent=0.4,
                      resolution=31)
        ok = np.flatnonzero(np.isfinite(m.peak_pa))
        pick = np.random.default_rng(7).choice(ok, size=24, replace=False)
        pts = m.grid.points[pick]
        fm = field_metrics(s.pulse, pts, s.geometry, medium=s.medium)
        ref_peak = np.maximum(fm.peak_positive, -fm.peak_negative)
        np.testing.assert_allclose(m.peak_pa[pick], ref_peak, rtol=PEAK_RTOL)
        np.testing.assert_allclose(m.peak_spl_db[pick], 20 * np.log10(ref_peak / P_REF), rtol=0, atol=1e-7)
        np.testing.assert_allclose(m.sel_db[pick], 10 * np.log10(fm.exposure / P_REF**2), rtol=0, atol=SEL_ATOL_DB)
        # the time of the peak: the pressure there, from the time series, is +-peak
        for i in pick[:4]:
            p = time_series(s.pulse, np.array([m.time_of_peak_s[i]]), m.grid.points[i][None, :], s.geometry,
                            medium=s.medium)[0, 0]
            assert abs(p) == pytest.approx(m.peak_pa[i], rel=1e-9)


def test_points_inside_the_sphere_are_blank_and_only_those():
    s = _setup("free")
    m = level_map(s.pulse, s.geometry, medium=s.medium, extent=0.1, resolution=61)
    dist = np.linalg.norm(m.grid.points - s.geometry.centre, axis=1)
    blank = ~np.isfinite(m.peak_pa)
    assert blank.any()
    np.testing.assert_array_equal(blank, dist < s.geometry.radius * (1 - 1e-12))
    for arr in (m.peak_spl_db, m.sel_db, m.time_of_peak_s, m.exposure_pa2s):
        np.testing.assert_array_equal(~np.isfinite(arr), blank)


def test_a_grid_through_the_wall_and_floor_is_blank_behind_them():
    s = _setup("wall-floor", wall_distance=0.05)
    grid = planar_grid((0.0, 0.0, 0.0), (0.4, 0.0, 0.0), (0.0, 0.0, 0.4), n_u=41)
    m = map_on_grid(s.pulse, s.geometry, grid, medium=s.medium)
    x, z = grid.points[:, 0], grid.points[:, 2]
    behind = (x < -0.05 - 1e-12) | (z < -1e-12)
    assert behind.sum() > 400
    assert np.all(np.isnan(m.peak_pa[behind])) and np.all(np.isnan(m.sel_db[behind]))
    inside = np.linalg.norm(grid.points - s.geometry.centre, axis=1) < s.geometry.radius
    assert np.all(np.isfinite(m.peak_pa[~behind & ~inside]))


@pytest.mark.parametrize(("config", "kw"), [("plane", {}), ("wall-floor", {"wall_distance": 0.05})])
def test_maps_are_cut_at_the_floor_and_the_wall(config, kw):
    s = _setup(config, **kw)
    for plane in ("vertical", "horizontal"):
        g = map_grid(s.geometry, plane=plane, extent=0.3, resolution=40)
        for pl in s.geometry.planes:
            assert np.all(pl.signed_distance(g.points) >= -1e-15)
        c = s.geometry.centre
        assert g.points[:, 0].max() == pytest.approx(c[0] + 0.3)
        if config == "wall-floor":
            assert g.points[:, 0].min() == pytest.approx(-0.05)
        if plane == "vertical":
            assert np.all(g.points[:, 1] == 0.0) and g.points[:, 2].min() == pytest.approx(0.0)
        else:
            assert np.allclose(g.points[:, 2], c[2])  # default: through the sphere's centre
        assert max(g.n_u, g.n_v) == 40


def test_default_resolution_gives_about_1e5_points_on_a_square_map():
    s = _setup("free")
    g = map_grid(s.geometry)
    assert 0.9e5 < g.points.shape[0] < 1.1e5


def test_free_field_vertical_map_is_mirror_symmetric_about_the_axis():
    s = _setup("free", "hertz")
    m = level_map(s.pulse, s.geometry, medium=s.medium, extent=0.3, resolution=45)
    x = m.grid.image(m.grid.points[:, 0])
    np.testing.assert_allclose(x[:, ::-1], -x, atol=1e-13)  # the grid itself is mirrored (to round-off of 0.3 m)
    pk, sel, t = (m.grid.image(a) for a in (m.peak_pa, m.sel_db, m.time_of_peak_s))
    np.testing.assert_allclose(pk[:, ::-1], pk, rtol=PEAK_RTOL)
    np.testing.assert_allclose(sel[:, ::-1], sel, rtol=0, atol=1e-9)
    np.testing.assert_allclose(t[:, ::-1], t, rtol=1e-9)


def test_sel_falls_6_db_per_doubling_of_distance_far_from_the_sphere():
    s = _setup("free")
    # 1 m spacing, the centre on the grid: point (c + k, c + k) lies k sqrt(2) m away at 45 degrees
    m = level_map(s.pulse, s.geometry, medium=s.medium, extent=40.0, resolution=81)
    c = 40
    sel = m.grid.image(m.sel_db)
    assert np.linalg.norm(m.grid.image(m.grid.points.T)[:, c, c] - s.geometry.centre) < 1e-12
    drops = [sel[c + k, c + k] - sel[c + 2 * k, c + 2 * k] for k in (2, 5, 10, 20)]
    errors = np.abs(np.array(drops) - DOUBLING_DB)
    assert errors[-1] < 1e-4  # 28 m -> 57 m
    assert np.all(errors < 3e-3)
    assert np.all(np.diff(errors) < 0)  # the near-field part dies away with distance


def test_csv_columns_and_rows(tmp_path):
    s = _setup("plane")
    m = level_map(s.pulse, s.geometry, medium=s.medium, extent=0.2, resolution=21)
    path = write_map_csv(m, tmp_path / "m.csv")
    lines = path.read_text().splitlines()
    assert lines[0] == ",".join(MAP_CSV_COLUMNS) == "x_m,y_m,z_m,peak_pa,peak_spl_db,sel_db,time_of_peak_s"
    data = np.genfromtxt(path, delimiter=",", skip_header=1)
    assert data.shape == (m.grid.points.shape[0], 7)
    np.testing.assert_allclose(data[:, :3], m.grid.points, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(data[:, 3], m.peak_pa, rtol=1e-10)
    np.testing.assert_allclose(data[:, 5], m.sel_db, atol=1e-6)
    assert np.array_equal(np.isnan(data[:, 4]), np.isnan(m.peak_spl_db))


def test_vtk_holds_the_map_with_units_in_the_names(tmp_path):
    pv = pytest.importorskip("pyvista")
    s = _setup("wall-floor", wall_distance=0.05)
    m = level_map(s.pulse, s.geometry, medium=s.medium, extent=0.2, resolution=16)
    paths = write_map_outputs(m, s.geometry, vtk=tmp_path / "m.vtu")
    assert [p.name for p in paths] == ["m.vtu", "m_geometry.vtu"]
    mesh = pv.read(tmp_path / "m.vtu")
    np.testing.assert_allclose(mesh.points, m.grid.points)
    assert mesh.n_cells == (m.grid.n_u - 1) * (m.grid.n_v - 1)
    for name in ("peak_pa", "peak_spl_db", "sel_db", "time_of_peak_s", "exposure_pa2s"):
        np.testing.assert_array_equal(np.asarray(mesh.point_data[name]), getattr(m, name))


@pytest.mark.slow
def test_png_is_written(tmp_path):
    Image = pytest.importorskip("PIL.Image")
    s = _setup("plane")
    m = level_map(s.pulse, s.geometry, medium=s.medium, plane="horizontal", height=0.05, extent=0.2,
                  resolution=24)
    (path,) = write_map_outputs(m, s.geometry, png=tmp_path / "m.png", title="t")
    with Image.open(path) as im:
        img = np.asarray(im.convert("RGB")).astype(int)
    assert img.shape[1] > img.shape[0] and img.std() > 20


BAD = [
    ({"plane": "diagonal"}, "plane"),
    ({"extent": -1.0}, "extent"),
    ({"extent": 0.03}, "extent"),  # inside the sphere's diameter
    ({"extent": 2e3}, "extent"),
    ({"extent": float("nan")}, "extent"),
    ({"resolution": 7}, "resolution"),
    ({"resolution": 20001}, "resolution"),
    ({"resolution": 40.5}, "resolution"),
    ({"height": 0.1}, "height"),  # with the vertical plane
    ({"plane": "horizontal", "height": -0.01}, "height"),  # below the floor
    ({"plane": "horizontal", "height": 5.0}, "height"),  # outside the map's box
    ({"resolution": 20000, "max_memory_mb": 100.0}, "resolution"),
    ({"max_memory_mb": -1.0}, "max_memory_mb"),
]


@pytest.mark.parametrize(("kw", "name"), BAD)
def test_bad_settings_are_refused_naming_the_setting(kw, name):
    s = _setup("plane")
    with pytest.raises(ParameterError) as err:
        plan_map(s.pulse, s.geometry, medium=s.medium, **kw)
    assert err.value.name == name
    with pytest.raises(ParameterError) as err:
        level_map(s.pulse, s.geometry, medium=s.medium, names=CLI_NAMES, **kw)
    assert err.value.name == CLI_NAMES[name]


def test_memory_refusal_says_what_to_change():
    s = _setup("plane")
    with pytest.raises(ParameterError) as err:
        plan_map(s.pulse, s.geometry, resolution=20000, names=CLI_NAMES)
    msg = str(err.value)
    assert msg.startswith("--resolution:") and "--max-memory" in msg and "MB" in msg


def test_settings_are_defined_once_for_the_command_and_the_scene():
    from acoustiviz.scene.schema import SCHEMA

    keys = SCHEMA["outputs"].keys["level_map"].keys
    for st in MAP_SETTINGS:
        k = keys[st.key]
        assert (k.default, k.low, k.high, k.low_open, k.choices, k.unit) == \
            (st.default, st.low, st.high, st.low_open, st.choices, st.unit)
