"""Image sources: geometry, eq 14 identity, and the rigid-plane boundary condition."""

import numpy as np
import pytest

from acoustiviz.core.geometry import geometry, images_free, images_plane, images_wall_floor
from acoustiviz.core.images import ImageSource, mirror_point
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import pressure, pulse_response, sphere_pressure
from acoustiviz.errors import ParameterError

A = 0.01905
RNG = np.random.default_rng(3)
#: the normal gradient on a plane vanishes to round-off relative to one sphere's own gradient
BC_RTOL = 1e-10


def _grad_one(pulse, t, pts, src, radius, medium=AIR):
    """Exact pressure gradient (Pa/m) of one sphere, by the chain rule on P0 Re[C Y] (n, m, 3)."""
    d = pts - src.position
    r = np.linalg.norm(d, axis=1)
    dh = d / r[:, None]
    ct = dh @ src.axis
    k = medium.rho * medium.c * radius**2
    s = complex(-medium.c / radius, medium.c / radius)
    tr = t[None, :] - ((r - radius) / medium.c)[:, None]
    y = pulse_response(pulse, tr, radius=radius, medium=medium)
    acc = pulse.acceleration(tr)
    dy = np.where(tr >= 0, s * y + acc, 0.0)
    cc = (r / radius - 1j * (1 - r / radius))[:, None]
    p0 = (k * ct / r**2)[:, None]
    rr = r[:, None]
    dp_dr = (-2 * p0 / rr) * np.real(cc * y) + p0 * np.real(
        (1 + 1j) / radius * y - cc * dy / medium.c
    )
    dp_dct = (k / r**2)[:, None] * np.real(cc * y)
    gct = (src.axis[None, :] - ct[:, None] * dh) / r[:, None]
    return dp_dr[..., None] * dh[:, None, :] + dp_dct[..., None] * gct[:, None, :]


def _field(pulse, t, pts, cfg, signs=None):
    signs = signs or [1.0] * len(cfg.sources)
    return sum(
        sg * sphere_pressure(pulse, t, pts, radius=cfg.radius, centre=s.position, axis=s.axis)
        for sg, s in zip(signs, cfg.sources, strict=True)
    )


def _points_on(plane, cfg, n=40, span=0.5):
    """Random points on ``plane`` inside the fluid region of ``cfg``, away from the sphere."""
    u = np.cross(plane.normal, [0.3, 0.5, 0.7])
    u /= np.linalg.norm(u)
    v = np.cross(plane.normal, u)
    pts = plane.point + span * (
        RNG.uniform(-1, 1, (4 * n, 1)) * u + RNG.uniform(-1, 1, (4 * n, 1)) * v
    )
    keep = cfg.in_fluid(pts) & (np.linalg.norm(pts - cfg.centre, axis=1) > 1.5 * cfg.radius)
    return pts[keep][:n]


def test_geometry_plane_and_corner():
    cfg = images_plane(A)
    assert len(cfg.sources) == 2 and len(cfg.planes) == 1
    np.testing.assert_allclose(cfg.sources[1].position, [0, 0, -A])
    np.testing.assert_allclose(cfg.sources[1].axis, [0, 0, -1])
    np.testing.assert_allclose(cfg.contact_point, [0, 0, 0], atol=1e-15)
    wf = images_wall_floor(A, 0.05)
    pos = {s.label: s.position for s in wf.sources}
    np.testing.assert_allclose(pos["wall"], [-0.1, 0, A])
    np.testing.assert_allclose(pos["floor+wall"], [-0.1, 0, -A])
    assert [s.order for s in wf.sources] == [0, 1, 1, 2]
    ww = images_wall_floor(A, strike="wall", height=0.03)
    np.testing.assert_allclose(ww.contact_point, [-A, 0, 0.03])
    np.testing.assert_allclose([s.axis[0] for s in ww.sources], [1, 1, -1, -1])
    assert images_free(A).sources[0].order == 0


def test_in_fluid_mask():
    wf = images_wall_floor(A, 0.05)
    pts = np.array([[0.0, 0.0, 0.3], [0, 0, -0.01], [-0.06, 0, 0.1], [0, 0, A], [-0.05, 0, 0.0]])
    assert wf.in_fluid(pts).tolist() == [True, False, False, False, True]


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(name="wall-floor", radius=A, wall_distance=0.01), "wall_distance"),
        (dict(name="corner", radius=A), "config"),
        (dict(name="plane", radius=-1.0), "radius"),
        (dict(name="wall-floor", radius=A, wall_distance=0.05, strike="roof"), "strike"),
        (dict(name="wall-floor", radius=A, wall_distance=0.05, strike="wall"), "wall_distance"),
    ],
)
def test_bad_configuration_names_parameter(kwargs, name):
    with pytest.raises(ParameterError) as err:
        geometry(**kwargs)
    assert err.value.name == name


