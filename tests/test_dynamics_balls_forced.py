"""Several balls in operation: the forced multi-ball kernel and the attractors of its damper."""

import math

import numpy as np
import pytest

from acoustiviz._validate import ParameterError
from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics.balls import BallState, Cavity, MultiBallModel
from acoustiviz.dynamics.balls_forced import (
    ball_attractor_response,
    ball_attractors_at,
    ball_start_states,
    check_ball_settings,
)
from acoustiviz.dynamics.balls_solve import simulate_balls
from acoustiviz.dynamics.forced import Excitation, attractors_at, check_settings

#: A damper and a forcing with a stable period-1 orbit of four impacts per cycle.
PERIODIC = DamperModel(C=5.0)
PERIODIC_FORCING = Excitation(4.0, 10.0)
AMPLITUDE_RTOL = 1e-6


def _linear(model, frequency, force):
    """Steady complex amplitude in m of ``M x'' + C x' + K x = F0 cos wt``."""
    w = 2.0 * math.pi * frequency
    return force / complex(model.K - model.M * w * w, model.C * w)


def test_without_contact_the_main_mass_follows_the_linear_forced_response():
    model = MultiBallModel.from_damper(DamperModel(C=0.5, gap=10.0), 2)
    f, f0 = 3.0, 4.0
    x = _linear(model, f, f0)
    w = 2.0 * math.pi * f
    start = BallState(x.real, -w * x.imag)  # on the steady state at t = 0: no transient
    t = np.linspace(0.0, 4.0, 401)
    r = simulate_balls(model, 4.0, initial=start, excitation=Excitation(f, f0), t_eval=t)
    assert r.success and len(r.impacts) == 0
    exact = (x * np.exp(1j * w * t)).real
    assert np.max(np.abs(r.x - exact)) < 1e-9 * abs(x)
    np.testing.assert_allclose(r.w, 0.0, atol=0.0)  # the balls stay at rest, untouched


def test_without_contact_the_attractor_is_the_linear_steady_state():
    model = MultiBallModel.from_damper(DamperModel(C=0.5, gap=10.0), 3)
    ex = Excitation(3.0, 4.0)
    fa = ball_attractors_at(model, ex, check_ball_settings(model, ex, starts=1, max_cycles=50))
    (a,) = fa.attractors
    assert a.regime == "periodic-1" and a.impacts_per_cycle == 0
    assert a.amplitude == pytest.approx(abs(_linear(model, 3.0, 4.0)), rel=1e-9)


def _single_ball(model, ex):
    fa = attractors_at(model, ex, check_settings(model, ex, starts=1, max_cycles=300))
    (a,) = fa.attractors
    assert a.regime == "periodic-1"  # the reference: a stable orbit found by shooting
    return a


def _multi(model, ex):
    fa = ball_attractors_at(model, ex, check_ball_settings(model, ex, starts=1, max_cycles=300))
    (a,) = fa.attractors
    return a


def test_one_ball_through_the_multi_ball_path_agrees_with_forced():
    ref = _single_ball(PERIODIC, PERIODIC_FORCING)
    a = _multi(MultiBallModel.from_damper(PERIODIC, 1), PERIODIC_FORCING)
    assert a.period == ref.period and a.impacts_per_cycle == ref.impacts_per_cycle
    assert a.amplitude == pytest.approx(ref.amplitude, rel=AMPLITUDE_RTOL)
    # the multipliers of differences of the direct map: those of the single-ball shooting
    assert a.stable and a.floquet.size == 4
    np.testing.assert_allclose(np.abs(a.floquet), np.abs(ref.floquet), rtol=0, atol=1e-4)
    # the final state in the single-ball form (x, v, y, w), on the same orbit's section point
    np.testing.assert_allclose(a.final_state, ref.final_state, rtol=0, atol=1e-7)


