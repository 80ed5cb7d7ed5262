"""Forced impact damper: linear limit, Masri-Caughey reference, energy balance, second method."""

import math

import numpy as np
import pytest

from acoustiviz.dynamics._contact import free_restitution
from acoustiviz.dynamics._records import params_record
from acoustiviz.dynamics.forced import (
    Excitation,
    _params,
    linear_start,
    simulate_cycles,
    steady_state,
)
from acoustiviz.dynamics.model import DamperModel
from acoustiviz.dynamics.periodic import linear_amplitude, masri_caughey
from acoustiviz.errors import ParameterError

#: A damper whose symmetric two-impacts-per-cycle motion is stable near resonance.
MC_MODEL = DamperModel(C=1.0, m=0.1)
MC_FORCE = 2.0
MC_FREQS = (4.9, 5.1, 5.3)


# ------------------------------------------------------------------ linear limit
@pytest.mark.parametrize("solver", ["event", "impact-map", "newmark"])
@pytest.mark.parametrize("kind,amp", [("force", 5.0), ("base", 0.01)])
def test_no_impacts_amplitude_is_the_linear_steady_state(solver, kind, amp):
    model = DamperModel(C=2.0, gap=10.0)  # the impact mass never reaches a wall
    for f in (3.0, 5.0, 7.0):
        ex = Excitation(f, amp, kind)
        r = steady_state(model, ex, solver=solver, initial=(0.0, 0.0, 0.0, 0.0), tolerance=1e-10,
                         restitution=0.5 if solver == "impact-map" else None,
                         steps_per_cycle=4000 if solver == "newmark" else None)
        assert r.converged and r.regime == "periodic-1"
        assert r.impacts_per_cycle == 0
        # independent closed form: |X| = |F| / sqrt((K - M w^2)^2 + (C w)^2)
        w = 2 * math.pi * f
        den = math.hypot(model.K - model.M * w * w, model.C * w)
        ref = amp / den if kind == "force" else amp * math.hypot(model.K, model.C * w) / den
        tol = 1e-5 if solver == "newmark" else 1e-8
        assert r.amplitude == pytest.approx(ref, rel=tol)
        assert linear_amplitude(model, ex) == pytest.approx(ref, rel=1e-12)


def test_contact_onset_is_bracketed_exactly_at_grazing():
    """The impact mass at rest sees z = -x(t): it touches a wall iff |X| >= d/2."""
    ex = Excitation(4.0, 5.0)
    amp = abs(ex.linear_response(DamperModel()))
    for factor, touches in ((1 - 1e-7, True), (1 + 1e-7, False)):
        model = DamperModel(gap=2 * amp * factor)
        start = linear_start(model, ex)
        _, imp, _ = simulate_cycles(model, ex, 1, solver="event", initial=(*start[:2], 0.0, 0.0))
        assert (len(imp) > 0) == touches


# ------------------------------------------------------------------ Masri and Caughey
def _symmetric(r):
    """True for one impact on each wall, half a period apart."""
    if r.regime != "periodic-1" or r.impacts_per_cycle != 2:
        return False
    d = abs(r.impact_phases[1] - r.impact_phases[0])
    return abs(d - math.pi) < 1e-4 and r.impact_walls[0] == -r.impact_walls[1]


@pytest.mark.parametrize("f", MC_FREQS)
def test_impact_map_on_the_masri_caughey_orbit_stays_there(f):
    ex = Excitation(f, MC_FORCE)
    e = 0.5
    sols = [s for s in masri_caughey(MC_MODEL, ex, e) if s.valid]
    assert sols
    for s in sols:
        _, imp, _ = simulate_cycles(MC_MODEL, ex, 3, solver="impact-map", restitution=e,
                                    initial=s.state(MC_MODEL, ex, 0.0))
        assert len(imp) == 6
        np.testing.assert_allclose(imp[:, 2], s.approach_speed, rtol=1e-9)
        ph = np.mod(ex.omega * imp[:, 0] - s.phase + 0.5, math.pi) - 0.5
        np.testing.assert_allclose(ph, 0.0, atol=1e-9)


