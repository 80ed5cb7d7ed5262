"""Shoebox room: image lattice, order rules and reverberation, checked against independent references.

References used here: pyroomacoustics' ShoeBox image-source model (a separate implementation, in
float32); brute-force enumeration of the lattice; the mirror symmetry of the pressure field
about each rigid wall computed with the free-field sphere model of :mod:`acoustiviz.core.radiation`;
today's wall-floor corner of :mod:`acoustiviz.core.images`; Sabine's and Eyring's formulas and a
direction-averaged decay for the Schroeder curves.
"""

import math
import tracemalloc

import numpy as np
import pytest

from acoustiviz.core.contact import Impact, acceleration_pulse
from acoustiviz.core.images import images_wall_floor
from acoustiviz.core.medium import AIR, Medium
from acoustiviz.core.radiation import pressure
from acoustiviz.core.room import (
    SURFACES,
    Shoebox,
    echo_density_time,
    energy_order,
    image_count,
    image_energy_decay,
    image_sources,
    max_order_for_memory,
    mixing_time,
    order_for_time,
    reverberation_time,
)
from acoustiviz.errors import ParameterError

A = 0.01905  # the paper's sphere, m
#: pyroomacoustics computes its images and damping in float32
F32 = float(np.finfo(np.float32).eps)
#: mirrored samples of a symmetric field agree to round-off relative to the field's largest value
SYM_RTOL = 1e-11
#: the rigid room and today's corner agree before any further image arrives
CORNER_RTOL = 1e-12

PRA_WALLS = ("west", "east", "south", "north", "floor", "ceiling")  # x0, x1, y0, y1, z0, z1


def _pulse(kind="half-sine"):
    mass = 7800 * 4 / 3 * np.pi * A**3
    return acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=mass), kind)


def _room_pressure(pulse, t, pts, im, medium=AIR, chunk=128):
    """Summed pressure (n_pts, n_t) in Pa of the images (rigid: weights 1 unless given)."""
    out = np.zeros((pts.shape[0], t.size))
    w = im.weights if im.weights.ndim == 1 else im.weights[:, 0]
    for lo in range(0, len(im), chunk):
        pos, ax, ww = im.positions[lo:lo + chunk], im.directions[lo:lo + chunk], w[lo:lo + chunk]
        d = pts[None, :, :] - pos[:, None, :]  # (i, p, 3)
        r = np.linalg.norm(d, axis=2)
        ct = np.einsum("ipk,ik->ip", d, ax) / r
        p = pressure(pulse, t[None, None, :], r[..., None], ct[..., None], radius=A, medium=medium)
        out += np.einsum("i,ipt->pt", ww, p)
    return out


# ------------------------------------------------------------------------------- the lattice
@pytest.mark.parametrize("order", [0, 1, 2, 3, 7, 12])
def test_image_count_formula_and_brute_force_lattice(order):
    room = Shoebox((3.0, 2.0, 1.5), 0.2)
    im = image_sources(room, (1.0, 0.7, A), order, radius=A)
    assert len(im) == image_count(order) == (4 * order**3 + 6 * order**2 + 8 * order + 3) // 3
    k = np.indices((2 * order + 1,) * 3).reshape(3, -1).T - order
    brute = k[np.abs(k).sum(axis=1) <= order]
    assert {tuple(r) for r in im.lattice.tolist()} == {tuple(r) for r in brute.tolist()}
    assert np.all(np.diff(im.orders) >= 0) and im.orders[0] == 0
    np.testing.assert_array_equal(im.orders, np.abs(im.lattice).sum(axis=1))
    np.testing.assert_array_equal(im.reflections.sum(axis=1), im.orders)
    # the images are distinct points (no duplicates to search for)
    assert np.unique(np.round(im.positions, 9), axis=0).shape[0] == len(im)


