"""Speed and accuracy of the field evaluator: each configuration x pulse, then scaling and memory.

Run ``python benchmarks/bench_field.py`` (or ``--quick``; ``--write`` also keeps the output in
``benchmarks/results/bench_field.txt``, machine and date first). The scene is the paper's Figure 2
impact (a = 19.05 mm steel sphere, 1.4 m/s, K = 5.6e8 N/m^1.5). The first table times
``field_metrics`` (peak refined, RMS, SEL; default windows) and ``time_series`` on the same points
for the free field, the plane and the wall-floor corner with the half-sine, the exact Hertz pulse
and the Hertz pulse sampled at 1025 points and interpolated linearly (the former default), all
in one run, and measures each row against adaptive quadrature (SciPy ``quad`` of paper eq 11
times the closed-form pulse): the largest error of ``time_series`` over a few points and times,
and of the refined peak (a bounded search on the quadrature itself), relative to the peak.
A third table times ``field.fast_peaks`` (positive and negative peaks and SEL with no time loop)
on 1e6 corner points against the refined ``field_metrics`` on a subset (``--peaks-only``: that
table alone). The last table is the half-sine on the plane from 1e3 to 1e6 points against a
per-point numerical convolution. A *point-sample* is the pressure at one point and one time (all images
summed). The evaluator runs on one thread; times are CPU seconds of this process.
"""

from __future__ import annotations

import argparse
import math
import tracemalloc
import warnings

import numpy as np
from _timing import cpu_best_of, run_writing
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from acoustiviz import field
from acoustiviz.core import approximations
from acoustiviz.core.contact import HERTZ_DURATION_CONSTANT, Impact, SampledPulse, acceleration_pulse, hertz_pulse_shape
from acoustiviz.core.geometry import geometry, images_plane
from acoustiviz.core.medium import AIR
from acoustiviz.field import _closed
from acoustiviz.field.grids import planar_grid

A = 0.01905


def _compile_kernels(*calls):
    """Run ``calls`` on the compiled kernels (small requests are otherwise summed in numpy): compile outside timings."""
    small, _closed.SMALL_WORK = _closed.SMALL_WORK, 0
    try:
        for call in calls:
            call()
    finally:
        _closed.SMALL_WORK = small


def _scene():
    pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * A**3))
    return pulse, images_plane(A)


def _grid(n):
    side = int(round(np.sqrt(n)))
    g = planar_grid((0.5, 0.0, 0.55), (0.9, 0.0, 0.0), (0.0, 0.9, 0.9), n_u=side, n_v=side)
    return g.points


def _exact_acceleration(kind, imp):
    """The pulse written out independently of the library's pulse objects (m/s^2 at t in s)."""
    tau = imp.duration
    if kind == "half-sine":
        return lambda t: imp.peak_acceleration * math.sin(math.pi * t / tau) if 0 <= t <= tau else 0.0
    return lambda t: imp.peak_acceleration * float(hertz_pulse_shape(t * HERTZ_DURATION_CONSTANT / tau))


def _quad_pressure(acc, tau, t, x, cfg):
    """Pressure in Pa at point x, time t: sum over images of int h(t - d - xi) A(xi) dxi (eq 11) by quad."""
    lam = AIR.c / A
    total = 0.0
    for src in cfg.sources:
        d = x - src.position
        r = float(np.linalg.norm(d))
        ct = float(d @ src.axis) / r
        tp = t - (r - A) / AIR.c
        hi, lo = min(tp, tau), max(0.0, tp - 80 / lam)
        if hi <= lo:
            continue
        amp = AIR.rho * AIR.c * A * A * ct / r**2

        def f(xi, tp=tp, r=r, amp=amp):
            u = tp - xi
            return amp * ((1 - r / A) * math.sin(lam * u) + r / A * math.cos(lam * u)) * math.exp(-lam * u) * acc(xi)

        edges = np.linspace(lo, hi, 9)
        total += sum(quad(f, e0, e1, limit=200, epsabs=0, epsrel=1e-12)[0]
                     for e0, e1 in zip(edges[:-1], edges[1:], strict=True))
    return total


