"""Level plots: 1/3-octave band spectra and weighted levels side by side."""

from __future__ import annotations

import numpy as np

from .style import new_axes, style

__all__ = ["plot_band_levels", "plot_weighted_levels"]


def plot_band_levels(nominal_hz, leq_db, ax=None, *, lmax_db=None, label=None, **line_kwargs):
    """Plot 1/3-octave band levels against band centre frequency.

    Parameters
    ----------
    nominal_hz : (n_bands,) array_like
        Nominal mid-band frequencies in Hz (log axis).
    leq_db : (n_bands,) array_like
        Band equivalent levels in dB re 20 µPa (steps, solid).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure is made when omitted.
    lmax_db : (n_bands,) array_like, optional
        Band maximum (F) levels in dB re 20 µPa (steps, dashed, same colour).
    label : str, optional
        Legend label.
    **line_kwargs
        Passed to :meth:`matplotlib.axes.Axes.step`.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> ax = plot_band_levels([500, 630, 800], [60.0, 62.0, 58.0], lmax_db=[70.0, 71.0, 69.0], label="x")
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('1/3-octave band centre (Hz)', 'band level (dB re 20 µPa)')
    """
    with style():
        ax = new_axes(ax)
        f = np.asarray(nominal_hz, dtype=float)
        (line,) = ax.step(f, np.asarray(leq_db, dtype=float), where="mid", label=f"{label} Leq" if label else "Leq",
                          **line_kwargs)
        if lmax_db is not None:
            ax.step(f, np.asarray(lmax_db, dtype=float), where="mid", linestyle="--", color=line.get_color(),
                    label=f"{label} LFmax" if label else "LFmax")
        ax.set_xscale("log")
        ax.set_xlabel("1/3-octave band centre (Hz)")
        ax.set_ylabel("band level (dB re 20 µPa)")
        ax.legend(fontsize=8)
    return ax


def plot_weighted_levels(names, rows, ax=None, *, columns=("lcpeak_db", "lafmax_db", "laeq_db", "sel_a_db")):
    """Grouped bars of weighted levels for several designs or listeners.

    Parameters
    ----------
    names : sequence of str
        One name per row (group of bars).
    rows : sequence of dict
        Levels in dB keyed by column (as :meth:`acoustiviz.levels.SoundLevels.rows` gives).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    columns : sequence of str
        Which levels to draw.

    Returns
    -------
    matplotlib.axes.Axes
    """
    labels = {"lzpeak_db": "LZpeak", "lcpeak_db": "LCpeak", "lafmax_db": "LAFmax", "lasmax_db": "LASmax",
              "laeq_db": "LAeq", "lzeq_db": "LZeq", "sel_db": "SEL", "sel_a_db": "SEL(A)"}
    with style():
        ax = new_axes(ax)
        x = np.arange(len(columns))
        width = 0.8 / max(len(rows), 1)
        for i, (name, row) in enumerate(zip(names, rows, strict=True)):
            vals = [row[c] for c in columns]
            bars = ax.bar(x + (i - (len(rows) - 1) / 2) * width, vals, width, label=name)
            ax.bar_label(bars, fmt="%.1f", fontsize=7)
        ax.set_xticks(x, [labels.get(c, c) for c in columns])
        ax.set_ylabel("level (dB re 20 µPa; SEL re (20 µPa)² s)")
        ax.legend(fontsize=8)
    return ax
