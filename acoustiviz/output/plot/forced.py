"""Figures of the damper in operation: frequency response, bifurcation diagram and the levels of its noise.

Each function takes ``ax=None`` and returns the Axes; styling is local (no global rcParams).
"""

from __future__ import annotations

import math

import numpy as np

from .style import new_axes, style

__all__ = ["plot_frequency_response", "plot_bifurcation", "plot_operating_levels", "shade_frequencies"]


def _regime_colour(regime: str) -> str:
    if regime in ("non-periodic", "chaotic"):
        return "tab:red"
    if regime == "quasi-periodic":
        return "tab:orange"
    if regime in ("failed", "unresolved"):
        return "0.6"
    return {"periodic-1": "tab:blue", "periodic-2": "tab:green"}.get(regime, "tab:purple")


def _plot_attractors(response, ax):
    """Every attractor of an :class:`acoustiviz.dynamics.forced.AttractorResponse` on amplitude axes (mm)."""
    entries = [e for e in response.entries() if e[2].success]
    regimes = set()
    worst: dict = {}
    for i, _, a, basin in entries:
        f = response.frequencies[i]
        regimes.add(a.regime)
        c = _regime_colour(a.regime)
        err = 1e3 * a.amplitude_std_err if not a.period else 0.0
        ax.errorbar(f, 1e3 * a.amplitude, yerr=err or None, fmt="o", ms=4 + 4 * basin, color=c,
                    mfc=c if basin > 0 else "none", capsize=2, lw=0.8)
        worst[i] = max(worst.get(i, 0.0), a.amplitude)
    idx = sorted(worst)
    ax.plot(response.frequencies[idx], [1e3 * worst[i] for i in idx], color="k", lw=1.0,
            label="with damper, largest amplitude (worst case)")
    return regimes


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
        periodic-1, green periodic-2, purple longer periods, red chaotic, orange quasi-periodic,
        grey unresolved). For an attractor response every attractor is drawn, the marker's
        size growing with its basin fraction (open: found only by continuation), non-periodic
        ones with their standard error, and the largest amplitude per frequency joined (the
        worst case); for a single sweep the downward sweep is dashed when present and the
        frequencies with hysteresis shaded.
    """
    f = response.frequencies
    with style():
        ax = new_axes(ax, figsize=(7.0, 4.2))
        fine = np.linspace(f.min(), f.max(), 400)
        attractors = hasattr(response, "per_frequency")
        r0 = response.per_frequency[0].attractors[0] if attractors else response.primary[0]
        lin = [abs(r0.excitation.at(fi).linear_response(r0.model)) for fi in fine]
        ax.plot(fine, 1e3 * np.asarray(lin), color="0.5", lw=1.2, label="without damper (linear)")
        if attractors:
            regimes = _plot_attractors(response, ax)
            for reg in sorted(regimes):
                ax.plot([], [], "o", color=_regime_colour(reg), label=reg)
            ax.plot([], [], "o", color="0.3", mfc="none", label="found only by continuation")
            ax.set_yscale("log")
            ax.set_xlabel("forcing frequency (Hz)")
            ax.set_ylabel("main-mass amplitude (mm)")
            ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
            return ax
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
            for lo, hi in _spans(f, response.hysteresis):
                ax.axvspan(lo, hi, color="orange", alpha=0.2, lw=0)
        regimes = {r.regime for r in response.primary + (response.down or ())}
        longer = any(g.startswith("periodic-") and g not in ("periodic-1", "periodic-2") for g in regimes)
        for reg, shown in (("periodic-1", "periodic-1" in regimes), ("periodic-2", "periodic-2" in regimes),
                           ("periodic-n (n > 2)", longer), ("non-periodic", "non-periodic" in regimes),
                           ("failed", "failed" in regimes)):
            if shown:  # only the regimes present
                ax.plot([], [], "o", color=_regime_colour(reg), label=reg)
        if response.down is not None and np.any(response.hysteresis):
            ax.axvspan(np.nan, np.nan, color="orange", alpha=0.2, lw=0, label="hysteresis (up and down differ)")
        ax.set_yscale("log")
        ax.set_xlabel("forcing frequency (Hz)")
        ax.set_ylabel("main-mass amplitude (mm)")
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return ax


def _spans(f: np.ndarray, mask) -> list:
    """``(lo, hi)`` spans in Hz covering the runs of ``mask``, each point widened to its neighbours' midpoints."""
    f = np.asarray(f, dtype=float)
    mask = np.asarray(mask, dtype=bool)
    if f.size == 0 or not mask.any():
        return []
    step = float(np.min(np.diff(f))) if f.size > 1 else 0.1
    edges = np.concatenate([[f[0] - step / 2], (f[1:] + f[:-1]) / 2, [f[-1] + step / 2]])
    out, i = [], 0
    while i < f.size:
        if mask[i]:
            j = i
            while j + 1 < f.size and mask[j + 1]:
                j += 1
            out.append((float(edges[i]), float(edges[j + 1])))
            i = j + 1
        else:
            i += 1
    return out