def _accuracy(kind, pulse, imp, cfg, pts):
    """Largest error of time_series and of the refined peaks against quadrature, relative to the peak."""
    acc = _exact_acceleration(kind, imp)
    fm = field.field_metrics(pulse, pts, cfg)
    err_s, err_p = 0.0, 0.0
    for i, x in enumerate(pts):
        t0 = fm.window_start[i]
        tt = t0 + np.linspace(0.0, imp.duration + 6 * A / AIR.c, 13)
        ref = np.array([_quad_pressure(acc, imp.duration, t, x, cfg) for t in tt])
        got = field.time_series(pulse, tt, x[None, :], cfg)[0]
        # the peak: the extreme of a 20x denser series, then a bounded search on the quadrature itself
        dense_t = t0 + np.arange(0.0, fm.window, fm.sample_interval / 20)
        dense = field.time_series(pulse, dense_t, x[None, :], cfg)[0]
        k = int(np.argmax(np.abs(dense)))
        sign = math.copysign(1.0, dense[k])
        lo, hi = dense_t[max(k - 1, 0)], dense_t[min(k + 1, dense_t.size - 1)]
        res = minimize_scalar(lambda t, x=x, sign=sign: -sign * _quad_pressure(acc, imp.duration, t, x, cfg),
                              bounds=(lo, hi), method="bounded", options={"xatol": 1e-13})
        peak = -res.fun
        err_s = max(err_s, float(np.max(np.abs(got - ref))) / peak)
        err_p = max(err_p, abs(fm.peak[i] / peak - 1))
    return err_s, err_p


def _cpu_best_of(f, repeat: int) -> float:
    """Shortest CPU time in s of this process over ``repeat`` calls (steadier than wall time on a shared machine)."""
    return cpu_best_of(f, repeat)[0]


def pulse_table(quick: bool) -> None:
    """Throughput of each configuration x pulse, the ratio to the half-sine, and accuracy against quadrature."""
    from scipy.integrate import IntegrationWarning

    warnings.simplefilter("ignore", IntegrationWarning)  # quad's round-off notes at the 1e-13 level
    imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * A**3)
    hertz = acceleration_pulse(imp, "hertz")
    pulses = {"half-sine": acceleration_pulse(imp, "half-sine"), "hertz": hertz,
              "hertz-1025-linear": SampledPulse(hertz.times, hertz.acceleration_samples, "sampled")}
    n = 5_000 if quick else 40_000
    ns_max = 2_000
    rng = np.random.default_rng(0)
    print(f"{n:,} random points per configuration for field_metrics, the first {ns_max:,} for time_series "
          f"(4 ms at 64 samples per a/c); CPU s, best of 3; "
          f"tau = {imp.duration * 1e6:.1f} us, a/c = {A / AIR.c * 1e6:.1f} us")
    hdr = (f"{'config':>10} {'pulse':>18} {'metrics s':>10} {'points/s':>10} {'x half-sine':>11} "
           f"{'series s':>9} {'x half-sine':>11} {'series err':>11} {'peak err':>9}")
    print(hdr)
    print("-" * len(hdr))
    for name in ("free", "plane", "wall-floor"):
        cfg = geometry(name, A, wall_distance=0.1) if name == "wall-floor" else geometry(name, A)
        pts = rng.uniform([0.05, -0.5, 0.05], [1.0, 0.5, 1.0], (n, 3))
        pts = pts[cfg.in_fluid(pts)]
        t = np.arange(0.0, 4e-3, field.default_sample_interval(pulses["half-sine"], A))
        ns = min(pts.shape[0], ns_max)
        base_m = base_s = None
        for kind, pulse in pulses.items():
            _compile_kernels(lambda pulse=pulse, cfg=cfg, pts=pts: field.field_metrics(pulse, pts[:10], cfg),
                             lambda pulse=pulse, cfg=cfg, pts=pts, t=t: field.time_series(pulse, t, pts[:10], cfg))
            el_m = _cpu_best_of(lambda pulse=pulse, cfg=cfg, pts=pts: field.field_metrics(pulse, pts, cfg), 3)
            el_s = _cpu_best_of(lambda pulse=pulse, cfg=cfg, sub=pts[:ns], t=t: field.time_series(pulse, t, sub, cfg),
                                3)
            base_m, base_s = (el_m, el_s) if base_m is None else (base_m, base_s)
            exact_kind = "half-sine" if kind == "half-sine" else "hertz"
            err_s, err_p = _accuracy(exact_kind, pulse, imp, cfg, pts[:2] if quick else pts[:3])
            print(f"{name:>10} {kind:>18} {el_m:10.3f} {pts.shape[0] / el_m:10.3e} {el_m / base_m:11.2f} "
                  f"{el_s:9.3f} {el_s / base_s:11.2f} {err_s:11.1e} {err_p:9.1e}")
    print()


