"""Reference runs and impact-by-impact comparison."""

import dataclasses
import math

import numpy as np
import pytest
from _damper_reference import (
    IVP_RTOL,
    N_COMPARE,
    REFERENCE_RTOL,
    RESOLVED_BOUND,
    compare_impacts,
    reference,
    resolved_impacts,
    solve_ivp_impacts,
)

from acoustiviz.constants import DEFAULT_RTOL
from acoustiviz.dynamics import TABLE1, ImpactTable, InitialState, simulate


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
    ivp = solve_ivp_impacts(TABLE1, n_impacts=4, rtol=IVP_RTOL)
    ev = simulate(TABLE1, 0.3, rtol=1e-13).impacts
    c = compare_impacts(ivp, ev, 4)
    assert c.walls_match and c.velocity_error < 1e-9 and c.time_error < 1e-11


def test_independent_method_refuses_tolerances_at_the_round_off_floor():
    with pytest.raises(ValueError, match="rtol"):
        solve_ivp_impacts(TABLE1, n_impacts=1, rtol=3e-14)


def test_independent_method_reports_a_failure_instead_of_fewer_impacts(monkeypatch):
    import scipy.integrate

    real = scipy.integrate.solve_ivp
    calls = []

    def gives_up_on_the_third_phase(*args, **kwargs):
        calls.append(1)
        sol = real(*args, **kwargs)
        if len(calls) == 3:
            sol.status, sol.message = -1, "Required step size is less than spacing between numbers."
        return sol

    monkeypatch.setattr(scipy.integrate, "solve_ivp", gives_up_on_the_third_phase)
    with pytest.raises(RuntimeError, match="impact 2 of 4.*spacing between numbers"):
        solve_ivp_impacts(TABLE1, n_impacts=4, rtol=IVP_RTOL)


@pytest.fixture(scope="module")
def converged():
    """The reference run over 3 s and the independent method at two tolerances, 10x apart."""
    ref = reference(TABLE1, 3.0).impacts
    ivp = solve_ivp_impacts(TABLE1, n_impacts=N_COMPARE, rtol=IVP_RTOL)
    coarser = solve_ivp_impacts(TABLE1, n_impacts=N_COMPARE, rtol=10 * IVP_RTOL)
    return ref, ivp, coarser


#: Agreement the independent check asks for, s: twice the independent method's own error on the
#: impacts it resolves (at most about 1.5 x RESOLVED_BOUND) and a third of the error it must catch.
RESOLUTION = 3e-10
#: Relative impact-speed agreement asked for on the same impacts: the independent method's own
#: error there reached 6.5e-10 on an AMD EPYC and 1.2e-9 on a Xeon (its step control sums with
#: BLAS, whose kernels differ between processors); 2.5x above the larger.
SPEED_RESOLUTION = 3e-9


@pytest.mark.slow
def test_independent_method_confirms_the_reference_on_every_impact_it_resolves(converged):
    # The independent method (SciPy DOP853 on eq 15 in physical time, 4500 epsilon above the
    # round-off floor) is compared impact by impact over the leading impacts it resolves: its own
    # error, estimated by a run at a 10x looser tolerance, grows with the motion's sensitivity
    # (about 1e5 from the first impacts to the 40th), so it resolves about the first 15 impacts
    # to RESOLVED_BOUND (the first 10 with a 5x margin, 10 at least on any CPU); fewer would
    # leave the check without teeth.
    ref, ivp, coarser = converged
    assert len(ivp) == len(coarser) == N_COMPARE  # it reports a failure rather than fewer rows
    n = resolved_impacts(ivp, coarser, RESOLVED_BOUND)
    assert n >= 10, f"the independent method resolves only {n} impacts to {RESOLVED_BOUND:g} s"
    c = compare_impacts(ivp, ref, n)
    assert c.n == n and c.walls_match, c
    assert c.time_error < RESOLUTION and c.velocity_error < SPEED_RESOLUTION, c


def test_the_independent_check_catches_an_impact_time_off_by_1e_9_s(converged):
    ref, ivp, coarser = converged
    n = resolved_impacts(ivp, coarser, RESOLVED_BOUND)
    for k in (0, n // 2, n - 1):  # one impact time shifted by 1 ns
        shifted = ivp.time.copy()
        shifted[k] += 1e-9
        bad = dataclasses.replace(ivp, time=shifted)
        assert compare_impacts(bad, ref, n).time_error >= RESOLUTION
    # a whole run perturbed: the initial velocity changed by 1 part in 1e8 moves the first impact
    # by 1.1e-10 s, the 9th by 1.4e-9 s and the 11th by 3.2e-9 s; the comparison rejects it
    run = simulate(TABLE1, 1.5, rtol=REFERENCE_RTOL, initial=InitialState(v=2.0 * (1 + 1e-8))).impacts
    moved = compare_impacts(run, ref, n)
    assert moved.walls_match and 1e-9 < moved.time_error < 1e-8, moved
    assert not moved.time_error < RESOLUTION


def test_default_tolerance_reaches_1e_8_s_on_the_first_40_impact_times(converged):
    # the reference (event solver at 2e-15) is confirmed by the independent method on the
    # impacts it resolves (above) and is converged over all 40: it moves by less than 1e-9 s
    # when its tolerance halves (round-off differences between CPUs grow to about 1e-11 s by the
    # 40th impact, so this holds with a 20x margin)
    ref = converged[0]
    assert len(ref) >= N_COMPARE == 40
    finer = compare_impacts(simulate(TABLE1, 3.0, rtol=REFERENCE_RTOL / 2).impacts, ref)
    assert finer.n == N_COMPARE and finer.walls_match and finer.time_error < 1e-9
    run = simulate(TABLE1, 3.0)
    assert run.settings["rtol"] == DEFAULT_RTOL  # the default every front-end uses
    default = compare_impacts(run.impacts, ref)
    assert default.n == N_COMPARE and default.walls_match and default.time_error < 1e-8
