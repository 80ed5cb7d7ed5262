"""Hertz contact checked against independent integrations and conservation laws."""

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from acoustiviz._validate import ParameterError
from acoustiviz.core.contact import (
    HERTZ_DURATION_CONSTANT,
    PAPER_DURATION_CONSTANT,
    HalfSinePulse,
    Impact,
    SampledPulse,
    acceleration_pulse,
    contact_duration,
    damped_contact,
    effective_mass,
    hertz_pulse_shape,
    hertz_stiffness,
    max_approach,
    peak_acceleration,
    peak_force,
    restitution,
)
from acoustiviz.core.materials import Material, material

# the paper's Figure 2 sphere (steel, radius 19.05 mm): its mass in kg; its impact is the fixture paper_impact
RADIUS = 0.01905
MASS = 7800 * 4 / 3 * math.pi * RADIUS**3
TIGHT = 1e-10


def _undamped_ode(meff, k, u0, c1=0.0):
    """Dimensional contact ODE integrated independently of the library."""

    def rhs(_t, y):
        a, v = y
        return (v, -(k * max(a, 0.0) ** 1.5 + c1 * v) / meff)

    def end(_t, y):
        return y[0]

    end.terminal, end.direction = True, -1
    tau_guess = 10 * (meff * u0**2 / k) ** 0.4 / u0
    return solve_ivp(rhs, (0, 100 * tau_guess), (0.0, u0), method="DOP853", rtol=1e-12, atol=1e-20,
                     events=end, dense_output=True, first_step=tau_guess * 1e-6)


def test_duration_constant_is_four_fifths_beta():
    # (4/5) B(2/5, 1/2) from an independent quadrature of 2 * int_0^1 dx / sqrt(1 - x^2.5)
    val, _ = quad(lambda x: 1.0 / math.sqrt(1.0 - x**2.5), 0, 1, limit=200, epsabs=0, epsrel=1e-13)
    assert HERTZ_DURATION_CONSTANT == pytest.approx(2 * val, rel=1e-10)
    assert HERTZ_DURATION_CONSTANT == pytest.approx(2.943275, abs=5e-7)
    # the paper's rounding differs only in the fifth digit
    assert abs(PAPER_DURATION_CONSTANT / HERTZ_DURATION_CONSTANT - 1) < 3e-5


def test_duration_and_peaks_match_direct_integration(paper_impact):
    sol = _undamped_ode(MASS, 5.6e8, 1.4)
    t_end = sol.t_events[0][0]
    assert paper_impact.duration == pytest.approx(t_end, rel=1e-9)
    tt = np.linspace(0, t_end, 20001)
    alpha = sol.sol(tt)[0]
    assert paper_impact.max_approach == pytest.approx(alpha.max(), rel=1e-8)
    assert paper_impact.peak_force == pytest.approx(5.6e8 * alpha.max() ** 1.5, rel=1e-8)
    # energy: (2/5) K alpha_max^2.5 = 1/2 m U0^2
    assert 0.4 * 5.6e8 * paper_impact.max_approach**2.5 == pytest.approx(0.5 * MASS * 1.4**2, rel=1e-12)


def test_paper_eq3_peak_acceleration(paper_impact):
    k, u0 = 5.6e8, 1.4
    kstar = 1 / MASS
    eq3 = k / MASS * (5 * u0**2 / (4 * kstar * k)) ** 0.6
    assert peak_acceleration(u0, k, MASS) == pytest.approx(eq3, rel=1e-13)
    # eq 13's amplitude (125 K^2 U0^6 / (64 m^2))^(1/5) is the same number
    assert paper_impact.peak_acceleration == pytest.approx((125 * k**2 * u0**6 / (64 * MASS**2)) ** 0.2, rel=1e-13)


def test_stiffness_matches_paper_eq2_literally():
    steel, glass = material("steel"), material("glass")
    a = 0.01
    eq2 = 4 / (3 * math.pi) * math.sqrt(a) / (
        (1 - steel.nu**2) / (math.pi * steel.E) + (1 - glass.nu**2) / (math.pi * glass.E)
    )
    assert hertz_stiffness(a, steel, glass) == pytest.approx(eq2, rel=1e-13)


