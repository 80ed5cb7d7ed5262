"""Frequency response of the forced damper: continuation, hysteresis, parallel runs."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from acoustiviz.dynamics.forced import frequency_response
from acoustiviz.dynamics.model import DamperModel
from acoustiviz.errors import ParameterError


def test_sweeps_up_and_down_find_coexisting_motions():
    """Above resonance the Table 1 damper at 5 N has an impacting and a non-impacting motion."""
    resp = frequency_response(DamperModel(), [6.0, 6.5, 7.0], 5.0, sweep="both")
    up, down = resp.primary[1:], resp.down[1:]
    assert all(r.converged for r in up + down)
    # upward from 6 Hz the impacting branch (two impacts per cycle) is carried to 7 Hz
    assert [r.impacts_per_cycle for r in up] == [2.0, 2.0]
    assert all(r.reduction_db > 3.0 for r in up)
    # downward from the linear start at 7 Hz the mass stays clear of the walls: linear amplitude
    assert [r.impacts_per_cycle for r in down] == [0.0, 0.0]
    for r in down:
        assert r.amplitude == pytest.approx(r.amplitude_without_damper, rel=1e-5)
    assert list(resp.hysteresis[1:]) == [True, True]
    assert resp.regime_change[1]  # non-periodic at 6 Hz, periodic-1 at 6.5 Hz


def test_continuation_starts_from_the_previous_state():
    chained = frequency_response(DamperModel(), [6.0, 6.5], 5.0, sweep="up")
    alone = frequency_response(DamperModel(), [6.5], 5.0, sweep="up")
    # from the 6 Hz motion the 6.5 Hz run lands on another branch than from the linear start
    assert chained.primary[1].impacts_per_cycle == 2.0
    assert alone.primary[0].impacts_per_cycle == 0.0


def test_independent_runs_on_an_executor_equal_serial_runs():
    f = np.array([3.0, 6.5, 7.0])
    serial = frequency_response(DamperModel(), f, 5.0, sweep="independent")
    with ThreadPoolExecutor(2) as ex:
        par = frequency_response(DamperModel(), f, 5.0, sweep="independent", executor=ex)
    np.testing.assert_array_equal(serial.amplitude, par.amplitude)
    assert [r.regime for r in serial.primary] == [r.regime for r in par.primary]


def test_bifurcation_points_give_one_point_per_cycle_of_the_period():
    resp = frequency_response(DamperModel(), [3.0, 7.0], 5.0, sweep="up")
    fs, xs = resp.bifurcation_points()
    periods = [r.period for r in resp.primary]
    assert fs.size == xs.size == sum(periods)


@pytest.mark.parametrize("kwargs,name", [
    ({"frequencies": [], "sweep": "up"}, "frequencies"),
    ({"frequencies": [3.0, 3.0], "sweep": "up"}, "frequencies"),
    ({"frequencies": [3.0], "sweep": "around"}, "sweep"),
    ({"frequencies": [3.0], "sweep": "up", "executor": object()}, "executor"),
    ({"frequencies": [3.0], "sweep": "up", "solver": "euler"}, "solver"),
])
def test_bad_arguments_name_the_parameter(kwargs, name):
    f = kwargs.pop("frequencies")
    with pytest.raises(ParameterError) as err:
        frequency_response(DamperModel(), f, 5.0, **kwargs)
    assert err.value.name == name
