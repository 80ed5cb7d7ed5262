"""Field evaluator: against direct sums of sphere_pressure, chunking, memory cap, metrics."""

import threading
import tracemalloc

import numpy as np
import pytest

from acoustiviz import field
from acoustiviz._validate import ParameterError
from acoustiviz.core.contact import Impact, acceleration_pulse
from acoustiviz.core.geometry import geometry as av_geometry
from acoustiviz.core.geometry import images_free, images_plane, images_wall_floor
from acoustiviz.core.radiation import sphere_pressure

A = 0.01905
#: the evaluator drops tails below DEFAULT_CUTOFF = 1e-10 of each sphere's scale
RTOL = 1e-8
CONFIGS = {
    "free": images_free(A),
    "plane": images_plane(A),
    "corner": images_wall_floor(A, 0.05),
    "corner-wall": images_wall_floor(A, strike="wall", height=0.03),
}


def _direct(pulse, t, pts, cfg):
    """Reference: a plain sum of free-field spheres from the radiation core."""
    return sum(sphere_pressure(pulse, t, pts, radius=A, centre=s.position, axis=s.axis) for s in cfg.sources)


def _points(cfg, n=60, seed=1):
    rng = np.random.default_rng(seed)
    pts = rng.uniform([-0.05, -0.6, 0.0], [0.8, 0.6, 0.8], (4 * n, 3))
    return pts[cfg.in_fluid(pts)][:n]


@pytest.mark.parametrize("kind", ["half-sine", "hertz"])
@pytest.mark.parametrize("name", list(CONFIGS))
def test_time_series_matches_direct_sum(kind, name, paper_pulse):
    cfg = CONFIGS[name]
    pulse = paper_pulse(kind)
    pts = _points(cfg)
    t = np.linspace(-1e-4, 5e-3, 1700)
    ref = _direct(pulse, t, pts, cfg)
    got = field.time_series(pulse, t, pts, cfg)
    np.testing.assert_allclose(got, ref, rtol=0, atol=RTOL * np.max(np.abs(ref)))
    # a non-uniform grid takes the vectorised path, which drops the same tails
    tn = np.sort(np.random.default_rng(2).uniform(0, 5e-3, 200))
    got = field.time_series(pulse, tn, pts, cfg)
    np.testing.assert_allclose(got, _direct(pulse, tn, pts, cfg), rtol=0, atol=RTOL * np.max(np.abs(ref)))


def test_chunked_equals_unchunked(paper_pulse):
    cfg = CONFIGS["corner"]
    pulse = paper_pulse("half-sine")
    pts = _points(cfg, 300)
    t = np.linspace(0, 4e-3, 500)
    big = field.time_series(pulse, t, pts, cfg)
    # chunks regroup the points of the vectorised geometry (BLAS matrix-vector products whose SIMD blocks and
    # scalar tails round differently): the same values to round-off, amplified by (r/c)/T ~ 3 at most; 1e-12
    # of the peak is far above that and far below what a point in the wrong chunk or a lost row would give
    tol = 1e-12 * np.max(np.abs(big))
    small = field.time_series(pulse, t, pts, cfg, memory_limit=8 * t.size * pts.shape[0] + 20_000)
    np.testing.assert_allclose(small, big, rtol=0, atol=tol)
    blocks = list(field.iter_time_series(pulse, t, pts, cfg, memory_limit=200_000))
    assert len(blocks) > 1
    np.testing.assert_allclose(np.vstack([b for _, _, b in blocks]), big, rtol=0, atol=tol)
    m1 = field.field_metrics(pulse, pts, cfg)
    m2 = field.field_metrics(pulse, pts, cfg, memory_limit=50_000)
    np.testing.assert_allclose(m1.rms, m2.rms, rtol=1e-12, atol=0)
    np.testing.assert_allclose(m1.peak, m2.peak, rtol=1e-12, atol=0)


