"""Exact maxima of the main mass, checked against independent computations.

The reference is SciPy's DOP853 (``solve_ivp``) on eq 15 with the right-hand side written here,
each flight and each contact a separate integration, and the turning points of x located by its
events on the velocity; and, for free vibration, the closed form of a damped oscillator.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from acoustiviz.dynamics import DamperModel, InitialState, exact_maxima, simulate
from acoustiviz.dynamics.maxima import Maxima, excursion_maxima
from acoustiviz.dynamics.metrics import damping_metrics, positive_maxima, sample_times
from acoustiviz.errors import ParameterError


def _ivp_turning_points(model, t_stop, rtol=1e-12):
    """(time s, x m) of every zero of the main-mass velocity up to ``t_stop``, by solve_ivp."""
    M, K, C, m = model.M, model.K, model.C, model.m
    hg, kh, c1 = 0.5 * model.gap, model.k_hertz, model.c1

    def rhs_for(s):
        def rhs(_t, q):
            x, v, y, w = q
            f = 0.0
            if s != 0 and s * (y - x) - hg > 0:
                f = kh * (s * (y - x) - hg) ** 1.5 + c1 * s * (w - v)
            return [v, (s * f - K * x - C * v) / M, w, -s * f / m]

        return rhs

    def crossing(s, direction):
        def g(_t, q):
            return s * (q[2] - q[0]) - hg

        g.terminal, g.direction = True, direction
        return g

    def turn(_t, q):
        return q[1]

    q, t0, s, found = np.array(InitialState().as_tuple(model)), 0.0, 0, []
    while t0 < t_stop:
        events = [crossing(1, 1), crossing(-1, 1)] if s == 0 else [crossing(s, -1)]
        sol = solve_ivp(rhs_for(s), (t0, t_stop), q, method="DOP853", rtol=rtol, atol=1e-15,
                        events=[*events, turn], first_step=None if s == 0 else 1e-9)
        found += [(t, qq[0]) for t, qq in zip(sol.t_events[-1], sol.y_events[-1], strict=True)]
        if sol.status != 1:
            break
        k = (0 if sol.t_events[0].size else 1) if s == 0 else 0
        s = (1 if k == 0 else -1) if s == 0 else 0
        t0, q = float(sol.t_events[k][0]), sol.y_events[k][0]
    return np.array(found)


def test_turning_points_match_an_independent_integration_also_inside_contacts():
    # a soft contact lasts long enough for the main mass to turn while touching
    model = DamperModel(m=0.2, k_hertz=1e5, c1=2.0)
    run = simulate(model, 1.0, rtol=1e-13)
    ref = _ivp_turning_points(model, 1.0)
    ext = run.extrema
    assert len(ext) == len(ref)
    np.testing.assert_allclose(ext.time, ref[:, 0], rtol=0, atol=1e-8)
    np.testing.assert_allclose(ext.value, ref[:, 1], rtol=0, atol=1e-9)
    imp = run.impacts
    in_contact = [np.any((imp.time < t) & (t < imp.time + imp.duration)) for t in ext.time]
    assert sum(in_contact) >= 3  # the contact path was exercised
    assert np.all(np.diff(ext.time) > 0) and set(np.unique(ext.kind)) == {-1.0, 1.0}


def test_eq16_of_the_issue_example_is_the_exact_value():
    # Table 1 with m = 60 g, d = 4 cm: an impact falls 6e-5 s before the first maximum
    model = DamperModel(m=0.06)
    run = simulate(model, 5.0)
    ref = _ivp_turning_points(model, 0.3)
    maxima = ref[ref[:, 1] > 0]
    want = (maxima[0, 1] - maxima[1, 1]) / (maxima[1, 0] - maxima[0, 0])
    got = damping_metrics(run).two_maxima
    assert got.value == pytest.approx(want, rel=1e-9)
    assert round(100 * got.value, 4) == 0.9497  # cm/s; sampling at 200 per period gave 0.9427
    assert (got.t_start, got.t_stop) == pytest.approx((maxima[0, 0], maxima[1, 0]), abs=1e-10)


def test_exact_maxima_bound_a_dense_evaluation():
    # no sample of the run's own dense output exceeds an exact maximum, and the samples approach it
    model = DamperModel(m=0.06)
    run = simulate(model, 2.0)
    mx = exact_maxima(run)
    assert mx.time.size >= 8
    for tk, xk in zip(mx.time[:8], mx.value[:8], strict=True):
        t = np.linspace(tk - 2e-3, tk + 2e-3, 4001)
        x = simulate(model, tk + 3e-3, t_eval=t).x
        assert x.max() <= xk + 1e-13
        assert x.max() >= xk - 0.5 * 1e-6**2 * 1e3 * abs(xk)  # (step / 2)^2 x'' with x'' ~ 1e3 x


def test_free_vibration_maxima_are_the_closed_form_ones():
    # no impacts (a gap wider than any excursion): x = e^{-a t} (v0 / wd) sin(wd t), maxima at
    # tan(wd t) = wd / a
    model = DamperModel(gap=2.0, C=0.5)
    run = simulate(model, 1.0, initial=InitialState(v=0.5))
    assert len(run.impacts) == 0
    a = model.C / (2 * model.M)
    wd = math.sqrt(model.K / model.M - a * a)
    t1 = math.atan2(wd, a) / wd
    tk = t1 + 2 * math.pi / wd * np.arange(5)
    tk = tk[tk < 1.0]
    xk = np.exp(-a * tk) * 0.5 / wd * np.sin(wd * tk)
    mx = exact_maxima(run)
    n = tk.size - (1 if tk[-1] > 1.0 - math.pi / wd else 0)  # the last may still be open
    # times near 1 s (ulp 2e-16) built from atan2 and sums of periods: 1e-12 s is well above their round-off
    np.testing.assert_allclose(mx.time[:n], tk[:n], rtol=0, atol=1e-12)
    np.testing.assert_allclose(mx.value[:n], xk[:n], rtol=1e-13)


@pytest.mark.slow
def test_impact_map_kinks_and_newmark_interpolant_give_maxima_near_the_exact_ones():
    # the two approximate solvers follow the exact maxima to their own accuracy (an impact falls
    # 6e-5 s before the first maximum here, the hardest case)
    model = DamperModel(m=0.06)
    exact = exact_maxima(simulate(model, 0.4))
    nm = exact_maxima(simulate(model, 0.4, solver="newmark", dt=5e-7))
    np.testing.assert_allclose(nm.value[:2], exact.value[:2], rtol=2e-5)
    np.testing.assert_allclose(nm.time[:2], exact.time[:2], atol=2e-6)
    im = exact_maxima(simulate(model, 0.4, solver="impact-map"))
    np.testing.assert_allclose(im.value[:2], exact.value[:2], rtol=2e-3)
    np.testing.assert_allclose(im.time[:2], exact.time[:2], atol=1e-3)


def test_sampled_maxima_converge_to_the_exact_ones():
    model = DamperModel(m=0.06)
    fine = simulate(model, 1.0, t_eval=sample_times(1.0, model, 20000))
    exact = exact_maxima(fine)
    sampled = positive_maxima(fine.t, fine.x)
    np.testing.assert_allclose(sampled.value[:4], exact.value[:4], rtol=1e-6)


def test_excursion_grouping_keeps_the_largest_turning_point_and_drops_an_open_excursion():
    # x: 0 -> 3 -> 2 -> 4 -> -1 (one excursion, its max 4), -> 5 -> end at 1 (still open)
    t = np.arange(7.0)
    x = np.array([0.0, 3.0, 2.0, 4.0, -1.0, 5.0, 1.0])
    mx = excursion_maxima(t, x)
    assert mx.time.tolist() == [3.0] and mx.value.tolist() == [4.0]
    # a record starting inside an excursion counts it from its first value
    assert excursion_maxima([0.0, 1.0, 2.0], [2.0, 1.0, -1.0]).value.tolist() == [2.0]
    assert isinstance(mx, Maxima)


def test_bad_inputs_are_refused():
    with pytest.raises(ParameterError, match="result"):
        exact_maxima(object())
    with pytest.raises(ParameterError, match="x"):
        damping_metrics(np.arange(5.0))
    with pytest.raises(ParameterError, match="t"):
        excursion_maxima([0.0, 1.0], [1.0])
