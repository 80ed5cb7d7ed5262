"""Metrics of the damper checked on signals whose maxima, slopes and settling are known."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from acoustiviz._validate import ParameterError
from acoustiviz.core import contact
from acoustiviz.dynamics import TABLE1, DamperModel, InitialState, simulate
from acoustiviz.dynamics.metrics import (
    Maxima,
    damping_inclination,
    envelope_inclination,
    free_response,
    positive_maxima,
    restitution_curve,
    sample_times,
    settling_time,
)


def test_positive_maxima_of_a_sine_with_linear_envelope():
    t = np.linspace(0, 5, 20001)
    env = 0.05 - 0.004 * t
    x = env * np.sin(2 * np.pi * t)
    mx = positive_maxima(t, x)
    assert mx.time.size == 5
    # exact maxima: roots of d/dt[(a - b t) sin(2 pi t)] near t = k + 1/4
    def slope(s):
        return -0.004 * np.sin(2 * np.pi * s) + (0.05 - 0.004 * s) * 2 * np.pi * np.cos(2 * np.pi * s)

    tk = np.array([brentq(slope, k, k + 0.5) for k in range(5)])
    xk = (0.05 - 0.004 * tk) * np.sin(2 * np.pi * tk)
    np.testing.assert_allclose(mx.time, tk, atol=1e-6)
    np.testing.assert_allclose(mx.value, xk, rtol=1e-8)
    two = damping_inclination(mx)
    fit = envelope_inclination(mx, window_fraction=0.1)
    np.testing.assert_allclose(two.value, (xk[0] - xk[1]) / (tk[1] - tk[0]), rtol=1e-6)
    np.testing.assert_allclose(fit.value, -np.polyfit(tk, xk, 1)[0], rtol=1e-6)
    assert fit.n_maxima == 5 and fit.method == "envelope-fit"


def test_a_kink_inside_an_excursion_is_not_a_maximum():
    t = np.linspace(0, 1, 1001)
    x = np.sin(2 * np.pi * t) * np.where(t < 0.3, 1.0, 0.5)  # a sudden drop (an impact)
    assert positive_maxima(t, x).time.size == 1


def test_envelope_window_and_settling_time():
    tm = np.arange(10.0)
    xm = 1.0 * 0.5**tm  # 1, 0.5, 0.25, 0.125, 0.0625, 0.031 ...
    mx = Maxima(tm, xm)
    fit = envelope_inclination(mx, window_fraction=0.2)
    assert fit.n_maxima == 3 and fit.t_stop == 2.0
    np.testing.assert_allclose(fit.value, -np.polyfit(tm[:3], xm[:3], 1)[0])
    assert settling_time(mx, 0.05) == 5.0  # 0.031 < 0.05 from t = 5 on
    assert math.isnan(settling_time(Maxima(tm, np.ones(10)), 0.05))
    with pytest.raises(ParameterError, match="window_fraction"):
        envelope_inclination(mx, window_fraction=1.5)


def test_free_response_matches_the_oscillator_equation():
    model = TABLE1
    t = np.linspace(0, 1, 100001)
    x = free_response(t, model)
    # residual of M x'' + C x' + K x = 0 by finite differences
    h = t[1] - t[0]
    xd = np.gradient(x, h)
    xdd = np.gradient(xd, h)
    res = model.M * xdd + model.C * xd + model.K * x
    assert np.max(np.abs(res[5:-5])) < 1e-5 * model.K * np.max(np.abs(x))
    assert x[0] == 0 and (x[1] - x[0]) / h == pytest.approx(2.0, rel=1e-4)
    # over- and critically damped branches start the same way
    for c in (2 * math.sqrt(model.K * model.M), 100.0):
        xx = free_response(t[:3], DamperModel(C=c), InitialState(x=0.01, v=0.0))
        assert xx[0] == pytest.approx(0.01)


def test_damper_reduces_the_maxima_faster_than_the_dashpot_alone():
    t = sample_times(4.0)
    r = simulate(TABLE1, 4.0, t_eval=t)
    with_damper = envelope_inclination(positive_maxima(r.t, r.x))
    without = envelope_inclination(positive_maxima(t, free_response(t)))
    # dashpot alone: x_max falls as exp(-C t / 2M); eq 16 gives X1 (1 - exp(-C T / 2M)) / T
    a = TABLE1.C / (2 * TABLE1.M)
    wd = math.sqrt(TABLE1.main_frequency**2 - a * a)
    period = 2 * math.pi / wd
    x1 = 2 / wd * math.exp(-a * math.atan(wd / a) / wd)
    two = damping_inclination(positive_maxima(t, free_response(t)))
    np.testing.assert_allclose(two.value, x1 * (1 - math.exp(-a * period)) / period, rtol=1e-4)
    assert with_damper.value > 1.5 * without.value


def test_restitution_rises_with_impact_mass_and_speed():
    masses = np.array([0.01, 0.04, 0.1])
    speeds = np.array([0.5, 2.0])
    e = restitution_curve(masses, speeds)
    assert e.shape == (3, 2)
    assert np.all(np.diff(e, axis=0) > 0) and np.all(np.diff(e, axis=1) > 0)
    np.testing.assert_allclose(
        e[1, 1], contact.restitution(2.0, TABLE1.k_hertz, 0.04, TABLE1.M, TABLE1.c1), rtol=1e-12
    )


def test_damping_metrics_bundles_the_three_definitions():
    import numpy as np

    from acoustiviz.dynamics.metrics import (
        damping_inclination,
        damping_metrics,
        envelope_inclination,
        positive_maxima,
        settling_time,
    )

    t = np.linspace(0.0, 10.0, 20001)
    x = np.exp(-0.4 * t) * np.sin(2 * np.pi * t)  # decays below 5 % of the first maximum by t ~ 7.5 s
    got = damping_metrics(t, x, window_fraction=0.4, settling_fraction=0.05)
    mx = positive_maxima(t, x)
    assert got.two_maxima == damping_inclination(mx)
    assert got.fit == envelope_inclination(mx, 0.4)
    assert got.settling_time == settling_time(mx, 0.05)
    assert 7.0 < got.settling_time < 8.5
