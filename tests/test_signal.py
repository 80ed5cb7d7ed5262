"""The calibrated pressure signal: validation, derived times and windows by time."""

import numpy as np
import pytest

import acoustiviz
from acoustiviz.core.signal import Signal
from acoustiviz.errors import ParameterError


def test_derived_properties_follow_from_the_rate_and_the_start():
    fs, t0 = 8000.0, -0.25
    sig = Signal(np.zeros((3, 400)), fs, start=t0)
    assert sig.channels == 3 and sig.n_samples == 400
    assert sig.duration == pytest.approx(400 / fs, rel=1e-15)
    assert sig.stop == pytest.approx(t0 + 0.05, rel=1e-15)
    assert sig.times.shape == (400,)
    assert sig.times[0] == t0
    np.testing.assert_allclose(np.diff(sig.times), 1 / fs, rtol=1e-9)
    assert sig.as_channels().shape == (3, 400)
    assert Signal(np.ones(5), 1.0).as_channels().shape == (1, 5)


def test_the_samples_are_a_private_read_only_copy():
    raw = np.array([1.0, 2.0, 3.0])
    sig = Signal(raw, 10.0)
    raw[0] = 99.0
    assert sig.pressure[0] == 1.0
    with pytest.raises(ValueError):
        sig.pressure[1] = 5.0
    with pytest.raises(AttributeError):
        sig.sample_rate = 20.0


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"pressure": [1.0, np.nan], "sample_rate": 10.0}, "pressure"),
    ({"pressure": [1.0, np.inf], "sample_rate": 10.0}, "pressure"),
    ({"pressure": np.zeros((2, 2, 2)), "sample_rate": 10.0}, "pressure"),
    ({"pressure": [], "sample_rate": 10.0}, "pressure"),
    ({"pressure": ["a", "b"], "sample_rate": 10.0}, "pressure"),
    ({"pressure": [1.0, 2.0], "sample_rate": 0.0}, "sample_rate"),
    ({"pressure": [1.0, 2.0], "sample_rate": -48000}, "sample_rate"),
    ({"pressure": [1.0, 2.0], "sample_rate": np.inf}, "sample_rate"),
    ({"pressure": [1.0, 2.0], "sample_rate": 10.0, "start": np.nan}, "start"),
])
def test_bad_values_are_refused_naming_the_parameter(kwargs, name):
    with pytest.raises(ParameterError, match=rf"^{name}: "):
        Signal(**kwargs)


def test_window_keeps_the_samples_inside_and_their_times():
    fs = 1000.0
    sig = Signal(np.vstack([np.arange(1000.0), -np.arange(1000.0)]), fs, start=2.0)
    part = sig.window(2.1, 2.3)
    assert part.channels == 2 and part.n_samples == 200 and part.sample_rate == fs
    assert part.start == pytest.approx(2.1, abs=1e-12)
    np.testing.assert_array_equal(part.pressure[0], np.arange(100.0, 300.0))
    np.testing.assert_array_equal(part.pressure[1], -np.arange(100.0, 300.0))
    # the window's times are the original times of the kept samples
    np.testing.assert_allclose(part.times, sig.times[100:300], atol=1e-12)
    whole = sig.window()
    np.testing.assert_array_equal(whole.pressure, sig.pressure)
    assert whole.start == sig.start


@pytest.mark.parametrize(("start", "stop", "name"), [
    (1.9, None, "start"),  # before the first sample
    (3.0, None, "start"),  # at the signal's stop
    (None, 3.5, "stop"),  # after the end
    (2.5, 2.5, "stop"),  # empty
    (2.5, 2.5005, "stop"),  # fewer than two samples
])
def test_windows_outside_the_signal_are_refused_naming_the_bound(start, stop, name):
    sig = Signal(np.zeros(1000), 1000.0, start=2.0)
    with pytest.raises(ParameterError, match=rf"^{name}: "):
        sig.window(start, stop)


def test_signal_is_exported_at_the_top_level():
    assert acoustiviz.Signal is Signal and "Signal" in acoustiviz.__all__


def test_an_owned_read_only_array_is_kept_and_anything_else_copied():
    owned = np.arange(6.0)
    owned.flags.writeable = False
    assert Signal(owned, 10.0).pressure is owned  # nobody can change it: no second copy of a long signal
    view = owned[1:]
    assert Signal(view, 10.0).pressure is not view  # a view of someone's data: copied
    ints = np.arange(6)
    ints.flags.writeable = False
    kept = Signal(ints, 10.0).pressure
    assert kept.dtype == float and not kept.flags.writeable


def test_a_rendering_hands_its_samples_over_without_a_copy():
    from acoustiviz.sound import CavityScene, ClickModel, ImpactSequence, render

    out = render(ImpactSequence([0.01], [-1], [1.0]), CavityScene(), ClickModel(), [0.0, 0.5, 0.5],
                 sample_rate=48000, duration=0.02)
    assert out.signal.pressure.flags.owndata and not out.signal.pressure.flags.writeable