def exposure_table(quick: bool) -> None:
    """Exposure of the whole response with no time grid (field.exposure) on the corner, against field_metrics."""
    imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * A**3)
    cfg = geometry("wall-floor", A, wall_distance=0.1)
    n = 100_000 if quick else 1_000_000
    pts = np.random.default_rng(1).uniform([0.05, -0.5, 0.05], [1.0, 0.5, 1.0], (n, 3))
    print(f"exposure (SEL) of the whole response without a time grid, wall-floor corner, {n:,} points "
          "(CPU s, best of 3)")
    hdr = (f"{'pulse':>10} {'setup s':>8} {'exposure s':>11} {'points/s':>10} "
           f"{'vs field_metrics (dt = a/c/256)':>32}")
    print(hdr)
    print("-" * len(hdr))
    for kind in ("half-sine", "hertz"):
        pulse = acceleration_pulse(imp, kind)
        field.exposure(pulse, pts[:10], cfg)  # compile
        setup = _cpu_best_of(lambda pulse=pulse: field.pulse_correlations(pulse, A), 1)
        corr = field.pulse_correlations(pulse, A)
        el = _cpu_best_of(lambda pulse=pulse, corr=corr: field.exposure(pulse, pts, cfg, correlations=corr), 3)
        e = field.exposure(pulse, pts[:500], cfg, correlations=corr)
        fm = field.field_metrics(pulse, pts[:500], cfg, sample_interval=A / AIR.c / 256)
        err = float(np.max(np.abs(e / fm.exposure - 1)))
        print(f"{kind:>10} {setup:8.3f} {el:11.3f} {n / el:10.3e} {err:32.1e}")
    print()


def _second_search(pulse, pts, cfg, fp):
    """Peaks where a second search (another coarse step) differs from ``fp``, and how many of ``fp``'s are low.

    Each disagreement is settled by scanning the closed form (paper eqs 12-14 summed over the images)
    at 0.2 ns around both reported times.
    """
    from acoustiviz.core.radiation import pulse_response

    other = field.fast_peaks(pulse, pts, cfg, exposure=False, table=field.peak_table(pulse, cfg, samples=17, fine=64))
    differ = missed = 0
    for sign, name, when in ((1.0, "peak_positive", "time_positive"), (-1.0, "peak_negative", "time_negative")):
        a, b = getattr(fp, name), getattr(other, name)
        for i in np.nonzero(np.abs(a - b) > 1e-9 * fp.peak)[0]:
            differ += 1
            t0, t1 = sorted((getattr(fp, when)[i], getattr(other, when)[i]))
            t = np.arange(t0 - 2e-5, t1 + 2e-5, 2e-10)
            delay, p0, cc, _ = field.source_geometry(pts[i:i + 1], cfg)
            y = pulse_response(pulse, t[:, None] - delay[0][None, :], radius=A)
            best = float(np.max(sign * np.sum(p0[0] * (cc[0].real * y.real - cc[0].imag * y.imag), axis=1)))
            missed += int(best - sign * a[i] > 1e-9 * fp.peak[i])
    return differ, missed