def _pra_images(dims, alpha, centre, order, bands=None):
    pra = pytest.importorskip("pyroomacoustics")
    if bands is None:
        mats = {w: pra.Material(float(a)) for w, a in zip(PRA_WALLS, alpha, strict=True)}
    else:
        mats = {w: pra.Material({"description": w, "coeffs": list(map(float, a)), "center_freqs": list(bands)})
                for w, a in zip(PRA_WALLS, alpha, strict=True)}
    room = pra.ShoeBox(list(dims), fs=16000, materials=mats, max_order=order, air_absorption=False)
    room.add_source(list(centre))
    room.add_microphone([d / 2 for d in dims])
    room.image_source_model()
    s = room.sources[0]
    return (s.images.T.astype(float), s.damping.T.astype(float), s.orders.astype(int),
            s.orders_xyz.T.astype(int), room)


def _sorted(*cols):
    m = np.column_stack(cols)
    return m[np.lexsort(np.round(m[:, :3], 4).T[::-1])]


@pytest.mark.parametrize("alpha", [0.1, (0.1, 0.2, 0.3, 0.05, 0.15, 0.25), (0.0, 0.9, 0.5, 0.0, 0.7, 0.35)],
                         ids=["uniform", "six", "rigid-and-soft"])
def test_images_equal_pyroomacoustics(alpha):
    dims, centre, order = (6.0, 4.0, 3.0), (2.0, 1.5, A), 9
    room = Shoebox(dims, alpha)
    ours = image_sources(room, centre, order, radius=A)
    pos, damp, orders, lattice, _ = _pra_images(dims, room.absorption, centre, order)
    assert len(orders) == len(ours)
    a = _sorted(ours.positions, ours.weights, ours.orders, ours.lattice)
    b = _sorted(pos, damp[:, 0], orders, lattice)
    scale = np.abs(b[:, :3]).max()
    np.testing.assert_allclose(a[:, :3], b[:, :3], rtol=0, atol=4 * F32 * scale)
    np.testing.assert_allclose(a[:, 3], b[:, 3], rtol=4 * F32 * order, atol=0)
    np.testing.assert_array_equal(a[:, 4:], b[:, 4:])  # orders and lattice indices


def test_banded_weights_equal_pyroomacoustics():
    dims, centre, order = (5.0, 3.5, 2.8), (1.1, 2.0, 1.0), 6
    pra = pytest.importorskip("pyroomacoustics")
    probe = pra.ShoeBox(list(dims), fs=16000, max_order=1)
    bands = probe.octave_bands.centers
    nb = len(bands)
    rng = np.random.default_rng(7)
    alpha = rng.uniform(0.02, 0.6, (6, nb))
    room = Shoebox(dims, alpha)
    ours = image_sources(room, centre, order, radius=A, direction=(0.3, -0.4, 0.5))
    assert ours.weights.shape == (len(ours), nb)
    pos, damp, orders, _, _ = _pra_images(dims, alpha, centre, order, bands=bands)
    a = _sorted(ours.positions, ours.weights)
    b = _sorted(pos, damp)
    np.testing.assert_allclose(a[:, :3], b[:, :3], rtol=0, atol=4 * F32 * np.abs(b[:, :3]).max())
    np.testing.assert_allclose(a[:, 3:], b[:, 3:], rtol=4 * F32 * order, atol=0)


