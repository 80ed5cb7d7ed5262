"""The shoebox room as a geometry value, through the field evaluator, checked against independent references.

References: today's wall-floor corner geometry (the room's four corner images are its sources),
the free field (a room larger than any arrival in the window), the symmetry of the field about each
rigid wall (zero normal particle velocity), and the closed-form room images of
:mod:`acoustiviz.core.room` (themselves checked against pyroomacoustics in ``tests/test_room.py``).
"""

import math

import numpy as np
import pytest

from acoustiviz.core.geometry import GEOMETRIES, FreeField, WallFloorCorner, geometry
from acoustiviz.core.medium import AIR
from acoustiviz.core.reverberation import energy_order, order_for_time
from acoustiviz.core.room import Shoebox, image_count, image_sources
from acoustiviz.core.room_geometry import Room
from acoustiviz.errors import ParameterError
from acoustiviz.field import time_series

A = 0.01905  # the paper's sphere, m


def test_room_is_registered_and_built_by_name():
    g = geometry("room", A, dimensions="6,4,3", absorption="0.1", source="2,1.5,0.01905", duration=0.05)
    assert GEOMETRIES["room"] is Room and isinstance(g, Room)
    assert g.dimensions == (6.0, 4.0, 3.0) and g.absorption == (0.1,) and g.source == (2.0, 1.5, A)
    # the order is the time rule's (every image that can arrive in 50 ms), its images the closed-form count
    assert g.image_order == order_for_time(Shoebox((6, 4, 3), 0.1), 0.05, radius=A, medium=AIR)
    assert g.image_count == image_count(g.image_order) == len(g.images())
    assert g.neglected_energy_db == -math.inf
    # without a window: the energy rule at the stated tolerance
    h = geometry("room", A, dimensions=(6, 4, 3), absorption=0.3, tolerance_db=-30.0)
    ref = energy_order(Shoebox((6, 4, 3), 0.3), -30.0, radius=A, max_order=10**6)
    assert (h.image_order, h.image_count) == (ref.order, ref.images)
    assert h.neglected_energy_db <= -30.0
    s = h.settings()
    assert {"image_order", "images", "neglected_energy_db"} <= set(s)


def test_room_images_are_the_closed_form_images():
    g = Room(A, (5.0, 4.0, 3.0), (0.1, 0.2, 0.3, 0.4, 0.5, 0.6), (1.0, 2.0, A), order=3)
    im = image_sources(Shoebox((5, 4, 3), (0.1, 0.2, 0.3, 0.4, 0.5, 0.6)), (1.0, 2.0, A), 3, radius=A)
    s = g.images()
    np.testing.assert_array_equal(s.positions, im.positions)
    np.testing.assert_array_equal(s.axes, im.directions)
    np.testing.assert_array_equal(s.weights, im.weights)
    np.testing.assert_array_equal(s.orders, im.orders)
    assert s.orders[0] == 0 and np.array_equal(s.axes[0], [0, 0, 1])


@pytest.mark.parametrize("settings, name, words", [
    ({"dimensions": (-6, 4, 3), "absorption": 0.1}, "dimensions", "> 0"),
    ({"dimensions": (6, 4, 3), "absorption": 1.0}, "absorption", "[0, 1)"),
    ({"dimensions": (6, 4, 3), "absorption": (0.1, 0.1, 0.1, 0.1, 0.1, -0.2)}, "absorption", "z1"),
    ({"dimensions": (6, 4, 3), "absorption": (0.1, 0.2)}, "absorption", "six"),
    ({"dimensions": (6, 4, 3), "absorption": 0.1, "source": (7, 1, 1)}, "source", "[0.01905, 5.98095]"),
    ({"dimensions": (6, 4, 3), "absorption": 0.1, "source": (2, 1, 0.01)}, "source", "inside the room"),
    ({"dimensions": (6, 4, 3)}, "duration", "rigid"),
    ({"absorption": 0.1}, "dimensions", "required"),
    ({"dimensions": (6, 4, 3), "absorption": 0.1, "strike": "wall"}, "strike", "x0"),
])
def test_bad_room_settings_are_refused_naming_the_setting(settings, name, words):
    with pytest.raises(ParameterError) as err:
        geometry("room", A, **settings)
    assert err.value.name == name and words in str(err.value) and "\n" not in str(err.value)