def fast_peaks_table(quick: bool) -> None:
    """Peaks and SEL on the corner without a time loop (field.fast_peaks), against the refined field_metrics."""
    imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * A**3)
    cfg = geometry("wall-floor", A, wall_distance=0.1)
    n = 100_000 if quick else 1_000_000
    pts = np.random.default_rng(1).uniform([0.05, -0.5, 0.05], [1.0, 0.5, 1.0], (n, 3))
    nsub = 2_000
    print(f"peak (positive and negative) + SEL without a time loop (field.fast_peaks), wall-floor corner, {n:,} "
          f"points; CPU s of one thread (numba kernels, not parallel), best of 2; error against field_metrics "
          f"(refined peaks, exposure of field.exposure) on the first {nsub:,}")
    hdr = (f"{'pulse':>10} {'setup s':>8} {'peak+SEL s':>11} {'total s':>8} {'points/s':>10} {'refined/pt':>10} "
           f"{'peak err':>9} {'above fm':>9} {'SEL err':>8} {'field_metrics s':>16} {'2nd differs':>11} "
           f"{'missed':>7}")
    print(hdr)
    print("-" * len(hdr))
    for kind in ("hertz", "half-sine"):
        pulse = acceleration_pulse(imp, kind)
        field.fast_peaks(pulse, pts[:10], cfg)  # compile
        setup = _cpu_best_of(lambda pulse=pulse: (field.peak_table(pulse, cfg), field.pulse_correlations(pulse, A)),
                             1)
        tb, corr = field.peak_table(pulse, cfg), field.pulse_correlations(pulse, A)
        el = _cpu_best_of(lambda pulse=pulse, tb=tb, corr=corr: field.fast_peaks(pulse, pts, cfg, table=tb,
                                                                                  correlations=corr), 2)
        fp = field.fast_peaks(pulse, pts[:nsub], cfg, table=tb, correlations=corr)
        el_fm = _cpu_best_of(lambda pulse=pulse: field.field_metrics(pulse, pts[:nsub], cfg), 1)
        fm = field.field_metrics(pulse, pts[:nsub], cfg)
        dpos = (fp.peak_positive - fm.peak_positive) / fm.peak
        dneg = (fm.peak_negative - fp.peak_negative) / fm.peak
        err = float(max(np.abs(dpos).max(), np.abs(dneg).max()))
        above = int(np.sum((dpos > 1e-8) | (dneg > 1e-8)))  # field_metrics' sampled search took a lower maximum
        sel = float(np.max(np.abs(fp.exposure / field.exposure(pulse, pts[:nsub], cfg, correlations=corr) - 1)))
        refs = float(np.mean(fp.refinements))
        differ, missed = _second_search(pulse, pts, cfg, field.fast_peaks(pulse, pts, cfg, table=tb, exposure=False))
        print(f"{kind:>10} {setup:8.3f} {el:11.3f} {setup + el:8.3f} {n / el:10.3e} {refs:10.2f} {err:9.1e} "
              f"{above:9d} {sel:8.1e} {el_fm * n / nsub:15.1f}* {differ:11d} {missed:7d}")
    print("  setup: the pulse's tables (field.peak_table, field.pulse_correlations), once per pulse and "
          "configuration; total = setup + peak+SEL")
    print("  2nd differs: peaks (of either sign, all points) where a second search with another coarse step (17 per "
          "min(T, a/c), delays rounded to 1/64 of it) differs by more than 1e-9 of the peak; missed: those where a "
          "0.2 ns scan of the closed form shows the default search low by more than 1e-9")
    print("  * field_metrics time extrapolated from the subset; 'above fm': points where fast_peaks found a higher "
          "maximum than field_metrics (peak err then counts that difference)")
    print()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true",
                        help="also write the output to benchmarks/results/bench_field.txt (machine and date first)")
    parser.add_argument("--quick", action="store_true", help="small grids only (seconds)")
    parser.add_argument("--pulses-only", action="store_true", help="only the configuration x pulse table")
    parser.add_argument("--peaks-only", action="store_true", help="only the fast peak + SEL table")
    args = parser.parse_args(argv)
    if args.peaks_only:
        fast_peaks_table(args.quick)
        return 0
    pulse_table(args.quick)
    exposure_table(args.quick)
    fast_peaks_table(args.quick)
    if args.pulses_only:
        return 0
    pulse, cfg = _scene()
    dt = field.default_sample_interval(pulse, A)
    sizes = [1_000, 10_000] if args.quick else [1_000, 10_000, 100_000, 1_000_000]
    _compile_kernels(lambda: field.field_metrics(pulse, _grid(100), cfg),
                     lambda: field.time_series(pulse, np.arange(0, 1e-3, dt), _grid(100), cfg))
    approximations.convolution_pressure(pulse, np.arange(0, 1e-3, dt), 0.5, 0.5, radius=A, step=dt)  # warm up

    print(
        f"scene: plane, a = {A * 1e3:g} mm, pulse {pulse.kind} tau = {pulse.duration * 1e6:.1f} us, "
        f"dt = {dt * 1e9:.1f} ns, window per point = whole non-zero response; CPU s, best of 2 (1 at 1e6 points)"
    )
    hdr = (
        f"{'points':>9} {'samples/pt':>10} {'metrics s':>10} {'metrics pt-samp/s':>18} "
        f"{'series pt-samp/s':>17} {'convolution pt-samp/s':>22} {'speed-up':>9}"
    )
    print(hdr)
    print("-" * len(hdr))
    for n in sizes:
        pts = _grid(n)
        el, fm = cpu_best_of(lambda pts=pts: field.field_metrics(pulse, pts, cfg), 1 if n >= 1e6 else 2)
        m = int(round(fm.window / fm.sample_interval))
        rate = pts.shape[0] * m / el
        # time series on a shared grid, for at most 5 000 points (the result must fit in memory)
        ns = min(pts.shape[0], 5_000)
        t = np.arange(0.0, 4e-3, dt)
        el_s, _ = cpu_best_of(lambda ns=ns, t=t, pts=pts: field.time_series(pulse, t, pts[:ns], cfg), 2)
        rate_s = ns * t.size / el_s
        # the straightforward method: per point and image, convolve the sampled pulse and kernel
        nc = 20
        t_conv = np.arange(m) * dt

        def conv(pts=pts, t_conv=t_conv, nc=nc):
            for x in pts[:nc]:
                p = np.zeros(t_conv.size)
                for s in cfg.sources:
                    d = x - s.position
                    r = float(np.linalg.norm(d))
                    tt = t_conv + field.source_geometry(x, cfg)[0].min()
                    p += approximations.convolution_pressure(pulse, tt, r, float(d @ s.axis) / r, radius=A, step=dt)
            return p

        el_c, _ = cpu_best_of(conv, 2)
        rate_c = nc * m / el_c
        print(f"{pts.shape[0]:9d} {m:10d} {el:10.3f} {rate:18.3e} {rate_s:17.3e} {rate_c:22.3e} {rate / rate_c:9.0f}")

    n_mem = 100_000 if args.quick else 1_000_000
    pts = _grid(n_mem)
    cap = field.DEFAULT_MEMORY_LIMIT
    tracemalloc.start()
    tracemalloc.reset_peak()
    field.field_metrics(pulse, pts, cfg, memory_limit=cap)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print()
    print(
        f"peak memory of field_metrics on {pts.shape[0]:,} points (tracemalloc, inputs excluded): "
        f"{peak / 2**20:.1f} MiB; cap {cap / 2**20:.0f} MiB -> {'within' if peak <= cap else 'OVER'} the cap"
    )
    small = 64 * 2**20
    tracemalloc.start()
    tracemalloc.reset_peak()
    field.field_metrics(pulse, pts, cfg, memory_limit=small)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(
        f"same with memory_limit = {small / 2**20:.0f} MiB: peak {peak / 2**20:.1f} MiB -> "
        f"{'within' if peak <= small else 'OVER'} the cap"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(run_writing("bench_field", main))