@pytest.mark.slow
def test_memory_cap_is_respected(paper_pulse):
    cfg = CONFIGS["plane"]
    pulse = paper_pulse("half-sine")
    rng = np.random.default_rng(5)
    pts = rng.uniform([-1, -1, 0.05], [1, 1, 1], (200_000, 3))
    cap = 16 * 2**20
    field.field_metrics(pulse, pts[:1000], cfg, sample_interval=2e-6)  # compile outside the trace
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        fm = field.field_metrics(pulse, pts, cfg, sample_interval=2e-6, memory_limit=cap)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak <= cap
    assert np.all(np.isfinite(fm.peak))
    with pytest.raises(ParameterError) as err:
        field.time_series(pulse, np.linspace(0, 1e-3, 1000), pts, cfg, memory_limit=cap)
    assert err.value.name == "memory_limit"


def test_metrics_match_a_full_series(paper_pulse):
    cfg = CONFIGS["corner"]
    pulse = paper_pulse("half-sine")
    pts = _points(cfg, 40)
    dt = 5e-7
    t = np.arange(0, 6e-3, dt)
    ref = _direct(pulse, t, pts, cfg)
    fm = field.field_metrics(pulse, pts, cfg, t=t)
    raw = field.field_metrics(pulse, pts, cfg, t=t, refine=False)  # the extreme samples themselves
    scale = np.max(np.abs(ref))
    np.testing.assert_allclose(raw.peak_positive, ref.max(axis=1), atol=RTOL * scale)
    np.testing.assert_allclose(raw.peak_negative, ref.min(axis=1), atol=RTOL * scale)
    # refined between the samples: beyond the samples, by at most what 0.5 us of sampling can miss
    assert np.all(fm.peak_positive >= raw.peak_positive) and np.all(fm.peak_negative <= raw.peak_negative)
    np.testing.assert_allclose(fm.peak, raw.peak, rtol=1e-3)
    np.testing.assert_allclose(fm.rms, np.sqrt(np.mean(ref**2, axis=1)), rtol=1e-7)
    np.testing.assert_allclose(fm.exposure, np.sum(ref**2, axis=1) * dt, rtol=1e-7)
    # the per-point windows (default) see the whole response: same exposure to the sampling
    own = field.field_metrics(pulse, pts, cfg, sample_interval=dt)
    np.testing.assert_allclose(own.exposure, fm.exposure, rtol=2e-3)
    np.testing.assert_allclose(own.peak, fm.peak, rtol=2e-3)
    assert np.all(own.peak_to_peak >= own.peak)
    np.testing.assert_allclose(own.peak_spl_db, 20 * np.log10(own.peak / 20e-6))
    np.testing.assert_allclose(own.sel_db, 10 * np.log10(own.exposure / 4e-10))


@pytest.mark.parametrize("kind", ["half-sine", "hertz"])
def test_figure2_m_shape(kind, paper_pulse, plane_geometry):
    """Paper Figure 2 (r = 0.7 m, θ = 45°): three lobes, positive, negative, positive."""
    cfg = plane_geometry
    pulse = paper_pulse(kind)
    th = np.pi / 4
    obs = cfg.centre + 0.7 * np.array([np.sin(th), 0.0, np.cos(th)])
    t = np.arange(1.5e-3, 3.5e-3, 2e-7)
    p = field.time_series(pulse, t, obs, cfg)[0]
    big = np.abs(p) > 0.1 * np.max(np.abs(p))
    signs = np.sign(p[big])  # signs of the significant lobes, in time order
    lobes = signs[np.r_[True, signs[1:] != signs[:-1]]]
    assert lobes.tolist() == [1.0, -1.0, 1.0]
    assert 0.1 < np.max(np.abs(p)) < 10.0  # Pa
    if kind == "hertz":  # with the exact Hertz pulse the dip is the largest lobe, as in the paper
        assert -p.min() > p.max()


def test_snapshots_match_direct_sum_and_mask_outside(paper_pulse):
    cfg = CONFIGS["corner"]
    pulse = paper_pulse("hertz")
    pts = np.vstack([_points(cfg, 50), [[-0.2, 0, 0.1], [0, 0, -0.1]]])
    times = np.array([0.5e-3, 1.2e-3, 2.0e-3])
    snap = field.snapshots(pulse, times, pts, cfg, memory_limit=20_000)
    ref = _direct(pulse, times, pts[:-2], cfg).T
    np.testing.assert_allclose(snap[:, :-2], ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))
    assert np.all(np.isnan(snap[:, -2:]))
    fm = field.field_metrics(pulse, pts, cfg)
    assert np.all(np.isnan(fm.peak[-2:])) and np.all(np.isfinite(fm.peak[:-2]))


