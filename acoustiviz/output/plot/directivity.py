"""Polar plots of directivity: peak SPL and RMS pressure versus polar angle (paper Figure 3)."""

from __future__ import annotations

import numpy as np

from .style import new_axes, style

__all__ = ["plot_directivity", "directivity_figure", "half_space_axes", "levels_polar_figure"]

_QUANTITIES = {
    "spl": ("spl_db", "peak SPL (dB re 20 µPa)"),
    "rms": ("rms", "RMS pressure (Pa)"),
    "peak": ("peak", "peak pressure max|p| (Pa)"),
}


def plot_directivity(directivity, quantity: str = "spl", ax=None, *, label=None, mirror: bool = False, **kw):
    """Draw a directivity on polar axes, 0° along the acceleration axis.

    Parameters
    ----------
    directivity : acoustiviz.field.Directivity
        The result of :func:`acoustiviz.field.directivity`.
    quantity : {"spl", "rms", "peak"}
        Peak SPL in dB re 20 µPa, RMS pressure in Pa, or max |p| in Pa.
    ax : matplotlib.projections.polar.PolarAxes, optional
        Polar axes to draw on; new ones are made when omitted.
    label : str, optional
        Legend label.
    mirror : bool
        Also draw the curve mirrored to negative angles (the field is axisymmetric).
    **kw
        Passed to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.projections.polar.PolarAxes
        The axes drawn on; the radial unit is written in the title.
    """
    from ..._validate import check_choice

    check_choice("quantity", quantity, tuple(_QUANTITIES))
    attr, unit_label = _QUANTITIES[quantity]
    th = np.asarray(directivity.angle, dtype=float)
    val = np.asarray(getattr(directivity, attr), dtype=float)
    with style():
        ax = new_axes(ax, polar=True, figsize=(5.0, 4.6))
        (line,) = ax.plot(th, val, marker="o", ms=3, label=label, **kw)
        if mirror:
            ax.plot(-th, val, color=line.get_color(), ls="--", lw=0.8)
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)
        lo = float(np.nanmin(val))
        hi = float(np.nanmax(val))
        if quantity == "spl":
            ax.set_rlim(max(lo - 10.0, 0.0) if np.isfinite(lo) else 0.0, hi + 3.0)
        else:
            ax.set_rlim(0.0, hi * 1.08 if hi > 0 else 1.0)
        ax.set_title(f"{unit_label} vs angle from the acceleration axis (deg)", fontsize=9)
        ax.set_xlabel(f"radial axis: {unit_label}", fontsize=8)
        if label:
            ax.legend(loc="upper right", bbox_to_anchor=(1.08, 1.02), fontsize=8)
    return ax


def half_space_axes(fig, axes=None) -> None:
    """Cut the polar axes of ``fig`` (or ``axes``) to 0-90°, the half space, with room made for their labels.

    A polar axes cut to a quarter moves its radial tick labels to its 0° edge only when it is drawn;
    a constrained layout run before that takes them where a full circle has them, inside the disc,
    and leaves them no room at the figure's edge or beside the next panel (they were clipped or
    overlapped). One draw without rendering puts them in place, so the layout that follows, when
    the figure is saved, makes room for them.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (with a layout engine, typically constrained).
    axes : sequence of PolarAxes, optional
        The axes to cut (default: every axes of ``fig``).
    """
    for ax in fig.axes if axes is None else axes:
        ax.set_thetamin(0)
        ax.set_thetamax(90)
    fig.draw_without_rendering()


def directivity_figure(directivity, *, title: str = "", half_space: bool = True):
    """Paper Figure 3 as one figure: peak SPL (A) and RMS pressure (B) against angle, polar.

    Parameters
    ----------
    directivity : acoustiviz.field.Directivity
        Peaks and RMS against polar angle.
    title : str
        Figure title.
    half_space : bool
        Show only 0-90° (the half space above a plane or the corner's side); False shows 0-180°.

    Returns
    -------
    matplotlib.figure.Figure
        A figure with two polar axes (not attached to pyplot).
    """
    from matplotlib.figure import Figure

    with style():
        fig = Figure(figsize=(9.5, 4.8), layout="constrained")
        axes = [fig.add_subplot(1, 2, k, projection="polar") for k in (1, 2)]
        plot_directivity(directivity, "spl", ax=axes[0])
        plot_directivity(directivity, "rms", ax=axes[1])
        if title:
            fig.suptitle(title, fontsize=10)
        if half_space:
            half_space_axes(fig)
        else:  # a first draw places the polar labels, so the layout at saving makes room for them (matplotlib 3.10)
            fig.draw_without_rendering()
    return fig


def levels_polar_figure(angle, levels: dict, *, title: str = ""):
    """Levels in dB against the signed angle from the acceleration axis, one line each, on polar axes.

    Parameters
    ----------
    angle : (n,) array_like
        Angles in rad from the acceleration axis (0 up, positive clockwise).
    levels : dict
        Legend label -> (n,) levels in dB (NaN: not drawn).
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        A figure with one polar axes (not attached to pyplot).
    """
    from matplotlib.figure import Figure

    th = np.asarray(angle, dtype=float)
    with style():
        fig = Figure(figsize=(5.6, 5.0), layout="constrained")
        ax = fig.add_subplot(projection="polar")
        for label, values in levels.items():
            ax.plot(th, np.asarray(values, dtype=float), marker="o", ms=3, label=label)
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)
        every = np.concatenate([np.asarray(v, dtype=float) for v in levels.values()])
        every = every[np.isfinite(every)]
        if every.size:
            ax.set_rlim(max(float(every.min()) - 10.0, 0.0), float(every.max()) + 3.0)
        ax.set_thetamin(float(np.degrees(th.min())))
        ax.set_thetamax(float(np.degrees(th.max())))
        ax.set_title("level (dB) vs angle from the acceleration axis (deg)", fontsize=9)
        ax.legend(loc="upper right", bbox_to_anchor=(1.12, 1.05), fontsize=8)
        if title:
            fig.suptitle(title, fontsize=10)
        fig.draw_without_rendering()
    return fig