@pytest.mark.parametrize("f,e", [(4.9, 0.5), (5.1, 0.5), (5.3, 0.5), (5.1, 0.8), (5.3, 0.8)])
def test_impact_map_converges_to_masri_caughey(f, e):
    ex = Excitation(f, MC_FORCE)
    r = steady_state(MC_MODEL, ex, solver="impact-map", restitution=e, tolerance=1e-10)
    assert _symmetric(r)
    s = min((q for q in masri_caughey(MC_MODEL, ex, e) if q.valid),
            key=lambda q: abs(q.approach_speed - r.impact_speeds[0]))
    assert r.amplitude == pytest.approx(s.amplitude, rel=1e-6)
    np.testing.assert_allclose(r.impact_speeds, s.approach_speed, rtol=1e-7)
    assert np.min(np.abs(np.mod(r.impact_phases - s.phase + 1, 2 * math.pi) - 1)) < 1e-6


def _mc_compliant(model, ex):
    """Masri-Caughey with the restitution of the compliant contact at its own impact speed."""
    e, s = 0.9, None
    p = _params(model)
    for _ in range(40):
        s = [q for q in masri_caughey(model, ex, e) if q.valid][0]
        e_new = free_restitution(p, s.approach_speed, 1e-12)[0]
        if abs(e_new - e) < 1e-13:
            break
        e = e_new
    return s


@pytest.mark.parametrize("f", MC_FREQS[1:])
def test_compliant_restitution_map_matches_masri_caughey(f):
    ex = Excitation(f, MC_FORCE)
    r = steady_state(MC_MODEL, ex, solver="impact-map", tolerance=1e-10)
    s = _mc_compliant(MC_MODEL, ex)
    assert _symmetric(r)
    assert r.amplitude == pytest.approx(s.amplitude, rel=1e-6)
    np.testing.assert_allclose(r.impact_speeds, s.approach_speed, rtol=1e-7)


def test_event_solver_tends_to_masri_caughey_as_contacts_shorten():
    """The compliant solution differs from the instantaneous one by O(contact time x ω)."""
    ex = Excitation(5.1, MC_FORCE)
    errs, durs = [], []
    for kh in (5.6e8, 5.6e10, 5.6e12):
        model = DamperModel(C=1.0, m=0.1, k_hertz=kh)
        r = steady_state(model, ex, solver="event", tolerance=1e-10)
        assert _symmetric(r)
        s = _mc_compliant(model, ex)
        errs.append(abs(r.amplitude / s.amplitude - 1))
        durs.append(float(np.mean(r.impact_durations)))
        assert abs(r.impact_speeds[0] / s.approach_speed - 1) < 0.2 * errs[-1] + 1e-9
    assert errs[0] < 0.03
    # first order in the contact duration
    for i in range(2):
        assert errs[i] / errs[i + 1] == pytest.approx(durs[i] / durs[i + 1], rel=0.1)


# ------------------------------------------------------------------ energy and second method
@pytest.mark.parametrize("solver,tol", [("event", 1e-8), ("impact-map", 1e-10), ("newmark", 1e-3)])
@pytest.mark.slow
def test_energy_balance_per_cycle_closes(solver, tol):
    ex = Excitation(5.1, MC_FORCE)
    r = steady_state(MC_MODEL, ex, solver=solver, tolerance=1e-3 if solver == "newmark" else 1e-8,
                     restitution=0.5 if solver == "impact-map" else None)
    assert r.impacts_per_cycle >= 2
    assert r.work_input > 0
    assert abs(r.energy_closure) < tol
    assert r.dissipated_contact > 0 and r.dissipated_main > 0


def test_newmark_converges_to_the_event_solver():
    """Two cycles from the linear start: ten impacts, same times and speeds as the step shrinks."""
    ex = Excitation(5.1, MC_FORCE)
    _, ie, _ = simulate_cycles(MC_MODEL, ex, 2, solver="event", rtol=1e-12)
    errs = []
    for spc in (50_000, 200_000):
        _, inm, _ = simulate_cycles(MC_MODEL, ex, 2, solver="newmark", steps_per_cycle=spc)
        assert len(inm) == len(ie) >= 8
        errs.append(np.max(np.abs(inm[:, 0] - ie[:, 0])))
        np.testing.assert_allclose(inm[:, 2], ie[:, 2], rtol=2e-2)  # approach speeds
        np.testing.assert_allclose(inm[:, 3], ie[:, 3], rtol=2e-2)  # separation speeds
    assert errs[1] < 5e-5  # s, against contacts of 4e-4 s
    assert errs[1] < errs[0] / 3


