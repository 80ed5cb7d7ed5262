"""Periodic orbits by shooting: linear limit, Masri-Caughey, Floquet multipliers, a period doubling."""

import math

import numpy as np
import pytest

from acoustiviz.dynamics.forced import (
    Excitation,
    PoincareMap,
    attractors_at,
    check_settings,
    section_scale,
    shoot,
    steady_state,
)
from acoustiviz.dynamics.model import DamperModel
from acoustiviz.dynamics.periodic import masri_caughey

#: A damper whose symmetric two-impacts-per-cycle motion is stable near resonance.
MC_MODEL = DamperModel(C=1.0, m=0.1)


def _linear_reference(model, f, amp, kind):
    """|X| by the closed form of the main mass alone (independent of the code under test)."""
    w = 2 * math.pi * f
    den = math.hypot(model.K - model.M * w * w, model.C * w)
    return amp / den if kind == "force" else amp * math.hypot(model.K, model.C * w) / den


@pytest.mark.parametrize("solver", ["event", "impact-map"])
@pytest.mark.parametrize("kind,amp", [("force", 5.0), ("base", 0.01)])
def test_without_impacts_the_orbit_is_the_linear_steady_state_to_1e_9(solver, kind, amp):
    model = DamperModel(C=0.05, gap=10.0)  # Table 1's light damping: the transient decays 0.1 % a cycle
    for f in (3.0, 4.0, 6.0, 7.0):
        r = steady_state(model, Excitation(f, amp, kind), solver=solver, initial=(0.0, 0.0, 0.0, 0.0),
                         tolerance=1e-12, restitution=0.5 if solver == "impact-map" else None)
        assert r.regime == "periodic-1" and r.converged and r.residual < 1e-12
        assert r.impacts_per_cycle == 0
        assert r.amplitude == pytest.approx(_linear_reference(model, f, amp, kind), rel=1e-9)
        assert r.cycles < 20  # Newton, not thousands of cycles of transient


def test_linear_multipliers_are_exp_lambda_t():
    """Monodromy of the linear system: exp((-a ± i ω_d) T) for the main mass, 1 twice for the free impact mass."""
    model = DamperModel(C=2.0, gap=10.0)
    a = model.C / (2 * model.M)
    wd = math.sqrt(model.K / model.M - a * a)
    for f in (3.0, 5.0, 7.0):
        r = steady_state(model, Excitation(f, 5.0), initial=(0.0, 0.0, 0.0, 0.0), tolerance=1e-12)
        mu = r.floquet
        lam = np.exp(complex(-a, wd) / f)
        osc = sorted(mu, key=lambda z: abs(z - 1))[2:]  # the two farthest from 1
        assert sorted([z.imag for z in osc]) == pytest.approx(sorted([lam.imag, -lam.imag]), abs=1e-8)
        assert [z.real for z in osc] == pytest.approx([lam.real] * 2, abs=1e-8)
        free = sorted(mu, key=lambda z: abs(z - 1))[:2]
        assert np.max(np.abs(np.array(free) - 1)) < 1e-5
        assert r.stable  # neutral, not unstable


@pytest.mark.parametrize("f,e", [(4.9, 0.5), (5.0, 0.5), (5.3, 0.5), (5.3, 0.8)])
def test_shooting_lands_on_masri_caughey_to_1e_10(f, e):
    """From a start 1 % off, Newton on the impact map's P(s) = s finds the closed-form orbit."""
    ex = Excitation(f, 2.0)
    settings = check_settings(MC_MODEL, ex, solver="impact-map", restitution=e)
    scale = section_scale(MC_MODEL, ex)
    pmap = PoincareMap(MC_MODEL, ex, settings)
    sols = [s for s in masri_caughey(MC_MODEL, ex, e) if s.valid]
    assert sols
    for s in sols:
        x, v, y, w = s.state(MC_MODEL, ex, 0.0)
        exact = np.array([x, v, y - x, w - v])
        start = exact + 0.01 * scale * np.array([1.0, -1.0, 0.5, 1.0])
        shot = shoot(pmap, start, 1, 1e-13, scale)
        assert shot.converged and shot.iterations <= 8
        np.testing.assert_allclose(shot.point / scale, exact / scale, rtol=0, atol=1e-10)


def test_masri_caughey_orbit_stability_agrees_with_the_direct_run():
    """The stable closed-form orbit is what the direct run settles on, with every multiplier inside."""
    ex = Excitation(5.3, 2.0)
    r = steady_state(MC_MODEL, ex, solver="impact-map", restitution=0.5, tolerance=1e-12)
    s = min((q for q in masri_caughey(MC_MODEL, ex, 0.5) if q.valid), key=lambda q: abs(q.x0 - r.poincare[0, 0]))
    assert r.regime == "periodic-1" and r.stable and r.max_floquet_modulus < 1
    np.testing.assert_allclose(r.impact_speeds, s.approach_speed, rtol=1e-10)
    assert r.amplitude == pytest.approx(s.amplitude, rel=1e-10)  # the closed form's maximum, refined