def test_directions_flip_with_odd_reflections():
    room = Shoebox((4.0, 3.0, 2.5), 0.3)
    u = np.array([0.2, -0.5, 0.8])
    im = image_sources(room, (1.0, 1.2, 0.9), 5, radius=A, direction=u)
    sign = np.where(im.lattice % 2 == 0, 1.0, -1.0)
    np.testing.assert_allclose(im.directions, sign * u / np.linalg.norm(u), rtol=0, atol=1e-15)
    # named strikes give the inward normal of the struck surface
    for i, name in enumerate(SURFACES):
        d = image_sources(room, (1.0, 1.2, 0.9), 0, radius=A, direction=name).directions[0]
        expect = np.zeros(3)
        expect[i // 2] = 1.0 if i % 2 == 0 else -1.0
        np.testing.assert_array_equal(d, expect)


@pytest.mark.parametrize("wall", range(6), ids=SURFACES)
def test_images_pair_up_as_mirrors_across_each_wall(wall):
    """Each image's mirror across a wall plane is an image with the mirrored direction, one reflection away."""
    dims = np.array([4.0, 3.0, 2.5])
    room = Shoebox(dims, (0.1, 0.2, 0.3, 0.4, 0.5, 0.6))
    order = 8
    im = image_sources(room, (1.0, 1.2, A), order, radius=A, direction=(0.2, 0.3, 0.9))
    axis = wall // 2
    plane = 0.0 if wall % 2 == 0 else dims[axis]
    mirrored = im.positions.copy()
    mirrored[:, axis] = 2 * plane - mirrored[:, axis]
    index = {tuple(np.round(p, 9)): i for i, p in enumerate(im.positions)}
    beta = room.reflection[wall]
    paired = 0
    for i in range(len(im)):
        j = index.get(tuple(np.round(mirrored[i], 9)))
        if j is None:
            assert im.orders[i] == order  # only the outermost shell may lack its partner (order N + 1)
            continue
        paired += 1
        assert abs(im.orders[j] - im.orders[i]) == 1
        d = im.directions[i].copy()
        d[axis] = -d[axis]
        np.testing.assert_array_equal(im.directions[j], d)
        # the member of the pair beyond the wall carries one more reflection in it
        beyond_j = (im.positions[j, axis] < plane) if wall % 2 == 0 else (im.positions[j, axis] > plane)
        ratio = im.weights[j] / im.weights[i]
        assert ratio == pytest.approx(beta if beyond_j else 1.0 / beta, rel=1e-13)
    assert paired >= image_count(order - 1)


# ------------------------------------------------------------------------------- pressure fields
def _wall_points(dims, wall, n=8):
    """n points on a wall face, on a grid away from its edges."""
    axis = wall // 2
    others = [i for i in range(3) if i != axis]
    u = np.array([0.2, 0.45, 0.7, 0.85, 0.3, 0.6, 0.15, 0.8])[:n]
    v = np.array([0.3, 0.8, 0.25, 0.6, 0.55, 0.15, 0.7, 0.9])[:n]
    pts = np.zeros((n, 3))
    pts[:, axis] = 0.0 if wall % 2 == 0 else dims[axis]
    pts[:, others[0]] = u * dims[others[0]]
    pts[:, others[1]] = v * dims[others[1]]
    return pts


def _normal_derivative_check(im, dims, order, pulse, h):
    """Max over walls of |p(x_w + h n) - p(x_w - h n)| / max|p| before any image of order > N arrives."""
    room_h = Shoebox(dims)
    # an image of order > N is at least (N - 2) H from the room, so at least (N - 2) H - h from the points
    t_end = ((order - 2) * room_h.lattice_spacing - h - A) / AIR.c
    t = np.linspace(0.0, t_end, 240)
    worst = 0.0
    for wall in range(6):
        axis = wall // 2
        pts = _wall_points(dims, wall)
        off = np.zeros(3)
        off[axis] = h
        p_in = _room_pressure(pulse, t, pts + off, im)
        p_out = _room_pressure(pulse, t, pts - off, im)
        scale = np.abs(p_in).max()
        assert scale > 0
        worst = max(worst, float(np.abs(p_in - p_out).max() / scale))
    return worst, t_end


def test_normal_velocity_vanishes_on_every_rigid_wall():
    """Central differences of p across each rigid wall vanish (Euler: dp/dn = -rho du_n/dt = 0).

    At finite order the image set is closed under the mirror of a wall only up to its outermost
    shell, so the check runs until the first image of order N + 1 can arrive anywhere near the
    room (:func:`order_for_time`'s bound); until then the truncated sum is the whole field.
    """
    dims = np.array([0.5, 0.4, 0.3])
    order = 10
    pulse = _pulse()
    im = image_sources(Shoebox(dims), (0.2, 0.15, A), order, radius=A)
    h = 1e-3
    worst, t_end = _normal_derivative_check(im, dims, order, pulse, h)
    assert t_end > 4e-3  # tens of reflections have arrived by then (a 0.5 m room, 1771 images)
    assert worst < SYM_RTOL
    # the check has teeth: images that keep the real direction break the wall condition
    bad = type(im)(im.positions, np.broadcast_to(im.directions[0], im.directions.shape), im.weights, im.orders,
                   im.lattice)
    worst_bad, _ = _normal_derivative_check(bad, dims, order, pulse, h)
    assert worst_bad > 1e-2


def test_rigid_room_equals_wall_floor_corner_until_the_next_image():
    """In a rigid room, until the first image beyond the corner's four arrives, p equals the corner's."""
    wall_distance = 0.05
    dims = (3.0, 2.5, 2.0)
    y0 = 1.2
    corner = images_wall_floor(A, wall_distance)
    shift = np.array([wall_distance, y0, 0.0])
    t_end = 12e-3
    order = order_for_time(Shoebox(dims), t_end, radius=A)
    im = image_sources(Shoebox(dims), shift + corner.centre, order, radius=A)
    in_corner = (np.abs(im.lattice[:, 1]) == 0) & (im.lattice[:, 0] >= -1) & (im.lattice[:, 0] <= 0) \
        & (im.lattice[:, 2] >= -1) & (im.lattice[:, 2] <= 0)
    assert in_corner.sum() == 4
    pts = np.array([[0.3, 1.5, 0.2], [0.1, 1.2, 0.05], [0.6, 0.9, 0.4], [0.02, 1.3, 0.3]])
    pulse = _pulse("hertz")
    t = np.linspace(0.0, t_end, 600)
    p_room = _room_pressure(pulse, t, pts, im)
    corner_sources = [shift + s.position for s in corner.sources]
    corner_axes = [s.axis for s in corner.sources]
    p_corner = np.zeros_like(p_room)
    for pos, ax in zip(corner_sources, corner_axes, strict=True):
        d = pts - pos
        r = np.linalg.norm(d, axis=1)
        p_corner += pressure(pulse, t[None, :], r[:, None], (d @ ax / r)[:, None], radius=A)
    # the four room images the corner holds are its sources, with the same axes
    got = im.positions[in_corner][np.lexsort(im.positions[in_corner].T)]
    want = np.array(corner_sources)[np.lexsort(np.array(corner_sources).T)]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-15)
    for i, pt in enumerate(pts):
        r_other = np.linalg.norm(im.positions[~in_corner] - pt, axis=1)
        t_next = (r_other.min() - A) / AIR.c
        before = t < t_next
        assert before.sum() > 50 and t_next < t_end  # the comparison stops where the room differs
        scale = np.abs(p_corner[i]).max()
        np.testing.assert_allclose(p_room[i, before], p_corner[i, before], rtol=0, atol=CORNER_RTOL * scale)
        assert np.abs(p_room[i, ~before] - p_corner[i, ~before]).max() > 1e-6 * scale


