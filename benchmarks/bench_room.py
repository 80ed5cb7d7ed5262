"""Speed of the shoebox room's image sources, and pyroomacoustics' impulse responses of the same room.

Run ``python benchmarks/bench_room.py`` (``--quick``: orders to 10 and 1e3 receivers; ``--write``:
also save the output in ``benchmarks/results/bench_room.txt``).

1. Image construction (:func:`acoustiviz.core.room.image_sources`) by order 1..30 in a 6 x 4 x 3 m
   room with alpha = 0.1 on every surface: the number of images, the best of several runs, and the
   rate in images per second.
2. pyroomacoustics (the peer reference, a test-only dependency) on the same room and source at
   order 10: ``image_source_model`` and ``compute_rir`` at 96 kHz (the rate the levels are computed
   at) for 1e4 receivers uniformly spread in the room, in chunks of 500 receivers so that the
   impulse responses (about 17 000 samples each) fit in memory; when the first chunk shows the
   whole would take over a minute, 1e3 receivers instead, and the table says so. This is the
   pyroomacoustics side of the issue's goal (peak and SEL of one impact at 1e4 receivers at order
   10 at least 10x faster than pyroomacoustics' impulse responses).
3. The field evaluator's side, in the same run: the peak and the SEL of one impact of the Figure 2
   sphere in the same room at order 10 (:class:`acoustiviz.core.room_geometry.Room`) at receivers
   drawn as in 2 (``--receivers``, default 1e4), by :func:`acoustiviz.field.fast_peaks` (both in
   one pass, on its default threads: one per CPU) after the pulse's tables
   (:func:`acoustiviz.field.peaks.peak_table` and :func:`acoustiviz.field.pulse_correlations`,
   once); the peak alone and the SEL alone (:func:`acoustiviz.field.exposure`) on 1000 of them; the
   all-in time at 1e4 receivers (tables once, their kernels loaded before as the evaluator's, plus
   the per-receiver cost) and its ratio to
   pyroomacoustics' at 1e4, with whether the issue's 10x is met. Then both sides alternately on the
   same 1000 receivers, each on its default threads and on one thread.
4. A 20 s WAV of the Table 1 damper (the ``acoustiviz auralize`` defaults, simulated once) at the
   listener (3, 2, 1.5) m: rendered in free field, then in the 6 x 4 x 3 m room with alpha = 0.1
   (images to -60 dB, built inside the timing), then in the same room with the statistical late
   tail (``--late-tail``: exact images to the transition time, a seeded tail to -60 dB), and with
   the tail and absorption per octave band (125 Hz to 4 kHz, alpha 0.1 to 0.35), alternately, best
   of ``--wav-repeat``; CPU time. Then the whole ``acoustiviz auralize`` command the same ways.
   ``--only-wav`` runs this section alone.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _timing import best_of, run_writing

from acoustiviz.constants import ANALYSIS_RATE
from acoustiviz.core.room import Shoebox, image_count, image_sources

DIMS = (6.0, 4.0, 3.0)
ALPHA = 0.1
RADIUS = 0.01905
SOURCE = (2.0, 1.5, RADIUS)
CHUNK = 500
BUDGET_S = 60.0


def construction_table(max_order: int) -> None:
    room = Shoebox(DIMS, ALPHA)
    print(f"1. image construction, {DIMS[0]:g} x {DIMS[1]:g} x {DIMS[2]:g} m room, alpha = {ALPHA:g}")
    print(f"{'order':>5} {'images':>9} {'time ms':>9} {'Mimages/s':>10}")
    for n in range(1, max_order + 1):
        repeat = 7 if n <= 15 else 3
        t, im = best_of(lambda n=n: image_sources(room, SOURCE, n, radius=RADIUS), repeat)
        assert len(im) == image_count(n)
        print(f"{n:>5} {len(im):>9} {1e3 * t:>9.3f} {len(im) / t / 1e6:>10.2f}")


def _pra_chunk(pra, mics: np.ndarray, order: int, rate: int):
    room = pra.ShoeBox(list(DIMS), fs=rate, materials=pra.Material(ALPHA), max_order=order, air_absorption=False)
    room.add_source(list(SOURCE))
    room.add_microphone_array(mics.T)
    t0 = time.perf_counter()
    room.image_source_model()
    t1 = time.perf_counter()
    room.compute_rir()
    t2 = time.perf_counter()
    samples = len(room.rir[0][0])
    return t1 - t0, t2 - t1, samples


def pyroomacoustics_table(receivers: int, order: int, rate: int) -> None:
    try:
        import pyroomacoustics as pra
    except ImportError:
        print("2. pyroomacoustics is not installed (pip install -e '.[test]'): skipped")
        return None
    rng = np.random.default_rng(20261125)
    lo = np.full(3, 0.05)
    hi = np.array(DIMS) - 0.05
    first = rng.uniform(lo, hi, (CHUNK, 3))
    ism, rir, samples = _pra_chunk(pra, first, order, rate)
    note = ""
    if (ism + rir) * receivers / CHUNK > BUDGET_S:
        note = (f" (1e4 receivers would take about {(ism + rir) * 1e4 / CHUNK:.0f} s, over the {BUDGET_S:.0f} s "
                f"budget: {1000} receivers instead)")
        receivers = 1000
    total_ism, total_rir, done = ism, rir, CHUNK
    while done < receivers:
        m = min(CHUNK, receivers - done)
        a, b, _ = _pra_chunk(pra, rng.uniform(lo, hi, (m, 3)), order, rate)
        total_ism, total_rir, done = total_ism + a, total_rir + b, done + m
    if done > receivers:  # the first chunk alone was more than asked
        scale = receivers / done
        total_ism, total_rir, done = total_ism * scale, total_rir * scale, receivers
    t_ours, im = best_of(lambda: image_sources(Shoebox(DIMS, ALPHA), SOURCE, order, radius=RADIUS), 7)
    print()
    print(f"2. pyroomacoustics {pra.__version__}, same room and source, order {order} ({len(im)} images), "
          f"{rate} Hz, {done} receivers in chunks of {CHUNK}, fractional delays on "
          f"{pra.constants.get('num_threads')} threads{note}")
    print(f"{'stage':<34} {'time s':>9} {'ms/receiver':>12}")
    print(f"{'image_source_model':<34} {total_ism:>9.3f} {1e3 * total_ism / done:>12.4f}")
    print(f"{'compute_rir (' + str(samples) + ' samples each)':<34} {total_rir:>9.3f} {1e3 * total_rir / done:>12.4f}")
    print(f"{'pyroomacoustics total':<34} {total_ism + total_rir:>9.3f} {1e3 * (total_ism + total_rir) / done:>12.4f}")
    print(f"{'acoustiviz image_sources (once)':<34} {t_ours:>9.5f} {'-':>12}")
    return 1e3 * (total_ism + total_rir) / done, done


def field_table(receivers: int, order: int, pra) -> None:
    from acoustiviz.core.contact import Impact, acceleration_pulse
    from acoustiviz.core.room_geometry import Room
    from acoustiviz.field import exposure, fast_peaks, pulse_correlations
    from acoustiviz.field.peaks import _threads, peak_table

    pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * RADIUS**3),
                               "half-sine")
    rng = np.random.default_rng(20261125)
    pts = rng.uniform(np.full(3, 0.05), np.array(DIMS) - 0.05, (receivers, 3))
    # the tables' kernels loaded before the timing (as fast_peaks' below), by another impact's tables
    other = acceleration_pulse(Impact(velocity=0.7, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * RADIUS**3),
                               "half-sine")
    peak_table(other, Room(RADIUS, DIMS, ALPHA, SOURCE, order=2))
    pulse_correlations(other, RADIUS)
    t0 = time.perf_counter()
    room = Room(RADIUS, DIMS, ALPHA, SOURCE, order=order)
    room.images()
    ta = time.perf_counter()
    table = peak_table(pulse, room)  # once per pulse, sphere and room: Y over the pulse
    t1 = time.perf_counter()
    corr = pulse_correlations(pulse, RADIUS)  # once per pulse and sphere: the correlations of Y
    t2 = time.perf_counter()
    fast_peaks(pulse, pts[:2], room, table=table, correlations=corr)  # compiled (or loaded) before the timing
    exposure(pulse, pts[:2], room, correlations=corr)
    t3 = time.perf_counter()
    pk = fast_peaks(pulse, pts, room, table=table, correlations=corr)  # peak and SEL in one pass, all CPUs
    t4 = time.perf_counter()
    threads = _threads(None, receivers)
    assert np.all(np.isfinite(pk.peak_positive)) and np.all(pk.exposure > 0)
    sub = pts[:min(receivers, 1000)]  # the breakdown on a subset
    t5 = time.perf_counter()
    fast_peaks(pulse, sub, room, table=table, correlations=corr, exposure=False, workers=1)
    t6 = time.perf_counter()
    e = exposure(pulse, sub, room, correlations=corr)
    t7 = time.perf_counter()
    np.testing.assert_allclose(e, pk.exposure[:len(sub)], rtol=1e-11)  # the two SEL paths agree
    setup = (ta - t0) + (t2 - ta)
    per = 1e3 * (t4 - t3) / receivers
    print()
    print(f"3. acoustiviz peak and SEL of one impact, room order {order} ({room.image_count} images), "
          f"{receivers} receivers on {threads} thread{'s' if threads > 1 else ''} (wall time, as 2.; kernels "
          f"compiled before the timing; the breakdown on 1 thread)")
    print(f"{'stage':<40} {'time s':>9} {'ms/receiver':>12}")
    print(f"{'Room value and its images':<40} {ta - t0:>9.3f} {'-':>12}")
    print(f"{'peak_table (once)':<40} {t1 - ta:>9.3f} {'-':>12}")
    print(f"{'pulse_correlations (once)':<40} {t2 - t1:>9.3f} {'-':>12}")
    print(f"{'fast_peaks, peak + SEL in one pass':<40} {t4 - t3:>9.3f} {per:>12.4f}")
    print(f"{'  of which: peak alone (' + str(len(sub)) + ' receivers)':<40} {t6 - t5:>9.3f} "
          f"{1e3 * (t6 - t5) / len(sub):>12.4f}")
    print(f"{'  exposure alone (field.exposure, same)':<40} {t7 - t6:>9.3f} {1e3 * (t7 - t6) / len(sub):>12.4f}")
    ours = setup + 1e-3 * per * 1e4
    print(f"{'acoustiviz at 1e4 receivers, all-in':<40} {ours:>9.3f} {1e3 * ours / 1e4:>12.4f}")
    if pra is not None:
        pra_ms, pra_n = pra
        theirs = 1e-3 * pra_ms * 1e4
        note = "" if pra_n >= 10_000 else f" (pyroomacoustics measured at {pra_n} receivers, scaled)"
        ratio = theirs / ours
        print(f"pyroomacoustics at 1e4 receivers: {theirs:.3f} s; pyroomacoustics / acoustiviz, all-in: {ratio:.3g}"
              f"{note}")
        print(f"goal (peak + SEL at 1e4 receivers at least 10x faster than pyroomacoustics' impulse responses): "
              f"{'met' if ratio >= 10.0 else 'not met'} ({ratio:.3g}x)")
        _interleaved(pulse, room, table, corr, pts[:2 * CHUNK])


def _interleaved(pulse, room, table, corr, mics: np.ndarray, repeat: int = 3) -> None:
    """Both sides on the same receivers, alternately, best of ``repeat`` (robust to a shared machine's load)."""
    import pyroomacoustics as pra

    from acoustiviz.field import fast_peaks

    threads = int(pra.constants.get("num_threads"))
    ours_n = max(2, threads)
    theirs, one, ours, ours1 = [], [], [], []
    for _ in range(repeat):
        ism, rir, _ = _pra_chunk(pra, mics, 10, ANALYSIS_RATE)
        theirs.append(ism + rir)
        pra.constants.set("num_threads", 1)  # its fractional delays on one thread
        try:
            ism, rir, _ = _pra_chunk(pra, mics, 10, ANALYSIS_RATE)
        finally:
            pra.constants.set("num_threads", threads)
        one.append(ism + rir)
        t0 = time.perf_counter()
        fast_peaks(pulse, mics, room, table=table, correlations=corr, workers=ours_n)
        ours.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        fast_peaks(pulse, mics, room, table=table, correlations=corr, workers=1)
        ours1.append(time.perf_counter() - t0)
    a, a1, b, b1 = (1e3 * min(x) / len(mics) for x in (theirs, one, ours, ours1))
    print(f"alternately on the same {len(mics)} receivers, best of {repeat} (per receiver, tables apart):")
    print(f"  pyroomacoustics on {threads} threads {a:.4f} ms, on 1 thread {a1:.4f} ms; acoustiviz peak + SEL on "
          f"{ours_n} threads {b:.4f} ms, on 1 thread {b1:.4f} ms")
    print(f"  ratios, {threads} threads to {ours_n}: {a / b:.3g}; 1 thread to 1: {a1 / b1:.3g}")


BANDS = "125:0.1,250:0.15,500:0.2,1000:0.25,2000:0.3,4000:0.35"


def _wav_cases():
    """Name, room settings and RoomSound of each way of hearing the room in section 4."""
    from acoustiviz.sound import RoomSound, parse_absorption_bands

    room = {"dimensions": DIMS, "absorption": ALPHA, "source": SOURCE}
    centres, alpha = parse_absorption_bands(BANDS)
    banded = {**room, "absorption": tuple(alpha.min(axis=1))}
    return [("free", None, None), ("room", room, None), ("tail", room, RoomSound(late_tail=True)),
            ("tail+bands", banded, RoomSound(late_tail=True, band_centres=centres, band_absorption=alpha))]


def wav_table(repeat: int) -> None:
    from acoustiviz.app.damper import run_damper
    from acoustiviz.app.wav import cavity
    from acoustiviz.constants import DEFAULT_DURATION
    from acoustiviz.dynamics import DamperModel
    from acoustiviz.sound import ClickModel, render

    model = DamperModel()
    run = run_damper(model, DEFAULT_DURATION)
    seq = run.result.impacts.sequence()
    click = ClickModel(k_hertz=model.k_hertz, mass=model.m, main_mass=model.M)
    listener = [3.0, 2.0, 1.5]
    cases = _wav_cases()
    times = {name: [] for name, _, _ in cases}
    info = {}
    for _ in range(repeat):
        for name, room, rs in cases:
            t0 = time.process_time()
            scene = cavity("free", RADIUS, model.gap, room=room)
            out = render(seq, scene, click, listener, duration=DEFAULT_DURATION, room_sound=rs)
            times[name].append(time.process_time() - t0)
            if room is not None:
                geometry = out.scene.geometry
                r = out.room or {"image_order": geometry.image_order, "images": geometry.image_count,
                                 "neglected_energy_db": geometry.neglected_energy_db, "transition_s": None}
                info[name] = (r["image_order"], r["images"], r["neglected_energy_db"], r["transition_s"],
                              out.n_samples / out.sample_rate)
    best = {k: min(v) for k, v in times.items()}
    print()
    print(f"4. {DEFAULT_DURATION:g} s WAV of the Table 1 damper ({len(seq)} impacts), listener (3, 2, 1.5) m, 48 kHz, "
          f"CPU time, best of {repeat}")
    print(f"{'surroundings':<72} {'time s':>8} {'/ free':>7}")
    print(f"{'free field':<72} {best['free']:>8.3f} {1.0:>7.2f}")
    labels = {"room": "room 6 x 4 x 3 m, alpha 0.1, exact images",
              "tail": "room, --late-tail",
              "tail+bands": "room, --late-tail --absorption-bands (6 bands)"}
    for name in ("room", "tail", "tail+bands"):
        order, images, neg, t_x, sig = info[name]
        label = f"{labels[name]}: order {order} ({images:,} images)"
        print(f"{label:<72} {best[name]:>8.3f} {best[name] / best['free']:>7.2f}")
    for name in ("room", "tail", "tail+bands"):
        order, images, neg, t_x, sig = info[name]
        trans = f", transition {1e3 * t_x:.1f} ms" if t_x is not None else ""
        print(f"  {name}: neglected energy {float(neg):.1f} dB{trans}, signal {sig:.2f} s")
    print("goal: the room within 3x the free field (render)")
    # the whole command, as a user runs it: damper simulation, rendering, calibration, files
    import contextlib
    import io
    import tempfile

    from acoustiviz.cli import main as cli

    room_args = ["--room", ",".join(f"{x:g}" for x in DIMS), "--source", ",".join(f"{x:g}" for x in SOURCE)]
    commands = {"free": ["--config", "free"], "room": [*room_args, "--absorption", f"{ALPHA:g}"],
                "tail": [*room_args, "--absorption", f"{ALPHA:g}", "--late-tail"],
                "tail+bands": [*room_args, "--absorption-bands", BANDS, "--late-tail"]}
    whole = {k: [] for k in commands}
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(repeat):
            for name, extra in commands.items():
                t0 = time.process_time()
                with contextlib.redirect_stdout(io.StringIO()):
                    assert cli(["auralize", *extra, "--listener", "3,2,1.5", "--wav", f"{tmp}/{i}.wav", "--force"]) == 0
                whole[name].append(time.process_time() - t0)
    best = {k: min(v) for k, v in whole.items()}
    print(f"{'acoustiviz auralize (whole command)':<72} {'time s':>8} {'/ free':>7}")
    for name, label in (("free", "--config free"), ("room", "--room 6,4,3 --absorption 0.1"),
                        ("tail", "--room 6,4,3 --absorption 0.1 --late-tail"),
                        ("tail+bands", "--room 6,4,3 --absorption-bands ... --late-tail")):
        print(f"{label:<72} {best[name]:>8.3f} {best[name] / best['free']:>7.2f}")
    print("goal: the room within 3x the free field (whole command)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="orders 1..10 and 1e3 receivers")
    parser.add_argument("--receivers", type=int, default=10_000, help="receivers of the acoustiviz side (3.)")
    parser.add_argument("--wav-repeat", type=int, default=2, help="repeats of the WAV timing (4.)")
    parser.add_argument("--only-wav", action="store_true", help="section 4 (the WAV timings) alone")
    args = parser.parse_args(argv)
    if args.only_wav:
        wav_table(args.wav_repeat)
        return 0
    construction_table(10 if args.quick else 30)
    pra = pyroomacoustics_table(1000 if args.quick else 10_000, 10, ANALYSIS_RATE)
    field_table(1000 if args.quick else args.receivers, 10, pra)
    wav_table(args.wav_repeat)
    return 0


if __name__ == "__main__":
    raise SystemExit(run_writing("bench_room", main))