def test_listener_region_is_inside_the_room_outside_the_sphere():
    g = Room(A, (6.0, 4.0, 3.0), 0.1, (2.0, 1.5, A))
    ok = g.in_fluid([[3, 2, 1.5], [2, 1.5, A + 0.5 * A], [6.1, 2, 1], [3, 2, -0.01], [0, 0, 0]])
    assert ok.tolist() == [True, False, False, False, True]
    with pytest.raises(ParameterError, match="inside the sphere"):
        g.in_room("--listener", [[2, 1.5, 1.5 * A]])
    with pytest.raises(ParameterError, match="outside the room"):
        g.in_room("--listener", [[3, 5, 1]])


def test_rigid_room_equals_the_wall_floor_corner_until_the_third_image_arrives(paper_pulse):
    """Through the geometry value and the field evaluator: the corner's four sources, nothing else, until
    the first room image beyond them (the third surface's) can arrive."""
    wall = 0.05
    corner = WallFloorCorner(A, wall)
    dims = (4.0, 5.0, 3.5)
    shift = np.array([wall, 2.2, 0.0])  # the corner's wall x = -wall is the room's x0, its floor the room's
    room = Room(A, dims, 0.0, tuple(shift + corner.centre), duration=0.03)
    pulse = paper_pulse()
    rng = np.random.default_rng(25)
    pts = np.column_stack([rng.uniform(0.3, 1.2, 6), rng.uniform(-0.8, 0.8, 6), rng.uniform(0.1, 0.9, 6)])
    t = np.arange(0.0, 0.03, pulse.duration / 200)
    p_room = time_series(pulse, t, pts + shift, room)
    p_corner = time_series(pulse, t, pts, corner)
    srcs = room.images()
    extra = ~np.isin(np.arange(len(srcs)), _corner_rows(srcs.positions, shift + np.array(
        [s.position for s in corner.sources])))
    for i, pt in enumerate(pts + shift):
        first = (np.linalg.norm(srcs.positions[extra] - pt, axis=1).min() - A) / AIR.c
        before = t < first
        scale = np.abs(p_corner[i]).max()
        assert before.sum() > 100
        np.testing.assert_allclose(p_room[i, before], p_corner[i, before], rtol=0, atol=1e-12 * scale)
        assert np.abs(p_room[i, ~before] - p_corner[i, ~before]).max() > 1e-6 * scale  # and then differs


def _corner_rows(positions, corner_positions):
    rows = [int(np.argmin(np.linalg.norm(positions - c, axis=1))) for c in corner_positions]
    for r, c in zip(rows, corner_positions, strict=True):
        assert np.linalg.norm(positions[r] - c) < 1e-12
    return rows


def test_a_room_larger_than_every_arrival_in_the_window_is_the_free_field(paper_pulse):
    pulse = paper_pulse()
    window = 0.006
    room = Room(A, (40.0, 30.0, 20.0), 0.2, (20.0, 15.0, 10.0), strike="floor", duration=window)
    assert room.image_count > 1  # the images are there, they just cannot arrive in time
    free = FreeField(A)
    shift = np.array(room.source) - free.centre
    pts = np.array([[0.4, 0.1, 0.3], [-0.5, 0.2, -0.6], [0.0, 0.9, 0.05], [0.3, -0.3, 0.0]])
    t = np.arange(0.0, window, pulse.duration / 300)
    p_room = time_series(pulse, t, pts + shift, room)
    p_free = time_series(pulse, t, pts, free)
    nearest = (np.linalg.norm(room.images().positions[1:][:, None] - (pts + shift)[None], axis=-1).min() - A)
    assert nearest / AIR.c > window
    assert np.abs(p_free).max() > 0.01
    # the same sum of one source: equal but for the round-off of coordinates 20 m from the origin
    np.testing.assert_allclose(p_room, p_free, rtol=0, atol=1e-12 * np.abs(p_free).max())