# ------------------------------------------------------------------------------- choosing the order
@pytest.mark.parametrize("seed", range(4))
def test_order_for_time_holds_every_image_that_can_arrive(seed):
    rng = np.random.default_rng(seed)
    dims = rng.uniform(0.8, 4.0, 3)
    room = Shoebox(dims)
    medium = Medium(c=343.2)
    t = rng.uniform(2e-3, 25e-3)
    n = order_for_time(room, t, radius=A, medium=medium)
    im = image_sources(room, rng.uniform(A, dims - A), n + 6, radius=A)
    # receivers everywhere in the room, corners included (where the bound is nearly reached)
    corners = np.indices((2, 2, 2)).reshape(3, -1).T * dims
    rcv = np.vstack([rng.uniform(0, dims, (200, 3)), corners])
    worst = 0
    for chunk in np.array_split(rcv, 8):
        r = np.linalg.norm(im.positions[:, None, :] - chunk[None, :, :], axis=2)
        arrives = (r - A) / medium.c <= t
        worst = max(worst, int(im.orders[arrives.any(axis=1)].max()))
    assert worst <= n
    # the bound is not vacuous: orders close to it do arrive somewhere in the room
    assert worst >= 0.6 * n - 3


def test_order_for_time_examples():
    room = Shoebox((6.0, 4.0, 3.0))
    h = 1 / math.sqrt(1 / 36 + 1 / 16 + 1 / 9)
    assert room.lattice_spacing == pytest.approx(h, rel=1e-15)
    for t in (0.0, 1e-3, 0.05, 0.2):
        assert order_for_time(room, t, radius=A) == 3 + math.floor((AIR.c * t + A) / h)


