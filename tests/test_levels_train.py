"""Levels of a train of short sounds from the sounds alone against the same levels of the whole signal."""

import numpy as np
import pytest

from acoustiviz.core.signal import Signal
from acoustiviz.errors import ParameterError
from acoustiviz.levels import METRICS, sound_levels
from acoustiviz.levels.train import signal_levels, train_levels, train_signal

FS = 96000
ALL = list(METRICS)
#: Exposure, equivalent and peak levels are sums and maxima of the very samples the whole-signal
#: filters compute, carried across the silences in closed form: equal up to round-off. The
#: time-weighted maxima are accepted within MAX_RELATIVE_GAP (1e-6 relative, 4.3e-6 dB).
TOL_DB = {m: (5e-6 if m in ("lafmax", "lasmax") else 1e-9) for m in ALL}


def _assert_same(starts, windows, n, fs=FS, first=0):
    fast = train_levels(starts, windows, fs, n, ALL, first_sample=first)
    full = sound_levels(Signal(train_signal(starts, windows, n), fs), start=first / fs)
    for m, field in METRICS.items():
        ref = float(getattr(full, field)[0])
        assert fast[m] == pytest.approx(ref, abs=TOL_DB[m]), m


def _clicks(k, width, seed):
    rng = np.random.default_rng(seed)
    t = np.arange(width)
    shape = np.sin(np.pi * t / 40) * (t < 40) - 0.3 * np.exp(-t / 30.0) * (t >= 40)
    return rng.uniform(0.2, 3.0, (k, 1)) * shape[None, :]


def test_train_signal_adds_the_windows_inside_the_interval():
    w = np.array([[1.0, 2.0, 3.0], [10.0, 20.0, 30.0], [5.0, 5.0, 5.0]])
    p = train_signal([-1, 1, 4], w, 6)
    np.testing.assert_array_equal(p, [2.0, 13.0, 20.0, 30.0, 5.0, 5.0])


def test_isolated_clicks_over_twenty_seconds():
    rng = np.random.default_rng(5)
    n = 20 * FS
    starts = np.sort(rng.choice(n - 400, 120, replace=False))
    _assert_same(starts, _clicks(120, 300, 1), n)


def test_overlapping_clicks_and_windows_across_both_ends():
    n = FS // 2
    starts = np.array([-150, 0, 100, 130, 2000, 2200, 2210, 30000, n - 200, n - 5])
    _assert_same(starts, _clicks(starts.size, 300, 2), n)


def test_a_low_tone_whose_ring_down_outlasts_the_blocks():
    # 40 ms of 25 Hz stopped at a peak of its slope: the A weighting's 20 Hz poles ring for tens of ms
    # after it, so the silences' bounds fail at first and the blocks after it are filtered too
    t = np.arange(3840) / FS
    low = 3.0 * np.sin(2 * np.pi * 25 * t)
    starts = np.array([1000, 40000, 60000])
    _assert_same(starts, np.stack([low, 0.5 * low, -low]), FS)


def test_more_window_samples_than_signal():
    starts = np.arange(0, 20000, 90)
    _assert_same(starts, _clicks(starts.size, 300, 6), 20000)


def test_silence_and_a_lower_rate():
    assert all(v == -np.inf for v in train_levels([10], np.zeros((1, 50)), FS, FS, ALL).values())
    # at 48 kHz the weighting is not a cascade of sections at the rate: the whole signal is filtered
    _assert_same([100, 9000], _clicks(2, 200, 3), 24000, fs=48000)


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"starts": [0.5]}, "starts"), ({"windows": np.ones(4)}, "windows"),
    ({"windows": np.full((1, 4), np.nan)}, "windows"), ({"n_samples": 1}, "n_samples"),
    ({"metrics": ["loud"]}, "metrics"), ({"sample_rate": 96000.5}, "sample_rate"),
])
def test_bad_input_is_refused_by_name(kwargs, name):
    args = {"starts": [0], "windows": np.ones((1, 4)), "sample_rate": FS, "n_samples": 100, "metrics": ["laeq"]}
    args.update(kwargs)
    with pytest.raises(ParameterError) as err:
        train_levels(**args)
    assert err.value.name == name


