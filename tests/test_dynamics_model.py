"""The damper model: Table 1 defaults, derived quantities and argument checks."""

import math

import pytest

from acoustiviz._validate import ParameterError
from acoustiviz.core import contact
from acoustiviz.dynamics import TABLE1, DamperModel, InitialState


def test_table1_defaults():
    assert (TABLE1.M, TABLE1.K, TABLE1.C, TABLE1.m) == (0.5, 500.0, 0.05, 0.0405)
    assert (TABLE1.k_hertz, TABLE1.c1, TABLE1.gap) == (5.6e8, 20.0, 0.04)
    assert TABLE1.clip_tensile is False
    assert TABLE1.effective_mass == pytest.approx(0.0405 * 0.5 / 0.5405)
    assert TABLE1.main_frequency == pytest.approx(math.sqrt(1000.0))
    assert TABLE1.underdamped


def test_contact_quantities_follow_hertz():
    u = 1.3
    meff = TABLE1.effective_mass
    assert TABLE1.contact_duration(u) == pytest.approx(contact.contact_duration(u, 5.6e8, meff))
    kt = 1.5 * 5.6e8 * math.sqrt(contact.max_approach(u, 5.6e8, meff))
    assert TABLE1.contact_frequency(u) == pytest.approx(math.sqrt(kt / meff))


def test_energy_includes_the_hertz_term():
    d = 1e-4
    e = TABLE1.energy(0.0, 0.0, 0.02 + d, 0.0)
    assert e == pytest.approx(0.4 * 5.6e8 * d**2.5)


def test_initial_state_defaults_follow_figure_5():
    x, v, y, w = InitialState().as_tuple(TABLE1)
    assert (x, v, y, w) == (0.0, 2.0, 0.0, 0.0)
    assert InitialState().max_relative_speed(TABLE1) == pytest.approx(math.sqrt(2.0 / TABLE1.effective_mass))


@pytest.mark.parametrize("field, value", [("M", 0), ("m", -1), ("gap", 0), ("K", -5),
                                          ("C", -0.1), ("k_hertz", 0), ("c1", -1)])
def test_bad_parameters_are_named(field, value):
    with pytest.raises(ParameterError) as info:
        DamperModel(**{field: value})
    assert info.value.name == field


def test_impact_mass_must_start_inside_the_cavity():
    with pytest.raises(ParameterError, match="cavity"):
        InitialState(y=0.03).as_tuple(TABLE1)
    with pytest.raises(ParameterError, match="v"):
        InitialState(v=float("nan"))
