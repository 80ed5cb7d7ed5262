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
    configuration,
    geometry,
)
from acoustiviz.core.images import ImageSet, ImageSource, Plane, images_of
from acoustiviz.errors import ParameterError

A = 0.01905


def test_registry_names_its_classes():
    assert CONFIGURATIONS == ("free", "plane", "wall-floor")
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
    ("room", {}, "config"),
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


def test_configuration_is_the_explicit_constructor():
    assert configuration("wall-floor", A, wall_distance=0.07) == WallFloorCorner(A, 0.07)
    assert configuration("plane", A, wall_distance=0.07) == ReflectingPlane(A)  # others' settings ignored


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
