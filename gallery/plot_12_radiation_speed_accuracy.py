"""
Speed against accuracy of the radiation models.
===============================================

The exact closed form of paper eqs 11-13 against three cheaper models: the incompressible
near field ``ρ a³ cosθ A(t')/(2r²)``, the radiating compact dipole
``ρ a³ cosθ A'(t')/(2rc)`` and the numerical convolution of the sampled pulse with the sampled
impulse response (step ``min(τ, a/c)/64``), for a pulse of the exact Hertz shape (whose
derivative is continuous; a half-sine's kinks make the far-field formula jump by its whole
peak). The error is the largest deviation from the exact waveform divided by its peak,
over distance ``kr`` (``k = π/(cτ)``) and over the pulse length ``l τ = cτ/a`` (so
``ka = π/(lτ)``); dashed lines are the proven bounds the evaluator's ``tolerance`` uses.
The last panel is the cost per point-sample. The compact-sphere models only pay off for long
pulses (``lτ`` in the hundreds: a small bead on a soft surface) and only where a numpy
evaluation is wanted anyway; for the paper's steel sphere (``lτ ≈ 9.5``) the exact form is
needed and, run by the numba kernel, it is also the fastest.
"""

# %%
import time

import numpy as np
from _gallery import fast_mode, output_dir

from acoustiviz.core import approximations as ap
from acoustiviz.core.contact import HalfSinePulse, Impact, SampledPulse, acceleration_pulse
from acoustiviz.core.geometry import images_free
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import pressure, radiation_coefficients
from acoustiviz.field import time_series
from acoustiviz.output.plot.style import save_figure, style

A = 0.01905
C = AIR.c
N_T = 1500 if fast_mode() else 6000


HERTZ = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=0.2259), "hertz")


def hertz_shape(duration):
    """The exact Hertz pulse shape stretched to ``duration`` s, peak 1e4 m/s²."""
    acc = HERTZ.acceleration_samples
    return SampledPulse(HERTZ.times * duration / HERTZ.duration, 1e4 * acc / acc.max(), kind="hertz")


def errors(l_tau, kr):
    """Relative max errors of the three cheap models and their bounds at one (l τ, kr)."""
    tau = l_tau * A / C
    pulse = hertz_shape(tau)
    r = kr * C * tau / np.pi
    if r < 1.2 * A:  # no observer inside (or touching) the sphere
        return dict.fromkeys(["near-field", "far-field", "convolution", "near bound", "far bound"], np.nan)
    t = (r - A) / C + np.linspace(0, tau + 25 * A / C, N_T)
    ex = pressure(pulse, t, r, 1.0, radius=A)
    peak = np.max(np.abs(ex))
    p0, cc = radiation_coefficients(r, 1.0, radius=A)
    out = {
        "near-field": np.max(np.abs(ap.near_field_pressure(pulse, t, r, 1.0, radius=A) - ex)) / peak,
        "far-field": np.max(np.abs(ap.far_field_pressure(pulse, t, r, 1.0, radius=A) - ex)) / peak,
        "convolution": np.max(np.abs(ap.convolution_pressure(pulse, t, r, 1.0, radius=A) - ex)) / peak,
        "near bound": float(ap.near_field_bound(pulse, p0, cc, radius=A)) / peak,
        "far bound": float(ap.far_field_bound(pulse, p0, cc, radius=A)) / peak,
    }
    return out


kr_values = np.geomspace(0.02, 200, 9 if fast_mode() else 25)
ltau_values = np.geomspace(1, 3000, 8 if fast_mode() else 22)
by_kr = {lt: [errors(lt, kr) for kr in kr_values] for lt in (10.0, 1000.0)}
by_lt = {kr: [errors(lt, kr) for lt in ltau_values] for kr in (0.1, 30.0)}

# %% cost per point-sample (one point per row, several hundred samples each)
pulse = HalfSinePulse(amplitude=1e4, duration=10 * A / C)
n_pts = 200 if fast_mode() else 2000
r = np.linspace(0.1, 1.0, n_pts)[:, None]
t = np.linspace(0, 4e-3, 800)[None, :]
geometry = images_free(A)
pts = geometry.centre + np.c_[np.zeros(n_pts), np.zeros(n_pts), r[:, 0]]
time_series(pulse, t[0], pts[:5], geometry)  # compile


def cost(f, n):
    t0 = time.perf_counter()
    f()
    return (time.perf_counter() - t0) / n


costs = {
    "exact (numba evaluator)": cost(lambda: time_series(pulse, t[0], pts, geometry), pts.shape[0] * t.size),
    "exact (numpy closed form)": cost(lambda: pressure(pulse, t, r, 1.0, radius=A), r.size * t.size),
    "near-field": cost(lambda: ap.near_field_pressure(pulse, t, r, 1.0, radius=A), r.size * t.size),
    "far-field": cost(lambda: ap.far_field_pressure(pulse, t, r, 1.0, radius=A), r.size * t.size),
    "convolution": cost(
        lambda: [ap.convolution_pressure(pulse, t[0], float(x), 1.0, radius=A) for x in r[:40, 0]], 40 * t.size
    ),
}

# %%
from matplotlib.figure import Figure  # noqa: E402

colours = {"near-field": "C0", "far-field": "C3", "convolution": "C2"}
with style():
    fig = Figure(figsize=(13, 4.3), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(1, 3)
    for lt, ls in zip(by_kr, ("-", ":"), strict=True):
        for name, col in colours.items():
            ax1.loglog(kr_values, [e[name] for e in by_kr[lt]], ls, color=col, label=f"{name}, lτ = {lt:g}")
        ax1.loglog(kr_values, [e["near bound"] for e in by_kr[lt]], "--", color="C0", lw=0.7)
        ax1.loglog(kr_values, [e["far bound"] for e in by_kr[lt]], "--", color="C3", lw=0.7)
    ax1.set_xlabel("kr = π r / (c τ) (–)")
    ax1.set_ylabel("max |p_model − p_exact| / max |p_exact| (–)")
    ax1.set_title("(A) error against distance")
    ax1.legend(fontsize=7)
    for kr, ls in zip(by_lt, ("-", ":"), strict=True):
        for name, col in colours.items():
            ax2.loglog(ltau_values, [e[name] for e in by_lt[kr]], ls, color=col, label=f"{name}, kr = {kr:g}")
        ax2.loglog(ltau_values, [e["near bound"] for e in by_lt[kr]], "--", color="C0", lw=0.7)
        ax2.loglog(ltau_values, [e["far bound"] for e in by_lt[kr]], "--", color="C3", lw=0.7)
    ax2.set_xlabel("l τ = c τ / a,  ka = π / lτ (–)")
    ax2.set_title("(B) error against pulse length; dashed: proven bounds")
    ax2.legend(fontsize=7)
    names = list(costs)
    ax3.barh(names, [costs[k] * 1e9 for k in names], color=["C4", "C5", "C0", "C3", "C2"])
    ax3.set_xscale("log")
    ax3.set_xlabel("cost per point-sample (ns, one core)")
    ax3.set_title("(C) cost")
    for y, k in enumerate(names):
        ax3.text(costs[k] * 1e9 * 1.1, y, f"{costs[k] * 1e9:.3g} ns", va="center", fontsize=8)
    ax3.set_xlim(right=max(costs.values()) * 1e9 * 8)
    out = output_dir() / "plot_12_radiation_speed_accuracy.png"
    save_figure(fig, out)
print(f"wrote {out}")
