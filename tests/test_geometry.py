"""Geometry values: the registry, the front-ends' settings rule, image sets, regions and views."""

import numpy as np
import pytest

from acoustiviz.constants import DEFAULT_WALL_DISTANCE
from acoustiviz.core.geometry import (
    CONFIGURATIONS,
    GEOMETRIES,
    Configuration,
    FreeField,
    ReflectingPlane,
    WallFloorCorner,
    geometry,
)
from acoustiviz.core.images import ImageSet, ImageSource, Plane, images_of
from acoustiviz.errors import ParameterError

A = 0.01905


def test_registry_names_its_classes():
    assert CONFIGURATIONS == ("free", "plane", "wall-floor")
    assert tuple(GEOMETRIES) == (*CONFIGURATIONS, "room")  # the room needs its dimensions: not a --config choice
    assert all(cls.name == name for name, cls in GEOMETRIES.items())
    assert [type(geometry(n, A)) for n in CONFIGURATIONS] == [FreeField, ReflectingPlane, WallFloorCorner]


def test_front_end_defaults():
    corner = geometry("wall-floor", A)
    assert corner.wall_distance == DEFAULT_WALL_DISTANCE and corner.strike == "floor" and corner.height is None
    wall = geometry("wall-floor", A, strike="wall")
    assert (wall.wall_distance, wall.height) == (A, A)
    np.testing.assert_array_equal(wall.contact_point, [-A, 0.0, A])


@pytest.mark.parametrize("name, settings, bad", [
    ("plane", {"wall_distance": 0.1}, "wall_distance"),
    ("free", {"strike": "wall"}, "strike"),
    ("plane", {"height": 0.1}, "height"),
    ("wall-floor", {"height": 0.1}, "height"),
    ("wall-floor", {"strike": "wall", "wall_distance": 0.1}, "wall_distance"),
    ("wall-floor", {"wall_distance": 0.5 * A}, "wall_distance"),
    ("wall-floor", {"strike": "wall", "height": 0.5 * A}, "height"),
    ("wall-floor", {"strike": "roof"}, "strike"),
    ("room", {}, "dimensions"),  # a room needs its dimensions
    ("plane", {"dimensions": (6, 4, 3)}, "dimensions"),
    ("roof", {}, "config"),
    ("plane", {"colour": "red"}, "colour"),
])
def test_settings_that_do_not_apply_are_refused(name, settings, bad):
    with pytest.raises(ParameterError) as err:
        geometry(name, A, **settings)
    assert err.value.name == bad


def test_lenient_keeps_only_what_applies():
    table = {"wall_distance": 0.2, "strike": "floor", "height": 0.3}
    assert geometry("plane", A, lenient=True, **table) == ReflectingPlane(A)
    assert geometry("wall-floor", A, lenient=True, **table) == WallFloorCorner(A, 0.2)
    wall = geometry("wall-floor", A, lenient=True, **{**table, "strike": "wall"})
    assert (wall.wall_distance, wall.strike, wall.height) == (A, "wall", 0.3)


def test_geometry_builds_by_name_and_ignores_others_settings_when_lenient():
    assert geometry("wall-floor", A, wall_distance=0.07) == WallFloorCorner(A, 0.07)
    assert geometry("plane", A, lenient=True, wall_distance=0.07) == ReflectingPlane(A)  # others' settings ignored


@pytest.mark.parametrize("g", [FreeField(A), ReflectingPlane(A), WallFloorCorner(A, 0.05),
                               WallFloorCorner(A, strike="wall", height=0.04)], ids=["free", "plane", "corner", "wall"])
def test_image_set_is_the_sources_as_arrays(g):
    imgs = g.images()
    assert isinstance(imgs, ImageSet) and len(imgs) == len(g.sources) == 2 ** len(g.planes)
    np.testing.assert_array_equal(imgs.positions, [s.position for s in g.sources])
    np.testing.assert_array_equal(imgs.axes, [s.axis for s in g.sources])
    np.testing.assert_array_equal(imgs.orders, [s.order for s in g.sources])
    np.testing.assert_array_equal(imgs.weighted_axes, imgs.axes)  # rigid planes: weight 1
    assert imgs.labels[0] == "real" and imgs.orders[0] == 0
    back = imgs.sources()
    np.testing.assert_array_equal([s.position for s in back], imgs.positions)


def test_reflection_weights_multiply_along_the_path():
    floor = Plane([0, 0, 0], [0, 0, 1], "floor", reflection=0.5)
    wall = Plane([-0.1, 0, 0], [1, 0, 0], "wall", reflection=-0.25)
    srcs = images_of(ImageSource([0, 0, A], [0, 0, 1]), (floor, wall))
    assert [s.weight for s in srcs] == [1.0, 0.5, -0.25, -0.125]
    imgs = ImageSet.of(srcs)
    np.testing.assert_array_equal(imgs.weighted_axes[:, 2], [1.0, -0.5, -0.25, 0.125])
    with pytest.raises(ParameterError):
        Plane([0, 0, 0], [0, 0, 1], reflection=1.5)