@pytest.mark.parametrize("alpha, tol_db", [(0.3, -30.0), ((0.05, 0.5, 0.2, 0.3, 0.1, 0.6), -40.0)],
                         ids=["uniform", "six"])
def test_energy_order_bound_holds_by_brute_force(alpha, tol_db):
    """The images beyond the chosen order carry less than the bound, at receivers all over the room."""
    dims = np.array([3.0, 2.2, 1.8])
    room = Shoebox(dims, alpha)
    res = energy_order(room, tol_db, radius=A)
    assert res.neglected_db <= tol_db and not res.capped
    assert res.images == image_count(res.order)
    # brute force: images to a much higher order (the rest below 1e-4 of the neglected part)
    deep = res.order + 40
    im = image_sources(room, (0.7, 1.1, A), deep, radius=A)
    rng = np.random.default_rng(11)
    rcv = np.vstack([rng.uniform(0, dims, (30, 3)), np.indices((2, 2, 2)).reshape(3, -1).T * dims])
    kept = im.orders <= res.order
    w2 = im.weights**2
    worst = -np.inf
    for pt in rcv:
        e = w2 / np.sum((im.positions - pt) ** 2, axis=1)
        worst = max(worst, 10 * np.log10(e[~kept].sum() / e.sum()))
    assert worst <= res.neglected_db
    # a much lower order would not do: the rule is not needlessly generous by more than its bounds
    lower = energy_order(room, tol_db + 20.0, radius=A).order
    e = w2 / np.sum((im.positions - rcv[0]) ** 2, axis=1)
    assert 10 * np.log10(e[im.orders > lower].sum() / e.sum()) > tol_db


def test_energy_order_with_a_window_and_a_cap():
    rigid = Shoebox((6.0, 4.0, 3.0), (0.0, 0.1, 0.1, 0.1, 0.1, 0.1))
    with pytest.raises(ParameterError, match="duration") as err:
        energy_order(rigid, radius=A)
    assert "x0" in str(err.value)
    res = energy_order(rigid, -60.0, radius=A, duration=0.05)
    assert res.order <= order_for_time(rigid, 0.05, radius=A)
    capped = energy_order(Shoebox((6.0, 4.0, 3.0), 0.1), -60.0, radius=A, max_order=20)
    assert capped.capped and capped.order == 20 and capped.neglected_db > -60.0
    full = energy_order(Shoebox((6.0, 4.0, 3.0), 0.1), -60.0, radius=A)
    assert full.order > 20 and full.neglected_db <= -60.0
    # banded absorption: the worst band decides
    banded = Shoebox((6.0, 4.0, 3.0), np.column_stack([np.full(6, 0.5), np.full(6, 0.1)]))
    assert energy_order(banded, -60.0, radius=A).order == full.order


# ------------------------------------------------------------------------------- reverberation
def test_sabine_and_eyring_formulas():
    room = Shoebox((6.0, 4.0, 3.0), 0.1)
    # by hand: V = 72 m^3, S = 108 m^2, A = 10.8 m^2, 24 ln 10 / 343.2 = 0.161 s/m
    k = 24 * math.log(10) / 343.2
    assert k == pytest.approx(0.1610, abs=5e-5)
    assert reverberation_time(room, "sabine") == pytest.approx(k * 72 / 10.8, rel=1e-14)
    assert reverberation_time(room, "eyring") == pytest.approx(k * 72 / (-108 * math.log(0.9)), rel=1e-14)
    # Eyring tends to Sabine for small absorption; Sabine's is always the longer
    small = Shoebox((6.0, 4.0, 3.0), 1e-4)
    assert reverberation_time(small, "eyring") / reverberation_time(small, "sabine") == pytest.approx(1, abs=1e-4)
    water = Medium(c=1481.0, rho=998.0)
    assert reverberation_time(room, "sabine", medium=water) == pytest.approx(
        reverberation_time(room, "sabine") * 343.2 / 1481.0, rel=1e-14)
    banded = Shoebox((6.0, 4.0, 3.0), np.column_stack([np.full(6, 0.1), np.full(6, 0.3)]))
    np.testing.assert_allclose(reverberation_time(banded), [reverberation_time(room),
                                                            reverberation_time(Shoebox((6.0, 4.0, 3.0), 0.3))])
    assert reverberation_time(Shoebox((6.0, 4.0, 3.0)), "sabine") == math.inf


