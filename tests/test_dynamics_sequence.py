"""The one impact sequence: built from a simulation's impact table and from a forced steady state."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from acoustiviz.dynamics import ImpactSequence, ImpactTable, InitialState, simulate
from acoustiviz.errors import ParameterError
from acoustiviz.sound import ImpactSequence as SoundImpactSequence


def test_the_sound_and_the_dynamics_share_one_type():
    assert SoundImpactSequence is ImpactSequence


def test_an_impact_tables_sequence_keeps_times_walls_and_speeds(table1_model):
    table = simulate(table1_model, 0.5, initial=InitialState(v=2.0)).impacts
    seq = table.sequence()
    assert len(seq) == len(table) > 3
    np.testing.assert_array_equal(seq.times, table.time)
    np.testing.assert_array_equal(seq.walls, table.wall.astype(int))
    np.testing.assert_array_equal(seq.velocities, np.abs(table.approach_velocity))
    assert seq == ImpactSequence.from_table(table)  # the generic reader agrees


def test_a_steady_states_measured_impacts_make_a_sequence():
    state = SimpleNamespace(impact_times=np.array([0.1, 0.15, 0.2]), impact_walls=np.array([1.0, -1.0, 1.0]),
                            impact_speeds=np.array([0.4, 0.3, 0.5]), impact_phases=np.zeros(3))
    seq = ImpactSequence.from_steady_state(state)
    assert seq == ImpactSequence([0.1, 0.15, 0.2], [1, -1, 1], [0.4, 0.3, 0.5])
    assert seq != ImpactSequence([0.1, 0.15, 0.2], [1, -1, 1], [0.4, 0.3, 0.6])


def test_a_steady_states_grazes_make_no_impact_and_times_count_from_the_origin():
    """A contact recorded at zero or negative approach speed (a graze) is left out; ``origin`` shifts the times."""
    state = SimpleNamespace(impact_times=np.array([2.1, 2.15, 2.2, 2.3]), impact_walls=np.array([1.0, -1.0, 1.0, -1.0]),
                            impact_speeds=np.array([0.4, -0.3, 0.5, 0.0]))
    seq = ImpactSequence.from_steady_state(state, origin=2.0)
    np.testing.assert_allclose(seq.times, [0.1, 0.2], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(seq.walls, [1, 1])
    np.testing.assert_array_equal(seq.velocities, [0.4, 0.5])
    assert len(ImpactSequence.from_steady_state(SimpleNamespace(impact_times=np.empty(0), impact_walls=np.empty(0),
                                                                impact_speeds=np.empty(0)))) == 0


def test_an_empty_table_gives_an_empty_sequence_and_bad_rows_are_refused():
    empty = ImpactTable.from_rows(np.empty((0, 8)))
    assert len(empty.sequence()) == 0
    bad = ImpactTable.from_rows(np.array([[0.1, 0.5, 1.0, 0.8, 1e-4, 10.0, 1e-3, 0.0]]))
    with pytest.raises(ParameterError, match="wall"):
        bad.sequence()
