"""1/3-octave bands of a click train decimated from its clicks alone, against decimating every sample."""

import numpy as np
import pytest
from scipy.signal import resample_poly

from acoustiviz.constants import P_REF
from acoustiviz.core.signal import Signal
from acoustiviz.levels import third_octave_levels
from acoustiviz.levels._filters import OctaveFilterBank, time_weighting
from acoustiviz.levels.bands import decimate

FS = 96000


def _train(n, starts, width=400, channels=2, seed=3):
    rng = np.random.default_rng(seed)
    t = np.arange(width)
    p = np.zeros((channels, n))
    for s in starts:
        w = min(width, n - s)
        p[:, s:s + w] += rng.uniform(0.2, 3.0, (channels, 1)) * (np.sin(2 * np.pi * t / 23.0) * np.exp(-t / 80.0))[:w]
    return p


@pytest.mark.parametrize("q", [1, 2, 5, 16, 137, 500])
def test_decimating_the_clicks_alone_equals_decimating_every_sample(q):
    n = 300007
    p = _train(n, [0, 7, 1000, 1450, 60000, 60300, 200000, n - 90])
    for offset in (0.0, np.array([[2e-3], [-7e-4]])):
        ref = resample_poly(p - offset, 1, q, axis=-1)
        got = decimate(p, q, offset)
        assert got.shape == ref.shape
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))


def test_a_dense_signal_and_silence_are_decimated_as_they_are():
    rng = np.random.default_rng(8)
    p = rng.normal(size=(1, 50000))
    np.testing.assert_array_equal(decimate(p, 7), resample_poly(p, 1, 7, axis=-1))
    np.testing.assert_array_equal(decimate(np.zeros((1, 50000)), 7), np.zeros((1, 50000 // 7 + 1)))


def test_band_levels_of_a_click_train_equal_those_of_the_whole_signal():
    # reference: every band's signal decimated and filtered over every sample (the bank's own band_signal)
    n = 4 * FS
    rng = np.random.default_rng(4)
    p = _train(n, np.sort(rng.choice(n - 400, 40, replace=False)))
    bl = third_octave_levels(Signal(p, FS), start=0.5, stop=3.5)
    bank = OctaveFilterBank(FS, fraction=3, order=6, limits=[25.0, 20000.0])
    i0, i1 = FS // 2, 7 * FS // 2
    x = p - np.mean(p[:, i0:i1], axis=1, keepdims=True)
    for k in range(len(bank.freq)):
        q = int(bank.factor[k])
        y = bank.band_signal(x, k)
        j0, j1 = i0 // q, -(-i1 // q)
        leq = 10 * np.log10(np.mean(y[:, j0:j1] ** 2, axis=1) / P_REF**2)
        lmax = 10 * np.log10(np.max(time_weighting(y, FS / q, mode="fast")[:, j0:j1], axis=1) / P_REF**2)
        np.testing.assert_allclose(bl.leq_db[:, k], leq, rtol=0, atol=1e-9)
        np.testing.assert_allclose(bl.lmax_db[:, k], lmax, rtol=0, atol=1e-9)
