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
