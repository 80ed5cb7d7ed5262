"""Figures of the impact-damper dynamics.

Free vibration (paper Figure 5), restitution (Figure 7), and the speed-versus-accuracy chart.

Each function takes ``ax=None`` and returns the Axes; styling is local (no global rcParams).
"""

from __future__ import annotations

import numpy as np

from .style import new_axes, style

__all__ = ["plot_free_vibration", "plot_restitution", "plot_speed_accuracy", "plot_impacts_followed"]

_MARKERS = {"newmark": "s", "event": "o", "impact-map": "^"}


def _solvers(rows):
    out = []
    for r in rows:
        if r["solver"] not in out:
            out.append(r["solver"])
    return out


def plot_free_vibration(result, ax=None, *, without=True, impacts=True):
    """Main-mass displacement x(t) with the damper and, optionally, without it (Figure 5).

    Parameters
    ----------
    result : acoustiviz.dynamics.SimulationResult
        A run with dense output (``t_eval``); x is drawn in cm against t in s.
    ax : matplotlib Axes, optional
    without : bool
        Also draw the main oscillator alone (impact mass removed, closed form).
    impacts : bool
        Mark the contact start times along the top of the axes.

    Returns
    -------
    matplotlib Axes
    """
    from ...dynamics.metrics import free_response

    with style():
        ax = new_axes(ax, figsize=(7.5, 4.0))
        t = np.asarray(result.t)
        if without:
            x0 = free_response(t, result.model, result.initial)
            ax.plot(t, 100 * x0, color="0.65", lw=0.8, label="without impact damper")
        ax.plot(t, 100 * np.asarray(result.x), color="C0", lw=0.8,
                label=f"with impact damper ({result.solver})")
        if impacts and len(result.impacts):
            top = 100 * max(np.max(np.abs(result.x)), 1e-12) * 1.12
            ax.plot(result.impacts.time, np.full(len(result.impacts), top), "|", color="C3",
                    ms=5, label=f"impacts ({len(result.impacts)})")
        ax.set_xlabel("time t (s)")
        ax.set_ylabel("main-mass displacement x (cm)")
        mdl = result.model
        ax.set_title(
            f"Free vibration: M = {mdl.M:g} kg, m = {1000 * mdl.m:g} g, d = {100 * mdl.gap:g} cm, "
            f"dx/dt(0) = {result.initial.v:g} m/s"
        )
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncols=3, fontsize=8)
    return ax


def plot_restitution(masses, velocities, restitution, ax=None, *, clip_tensile=False):
    """Restitution versus impact mass, one curve per approach speed (paper Figure 7).

    Parameters
    ----------
    masses : (n,) array_like
        Impact masses in kg (drawn in g).
    velocities : (k,) array_like
        Approach speeds in m/s.
    restitution : (n, k) array_like
        Coefficient of restitution (dimensionless).
    ax : matplotlib Axes, optional
    clip_tensile : bool
        Only labels the title with the contact-force form used.

    Returns
    -------
    matplotlib Axes
    """
    m = np.asarray(masses, dtype=float)
    u = np.asarray(velocities, dtype=float)
    e = np.asarray(restitution, dtype=float).reshape(m.size, u.size)
    with style():
        ax = new_axes(ax)
        for j, uj in enumerate(u):
            ax.plot(1000 * m, e[:, j], marker="o", ms=3, label=f"U0 = {uj:g} m/s")
        ax.set_xlabel("impact mass m (g)")
        ax.set_ylabel("coefficient of restitution e (–)")
        form = "force clipped at zero" if clip_tensile else "paper's force (may pull)"
        ax.set_title(f"Restitution of the damped Hertz contact, {form}")
        ax.legend(fontsize=8)
    return ax


def plot_speed_accuracy(rows, ax=None, *, goal=None):
    """Error over the first impacts against solver run time, one marker series per solver.

    Parameters
    ----------
    rows : sequence of mapping
        Each with ``solver`` (str), ``label`` (str, the setting), ``time_s`` (run time in s) and
        ``error`` (max relative error of the approach speeds, dimensionless).
    ax : matplotlib Axes, optional
    goal : tuple of float, optional
        ``(time_s, error)`` of the goal, drawn as dashed lines.

    Returns
    -------
    matplotlib Axes
    """
    with style():
        ax = new_axes(ax, figsize=(7.0, 4.5))
        for i, s in enumerate(_solvers(rows)):
            sel = [r for r in rows if r["solver"] == s]
            tt = [r["time_s"] for r in sel]
            ee = [max(r["error"], 1e-17) for r in sel]
            ax.plot(tt, ee, marker=_MARKERS.get(s, "D"), ls="-", color=f"C{i}", label=s)
            below = s == "impact-map"
            for k, (r, t_, e_) in enumerate(zip(sel, tt, ee, strict=True)):
                dy = -10 - 9 * k if below else 3
                ax.annotate(r["label"], (t_, e_), textcoords="offset points", xytext=(4, dy),
                            fontsize=7, color=f"C{i}")
        if goal is not None:
            ax.axvline(goal[0], ls="--", color="0.5", lw=0.8)
            ax.axhline(goal[1], ls="--", color="0.5", lw=0.8)
            ax.annotate(f"goal: < {1000 * goal[0]:g} ms, error < {goal[1]:g}", (goal[0], goal[1]),
                        textcoords="offset points", xytext=(4, -12), fontsize=8, color="0.4")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("solver run time (s), warm")
        ax.set_ylabel("max relative error of approach speed,\nfirst 40 impacts (–)")
        ax.set_title("Impact damper, Table 1, 20 s of motion: error against run time")
        ax.legend(fontsize=8)
    return ax


def plot_impacts_followed(rows, ax=None, *, n_compare=40):
    """Leading impacts each solver setting reproduces (within 1e-3) against its run time.

    Parameters
    ----------
    rows : sequence of mapping
        Each with ``solver``, ``label``, ``time_s`` (run time in s) and ``n_agree`` (number of
        leading impacts on the same wall with approach speed within 1e-3 of the reference).
    ax : matplotlib Axes, optional
    n_compare : int
        Number of impacts compared (drawn as a dashed line).

    Returns
    -------
    matplotlib Axes
    """
    with style():
        ax = new_axes(ax, figsize=(7.0, 3.5))
        for i, s in enumerate(_solvers(rows)):
            sel = [r for r in rows if r["solver"] == s]
            ax.plot([r["time_s"] for r in sel], [r["n_agree"] for r in sel],
                    marker=_MARKERS.get(s, "D"), ls="-", color=f"C{i}", label=s)
        ax.axhline(n_compare, ls="--", color="0.5", lw=0.8)
        ax.set_xscale("log")
        ax.set_ylim(0, n_compare * 1.1)
        ax.set_xlabel("solver run time (s), warm")
        ax.set_ylabel("leading impacts within 1e-3 (–)")
        ax.set_title("How long each setting follows the reference")
        ax.legend(fontsize=8, loc="center right")
    return ax