def _schroeder_t30(times, energy):
    sch = np.cumsum(energy[::-1])[::-1]
    level = 10 * np.log10(sch / sch[0])
    m = (level <= -5) & (level >= -35)
    return -60.0 / np.polyfit(times[m], level[m], 1)[0]


def _image_sum_t30(room, receiver, t_max, bin_s=1e-3):
    n = order_for_time(room, t_max, radius=A)
    im = image_sources(room, np.array([0.2, 0.27, 0.0]) * room.dimensions + np.array([0, 0, A]), n, radius=A)
    r = np.linalg.norm(im.positions - receiver, axis=1)
    t = (r - A) / AIR.c
    edges = np.arange(0.0, t_max + bin_s, bin_s)
    keep = t < edges[-1]
    e, _ = np.histogram(t[keep], edges, weights=(im.weights[keep] ** 2 / r[keep] ** 2))
    return _schroeder_t30(edges[:-1], e)


def test_schroeder_decay_of_an_image_sum_gives_eyring_in_a_cube():
    """Uniform absorption in a cube: the image sum's T30 is Eyring's within 10 %, Sabine's is not.

    The images' weights are exactly beta^n with n reflections, about c t S/(4V) of them after a
    time t on average over directions: Eyring's assumption. Sabine's formula replaces
    -ln(1 - alpha) by alpha and overestimates the time for an absorbing room.
    """
    room = Shoebox((5.0, 5.0, 5.0), 0.4)
    te, ts = reverberation_time(room, "eyring"), reverberation_time(room, "sabine")
    t30 = _image_sum_t30(room, np.array([3.1, 2.2, 1.7]), 0.7 * te)
    assert abs(t30 / te - 1) < 0.10
    assert abs(t30 / ts - 1) > 0.10


@pytest.mark.parametrize("dims, alpha", [((6.0, 4.0, 3.0), 0.3), ((10.0, 7.0, 3.0), 0.3),
                                         ((6.0, 4.0, 3.0), (0.1, 0.4, 0.2, 0.2, 0.5, 0.05))],
                         ids=["6x4x3", "10x7x3", "6x4x3-six"])
def test_schroeder_decay_follows_the_direction_averaged_decay(dims, alpha):
    """In an elongated room the image sum reverberates longer than Eyring's time (Jensen), as predicted.

    :func:`image_energy_decay` averages the exponential decay over the images' directions;
    Eyring's formula is the exponential of the average. The Schroeder T30 of the image sum
    follows the average to 3 %, and lies above Eyring's by more in the longer room.
    """
    room = Shoebox(dims, alpha)
    te = reverberation_time(room, "eyring")
    t_max = 0.7 * te
    t30 = _image_sum_t30(room, np.array([0.55, 0.6, 0.45]) * room.dimensions, t_max)
    tt = np.arange(0.0, t_max, 1e-4)
    t30_model = _schroeder_t30(tt, image_energy_decay(room, tt))
    assert abs(t30 / t30_model - 1) < 0.03
    assert t30 > te


def test_image_energy_decay_is_the_image_density_times_the_mean_weight():
    room = Shoebox((4.0, 3.0, 2.5), 0.2)
    # no absorption: the rate is 4 pi c / V (image density 4 pi c^3 t^2 / V times 1/(ct)^2)
    rigid = Shoebox((4.0, 3.0, 2.5))
    np.testing.assert_allclose(image_energy_decay(rigid, [0.0, 0.1, 1.0]), 4 * math.pi * AIR.c / 30.0, rtol=1e-14)
    # the directional average of |u_i| is 1/2: at small t, log-slope = c S ln(1 - alpha) / (4 V)
    t = np.array([0.0, 1e-6])
    e = image_energy_decay(room, t)
    slope = np.log(e[1] / e[0]) / 1e-6
    assert slope == pytest.approx(AIR.c * room.surface_area * math.log(0.8) / (4 * room.volume), rel=1e-4)


