"""ISO 532-1 loudness and DIN 45692 sharpness through mosqito (skipped when it is not installed)."""

import math

import numpy as np
import pytest

from acoustiviz.core.signal import Signal
from acoustiviz.levels import hearing as loudness_module

pytestmark = pytest.mark.skipif(not loudness_module.loudness_available(),
                                reason="mosqito (extra 'hearing') not installed")

FS = 48000


def tone(freq, spl_db, seconds=1.0, fs=FS):
    t = np.arange(int(seconds * fs)) / fs
    return math.sqrt(2) * 20e-6 * 10 ** (spl_db / 20) * np.sin(2 * np.pi * freq * t)


@pytest.mark.slow
def test_1khz_tone_at_40_db_is_one_sone():
    assert loudness_module.loudness(Signal(tone(1000, 40), FS), start=0.2).n5_sone[0] == pytest.approx(1.0, abs=0.03)


@pytest.mark.slow
def test_ten_phon_more_doubles_the_loudness():
    out = loudness_module.loudness(Signal(np.stack([tone(1000, 60), tone(1000, 70)]), FS), start=0.2)
    assert out.n5_sone[0] == pytest.approx(4.0, rel=0.05)
    assert out.n5_sone[1] / out.n5_sone[0] == pytest.approx(2.0, rel=0.05)


@pytest.mark.slow
def test_critical_band_noise_at_1khz_60_db_is_one_acum():
    # DIN 45692: the reference sound of 1 acum is a critical-band-wide noise at 1 kHz and 60 dB
    rng = np.random.default_rng(3)
    n = FS
    spec = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1 / FS)
    spec[(f < 920) | (f > 1080)] = 0
    x = np.fft.irfft(spec, n)
    x *= 20e-6 * 10 ** (60 / 20) / np.sqrt(np.mean(x**2))
    assert loudness_module.loudness(Signal(x, FS), start=0.2).sharpness_acum[0] == pytest.approx(1.0, abs=0.1)


@pytest.mark.slow
def test_other_rates_are_resampled_to_48_khz():
    lo = loudness_module.loudness(Signal(tone(1000, 50, fs=96000), 96000), start=0.2)
    ref = loudness_module.loudness(Signal(tone(1000, 50), FS), start=0.2)
    assert lo.n5_sone[0] == pytest.approx(ref.n5_sone[0], rel=0.01)
