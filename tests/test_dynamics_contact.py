"""The compiled contact of the impact damper: its peak force and the derivatives that locate it."""

import math

import numpy as np
import pytest

from acoustiviz.dynamics import DamperModel
from acoustiviz.dynamics._contact import free_restitution
from acoustiviz.dynamics._status import kernel_params

#: Agreement wanted of the peak force with the closed form at the contact's tolerance 1e-13.
PEAK_RTOL = 1e-12


@pytest.mark.parametrize("u0", [0.05, 0.7, 3.0])
def test_undamped_peak_force_is_the_hertz_closed_form(u0):
    # two free bodies: F_max = K alpha_max^(3/2), alpha_max = (5 m_eff U0^2 / (4 K))^(2/5) (Johnson 1985, 11.4)
    model = DamperModel(c1=0.0)
    e, _, peak = free_restitution(kernel_params(model), u0, 1e-13)
    meff = model.m * model.M / (model.m + model.M)
    amax = (5.0 * meff * u0 * u0 / (4.0 * model.k_hertz)) ** 0.4
    assert e == pytest.approx(1.0, abs=1e-11)
    assert peak == pytest.approx(model.k_hertz * amax**1.5, rel=PEAK_RTOL)


def test_damped_peak_force_is_the_largest_force_of_the_contact():
    # with damping the maximum comes before the deepest penetration: no closed form, but no force
    # found by a dense golden-section search over the contact may exceed the reported peak
    numba = pytest.importorskip("numba")
    from acoustiviz.dynamics import _contact as cm
    from acoustiviz.dynamics._records import as_params, without_main

    @numba.njit
    def force_at(p, u0, sigma):
        # the two masses alone, as the restitution kernel sees them, in 400 DOP853 steps from the onset
        prm = without_main(as_params(p))
        y = np.zeros(8)
        y[4] = u0
        work = np.zeros((8, 8))
        kst = np.zeros((13, 8))
        ynew, fnew, ytmp = np.zeros(8), np.zeros(8), np.zeros(8)
        cm._rhs_into(y, prm, None, 0.0, 1.0, work, np.int64(1))
        f0 = work[1].copy()
        for _ in range(400):
            cm._dop_step(y, f0, sigma / 400, prm, None, 0.0, 1.0, kst, ytmp, ynew, fnew)
            y[:] = ynew
            f0[:] = fnew
        return prm.k_hertz * y[3] ** 3 + prm.c1 * y[4]

    model = DamperModel(c1=40.0)
    p = kernel_params(model)
    u0 = 1.2
    _, _, peak = free_restitution(p, u0, 1e-13)
    lo, hi = 1e-4, 0.05  # sigma (s m^-0.5) around the maximum, inside the contact
    g = 0.6180339887498949
    best = 0.0
    for _ in range(80):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        fa, fb = force_at(p, u0, a), force_at(p, u0, b)
        best = max(best, fa, fb)
        if fa < fb:
            lo = a
        else:
            hi = b
    assert best == pytest.approx(peak, rel=PEAK_RTOL)


@pytest.mark.parametrize("forced", [False, True])
def test_second_derivative_of_the_force_matches_differences(forced):
    numba = pytest.importorskip("numba")
    from acoustiviz.dynamics import _contact as cm
    from acoustiviz.dynamics._records import as_params

    @numba.njit
    def derivatives(p, fc, y, d):
        prm = as_params(p)
        n = y.shape[0]
        work = np.zeros((8, n))
        kst = np.zeros((13, n))
        cm._rhs_into(y, prm, fc, 0.3, -1.0, work, np.int64(1))
        f0 = work[1].copy()
        exact = cm._d2fds2(y, f0, prm, fc, 0.3, -1.0)
        g = np.zeros(4)
        ynew, fnew, ytmp = np.zeros(n), np.zeros(n), np.zeros(n)
        for k, h in enumerate((-2.0 * d, -d, d, 2.0 * d)):
            cm._dop_step(y, f0, h, prm, fc, 0.3, -1.0, kst, ytmp, ynew, fnew)
            g[k] = cm._dfds(ynew, fnew, prm)
        return exact, (g[0] - 8.0 * g[1] + 8.0 * g[2] - g[3]) / (12.0 * d)

    p = kernel_params(DamperModel(c1=40.0))
    fc = np.array([2.0 * math.pi * 5.0, 5.0, -3.0]) if forced else None
    y = np.array([1e-4, 2e-3, 0.3, math.sqrt(3e-5), 0.4, 0.0, 0.0, 0.0] + ([0.0] if forced else []))
    exact, fd = derivatives(p, fc, y, 1e-4)
    assert exact == pytest.approx(fd, rel=1e-7)
