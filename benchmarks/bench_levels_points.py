"""Speed and agreement of the weighted levels per observer point (weighted balloons and directivities).

Run ``python benchmarks/bench_levels_points.py`` (``--quick``: a 12-node balloon; ``--pulse hertz``).
The paper's click (19.05 mm steel sphere at 1.4 m/s) in the three configurations.

1. Where the time goes: one chunk of 64 balloon points, each stage of the full-interval computation
   (the closed form at L x 96 kHz, its decimation, the A and C weightings and the F and S time
   weightings over 96 000 samples, the statistics) and of the fast one (the same closed form, FFT
   decimation of the sound only, the transient levels).
2. Old against new on the same points, side by side in one run: the default balloon (32 polar
   nodes at 0.7 m, 64 points a chunk as the balloon takes them) and a 181-angle directivity at
   0.7 m (1 deg steps in free field, 0.5 deg over the quarter circle of the plane and the corner).
   ``old`` is :func:`acoustiviz.sound.impact_levels.reference_metric_levels` (``impact_signals`` over 1 s and
   ``sound_levels``), which computes all eight levels whichever is asked, so it is timed once per
   view and configuration; ``new`` is :func:`acoustiviz.sound.impact_levels.points_metric_levels` for that
   metric alone (``all 8``: the eight from one sound). ``max |dL|`` is the largest difference in dB
   between the two over the points.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _timing import best_of

from acoustiviz.app.impacts import impact_setup
from acoustiviz.app.views import directivity_angles
from acoustiviz.constants import ANALYSIS_RATE
from acoustiviz.core.signal import Signal
from acoustiviz.field import directivity, time_series, waveform_span
from acoustiviz.field.balloon import balloon_data
from acoustiviz.levels import METRICS, sound_levels
from acoustiviz.levels.transient import transient_levels
from acoustiviz.sound.impact_levels import points_metric_levels, reference_metric_levels

CONFIGS = ("free", "plane", "wall-floor")


def _setup(config, pulse):
    return impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config=config, pulse=pulse)


def balloon_points(s, n_theta: int) -> np.ndarray:
    """The points a weighted balloon of ``n_theta`` polar nodes at 0.7 m evaluates its level at."""
    seen = {}

    def grab(points):
        seen["points"] = np.asarray(points, dtype=float)
        return np.zeros(len(points))

    balloon_data(s.pulse, s.geometry, medium=s.medium, distance=0.7, n_theta=n_theta, levels=(grab, "level"))
    return seen["points"]


def directivity_points(s) -> np.ndarray:
    step = 1.0 if s.geometry.name == "free" else 0.5
    d = directivity(s.pulse, s.geometry, 0.7, directivity_angles(s.geometry, step), medium=s.medium)
    return np.asarray(d.points, dtype=float)


def part_stages(pulse: str, repeat: int) -> None:
    from scipy.signal import fftconvolve, upfirdn

    from acoustiviz.levels._library import library
    from acoustiviz.levels.weighted import weighted
    from acoustiviz.sound import decimation_filter, oversampling_factor

    s = _setup("plane", pulse)
    pts = balloon_points(s, 32)[:64]
    fs = ANALYSIS_RATE
    print(f"\n1. stages for one chunk of 64 balloon points (plane, {pulse}), best of {repeat}, ms")
    t_span, spans = best_of(lambda: np.array([waveform_span(s.pulse, p, s.geometry, medium=s.medium)
                                              for p in pts]), repeat)
    L = oversampling_factor(fs, s.pulse.duration)
    h = decimation_filter(L)
    K = (h.size - 1) // (2 * L)
    t0 = np.floor(spans[:, 0].min() * fs) / fs
    n_sound = int(np.ceil((spans[:, 1].max() - t0) * fs)) + 1
    t = t0 + np.arange(n_sound * L) / (L * fs)
    t_ts, hi = best_of(lambda: time_series(s.pulse, t, pts, s.geometry, medium=s.medium), repeat)
    t_up, low = best_of(lambda: upfirdn(h, hi, up=1, down=L, axis=1)[:, K:K + n_sound + K], repeat)
    t_fft, _ = best_of(lambda: fftconvolve(hi, h[None, :], axes=1)[:, K * L:(2 * K + n_sound) * L:L], repeat)
    p = np.zeros((pts.shape[0], fs))
    p[:, :low.shape[1]] = low
    t_a, pa = best_of(lambda: weighted(Signal(p, fs), "A").pressure, repeat)
    t_c, _ = best_of(lambda: weighted(Signal(p, fs), "C"), repeat)
    t_f, _ = best_of(lambda: library().time_weighting(pa, fs, mode="fast"), repeat)
    t_s, _ = best_of(lambda: library().time_weighting(pa, fs, mode="slow"), repeat)
    t_all, _ = best_of(lambda: sound_levels(Signal(p, fs)), repeat)
    t_tr, _ = best_of(lambda: transient_levels(low, fs, fs, list(METRICS)), repeat)
    print(f"   L = {L}, {h.size} decimation taps, {n_sound * L} samples at {L * fs / 1e6:g} MHz, "
          f"{low.shape[1]} of {fs} samples at {fs / 1e3:g} kHz hold sound")
    rows = [("waveform_span, 64 points", t_span, t_span), (f"time_series at {L} x 96 kHz", t_ts, t_ts),
            ("decimation: upfirdn | FFT", t_up, t_fft), ("A weighting, 96 000 samples", t_a, None),
            ("C weighting, 96 000 samples", t_c, None), ("F time weighting", t_f, None),
            ("S time weighting", t_s, None),
            ("all 8 levels: sound_levels | transient", t_all, t_tr)]
    print(f"   {'stage':>40} {'old (ms)':>9} {'new (ms)':>9}")
    for name, old, new in rows:
        print(f"   {name:>40} {old * 1e3:9.1f} {'' if new is None else f'{new * 1e3:9.1f}':>9}")


def _max_diff(a, b) -> float:
    both = np.isfinite(a) & np.isfinite(b)
    if not np.array_equal(np.isfinite(a), np.isfinite(b)):
        return float("inf")
    return float(np.max(np.abs(a[both] - b[both]))) if both.any() else 0.0


def part_compare(pulse: str, n_theta: int, repeat: int) -> None:
    print(f"\n2. old (full 1 s interval) against new (sound + exact tails), {pulse} pulse")
    hdr = f"{'view':>11} {'config':>10} {'points':>6} {'metric':>7} {'old (s)':>8} {'new (s)':>8} {'ratio':>6} " \
          f"{'max |dL| (dB)':>13}"
    print(hdr)
    print("-" * len(hdr))
    metrics = list(METRICS)
    for view in ("balloon", "directivity"):
        for config in CONFIGS:
            s = _setup(config, pulse)
            pts = balloon_points(s, n_theta) if view == "balloon" else directivity_points(s)
            chunk = 64 if view == "balloon" else None
            args = (s.pulse, pts, s.geometry, s.medium)
            points_metric_levels(metrics, s.pulse, pts[:4], s.geometry, s.medium)  # warm caches
            t_old, ref = best_of(lambda a=args, c=chunk: reference_metric_levels(metrics, *a, chunk=c),
                                 1 if view == "balloon" else repeat)
            for m in [*metrics, "all 8"]:
                names = metrics if m == "all 8" else [m]
                t_new, new = best_of(lambda a=args, c=chunk, n=names: points_metric_levels(n, *a, chunk=c), repeat)
                diff = max(_max_diff(new[k], ref[k]) for k in names)
                print(f"{view:>11} {config:>10} {pts.shape[0]:>6} {m:>7} {t_old:8.2f} {t_new:8.3f} "
                      f"{t_old / t_new:6.1f} {diff:13.1e}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a 12-node balloon and one repeat")
    parser.add_argument("--pulse", choices=("half-sine", "hertz"), default="half-sine", help="the click's pulse")
    parser.add_argument("--repeat", type=int, default=2, help="timed repeats of the fast path (default 2)")
    args = parser.parse_args(argv)
    repeat = 1 if args.quick else max(1, args.repeat)
    t0 = time.perf_counter()
    part_stages(args.pulse, 3)
    part_compare(args.pulse, 12 if args.quick else 32, repeat)
    print(f"\n(total {time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