def test_windows_and_decay_time(paper_pulse):
    cfg = CONFIGS["plane"]
    pulse = paper_pulse("half-sine")
    obs = np.array([[0.0, 0.0, 1.0 + A]])
    start, stop = field.arrival_windows(pulse, obs, cfg)
    c = field.AIR.c
    assert start[0] == pytest.approx((1.0 - A) / c)
    tail = field.decay_time(A)
    assert tail == pytest.approx(A / c * np.log(1e10))
    assert stop[0] == pytest.approx((1.0 + 2 * A - A) / c + pulse.duration + tail)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda p, c: field.time_series(p, [0, 1e-3], [[0, 0, 1]], c, memory_limit=-1), "memory_limit"),
        (lambda p, c: field.time_series(p, [0, 1e-3], [[0, 0]], c), "points"),
        (lambda p, c: field.time_series("pulse", [0, 1e-3], [[0, 0, 1]], c), "pulse"),
        (lambda p, c: field.time_series(p, [0, 1e-3], [[0, 0, 1]], "plane"), "geometry"),
        (lambda p, c: field.field_metrics(p, [[0, 0, 1]], c, cutoff=2.0), "cutoff"),
        (lambda p, c: field.field_metrics(p, [[0, 0, 1]], c, window=0.0), "window"),
        (lambda p, c: field.field_metrics(p, [[0, 0, 1]], c, t=[0, 1e-4, 3e-4]), "t"),
    ],
)
def test_bad_inputs_name_the_parameter(call, name, paper_pulse):
    with pytest.raises(ParameterError) as err:
        call(paper_pulse("half-sine"), CONFIGS["plane"])
    assert err.value.name == name


@pytest.mark.parametrize("kind", ["half-sine", "hertz"])
@pytest.mark.parametrize("name", ["plane", "corner"])
@pytest.mark.slow
def test_peaks_are_refined_to_the_continuous_maximum(kind, name, paper_pulse):
    # an independent reference: the direct sum of sphere_pressure sampled every 10 ns, then SciPy's
    # bounded Brent search on that sum around the densest sample; the refined peaks agree to 1e-8
    # (the samples of the default grid, 64 per min(tau, a/c), are off by up to ~1e-4)
    from scipy.optimize import minimize_scalar

    cfg = CONFIGS[name]
    pulse = paper_pulse(kind)
    pts = _points(cfg, 4, seed=5)
    fm = field.field_metrics(pulse, pts, cfg)
    raw = field.field_metrics(pulse, pts, cfg, refine=False)
    for i, x in enumerate(pts):
        tt = fm.window_start[i] + np.arange(0.0, fm.window - fm.sample_interval, 1e-8)
        dense = _direct(pulse, tt, x[None, :], cfg)[0]
        for sign, got, sampled in ((1.0, fm.peak_positive[i], raw.peak_positive[i]),
                                   (-1.0, fm.peak_negative[i], raw.peak_negative[i])):
            k = int(np.argmax(sign * dense))
            res = minimize_scalar(lambda t, x=x, sign=sign: -sign * _direct(pulse, [t], x[None, :], cfg)[0, 0],
                                  bounds=(tt[max(k - 1, 0)], tt[min(k + 1, tt.size - 1)]), method="bounded",
                                  options={"xatol": 1e-15})
            ref = -sign * res.fun
            assert abs(got / ref - 1) < 1e-8
            assert abs(got) >= abs(sampled) * (1 - 1e-15)  # never below the samples


def test_directivity_peaks_are_refined(paper_pulse):
    # Figure 3 setting: the peak on the circle against the dense reference at one angle
    cfg = CONFIGS["plane"]
    pulse = paper_pulse("half-sine")
    d = field.directivity(pulse, cfg, 0.7, np.radians([40.0]))
    x = d.points[0]
    tt = d.metrics.window_start[0] + np.arange(0.0, d.metrics.window, 2e-9)
    dense = np.abs(_direct(pulse, tt, x[None, :], cfg)[0])
    assert abs(d.peak[0] / dense.max() - 1) < 1e-8


