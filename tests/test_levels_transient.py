"""Levels of a transient from its sound alone against the same levels over the whole zero-padded interval."""

import numpy as np
import pytest
from scipy.signal import sosfilt

import acoustiviz.levels.transient as transient
from acoustiviz.core.signal import Signal
from acoustiviz.errors import ParameterError
from acoustiviz.levels import METRICS, sound_levels
from acoustiviz.levels._library import library, weighting_sos
from acoustiviz.levels.transient import free_response_energy, transient_levels

FS = 96000
ALL = list(METRICS)


def _padded(head, n):
    return np.pad(np.atleast_2d(head), ((0, 0), (0, n - np.atleast_2d(head).shape[1])))


def _assert_same(head, n, tol_db=1e-6, fs=FS):
    fast = transient_levels(head, fs, n, ALL)
    full = sound_levels(Signal(_padded(head, n), fs))
    for m, field in METRICS.items():
        np.testing.assert_allclose(fast[m], getattr(full, field), rtol=0, atol=tol_db, err_msg=m)


def _bursts():
    t = np.arange(FS // 10) / FS
    tone = np.sin(2 * np.pi * 1000 * t[:480]) * np.hanning(480)  # 5 ms, 1 kHz, smooth ends
    low = 3.0 * np.sin(2 * np.pi * 25 * t[:3840])  # 40 ms of 25 Hz cut off at a peak of its slope
    step = np.r_[np.ones(200), np.zeros(10)]  # a pressure pulse with a mean: a long high-pass tail
    return np.stack([np.pad(tone, (0, 3840 - 480)), low, np.pad(step, (0, 3840 - 210))])


@pytest.mark.parametrize("curve", ["A", "C"])
def test_sections_are_the_librarys_filter(curve):
    x = np.sin(2 * np.pi * np.cumsum(np.linspace(10, 30000, 8000)) / FS)  # a chirp, not the probe
    sos = weighting_sos(FS, curve)
    ref = library().weighting_filter(x, FS, curve)
    assert np.max(np.abs(sosfilt(sos, x) - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_no_sections_where_the_library_resamples():
    assert weighting_sos(48000, "A") is None


@pytest.mark.parametrize("curve", ["A", "C"])
@pytest.mark.parametrize("horizon", [1, 7, 300, 95000])
def test_free_response_energy_is_the_sum_of_squares_of_the_free_response(curve, horizon):
    sos = weighting_sos(FS, curve)
    state = np.random.default_rng(3).standard_normal((sos.shape[0], 4, 2))
    y, _ = sosfilt(sos, np.zeros((4, horizon)), axis=-1, zi=state)
    np.testing.assert_allclose(free_response_energy(FS, curve, state, horizon), np.sum(y * y, axis=1), rtol=1e-6)


def test_free_response_energy_of_no_samples_is_zero_and_bad_states_are_refused():
    sos = weighting_sos(FS, "A")
    assert np.all(free_response_energy(FS, "A", np.ones((sos.shape[0], 2, 2)), 0) == 0.0)
    with pytest.raises(ParameterError, match="state"):
        free_response_energy(FS, "A", np.ones((2, 2)), 10)


def test_bursts_match_the_full_interval():
    _assert_same(_bursts(), FS)


def test_a_short_settling_stretch_is_lengthened_until_the_bounds_hold(monkeypatch):
    calls = []
    run = transient._run

    def spy(curve, fs, x, stop, n):
        calls.append((curve, x.shape[0], stop))
        return run(curve, fs, x, stop, n)

    monkeypatch.setattr(transient, "SETTLE_SAMPLES", 1)
    monkeypatch.setattr(transient, "_run", spy)
    _assert_same(_bursts(), FS, tol_db=1e-4)
    assert len([c for c in calls if c[0] == "A"]) > 1 and len([c for c in calls if c[0] == "C"]) > 1


def test_a_head_filling_the_interval_and_silence():
    heads = _bursts()
    _assert_same(heads, heads.shape[1])
    fast = transient_levels(np.zeros((2, 50)), FS, FS, ALL)
    assert all(np.all(np.isneginf(v)) for v in fast.values())


def test_where_the_library_resamples_the_levels_are_those_of_the_full_signal():
    fs = 48000
    click = np.r_[np.hanning(40) * np.sin(np.arange(40)), np.zeros(5)]
    fast = transient_levels(click, fs, fs, ALL)
    full = sound_levels(Signal(_padded(click, fs), fs))
    for m, field in METRICS.items():
        np.testing.assert_array_equal(fast[m], getattr(full, field))


def test_bad_inputs_name_the_argument():
    with pytest.raises(ParameterError, match="n_samples"):
        transient_levels(np.ones(100), FS, 50, ["laeq"])
    with pytest.raises(ParameterError, match="metrics"):
        transient_levels(np.ones(100), FS, 500, ["lxyz"])
    with pytest.raises(ParameterError, match="head"):
        transient_levels(np.array([1.0, np.nan]), FS, 500, ["laeq"])
