"""Cheap radiation models: their proven bounds hold, they converge, and the tolerance picks them."""

import numpy as np
import pytest

from acoustiviz import field
from acoustiviz.core import approximations as ap
from acoustiviz.core.contact import HalfSinePulse, Impact, acceleration_pulse
from acoustiviz.core.geometry import images_plane
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import pressure, radiation_coefficients

A = 0.01905


@pytest.mark.parametrize("l_tau", [None, 0.5, 5.0, 50.0, 500.0], ids=["hertz", "ltau0.5", "ltau5", "ltau50", "ltau500"])
def test_bounds_hold(l_tau, hertz_pulse):
    # the paper's Hertz pulse, and half-sines of length l_tau in units of a/c
    pulse = hertz_pulse if l_tau is None else HalfSinePulse(amplitude=1e4, duration=l_tau * A / AIR.c)
    for r in (A, 2 * A, 0.1, 0.7, 10.0):
        for ct in (1.0, -0.3):
            t = np.linspace(0, (r - A) / AIR.c + pulse.duration + 30 * A / AIR.c, 30001)
            ex = pressure(pulse, t, r, ct, radius=A)
            p0, cc = radiation_coefficients(r, ct, radius=A)
            near = np.max(np.abs(ex - ap.near_field_pressure(pulse, t, r, ct, radius=A)))
            far = np.max(np.abs(ex - ap.far_field_pressure(pulse, t, r, ct, radius=A)))
            assert near <= ap.near_field_bound(pulse, p0, cc, radius=A) * (1 + 1e-9)
            assert far <= ap.far_field_bound(pulse, p0, cc, radius=A) * (1 + 1e-9)


def test_limits_of_a_compact_sphere():
    """Long pulses (l τ >> 1): near field exact as r -> a, far field exact as kr -> ∞."""
    pulse = HalfSinePulse(amplitude=1e4, duration=2000 * A / AIR.c)
    t_near = np.linspace(0, pulse.duration * 1.2, 20001)
    ex = pressure(pulse, t_near, 1.5 * A, 1.0, radius=A)
    nf = ap.near_field_pressure(pulse, t_near, 1.5 * A, 1.0, radius=A)
    assert np.max(np.abs(ex - nf)) < 5e-3 * np.max(np.abs(ex))
    r = 100 * AIR.c * pulse.duration  # kr ~ 300
    t = np.linspace(0, (r - A) / AIR.c + pulse.duration * 1.2, 20001)
    ex = pressure(pulse, t, r, 1.0, radius=A)
    ff = ap.far_field_pressure(pulse, t, r, 1.0, radius=A)
    # away from the two kinks of the half-sine the dipole formula holds to O(1/(l τ))
    tr = t - (r - A) / AIR.c
    away = (tr > 0.05 * pulse.duration) & (tr < 0.95 * pulse.duration)
    assert np.max(np.abs(ex - ff)[away]) < 1e-2 * np.max(np.abs(ex))


def test_convolution_converges_at_second_order():
    pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=0.2259), "half-sine")
    t = np.linspace(1.9e-3, 3e-3, 500)
    ex = pressure(pulse, t, 0.7, 0.7, radius=A)
    errs = [
        np.max(np.abs(ap.convolution_pressure(pulse, t, 0.7, 0.7, radius=A, step=h) - ex)) for h in (2e-6, 1e-6, 5e-7)
    ]
    assert errs[0] / errs[1] == pytest.approx(4, rel=0.25)
    assert errs[1] / errs[2] == pytest.approx(4, rel=0.25)


def test_tolerance_picks_models_within_the_bound():
    a = 1e-3
    cfg = images_plane(a)
    pulse = HalfSinePulse(amplitude=1e3, duration=5e-3)  # l τ = 1700: a compact sphere
    r = np.geomspace(2.5e-3, 1.0, 40)
    pts = np.c_[0.6 * r, np.zeros_like(r), a + 0.8 * r]
    exact = field.field_metrics(pulse, pts, cfg, sample_interval=2e-6)
    tol = 1e-3 * float(np.max(exact.peak))
    got = field.field_metrics(pulse, pts, cfg, sample_interval=2e-6, tolerance=tol)
    names = got.model_name
    assert "near-field" in names and "exact" in names
    assert set(names) <= set(ap.MODELS)
    slack = 1e-9 * float(np.max(exact.peak))  # the exact evaluator's tail cutoff
    assert np.all(np.abs(got.peak - exact.peak) <= tol + slack)
    assert np.all(np.abs(got.rms - exact.rms) <= tol + slack)
    # every cheap pick is justified by its bound
    delay, p0, cc, _ = field.source_geometry(pts, cfg)
    bound = np.sum(ap.near_field_bound(pulse, p0, cc, radius=a), axis=1)
    assert np.all(bound[names == "near-field"] <= tol)
    assert np.all(bound[names == "exact"] > tol)
