"""The direct run of a start in one compiled call per stretch of cycles against one call per cycle."""

from dataclasses import replace

import numpy as np
import pytest

from acoustiviz.dynamics import _attractors
from acoustiviz.dynamics.forced import SCREENED_CHECKPOINT_RETURN, Excitation, SteadyStateOptions, attractors_at
from acoustiviz.dynamics.model import DamperModel


def _cycle_by_cycle(self, k0, next_try):
    """The search's direct run one driver call per cycle (the search looks at every cycle)."""
    return k0, self.step(k0)


def _same(a, b):
    assert len(a.attractors) == len(b.attractors)
    for x, y in zip(a.attractors, b.attractors, strict=True):
        assert (x.regime, x.period, x.cycles) == (y.regime, y.period, y.cycles)
        assert x.cycles_integrated == y.cycles_integrated
        assert x.amplitude == y.amplitude and x.amplitude_std_err == y.amplitude_std_err
        np.testing.assert_array_equal(x.poincare, y.poincare)
        np.testing.assert_array_equal(x.impact_times, y.impact_times)
        assert x.final_state == y.final_state
    assert (a.counts, a.seeded, a.cycles_integrated) == (b.counts, b.seeded, b.cycles_integrated)


@pytest.mark.parametrize("mass,frequency,solver", [
    (0.0385, 4.5, "event"),  # periodic orbits reached by several starts
    (0.0385, 5.5, "event"),  # chaotic and periodic motions coexisting
    (None, 5.0, "event"),  # every start on one chaotic motion
    (None, 6.0, "impact-map"),
])
def test_stretches_of_cycles_give_the_bits_of_one_call_per_cycle(monkeypatch, mass, frequency, solver):
    model, ex = DamperModel(), Excitation(frequency, 5.0)
    model = model if mass is None else replace(model, m=mass)
    options = SteadyStateOptions(solver=solver, checkpoint_return=SCREENED_CHECKPOINT_RETURN, reuse_known=True)
    fast = attractors_at(model, ex, options)
    monkeypatch.setattr(_attractors._Settler, "advance", _cycle_by_cycle)
    slow = attractors_at(model, ex, options)
    _same(fast, slow)


def test_the_full_search_is_unchanged_too(monkeypatch):
    """Every checkpoint tried and known orbits measured again (the defaults): the same bits either way."""
    model, ex = replace(DamperModel(), m=0.0385), Excitation(3.5, 5.0)
    fast = attractors_at(model, ex, SteadyStateOptions())
    monkeypatch.setattr(_attractors._Settler, "advance", _cycle_by_cycle)
    _same(fast, attractors_at(model, ex, SteadyStateOptions()))


def _runner(solver, state=None, max_impacts=200, rows=None):
    from acoustiviz.dynamics._forced_steady import _Runner, linear_start

    model, ex = replace(DamperModel(), m=0.0385), Excitation(5.5, 5.0)
    options = SteadyStateOptions(solver=solver, max_impacts_per_cycle=max_impacts)
    return _Runner(model, ex, options, linear_start(model, ex) if state is None else state, rows=rows)


@pytest.mark.parametrize("solver", ["event", "impact-map", "newmark"])
@pytest.mark.parametrize("carry", [False, True])
def test_cycles_in_one_call_give_the_bits_of_one_call_per_cycle(solver, carry):
    """Several cycles in one kernel call: the same states, impact rows, accumulators, cycle counts and times."""
    count = 12
    one, many = _runner(solver, rows=200 * count), _runner(solver, rows=200 * count)
    for run in (one, many):  # somewhere along the transient, not at the start
        run.cycles(5, 0, np.zeros(5), False)
    acc_one, acc_many = np.array([0.0, 0.0, 0.0, -np.inf, np.inf]), np.array([0.0, 0.0, 0.0, -np.inf, np.inf])
    n, sections = 0, []
    for _ in range(count):
        n, status = one.cycle(n if carry else 0, acc_one, True)
        sections.append(one.state())
        assert status == 0
    states = np.full((count, 4), np.nan) if carry else None
    n_many, status, done = many.cycles(count, 0, acc_many, True, states)
    assert (status, done, many.k, many.total) == (0, count, one.k, one.total)
    assert n_many == n and n > (count if carry else 0)  # impacts in every cycle, carried on or rewritten
    np.testing.assert_array_equal(many.st, one.st)
    np.testing.assert_array_equal(acc_many, acc_one)
    np.testing.assert_array_equal(many.imp[:n], one.imp[:n])
    if carry:
        np.testing.assert_array_equal(states, np.array(sections))


def test_cycles_in_one_call_stop_where_one_call_per_cycle_stops():
    """A cycle with more impacts than allowed (here the 17th) stops both at that cycle, in the same state."""
    one, many = _runner("event", max_impacts=4), _runner("event", max_impacts=4)
    acc = np.zeros(5)
    status = 0
    while not status and one.k < 50:
        _, status = one.cycle(0, acc, False)
    assert status != 0 and one.k > 1  # some cycles pass, then one has more than 4 impacts
    _, status_many, done = many.cycles(50, 0, np.zeros(5), False)
    assert (status_many, done, many.k, many.total) == (status, one.k, one.k, one.total)
    np.testing.assert_array_equal(many.st, one.st)


def test_a_window_the_solver_stops_reports_the_cycle_and_state_of_the_stop():
    """The window's run in stretches stops where one call per cycle stops, its twin's cycles counted up to there."""
    from acoustiviz.dynamics._forced_steady import linear_start
    from acoustiviz.dynamics._measure import measure_window

    one = _runner("event", max_impacts=4)
    acc = np.zeros(5)
    status = 0
    while not status and one.k < 50:
        _, status = one.cycle(0, acc, False)
    assert status != 0 and one.k > 1
    steady = measure_window(one.model, Excitation(5.5, 5.0), SteadyStateOptions(max_impacts_per_cycle=4),
                            linear_start(one.model, Excitation(5.5, 5.0)), 100, 1000)
    assert not steady.success
    assert steady.cycles == 100 + one.k
    assert steady.final_state == tuple(one.state())
    assert steady.cycles_integrated == 1000 + one.k + (one.k - 1)  # the twin does not run the cycle that stopped
