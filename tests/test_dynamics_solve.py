"""Impact-damper solvers checked against independent references.

References: the closed-form damped oscillator (written out here), conservation of energy and
momentum, the Hertz impact laws (impulse 2 m_eff U0 without damping), the separate contact
integration of acoustiviz.core.contact, and scipy's solve_ivp with events as a second method.
"""

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from acoustiviz._validate import ParameterError
from acoustiviz.core import contact
from acoustiviz.dynamics import (
    TABLE1,
    AccuracyWarning,
    DamperModel,
    InitialState,
    central_difference_excursion,
    default_step,
    explicit_step_limit,
    shortest_contact,
    simulate,
)
from acoustiviz.output.tables import IMPACT_COLUMNS, write_impact_table

RTOL_CLOSURE = 1e-11  # energy closure of the event solver, relative to the initial energy


def oscillator(t, x0, v0, M, K, C):
    """Closed-form underdamped oscillator (textbook), independent of the package."""
    a = C / (2 * M)
    wd = math.sqrt(K / M - a * a)
    e = np.exp(-a * t)
    x = e * (x0 * np.cos(wd * t) + (v0 + a * x0) / wd * np.sin(wd * t))
    v = e * (
        (v0 + a * x0) * np.cos(wd * t) - (x0 * wd + a * (v0 + a * x0) / wd) * np.sin(wd * t)
    )
    return x, v


# --------------------------------------------------------------------------- free motion
@pytest.mark.parametrize("solver", ["event", "newmark", "impact-map"])
def test_no_contact_follows_closed_form_oscillator(solver):
    model = DamperModel(gap=1.0)  # the impact mass never reaches a wall
    t = np.linspace(0.0, 1.0, 201)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        r = simulate(model, 1.0, solver=solver, t_eval=t, dt=1e-5)
    x, v = oscillator(t, 0.0, 2.0, model.M, model.K, model.C)
    # Newmark's phase error is (w h)^2/12 per radian: 31.6 rad x (3.2e-4)^2/12 ~ 3e-7
    tol = 1e-6 if solver == "newmark" else 1e-12
    assert len(r.impacts) == 0
    np.testing.assert_allclose(r.x, x, atol=tol * 0.07)
    np.testing.assert_allclose(r.v, v, atol=tol * 2)
    np.testing.assert_allclose(r.y, 0.0, atol=1e-15)


# --------------------------------------------------------------------------- one contact
def _single_impact_model(c1=0.0, clip=False):
    # a nearly free main mass (K, C tiny): the contact is a two-body Hertz impact
    return DamperModel(M=0.5, K=1e-6, C=0.0, m=0.0405, gap=0.04, k_hertz=5.6e8, c1=c1,
                       clip_tensile=clip)


def test_undamped_contact_obeys_hertz_laws():
    model = _single_impact_model()
    u0 = 1.5
    # the impact mass crosses d/2 = 0.02 m at 1.5 m/s: contact at 13.3 ms, over within 0.3 ms
    r = simulate(model, 0.014, initial=InitialState(v=0.0, w=u0))
    imp = r.impacts
    assert len(imp) == 1 and imp.wall[0] == 1  # impact mass moving in +x hits wall +1
    meff = model.effective_mass
    np.testing.assert_allclose(imp.approach_velocity[0], u0, rtol=1e-12)
    np.testing.assert_allclose(imp.restitution[0], 1.0, rtol=1e-9)
    np.testing.assert_allclose(imp.impulse[0], 2 * meff * u0, rtol=1e-9)
    np.testing.assert_allclose(imp.duration[0], contact.contact_duration(u0, model.k_hertz, meff),
                               rtol=1e-9)
    np.testing.assert_allclose(imp.peak_force[0], contact.peak_force(u0, model.k_hertz, meff),
                               rtol=1e-9)
    np.testing.assert_allclose(imp.energy_lost[0], 0.0, atol=1e-15)
    # momentum M v + m w is conserved across the impact (the spring's impulse is ~1e-15 N s)
    xf, vf, yf, wf = r.final_state
    np.testing.assert_allclose(model.M * vf + model.m * wf, model.m * u0, rtol=1e-10)


@pytest.mark.parametrize("clip", [False, True])
def test_damped_contact_restitution_matches_contact_module(clip):
    model = _single_impact_model(c1=20.0, clip=clip)
    u0 = 0.7
    r = simulate(model, 0.05, initial=InitialState(v=0.0, w=u0))
    e_ref = contact.restitution(u0, model.k_hertz, model.m, model.M, model.c1, clip)
    np.testing.assert_allclose(r.impacts.restitution[0], e_ref, rtol=1e-8)
    # energy lost = relative kinetic energy lost
    lost = 0.5 * model.effective_mass * u0**2 * (1 - e_ref**2)
    np.testing.assert_allclose(r.impacts.energy_lost[0], lost, rtol=1e-7)


