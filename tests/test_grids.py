"""Spherical and planar grids: quadrature weights, known integrals, geometry, pyvista form."""

import math

import numpy as np
import pytest

from acoustiviz._validate import ParameterError
from acoustiviz.core.geometry import images_free, images_plane, images_wall_floor
from acoustiviz.field.grids import planar_grid, spherical_grid, spherical_grid_for

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