def test_exact_pulse_shape_solves_the_ode():
    # s'' = -(5/4) s^1.5, s(0)=0, s'(0)=1, integrated here independently
    sol = solve_ivp(lambda _t, y: (y[1], -1.25 * max(y[0], 0) ** 1.5), (0, HERTZ_DURATION_CONSTANT),
                    (0.0, 1.0), method="DOP853", rtol=1e-13, atol=1e-15, dense_output=True)
    th = np.linspace(0, HERTZ_DURATION_CONSTANT, 401)
    ref = np.maximum(sol.sol(th)[0], 0) ** 1.5
    assert np.max(np.abs(hertz_pulse_shape(th) - ref)) < 1e-9
    assert hertz_pulse_shape(np.array([-1e-3, HERTZ_DURATION_CONSTANT + 1e-3])).tolist() == [0, 0]


@pytest.mark.parametrize("partner", [math.inf, 0.5, 0.05])
def test_exact_pulse_impulse_and_rebound(partner):
    imp = Impact(velocity=2.0, k_hertz=5.6e8, mass=0.0405, partner_mass=partner)
    tau = imp.duration
    scale = imp.velocity / imp.max_approach

    def acc(t):
        return imp.peak_acceleration * float(hertz_pulse_shape(t * scale))

    dv, _ = quad(acc, 0, tau, limit=200, epsabs=0, epsrel=1e-12)
    # impulse 2 m_eff U0 of an elastic contact
    assert imp.mass * dv == pytest.approx(2 * imp.effective_mass * imp.velocity, rel=1e-9)
    # the approach returns to zero at the end: U0 tau - (m/m_eff) int (tau - xi) A dxi = 0
    moment, _ = quad(lambda x: (tau - x) * acc(x), 0, tau, limit=200, epsabs=0, epsrel=1e-12)
    assert imp.velocity * tau - imp.mass / imp.effective_mass * moment == pytest.approx(
        0, abs=1e-9 * imp.max_approach)
    # the sampled pulse keeps the impulse to its sampling accuracy
    sp = acceleration_pulse(imp, "hertz", n_samples=2049)
    assert isinstance(sp, SampledPulse) and sp.kind == "hertz"
    assert sp.velocity_change * imp.mass == pytest.approx(imp.impulse, rel=2e-6)


def test_half_sine_pulses_and_their_impulse(paper_impact):
    hs = acceleration_pulse(paper_impact, "half-sine")
    im = acceleration_pulse(paper_impact, "impulse-matched")
    assert isinstance(hs, HalfSinePulse) and hs.kind == "half-sine"
    assert im.kind == "impulse-matched"
    assert hs.duration == im.duration == pytest.approx(paper_impact.duration)
    assert hs.peak == pytest.approx(paper_impact.peak_acceleration)
    # peak-matched half-sine: area 2 A tau / pi = (5/2) C U0 / pi against the true 2 U0
    ratio = hs.velocity_change * MASS / paper_impact.impulse
    assert ratio == pytest.approx(1.25 * HERTZ_DURATION_CONSTANT / math.pi, rel=1e-12)
    assert ratio == pytest.approx(1.1711, abs=1e-4)
    assert im.velocity_change * MASS == pytest.approx(paper_impact.impulse, rel=1e-12)
    # numerically integrated area agrees with the closed form
    area, _ = quad(hs.acceleration, 0, hs.duration, epsabs=0, epsrel=1e-12)
    assert area == pytest.approx(hs.velocity_change, rel=1e-10)


def test_effective_mass_and_scalings():
    assert effective_mass(0.0405, 0.5) == pytest.approx(0.0405 * 0.5 / 0.5405)
    assert effective_mass(0.0405) == 0.0405
    u = np.array([0.5, 1.0, 2.0])
    # tau ~ U0^(-1/5), alpha_max ~ U0^(4/5), F ~ U0^(6/5)
    tau = contact_duration(u, 5.6e8, 0.04)
    assert tau[0] / tau[2] == pytest.approx(4 ** 0.2, rel=1e-12)
    am = max_approach(u, 5.6e8, 0.04)
    assert am[2] / am[0] == pytest.approx(4 ** 0.8, rel=1e-12)
    f = peak_force(u, 5.6e8, 0.04)
    assert f[2] / f[0] == pytest.approx(4 ** 1.2, rel=1e-12)


def test_restitution_undamped_is_one_and_matches_direct_integration():
    assert restitution(1.0, 5.6e8, 0.0405, 0.5, damping=0.0) == 1.0
    meff = effective_mass(0.0405, 0.5)
    for u0 in (0.3, 2.0):
        sol = _undamped_ode(meff, 5.6e8, u0, c1=20.0)
        e_ref = -sol.y_events[0][0][1] / u0
        e = restitution(u0, 5.6e8, 0.0405, 0.5, damping=20.0)
        assert e == pytest.approx(e_ref, rel=1e-8)
        assert 0 < e < 1