# --------------------------------------------------------------------------- energy balance
def test_energy_conserved_without_damping():
    model = DamperModel(C=0.0, c1=0.0)
    t = np.linspace(0, 2.0, 4001)
    r = simulate(model, 2.0, t_eval=t)
    assert len(r.impacts) > 20
    assert abs(r.energy.relative_closure_error) < RTOL_CLOSURE
    assert abs(r.energy.dissipated_main) < 1e-13 and abs(r.energy.dissipated_contact) < 1e-14
    assert np.max(np.abs(r.energy_residual())) < RTOL_CLOSURE * r.energy.initial


def test_energy_balance_closes_with_damping():
    t = np.linspace(0, 3.0, 3001)
    r = simulate(TABLE1, 3.0, t_eval=t)
    assert r.energy.dissipated_main > 0 and r.energy.dissipated_contact > 0
    assert abs(r.energy.relative_closure_error) < RTOL_CLOSURE
    assert np.max(np.abs(r.energy_residual())) < RTOL_CLOSURE * r.energy.initial
    # the impact table's energy losses add up to the contact dissipation
    np.testing.assert_allclose(r.impacts.energy_lost.sum(), r.energy.dissipated_contact, rtol=1e-12)


# --------------------------------------------------------------------------- a second method
def _solve_ivp_impacts(model, initial, n_impacts, rtol=1e-12):
    """Independent reference: scipy DOP853 with terminal events at contact onset and end."""
    M, K, C, m, hg, kh, c1 = model.M, model.K, model.C, model.m, model.gap / 2, model.k_hertz, model.c1

    def force(s, x, y, v, w):
        d = s * (y - x) - hg
        if s == 0 or d <= 0:
            return 0.0
        return kh * d**1.5 + c1 * s * (w - v)

    def rhs_factory(s):
        def rhs(_t, q):
            x, v, y, w = q
            f = force(s, x, y, v, w)
            return [v, (s * f - K * x - C * v) / M, w, -s * f / m]
        return rhs

    def hit(sign):
        def g(_t, q):
            return sign * (q[2] - q[0]) - hg
        g.terminal = True
        g.direction = 1
        return g

    def leave(s):
        def g(_t, q):
            return s * (q[2] - q[0]) - hg
        g.terminal = True
        g.direction = -1
        return g

    q = list(initial.as_tuple(model))
    t0 = 0.0
    out = []
    while len(out) < n_impacts:
        sol = solve_ivp(rhs_factory(0), (t0, t0 + 5), q, method="DOP853", rtol=rtol,
                        atol=1e-15, events=[hit(1), hit(-1)])
        k = 0 if sol.t_events[0].size else 1
        t0 = float(sol.t_events[k][0])
        q = sol.y_events[k][0]
        s = 1 if k == 0 else -1
        u0 = s * (q[3] - q[1])
        sol = solve_ivp(rhs_factory(s), (t0, t0 + 1), q, method="DOP853", rtol=rtol,
                        atol=1e-15, events=[leave(s)], first_step=1e-8)
        t1 = float(sol.t_events[0][0])
        q = sol.y_events[0][0]
        out.append((t0, s, u0, -s * (q[3] - q[1]), t1 - t0))
        t0 = t1
    return np.array(out)


def test_event_solver_agrees_with_solve_ivp():
    ref = _solve_ivp_impacts(TABLE1, InitialState(), 6)
    r = simulate(TABLE1, 0.3)
    imp = r.impacts.head(6)
    np.testing.assert_allclose(imp.time, ref[:, 0], rtol=0, atol=1e-11)
    np.testing.assert_array_equal(imp.wall, ref[:, 1])
    np.testing.assert_allclose(imp.approach_velocity, ref[:, 2], rtol=1e-9)
    np.testing.assert_allclose(imp.separation_velocity, ref[:, 3], rtol=1e-9)
    np.testing.assert_allclose(imp.duration, ref[:, 4], rtol=1e-7)


def test_newmark_converges_at_second_order_for_a_smooth_contact_force():
    model = DamperModel(c1=0.0)  # Hertz force alone: continuous, with a continuous derivative
    ev = simulate(model, 0.12).impacts.head(4)
    errs = []
    for dt in (2e-6, 1e-6):
        nm = simulate(model, 0.12, solver="newmark", dt=dt).impacts.head(4)
        errs.append(np.max(np.abs(nm.separation_velocity / ev.separation_velocity - 1)))
    assert errs[1] < 1e-5
    assert errs[0] / errs[1] > 3.0  # at least second order: halving the step quarters the error


