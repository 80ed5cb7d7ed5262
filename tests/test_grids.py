"""Spherical and planar grids: quadrature weights, known integrals, geometry, pyvista form."""

import math

import numpy as np
import pytest

from acoustiviz._validate import ParameterError
from acoustiviz.core.geometry import geometry, images_free, images_plane, images_wall_floor
from acoustiviz.core.room_geometry import Room
from acoustiviz.field.grids import SECTIONS, planar_grid, section_grid, spherical_grid, spherical_grid_for

A = 0.01905


@pytest.mark.parametrize("region, omega", [("sphere", 4 * math.pi), ("half", 2 * math.pi), ("quarter", math.pi)])
def test_weights_sum_to_solid_angle_and_points_lie_on_sphere(region, omega):
    g = spherical_grid(0.7, region=region, centre=(0.1, -0.2, 0.3), n_theta=12)
    # a sum of 288 trigonometric weights (error up to ~N eps = 6e-14 whatever the summation order) and norms of a
    # few roundings: 1e-12 and 1e-13 are above that and far below one weight (~3e-3 of the total)
    assert g.weights.sum() == pytest.approx(omega, rel=1e-12)
    np.testing.assert_allclose(np.linalg.norm(g.points - g.centre, axis=1), 0.7, rtol=1e-13)
    assert np.all(g.weights > 0)
    if region != "sphere":
        assert np.all(g.directions[:, 2] >= 0)
    if region == "quarter":
        assert np.all(g.directions[:, 0] >= 0)


# closed forms of ∫ f dΩ over the sphere, the half space z >= 0 and the quarter z >= 0, x >= 0
KNOWN = [
    (lambda d: d[:, 2] ** 2, 4 * math.pi / 3, 2 * math.pi / 3, math.pi / 3),
    (lambda d: d[:, 0] ** 4, 4 * math.pi / 5, 2 * math.pi / 5, math.pi / 5),
    (lambda d: d[:, 0] ** 2 * d[:, 1] ** 2 * d[:, 2] ** 2, 4 * math.pi / 105, 2 * math.pi / 105, math.pi / 105),
    (lambda d: d[:, 2], 0.0, math.pi, math.pi / 2),
    (lambda d: d[:, 1] * d[:, 0], 0.0, 0.0, 0.0),
]


@pytest.mark.parametrize("k", range(len(KNOWN)))
def test_known_integrals(k):
    f, *expected = KNOWN[k]
    for region, exp in zip(("sphere", "half", "quarter"), expected, strict=True):
        g = spherical_grid(2.0, region=region, n_theta=10)
        assert g.integrate(f(g.directions)) == pytest.approx(exp, abs=1e-13)
        assert g.average(np.ones(g.weights.size)) == pytest.approx(1.0)


def test_dipole_energy_with_area_weights():
    """∫ (cos θ / r)² dS = 4π/3 on any sphere around a point dipole (r-independent)."""
    for r in (0.3, 3.0):
        g = spherical_grid(r, n_theta=8, up=(1, 1, 0))
        f = (g.directions @ (np.array([1, 1, 0]) / math.sqrt(2)) / r) ** 2
        assert np.sum(g.area_weights * f) == pytest.approx(4 * math.pi / 3, rel=1e-13)


def test_grids_for_configurations_lie_in_the_fluid():
    for cfg, omega in [
        (images_free(A), 4 * math.pi),
        (images_plane(A), 2 * math.pi),
        (images_wall_floor(A, 0.05), math.pi),
    ]:
        g = spherical_grid_for(cfg, 1.0, n_theta=6)
        assert np.all(cfg.in_fluid(g.points))
        assert g.weights.sum() == pytest.approx(omega)
    with pytest.raises(ParameterError):
        spherical_grid_for(images_wall_floor(A, 0.05), 0.05)


def test_planar_grid_any_orientation():
    u = np.array([0.3, 0.1, 0.0])
    v = np.array([0.0, 0.2, 0.4])
    g = planar_grid((0.1, 0.2, 0.3), u, v, n_u=7, n_v=5)
    assert g.points.shape == (35, 3) and g.shape == (5, 7)
    # coordinates of order 0.5 m from a few roundings (a mean of 35): ulp 1e-16, so 1e-13 m is above round-off
    np.testing.assert_allclose(g.points.mean(axis=0), (0.1, 0.2, 0.3), atol=1e-13)
    np.testing.assert_allclose((g.points - g.points[0]) @ g.normal, 0, atol=1e-13)
    np.testing.assert_allclose(g.points[6] - g.points[0], u, atol=1e-13)  # u runs fastest
    np.testing.assert_allclose(g.points[-1] - g.points[0], u + v, atol=1e-13)
    img = g.image(np.arange(35.0))
    assert img[1, 0] == 7
    with pytest.raises(ParameterError):
        planar_grid((0, 0, 0), u, 2 * u)


def test_to_pyvista_keeps_point_order():
    pytest.importorskip("pyvista")
    g = planar_grid((0, 0, 0.1), (0.2, 0, 0), (0, 0, 0.1), n_u=5, n_v=3)
    mesh = g.to_pyvista()
    np.testing.assert_allclose(np.asarray(mesh.points), g.points)
    s = spherical_grid(1.0, region="half", n_theta=4)
    ms = s.to_pyvista()
    np.testing.assert_allclose(np.asarray(ms.points), s.points)