def test_enclosure_anchors_on_the_surfaces_nearest_the_sphere():
    assert FreeField(A).enclosure().kind == "sphere"
    np.testing.assert_array_equal(FreeField(A).enclosure().origin, [0, 0, A])
    half = ReflectingPlane(A).enclosure()
    assert half.kind == "half"
    np.testing.assert_array_equal(half.origin, [0.0, 0.0, 0.0])
    for g in (WallFloorCorner(A, 0.08), WallFloorCorner(A, strike="wall", height=0.3)):
        q = g.enclosure()
        assert q.kind == "quarter"
        assert all(abs(float((q.origin - p.point) @ p.normal)) == 0.0 for p in g.planes)  # on the edge
        edge = q.origin + np.linspace(-1, 1, 2001)[:, None] * np.array([0.0, 1.0, 0.0])
        assert np.argmin(np.linalg.norm(edge - g.centre, axis=1)) == 1000  # the edge's point nearest the centre


def test_views_and_limits():
    assert (FreeField(A).polar_limit_deg, ReflectingPlane(A).polar_limit_deg) == (180.0, 90.0)
    assert (FreeField(A).floor_height, ReflectingPlane(A).floor_height) == (None, 0.0)
    assert WallFloorCorner(A, 0.06).feature_distance == 0.06 and ReflectingPlane(A).feature_distance == 0.0
    assert WallFloorCorner(A, 0.06).caption() == "wall-floor, wall at 60 mm"
    assert WallFloorCorner(A, 0.06).caption(long=True) == "wall-floor (wall 60 mm from the centre)"
    assert FreeField(A).caption() == "free" and FreeField(A).settings() == {}
    assert WallFloorCorner(A, strike="wall").settings() == {"wall_distance_m": A, "strike": "wall", "height_m": A}
    v = WallFloorCorner(A, strike="wall", height=0.1).view_region()
    assert v.kind == "quarter"
    np.testing.assert_array_equal(v.origin, [-A, 0, 0.1])
    d = ReflectingPlane(A).sphere_distance([[0, 0, 1.0 + A], [0, 0, A]])
    np.testing.assert_allclose(d, [1.0 - A, -A])


def test_with_sources_keeps_the_surfaces():
    g = WallFloorCorner(A, 0.05)
    far = ImageSource([0, 0, 0.1], [0, 0, -1], 0, "far")
    moved = g.with_sources(g.image_sources(far))
    assert isinstance(moved, Configuration) and moved.planes == g.planes and moved.name == "wall-floor"
    np.testing.assert_allclose(moved.sources[1].position, [0, 0, -0.1])
    np.testing.assert_allclose(moved.sources[2].position, [-0.1, 0, 0.1])
    with pytest.raises(ParameterError):
        Configuration("x", A, (moved.sources[1],))  # the real sphere must come first


# --------------------------------------------------------------------------- the design test
# A geometry the package does not ship, defined here as a new geometry would be: one class and one
# registry entry. The field evaluator, the fast peak kernel and the auralisation take it unchanged.
from dataclasses import dataclass  # noqa: E402
from functools import cached_property  # noqa: E402
from typing import ClassVar  # noqa: E402

from acoustiviz.core.geometry import Geometry  # noqa: E402
from acoustiviz.core.images import mirror_point, mirror_vector  # noqa: E402


@dataclass(frozen=True)
class _RoomCorner(Geometry):
    """Floor z = 0 and walls x = -wx, y = -wy: three perpendicular planes, 7 images (exact)."""

    radius: float
    wx: float = 0.05
    wy: float = 0.08
    floor_reflection: float = 1.0

    name: ClassVar[str] = "room-corner"

    @cached_property
    def planes(self):
        return (Plane([0, 0, 0], [0, 0, 1], "floor", self.floor_reflection), Plane([-self.wx, 0, 0], [1, 0, 0], "wall"),
                Plane([0, -self.wy, 0], [0, 1, 0], "side"))

    @cached_property
    def real(self):
        return ImageSource([0.0, 0.0, self.radius], [0, 0, 1], 0, "real")

    def image_sources(self, real):
        out = [real]
        for mask in range(1, 8):
            used = [p for i, p in enumerate(self.planes) if mask >> i & 1]
            pos, ax, w = real.position, real.axis, real.weight
            for p in used:
                pos, ax, w = mirror_point(pos, p), mirror_vector(ax, p), w * p.reflection
            out.append(ImageSource(pos, ax, len(used), "+".join(p.label for p in used), w))
        return tuple(out)


def test_a_new_geometry_is_one_class_and_one_registry_entry(monkeypatch):
    monkeypatch.setitem(GEOMETRIES, "room-corner", _RoomCorner)
    g = geometry("room-corner", A)
    assert isinstance(g, _RoomCorner) and len(g.images()) == 8 and sorted(g.images().orders) == [0, 1, 1, 1, 2, 2, 2, 3]
    with pytest.raises(ParameterError):
        geometry("room-corner", A, wall_distance=0.1)  # settings it does not take are refused