@pytest.mark.parametrize("kind", ["half-sine", "hertz"])
@pytest.mark.slow
def test_exposure_without_a_time_grid_matches_quadrature(kind, paper_pulse, paper_impact):
    # the exposure from correlations of Y at the image delays against adaptive quadrature of p(t)^2,
    # p from the direct sum of free-field spheres; and the Riemann sum of field_metrics converges to it
    from scipy.integrate import quad

    cfg = CONFIGS["corner"]
    pulse = paper_pulse(kind)
    pts = np.array([[0.3, 0.1, 0.2], [0.02, -0.01, 0.03]])
    got = field.exposure(pulse, pts, cfg)
    fine = field.field_metrics(pulse, pts, cfg, sample_interval=A / field.AIR.c / 256)
    for i, x in enumerate(pts):
        d = field.source_geometry(x[None, :], cfg)[0][0]
        tau = paper_impact.duration
        cuts = np.unique(np.concatenate([np.linspace(d.min(), d.max() + tau + 50 * A / field.AIR.c, 60), d, d + tau]))
        ref = sum(quad(lambda t, x=x: _direct(pulse, [t], x[None, :], cfg)[0, 0] ** 2, a, b, epsabs=0,
                       epsrel=1e-12, limit=200)[0] for a, b in zip(cuts[:-1], cuts[1:], strict=True))
        assert abs(got[i] / ref - 1) < 1e-10
        assert abs(fine.exposure[i] / ref - 1) < 1e-8
    assert np.isnan(field.exposure(pulse, [[0.0, 0.0, A]], cfg)[0])  # the sphere's centre is not in the fluid


@pytest.mark.parametrize("kind", ["half-sine", "hertz"])
def test_exposure_table_interpolates_its_series(kind, paper_pulse):
    # the kernels read G and H by cubic Hermite from a table of the Chebyshev series and its
    # derivative; between the nodes they agree with the series to 1e-11 of G(0)
    pulse = paper_pulse(kind)
    corr = field.pulse_correlations(pulse, A)
    lag = np.random.default_rng(3).uniform(0.0, pulse.duration, 400)
    g, h = corr(lag)
    gs, hs = corr.series(lag)
    scale = abs(corr.series(0.0)[0][0])
    assert np.max(np.abs(g - gs)) < 1e-11 * scale
    assert np.max(np.abs(h - hs)) < 1e-11 * scale
    # beyond the pulse the closed form continues the series (no step at lag = T)
    g_t, h_t = corr(pulse.duration * (1 + 1e-12))
    g_s, h_s = corr.series(pulse.duration)
    assert abs(g_t[0] - g_s[0]) < 1e-10 * scale and abs(h_t[0] - h_s[0]) < 1e-10 * scale


@pytest.mark.slow
def test_exposure_of_a_long_pulse_matches_quadrature():
    # a half-sine 90 times longer than a/c (|s| T = 127): the correlations need more panels than
    # the paper's impact; the exposure on the plane against adaptive quadrature of p(t)^2
    from scipy.integrate import quad

    from acoustiviz.core.contact import HalfSinePulse

    pulse = HalfSinePulse(200.0, 5e-3)
    cfg = CONFIGS["plane"]
    pts = np.array([[0.4, 0.1, 0.3], [0.05, 0.0, 0.01]])
    got = field.exposure(pulse, pts, cfg)
    for i, x in enumerate(pts):
        d = field.source_geometry(x[None, :], cfg)[0][0]
        cuts = np.unique(np.concatenate([np.linspace(d.min(), d.max() + pulse.duration + 50 * A / field.AIR.c, 400),
                                         d, d + pulse.duration]))
        ref = sum(quad(lambda t, x=x: _direct(pulse, [t], x[None, :], cfg)[0, 0] ** 2, a, b, epsabs=0,
                       epsrel=1e-12, limit=200)[0] for a, b in zip(cuts[:-1], cuts[1:], strict=True))
        assert abs(got[i] / ref - 1) < 1e-9


