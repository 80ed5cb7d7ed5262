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
        cm._rhs_into(y, prm, None, cm.forcing_at(None, 0.0), 1.0, work, np.int64(1))
        f0 = work[1].copy()
        for _ in range(400):
            cm._dop_step(y, f0, sigma / 400, prm, None, cm.forcing_at(None, 0.0), 1.0, kst, ytmp, ynew, fnew)
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
        fab = cm.forcing_at(fc, 0.3)
        cm._rhs_into(y, prm, fc, fab, -1.0, work, np.int64(1))
        f0 = work[1].copy()
        exact = cm._d2fds2(y, f0, prm, fc, fab, -1.0)
        g = np.zeros(4)
        ynew, fnew, ytmp = np.zeros(n), np.zeros(n), np.zeros(n)
        for k, h in enumerate((-2.0 * d, -d, d, 2.0 * d)):
            cm._dop_step(y, f0, h, prm, fc, fab, -1.0, kst, ytmp, ynew, fnew)
            g[k] = cm._dfds(ynew, fnew, prm)
        return exact, (g[0] - 8.0 * g[1] + 8.0 * g[2] - g[3]) / (12.0 * d)

    p = kernel_params(DamperModel(c1=40.0))
    fc = np.array([2.0 * math.pi * 5.0, 5.0, -3.0]) if forced else None
    y = np.array([1e-4, 2e-3, 0.3, math.sqrt(3e-5), 0.4, 0.0, 0.0, 0.0] + ([0.0] if forced else []))
    exact, fd = derivatives(p, fc, y, 1e-4)
    assert exact == pytest.approx(fd, rel=1e-7)


def test_phase_polynomials_are_within_an_ulp_of_the_library_cosine_and_sine():
    numba = pytest.importorskip("numba")
    from acoustiviz.dynamics import _contact as cm

    @numba.njit
    def cos_sin(theta):
        c, s = np.empty_like(theta), np.empty_like(theta)
        for i in range(theta.shape[0]):
            c[i], s[i] = cm.phase_cos_sin(theta[i])
        return c, s

    tmax = cm.THETA_MAX
    inside = np.concatenate([np.linspace(-tmax, tmax, 20001), np.geomspace(1e-300, tmax, 2001),
                             -np.geomspace(1e-12, tmax, 501)])
    c, s = cos_sin(inside)
    ulps_c = np.abs(c - np.cos(inside)) / np.spacing(np.abs(np.cos(inside)))
    ulps_s = np.abs(s - np.sin(inside)) / np.spacing(np.abs(np.sin(inside)))
    assert ulps_c.max() <= 1.0
    assert ulps_s.max() <= 1.0
    # beyond the polynomials' range the library's functions themselves, whatever the phase
    beyond = np.array([np.nextafter(tmax, 1.0), -np.nextafter(tmax, 1.0), 0.5, -3.0, 1e4])
    c, s = cos_sin(beyond)
    assert np.array_equal(c, np.cos(beyond))
    assert np.array_equal(s, np.sin(beyond))


#: (ω rad/s, P N, Q N, onset s, wall, x m, v m/s, sqrt of the penetration m^0.5, its rate m/s): the paper's
#: forcing, a forcing comparable with the contact force, and a fast one whose phase passes THETA_MAX
#: within the contact.
FORCED_CONTACTS = [(2 * math.pi * 5, 3.0, -4.0, 0.37, 1.0, 1e-3, 0.2, 0.0, 1.5),
                   (2 * math.pi * 5, 300.0, 200.0, 12.91, -1.0, -2e-3, -0.1, 0.0, 0.8),
                   (2 * math.pi * 400, 300.0, -500.0, 3.3, 1.0, 1e-3, 0.3, 0.0, 0.05)]
#: The contact's tolerance in the comparison, and the agreement wanted with the reference at rtol 1e-13.
CONTACT_RTOL = 1e-12
REFERENCE_RTOL = 100 * CONTACT_RTOL


def _reference_contact(model, fc, tc, sw, x, v, xi, u):
    # SciPy's DOP853 on the same equations in the regularised time, the force from the library's
    # cosine and sine at the physical time, until xi = 0 (located on the dense output, polished by Newton)
    from scipy.integrate import solve_ivp

    M, K, C, m, kh, c1 = model.M, model.K, model.C, model.m, model.k_hertz, model.c1
    w, p, q = fc

    def rhs(_, y):
        t, x, v, xi, u = y[:5]
        fe = kh * xi**3
        fcn = fe + c1 * u
        force = p * math.cos(w * (tc + t)) + q * math.sin(w * (tc + t))
        spring = K * x + C * v - force
        return np.array([xi, xi * v, xi * (sw * fcn - spring) / M, 0.5 * u,
                         xi * (-fcn / m - fcn / M + sw * spring / M), xi * fcn, xi * (fcn - fe) * u, xi * C * v * v,
                         xi * force * v])

    def parted(_, y):
        return y[3]

    parted.terminal, parted.direction = True, -1
    y0 = [0.0, x, v, xi, u, 0.0, 0.0, 0.0, 0.0]
    end = solve_ivp(rhs, (0.0, 1.0), y0, method="DOP853", rtol=1e-13, atol=1e-20, events=parted).t_events[0][0]
    y = solve_ivp(rhs, (0.0, end), y0, method="DOP853", rtol=1e-13, atol=1e-20).y[:, -1]
    for _ in range(2):
        d = rhs(0.0, y)
        y = y - d * (y[3] / d[3])
    return y


@pytest.mark.parametrize("case", FORCED_CONTACTS)
def test_forced_contact_matches_an_independent_integration(case):
    numba = pytest.importorskip("numba")
    from acoustiviz.dynamics import _contact as cm
    from acoustiviz.dynamics._records import ContactStart, as_params

    @numba.njit
    def run(p, fc, tc, sw, x, v, xi, u, rtol):
        work = np.zeros((cm.N_WORK_ROWS, cm.NY + 1))
        kst = np.zeros((cm.N_STAGE_ROWS, cm.NY + 1))
        r = cm.contact(as_params(p), fc, ContactStart(tc, sw, x, v, xi, u), math.inf, rtol, None, np.int64(0), None,
                       0.0, 0.0, work, kst, None, None)
        return r.ended, r.y.copy()

    model = DamperModel()
    w, p, q, tc, sw, x, v, xi, u = case
    fc = np.array([w, p, q])
    ended, y = run(kernel_params(model), fc, tc, sw, x, v, xi, u, CONTACT_RTOL)
    ref = _reference_contact(model, (w, p, q), tc, sw, x, v, xi, u)
    assert ended
    # duration, main-mass state, separation rate, impulse and work of the forcing
    for i in (0, 1, 2, 4, 5, 8):
        assert y[i] == pytest.approx(ref[i], rel=REFERENCE_RTOL)