def test_regime_without_period_is_reported_with_its_evidence():
    """Table 1 at 4 Hz, 5 N: no periodic orbit; chaotic only with a positive exponent beyond its error bar."""
    r = steady_state(DamperModel(), Excitation(4.0, 5.0), max_cycles=40)
    assert not r.converged and r.period == 0 and math.isnan(r.residual)
    assert r.regime == "chaotic" and "Lyapunov" in r.message
    assert r.lyapunov - 3 * r.lyapunov_std_err > 0
    assert r.measured_cycles == 128 and r.amplitude_std_err > 0
    assert r.x_max - r.x_min >= 2 * r.amplitude  # the mean batch amplitude within the window's extremes


@pytest.mark.parametrize("kwargs,name", [
    ({"restitution": 1.5, "solver": "impact-map"}, "restitution"),
    ({"restitution": 0.5, "solver": "event"}, "restitution"),
    ({"solver": "rk4"}, "solver"),
    ({"tolerance": 0.5}, "tolerance"),
    ({"max_cycles": 3}, "max_cycles"),
])
def test_bad_settings_name_the_parameter(kwargs, name):
    with pytest.raises(ParameterError) as err:
        steady_state(DamperModel(), Excitation(5.0, 5.0), **kwargs)
    assert err.value.name == name


def test_bad_excitation_names_the_parameter():
    with pytest.raises(ParameterError) as err:
        Excitation(-1.0, 5.0)
    assert err.value.name == "frequency"
    with pytest.raises(ParameterError) as err:
        Excitation(5.0, 5.0, "wind")
    assert err.value.name == "kind"
    undamped = DamperModel(C=0.0)
    with pytest.raises(ParameterError) as err:
        steady_state(undamped, Excitation(undamped.main_frequency / (2 * math.pi), 1.0))
    assert err.value.name == "frequency"


@pytest.mark.parametrize("solver", ["event", "newmark"])
def test_a_run_may_start_inside_a_contact(solver):
    """A continued sweep can stop mid-contact: the next run resumes that contact."""
    model = DamperModel()
    hg = 0.5 * model.gap
    start = (0.0, 0.0, hg + 2e-5, 0.3)  # 20 µm into wall +1, still approaching at 0.3 m/s
    pts, imp, en = simulate_cycles(model, Excitation(6.5, 5.0), 1, solver=solver, initial=start,
                                   steps_per_cycle=100_000 if solver == "newmark" else None)
    # the resumed contact pushes the impact mass back: it leaves wall +1 towards wall -1
    assert abs(en[0] - en[1] - en[2] - en[3]) < 1e-6 * max(abs(en[0]), 1e-3) + (0 if solver == "event" else 1e-5)
    assert imp.size == 0 or imp[0, 0] > 0
    with pytest.raises(ParameterError) as err:
        steady_state(model, Excitation(6.5, 5.0), initial=(0.0, 0.0, 1.5 * hg, 0.0))
    assert err.value.name == "initial"


def test_masri_caughey_holds_for_base_excitation():
    """The closed form takes any harmonic force: a base motion acts through K and C."""
    model = DamperModel(C=1.0, m=0.1)
    ex = Excitation(5.1, 2.0 / model.K, "base")  # about the 2 N case, plus the dashpot's share
    for s in (q for q in masri_caughey(model, ex, 0.5) if q.valid):
        _, imp, en = simulate_cycles(model, ex, 3, solver="impact-map", restitution=0.5,
                                     initial=s.state(model, ex, 0.0))
        assert len(imp) == 6
        np.testing.assert_allclose(imp[:, 2], s.approach_speed, rtol=1e-9)
        # periodic: the work of the base equals what the dashpot and the impacts dissipate
        assert abs(en[3]) < 1e-9 * en[0]
        assert en[0] == pytest.approx(en[1] + en[2], rel=1e-9)
        # and the impact losses are the closed form's: (1 - e^2) m_eff u^2 / 2 per impact
        meff = model.effective_mass
        assert en[2] == pytest.approx(6 * 0.5 * meff * s.approach_speed**2 * (1 - 0.25), rel=1e-9)


def test_energy_balance_under_base_excitation_closes():
    r = steady_state(DamperModel(C=1.0, m=0.1), Excitation(5.1, 0.004, "base"), tolerance=1e-8)
    assert r.converged and r.impacts_per_cycle >= 2
    assert abs(r.energy_closure) < 1e-8


def test_impact_map_sticks_instead_of_chattering():
    """A Zeno train of rebounds on a pressing wall ends in sticking; the run completes and balances."""
    r = steady_state(DamperModel(), Excitation(4.75, 5.0), solver="impact-map", restitution=0.6)
    assert r.success and r.regime != "failed"
    assert abs(r.energy_closure) < 1e-9
    _, imp, en = simulate_cycles(DamperModel(), Excitation(5.0, 5.0), 40, solver="impact-map", restitution=0.6)
    assert np.sum(imp[:, 3] == 0.0) > 10  # plastic last rebounds: sticking phases
    assert abs(en[0] - en[1] - en[2] - en[3]) < 1e-10 * en[0]


