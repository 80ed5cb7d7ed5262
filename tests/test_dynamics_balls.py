"""Multi-ball impact dampers: the model, the compiled solver and an independent SciPy reference."""

from __future__ import annotations

import math

import numpy as np
import pytest
from _balls_reference import scipy_collisions

from acoustiviz.core.contact import hertz_stiffness, sphere_pair_stiffness
from acoustiviz.core.materials import material, sphere_radius
from acoustiviz.dynamics import DamperModel, InitialState, simulate
from acoustiviz.dynamics.balls import BallState, Cavity, MultiBallModel, cavity_body_names, equal_balls
from acoustiviz.dynamics.balls_solve import simulate_balls
from acoustiviz.errors import ParameterError

#: Agreement wanted of collision times with the SciPy reference and with the single-ball solver, in s.
TIME_TOL = 1e-8
#: Restitution of an undamped contact: 1 within this.
UNDAMPED_E_TOL = 1e-6


def test_sphere_pair_stiffness_is_paper_eq2_with_the_relative_radius():
    steel = material("steel")
    a, b = 0.01, 0.03
    assert sphere_pair_stiffness(a, b, steel, steel) == pytest.approx(hertz_stiffness(a * b / (a + b), steel, steel),
                                                                      rel=1e-15)
    # a huge partner approaches the sphere on a plane
    assert sphere_pair_stiffness(a, 1e9, steel, steel) == pytest.approx(hertz_stiffness(a, steel, steel), rel=1e-9)


def test_cavity_geometry_and_names():
    cav = equal_balls(3, 0.0405, 0.04, 5.6e8, 20.0)
    r = sphere_radius(0.0405, material("steel").density)
    assert cav.radii == pytest.approx((r, r, r))
    assert cav.length == pytest.approx(0.04 + 6 * r)
    assert cav.offsets == pytest.approx([-2 * r, 0.0, 2 * r])
    assert cav.c_ball == 20.0 and len(cav.k_ball) == 2
    model = MultiBallModel((cav, equal_balls(1, 0.01, 0.02, 1e8, 5.0)))
    names = cavity_body_names(model)
    assert names[0] == ("c1:wall-", "c1:ball1") and names[3] == ("c1:ball3", "c1:wall+")
    assert names[4] == ("c2:wall-", "c2:ball1") and len(names) == 6
    # equal spaces: N + 1 of them over the free travel
    q, u = BallState().reduced(MultiBallModel((cav,)))
    assert np.diff(np.concatenate([[-0.02], q[1:], [0.02]])) == pytest.approx([0.01] * 4)
    assert np.all(u[1:] == 0) and u[0] == 2.0


def test_bad_cavities_are_refused_naming_the_field():
    with pytest.raises(ParameterError, match="radii"):
        Cavity(0.04, (0.01, 0.01), (0.01,), 1e8, 1.0, (1e8,))
    with pytest.raises(ParameterError, match="k_ball"):
        Cavity(0.04, (0.01, 0.01), (0.01, 0.01), 1e8, 1.0)
    with pytest.raises(ParameterError, match="balls"):
        equal_balls(0, 0.01, 0.04, 1e8, 1.0)
    with pytest.raises(ParameterError, match="initial.y"):
        BallState(y=(0.0, 0.0)).reduced(MultiBallModel((equal_balls(2, 0.01, 0.04, 1e8, 1.0),)))


def test_one_ball_reproduces_the_single_ball_event_solver():
    """Same law, same contact kernel (the single-ball solver's sqrt(δ) time): see also the bit-for-bit test."""
    model = DamperModel()
    ref = simulate(model, 1.0)
    got = simulate_balls(MultiBallModel.from_damper(model, 1), 1.0)
    n = 20
    assert len(ref.impacts) >= n and len(got.impacts) >= n
    assert np.max(np.abs(got.impacts.time[:n] - ref.impacts.time[:n])) < TIME_TOL
    assert np.max(np.abs(got.impacts.duration[:n] - ref.impacts.duration[:n])) < TIME_TOL
    assert got.impacts.restitution[:n] == pytest.approx(ref.impacts.restitution[:n], rel=1e-7)
    assert got.impacts.approach_velocity[:n] == pytest.approx(ref.impacts.approach_velocity[:n], rel=1e-7)
    assert got.impacts.peak_force[:n] == pytest.approx(ref.impacts.peak_force[:n], rel=1e-6)
    assert got.impacts.energy_lost[:n] == pytest.approx(ref.impacts.energy_lost[:n], rel=1e-6)
    walls = np.where(ref.impacts.wall[:n] > 0, "wall+", "wall-")
    touched = np.where(got.impacts.first[:n] == "ball1", got.impacts.second[:n], got.impacts.first[:n])
    assert list(touched) == list(walls)


