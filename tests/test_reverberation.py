"""Order rules and reverberation of a shoebox room, checked by brute force and by independent formulas.

The order rules are checked against every image of a much deeper lattice at receivers all over the
room; the Schroeder decay of long image sums against Sabine's and Eyring's formulas and a
direction-averaged decay; the image density against a count of the images.
"""

import math

import numpy as np
import pytest
from scipy.signal import get_window

from acoustiviz.core.medium import AIR, Medium
from acoustiviz.core.reverberation import (
    complete_until,
    echo_density_time,
    energy_order,
    image_energy_decay,
    mixing_time,
    order_for_time,
    reverberation_time,
)
from acoustiviz.core.room import Shoebox, image_count, image_sources
from acoustiviz.core.tail import late_tail
from acoustiviz.errors import ParameterError

A = 0.01905  # the paper's sphere, m


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
    # the bound is tight: the order below it does arrive somewhere in the room (a corner)
    assert worst >= n - 1


def test_order_for_time_examples():
    room = Shoebox((6.0, 4.0, 3.0))
    h = 1 / math.sqrt(1 / 36 + 1 / 16 + 1 / 9)
    assert room.lattice_spacing == pytest.approx(h, rel=1e-15)
    for t in (0.0, 1e-3, 0.05, 0.2):
        assert order_for_time(room, t, radius=A) == 3 + math.floor((AIR.c * t + A) / h)


@pytest.mark.parametrize("alpha, tol_db", [(0.3, -30.0), ((0.05, 0.5, 0.2, 0.3, 0.1, 0.6), -40.0)],
                         ids=["uniform", "six"])
@pytest.mark.slow
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
    assert 0.0 < t30 / te - 1 < 0.08  # about 4 % above: the spread of sum |u_i| over directions is small
    assert abs(t30 / ts - 1) > 0.10


@pytest.mark.parametrize("dims, alpha, above", [((6.0, 4.0, 3.0), 0.3, (0.10, 0.18)),
                                                ((10.0, 7.0, 3.0), 0.3, (0.20, 0.35)),
                                                ((6.0, 4.0, 3.0), (0.1, 0.4, 0.2, 0.2, 0.5, 0.05), (0.0, 0.5))],
                         ids=["6x4x3", "10x7x3", "6x4x3-six"])
def test_schroeder_decay_follows_the_direction_averaged_decay(dims, alpha, above):
    """In an elongated room the image sum reverberates longer than Eyring's time (Jensen), as predicted.

    :func:`image_energy_decay` averages the exponential decay over the images' directions;
    Eyring's formula is the exponential of the average. The Schroeder T30 of the image sum
    follows the average to 3 %, and lies above Eyring's: by about 14 % in a 6 x 4 x 3 m room,
    more in the longer room.
    """
    room = Shoebox(dims, alpha)
    te = reverberation_time(room, "eyring")
    t_max = 0.7 * te
    t30 = _image_sum_t30(room, np.array([0.55, 0.6, 0.45]) * room.dimensions, t_max)
    tt = np.arange(0.0, t_max, 1e-4)
    t30_model = _schroeder_t30(tt, image_energy_decay(room, tt))
    assert abs(t30 / t30_model - 1) < 0.03
    assert above[0] < t30 / te - 1 < above[1]


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


@pytest.mark.parametrize("make, name, words", [
    (lambda: energy_order(Shoebox((6, 4, 3), 0.1), 3.0, radius=A), "tolerance_db", "[-200, 0)"),
    (lambda: energy_order(Shoebox((6, 4, 3), 0.1), radius=A, max_order=-2), "max_order", ">= 0"),
    (lambda: order_for_time(Shoebox((6, 4, 3), 0.1), -1.0, radius=A), "time", "[0, inf]"),
    (lambda: reverberation_time(Shoebox((6, 4, 3), 0.1), "norris"), "formula", "eyring"),
    (lambda: echo_density_time(Shoebox((6, 4, 3), 0.1), 0.0), "spacing", "> 0"),
    (lambda: image_energy_decay(Shoebox((6, 4, 3), 0.1), [-1.0]), "times", ">= 0"),
    (lambda: late_tail(Shoebox((6, 4, 3), 0.1), 0.0, 0.1, 48000, 7), "rng", "Generator"),
    (lambda: late_tail(Shoebox((6, 4, 3), 0.1), 0.0, 1e-6, 48000, np.random.default_rng(0)), "duration",
     "one sample"),
    (lambda: late_tail(Shoebox((6, 4, 3), np.full((6, 2), 0.1)), 0.0, 0.1, 48000, np.random.default_rng(0)),
     "band_centres", "required"),
    (lambda: late_tail(Shoebox((6, 4, 3), np.full((6, 2), 0.1)), 0.0, 0.1, 48000, np.random.default_rng(0),
                       band_centres=(1000.0, 500.0)), "band_centres", "increasing"),
    (lambda: complete_until(Shoebox((6, 4, 3), 0.1), -1, radius=A), "order", ">= 0"),
])
@pytest.mark.slow
def test_bad_input_names_the_field_and_the_range(make, name, words):
    with pytest.raises(ParameterError) as err:
        make()
    assert err.value.name == name
    assert words in err.value.detail