def test_newmark_converges_only_at_first_order_with_the_papers_damping():
    # c1 dδ/dt jumps from 0 to c1 U0 (38 N at 1.9 m/s) at first touch and back at the end:
    # a fixed-step implicit scheme makes an error of order (step x jump) at each contact
    ev = simulate(TABLE1, 0.12).impacts.head(4)
    errs = []
    for dt in (1e-6, 2.5e-7):
        nm = simulate(TABLE1, 0.12, solver="newmark", dt=dt).impacts.head(4)
        errs.append(np.mean(np.abs(nm.separation_velocity / ev.separation_velocity - 1)))
    assert errs[1] < 5e-4
    assert errs[1] < 0.5 * errs[0]


# --------------------------------------------------------------------------- where methods fail
def test_newmark_loses_accuracy_and_gains_energy_as_the_step_grows():
    tau = shortest_contact(TABLE1)
    ev = simulate(TABLE1, 0.3).impacts.head(5)
    err, gain = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        for frac in (1 / 100, 1 / 2):
            r = simulate(TABLE1, 0.3, solver="newmark", dt=frac * tau)
            imp = r.impacts.head(5)
            err.append(np.max(np.abs(imp.restitution / ev.restitution - 1)))
            gain.append(-r.energy.relative_closure_error)  # > 0: energy created
    assert err[0] < 1e-2 < err[1]
    assert 0 < gain[0] < 1e-5 and gain[1] > 1e-3


def test_newmark_refuses_or_warns_on_coarse_steps():
    tau = shortest_contact(TABLE1)
    with pytest.raises(ParameterError, match="dt"):
        simulate(TABLE1, 0.1, solver="newmark", dt=1.5 * tau)
    with pytest.warns(AccuracyWarning):
        simulate(TABLE1, 0.01, solver="newmark", dt=tau / 10)
    assert default_step(TABLE1) == pytest.approx(tau / 50)


def test_explicit_scheme_is_unstable_beyond_its_limit():
    h = explicit_step_limit(TABLE1)
    assert h < shortest_contact(TABLE1)
    stable = central_difference_excursion(TABLE1, 0.2, 0.5 * h)
    assert stable < 0.5 * TABLE1.gap + 1e-3
    assert central_difference_excursion(TABLE1, 0.2, 1.5 * h) == math.inf


def test_impact_map_close_for_stiff_contacts_and_departs_for_soft_ones():
    def first_separation_error(model):
        ev = simulate(model, 0.1, initial=InitialState(v=0.3)).impacts
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            im = simulate(model, 0.1, solver="impact-map", initial=InitialState(v=0.3)).impacts
        warned = any(issubclass(w.category, AccuracyWarning) for w in caught)
        return abs(im.separation_velocity[0] / ev.separation_velocity[0] - 1), warned

    stiff, warned_stiff = first_separation_error(DamperModel(gap=0.01))
    # a soft contact lasting half a radian of the main oscillation
    soft, warned_soft = first_separation_error(DamperModel(k_hertz=2e4, gap=0.01, c1=0.5))
    assert stiff < 1e-3 and not warned_stiff
    assert soft > 10 * stiff and soft > 1e-2 and warned_soft


def test_impact_map_uses_compliant_restitution():
    r = simulate(TABLE1, 1.0, solver="impact-map")
    imp = r.impacts.head(5)
    e_ref = contact.restitution(imp.approach_velocity, TABLE1.k_hertz, TABLE1.m, TABLE1.M, TABLE1.c1)
    # the map interpolates a 40-node table in ln(speed): ~2e-7, far below its model error (~1e-3)
    np.testing.assert_allclose(imp.restitution, e_ref, rtol=1e-6)
    meff = TABLE1.effective_mass
    # the same product by another route: a few roundings (< 1e-15); 1e-13 is above that, far below any wrong factor
    np.testing.assert_allclose(imp.impulse, (1 + imp.restitution) * meff * imp.approach_velocity,
                               rtol=1e-13)
    assert abs(r.energy.relative_closure_error) < 1e-13


# --------------------------------------------------------------------------- interface
def test_impact_table_and_csv(tmp_path):
    r = simulate(TABLE1, 1.0)
    imp = r.impacts
    assert set(np.unique(imp.wall)) <= {-1.0, 1.0}
    assert np.all(np.diff(imp.time) > 0)
    assert np.all(imp.approach_velocity > 0) and np.all(imp.separation_velocity > 0)
    assert imp.wall[0] == -1  # main mass starts moving +x, the impact mass at rest: z falls
    path = write_impact_table(tmp_path / "impacts.csv", imp)
    lines = path.read_text().splitlines()
    assert lines[0] == ",".join(IMPACT_COLUMNS)
    assert len(lines) == len(imp) + 1
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 0], imp.time, rtol=1e-15)
    with pytest.raises(ValueError):
        imp.time[0] = 0.0