def _scenes():
    return [geometry("free", A), geometry("plane", A),
            geometry("wall-floor", A, wall_distance=0.05),
            Room(A, (0.5, 0.4, 0.3), 0.1, (0.1, 0.15, A), order=1)]


@pytest.mark.parametrize("config", _scenes(), ids=["free", "plane", "wall-floor", "room"])
@pytest.mark.parametrize("section", list(SECTIONS))
@pytest.mark.parametrize("extent", [0.08, 0.3])
def test_section_grid_lies_in_the_fluid_and_reaches_the_walls(config, section, extent):
    g = section_grid(config, section, extent, 33)
    pts = g.points
    # on the fluid's side of every plane (rounding of the lattice's points: 1e-12 m)
    for p in config.planes:
        assert np.all((pts - p.point) @ p.normal >= -1e-12)
    outside = np.linalg.norm(pts - config.centre, axis=1) > config.radius
    assert np.all(config.in_fluid(pts[outside]))
    assert np.any(~outside) or extent > 0.2  # a section through the centre crosses the sphere
    # in the plane of the section through the centre, both in-plane axes reach a plane or the extent
    i, j = SECTIONS[section]
    k = 3 - i - j
    np.testing.assert_allclose(pts[:, k], config.centre[k], rtol=0, atol=1e-15)
    for axis in (i, j):
        for edge, sign in ((pts[:, axis].min(), -1.0), (pts[:, axis].max(), 1.0)):
            far = abs(edge - (config.centre[axis] + sign * extent)) < 1e-12
            on_plane = any(abs(edge - p.point[axis]) < 1e-12 and abs(p.normal[axis]) == 1.0 for p in config.planes)
            assert far or on_plane
    # square spacing up to the rounding of the counts: 1/32 of the longer side per step at most
    du = np.linalg.norm(g.u) / (g.n_u - 1)
    dv = np.linalg.norm(g.v) / (g.n_v - 1)
    assert max(g.n_u, g.n_v) == 33
    assert abs(du - dv) <= 0.5 * max(du, dv) / min(g.n_u - 1, g.n_v - 1) + 1e-15


def _old_box(config, extent):
    # the cut shared by the map's and the snapshot's former grids
    c = np.asarray(config.centre, dtype=float)
    lo, hi = c - extent, c + extent
    for p in config.planes:
        k = int(np.argmax(np.abs(p.normal)))
        if p.normal[k] > 0:
            lo[k] = max(lo[k], float(p.point[k]))
        else:
            hi[k] = min(hi[k], float(p.point[k]))
    return c, lo, hi


def _old_snapshot_grid(config, section, extent, n):
    c, lo, hi = _old_box(config, extent)
    i, j = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}[section]
    u, v = np.zeros(3), np.zeros(3)
    u[i], v[j] = hi[i] - lo[i], hi[j] - lo[j]
    centre = c.copy()
    centre[i], centre[j] = 0.5 * (lo[i] + hi[i]), 0.5 * (lo[j] + hi[j])
    long = max(u[i], v[j])
    return planar_grid(centre, u, v, n_u=max(2, int(round((n - 1) * u[i] / long)) + 1),
                       n_v=max(2, int(round((n - 1) * v[j] / long)) + 1))


def _old_map_grid(config, plane, height, extent, n):
    c, lo, hi = _old_box(config, extent)
    i, j = (0, 2) if plane == "vertical" else (0, 1)
    centre = 0.5 * (lo + hi)
    if plane == "vertical":
        centre[1] = c[1]
    else:
        centre[2] = height
    u, v = np.zeros(3), np.zeros(3)
    u[i], v[j] = hi[i] - lo[i], hi[j] - lo[j]
    long = max(u[i], v[j])
    return planar_grid(centre, u, v, n_u=max(2, int(round((n - 1) * u[i] / long)) + 1),
                       n_v=max(2, int(round((n - 1) * v[j] / long)) + 1))


@pytest.mark.parametrize("config", _scenes(), ids=["free", "plane", "wall-floor", "room"])
def test_section_grid_reproduces_the_snapshot_and_map_grids(config):
    from acoustiviz.app.maps import map_grid
    from acoustiviz.field.sections import section_planes

    for section in SECTIONS:
        for extent, n in ((0.1, 41), (0.25, 24)):
            old = _old_snapshot_grid(config, section, extent, n)
            assert np.array_equal(section_grid(config, section, extent, n).points, old.points)
            assert np.array_equal(section_planes(config, extent, sections=(section,), n_u=n)[0].points, old.points)
    for extent, n in ((0.1, 41), (0.25, 24)):
        old = _old_map_grid(config, "vertical", None, extent, n)
        assert np.array_equal(map_grid(config, plane="vertical", extent=extent, resolution=n).points, old.points)
        h = config.centre[2] + 0.01
        old = _old_map_grid(config, "horizontal", h, extent, n)
        new = map_grid(config, plane="horizontal", height=h, extent=extent, resolution=n).points
        assert np.array_equal(new, old.points)
