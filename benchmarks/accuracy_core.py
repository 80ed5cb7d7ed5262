"""Measured errors of the Hertz contact and rigid-sphere radiation against independent references.

Run ``python benchmarks/accuracy_core.py``: one line per check, with the error measured now.
The unit tests assert bounds on the same quantities; this prints the numbers themselves.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import minimize_scalar

from acoustiviz.core.contact import (
    HERTZ_DURATION_CONSTANT,
    HalfSinePulse,
    Impact,
    SampledPulse,
    acceleration_pulse,
    hertz_pulse_shape,
)
from acoustiviz.core.geometry import images_plane
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import impulse_response, pressure, pulse_response, sphere_pressure
from acoustiviz.field import directivity, field_metrics

A, R, COS = 0.01905, 0.7, math.cos(math.pi / 4)
LAM = AIR.c / A


def kernel(tp, r, ct):
    """Paper eq 11, written out."""
    return AIR.rho * AIR.c * A * A * ct / r**2 * ((1 - r / A) * math.sin(LAM * tp) + r / A * math.cos(LAM * tp)) * \
        math.exp(-LAM * tp)


def quad_pressure(pulse, tp, r, ct):
    out = np.zeros_like(tp)
    for i, x in enumerate(tp):
        hi, lo = min(x, pulse.duration), max(0.0, x - 80 / LAM)
        edges = np.linspace(lo, hi, 9)
        out[i] = sum(quad(lambda xi, x=x: kernel(x - xi, r, ct) * float(pulse.acceleration(xi)), e0, e1,
                          limit=200, epsabs=0, epsrel=1e-12)[0] for e0, e1 in zip(edges[:-1], edges[1:], strict=True))
    return out


def fd_synthesis(amp, tau, r, t):
    period = t.max() + tau + 45 / LAM
    n = int(2 ** math.ceil(math.log2(max(period / tau * 2500, 2**16))))
    w = 2 * np.pi * np.fft.fftfreq(n, d=period / n)
    k, w0 = w / AIR.c, np.pi / tau
    with np.errstate(divide="ignore", invalid="ignore"):
        spec = amp * w0 * (1 + np.exp(-1j * w * tau)) / (w0**2 - w**2)
    near = np.isclose(np.abs(w), w0, rtol=1e-9)
    spec[near] = amp * tau / 2 * np.exp(-1j * w[near] * tau / 2) / 1j * np.sign(w[near])
    tr = AIR.rho * A**3 * COS * (1 + 1j * k * r) / (r**2 * (2 * (1 + 1j * k * A) - (k * A) ** 2))
    return np.real(np.exp(1j * np.outer(t, w)) @ (tr * np.exp(-1j * k * (r - A)) * spec)) / period


def main():
    rows = []
    val, _ = quad(lambda x: 1 / math.sqrt(1 - x**2.5), 0, 1, epsabs=0, epsrel=1e-13, limit=200)
    rows.append(("Hertz constant (4/5)B(2/5,1/2) vs quadrature", abs(HERTZ_DURATION_CONSTANT / (2 * val) - 1)))
    sol = solve_ivp(lambda _t, y: (y[1], -1.25 * max(y[0], 0) ** 1.5), (0, HERTZ_DURATION_CONSTANT), (0, 1),
                    method="DOP853", rtol=1e-13, atol=1e-15, dense_output=True)
    th = np.linspace(0, HERTZ_DURATION_CONSTANT, 401)
    rows.append(("exact Hertz pulse shape vs ODE (abs, peak 1)",
                 np.abs(hertz_pulse_shape(th) - np.maximum(sol.sol(th)[0], 0) ** 1.5).max()))
    imp = Impact(2.0, 5.6e8, 0.0405, 0.5)
    sc = imp.velocity / imp.max_approach
    dv = quad(lambda t: imp.peak_acceleration * float(hertz_pulse_shape(t * sc)), 0, imp.duration,
              epsabs=0, epsrel=1e-12, limit=200)[0]
    rows.append(("exact pulse impulse vs 2 m_eff U0", abs(imp.mass * dv / imp.impulse - 1)))
    h0 = impulse_response((R - A) / AIR.c, R, COS, radius=A)
    rows.append(("h(0+) vs rho c (a/r) cos", abs(h0 / (AIR.rho * AIR.c * A / R * COS) - 1)))
    area = quad(lambda tp: kernel(tp, R, COS), 0, 60 / LAM, epsabs=0, epsrel=1e-13, limit=400)[0]
    rows.append(("int h dt vs rho a^3 cos / (2 r^2)", abs(area / (AIR.rho * A**3 * COS / (2 * R**2)) - 1)))
    tau = 2000 / LAM
    pulse = HalfSinePulse(1e3, tau)
    tp = np.linspace(0.05, 0.95, 19) * tau
    r = 2e4
    ff = pressure(pulse, tp + (r - A) / AIR.c, r, COS, radius=A)
    ref = AIR.rho * A**3 * COS / (2 * r * AIR.c) * 1e3 * math.pi / tau * np.cos(math.pi * tp / tau)
    rows.append(("far-field dipole limit (l tau = 2000, r = 2e4 m)", np.abs(ff - ref).max() / np.abs(ref).max()))
    tau, r = 1e4 / LAM, 1.5 * A
    pulse = HalfSinePulse(1e3, tau)
    tp = np.linspace(0.05, 0.95, 19) * tau
    nf = pressure(pulse, tp + (r - A) / AIR.c, r, COS, radius=A)
    ref = AIR.rho * A**3 * COS / (2 * r**2) * pulse.acceleration(tp)
    err = np.abs(nf - ref).max() / np.abs(ref).max()
    rows.append(("incompressible near-field limit (l tau = 1e4, r = 1.5 a)", err))
    for ltau in (0.01, 1.0, 100.0, 1e4):
        tau = ltau / LAM
        pulse = HalfSinePulse(1e4, tau)
        tp = np.concatenate([np.linspace(0, tau, 23)[1:], tau + np.linspace(0, 12 / LAM, 12)[1:]])
        ref = quad_pressure(pulse, tp, R, COS)
        got = pressure(pulse, tp + (R - A) / AIR.c, R, COS, radius=A)
        err = np.abs(got - ref).max() / np.abs(ref).max()
        rows.append((f"half-sine closed form vs quadrature, l tau = {ltau:g}", err))
    hz = Impact(1.4, 5.6e8, 7800 * 4 / 3 * math.pi * A**3)
    sp = acceleration_pulse(hz, "hertz")

    class Exact:
        duration = hz.duration

        @staticmethod
        def acceleration(t):
            return hz.peak_acceleration * hertz_pulse_shape(t * hz.velocity / hz.max_approach)

    tp = np.linspace(0, hz.duration + 10 / LAM, 31)[1:]
    ref = quad_pressure(Exact, tp, R, COS)
    got = pressure(sp, tp + (R - A) / AIR.c, R, COS, radius=A)
    rows.append(("exact Hertz pulse (closed form) pressure vs quadrature", np.abs(got - ref).max() / np.abs(ref).max()))
    lin = SampledPulse(sp.times, sp.acceleration_samples)  # the former default: 1025 samples, linear between
    got = pressure(lin, tp + (R - A) / AIR.c, R, COS, radius=A)
    err = np.abs(got - ref).max() / np.abs(ref).max()
    rows.append(("Hertz pulse sampled at 1025 points, linear, vs quadrature", err))
    err = abs(sp.velocity_change * hz.mass / hz.impulse - 1)
    rows.append(("exact Hertz pulse impulse (closed form) vs 2 m_eff U0 / m", err))
    s_pole = complex(-LAM, LAM)
    ends = hz.duration * np.array([1e-4, 1e-3, 0.5, 0.999, 0.9999, 1.0])
    yref = np.array([sum(quad(lambda xi, x=x, f=f: f(np.exp(s_pole * (x - xi))) * float(Exact.acceleration(xi)), 0, x,
                              limit=400, epsabs=0, epsrel=1e-13)[0] * w for f, w in ((np.real, 1), (np.imag, 1j)))
                     for x in ends])
    ypeak = np.abs(pulse_response(sp, np.linspace(0, hz.duration, 2001), radius=A)).max()
    rows.append(("exact Hertz Y at 1e-4..1 of the contact vs quadrature (of max|Y|)",
                 np.abs(pulse_response(sp, ends, radius=A) - yref).max() / ypeak))
    cfg = images_plane(A)
    angles = np.radians(np.arange(0.0, 91.0, 15.0))
    for kind in ("half-sine", "hertz"):
        pulse = acceleration_pulse(hz, kind)
        d = directivity(pulse, cfg, 0.7, angles)
        raw = field_metrics(pulse, d.points, cfg, window=d.metrics.window, refine=False)
        err_r = err_s = 0.0
        for i, x in enumerate(d.points):
            def p_at(t, x=x, pulse=pulse):
                return sum(sphere_pressure(pulse, [t], x[None, :], radius=A, centre=src.position, axis=src.axis)[0, 0]
                           for src in cfg.sources)

            tt = d.metrics.window_start[i] + np.arange(0.0, d.metrics.window, 1e-8)
            dense = sum(sphere_pressure(pulse, tt, x[None, :], radius=A, centre=src.position, axis=src.axis)[0]
                        for src in cfg.sources)
            k = int(np.argmax(np.abs(dense)))
            res = minimize_scalar(lambda t, p_at=p_at: -abs(p_at(t)), bounds=(tt[max(k - 1, 0)], tt[k + 1]),
                                  method="bounded", options={"xatol": 1e-15})
            err_r = max(err_r, abs(d.peak[i] / -res.fun - 1))
            err_s = max(err_s, abs(raw.peak[i] / -res.fun - 1))
        rows.append((f"Figure 3 peaks (0-90 deg), {kind}: refined vs 10 ns + Brent reference", err_r))
        rows.append((f"Figure 3 peaks (0-90 deg), {kind}: largest sample (former) vs same", err_s))
    for ltau, r in ((0.5, 0.7), (28.9, 0.7), (3.0, 2 * A), (300.0, 5.0)):
        tau = ltau / LAM
        t = (r - A) / AIR.c + np.linspace(-0.1 * tau, tau + 10 / LAM, 120)
        got = pressure(HalfSinePulse(1e4, tau), t, r, COS, radius=A)
        ref = fd_synthesis(1e4, tau, r, t)
        rows.append((f"waveform vs frequency-domain synthesis (eq 7/9), l tau = {ltau:g}, r = {r:g} m",
                     np.abs(got - ref).max() / np.abs(got).max()))
    width = max(len(n) for n, _ in rows)
    print(f"{'check'.ljust(width)}  relative error")
    print(f"{'-' * width}  --------------")
    for name, err in rows:
        print(f"{name.ljust(width)}  {err:.2e}")


if __name__ == "__main__":
    main()
