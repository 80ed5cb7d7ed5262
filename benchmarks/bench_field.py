"""Speed and memory of the field evaluator against a per-point numerical convolution.

Run ``python benchmarks/bench_field.py`` (or ``--quick``). The scene is the paper's Figure 2
impact (a = 19.05 mm steel sphere, 1.4 m/s, K = 5.6e8 N/m^1.5, half-sine pulse) on a rigid
plane; observers fill a planar grid 0.05-1 m from the contact point. A *point-sample* is the
pressure at one point and one time (all images summed). The evaluator runs on one thread.
"""

from __future__ import annotations

import argparse
import tracemalloc

import numpy as np
from _timing import best_of

from acoustiviz import field
from acoustiviz.core import approximations
from acoustiviz.core.contact import Impact, acceleration_pulse
from acoustiviz.core.images import images_plane
from acoustiviz.field.grids import planar_grid

A = 0.01905


def _scene():
    pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * A**3))
    return pulse, images_plane(A)


def _grid(n):
    side = int(round(np.sqrt(n)))
    g = planar_grid((0.5, 0.0, 0.55), (0.9, 0.0, 0.0), (0.0, 0.9, 0.9), n_u=side, n_v=side)
    return g.points


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small grids only (seconds)")
    args = parser.parse_args(argv)
    pulse, cfg = _scene()
    dt = field.default_sample_interval(pulse, A)
    sizes = [1_000, 10_000] if args.quick else [1_000, 10_000, 100_000, 1_000_000]
    field.field_metrics(pulse, _grid(100), cfg)  # compile the kernels outside the timings
    field.time_series(pulse, np.arange(0, 1e-3, dt), _grid(100), cfg)
    approximations.convolution_pressure(pulse, np.arange(0, 1e-3, dt), 0.5, 0.5, radius=A, step=dt)  # warm up

    print(
        f"scene: plane, a = {A * 1e3:g} mm, pulse {pulse.kind} tau = {pulse.duration * 1e6:.1f} us, "
        f"dt = {dt * 1e9:.1f} ns, window per point = whole non-zero response"
    )
    hdr = (
        f"{'points':>9} {'samples/pt':>10} {'metrics s':>10} {'metrics pt-samp/s':>18} "
        f"{'series pt-samp/s':>17} {'convolution pt-samp/s':>22} {'speed-up':>9}"
    )
    print(hdr)
    print("-" * len(hdr))
    for n in sizes:
        pts = _grid(n)
        el, fm = best_of(lambda pts=pts: field.field_metrics(pulse, pts, cfg), 1 if n >= 1e6 else 2)
        m = int(round(fm.window / fm.sample_interval))
        rate = pts.shape[0] * m / el
        # time series on a shared grid, for at most 5 000 points (the result must fit in memory)
        ns = min(pts.shape[0], 5_000)
        t = np.arange(0.0, 4e-3, dt)
        el_s, _ = best_of(lambda ns=ns, t=t, pts=pts: field.time_series(pulse, t, pts[:ns], cfg), 2)
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

        el_c, _ = best_of(conv, 2)
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
    raise SystemExit(main())