def test_two_cavities_of_half_balls_act_as_one_ball_of_doubled_contact():
    """Two identical cavities, each with one ball of half the mass, started alike, stay alike.

    Each wall then pushes its half ball with ``k δ^1.5 + c δ'`` and the main mass feels twice that:
    the motion of one ball of the whole mass whose contact law is doubled, ``2k``, ``2c``.
    """
    m = PERIODIC
    half = Cavity(m.gap, (0.5 * m.m,), (0.01,), 0.5 * m.k_hertz, 0.5 * m.c1)
    twin = MultiBallModel((half, half), m.M, m.K, m.C)
    a = _multi(twin, PERIODIC_FORCING)
    ref = _single_ball(m, PERIODIC_FORCING)
    assert a.period == ref.period
    assert a.amplitude == pytest.approx(ref.amplitude, rel=AMPLITUDE_RTOL)
    assert a.impacts_per_cycle == 2 * ref.impacts_per_cycle  # each cavity's collisions counted
    p = a.poincare
    np.testing.assert_allclose(p[:, 2], p[:, 3], rtol=0, atol=1e-12)  # the two balls move alike
    # ... on an orbit unstable to their moving apart, which only a start on the symmetric set reaches
    assert not a.stable and np.max(np.abs(a.floquet)) > 2.0


def test_identical_cavities_find_the_two_mirror_orbits_of_their_balls_apart():
    """The spread starts differ between cavities: the balls leave the unstable symmetric orbit.

    Swapping the two identical cavities maps a motion onto another: the stable orbits come as a
    mirror pair, with the same amplitude and the balls' section points exchanged.
    """
    m = PERIODIC
    half = Cavity(m.gap, (0.5 * m.m,), (0.01,), 0.5 * m.k_hertz, 0.5 * m.c1)
    twin = MultiBallModel((half, half), m.M, m.K, m.C)
    fa = ball_attractors_at(twin, PERIODIC_FORCING, check_ball_settings(twin, PERIODIC_FORCING, starts=6,
                                                                        max_cycles=600))
    stable = [a for a in fa.attractors if a.stable]
    assert [a.stable for a in fa.attractors].count(False) <= 1 and len(stable) == 2
    a, b = stable
    assert a.period == b.period == 1 and a.amplitude == pytest.approx(b.amplitude, rel=AMPLITUDE_RTOL)
    np.testing.assert_allclose(a.poincare[:, [2, 3, 4, 5]], b.poincare[:, [3, 2, 5, 4]], rtol=0, atol=1e-6)
    assert abs(a.poincare[0, 2] - a.poincare[0, 3]) > 1e-3  # apart by millimetres


def test_energy_balance_closes_with_forcing():
    model = MultiBallModel.from_damper(DamperModel(), 3)
    # from rest: the forcing alone brings the energy (and sets the velocity tolerance)
    r = simulate_balls(model, 3.0, excitation=Excitation(5.0, 10.0), initial=BallState(0.0, 0.0))
    e = r.energy
    assert len(r.impacts) > 50 and r.work_input > 0
    closure = e.initial + r.work_input - (e.kinetic + e.spring + e.hertz + e.dissipated_main + e.dissipated_contact)
    assert abs(closure) < 1e-8 * r.work_input


def test_energy_balance_closes_over_a_measured_orbit():
    a = _multi(MultiBallModel.from_damper(PERIODIC, 2), PERIODIC_FORCING)
    assert a.success and a.work_input > 0
    assert abs(a.energy_closure) < 1e-6


def test_base_motion_is_mapped_as_in_forced():
    model = MultiBallModel.from_damper(DamperModel(C=0.5, gap=10.0), 1)
    ex = Excitation(3.0, 0.002, "base")
    w = ex.omega
    x = complex(model.K, model.C * w) * 0.002 / complex(model.K - model.M * w * w, model.C * w)
    t = np.linspace(0.0, 2.0, 201)
    r = simulate_balls(model, 2.0, initial=BallState(x.real, -w * x.imag), excitation=ex, t_eval=t)
    assert np.max(np.abs(r.x - (x * np.exp(1j * w * t)).real)) < 1e-9 * abs(x)


def test_free_vibration_is_unchanged_by_an_absent_excitation():
    model = MultiBallModel.from_damper(DamperModel(), 2)
    a = simulate_balls(model, 0.5)
    b = simulate_balls(model, 0.5, excitation=None)
    assert np.array_equal(a.impacts.time, b.impacts.time) and a.work_input == 0.0


def test_starts_follow_the_single_ball_rules():
    model = MultiBallModel.from_damper(PERIODIC, 1)
    from acoustiviz.dynamics.forced import start_states

    for ours, theirs in zip(ball_start_states(model, PERIODIC_FORCING, 6), start_states(PERIODIC, PERIODIC_FORCING, 6),
                            strict=True):
        assert (ours.x, ours.v, ours.y[0], ours.w[0]) == pytest.approx(theirs, abs=1e-15)