def test_field_of_a_new_geometry_meets_every_rigid_plane(paper_pulse):
    """∂p/∂n = 0 on the floor and both walls (finite differences of the evaluator's pressure).

    The stencil straddles the kinks of the pulse's start and end where the images' wavefronts meet
    the plane at an angle, so the bound is 1e-5 of the free field's gradient (the shipped corner gives
    1e-9 on its wall with the same stencil); an image of the wrong sign breaks it by orders of magnitude.
    """
    from acoustiviz import field

    g = _RoomCorner(A)
    pulse = paper_pulse("hertz")
    t = np.linspace(0.0, 2e-3, 400)
    rng = np.random.default_rng(5)
    wrong = _RoomCorner(A, floor_reflection=-1.0)  # the floor's images with the wrong sign
    h = 1e-5
    for pl in g.planes:
        u = np.cross(pl.normal, [0.3, 0.5, 0.7])
        u /= np.linalg.norm(u)
        v = np.cross(pl.normal, u)
        pts = pl.point + 0.3 * (rng.uniform(-1, 1, (400, 1)) * u + rng.uniform(-1, 1, (400, 1)) * v)
        pts = pts[g.in_fluid(pts) & (g.sphere_distance(pts) > 3 * A)][:12]
        assert len(pts) >= 6

        def grad(conf, pts=pts, pl=pl):  # one-sided, 4th order: points below the plane are not in the fluid
            p = [field.time_series(pulse, t, pts + k * h * pl.normal, conf) for k in range(5)]
            return (-25.0 * p[0] + 48.0 * p[1] - 36.0 * p[2] + 16.0 * p[3] - 3.0 * p[4]) / (12.0 * h)

        dp, free = grad(g), grad(FreeField(A))
        assert np.max(np.abs(dp)) <= 1e-5 * np.max(np.abs(free))
        if pl.label == "floor":  # (the walls stay symmetric: each pair of images across them has one weight)
            assert np.max(np.abs(grad(wrong))) > 1e-2 * np.max(np.abs(free))


def test_reflection_weights_reach_the_field_and_the_peak_kernel(paper_pulse):
    """An absorbing floor (pressure reflection 0.5): the evaluator equals the weighted sum of spheres."""
    from acoustiviz import field
    from acoustiviz.core.radiation import sphere_pressure

    g = _RoomCorner(A, floor_reflection=0.5)
    assert sorted(np.round(g.images().weights, 12)) == [0.5] * 4 + [1.0] * 4
    pulse = paper_pulse("hertz")
    rng = np.random.default_rng(11)
    pts = rng.uniform([-0.04, -0.07, 0.0], [0.5, 0.5, 0.5], (40, 3))
    pts = pts[g.in_fluid(pts) & (g.sphere_distance(pts) > 2 * A)]
    t = np.linspace(0.0, 3e-3, 600)
    ref = sum(s.weight * sphere_pressure(pulse, t, pts, radius=A, centre=s.position, axis=s.axis) for s in g.sources)
    got = field.time_series(pulse, t, pts, g)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-8 * np.max(np.abs(ref)))
    rigid = field.time_series(pulse, t, pts, _RoomCorner(A))
    assert np.max(np.abs(rigid - got)) > 0.05 * np.max(np.abs(ref))  # the weight matters at these points
    fp, fm = field.fast_peaks(pulse, pts, g), field.field_metrics(pulse, pts, g)
    np.testing.assert_allclose(fp.peak_positive, fm.peak_positive, rtol=1e-7)
    np.testing.assert_allclose(fp.peak_negative, fm.peak_negative, rtol=1e-7)
    np.testing.assert_allclose(fp.exposure, fm.exposure, rtol=1e-6)


def test_auralisation_images_the_far_wall_in_a_new_geometry():
    from acoustiviz.sound import CavityScene, wall_sources

    g = _RoomCorner(A, floor_reflection=0.5)
    far = wall_sources(CavityScene(g, gap=0.04), +1)
    assert len(far) == 8 and far[0].label == "far"
    np.testing.assert_allclose(far[0].position, [0, 0, A + 0.04])
    for s_far, s_near in zip(far, g.sources, strict=True):  # mirrored like the struck sphere's images
        assert (s_far.order, s_far.weight) == (s_near.order, s_near.weight)
        np.testing.assert_allclose(s_far.axis, -s_near.axis)


def test_registry_names_match_the_constants():
    # the --config choices and the room's surfaces are facts the light parsers read from constants;
    # the registry's classes and the room's per-surface arrays must agree with them
    from acoustiviz import constants
    from acoustiviz.core.geometry import GEOMETRIES
    from acoustiviz.core.room import SURFACES
    from acoustiviz.core.room_geometry import Room

    assert constants.CONFIGURATIONS == tuple(n for n, c in GEOMETRIES.items() if not c.REQUIRED)
    assert GEOMETRIES[Room.name] is Room and Room.REQUIRED
    assert SURFACES == constants.ROOM_SURFACES
    assert set(constants.ROOM_STRIKES) == {"floor", "ceiling", *SURFACES}


def test_the_package_exports_every_name_lazily():
    import acoustiviz

    for name in acoustiviz.__all__:
        assert getattr(acoustiviz, name) is not None, name
    assert sorted(acoustiviz.__all__) == dir(acoustiviz)
