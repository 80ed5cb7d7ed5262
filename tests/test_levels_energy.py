"""Sound energy of one impact: closed form, surface work, grid intensity, and their limits."""

import math

import numpy as np
import pytest
from scipy.integrate import quad, trapezoid

from acoustiviz.core.contact import HalfSinePulse, Impact, SampledPulse, acceleration_pulse
from acoustiviz.core.geometry import geometry
from acoustiviz.core.medium import AIR
from acoustiviz.errors import ParameterError
from acoustiviz.field.grids import spherical_grid_for
from acoustiviz.levels import (
    pulse_spectrum,
    radiated_energy_free,
    radiated_energy_grid,
    radiation_efficiency,
    radiation_resistance,
    sound_power,
    surface_work_free,
)

A = 0.01905
IMPACT = Impact(velocity=1.4, k_hertz=5.6e8, mass=0.0405)


@pytest.fixture(scope="module", params=["half-sine", "hertz"])
def pulse(request):
    return acceleration_pulse(IMPACT, request.param, n_samples=257)


@pytest.mark.slow
def test_closed_form_equals_far_field_intensity_over_the_free_grid(pulse):
    grid = spherical_grid_for(geometry("free", A), 1.0, n_theta=4)
    closed = radiated_energy_free(pulse, radius=A)
    grid_energy = radiated_energy_grid(pulse, geometry("free", A).sources, grid, radius=A)
    assert grid_energy == pytest.approx(closed, rel=1e-6)


@pytest.mark.slow
def test_closed_form_equals_the_surface_work_less_the_entrained_flow(pulse):
    assert surface_work_free(pulse, radius=A) == pytest.approx(radiated_energy_free(pulse, radius=A), rel=1e-6)


@pytest.mark.slow
def test_compact_limit_is_the_rayleigh_dipole():
    # tau >> a/c: R ~ (4 pi a^2/3) rho c (ka)^4 / 4, so E -> (pi rho a^6 / (3 c^3)) * integral (dA/dt)^2 dt
    a0, tau = 1e3, 300 * A / AIR.c
    pulse = HalfSinePulse(a0, tau)
    rayleigh = math.pi * AIR.rho * A**6 / (3 * AIR.c**3) * a0**2 * math.pi**2 / (2 * tau)
    # the step in dA/dt at both ends adds a tail above c/a that the (ka)^4 law overstates: O(a / (c tau))
    assert radiated_energy_free(pulse, radius=A) == pytest.approx(rayleigh, rel=2 * A / (AIR.c * tau))
    assert radiated_energy_free(pulse, radius=A) < rayleigh


def test_radiation_resistance_tends_to_the_piston_value_at_high_frequency():
    r = radiation_resistance(np.array([1e9]), radius=A)
    assert r[0] == pytest.approx(4 * math.pi * A**2 / 3 * AIR.rho * AIR.c, rel=1e-9)


def test_half_sine_spectrum_is_its_fourier_integral():
    pulse = HalfSinePulse(2.0, 1e-4)
    t = np.linspace(0, 1e-4, 20001)
    w = np.array([0.0, 1e4, math.pi / 1e-4, 1e5])
    direct = [trapezoid(pulse.acceleration(t) * np.exp(-1j * wi * t), t) for wi in w]
    assert np.allclose(pulse_spectrum(pulse, w), direct, rtol=1e-7, atol=1e-12)
    assert pulse_spectrum(pulse, np.array([0.0]))[0].real == pytest.approx(pulse.velocity_change)


def test_sampled_spectrum_is_the_fourier_integral_of_the_piecewise_linear_pulse():
    hertz = acceleration_pulse(IMPACT, "hertz", n_samples=33)
    pulse = SampledPulse(hertz.times, hertz.acceleration_samples)
    t = np.linspace(0, pulse.duration, 200001)
    w = np.array([0.0, 3e3, 3e4, 2e5])
    direct = [trapezoid(pulse.acceleration(t) * np.exp(-1j * wi * t), t) for wi in w]
    assert np.allclose(pulse_spectrum(pulse, w), direct, rtol=1e-6, atol=1e-9 * pulse.velocity_change)