def test_dense_output_agrees_between_solvers_before_chaos():
    t = np.linspace(0, 0.2, 41)
    ev = simulate(TABLE1, 0.2, t_eval=t)
    nm = simulate(TABLE1, 0.2, solver="newmark", dt=1e-6, t_eval=t)
    # Newmark at 1e-6 s: first-order error from the damping-force jumps (see above), ~2e-5 m
    np.testing.assert_allclose(nm.x, ev.x, atol=1e-4)
    np.testing.assert_allclose(nm.y, ev.y, atol=1e-4)
    fine = simulate(TABLE1, 0.2, solver="newmark", dt=2.5e-7, t_eval=t)
    assert np.max(np.abs(fine.x - ev.x)) < 0.5 * np.max(np.abs(nm.x - ev.x))


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"solver": "rk4"}, "solver"),
        ({"rtol": 0.1}, "rtol"),
        ({"t_eval": [0.2, 0.1]}, "t_eval"),
        ({"t_eval": [0.0, 5.0]}, "t_eval"),
        ({"initial": InitialState(y=0.05)}, "initial.y"),
    ],
)
def test_bad_arguments_name_the_parameter(kwargs, name):
    with pytest.raises(ParameterError) as info:
        simulate(TABLE1, 1.0, **kwargs)
    assert info.value.name == name


def test_closed_form_solvers_need_an_underdamped_main_oscillator():
    with pytest.raises(ParameterError, match="underdamped"):
        simulate(DamperModel(C=100.0), 0.1)
    r = simulate(DamperModel(C=100.0), 0.1, solver="newmark")
    assert r.success


# --------------------------------------------------------------------------- end of motion
def test_run_ending_inside_a_contact_keeps_the_hertz_energy():
    first = simulate(TABLE1, 0.05).impacts
    t_mid = first.time[0] + 0.5 * first.duration[0]
    for solver in ("event", "newmark"):
        r = simulate(TABLE1, t_mid, solver=solver, t_eval=[t_mid])
        assert len(r.impacts) == 1 and np.isnan(r.impacts.separation_velocity[0])
        # half-way through the contact much of the relative kinetic energy is stored elastically
        assert r.energy.hertz > 0.3 * 0.5 * TABLE1.effective_mass * first.approach_velocity[0] ** 2
    assert abs(r.energy.relative_closure_error) < 1e-4  # Newmark at its default step (tau/50)


def test_sticking_contacts_and_chattering_end_gracefully():
    heavy = simulate(DamperModel(c1=2000.0), 1.0)  # overdamped contacts: the masses nearly stick
    assert heavy.success and len(heavy.impacts) > 0
    assert np.all(heavy.impacts.restitution[:3] < 0.01)
    assert abs(heavy.energy.relative_closure_error) < RTOL_CLOSURE
    capped = simulate(TABLE1, 20.0, max_impacts=10)
    assert not capped.success and "max_impacts" in capped.message
    assert len(capped.impacts) == 10 and capped.t_end < 20.0
    assert abs(capped.energy.relative_closure_error) < RTOL_CLOSURE


def test_clipped_force_closes_the_energy_balance():
    r = simulate(DamperModel(clip_tensile=True), 2.0)
    assert abs(r.energy.relative_closure_error) < RTOL_CLOSURE
    assert np.all(r.impacts.energy_lost > 0)


def test_cheapest_solver_follows_the_tolerance():
    from acoustiviz.dynamics import TABLE1, DamperModel, InitialState, cheapest_solver, shortest_contact

    assert cheapest_solver(TABLE1, tolerance=1e-10)[0] == "event"
    assert cheapest_solver(TABLE1, tolerance=5e-2)[0] == "impact-map"
    # a soft contact lasts a good part of the main period: no tolerance short of 1 admits the map
    soft = DamperModel(k_hertz=1e4)
    prod = shortest_contact(soft, InitialState()) * soft.main_frequency
    assert prod > 0.3
    assert cheapest_solver(soft, tolerance=0.2)[0] == "event"
    # and the map's measured error on Table 1 is indeed within the tolerance it is chosen for
    import numpy as np

    from acoustiviz.dynamics import simulate

    ref = simulate(TABLE1, 0.5, solver="event")
    fast = simulate(TABLE1, 0.5, solver="impact-map")
    n = min(len(ref.impacts), len(fast.impacts), 5)
    err = np.abs(fast.impacts.approach_velocity[:n] / ref.impacts.approach_velocity[:n] - 1)
    assert err.max() < 5e-2
