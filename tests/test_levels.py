"""Weighted levels and 1/3-octave bands against known signals and the IEC 61672-1 / 61260-1 tables."""

import math

import numpy as np
import pytest

from acoustiviz.core.signal import Signal
from acoustiviz.errors import ParameterError
from acoustiviz.levels import band_energy_sum, level_db, sound_levels, third_octave_levels, weighted

FS = 48000
P_RMS_94 = 1.0  # Pa rms: 93.98 dB re 20 uPa
L_1PA = 20 * math.log10(1 / 20e-6)  # 93.9794 dB


def tone(freq, seconds=2.0, fs=FS, rms=P_RMS_94):
    t = np.arange(int(seconds * fs)) / fs
    return math.sqrt(2) * rms * np.sin(2 * np.pi * freq * t)


# IEC 61672-1:2013 Table 3 design goals (dB) at exact base-10 frequencies f = 1000 * 10^(n/10)
IEC_A = {-15: -39.4, -12: -26.2, -9: -16.1, -6: -8.6, -3: -3.2, 0: 0.0, 3: 1.2, 6: 1.0, 9: -1.1}
IEC_C = {-15: -3.0, -12: -0.8, -9: -0.2, 0: 0.0, 6: -0.8, 9: -3.0}


def _gain(curve, n):
    f = 1000 * 10 ** (n / 10)
    x = tone(f, seconds=1.5)
    lv_w = level_db(np.mean(weighted(Signal(x, FS), curve).pressure[FS // 2:] ** 2))
    return lv_w - level_db(np.mean(x[FS // 2:] ** 2))


def _tolerance(n):
    # far inside the class 1 limits (+-1.0 dB to 4 kHz, +1.5/-2.5 dB at 8 kHz); the table rounds to 0.1 dB
    return 0.1 if n <= 6 else 0.2


@pytest.mark.parametrize("n, expected", sorted(IEC_A.items()))
def test_a_weighting_matches_iec_table(n, expected):
    assert _gain("A", n) == pytest.approx(expected, abs=_tolerance(n))


@pytest.mark.parametrize("n, expected", sorted(IEC_C.items()))
def test_c_weighting_matches_iec_table(n, expected):
    assert _gain("C", n) == pytest.approx(expected, abs=_tolerance(n))


def test_calibrated_1khz_tone_reads_94_db_laeq_and_94_db_in_its_band():
    x = tone(1000)
    lv = sound_levels(Signal(x, FS), start=0.5)
    assert lv.laeq_db[0] == pytest.approx(L_1PA, abs=0.02)
    assert lv.lzeq_db[0] == pytest.approx(L_1PA, abs=0.01)
    bl = third_octave_levels(Signal(x, FS), start=0.5)
    k = list(bl.nominal_hz).index(1000.0)
    assert bl.leq_db[0, k] == pytest.approx(L_1PA, abs=0.1)
    assert bl.lmax_db[0, k] == pytest.approx(L_1PA, abs=0.15)
    assert np.all(np.delete(bl.leq_db[0], k) < L_1PA - 10)  # the neighbours see only the skirts


def test_100_hz_tone_a_weighting_is_minus_19_1_db():
    lv = sound_levels(Signal(tone(100), FS), start=0.5)
    assert lv.laeq_db[0] - lv.lzeq_db[0] == pytest.approx(-19.1, abs=0.1)


@pytest.mark.parametrize("freq", [1000.0, 250.0])
def test_lcpeak_of_a_steady_sine_is_3_01_db_above_its_c_weighted_leq(freq):
    x = tone(freq)
    lv = sound_levels(Signal(x, FS), start=0.5)
    lceq = level_db(np.mean(weighted(Signal(x, FS), "C").pressure[FS // 2:] ** 2))
    assert lv.lcpeak_db[0] - lceq == pytest.approx(10 * math.log10(2), abs=0.02)
    assert lv.lzpeak_db[0] - lv.lzeq_db[0] == pytest.approx(10 * math.log10(2), abs=0.01)


def test_fast_time_weighting_of_a_tone_burst_follows_the_exponential():
    # IEC 61672-1 5.9: the toneburst response is 10 lg(1 - exp(-Tb / tau)) re the steady level
    x = tone(4000, seconds=1.0)
    for tb in (0.2, 0.05):
        burst = np.where(np.arange(x.size) < tb * FS, x, 0.0)
        lv = sound_levels(Signal(burst, FS))
        steady = L_1PA + 1.0  # A(4 kHz) = +1.0 dB
        assert lv.lafmax_db[0] - steady == pytest.approx(10 * math.log10(1 - math.exp(-tb / 0.125)), abs=0.15)
        assert lv.lasmax_db[0] - steady == pytest.approx(10 * math.log10(1 - math.exp(-tb / 1.0)), abs=0.15)


def test_exposure_level_is_leq_plus_ten_log_of_the_interval():
    lv = sound_levels(Signal(tone(500), FS), start=0.25, stop=1.75)
    assert lv.interval == pytest.approx(1.5)
    assert lv.sel_db[0] == pytest.approx(lv.lzeq_db[0] + 10 * math.log10(1.5), abs=1e-9)
    assert lv.sel_a_db[0] == pytest.approx(lv.laeq_db[0] + 10 * math.log10(1.5), abs=1e-9)


def test_sel_of_a_click_is_its_integrated_square_and_ignores_silence_around_it():
    x = np.zeros(FS)
    x[1000:1048] = np.hanning(48) * 3.0
    expected = 10 * math.log10(np.sum(x**2) / FS / 20e-6**2)
    assert sound_levels(Signal(x, FS)).sel_db[0] == pytest.approx(expected, abs=1e-9)
    assert sound_levels(Signal(x, FS), start=0.01, stop=0.5).sel_db[0] == pytest.approx(expected, abs=1e-9)


def test_channels_are_independent():
    x = np.stack([tone(1000), 0.1 * tone(1000)])
    lv = sound_levels(Signal(x, FS), start=0.5)
    assert lv.lzeq_db[0] - lv.lzeq_db[1] == pytest.approx(20.0, abs=1e-6)
    assert [r["channel"] for r in lv.rows(["left", "right"])] == ["left", "right"]


def test_band_energies_of_band_limited_noise_add_up_to_its_total():
    rng = np.random.default_rng(7)
    n = 4 * FS
    spec = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1 / FS)
    spec[(f < 200) | (f > 8000)] = 0
    x = np.fft.irfft(spec, n)
    bl = third_octave_levels(Signal(x, FS), start=0.5)
    total = level_db(np.mean(x[FS // 2:] ** 2))
    assert bl.total_leq_db()[0] == pytest.approx(total, abs=0.3)
    assert band_energy_sum([[90.0, 90.0]])[0] == pytest.approx(90 + 10 * math.log10(2))


def test_band_leq_over_the_whole_signal_matches_the_librarys_own_bank():
    from acoustiviz.levels._library import library

    x = tone(315) + 0.3 * tone(2500)
    ours = third_octave_levels(Signal(x, FS))
    theirs, _ = library().OctaveFilterBank(FS, fraction=3, order=6, limits=[25, 20000]).filter(x)
    assert np.allclose(ours.leq_db[0], theirs, atol=1e-6)


def test_bands_run_from_25_hz_to_20_khz():
    bl = third_octave_levels(Signal(tone(1000, seconds=0.5), FS))
    assert bl.nominal_hz[0] == 25.0 and bl.nominal_hz[-1] == 20000.0 and bl.nominal_hz.size == 30
    assert np.allclose(bl.centre_hz[16], 1000.0)


@pytest.mark.parametrize("kwargs, name", [({"start": -1.0}, "start"), ({"stop": 5.0}, "stop"),
                                          ({"start": 1.0, "stop": 0.5}, "stop"), ({"start": 3.0}, "start")])
def test_bad_intervals_name_the_option(kwargs, name):
    with pytest.raises(ParameterError) as err:
        sound_levels(Signal(tone(1000), FS), **kwargs)
    assert err.value.name == name


def test_bad_inputs_are_refused_before_any_work():
    with pytest.raises(ParameterError, match="sample_rate"):
        third_octave_levels(Signal(tone(1000), 32000))
    with pytest.raises(ParameterError, match="pressure"):
        sound_levels(Signal(np.array([1.0, np.nan, 2.0]), FS))
    with pytest.raises(ParameterError, match="curve"):
        weighted(Signal(tone(1000), FS), "B")


@pytest.mark.slow
def test_metric_levels_give_one_value_per_row_and_name_the_option():
    from acoustiviz.levels import METRICS, metric_levels

    rows = np.stack([tone(1000), 0.5 * tone(1000), 0.25 * tone(100)])
    full = sound_levels(Signal(rows, FS), start=0.5)
    for name, field in METRICS.items():
        assert np.array_equal(metric_levels(Signal(rows, FS), name, start=0.5), getattr(full, field))
    laeq = metric_levels(Signal(rows, FS), "laeq", start=0.5)
    assert laeq[0] - laeq[1] == pytest.approx(20 * math.log10(2), abs=1e-6)
    with pytest.raises(ParameterError) as err:
        metric_levels(Signal(rows, FS), "dba")
    assert err.value.name == "metric"


def test_a_signal_that_starts_later_has_the_same_levels_over_the_same_samples():
    """start and stop are times on the signal's own axis: shifting the axis shifts them, not the levels."""
    x, t0 = tone(1000, seconds=1.0), 3.25
    at_zero = sound_levels(Signal(x, FS), start=0.25, stop=0.75)
    later = sound_levels(Signal(x, FS, start=t0), start=t0 + 0.25, stop=t0 + 0.75)
    for field in ("lzpeak_db", "lcpeak_db", "lafmax_db", "laeq_db", "sel_a_db"):
        np.testing.assert_array_equal(getattr(later, field), getattr(at_zero, field))
    assert later.start == pytest.approx(t0 + 0.25, abs=1e-12) and later.stop == pytest.approx(t0 + 0.75, abs=1e-12)
    bands = third_octave_levels(Signal(x, FS, start=t0), start=t0 + 0.25)
    assert bands.start == pytest.approx(t0 + 0.25, abs=1e-12)
    with pytest.raises(ParameterError) as err:  # an interval before the signal's start
        sound_levels(Signal(x, FS, start=t0), start=0.25)
    assert err.value.name == "start"


def test_weighting_returns_a_signal_on_the_same_axis():
    sig = Signal(tone(1000, seconds=0.5), FS, start=1.5)
    a = weighted(sig, "A")
    assert isinstance(a, Signal) and a.sample_rate == FS and a.start == 1.5 and a.n_samples == sig.n_samples
    np.testing.assert_array_equal(weighted(sig, "Z").pressure, sig.pressure)


@pytest.mark.parametrize("bad", [np.ones(100), [1.0, 2.0], Signal([1.0], FS)])
def test_levels_refuse_anything_but_a_signal_of_two_samples_or_more(bad):
    with pytest.raises(ParameterError) as err:
        sound_levels(bad)
    assert err.value.name == "signal"