@pytest.mark.parametrize("clip, start", [(False, (0.0, 2.0, None, 0.0)), (True, (0.0, 2.0, None, 0.0)),
                                         (False, (0.003, -1.5, 0.012, 0.8))])
def test_one_ball_bit_for_bit(clip, start):
    """One ball in one cavity: the multi-ball driver runs the single-ball solver's arithmetic.

    Free decay of the Table 1 damper over 20 s (the whole settling, a couple of hundred impacts), from
    the paper's start and from an off-centre moving ball: the impact tables and the motion at the
    output times are identical, not merely close.
    """
    model = DamperModel(clip_tensile=clip)
    x, v, y, w = start
    single = InitialState(x=x, v=v, y=y, w=w)
    several = BallState(x=x, v=v, y=None if y is None else (y,), w=(w,))
    first = simulate(model, 1.0, initial=single).impacts  # output times inside the first contacts too
    t_eval = np.union1d(np.linspace(0.0, 20.0, 4001), first.time + 0.5 * first.duration)
    ref = simulate(model, 20.0, initial=single, t_eval=t_eval)
    got = simulate_balls(MultiBallModel.from_damper(model, 1), 20.0, initial=several, t_eval=t_eval)
    assert ref.success and got.success
    a, b = ref.impacts, got.impacts
    assert len(a) > 100 and len(b) == len(a)
    for name in ("time", "approach_velocity", "separation_velocity", "restitution", "peak_force", "impulse",
                 "energy_lost"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.array_equal(b.end, a.time + a.duration)
    walls = np.where(a.wall > 0, "wall+", "wall-")
    touched = np.where(b.first == "ball1", b.second, b.first)
    assert list(touched) == list(walls)
    assert np.array_equal(got.x, ref.x) and np.array_equal(got.v, ref.v)
    assert np.array_equal(got.y[:, 0], ref.y) and np.array_equal(got.w[:, 0], ref.w)
    # the main mass's largest excursions (maxima of the sampled motion) therefore agree too
    assert np.max(got.x) == np.max(ref.x) and np.min(got.x) == np.min(ref.x)


def test_overlapping_contacts_leave_the_lone_path_and_agree_with_scipy():
    """A ball strikes a column whose next gap (0.1 um) closes while the first contact lasts.

    The contact begins alone, but the struck ball reaches its neighbour before it parts: the solver
    must take it again from its onset with every body integrated together. The two contacts then
    overlap in the table (a lone contact could not), and the touches agree with the SciPy reference.
    """
    cav = equal_balls(3, 0.02, 0.1, 1e9, 0.0, k_ball=5e8, c_ball=0.0)
    model = MultiBallModel((cav,), C=0.0)
    q = np.array([-0.005, 0.0, 1e-7])  # reduced coordinates: neighbours touch when theirs coincide
    start = BallState(v=0.0, y=tuple(q + cav.offsets), w=(1.0, 0.0, 0.0))
    ref = scipy_collisions(model, 2, t_max=0.02, initial=start)
    r = simulate_balls(model, 0.02, initial=start, t_eval=[0.02])
    imp = r.impacts
    assert len(ref) == 2 and len(imp) == 2
    assert [(imp.first[k], imp.second[k]) for k in range(2)] == [("ball1", "ball2"), ("ball2", "ball3")]
    assert [p for _, p in ref] == [1, 2]
    assert np.max(np.abs(imp.time - np.array([t for t, _ in ref]))) < TIME_TOL
    assert imp.time[1] < imp.end[0]  # overlapping contacts
    assert 0.02 * r.w[-1].sum() == pytest.approx(0.02 * 1.0, rel=1e-12)  # momentum
    assert abs(r.energy.relative_closure_error) < 1e-8


def _two_free_balls(c_ball: float):
    """Two equal balls, the first moving at 1 m/s, the second at rest; the main mass at rest (no wall reached)."""
    cav = equal_balls(2, 0.02, 0.1, 1e9, 0.0, k_ball=5e8, c_ball=c_ball)
    model = MultiBallModel((cav,), C=0.0)
    q, _ = BallState(v=0.0).reduced(model)
    start = BallState(v=0.0, y=tuple(q[1:] + cav.offsets), w=(1.0, 0.0))
    return model, start


def test_undamped_ball_contact_conserves_momentum_and_energy_and_swaps_velocities():
    model, start = _two_free_balls(0.0)
    r = simulate_balls(model, 0.05, initial=start, t_eval=[0.0, 0.05])
    assert len(r.impacts) == 1
    imp = r.impacts
    assert (imp.first[0], imp.second[0]) == ("ball1", "ball2")
    assert abs(imp.restitution[0] - 1.0) < UNDAMPED_E_TOL
    w_end = r.w[-1]
    assert w_end[0] == pytest.approx(0.0, abs=1e-6) and w_end[1] == pytest.approx(1.0, rel=1e-6)
    m = 0.02
    assert m * w_end.sum() == pytest.approx(m * 1.0, rel=1e-12)  # momentum
    assert 0.5 * m * np.sum(w_end**2) == pytest.approx(0.5 * m, rel=1e-6)  # energy
    assert imp.impulse[0] == pytest.approx(m * 1.0, rel=1e-6)
    assert r.x[-1] == 0.0 and r.energy.relative_closure_error == pytest.approx(0.0, abs=1e-10)


def test_motion_inside_a_contact_of_two_balls_conserves_momentum_and_energy():
    """Output times inside a lone contact of two balls: the pair's motion comes from the contact's own integration."""
    model, start = _two_free_balls(0.0)
    r = simulate_balls(model, 0.05, initial=start)
    t0, dur = r.impacts.time[0], r.impacts.duration[0]
    times = t0 + dur * np.array([0.25, 0.5, 0.75])
    r = simulate_balls(model, 0.05, initial=start, t_eval=times)
    m, k = 0.02, 5e8
    off = model.offsets()
    y0 = np.array(start.y)
    s = r.y - off  # reduced coordinates: the pair overlaps by s1 - s2
    pen = s[:, 0] - s[:, 1]
    assert np.all(pen > 0.0)
    assert np.all(r.x == 0.0) and np.all(r.v == 0.0)  # the main mass, at rest, flies in closed form
    assert m * r.w.sum(axis=1) == pytest.approx(np.full(3, m * 1.0), rel=1e-12)  # momentum
    # the centre of mass moves uniformly at 0.5 m/s
    assert 0.5 * r.y.sum(axis=1) == pytest.approx(0.5 * y0.sum() + 0.5 * times, abs=1e-12)
    energy = 0.5 * m * np.sum(r.w**2, axis=1) + 0.4 * k * pen**2.5
    assert energy == pytest.approx(np.full(3, 0.5 * m), rel=1e-9)
    assert pen[1] > pen[0] and pen[1] > pen[2]  # deepest half-way through the symmetric contact


def test_damped_ball_contact_loses_the_work_of_its_dissipative_force():
    model, start = _two_free_balls(5.0)
    r = simulate_balls(model, 0.05, initial=start)
    assert len(r.impacts) == 1
    u_a, u_s = r.impacts.approach_velocity[0], r.impacts.separation_velocity[0]
    mu = 0.5 * 0.02  # reduced mass of two equal balls
    lost_kinetic = 0.5 * mu * (u_a**2 - u_s**2)
    assert 0.0 < r.impacts.restitution[0] < 1.0
    assert r.impacts.energy_lost[0] == pytest.approx(lost_kinetic, rel=1e-7)


@pytest.mark.parametrize("n_balls", [2, 3, 5])
def test_first_collisions_agree_with_an_independent_scipy_reference(n_balls):
    model = MultiBallModel.from_damper(DamperModel(), n_balls)
    ref = scipy_collisions(model, 20)
    got = simulate_balls(model, ref[-1][0] + 1e-3)
    assert len(ref) == 20
    pr = model.pairs()
    first_pair = {("wall-" if a == 0 else f"ball{a}", "wall+" if b == 0 else f"ball{b}"): p
                  for p, (a, b) in enumerate(zip(pr["pa"], pr["pb"], strict=True))}
    pairs = [first_pair[(f, s)] for f, s in zip(got.impacts.first[:20], got.impacts.second[:20], strict=True)]
    assert pairs == [p for _, p in ref]
    assert np.max(np.abs(got.impacts.time[:20] - np.array([t for t, _ in ref]))) < TIME_TOL


def test_energy_account_closes_for_a_column():
    model = MultiBallModel.from_damper(DamperModel(), 4)
    r = simulate_balls(model, 2.0)
    assert r.success
    assert abs(r.energy.relative_closure_error) < 1e-8
    assert set(r.impacts.first) >= {"wall-", "ball1"}
    assert math.isfinite(r.impacts.restitution[0])
