"""Frequency response of the forced damper: every attractor, continuation, parallel runs."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from acoustiviz.dynamics.forced import attractor_response, frequency_response, same_motion
from acoustiviz.errors import ParameterError


@pytest.mark.slow
def test_coexisting_attractors_at_7_hz_are_all_reported(table1_model):
    """Table 1 at 7 Hz, 5 N: the motion without impacts and the two-impact orbit coexist."""
    resp = attractor_response(table1_model, [7.0], 5.0, sweep="independent", starts=6)
    fa = resp.per_frequency[0]
    assert fa.basin_fractions.sum() == pytest.approx(1.0) and sum(fa.counts) == 6
    quiet = [a for a in fa.attractors if a.impacts_per_cycle == 0]
    assert len(quiet) == 1  # the impact mass floating anywhere is one motion, not several
    q = quiet[0]
    assert q.regime == "periodic-1" and q.converged
    assert q.amplitude == pytest.approx(q.amplitude_without_damper, rel=1e-9)
    assert q.max_floquet_modulus == pytest.approx(1.0, abs=1e-6) and q.stable  # the free impact mass: neutral
    two = [a for a in fa.attractors if a.period == 1 and a.impacts_per_cycle == 2]
    assert two and two[0].stable and two[0].max_floquet_modulus < 1 and two[0].reduction_db > 3
    assert two[0].residual < 1e-9
    for i, a in enumerate(fa.attractors):  # de-duplicated
        assert not any(same_motion(a, b) for b in fa.attractors[i + 1:])


def test_continuation_seeds_the_neighbouring_frequency(table1_model):
    up = attractor_response(table1_model, [6.5, 7.0], 5.0, sweep="up", starts=2)
    ind = attractor_response(table1_model, [6.5, 7.0], 5.0, sweep="independent", starts=2)
    assert up.rounds >= 1 and sum(up.per_frequency[1].seeded) == len(up.per_frequency[0].attractors)
    assert sum(up.per_frequency[0].seeded) == 0  # nothing below 6.5 Hz
    assert ind.rounds == 0 and all(sum(fa.seeded) == 0 for fa in ind.per_frequency)


@pytest.mark.slow
def test_attractors_on_an_executor_equal_serial_runs(table1_model):
    f = np.array([6.5, 7.0])
    serial = attractor_response(table1_model, f, 5.0, sweep="independent", starts=2)
    with ThreadPoolExecutor(2) as ex:
        par = attractor_response(table1_model, f, 5.0, sweep="independent", starts=2, executor=ex)
    amps = [[a.amplitude for a in fa.attractors] for fa in serial.per_frequency]
    assert amps == [[a.amplitude for a in fa.attractors] for fa in par.per_frequency]


def test_bifurcation_points_give_n_points_for_period_n(table1_model):
    resp = attractor_response(table1_model, [7.0], 5.0, sweep="independent", starts=3)
    fs, xs = resp.bifurcation_points()
    assert fs.size == xs.size == sum(len(a.poincare) for _, _, a, _ in resp.entries())
    for _, _, a, _ in resp.entries():
        assert len(a.poincare) == (a.period if a.period else a.measured_cycles)


def test_single_start_sweep_down_from_the_linear_start_stays_without_impacts(table1_model):
    resp = frequency_response(table1_model, [6.5, 7.0], 5.0, sweep="down")
    for r in resp.primary:
        assert r.impacts_per_cycle == 0 and r.converged
        assert r.amplitude == pytest.approx(r.amplitude_without_damper, rel=1e-9)


@pytest.mark.parametrize("kwargs,name", [
    ({"frequencies": [], "sweep": "up"}, "frequencies"),
    ({"frequencies": [3.0, 3.0], "sweep": "up"}, "frequencies"),
    ({"frequencies": [3.0], "sweep": "around"}, "sweep"),
    ({"frequencies": [3.0], "sweep": "up", "executor": object()}, "executor"),
    ({"frequencies": [3.0], "sweep": "up", "solver": "euler"}, "solver"),
])
def test_bad_arguments_name_the_parameter(kwargs, name, table1_model):
    f = kwargs.pop("frequencies")
    with pytest.raises(ParameterError) as err:
        frequency_response(table1_model, f, 5.0, **kwargs)
    assert err.value.name == name


@pytest.mark.parametrize("kwargs,name", [
    ({"starts": 0}, "starts"),
    ({"tolerance": 0.0}, "tolerance"),
    ({"rtol": 1e-2}, "rtol"),
    ({"max_cycles": 3}, "max_cycles"),
    ({"sweep": "around"}, "sweep"),
])
def test_bad_attractor_settings_name_the_parameter(kwargs, name, table1_model):
    with pytest.raises(ParameterError) as err:
        attractor_response(table1_model, [5.0], 5.0, **kwargs)
    assert err.value.name == name