def _fast_peak_points(cfg, n, seed):
    """Random points in the fluid, a quarter within 1.5 a of the sphere, a quarter within 2 mm of a plane."""
    rng = np.random.default_rng(seed)
    far = rng.uniform([-0.05, -0.6, 0.0], [0.8, 0.6, 0.8], (n, 3))
    u = rng.normal(size=(n // 4, 3))
    near = u / np.linalg.norm(u, axis=1)[:, None] * A * rng.uniform(1.0, 1.5, (n // 4, 1)) + cfg.centre
    onto = rng.uniform([-0.05, -0.6, 0.0], [0.8, 0.6, 0.8], (n // 4, 3))
    for q, pl in enumerate(cfg.planes):  # move alternate points onto each plane, then up to 2 mm off it
        sel = slice(q, None, len(cfg.planes))
        off = (onto[sel] - pl.point) @ pl.normal
        onto[sel] += (rng.uniform(0.0, 2e-3, off.size) - off)[:, None] * pl.normal
    pts = np.vstack([far, near, onto])
    return pts[cfg.in_fluid(pts)]


@pytest.mark.parametrize("kind", ["hertz", "half-sine"])
@pytest.mark.parametrize("name", ["free", "plane", "corner"])
@pytest.mark.slow
def test_fast_peaks_match_the_refined_field_metrics(kind, name, paper_pulse):
    # against field_metrics (64 samples per min(T, a/c), then Brent on the closed form): never below
    # it by more than 1e-8 of the peak; and each peak is the pressure at its reported time, evaluated
    # independently by the vectorised closed form (radiation.pulse_response summed over the images),
    # so a value above field_metrics is a higher maximum that the sampled search passed by
    from acoustiviz.core.radiation import pulse_response

    cfg = CONFIGS[name]
    pulse = paper_pulse(kind)
    pts = _fast_peak_points(cfg, 240, seed=7)
    fp = field.fast_peaks(pulse, pts, cfg)
    fm = field.field_metrics(pulse, pts, cfg)
    delay, p0, cc, _ = field.source_geometry(pts, cfg)
    scale = fm.peak
    for got, ref, when, sign in ((fp.peak_positive, fm.peak_positive, fp.time_positive, 1.0),
                                 (fp.peak_negative, fm.peak_negative, fp.time_negative, -1.0)):
        assert np.all(sign * (got - ref) >= -1e-8 * scale)
        y = pulse_response(pulse, when[:, None] - delay, radius=A)
        at = np.sum(p0 * (cc.real * y.real - cc.imag * y.imag), axis=1)
        assert np.all(np.abs(got - at) <= 1e-10 * scale)
    # nearly all agree with the sampled search to 1e-8 (it may pick a lower one of two close maxima)
    agree = (np.abs(fp.peak_positive - fm.peak_positive) <= 1e-8 * scale) & \
        (np.abs(fp.peak_negative - fm.peak_negative) <= 1e-8 * scale)
    assert agree.mean() > 0.99
    np.testing.assert_allclose(fp.exposure, field.exposure(pulse, pts, cfg), rtol=1e-11)


def test_fast_peaks_a_close_pair_of_maxima_across_a_pulse_end(paper_pulse):
    # on the corner (wall at 0.1 m) this point's largest pressure has two maxima 20 us apart, 2e-3
    # apart in height, on either side of the end of the direct sphere's pulse (closer than the coarse
    # step can separate): the higher one is found, as by a 10 ns scan of the direct sum
    cfg = images_wall_floor(A, 0.1)
    pulse = paper_pulse("hertz")
    x = np.array([[0.39843532, -0.24594647, 0.06678298]])
    fp = field.fast_peaks(pulse, x, cfg, exposure=False)
    t = np.arange(1.80e-3, 1.88e-3, 1e-8)
    dense = _direct(pulse, t, x, cfg)[0]
    assert fp.peak_positive[0] >= dense.max()
    assert fp.peak_positive[0] == pytest.approx(dense.max(), rel=1e-8)
    assert abs(fp.time_positive[0] - t[np.argmax(dense)]) < 2e-8
    assert np.isnan(fp.exposure[0])


@pytest.mark.parametrize("x", [(0.09985707895096389, -0.4222972254255243, 0.06957363500316173),
                               (0.3135862306698611, -0.17956052216627472, 0.060130762082192035),
                               (0.5430742671773279, 0.48626835580640837, 0.11677409838035327)])
@pytest.mark.slow
def test_fast_peaks_two_maxima_either_side_of_a_pulse_end(x, paper_pulse, paper_impact):
    # corner, wall at 0.1 m: at these points the largest pressure has two maxima 1.3-1.5 coarse steps
    # apart, 1e-7 to 2e-5 apart in height, on either side of the end of one image's pulse, so that
    # the coarse samples show one hump (found among 1e6 random points: the search once took the
    # lower one). The higher one is found, as by a 1 ns scan of the direct sum refined by Brent.
    from scipy.optimize import minimize_scalar

    cfg = images_wall_floor(A, 0.1)
    pulse = paper_pulse("hertz")
    pts = np.array([x])
    fp = field.fast_peaks(pulse, pts, cfg, exposure=False)
    delay = field.source_geometry(pts, cfg)[0][0]
    t = np.arange(delay.min(), delay.max() + paper_impact.duration + 10 * A / field.AIR.c, 1e-9)
    dense = _direct(pulse, t, pts, cfg)[0]
    k = int(np.argmax(dense))
    res = minimize_scalar(lambda u: -_direct(pulse, [u], pts, cfg)[0, 0], bounds=(t[k - 1], t[k + 1]),
                          method="bounded", options={"xatol": 1e-15})
    assert fp.peak_positive[0] == pytest.approx(-res.fun, rel=1e-9)
    assert abs(fp.time_positive[0] - res.x) < 2e-8


def test_fast_peaks_outside_the_fluid_and_bad_options(paper_pulse):
    cfg = CONFIGS["corner"]
    pulse = paper_pulse("hertz")
    fp = field.fast_peaks(pulse, [[0.0, 0.0, A], [0.3, 0.0, -0.01], [0.3, 0.0, 0.3]], cfg)
    assert np.all(np.isnan(fp.peak_positive[:2])) and np.all(np.isnan(fp.exposure[:2]))
    assert fp.peak_positive[2] > 0 > fp.peak_negative[2] and fp.exposure[2] > 0
    with pytest.raises(ParameterError) as err:
        field.fast_peaks(pulse, [[0.3, 0.0, 0.3]], cfg, margin=-1.0)
    assert err.value.name == "margin"
    with pytest.raises(ParameterError) as err:
        field.peak_table(pulse, cfg, samples=1)
    assert err.value.name == "samples"
    for bad in (0, -2, 1.5, True, "2"):
        with pytest.raises(ParameterError, match=">= 1") as err:
            field.fast_peaks(pulse, [[0.3, 0.0, 0.3]], cfg, workers=bad)
        assert err.value.name == "workers"


@pytest.mark.parametrize("name", ["corner", "room"])
def test_fast_peaks_gives_the_same_numbers_on_any_number_of_threads(name, paper_pulse):
    # each point's search depends on that point alone: blocks shared among threads change nothing,
    # bit for bit (the room: 129 images, the search over sorted arrivals)
    from acoustiviz.core.room_geometry import Room

    cfg = Room(A, (6.0, 4.0, 3.0), 0.1, (2.0, 1.5, A), order=4) if name == "room" else CONFIGS[name]
    pulse = paper_pulse("half-sine")
    centre = np.array([2.0, 1.5, A]) if name == "room" else np.array([0.0, 0.0, A])
    pts = np.random.default_rng(7).uniform([0.05, 0.05, 0.05], [1.5, 1.5, 1.5], (203, 3))
    pts[:3] = centre + [[0.0, 0.0, 0.0], [0.3, 0.0, 0.3], [0.2, 0.1, 0.05]]  # the first inside the sphere
    one = field.fast_peaks(pulse, pts, cfg, workers=1)
    assert np.isnan(one.peak_positive[0]) and np.all(one.exposure[1:] > 0)
    for workers, chunk in ((2, 65536), (3, 17), (2, 1)):
        many = field.fast_peaks(pulse, pts, cfg, workers=workers, chunk=chunk)
        for col in ("peak_positive", "peak_negative", "time_positive", "time_negative", "exposure", "refinements"):
            np.testing.assert_array_equal(getattr(many, col), getattr(one, col))
    for workers in (1, 2):  # progress: points done after each block, in the calling thread, up to all of them
        calls = []

        def report(done, total, calls=calls):
            calls.append((done, total, threading.get_ident()))

        told = field.fast_peaks(pulse, pts, cfg, workers=workers, progress=report)
        np.testing.assert_array_equal(told.exposure, one.exposure)
        done = [c[0] for c in calls]
        assert len(calls) >= 3 and done[-1] == len(pts) and np.all(np.diff(done) > 0)
        assert {c[1] for c in calls} == {len(pts)} and {c[2] for c in calls} == {threading.get_ident()}


def test_fast_peaks_a_pulse_that_ends_abruptly(paper_pulse):
    # a sampled pulse cut off at 0.81 of its height: A jumps to zero at each image's pulse end, so p'
    # jumps there and a maximum may sit on that cusp (the breakpoint candidates are searched); the
    # peaks agree with field_metrics' sampled search refined on the closed form to 1e-8 of the peak
    from acoustiviz.core.contact import SampledPulse

    cfg = CONFIGS["corner"]
    tau = paper_pulse("half-sine").duration
    t = np.linspace(0.0, 0.7 * tau, 200)
    pulse = SampledPulse(t, 9800.0 * np.sin(np.pi * t / tau))
    pts = _fast_peak_points(cfg, 120, seed=3)
    fp = field.fast_peaks(pulse, pts, cfg, exposure=False)
    fm = field.field_metrics(pulse, pts, cfg)
    scale = fm.peak
    assert np.all(fp.peak_positive - fm.peak_positive >= -1e-8 * scale)
    assert np.all(fm.peak_negative - fp.peak_negative >= -1e-8 * scale)
    agree = (np.abs(fp.peak_positive - fm.peak_positive) <= 1e-8 * scale) & \
        (np.abs(fp.peak_negative - fm.peak_negative) <= 1e-8 * scale)
    assert agree.mean() > 0.95


def test_waveform_spans_are_the_spans_of_each_point(paper_pulse):
    cfg = CONFIGS["corner"]
    pulse = paper_pulse("hertz")
    pts = _points(cfg, n=12, seed=4)
    spans = field.waveform_spans(pulse, pts, cfg)
    assert spans.shape == (pts.shape[0], 2)
    for p, (first, end) in zip(pts, spans, strict=True):
        # first arrival: the nearest of the sphere and its images, (r - a)/c from its centre
        r = min(np.linalg.norm(p - s.position) for s in cfg.sources)
        assert first == pytest.approx((r - A) / field.AIR.c, rel=1e-12)
        assert (first, end) == field.waveform_span(pulse, p, cfg)


@pytest.mark.slow
def test_fast_peaks_far_from_a_wall_sample_only_the_arrivals(paper_pulse):
    # a wall 3 m away: the arrivals come 17 ms apart and the coarse pass samples only each arrival
    # and its decay (the free decay between them is taken in closed form); the peaks agree with
    # field_metrics' sampled search refined on the closed form, which samples the whole response
    cfg = images_wall_floor(A, 3.0)
    for kind in ("hertz", "half-sine"):
        pulse = paper_pulse(kind)
        pts = np.random.default_rng(8).uniform([-2.9, -1.0, 0.0], [1.0, 1.0, 1.5], (60, 3))
        pts = pts[cfg.in_fluid(pts)]
        fp = field.fast_peaks(pulse, pts, cfg)
        fm = field.field_metrics(pulse, pts, cfg)
        assert np.all(np.abs(fp.peak_positive - fm.peak_positive) <= 1e-8 * fm.peak)
        assert np.all(np.abs(fp.peak_negative - fm.peak_negative) <= 1e-8 * fm.peak)
        np.testing.assert_allclose(fp.exposure, field.exposure(pulse, pts, cfg), rtol=1e-12)


@pytest.mark.parametrize("t_b", [np.inf, 2.3e-4, 9e-5])
def test_decay_extremes_of_the_free_decay_on_an_interval(t_b):
    # the extremes of the images' free decay between two arrivals, against a 1 ns scan of the sum
    from acoustiviz.core.radiation import sphere_pole
    from acoustiviz.field._peak_kernels import _decay_extremes

    s = sphere_pole(A, field.AIR)
    delays = np.array([0.0, 1.3e-5, 4e-5, 5e-4])  # the last has not arrived by t_b
    rng = np.random.default_rng(2)
    are, aim = rng.normal(size=4), rng.normal(size=4)
    yend, end, t_a = 0.3 - 0.2j, 2e-5, 7e-5
    hi, thi, lo, tlo = _decay_extremes(t_a, t_b, t_a, 4, delays, are, aim, yend, end, s)
    t = np.arange(t_a, min(t_b, t_a + 2e-3) + 5e-13, 1e-9)
    p = sum(((are[j] + 1j * aim[j]) * yend * np.exp(s * (t - delays[j] - end))).real for j in range(3))
    assert hi == pytest.approx(p.max(), rel=1e-9, abs=1e-12 * np.abs(p).max())
    assert lo == pytest.approx(p.min(), rel=1e-9, abs=1e-12 * np.abs(p).max())
    assert t_a <= thi <= t_b and t_a <= tlo <= t_b


@pytest.mark.parametrize("kind", ["hertz", "half-sine"])
@pytest.mark.parametrize("config", ["plane", "wall-floor"])
@pytest.mark.slow
def test_rms_is_over_the_exact_window_not_one_rounded_to_whole_samples(kind, config):
    # RMS^2 x window is the exposure of the whole response, which field.exposure integrates in
    # closed form without a time grid (an independent route): with the window rounded up to whole
    # samples of the default step the RMS was 2e-4 to 8e-4 low
    imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=0.2264)
    pulse = acceleration_pulse(imp, kind)
    g = av_geometry(config, 0.01905, **({"wall_distance": 0.3} if config == "wall-floor" else {}))
    th = np.radians([0.0, 30.0, 45.0, 60.0, 85.0])
    pts = np.c_[0.7 * np.sin(th), 0 * th, 0.01905 + 0.7 * np.cos(th)]
    fm = field.field_metrics(pulse, pts, g)
    start, stop = field.arrival_windows(pulse, pts, g)
    assert fm.window == pytest.approx(float(np.max(stop - start)), rel=1e-15)
    assert fm.window / fm.sample_interval == pytest.approx(round(fm.window / fm.sample_interval), abs=1e-6)
    exact = np.sqrt(field.exposure(pulse, pts, g) / fm.window)
    np.testing.assert_allclose(fm.rms, exact, rtol=1e-6)


@pytest.mark.parametrize("kind", ["hertz", "half-sine"])
@pytest.mark.slow
def test_fast_peaks_reuses_its_tables_across_calls(kind, paper_impact):
    # the observer-independent tables are built once per pulse, configuration and medium: a second
    # call with equal (not identical) arguments hits the cache and gives the same numbers as the
    # tables passed explicitly; the result's columns share one buffer (no second copy)
    from acoustiviz.field import peaks

    cfg = CONFIGS["corner"]
    pts = _fast_peak_points(cfg, 40, seed=3)
    peaks._observer_tables.cache_clear()
    first = field.fast_peaks(acceleration_pulse(paper_impact, kind), pts, cfg)
    again = field.fast_peaks(acceleration_pulse(paper_impact, kind), pts, cfg)
    info = peaks._observer_tables.cache_info()
    assert (info.hits, info.misses) == (1, 1)
    pulse = acceleration_pulse(paper_impact, kind)
    explicit = field.fast_peaks(pulse, pts, cfg, table=field.peak_table(pulse, cfg),
                                correlations=field.pulse_correlations(pulse, A))
    for name in ("peak_positive", "peak_negative", "time_positive", "time_negative", "exposure", "refinements"):
        np.testing.assert_array_equal(getattr(again, name), getattr(first, name))
        np.testing.assert_array_equal(getattr(explicit, name), getattr(first, name))
    assert first.peak_positive.base is not None and first.peak_positive.base is first.exposure.base
    slower = Impact(velocity=0.7, k_hertz=5.6e8, mass=paper_impact.mass)
    other = field.fast_peaks(acceleration_pulse(slower, kind), pts, cfg)
    assert peaks._observer_tables.cache_info().misses == 2  # another pulse builds its own tables
    assert np.all(other.peak < first.peak)