def test_sampled_spectrum_stays_exact_where_its_segments_phase_is_small():
    """Frequencies whose phase per segment ``ω h`` spans φ1/φ2's switch to their series (near 1e-3 and 0.25)."""
    hertz = acceleration_pulse(IMPACT, "hertz", n_samples=33)
    pulse = SampledPulse(hertz.times, hertz.acceleration_samples)
    h = float(np.min(np.diff(pulse.times)))
    w = np.array([5e-4, 1e-3, 2e-3, 0.2, 0.25, 0.3]) / h
    t = np.linspace(0, pulse.duration, 200001)
    direct = [trapezoid(pulse.acceleration(t) * np.exp(-1j * wi * t), t) for wi in w]
    assert np.allclose(pulse_spectrum(pulse, w), direct, rtol=1e-6, atol=1e-9 * pulse.velocity_change)


@pytest.mark.parametrize("w", [0.0, 3e3, 3e4, 2e5, 2e6])
def test_exact_hertz_spectrum_is_the_fourier_integral_of_the_closed_form(w):
    pulse = acceleration_pulse(IMPACT, "hertz")
    tau = pulse.duration
    # QUADPACK's QAWO rule for the oscillatory weights cos(wt) and sin(wt), on pieces graded towards the
    # t^{3/2} ends of the contact
    edges = tau * np.unique(np.concatenate([np.geomspace(1e-6, 0.5, 20), 1 - np.geomspace(1e-6, 0.5, 20), [0, 1]]))
    tol = 1e-15 * pulse.velocity_change
    parts = [sum(quad(lambda t: float(pulse.acceleration(t)), lo, hi, weight=kind, wvar=w, limit=200, epsabs=tol,
                      epsrel=1e-11)[0] for lo, hi in zip(edges[:-1], edges[1:], strict=True))
             for kind in ("cos", "sin")]
    direct = parts[0] - 1j * parts[1]
    assert pulse_spectrum(pulse, np.array([w]))[0] == pytest.approx(direct, rel=1e-9, abs=1e-11 * pulse.velocity_change)


@pytest.mark.parametrize("config", ["plane", "wall-floor"])
@pytest.mark.slow
def test_grid_integration_converges_as_the_grid_is_refined(config):
    pulse = acceleration_pulse(IMPACT, "half-sine")
    cfg = geometry(config, A, lenient=True, wall_distance=0.05)
    e = [radiated_energy_grid(pulse, cfg.sources, spherical_grid_for(cfg, 1.0, n_theta=n), radius=A)
         for n in (3, 6, 12)]
    d1, d2 = abs(e[1] - e[0]), abs(e[2] - e[1])
    assert d2 < 0.1 * d1
    assert d2 < 1e-4 * e[2]


def test_efficiency_and_power_arithmetic_and_errors():
    assert radiation_efficiency([1e-6, 2e-6], [1e-3, 1e-3]) == pytest.approx([1e-3, 2e-3])
    assert sound_power([1e-6, 3e-6], 2.0) == pytest.approx(2e-6)
    with pytest.raises(ParameterError, match="energy_lost"):
        radiation_efficiency(1e-6, 0.0)
    with pytest.raises(ParameterError, match="duration"):
        sound_power([1e-6], 0.0)


@pytest.mark.slow
def test_run_energy_interpolates_the_configuration_ratio_faithfully():
    from acoustiviz.app.wav import cavity
    from acoustiviz.dynamics.result import ImpactTable
    from acoustiviz.levels.energy import run_energy
    from acoustiviz.sound import ClickModel, wall_sources

    speeds = np.array([0.2, 0.5, 0.9, 1.4, 2.0])
    n = speeds.size
    table = ImpactTable(time=np.arange(n) * 0.1, wall=-np.ones(n), approach_velocity=speeds,
                        separation_velocity=0.7 * speeds, restitution=np.full(n, 0.7), duration=np.full(n, 3e-4),
                        peak_force=np.full(n, 1e3), impulse=np.full(n, 0.1),
                        energy_lost=0.5 * 0.0405 * speeds**2 * (1 - 0.49))
    room = cavity("plane", A, 0.04)
    model = ClickModel()
    out = run_energy(table, room, model, duration=1.0)
    grid = spherical_grid_for(room.geometry, 1.0, n_theta=8)
    # the reference speeds are the table's quartiles: 0.2, 0.5, 0.9, 1.4, 2.0 -> exact at every impact
    for k, v in enumerate(speeds):
        direct = radiated_energy_grid(model.pulse_for(v), wall_sources(room, -1), grid, radius=A)
        assert out.energy_j[k] == pytest.approx(direct, rel=1e-9)
    # between reference speeds the log-speed interpolation of the ratio stays within 2 %
    mid = math.sqrt(0.9 * 1.4)
    ratio = lambda v: (radiated_energy_grid(model.pulse_for(v), wall_sources(room, -1), grid, radius=A)  # noqa: E731
                       / radiated_energy_free(model.pulse_for(v), radius=A))
    interp = np.interp(math.log(mid), np.log([0.9, 1.4]), [ratio(0.9), ratio(1.4)])
    assert interp == pytest.approx(ratio(mid), rel=0.02)
    assert out.sound_power_w == pytest.approx(out.energy_j.sum())
    assert out.loudest == n - 1 and out.efficiency[-1] == pytest.approx(out.energy_j[-1] / table.energy_lost[-1])


