"""Design maps and the design table (paper Figure 6 and Table 2).

Maps show a column of a gap × mass sweep (:class:`acoustiviz.sweep.SweepTable`) with the
impact mass in g along x and the gap in cm along y, one cell per design, and a colour bar
with units. The design-table figure draws, for each band of damping inclination, the range of
the maximum SPL of the sweep beside the paper's.
"""

from __future__ import annotations

import numpy as np

from .style import new_axes, style

__all__ = ["plot_inclination_map", "plot_spl_map", "plot_map", "plot_design_table"]


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges around sorted centres (half-way between neighbours; ±half a step at the ends)."""
    c = np.asarray(centres, dtype=float)
    if c.size == 1:
        h = 0.05 * abs(c[0]) or 0.5
        return np.array([c[0] - h, c[0] + h])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def plot_map(table, column: str, ax=None, *, scale: float = 1.0, label: str = "", cmap="viridis",
             centred: bool = False, annotate=None, fmt: str = "{:.1f}", title=None):
    """Draw one column of a gap × mass sweep as a coloured grid with a colour bar.

    Parameters
    ----------
    table : acoustiviz.sweep.SweepTable
        A sweep in which only the gap and the impact mass vary.
    column : str
        Column of ``sweep.csv`` to show.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure is made when omitted.
    scale : float
        Factor applied to the values (e.g. 100 for m/s → cm/s).
    label : str
        Colour-bar label, with the unit.
    cmap : str
        Colour map.
    centred : bool
        Centre the colour scale on zero (for signed quantities).
    annotate : bool, optional
        Write each value in its cell (default: when the grid has at most 12 × 12 cells).
    fmt : str
        Format of the annotations.
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.colors import TwoSlopeNorm

    z = table.grid(column) * scale
    gaps = np.asarray(table.spec.gap, dtype=float)
    masses = np.asarray(table.spec.masses, dtype=float)
    og, om = np.argsort(gaps), np.argsort(masses)
    z = z[np.ix_(og, om)]
    gx, mx = gaps[og] * 100.0, masses[om] * 1000.0
    with style():
        ax = new_axes(ax, figsize=(6.0, 4.6))
        norm = None
        finite = z[np.isfinite(z)]
        if centred and finite.size:
            lim = float(np.max(np.abs(finite))) or 1.0
            norm = TwoSlopeNorm(vcenter=0.0, vmin=-lim, vmax=lim)
        mesh = ax.pcolormesh(_edges(mx), _edges(gx), np.ma.masked_invalid(z), cmap=cmap, norm=norm,
                             shading="flat")
        cb = ax.figure.colorbar(mesh, ax=ax)
        cb.set_label(label)
        ax.set_xlabel("impact mass m (g)")
        ax.set_ylabel("gap d (cm)")
        ax.grid(False)
        if annotate is None:
            annotate = z.shape[0] <= 12 and z.shape[1] <= 12
        if annotate:
            lo, hi = mesh.get_clim()
            for i, g in enumerate(gx):
                for j, m in enumerate(mx):
                    v = z[i, j]
                    if not np.isfinite(v):
                        continue
                    rel = (v - lo) / (hi - lo) if hi > lo else 0.5
                    dark = rel < 0.55 if not centred else abs(rel - 0.5) > 0.3
                    ax.text(m, g, fmt.format(v), ha="center", va="center", fontsize=7,
                            color="white" if dark else "black")
        if title:
            ax.set_title(title)
    return ax


def plot_inclination_map(table, ax=None, *, definition: str = "two-maxima", **kwargs):
    """Paper Figure 6 A: damping inclination in cm/s over gap and impact mass.

    Parameters
    ----------
    table : acoustiviz.sweep.SweepTable
        A gap × mass sweep.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    definition : {"two-maxima", "fit"}
        Paper eq 16 from the first two maxima, or the envelope fit.
    **kwargs
        Passed to :func:`plot_map`.

    Returns
    -------
    matplotlib.axes.Axes
    """
    column = "inclination_two_maxima_m_s" if definition == "two-maxima" else "inclination_fit_m_s"
    what = "eq 16, first two maxima" if definition == "two-maxima" else "fit of the maxima envelope"
    kwargs.setdefault("title", f"(A) damping inclination ({what})")
    kwargs.setdefault("fmt", "{:.2f}")
    values = np.asarray(table[column], dtype=float)
    signed = bool(np.any(values[np.isfinite(values)] < 0))  # a diverging scale only when both signs occur
    return plot_map(table, column, ax, scale=100.0, label="damping inclination e (cm/s)",
                    cmap="RdBu_r" if signed else "viridis", centred=signed, **kwargs)


def plot_spl_map(table, ax=None, **kwargs):
    """Paper Figure 6 B: maximum SPL at the listener in dB over gap and impact mass.

    Parameters
    ----------
    table : acoustiviz.sweep.SweepTable
        A gap × mass sweep.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    **kwargs
        Passed to :func:`plot_map`.

    Returns
    -------
    matplotlib.axes.Axes
    """
    kwargs.setdefault("title", "(B) maximum sound pressure level at the listener")
    return plot_map(table, "max_spl_db", ax, label="max SPL (dB re 20 µPa)", cmap="magma", **kwargs)


def plot_design_table(bands, ax=None, *, paper=None, others=(), label="this sweep", title=None):
    """Paper Table 2 as a chart: per inclination band, the range of the maximum SPL.

    Parameters
    ----------
    bands : sequence of acoustiviz.sweep.Band
        The design table of a sweep (:func:`acoustiviz.sweep.design_table`).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    paper : sequence of (e in m/s, min dB, max dB, decrease dB), optional
        Reference rows to draw beside (e.g. :data:`acoustiviz.sweep.PAPER_TABLE2`).
    others : sequence of (str, sequence of Band)
        Further design tables to draw beside, with their legend labels.
    label : str
        Legend label of ``bands``.
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes
        One vertical bar per band and series, from the minimum to the maximum of the maximum
        SPL, labelled with the decrease in dB; damping inclination in cm/s along x.
    """
    series = [(label, [(b.centre, b.min_spl_db, b.max_spl_db, b.decrease_db) for b in bands])]
    series += [(lab, [(b.centre, b.min_spl_db, b.max_spl_db, b.decrease_db) for b in bs]) for lab, bs in others]
    if paper:
        series.append(("paper Table 2", [tuple(r) for r in paper]))
    colours = ["tab:blue", "tab:green", "tab:purple", "tab:red"]
    with style():
        ax = new_axes(ax, figsize=(7.0, 4.2))
        k = len(series)
        step = 0.07 / max(k, 1)
        for j, (lab, rows) in enumerate(series):
            colour = "tab:orange" if lab == "paper Table 2" else colours[j % len(colours)]
            off = (j - (k - 1) / 2) * step
            for i, (e, lo, hi, dec) in enumerate(rows):
                x = 100 * e + off
                ax.vlines(x, lo, hi, lw=5, color=colour, label=lab if i == 0 else None)
                ax.plot([x, x], [lo, hi], "_", ms=9, mew=1.5, color=colour)
                ax.text(x, hi + 0.3, f"{dec:.1f}" if lab != "paper Table 2" else f"{dec:.0f}", ha="center",
                        va="bottom", fontsize=6.5, color=colour)
        ax.set_xlabel("damping inclination e (cm/s), bands 0.1 cm/s wide")
        ax.set_ylabel("maximum SPL at the listener (dB re 20 µPa)")
        ax.legend(loc="upper right", fontsize=8)
        if title:
            ax.set_title(title)
    return ax
