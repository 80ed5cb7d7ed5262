"""Several balls in operation: the forced multi-ball kernel and the attractors of its damper."""

import math

import numpy as np
import pytest
from _balls_reference import scipy_collisions

from acoustiviz._validate import ParameterError
from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics.balls import BallState, Cavity, MultiBallModel, equal_balls
from acoustiviz.dynamics.balls_forced import (
    _ball_state,
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
#: Agreement wanted of collision times with the SciPy reference, in s.
TIME_TOL = 1e-8
#: The energy account with forcing: closure relative to the work of F.
CLOSURE_RTOL = 1e-9


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
    settings = check_ball_settings(twin, PERIODIC_FORCING, starts=6, max_cycles=600)
    fa = ball_attractors_at(twin, PERIODIC_FORCING, settings)
    stable = [a for a in fa.attractors if a.stable]
    assert [a.stable for a in fa.attractors].count(False) <= 1 and stable
    # two mirror pairs of stable orbits coexist, and which of the four the six starts reach changes with
    # the rounding of the integration: the mirror image of each one found, run from its section point
    # with the balls exchanged, must be a stable orbit of its own, found again in every digit it keeps
    mirrors = [_ball_state(a.poincare[0, [0, 1, 3, 2, 5, 4]], twin) for a in stable]
    stable = [a for a in ball_attractors_at(twin, PERIODIC_FORCING, settings, seeds=mirrors,
                                            previous=fa).attractors if a.stable]
    for a in stable:
        assert a.period == 1
        assert abs(a.poincare[0, 2] - a.poincare[0, 3]) > 1e-3  # apart by millimetres
        pair = [b for b in stable if np.allclose(a.poincare[:, [2, 3, 4, 5]], b.poincare[:, [3, 2, 5, 4]], rtol=0,
                                                 atol=1e-6)]
        assert len(pair) == 1 and pair[0] is not a
        assert a.amplitude == pytest.approx(pair[0].amplitude, rel=AMPLITUDE_RTOL)


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


def _single_ball_driver(model, ex, start, duration, rtol):
    """The single-ball forced driver (event solver, compliant contacts) from ``start`` over ``duration`` s in one call.

    Returns the impact rows (``IMPACT_COLUMNS``), the final ``(x, v, y, w)`` and the work of F and the
    energy dissipated by C in J.
    """
    from acoustiviz.dynamics import _forced_driver as fd
    from acoustiviz.dynamics._records import params_record
    from acoustiviz.dynamics.forced import _params, _together

    st = np.zeros(8)
    st[:4] = start
    imp = np.zeros((20000, 8))
    acc = np.zeros(5)
    n, status = fd.advance(params_record(_params(model)), ex.vector(model), _together(model, ex, "event"), st, 0.0,
                           duration, None, rtol, imp, 0, imp.shape[0], acc, False)
    assert status == 0
    return imp[:n], st[:4], acc[0], acc[1]


@pytest.mark.parametrize(("model", "ex", "cycles"), [(PERIODIC, PERIODIC_FORCING, 20),
                                                     (DamperModel(C=2.0), Excitation(5.0, 5.0), 100),
                                                     (DamperModel(C=2.0, clip_tensile=True), Excitation(5.0, 5.0),
                                                      50)])
def test_one_ball_in_operation_bit_for_bit(model, ex, cycles):
    """One ball in one cavity under forcing: the multi-ball path runs the single-ball forced driver's arithmetic.

    Each contact alone is the single-ball forced contact (the same compiled kernel, with the forcing and the
    contact's start time) and each flight the same closed form, so over ``cycles`` forcing cycles (hundreds of
    impacts for the second case) the impact tables, the final state, the work of F and the energy dissipated by
    C are identical, not merely close. (Both are advanced over the whole run in one call: the multi-ball cycle
    runner ends its cycles at ``k T`` s, the single-ball one at ``(k - 1) T + T`` s, one rounding apart.)
    """
    from acoustiviz.dynamics.forced import linear_start

    x, v, y, w = start = linear_start(model, ex)
    duration = cycles * ex.period
    rows, final, work, diss = _single_ball_driver(model, ex, start, duration, 1e-10)
    got = simulate_balls(MultiBallModel.from_damper(model, 1), duration, initial=BallState(x=x, v=v, y=(y,), w=(w,)),
                         excitation=ex, rtol=1e-10, t_eval=[duration])
    assert got.success
    b = got.impacts
    assert len(rows) >= 4 * cycles and len(b) == len(rows)
    for name, col in (("time", 0), ("approach_velocity", 2), ("separation_velocity", 3), ("peak_force", 5),
                      ("impulse", 6), ("energy_lost", 7)):
        assert np.array_equal(getattr(b, name), rows[:, col]), name
    assert np.array_equal(b.end, rows[:, 0] + rows[:, 4])
    walls = np.where(rows[:, 1] > 0, "wall+", "wall-")
    assert list(np.where(b.first == "ball1", b.second, b.first)) == list(walls)
    assert (got.x[-1], got.v[-1], got.y[-1, 0], got.w[-1, 0]) == tuple(final)
    assert got.work_input == work and got.energy.dissipated_main == diss


@pytest.mark.parametrize("n_balls", [1, 2, 3])
def test_energy_balance_closes_with_forcing_from_the_linear_start(n_balls):
    """Work of F = energy dissipated (dashpot and contacts) + change of mechanical energy, over hundreds of
    collisions of balls on walls and on one another."""
    model = MultiBallModel.from_damper(DamperModel(C=2.0), n_balls)
    ex = Excitation(5.0, 5.0)
    r = simulate_balls(model, 3.0, initial=ball_start_states(model, ex, 1)[0], excitation=ex)
    e = r.energy
    assert r.success and len(r.impacts) > 50 * n_balls and r.work_input > 0
    closure = e.initial + r.work_input - (e.kinetic + e.spring + e.hertz + e.dissipated_main + e.dissipated_contact)
    assert abs(closure) < CLOSURE_RTOL * r.work_input


@pytest.mark.parametrize("n_balls", [2, 3])
def test_first_forced_collisions_agree_with_an_independent_scipy_reference(n_balls):
    """A column in operation: lone contacts of balls with walls and with one another, the main mass forced."""
    model = MultiBallModel.from_damper(DamperModel(C=2.0), n_balls)
    ex = Excitation(5.0, 5.0)
    start = ball_start_states(model, ex, 1)[0]
    ref = scipy_collisions(model, 20, initial=start, excitation=ex)
    got = simulate_balls(model, ref[-1][0] + 1e-3, initial=start, excitation=ex)
    assert len(ref) == 20
    pr = model.pairs()
    first_pair = {("wall-" if a == 0 else f"ball{a}", "wall+" if b == 0 else f"ball{b}"): p
                  for p, (a, b) in enumerate(zip(pr["pa"], pr["pb"], strict=True))}
    pairs = [first_pair[(f, s)] for f, s in zip(got.impacts.first[:20], got.impacts.second[:20], strict=True)]
    assert pairs == [p for _, p in ref]
    assert len(set(pairs)) == n_balls + 1  # every wall and every neighbour pair collides
    assert np.max(np.abs(got.impacts.time[:20] - np.array([t for t, _ in ref]))) < TIME_TOL


def test_forced_main_mass_flies_in_closed_form_beside_a_lone_contact_of_two_balls():
    """Two balls collide alone while the forced main mass flies: inside and after the contact it follows
    ``M x'' + C x' + K x = F(t)`` (an independent SciPy integration), and the balls keep their momentum."""
    from scipy.integrate import solve_ivp

    cav = equal_balls(2, 0.02, 0.1, 1e9, 0.0, k_ball=5e8, c_ball=0.0)
    model = MultiBallModel((cav,), C=0.5)
    ex = Excitation(3.0, 4.0)
    q, _ = BallState(v=0.0).reduced(model)
    start = BallState(v=0.0, y=tuple(q[1:] + cav.offsets), w=(1.0, 0.0))
    r = simulate_balls(model, 0.05, initial=start, excitation=ex)
    assert len(r.impacts) == 1 and (r.impacts.first[0], r.impacts.second[0]) == ("ball1", "ball2")
    t0, dur = r.impacts.time[0], r.impacts.duration[0]
    times = np.append(t0 + dur * np.array([0.25, 0.5, 0.75]), 0.05)
    r = simulate_balls(model, 0.05, initial=start, excitation=ex, t_eval=times)
    w = ex.omega

    def main(t, s):
        return [s[1], (ex.amplitude * math.cos(w * t) - model.K * s[0] - model.C * s[1]) / model.M]

    ref = solve_ivp(main, (0.0, 0.05), [0.0, 0.0], t_eval=times, rtol=1e-12, atol=1e-15)
    scale = np.max(np.abs(ref.y[0]))
    assert scale > 0.0
    assert np.max(np.abs(r.x - ref.y[0])) < 1e-9 * scale
    assert np.max(np.abs(r.v - ref.y[1])) < 1e-9 * w * scale
    assert 0.02 * r.w.sum(axis=1) == pytest.approx(np.full(4, 0.02 * 1.0), rel=1e-12)  # momentum of the balls
    s = r.y - model.offsets()
    assert np.all(s[:3, 0] - s[:3, 1] > 0.0)  # the three inner times lie inside the contact
    e = r.energy
    closure = e.initial + r.work_input - (e.kinetic + e.spring + e.hertz + e.dissipated_main + e.dissipated_contact)
    assert abs(closure) < CLOSURE_RTOL * (e.initial + abs(r.work_input))


def test_forced_overlapping_contacts_leave_the_lone_path_and_agree_with_scipy():
    """A ball strikes a column whose next gap (0.1 um) closes while the first contact lasts, the main mass forced.

    The contact begins alone, but the struck ball reaches its neighbour before it parts: it is taken again
    from its onset with every body integrated together, and the touches agree with the SciPy reference.
    """
    cav = equal_balls(3, 0.02, 0.1, 1e9, 0.0, k_ball=5e8, c_ball=0.0)
    model = MultiBallModel((cav,), C=0.5)
    ex = Excitation(3.0, 4.0)
    q = np.array([-0.005, 0.0, 1e-7])  # reduced coordinates: neighbours touch when theirs coincide
    start = BallState(v=0.0, y=tuple(q + cav.offsets), w=(1.0, 0.0, 0.0))
    ref = scipy_collisions(model, 2, t_max=0.02, initial=start, excitation=ex)
    r = simulate_balls(model, 0.02, initial=start, t_eval=[0.02], excitation=ex)
    imp = r.impacts
    assert len(ref) == 2 and len(imp) == 2
    assert [(imp.first[k], imp.second[k]) for k in range(2)] == [("ball1", "ball2"), ("ball2", "ball3")]
    assert [p for _, p in ref] == [1, 2]
    assert np.max(np.abs(imp.time - np.array([t for t, _ in ref]))) < TIME_TOL
    assert imp.time[1] < imp.end[0]  # overlapping contacts
    assert 0.02 * r.w[-1].sum() == pytest.approx(0.02 * 1.0, rel=1e-12)  # momentum of the balls


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