def shade_frequencies(ax, f, mask, *, color="tab:red", alpha=0.12, label=None):
    """Shade the frequencies (Hz) where ``mask`` holds as contiguous bands; return the spans."""
    spans = _spans(f, mask)
    for lo, hi in spans:
        ax.axvspan(lo, hi, color=color, alpha=alpha, lw=0)
    if label and spans:
        ax.axvspan(np.nan, np.nan, color=color, alpha=alpha, lw=0, label=label)
    return spans


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
        a cloud for non-periodic motion; the unstable periodic orbits of an attractor response as
        open red circles, those of the same period at neighbouring frequencies within 25 % of each
        other joined by dashed lines (a branch as continuation followed it). When a few points
        exceed 20 times the median the axis stays linear up to the decade above twice the median
        and turns logarithmic beyond it (symlog), the linear part given two decades' height.
    """
    attractors = hasattr(response, "per_frequency")
    fs, xs = response.bifurcation_points() if attractors else response.bifurcation_points(which)
    with style():
        ax = new_axes(ax, figsize=(7.0, 4.2))
        ax.plot(fs, 1e3 * xs, ".", ms=2.5, color="k", label="attractors" if attractors else None)
        if attractors and response.unstable:
            _unstable(response, ax)
            ax.legend(fontsize=8, loc="upper left")
        span = 1e3 * float(np.max(np.abs(xs), initial=0.0))
        small = 1e3 * float(np.median(np.abs(xs))) if xs.size else 0.0
        if small > 0 and span > 20 * small:  # a resonance dwarfs the rest: logarithmic beyond a round decade
            _symlog(ax, 10.0 ** math.ceil(math.log10(2 * small)), span)
        ax.set_xlabel("forcing frequency (Hz)")
        ax.set_ylabel("x at forcing phase 0 (mm)")
    return ax


def _unstable(response, ax):
    """Unstable periodic orbits: open circles, the same period at neighbouring frequencies dashed."""
    by = {}
    for i, u in response.unstable:
        by.setdefault(u.period, {}).setdefault(i, []).extend(u.poincare[:, 0])
    for per_f in by.values():
        for i, xs in per_f.items():
            f = response.frequencies[i]
            ax.plot(np.full(len(xs), f), 1e3 * np.asarray(xs), "o", ms=3.5, mfc="none", color="tab:red")
            nxt = per_f.get(i + 1)
            if nxt:
                for x in xs:  # each point to its nearest at the next frequency, when near (one branch)
                    y = min(nxt, key=lambda q, x=x: abs(q - x))
                    if abs(y - x) <= 0.25 * max(abs(x), abs(y)):
                        ax.plot([f, response.frequencies[i + 1]], [1e3 * x, 1e3 * y], "--", color="tab:red", lw=0.8)
    ax.plot([], [], "o--", mfc="none", color="tab:red", lw=0.8, label="unstable periodic orbits")


def _symlog(ax, lin: float, span: float) -> None:
    """Linear within ±``lin`` (in the data's unit), logarithmic beyond, ticks at 0, ±lin/2 and the decades."""
    from matplotlib.ticker import FixedLocator, FuncFormatter

    ax.set_yscale("symlog", linthresh=lin, linscale=2.0)
    top = 10.0 ** math.ceil(math.log10(span))
    decades = [lin * 10.0**k for k in range(0, int(round(math.log10(top / lin))) + 1)]
    ticks = sorted({0.0, lin / 2, -lin / 2, *decades, *(-d for d in decades)})
    ax.yaxis.set_major_locator(FixedLocator(ticks))
    ax.yaxis.set_minor_locator(FixedLocator([]))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))


def plot_operating_levels(frequencies, levels: dict, regimes=None, ax=None):
    """Weighted levels of the damper's steady click train against forcing frequency.

    Parameters
    ----------
    frequencies : (n,) array_like
        Forcing frequencies in Hz.
    levels : dict
        ``{"laeq_db": ..., "lafmax_db": ..., "lcpeak_db": ...}`` (any of them), each ``(n,)`` in
        dB re 20 µPa; ``-inf`` where nothing strikes (marked as silent), NaN where not computed.
    regimes : sequence of str, optional
        Regime per frequency; non-periodic ones are shaded (their levels are a sample).
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib Axes
    """
    f = np.asarray(frequencies, dtype=float)
    names = (("lcpeak_db", "LCpeak", "^"), ("lafmax_db", "LAFmax", "s"), ("laeq_db", "LAeq", "o"))
    uf = np.unique(f)
    with style():
        ax = new_axes(ax, figsize=(7.0, 4.2))
        finite = []
        for key, name, mk in names:
            if key in levels:
                y = np.asarray(levels[key], dtype=float)
                finite.append(y[np.isfinite(y)])
                yf = np.where(np.isfinite(y), y, np.nan)
                if uf.size == f.size:
                    ax.plot(f, yf, "-" + mk, ms=3.5, lw=1.0, label=name)
                else:  # several attractors per frequency: each a marker, the loudest joined
                    line = ax.plot(f, yf, mk, ms=3.5, label=name)[0]
                    top = [np.nanmax(np.where(f == u, yf, np.nan)) if np.any(np.isfinite(yf[f == u])) else np.nan
                           for u in uf]
                    ax.plot(uf, top, "-", lw=1.0, color=line.get_color())
        ref = next((np.asarray(levels[k], dtype=float) for k in ("laeq_db", "lafmax_db", "lcpeak_db")
                    if k in levels), np.full(f.size, np.nan))
        silent = np.isneginf(ref)
        low = min((float(v.min()) for v in finite if v.size), default=0.0)
        if silent.any():
            ax.plot(f[silent], np.full(int(silent.sum()), low - 5.0), "x", color="0.4", label="no impacts (silent)")
        if regimes is not None:
            bad = {u: False for u in uf}
            for fi, g in zip(f, regimes, strict=True):
                bad[fi] = bad[fi] or not str(g).startswith("periodic-")
            shade_frequencies(ax, uf, [bad[u] for u in uf],
                              label="non-periodic (window statistics)")
        ax.set_xlabel("forcing frequency (Hz)")
        ax.set_ylabel("level (dB re 20 µPa)")
        ax.legend(fontsize=8, ncol=2, loc="lower right")
    return ax
