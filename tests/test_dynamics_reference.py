"""Reference runs and impact-by-impact comparison."""

import math

import numpy as np
from _damper_reference import compare_impacts, solve_ivp_impacts

from acoustiviz.dynamics import TABLE1, ImpactTable, simulate


def _table(t, u, wall):
    n = len(t)
    z = np.zeros(n)
    return ImpactTable(np.array(t), np.array(wall, float), np.array(u), np.array(u), z + 1, z, z, z, z)


def test_compare_impacts_measures_time_velocity_and_walls():
    ref = _table([1.0, 2.0, 3.0], [1.0, 2.0, 4.0], [1, -1, 1])
    same = compare_impacts(ref, ref, 3)
    assert (same.time_error, same.velocity_error, same.walls_match, same.n_agree) == (0, 0, True, 3)
    off = compare_impacts(_table([1.0, 2.1, 3.0], [1.0, 2.0, 4.4], [1, -1, -1]), ref, 3)
    assert math.isclose(off.time_error, 0.1) and math.isclose(off.velocity_error, 0.1)
    assert not off.walls_match and off.n_agree == 2
    short = compare_impacts(ref.head(2), ref, 3)
    assert short.velocity_error == math.inf


def test_independent_method_agrees_with_event_solver_on_early_impacts():
    ivp = solve_ivp_impacts(TABLE1, n_impacts=4, rtol=1e-12)
    ev = simulate(TABLE1, 0.3, rtol=1e-13).impacts
    c = compare_impacts(ivp, ev, 4)
    assert c.walls_match and c.velocity_error < 1e-9 and c.time_error < 1e-11