def test_columns_start_packed_inside_their_cavities():
    model = MultiBallModel.from_damper(PERIODIC, 3)
    for start in ball_start_states(model, PERIODIC_FORCING, 6):
        start.reduced(model)  # raises when a ball starts outside its cavity or overlapping


@pytest.mark.parametrize("balls", [2, 3, 5])
def test_a_column_pushed_against_a_wall_starts_inside_its_cavity(balls):
    # Table 1 near its resonance: the linear amplitude exceeds half the gap, the column starts on a wall
    table1 = DamperModel()
    model = MultiBallModel.from_damper(DamperModel(m=table1.m / balls), balls)
    for frequency in (4.6, 4.85, 5.1):
        excitation = Excitation(frequency, 5.0)
        assert abs(excitation.linear_response(model)) > table1.gap / 2
        for start in ball_start_states(model, excitation, 3):
            start.reduced(model)  # raises when a ball starts outside its cavity or overlapping


@pytest.mark.parametrize(("kwargs", "name"), [({"solver": "impact-map"}, "solver"), ({"starts": 0}, "starts"),
                                              ({"tolerance": 1.0}, "tolerance")])
def test_bad_settings_are_refused_by_name(kwargs, name):
    model = MultiBallModel.from_damper(PERIODIC, 2)
    with pytest.raises(ParameterError) as err:
        check_ball_settings(model, PERIODIC_FORCING, **kwargs)
    assert err.value.name == name


@pytest.mark.parametrize(("sweep", "seeded"), [("up", [(0,), (1,), (1,)]), ("down", [(1,), (1,), (0,)]),
                                               ("both", [(1,), (2,), (1,)]), ("independent", [(0,), (0,), (0,)])])
def test_the_response_has_the_shape_of_forced(sweep, seeded):
    # damped enough (C = 2 N s/m) for a continued state's transient to die out within the cycles run
    model = MultiBallModel.from_damper(DamperModel(C=2.0, gap=10.0), 2)
    resp = ball_attractor_response(model, [2.5, 2.0, 3.0], 4.0, sweep=sweep, starts=1, max_cycles=20)
    assert resp.frequencies.tolist() == [2.0, 2.5, 3.0] and resp.sweep == sweep
    for i, fa in enumerate(resp.per_frequency):
        (a,) = fa.attractors  # one linear steady state, met again by the seeds
        assert a.amplitude == pytest.approx(abs(_linear(model, resp.frequencies[i], 4.0)), rel=1e-9)
    # the attractors of each frequency continued to its neighbour(s) in the sweep's direction(s)
    assert [fa.seeded for fa in resp.per_frequency] == seeded


def test_a_run_restarts_from_the_latest_section_point_outside_every_contact():
    from types import SimpleNamespace

    from acoustiviz.dynamics.balls_forced import restart_state

    model = MultiBallModel.from_damper(DamperModel(), 1)
    half = model.cavities[0].gap / 2
    free, pressed = [0.001, 0.2, 0.5 * half, -0.1], [0.002, 0.1, 1.01 * half, 0.3]  # the ball into wall+
    back, start, overlap = restart_state(SimpleNamespace(model=model, poincare=np.array([free, pressed])))
    assert back == 1 and overlap == 0 and (start.x, start.v, start.w[0]) == pytest.approx((0.001, 0.2, 0.1))
    assert restart_state(SimpleNamespace(model=model, poincare=np.array([pressed, free])))[0] == 0
    # every point pressed: the last one with its ball moved back to touch the wall, velocities kept
    back, start, overlap = restart_state(SimpleNamespace(model=model, poincare=np.array([pressed])))
    assert back == 0 and overlap == pytest.approx(0.01 * half)
    assert start.y[0] - model.offsets()[0] - start.x == pytest.approx(half, rel=1e-8)
    assert (start.x, start.v, start.w[0]) == pytest.approx((0.002, 0.1, 0.4))
    start.reduced(model)


def test_a_pressed_column_is_moved_apart_to_touch():
    from types import SimpleNamespace

    from acoustiviz.dynamics.balls_forced import restart_state

    model = MultiBallModel.from_damper(DamperModel(m=0.0081), 5)
    half = model.cavities[0].gap / 2
    # the five balls pressed into each other and into wall- by 1 micrometre each
    s = -half - 1e-6 - 1e-6 * np.arange(5)
    point = np.concatenate([[0.0, 0.0], s, np.zeros(5)])
    _, start, overlap = restart_state(SimpleNamespace(model=model, poincare=point[None, :]))
    assert 0 < overlap < 1e-5
    start.reduced(model)