def test_half_sine_energy_is_the_integral_of_its_complex_transform():
    # the residue closed form against adaptive quadrature of R |A|² / ω² with the complex transform
    # |pulse_spectrum|², over 400 bands up to 400π / min(τ, a/c) (the rest falls off as ω⁻⁶)
    pulse = acceleration_pulse(IMPACT, "half-sine")
    wmax = 400 * math.pi / min(pulse.duration, A / AIR.c)

    def integrand(x):
        return float(radiation_resistance(np.array([x]), radius=A)[0] * abs(pulse_spectrum(pulse, x)) ** 2 / (x * x))

    edges = np.linspace(0.0, wmax, 401)
    total = sum(quad(integrand, lo, hi, epsabs=0, epsrel=1e-11, limit=200)[0]
                for lo, hi in zip(edges[:-1], edges[1:], strict=True))
    assert radiated_energy_free(pulse, radius=A) == pytest.approx(total / math.pi, rel=1e-7)


@pytest.mark.parametrize("ratio", [0.02, 0.1, 0.3, 1.0, 10.0, 100.0])
def test_half_sine_energy_equals_the_surface_work_from_short_to_long_contacts(ratio):
    # contact durations from 1/50 to 100 times a/c: the closed form against the work in time, whose
    # trapezoidal error (2000 samples per min(τ, a/c)) is about 1e-9
    pulse = HalfSinePulse(9800.0, ratio * A / AIR.c)
    assert radiated_energy_free(pulse, radius=A) == pytest.approx(surface_work_free(pulse, radius=A), rel=1e-7)


@pytest.mark.slow
@pytest.mark.parametrize("k_hertz", [5e11, 5e13])
@pytest.mark.parametrize("sampled", [False, True])
def test_contacts_shorter_than_a_over_c_resolve_the_radiation_corner(k_hertz, sampled):
    # contacts of 0.31 and 0.05 a/c spread |A|² far beyond c/a, where R(ω) turns from ω⁴ to flat: a
    # step per period of |A|² alone missed that corner (6.5e-3 and 0.11 high for the Hertz pulse)
    pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=k_hertz, mass=0.0405), "hertz")
    assert pulse.duration < 0.35 * A / AIR.c
    if sampled:
        t = np.linspace(0.0, pulse.duration, 257)
        pulse = SampledPulse(t, pulse.acceleration(t))
    assert radiated_energy_free(pulse, radius=A) == pytest.approx(surface_work_free(pulse, radius=A), rel=1e-7)


@pytest.mark.parametrize("name", ["plane", "wall-floor"])
def test_grid_energy_is_the_sum_of_every_directions_own_far_field(name):
    # directions on a ring about the image axis share one response; each direction evaluated on its own
    from acoustiviz.core.images import ImageSet
    from acoustiviz.core.radiation import pulse_response
    from acoustiviz.levels.energy import _time_grid

    pulse = acceleration_pulse(IMPACT, "half-sine")
    cfg = geometry(name, A, lenient=True, wall_distance=0.05)
    grid = spherical_grid_for(cfg, 1.0, n_theta=4)
    imgs = ImageSet.of(cfg.sources)
    pos = imgs.positions - np.asarray(grid.centre, dtype=float)
    reach = float(np.max(np.linalg.norm(pos, axis=1))) / AIR.c
    t = _time_grid(pulse, A, AIR, -reach, reach, per=100)
    ref = 0.0
    for n, wt in zip(np.asarray(grid.directions), np.asarray(grid.weights), strict=True):
        q = sum(float(n @ ax) * np.real((1 + 1j) * pulse_response(pulse, t + float(n @ x) / AIR.c, radius=A))
                for x, ax in zip(pos, imgs.weighted_axes, strict=True))
        ref += wt * trapezoid((AIR.rho * AIR.c * A * q) ** 2, t)
    got = radiated_energy_grid(pulse, cfg.sources, grid, radius=A)
    assert got == pytest.approx(ref / (AIR.rho * AIR.c), rel=1e-12)
