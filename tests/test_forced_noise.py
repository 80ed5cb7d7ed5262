"""The noise of the damper in operation: weighted levels of the steady click train, checked by other routes.

The references are built independently of :func:`acoustiviz.app.forced.operating_noise`: each
impact of one period is rendered alone (silence before and after it) and its exposure taken by
:func:`acoustiviz.levels.sound_levels`; the train's levels then follow from energy addition
(LAeq) and from the closed-form response of the F time weighting to a periodic train of short
pulses (LAFmax).
"""

import math

import numpy as np
import pytest

from acoustiviz.app.forced import default_listener, design_map, operating_noise
from acoustiviz.app.forced_noise import F_SETTLE, NOISE_RATE
from acoustiviz.app.wav import cavity
from acoustiviz.constants import P_REF, PAPER_RADIUS
from acoustiviz.core.signal import Signal
from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics.forced import Excitation, steady_state
from acoustiviz.levels import sound_levels
from acoustiviz.sound import ClickModel, ImpactSequence, render

TAU_F = 0.125  # s, IEC 61672-1 F time constant


@pytest.fixture(scope="module")
def symmetric():
    """Table 1 damper at 6.5 Hz, 5 N: period-1 motion with one impact on each wall per cycle."""
    model = DamperModel()
    r = steady_state(model, Excitation(6.5, 5.0), initial=(0.0, 0.0, 0.0, 0.5))
    assert r.regime == "periodic-1" and r.impacts_per_cycle == 2
    return r


@pytest.fixture(scope="module")
def noise(symmetric):
    return operating_noise(symmetric)


def _lone_click_exposures(r):
    """A- and Z-weighted exposure (Pa² s) of each impact of one period, each rendered alone at 96 kHz."""
    model = r.model
    clicks = ClickModel(k_hertz=model.k_hertz, mass=model.m, main_mass=model.M)
    scene = cavity("plane", PAPER_RADIUS, model.gap)
    ea, ez = [], []
    for wall, speed in zip(r.impact_walls, r.impact_speeds, strict=True):
        one = render(ImpactSequence([0.01], [int(wall)], [speed]), scene, clicks, default_listener(),
                     sample_rate=96000, duration=0.5)  # 0.5 s: the A filter's low-frequency tail dies out
        lv = sound_levels(Signal(one.pressure[0], one.sample_rate))
        ea.append(P_REF**2 * 10 ** (lv.sel_a_db[0] / 10))
        ez.append(P_REF**2 * 10 ** (lv.sel_db[0] / 10))
    return np.array(ea), np.array(ez)


def test_laeq_is_the_energy_sum_of_the_a_weighted_clicks(symmetric, noise):
    """LAeq = SEL_A,click + 10 lg(k / T), SEL_A,click the energy mean of the k clicks of a period T.

    The two walls' clicks differ at the listener (the struck wall's image sources differ), so the
    per-click exposure is their energy mean.
    """
    ea, ez = _lone_click_exposures(symmetric)
    period = 1 / 6.5
    assert np.all(ea > 0) and np.all(ez > ea / 10)
    sel_a_click = 10 * math.log10(ea.mean() / P_REF**2)
    assert noise.laeq_db == pytest.approx(sel_a_click + 10 * math.log10(2 / period), abs=0.02)
    assert noise.laeq_db == pytest.approx(10 * math.log10(ea.sum() / period / P_REF**2), abs=0.01)
    assert noise.lzeq_db == pytest.approx(10 * math.log10(ez.sum() / period / P_REF**2), abs=0.01)
    assert noise.sel_a_per_cycle_db == pytest.approx(10 * math.log10(ea.sum() / P_REF**2), abs=0.01)
    assert noise.sel_per_cycle_db == pytest.approx(10 * math.log10(ez.sum() / P_REF**2), abs=0.01)


