"""Shoebox room: image lattice, order rules and reverberation, checked against independent references.

References used here: pyroomacoustics' ShoeBox image-source model (a separate implementation, in
float32); brute-force enumeration of the lattice; the mirror symmetry of the pressure field
about each rigid wall computed with the free-field sphere model of :mod:`acoustiviz.core.radiation`;
today's wall-floor corner of :mod:`acoustiviz.core.geometry`; Sabine's and Eyring's formulas and a
direction-averaged decay for the Schroeder curves.
"""

import tracemalloc

import numpy as np
import pytest

from acoustiviz.core.geometry import images_wall_floor
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import pressure
from acoustiviz.core.reverberation import order_for_time
from acoustiviz.core.room import SURFACES, Shoebox, image_count, image_sources, max_order_for_memory
from acoustiviz.errors import ParameterError

A = 0.01905  # the paper's sphere, m
#: pyroomacoustics computes its images and damping in float32
F32 = float(np.finfo(np.float32).eps)
#: mirrored samples of a symmetric field agree to round-off relative to the field's largest value
SYM_RTOL = 1e-11
#: the rigid room and today's corner agree before any further image arrives
CORNER_RTOL = 1e-12

PRA_WALLS = ("west", "east", "south", "north", "floor", "ceiling")  # x0, x1, y0, y1, z0, z1


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
    # a lower order is a prefix: the same images as built for it
    low = im.up_to(order // 2)
    ref = image_sources(room, (1.0, 0.7, A), order // 2, radius=A)
    for name in ("positions", "directions", "weights", "orders", "lattice"):
        np.testing.assert_array_equal(getattr(low, name), getattr(ref, name))
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


def test_shoebox_is_a_value():
    room = Shoebox([6, 4, 3], 0.1)
    assert room == Shoebox((6.0, 4.0, 3.0), [0.1] * 6) and hash(room) == hash(Shoebox((6.0, 4.0, 3.0), 0.1))
    assert room != Shoebox((6.0, 4.0, 3.0), 0.2) and room != Shoebox((6.0, 4.0, 3.0), np.full((6, 1), 0.1))
    with pytest.raises(ValueError):
        room.dimensions[0] = 1.0
    assert room.areas.tolist() == [12.0, 12.0, 18.0, 18.0, 24.0, 24.0]
    assert room.absorption_area == pytest.approx(10.8, rel=1e-15) and room.mean_free_path == pytest.approx(8 / 3)


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


def _asymmetry(im, dims, pulse, h, t):
    """Max over the walls of |p(x_w + h n) - p(x_w - h n)| / max|p| at 8 points of each wall."""
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
    return worst


@pytest.mark.slow
def test_normal_velocity_vanishes_on_every_rigid_wall(paper_pulse):
    """Central differences of p across each rigid wall vanish (Euler: dp/dn = -rho du_n/dt = 0).

    At finite order the image set is closed under the mirror of a wall only up to its outermost
    shell, so the check runs until the first image of order N + 1 can arrive anywhere near the
    room (the bound of :func:`order_for_time`); until then the truncated sum is the whole field,
    and after it the truncation shows.
    """
    dims = np.array([0.5, 0.4, 0.3])
    order = 10
    pulse = paper_pulse()
    im = image_sources(Shoebox(dims), (0.2, 0.15, A), order, radius=A)
    h = 1e-3
    # an image of order > N is at least (N - 2) H from the room, so at least (N - 2) H - h from the points
    t_end = ((order - 2) * Shoebox(dims).lattice_spacing - h - A) / AIR.c
    assert t_end > 4e-3  # tens of reflections have arrived by then (a 0.5 m room, 1561 images)
    t = np.linspace(0.0, t_end, 240)
    assert _asymmetry(im, dims, pulse, h, t) < SYM_RTOL
    # the window matters: later, the missing order N + 1 breaks the symmetry by per cents
    assert _asymmetry(im, dims, pulse, h, np.linspace(t_end, 2 * t_end, 240)) > 1e-3
    # the check has teeth: images that keep the real direction break the wall condition
    bad = type(im)(im.positions, np.broadcast_to(im.directions[0], im.directions.shape), im.weights, im.orders,
                   im.lattice)
    assert _asymmetry(bad, dims, pulse, h, t) > 1e-2


def test_rigid_room_equals_wall_floor_corner_until_the_next_image(paper_pulse):
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
    pulse = paper_pulse("hertz")
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