def test_eq14_identity(paper_pulse, plane_geometry):
    """Sum with mirrored axes == paper eq 14 (minus sign, both angles from the real axis)."""
    pulse = paper_pulse()
    cfg = plane_geometry
    pts = RNG.uniform([-1, -1, 0], [1, 1, 1], (50, 3))
    t = np.linspace(0, 4e-3, 400)
    ours = _field(pulse, t, pts, cfg)
    d1 = pts - cfg.sources[0].position
    d2 = pts - cfg.sources[1].position
    r1, r2 = np.linalg.norm(d1, axis=1), np.linalg.norm(d2, axis=1)
    c1, c2 = d1[:, 2] / r1, d2[:, 2] / r2  # both from the real +z axis
    eq14 = pressure(pulse, t, r1[:, None], c1[:, None], radius=A) - pressure(
        pulse, t, r2[:, None], c2[:, None], radius=A
    )
    scale = np.max(np.abs(eq14))
    np.testing.assert_allclose(ours, eq14, rtol=0, atol=1e-13 * scale)


@pytest.mark.parametrize(
    "cfg",
    [
        images_plane(A),
        images_wall_floor(A, 0.05),
        images_wall_floor(A, 0.2),
        images_wall_floor(A, strike="wall", height=0.04),
    ],
    ids=["plane", "corner-near", "corner-far", "corner-wall-strike"],
)
def test_boundary_condition_on_every_plane(cfg, paper_pulse):
    """Normal particle velocity ∝ ∫ ∂p/∂n dt vanishes: ∂p/∂n = 0 at all times on each plane."""
    pulse = paper_pulse()
    t = np.linspace(0, 3e-3, 150)
    for plane in cfg.planes:
        pts = _points_on(plane, cfg)
        assert len(pts) >= 20
        grads = [_grad_one(pulse, t, pts, s, cfg.radius) @ plane.normal for s in cfg.sources]
        total = sum(grads)
        free = np.max(np.abs(grads[0]))
        assert free > 0
        assert np.max(np.abs(total)) <= BC_RTOL * free
        # a fine centred difference of the summed pressure agrees (mirror symmetry of p)
        h = 1e-6
        dp = (
            _field(pulse, t, pts + h * plane.normal, cfg)
            - _field(pulse, t, pts - h * plane.normal, cfg)
        ) / (2 * h)
        fd_free = (
            sphere_pressure(
                pulse, t, pts + h * plane.normal, radius=A, centre=cfg.centre, axis=cfg.axis
            )
            - sphere_pressure(
                pulse, t, pts - h * plane.normal, radius=A, centre=cfg.centre, axis=cfg.axis
            )
        ) / (2 * h)
        assert np.max(np.abs(dp)) <= 1e-6 * np.max(np.abs(fd_free))
        # a wrongly signed image breaks the boundary condition
        for k in range(1, len(cfg.sources)):
            wrong = total - 2 * grads[k]
            assert np.max(np.abs(wrong)) > 1e4 * BC_RTOL * free  # fails the check by far


@pytest.mark.parametrize(
    "cfg", [images_plane(A), images_wall_floor(A, 0.07)], ids=["plane", "corner"]
)
def test_mirror_symmetry_of_pressure(cfg, paper_pulse):
    pulse = paper_pulse()
    t = np.linspace(0, 3e-3, 120)
    for plane in cfg.planes:
        pts = RNG.uniform([-0.05, -0.5, 0.0], [0.6, 0.5, 0.6], (200, 3))
        pts = pts[cfg.in_fluid(pts) & (np.linalg.norm(pts - cfg.centre, axis=1) > 2 * A)][:60]
        img = mirror_point(pts, plane)
        p, pm = _field(pulse, t, pts, cfg), _field(pulse, t, img, cfg)
        np.testing.assert_allclose(pm, p, rtol=0, atol=1e-12 * np.max(np.abs(p)))


def test_image_source_validation():
    with pytest.raises(ParameterError):
        ImageSource([0, 0, 0], [0, 0, 0])


@pytest.mark.parametrize("conf", [
    geometry("plane", 0.01905),
    geometry("wall-floor", 0.01905, wall_distance=0.05),
    geometry("wall-floor", 0.01905, strike="wall", height=0.3),
])
def test_observer_points_keep_distance_and_angle(conf):
    from acoustiviz.core.geometry import observer_points

    angles = np.radians([0.0, 30.0, 60.0, 90.0])
    pts = observer_points(conf, 0.7, angles)
    rel = pts - conf.centre
    dist = np.linalg.norm(rel, axis=1)
    np.testing.assert_allclose(dist, 0.7, rtol=1e-13)  # sin, cos and a norm: a few roundings
    np.testing.assert_allclose(np.arccos(np.clip(rel @ conf.axis / dist, -1, 1)), angles, atol=1e-12)
    assert np.all(pts[:, 1] == 0)  # in the plane y = 0, normal to the wall
    assert np.all(conf.in_fluid(pts))  # on the side away from the wall and above the floor