def test_a_multiplier_crosses_minus_one_at_a_period_doubling():
    """Table 1 at 5 N: the five-impact period-1 orbit of 4.5 Hz, continued by shooting, loses
    stability through -1 near 4.5185 Hz, and a stable period-2 orbit branches off it."""
    model = DamperModel()
    r0 = steady_state(model, Excitation(4.5, 5.0))
    assert r0.regime == "periodic-1" and r0.impacts_per_cycle == 5 and r0.stable
    point, before, split = r0.poincare[0], None, []
    for f in (4.515, 4.516, 4.517, 4.518, 4.519, 4.520):
        ex = Excitation(f, 5.0)
        scale = section_scale(model, ex)
        pmap = PoincareMap(model, ex, check_settings(model, ex))
        shot = shoot(pmap, point, 1, 1e-9, scale)
        assert shot.converged
        point = shot.point
        lead = shot.multipliers[np.argmin(shot.multipliers.real)]
        if lead.real < -1:
            if not split:  # the first frequency beyond the crossing: stable just below it
                assert before is not None and np.max(np.abs(before)) < 1
            assert abs(lead.imag) < 1e-9  # a real multiplier leaves through -1
            w, vec = np.linalg.eig(shot.jacobian)
            v = vec[:, np.argmin(w.real)].real
            two = shoot(pmap, point + 0.03 * v / np.max(np.abs(v)) * scale, 2, 1e-9, scale)
            assert two.converged and two.stable
            split.append(np.max(np.abs(pmap(two.point, 1) - two.point) / scale))  # a genuine period 2
        before = shot.multipliers
    assert len(split) == 2 and 1e-3 < split[0] < split[1]  # the period-2 orbit grows from the period-1 one


@pytest.mark.slow
def test_two_contact_tolerances_find_the_same_attractors_at_5_hz():
    """Table 1 at 5 Hz, 5 N: rtol 1e-10 and 1e-12 give the same attractors, non-periodic
    statistics within their stated errors.

    Compared: the attractors reached from at least two of the six starts at either tolerance. An
    attractor reached from one start only has a basin small enough that whether a start's chaotic
    transient falls into it depends on round-off: at 5 Hz a period-1 orbit is reached from one
    start of six at rtol 1.1e-10 and 1.1e-12 and from none at 1e-10, 0.9e-10, 1e-12 and 0.9e-12
    (the sampling of the starts, not the tolerance, decides it).
    """
    model, ex = DamperModel(), Excitation(5.0, 5.0)
    sets = [attractors_at(model, ex, check_settings(model, ex, rtol=rtol, starts=6)) for rtol in (1e-10, 1e-12)]

    def common(s):
        kept = [x for x, c in zip(s.attractors, s.counts, strict=True) if c >= 2]
        assert len({x.regime for x in kept}) == len(kept)  # one of each regime here: matched by regime
        return {x.regime: x for x in kept}

    a, b = (common(s) for s in sets)
    assert a and set(a) == set(b)
    for regime, p in a.items():
        q = b[regime]
        if p.period:
            assert p.amplitude == pytest.approx(q.amplitude, rel=1e-8)
        else:
            assert abs(p.amplitude - q.amplitude) < 3 * math.hypot(p.amplitude_std_err, q.amplitude_std_err)
            assert abs(p.lyapunov - q.lyapunov) < 3 * math.hypot(p.lyapunov_std_err, q.lyapunov_std_err)


def test_newton_steps_are_the_least_norm_solution_without_blas():
    """The step solve (plain Jacobi SVD) equals the pseudo-inverse's, regular and rank-deficient."""
    from acoustiviz.dynamics._shooting import PINV_RCOND, pinv_solve

    rng = np.random.default_rng(7)
    for k in range(60):
        a = rng.normal(size=(4, 4))
        if k % 3 == 0:  # a floating impact mass: a direction the map does not move
            a[:, 3] = 2.0 * a[:, 2]
        b = rng.normal(size=4)
        x = pinv_solve(a, b, PINV_RCOND)
        # independent: the normal equations of the least-norm solution, a^T a x = a^T b with x in range(a^T)
        np.testing.assert_allclose(a.T @ (a @ x), a.T @ b, rtol=0, atol=1e-10 * np.abs(a.T @ b).max())
        np.testing.assert_allclose(x, np.linalg.pinv(a, rcond=PINV_RCOND) @ b, rtol=1e-9, atol=1e-12)


def test_a_solve_is_the_same_bit_for_bit_whatever_its_map_did_before():
    """The search depends on the last bits of the orbit points (``_shooting`` module docstring): a
    solve from one start must give the same point, residual, steps, multipliers and cost, from a
    fresh map or from one that has evaluated other points and periods."""
    model, ex = DamperModel(), Excitation(4.5, 5.0)
    settings = check_settings(model, ex)
    scale = section_scale(model, ex)
    orbit = steady_state(model, ex).poincare[0]
    start = orbit + 0.02 * scale * np.array([1.0, -1.0, 0.5, 1.0])

    def solve(pmap):
        before = pmap.cycles
        shot = shoot(pmap, start, 1, 1e-9, scale)
        return shot, pmap.cycles - before

    used = PoincareMap(model, ex, settings)
    first, cost = solve(used)
    assert first.converged and first.iterations >= 2  # Newton steps, not a start already on the orbit
    shoot(used, orbit - 0.05 * scale, 2, 1e-9, scale)  # the map's state moved elsewhere in between
    used(start + 0.1 * scale, 3)
    for shot, c in (solve(used), solve(PoincareMap(model, ex, settings))):
        assert np.array_equal(shot.point, first.point) and shot.residual == first.residual
        assert shot.iterations == first.iterations and c == cost
        assert np.array_equal(shot.multipliers, first.multipliers)