def test_trains_of_one_rate_and_length_share_the_filter_tables():
    from acoustiviz.levels.train import _free_rows, _tables

    train_levels([100], _clicks(1, 300, 4), FS, 3 * FS, ["laeq", "lafmax", "lcpeak"])
    before = _tables.cache_info().misses, _free_rows.cache_info().misses
    train_levels([900, 70000], _clicks(2, 300, 5), FS, 3 * FS, ["laeq", "lafmax", "lcpeak"])
    assert (_tables.cache_info().misses, _free_rows.cache_info().misses) == before


@pytest.mark.parametrize("stop", [None, 1.5])
def test_levels_of_a_mostly_silent_signal_equal_those_of_every_sample(stop):
    # two channels of clicks (one silent), against sound_levels over every sample of the signal
    rng = np.random.default_rng(11)
    n = 2 * FS
    p = np.zeros((3, n))
    for ch in (0, 2):
        for s in np.sort(rng.choice(n - 300, 25, replace=False)):
            p[ch, s:s + 300] += _clicks(1, 300, int(s))[0]
    fast = signal_levels(Signal(p, FS), stop=stop)
    full = sound_levels(Signal(p, FS), stop=stop)
    assert (fast.start, fast.stop, fast.sample_rate, fast.library) == (full.start, full.stop, full.sample_rate,
                                                                         full.library)
    for m, field in METRICS.items():
        np.testing.assert_allclose(getattr(fast, field)[[0, 2]], getattr(full, field)[[0, 2]], rtol=0, atol=TOL_DB[m])
        # the silent channel: silence, where filtering it beside the others leaves the 1e-150 floor tone
        assert getattr(fast, field)[1] == -np.inf and getattr(full, field)[1] < -2000.0


def test_dense_signals_later_intervals_and_low_rates_are_filtered_whole():
    rng = np.random.default_rng(12)
    noise = rng.normal(size=(1, FS // 2))
    click = np.zeros((1, 48000))
    click[0, 1000:1300] = _clicks(1, 300, 1)[0]
    for p, fs, start in ((noise, FS, None), (click, 48000, 0.01)):
        fast, full = signal_levels(Signal(p, fs), start=start), sound_levels(Signal(p, fs), start=start)
        for field in METRICS.values():
            np.testing.assert_array_equal(getattr(fast, field), getattr(full, field))


@pytest.mark.parametrize("first", [1, 999, 1100, 30000, 47000, 60100, 2 * FS - 2000])
def test_an_interval_that_starts_later_hears_the_sound_before_it_through_the_filters(first):
    # first: before the clicks, inside one, in a silence, just after a loud one, inside the last
    rng = np.random.default_rng(6)
    starts = np.r_[1000, 46000, 60000, np.sort(rng.choice(np.arange(61000, 2 * FS - 400), 20, replace=False))]
    w = _clicks(starts.size, 300, 7)
    w[2] *= 30.0  # a loud click whose ring-down and S average outlast the next blocks
    _assert_same(starts, w, 2 * FS, first=first)


def test_levels_over_a_later_interval_of_a_mostly_silent_signal():
    rng = np.random.default_rng(13)
    p = np.zeros(FS)
    for s in np.sort(rng.choice(FS - 300, 12, replace=False)):
        p[s:s + 300] += _clicks(1, 300, int(s))[0]
    fast, full = signal_levels(Signal(p, FS), start=0.3, stop=0.9), sound_levels(Signal(p, FS), start=0.3, stop=0.9)
    assert (fast.start, fast.stop) == (full.start, full.stop)
    for m, field in METRICS.items():
        np.testing.assert_allclose(getattr(fast, field), getattr(full, field), rtol=0, atol=TOL_DB[m])


def test_a_bad_first_sample_is_refused():
    with pytest.raises(ParameterError, match="first_sample"):
        train_levels([0], np.ones((1, 4)), FS, 100, ["laeq"], first_sample=99)