def test_sticking_phase_and_release_match_an_ode_solution():
    """Stuck on wall +1 the pair moves as M + m until x'' turns >= 0; then the main mass flies free."""
    from scipy.integrate import solve_ivp

    from acoustiviz.dynamics import _forced_driver as fd
    from acoustiviz.dynamics.forced import _params, _together

    model, ex = DamperModel(), Excitation(5.0, 5.0)
    M, m, K, C, w = model.M, model.m, model.K, model.C, ex.omega

    def pair(t, s):
        return [s[1], (5.0 * np.cos(w * t) - K * s[0] - C * s[1]) / (M + m)]

    def release(t, s):
        return pair(t, s)[1]

    release.direction = 1.0
    release.terminal = True
    x0, v0 = 0.05, 0.0  # the spring pulls back harder than the force pushes: the wall presses
    ref = solve_ivp(pair, (0, 0.2), [x0, v0], events=release, rtol=1e-12, atol=1e-14)
    t_rel = ref.t_events[0][0]
    xr, vr = ref.y_events[0][0]
    t1 = t_rel + 0.005
    free = solve_ivp(lambda t, s: [s[1], (5.0 * np.cos(w * t) - K * s[0] - C * s[1]) / M], (t_rel, t1),
                     [xr, vr], rtol=1e-12, atol=1e-14)
    st = np.array([x0, v0, x0 + 0.5 * model.gap, v0, 2.0, 1.0, 0.0, 0.0])
    imp = np.zeros((4, 8))
    acc = np.zeros(5)
    n, status = fd.advance(params_record(_params(model)), ex.vector(model), _together(model, ex, "impact-map"), st,
                           0.0, t1, 0.6, 1e-10, imp, 0, 4, acc, False)
    assert status == 0 and n == 0 and st[4] == 0.0  # released, no new impact yet
    assert st[0] == pytest.approx(free.y[0, -1], abs=1e-10)
    assert st[1] == pytest.approx(free.y[1, -1], abs=1e-9)
    assert st[3] == pytest.approx(vr, abs=1e-9)  # the impact mass leaves with the release velocity




@pytest.mark.parametrize("solver", ["event", "newmark"])
def test_zero_forcing_is_free_decay(solver):
    """With F = 0 the forced driver (bounded scan, quadrature energies, cycle by cycle) follows
    the free-decay solver (exact scan, closed-form energies) of the Table 1 damper, Figure 5 start."""
    from acoustiviz.dynamics import TABLE1, InitialState, simulate

    cycles, f = 5, 5.0  # 1 s of free decay, 22 impacts
    # Newmark restarts each cycle from accelerations recomputed from the state, not from the last
    # Newton iterate (converged to 1e-13): a small difference the chaotic motion then amplifies
    if solver == "event":
        forced_kw, free_kw, tol = {"rtol": 1e-13}, {"rtol": 1e-13}, 1e-11
    else:
        forced_kw, free_kw, tol = {"steps_per_cycle": 40000}, {"dt": 1.0 / (f * 40000)}, 1e-9
    pts, imp, en = simulate_cycles(TABLE1, Excitation(f, 0.0), cycles, solver=solver,
                                   initial=(0.0, 2.0, 0.0, 0.0), **forced_kw)
    r = simulate(TABLE1, cycles / f, solver=solver, initial=InitialState(), **free_kw)
    assert len(imp) == len(r.impacts) >= 20
    np.testing.assert_array_equal(imp[:, 1], r.impacts.wall)
    np.testing.assert_allclose(imp[:, 0], r.impacts.time, rtol=0, atol=tol)
    np.testing.assert_allclose(imp[:, 2], r.impacts.approach_velocity, rtol=10 * tol)
    if solver == "event":  # both locate the maximum of the contact force inside the step
        np.testing.assert_allclose(imp[:, 5], r.impacts.peak_force, rtol=1e-9)
    assert en[0] == 0.0  # no work without a force
    assert en[1] == pytest.approx(r.energy.dissipated_main, rel=10 * tol)
    assert en[2] == pytest.approx(r.energy.dissipated_contact, rel=10 * tol)
    np.testing.assert_allclose(pts[-1, :2], r.final_state[:2], rtol=100 * tol)