def test_restitution_rises_with_velocity_and_mass():
    # zeta = c1 alpha_max / (m_eff U0) falls with U0 and m: the paper's linear damping
    e_v = restitution(np.array([0.1, 0.5, 2.0]), 5.6e8, 0.0405, 0.5, damping=20.0)
    assert np.all(np.diff(e_v) > 0)
    e_m = [restitution(1.0, 5.6e8, m, 0.5, damping=20.0) for m in (0.01, 0.04, 0.1)]
    assert np.all(np.diff(e_m) > 0)


def test_damped_contact_impulse_and_clipping():
    imp = Impact(velocity=1.0, k_hertz=5.6e8, mass=0.0405, partner_mass=0.5, damping=20.0)
    dc = damped_contact(imp, n_output=20001)
    # impulse of the force = m_eff (U0 + U_separation)
    impulse = np.trapezoid(dc.force, dc.time)
    assert impulse == pytest.approx(imp.effective_mass * imp.velocity * (1 + dc.restitution), rel=1e-6)
    assert dc.force.min() < 0  # the paper's linear damping pulls as contact ends
    clipped = damped_contact(Impact(1.0, 5.6e8, 0.0405, 0.5, damping=20.0, clip_tensile=True))
    assert clipped.force.min() >= 0
    # clipping removes the pull, so the bodies part faster
    assert clipped.restitution > dc.restitution
    assert clipped.duration < dc.duration


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"velocity": 0.0, "k_hertz": 1e8, "mass": 0.1}, "velocity"),
        ({"velocity": 1.0, "k_hertz": -1.0, "mass": 0.1}, "k_hertz"),
        ({"velocity": 1.0, "k_hertz": 1e8, "mass": float("nan")}, "mass"),
        ({"velocity": 1.0, "k_hertz": 1e8, "mass": 0.1, "damping": -1}, "damping"),
    ],
)
def test_bad_impacts_name_the_field(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        Impact(**kwargs)


def test_unknown_pulse_and_material_are_clear_errors(paper_impact):
    with pytest.raises(ParameterError, match="pulse.*half-sine"):
        acceleration_pulse(paper_impact, "square")
    with pytest.raises(ParameterError, match="did you mean 'steel'"):
        material("steal")
    with pytest.raises(ParameterError, match="nu"):
        Material(E=1e9, nu=0.6, density=1000)


def test_damped_contact_peak_force_is_the_refined_maximum():
    """The peak is the maximum of the dense solution, not the largest of the output samples."""
    undamped = Impact(1.4, 5.6e8, 0.0405, 0.5)
    dc = damped_contact(undamped, n_output=64)
    # without damping the peak is the closed form K (5 m_eff U0^2 / (4 K))^(3/5)
    assert dc.peak_force == pytest.approx(undamped.peak_force, rel=1e-10)  # the ODE is solved to rtol 1e-11
    assert dc.peak_force > float(dc.force.max())  # 64 samples miss the top
    damped = Impact(1.4, 5.6e8, 0.0405, 0.5, damping=20.0)
    coarse, fine = damped_contact(damped, n_output=64), damped_contact(damped, n_output=400_001)
    assert coarse.peak_force == pytest.approx(fine.peak_force, rel=1e-12)
    assert coarse.peak_force >= float(fine.force.max()) * (1 - 1e-13)  # no sample lies above it
    assert coarse.peak_force - float(fine.force.max()) < 1e-9 * coarse.peak_force


def test_sampled_pulses_compare_by_value():
    """Two pulses with the same samples are equal (a settings object holding one can be compared)."""
    from acoustiviz.core.pulses import HertzPulse, SampledPulse

    assert HertzPulse(1000.0, 1e-4) == HertzPulse(1000.0, 1e-4)
    assert HertzPulse(1000.0, 1e-4) != HertzPulse(1001.0, 1e-4)
    assert SampledPulse([0.0, 1e-4, 2e-4], [0.0, 1.0, 0.0]) == SampledPulse((0.0, 1e-4, 2e-4), (0.0, 1.0, 0.0))
    assert SampledPulse([0.0, 1e-4, 2e-4], [0.0, 1.0, 0.0]) != SampledPulse([0.0, 1e-4, 2e-4], [0.0, 2.0, 0.0])
    assert HertzPulse(1000.0, 1e-4) != SampledPulse(HertzPulse(1000.0, 1e-4).times,
                                                    HertzPulse(1000.0, 1e-4).acceleration_samples, "hertz")
    with pytest.raises(TypeError):
        hash(HertzPulse(1000.0, 1e-4))