# ------------------------------------------------------------------------------- the statistical tail
def test_complete_until_holds_every_image_of_higher_order_back():
    rng = np.random.default_rng(5)
    room = Shoebox((3.0, 2.4, 2.0), 0.2)
    order = 9
    t_c = complete_until(room, order, radius=A)
    assert order_for_time(room, 0.999 * t_c, radius=A) <= order  # the inverse of order_for_time
    im = image_sources(room, (0.8, 1.1, A), order + 8, radius=A)
    rcv = np.vstack([rng.uniform(0, room.dimensions, (300, 3)),
                     np.indices((2, 2, 2)).reshape(3, -1).T * room.dimensions])
    beyond = im.positions[im.orders > order]
    for chunk in np.array_split(rcv, 6):
        r = np.linalg.norm(beyond[:, None, :] - chunk[None, :, :], axis=2)
        assert ((r - A) / AIR.c).min() >= t_c


def test_expected_decay_is_the_image_sum_after_the_transition():
    """Where the exact images stop, the tail's expected energy is that of the images that follow.

    Energy of the images arriving in 20 ms windows from the transition on, at three receivers,
    against the integral of :func:`image_energy_decay` over the same windows.
    """
    room = Shoebox((6.0, 4.0, 3.0), 0.3)
    t_c = complete_until(room, 12, radius=A)
    im = image_sources(room, (2.0, 1.5, A), order_for_time(room, t_c + 0.06, radius=A), radius=A)
    ratios = []
    for receiver in ([3.1, 2.2, 1.3], [0.5, 3.5, 2.5], [5.5, 0.3, 0.2]):
        r = np.linalg.norm(im.positions - np.array(receiver), axis=1)
        t = (r - A) / AIR.c
        for lo in (t_c, t_c + 0.02, t_c + 0.04):
            m = (t >= lo) & (t < lo + 0.02)
            tt = np.linspace(lo, lo + 0.02, 2001)
            ratios.append(np.sum(im.weights[m] ** 2 / r[m] ** 2) / np.trapezoid(image_energy_decay(room, tt), tt))
    ratios = np.array(ratios)
    assert np.all(np.abs(ratios - 1) < 0.2)  # hundreds of images a window: fluctuations of about 10 %
    assert abs(ratios.mean() - 1) < 0.05


@pytest.mark.slow
def test_late_tail_follows_the_decay_and_is_reproducible():
    room = Shoebox((6.0, 4.0, 3.0), 0.3)
    fs, start, dur = 48000, 0.065, 0.3
    h = late_tail(room, start, dur, fs, np.random.default_rng(1))
    assert h.shape == (round(dur * fs),)
    np.testing.assert_array_equal(h, late_tail(room, start, dur, fs, np.random.default_rng(1)))
    t = start + np.arange(h.size) / fs
    for lo in np.arange(0.0, dur, 0.05):  # 2400 samples a window: the energy to a few per cent
        m = (t >= start + lo) & (t < start + lo + 0.05)
        expected = np.sum(image_energy_decay(room, t[m])) / fs
        assert np.sum(h[m] ** 2) == pytest.approx(expected, rel=0.08)


@pytest.mark.slow
def test_banded_tail_decays_in_each_band_at_its_own_rate():
    """The energy of each band of the tail, from its spectrum, is that band's share of its own decay.

    Blackman-Harris windows (sidelobes below -92 dB, the bins within 5 of a band edge left out) at
    the start and 0.16 s later, when the bands differ by 30 dB; four seeds averaged (each window
    has 80 to 360 degrees of freedom a band).
    """
    centres = np.array([500.0, 2000.0, 6000.0])
    room = Shoebox((6.0, 4.0, 3.0), np.tile([0.1, 0.2, 0.35], (6, 1)))
    fs, start, dur = 16000, 0.02, 0.3
    edges = np.sqrt(centres[:-1] * centres[1:])
    win = round(0.08 * fs)
    w = get_window("blackmanharris", win)
    f = np.fft.rfftfreq(win, 1 / fs)
    band = np.searchsorted(edges, f, side="right")
    away = np.min(np.abs(f[:, None] - edges[None, :]), axis=1) >= 5 * fs / win
    t = start + np.arange(round(dur * fs)) / fs
    tails = [late_tail(room, start, dur, fs, np.random.default_rng(seed), band_centres=centres) for seed in range(4)]
    for lo in (0, 2 * win):
        # expected h^2 per sample in each band, weighted by the window as the spectrum is
        rate = (image_energy_decay(room, t[lo:lo + win]) * w[:, None] ** 2).sum(axis=0) / np.sum(w**2) / fs
        power = np.mean([np.abs(np.fft.rfft(h[lo:lo + win] * w)) ** 2 for h in tails], axis=0)
        power *= 2 / (win * np.sum(w**2))  # one-sided: the bins sum to the mean square
        for b in range(3):
            sel = (band == b) & away
            share = np.count_nonzero(sel) / f.size  # the share of a white spectrum these bins hold
            assert power[sel].sum() == pytest.approx(share * rate[b], rel=0.15)
    assert rate[0] / rate[2] > 1e3  # the bands do decay at different rates