@pytest.mark.parametrize("wall", range(6))
def test_normal_particle_velocity_vanishes_on_each_rigid_wall(wall, paper_pulse):
    """One-sided second-order differences of p normal to each rigid wall at 8 points vanish (p is even there),
    while the same difference of the direct sound alone does not."""
    dims = np.array([3.0, 2.5, 2.0])
    room = Room(A, tuple(dims), 0.0, (1.1, 0.9, 0.7), strike="x1", duration=0.012)
    pulse = paper_pulse()
    rng = np.random.default_rng(100 + wall)
    ax, far = wall // 2, wall % 2
    pts = rng.uniform(0.2, 1.0, (8, 3)) * dims
    pts[:, ax] = dims[ax] if far else 0.0
    n = np.zeros(3)
    n[ax] = -1.0 if far else 1.0  # into the room
    h = 2e-5
    t = np.arange(0.0, 0.012, pulse.duration / 100)
    p = [time_series(pulse, t, pts + k * h * n, room) for k in range(3)]
    dpdn = (-3 * p[0] + 4 * p[1] - p[2]) / (2 * h)
    direct = Room(A, tuple(dims), 0.0, (1.1, 0.9, 0.7), strike="x1", order=0)
    q = [time_series(pulse, t, pts + k * h * n, direct) for k in range(3)]
    dqdn = (-3 * q[0] + 4 * q[1] - q[2]) / (2 * h)
    assert np.abs(dqdn).max() > 1.0  # Pa/m: the direct sound alone has a normal gradient
    # the stencil's own error is O(h^2 p''') (1e-5 to 3e-4 of the direct gradient here, falling as h^2);
    # an image with the wrong axis or weight leaves an O(1) gradient
    assert np.abs(dpdn).max() < 1e-3 * np.abs(dqdn).max()


def test_room_exposure_over_near_pairs_equals_every_pair(monkeypatch, paper_pulse):
    """Past 64 images the exposure sorts the arrivals and sums the pairs further apart than the pulse
    as one running sum of damped exponentials: the all-pairs sum agrees to 1e-12, both reading the
    same table of the correlations (the half-sine's closed-form close pairs, which need no table,
    are checked against an exact pair sum in tests/test_room_peaks.py)."""
    import dataclasses
    import sys

    import acoustiviz.field  # noqa: F401 - the module, not the function of the same name

    ex = sys.modules["acoustiviz.field.exposure"]
    room = Room(A, (6.0, 4.0, 3.0), 0.1, (2.0, 1.5, A), order=6)
    pts = np.random.default_rng(7).uniform(0.05, 1.0, (12, 3)) * np.array([6.0, 4.0, 3.0])
    corr = ex.pulse_correlations(paper_pulse(), A)
    tabled = dataclasses.replace(corr, lag_terms=np.zeros(0, complex))  # the close pairs from the table
    near = ex.exposure(paper_pulse(), pts, room, correlations=tabled)
    monkeypatch.setattr(ex, "PAIRS_ABOVE", 10**9)
    every = ex.exposure(paper_pulse(), pts, room, correlations=tabled)
    np.testing.assert_allclose(near, every, rtol=1e-12)


def test_wav_trains_equal_the_closed_form_render(monkeypatch):
    """The renderer's fractional-delay trains (past TRAIN_ABOVE sources) against its closed form per source:
    the same band-limited signal to 1e-4 of its peak (the windowed-sinc interpolator's accuracy)."""
    import sys

    import acoustiviz.sound  # noqa: F401
    from acoustiviz.sound import CavityScene, ClickModel, ImpactSequence, render

    syn = sys.modules["acoustiviz.sound.synthesis"]
    room = Room(A, (6.0, 4.0, 3.0), 0.1, (2.0, 1.5, A), order=3)
    scene = CavityScene(room, gap=0.04)
    seq = ImpactSequence([0.001, 0.0123], [-1, 1], [1.4, 0.8])
    monkeypatch.setattr(syn, "TRAIN_ABOVE", 10**9)
    exact = render(seq, scene, ClickModel(), [3.0, 2.0, 1.5]).pressure[0]
    monkeypatch.setattr(syn, "TRAIN_ABOVE", 8)
    trains = render(seq, scene, ClickModel(), [3.0, 2.0, 1.5]).pressure[0]
    assert trains.shape == exact.shape
    np.testing.assert_allclose(trains, exact, rtol=0, atol=1e-4 * np.abs(exact).max())
