"""Closed-form forced flights: work and dissipation, contact onset, the scan's table of trial times.

The kernels are checked against an independent numerical integration of the main mass
``M x'' + C x' + K x = P cos ωt + Q sin ωt`` (SciPy, tight tolerances).
"""

import math

import numpy as np
import pytest
from numba import njit
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from acoustiviz.dynamics._flight import (
    _MEMO_SLOTS,
    _gaps,
    _memo_new,
    _remember,
    _trial,
    flight_coeffs,
    flight_energy,
    scan_forced,
)

M, K, C = 1.0, 1000.0, 2.0  # kg, N/m, N s/m: the main oscillator
OMEGA = 2 * math.pi * 5.0  # rad/s
#: Relative agreement of the closed forms with the SciPy integration (rtol 1e-12).
ODE_RTOL = 1e-9
#: Agreement in s of a contact onset with the SciPy reference.
ONSET_TOL = 1e-9


def _forcing(p, q):
    """Forcing vector ``[ω, P, Q, A_c, A_s]`` with the particular solution solved here."""
    s = K - M * OMEGA**2
    ac, as_ = np.linalg.solve([[s, C * OMEGA], [-C * OMEGA, s]], [p, q])
    return np.array([OMEGA, p, q, ac, as_])


@njit
def _energy(t0, x, v, y, w, a, wd, fc, hg, tau, cdamp):
    c = flight_coeffs(t0, x, v, y, w, a, wd, fc, hg)
    return flight_energy(c, tau, fc, cdamp)


@njit
def _scan(t0, x, v, y, w, a, wd, fc, hg, tau_end):
    c = flight_coeffs(t0, x, v, y, w, a, wd, fc, hg)
    return scan_forced(c, tau_end)


@njit
def _table(t0, x, v, y, w, a, wd, fc, hg, tau, tau_next):
    """Store marker values at ``tau`` and read ``tau`` and ``tau_next`` back (module ``_trial``)."""
    c = flight_coeffs(t0, x, v, y, w, a, wd, fc, hg)
    memo = _memo_new()
    bits = memo.view(np.uint64)
    first = _trial(tau, c, memo, bits)
    _remember(memo, first[4], tau, 1.0, 2.0, 3.0, 4.0)  # not the flight's values: they show where a value came from
    again = _trial(tau, c, memo, bits)
    _remember(memo, _trial(tau_next, c, memo, bits)[4], tau, 1.0, 2.0, 3.0, 4.0)
    near = _trial(tau_next, c, memo, bits)
    return first, again, near, _gaps(tau, c), _gaps(tau_next, c)


def _oscillator():
    a = C / (2 * M)
    return a, math.sqrt(K / M - a * a)


def _reference(t0, x0, v0, fc, tau):
    """SciPy integration of x, v, the work of F and the energy dissipated by C over ``[t0, t0 + tau]``."""
    om, p, q = fc[0], fc[1], fc[2]

    def rhs(t, s):
        f = p * math.cos(om * t) + q * math.sin(om * t)
        return [s[1], (f - C * s[1] - K * s[0]) / M, f * s[1], C * s[1] ** 2]

    return solve_ivp(rhs, (t0, t0 + tau), [x0, v0, 0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-15,
                     dense_output=True)


@pytest.mark.parametrize("p,q", [(5.0, 0.0), (3.0, -4.0), (0.0, 0.0)])
def test_flight_energy_matches_an_independent_integration(p, q):
    """Work of F and dissipation by C over a flight of several forcing quarter periods (and none without force)."""
    fc = _forcing(p, q)
    a, wd = _oscillator()
    t0, x0, v0, tau = 0.37, 2e-3, -0.05, 0.31
    work, diss = _energy(t0, x0, v0, 0.0, 0.0, a, wd, fc, 0.02, tau, C)
    ref = _reference(t0, x0, v0, fc, tau)
    assert ref.success
    scale = max(abs(ref.y[2, -1]), ref.y[3, -1])
    assert work == pytest.approx(ref.y[2, -1], abs=ODE_RTOL * scale)
    assert diss == pytest.approx(ref.y[3, -1], rel=ODE_RTOL)
    if p == q == 0.0:
        assert work == 0.0


def test_forced_scan_finds_the_first_of_two_nearby_wall_crossings():
    """A slow impact mass drifting towards wall +1 while the forced main mass oscillates: its gap dips below
    zero twice in a row (a long run of halved steps near the wall); the scan returns the first crossing."""
    fc = _forcing(5.0, 0.0)
    a, wd = _oscillator()
    t0, x0, v0, hg, tau_end = 0.1, 0.0, 0.0, 0.02, 0.4
    ref = _reference(t0, x0, v0, fc, tau_end)
    times = np.linspace(0.0, tau_end, 400_001)
    xs = ref.sol(t0 + times)[0]
    w = 0.01  # m/s, the impact mass's drift
    # start it where the gap d/2 - z (z = y - x) just closes at the deepest point of the first dip
    k = np.argmin(hg - (w * times - xs)[: times.size // 2])
    y0 = hg - (w * times[k] - xs[k]) + 1e-7
    gap = hg - (y0 + w * times - xs)
    first = np.flatnonzero(gap <= 0.0)[0]
    onset = brentq(lambda s: hg - (y0 + w * s - ref.sol(t0 + s)[0]), times[first - 1], times[first], xtol=1e-15)
    found, tau, wall = _scan(t0, x0, v0, y0, w, a, wd, fc, hg, tau_end)
    assert found and wall == 1.0
    assert tau == pytest.approx(onset, abs=ONSET_TOL)


def test_scan_table_gives_back_values_only_for_the_same_time():
    """A rejected trial time read again comes from the table; the next float after it is evaluated."""
    fc = _forcing(5.0, 1.0)
    a, wd = _oscillator()
    tau = 0.0123
    tau_next = np.nextafter(tau, 1.0)
    first, again, near, g, g_next = _table(0.2, 1e-3, 0.01, 0.0, 0.02, a, wd, fc, 0.02, tau, tau_next)
    assert first[:4] == g  # an empty table: evaluated
    assert again == (1.0, 2.0, 3.0, 4.0, first[4])  # from the table
    assert near[:4] == g_next  # not the same time: evaluated, whatever its slot holds
    for slot in (first[4], near[4]):
        assert 0 <= slot < 5 * _MEMO_SLOTS and slot % 5 == 0