def test_lafmax_is_the_periodic_maximum_of_the_f_weighted_train(symmetric, noise):
    """F-weighted mean square just after click i = Σ_j (E_A,j / τ) e^{-(t_i - t_j)/τ} over all past clicks.

    For a periodic train (window W) the sum over earlier windows is the geometric factor
    1 / (1 - e^{-W/τ}); the clicks (< 1 ms) are short against τ = 125 ms.
    """
    ea, _ = _lone_click_exposures(symmetric)
    w = 1 / 6.5
    t = np.mod(symmetric.impact_times, w)
    env = [sum(ea[j] / TAU_F * math.exp(-np.mod(t[i] - t[j], w) / TAU_F) for j in range(t.size))
           / (1 - math.exp(-w / TAU_F)) for i in range(t.size)]
    assert noise.lafmax_db == pytest.approx(10 * math.log10(max(env) / P_REF**2), abs=0.05)


def test_level_ordering_and_interval(symmetric, noise):
    # the mean of the F-weighted envelope over whole periods is the mean square: max >= mean
    assert noise.lafmax_db >= noise.laeq_db
    assert noise.lcpeak_db >= noise.lafmax_db + 10  # an impulsive train: peak far above its running rms
    assert noise.lzpeak_db >= noise.lzeq_db
    assert noise.settled and noise.start >= F_SETTLE
    assert noise.sample_rate == NOISE_RATE == 96000
    # a whole number of forcing cycles, at least the 1 s asked for (to the sample)
    assert noise.duration * 6.5 == pytest.approx(noise.cycles, abs=6.5 / NOISE_RATE)
    assert noise.cycles == 7 and noise.duration >= 1.0 - 1 / NOISE_RATE


def test_levels_do_not_depend_on_how_many_periods_are_averaged(symmetric, noise):
    short = operating_noise(symmetric, seconds=0.2)
    assert short.cycles == 2
    for c in ("laeq_db", "lafmax_db", "lzeq_db"):
        assert getattr(short, c) == pytest.approx(getattr(noise, c), abs=0.005), c
    # a sampled peak depends on where each click falls on the 96 kHz grid (T is not a whole number
    # of samples), a few hundredths of a dB
    for c in ("lcpeak_db", "lzpeak_db"):
        assert getattr(short, c) == pytest.approx(getattr(noise, c), abs=0.05), c


def test_a_silent_steady_state_has_no_level():
    # at 3 Hz and 5 N the main mass moves 15.5 mm, clear of the 20 mm half gap: no impacts
    r = steady_state(DamperModel(), Excitation(3.0, 5.0))
    nz = operating_noise(r, seconds=0.5)
    assert r.impacts_per_cycle == 0
    assert nz.laeq_db == nz.lafmax_db == nz.lcpeak_db == -math.inf


@pytest.mark.slow
def test_design_map_gives_laeq():
    # at 3 Hz and 5 N the main mass moves 15.5 mm: clear of a 20 mm half gap, not of a 10 mm one
    d = design_map(DamperModel(), [0.0405], [0.02, 0.04], 3.0, 5.0, seconds=0.3)
    assert d.reduction_db.shape == d.laeq_db.shape == (1, 2)
    assert d.reduction_db[0, 1] == pytest.approx(0.0, abs=1e-9)
    assert d.laeq_db[0, 1] == -np.inf
    assert np.isfinite(d.laeq_db[0, 0]) and d.laeq_db[0, 0] > 40
    assert d.lcpeak_db[0, 0] > d.lafmax_db[0, 0] >= d.laeq_db[0, 0]


def test_levels_from_the_clicks_alone_equal_those_of_every_sample(noise):
    # the train's levels are computed from its clicks (the filters' states carried across the
    # silences); filtering every sample of the same rendering gives them to round-off
    lv = sound_levels(Signal(noise.pressure, noise.sample_rate), start=noise.start, stop=noise.stop)
    assert noise.laeq_db == pytest.approx(float(lv.laeq_db[0]), abs=1e-9)
    assert noise.lzeq_db == pytest.approx(float(lv.lzeq_db[0]), abs=1e-9)
    assert noise.lcpeak_db == pytest.approx(float(lv.lcpeak_db[0]), abs=1e-9)
    assert noise.lzpeak_db == pytest.approx(float(lv.lzpeak_db[0]), abs=1e-9)
    assert noise.lafmax_db == pytest.approx(float(lv.lafmax_db[0]), abs=5e-6)  # within MAX_RELATIVE_GAP