def test_echo_density_matches_the_counted_images():
    """Images arrive at 4 pi c^3 t^2 / V per second (Kuttruff): 4 pi (c t)^3 / (3 V) by time t, counted.

    One image per cell of volume V, so the count within a sphere is its volume over V to within
    the cells its surface cuts (1 % at 60 ms in this room).
    """
    room = Shoebox((4.0, 3.0, 2.5))
    t_end = 0.06
    n = order_for_time(room, t_end, radius=A)
    im = image_sources(room, (1.3, 0.9, A), n, radius=A)
    for receiver in ([2.1, 1.7, 1.2], [0.1, 0.1, 0.1]):
        r = np.linalg.norm(im.positions - np.array(receiver), axis=1)
        counted = np.count_nonzero(r < AIR.c * t_end)
        assert counted == pytest.approx(4 * math.pi * (AIR.c * t_end) ** 3 / (3 * room.volume), rel=0.02)
    # the time at which the mean spacing is dt: the density then is 1/dt
    dt = 1e-4
    t = echo_density_time(room, dt)
    assert 4 * math.pi * AIR.c**3 * t**2 / room.volume == pytest.approx(1 / dt, rel=1e-12)
    assert mixing_time(Shoebox((10.0, 10.0, 10.0))) == pytest.approx(math.sqrt(1000.0) * 1e-3, rel=1e-15)


# ------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("make, name, words", [
    (lambda: Shoebox((6.0, 4.0), 0.1), "dimensions", "3 lengths"),
    (lambda: Shoebox((6.0, -4.0, 3.0), 0.1), "dimensions (Ly)", "> 0"),
    (lambda: Shoebox((6.0, 4.0, 3.0), 1.0), "absorption", "[0, 1)"),
    (lambda: Shoebox((6.0, 4.0, 3.0), (0.1, 0.1, -0.1, 0.1, 0.1, 0.1)), "absorption", "y0"),
    (lambda: Shoebox((6.0, 4.0, 3.0), (0.1, 0.2)), "absorption", "six"),
    (lambda: image_sources(Shoebox((6, 4, 3)), (2, 1, 0.01), 2, radius=A), "centre", "z must lie in"),
    (lambda: image_sources(Shoebox((6, 4, 0.03)), (2, 1, 0.015), 2, radius=A), "radius", "does not fit"),
    (lambda: image_sources(Shoebox((6, 4, 3)), (2, 1, 1), -1, radius=A), "order", ">= 0"),
    (lambda: image_sources(Shoebox((6, 4, 3)), (2, 1, 1), 2.5, radius=A), "order", "integer"),
    (lambda: image_sources(Shoebox((6, 4, 3)), (2, 1, 1), 2, radius=A, direction="roof"), "direction", "x0"),
    (lambda: image_sources(Shoebox((6, 4, 3)), (2, 1, 1), 2, radius=A, direction=(0, 0, 0)), "direction",
     "non-zero"),
    (lambda: image_sources(Shoebox((6, 4, 3)), (2, 1, 1), 60, radius=A, max_memory_mb=10), "order",
     "(4N^3 + 6N^2 + 8N + 3)/3"),
    (lambda: energy_order(Shoebox((6, 4, 3), 0.1), 3.0, radius=A), "tolerance_db", "[-200, 0)"),
    (lambda: reverberation_time(Shoebox((6, 4, 3), 0.1), "norris"), "formula", "eyring"),
])
def test_bad_input_names_the_field_and_the_range(make, name, words):
    with pytest.raises(ParameterError) as err:
        make()
    assert err.value.name == name
    assert words in err.value.detail


def test_memory_budget_counts_images_before_building():
    """The largest order the budget admits is built within it (peak of numpy's allocations)."""
    budget_mb = 20.0
    nmax = max_order_for_memory(budget_mb)
    assert nmax > 20
    tracemalloc.start()
    try:
        image_sources(Shoebox((6, 4, 3), 0.1), (2, 1, 1), nmax, radius=A, max_memory_mb=budget_mb)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak <= budget_mb * 1e6
    with pytest.raises(ParameterError, match=f"must lie in \\[0, {nmax}\\]"):
        image_sources(Shoebox((6, 4, 3), 0.1), (2, 1, 1), nmax + 1, radius=A, max_memory_mb=budget_mb)
    assert max_order_for_memory(budget_mb, bands=8) < nmax
