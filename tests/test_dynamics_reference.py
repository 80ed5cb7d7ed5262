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


def test_default_tolerance_reaches_1e_8_s_on_the_first_40_impact_times():
    # the converged reference (event solver at 2e-15) is itself checked: it moves by less than
    # 1e-9 s when its tolerance halves, and an independent method (SciPy DOP853 on eq 15 in physical
    # time, at its finest tolerance) approaches it to within its own chaotic error growth
    from _damper_reference import N_COMPARE, REFERENCE_RTOL, reference

    from acoustiviz.constants import DEFAULT_RTOL

    ref = reference(TABLE1, 3.0).impacts
    assert len(ref) >= N_COMPARE == 40
    finer = compare_impacts(simulate(TABLE1, 3.0, rtol=REFERENCE_RTOL / 2).impacts, ref)
    assert finer.walls_match and finer.time_error < 1e-9
    ivp = compare_impacts(solve_ivp_impacts(TABLE1, n_impacts=N_COMPARE, rtol=3e-14), ref)
    assert ivp.n == N_COMPARE and ivp.walls_match and ivp.time_error < 2e-7
    run = simulate(TABLE1, 3.0)
    assert run.settings["rtol"] == DEFAULT_RTOL  # the default every front-end uses
    default = compare_impacts(run.impacts, ref)
    assert default.n == N_COMPARE and default.walls_match and default.time_error < 1e-8
