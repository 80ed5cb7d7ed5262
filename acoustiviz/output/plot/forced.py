"""Figures of the damper in operation: frequency response and bifurcation diagram.

Each function takes ``ax=None`` and returns the Axes; styling is local (no global rcParams).
"""

from __future__ import annotations

import numpy as np

from ._style import new_axes, style

__all__ = ["plot_frequency_response", "plot_bifurcation"]


def _regime_colour(regime: str) -> str:
    if regime == "non-periodic":
        return "tab:red"
    if regime == "failed":
        return "0.6"
    return {"periodic-1": "tab:blue", "periodic-2": "tab:green"}.get(regime, "tab:purple")


def plot_frequency_response(response, ax=None):
    """Main-mass amplitude against forcing frequency, with and without the damper.

    Parameters
    ----------
    response : acoustiviz.dynamics.forced.FrequencyResponse
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib Axes
        Amplitude in mm (log scale) against frequency in Hz; markers coloured by regime (blue
        periodic-1, green periodic-2, purple longer periods, red non-periodic); the downward
        sweep dashed when present; frequencies with hysteresis shaded.
    """
    f = response.frequencies
    with style():
        ax = new_axes(ax, figsize=(7.0, 4.2))
        fine = np.linspace(f.min(), f.max(), 400)
        r0 = response.primary[0]
        lin = [abs(r0.excitation.at(fi).linear_response(r0.model)) for fi in fine]
        ax.plot(fine, 1e3 * np.asarray(lin), color="0.5", lw=1.2, label="without damper (linear)")
        label = {"up": "with damper, sweep up", "down": "with damper, sweep down",
                 "both": "with damper, sweep up", "independent": "with damper"}[response.sweep]
        ax.plot(f, 1e3 * response.amplitude, color="k", lw=1.0, label=label)
        for fi, r in zip(f, response.primary, strict=True):
            ax.plot(fi, 1e3 * r.amplitude, "o", ms=5, color=_regime_colour(r.regime))
        if response.down is not None:
            down = np.array([r.amplitude for r in response.down])
            ax.plot(f, 1e3 * down, "--", color="k", lw=1.0, label="with damper, sweep down")
            for fi, r in zip(f, response.down, strict=True):
                ax.plot(fi, 1e3 * r.amplitude, "s", ms=4, mfc="none", color=_regime_colour(r.regime))
            df = np.min(np.diff(f)) / 2 if f.size > 1 else 0.05
            for fi, h in zip(f, response.hysteresis, strict=True):
                if h:
                    ax.axvspan(fi - df / 2, fi + df / 2, color="orange", alpha=0.2, lw=0)
        regimes = {r.regime for r in response.primary + (response.down or ())}
        for reg in ("periodic-1", "periodic-2", "periodic-n (n > 2)", "non-periodic") + (
                ("failed",) if "failed" in regimes else ()):
            ax.plot([], [], "o", color=_regime_colour(reg), label=reg)
        ax.set_yscale("log")
        ax.set_xlabel("forcing frequency (Hz)")
        ax.set_ylabel("main-mass amplitude (mm)")
        ax.legend(fontsize=8, ncol=2)
    return ax


def plot_bifurcation(response, ax=None, which: str = "primary"):
    """Poincaré displacement of the main mass (at forcing phase 0) against frequency.

    Parameters
    ----------
    response : acoustiviz.dynamics.forced.FrequencyResponse
    ax : matplotlib Axes, optional
    which : {"primary", "down"}

    Returns
    -------
    matplotlib Axes
        x in mm at t = kT against frequency in Hz: one dot for period-1 motion, n for period-n,
        a cloud for non-periodic motion. When a few points exceed 20 times the median the axis
        turns logarithmic beyond twice the median (symlog).
    """
    fs, xs = response.bifurcation_points(which)
    with style():
        ax = new_axes(ax, figsize=(7.0, 4.2))
        ax.plot(fs, 1e3 * xs, ".", ms=2.5, color="k")
        span = float(np.max(np.abs(xs), initial=0.0))
        small = float(np.median(np.abs(xs))) if xs.size else 0.0
        if small > 0 and span > 20 * small:  # a resonance dwarfs the rest: logarithmic beyond 2x median
            ax.set_yscale("symlog", linthresh=2e3 * small)
        ax.set_xlabel("forcing frequency (Hz)")
        ax.set_ylabel("x at forcing phase 0 (mm)")
    return ax
