"""Pressure waveform plots: pressure in Pa against time in ms."""

from __future__ import annotations

import numpy as np

from .style import new_axes, style

__all__ = ["plot_waveform"]


def plot_waveform(t, p, ax=None, *, label=None, title=None, **line_kwargs):
    """Plot a pressure time series.

    Parameters
    ----------
    t : (m,) array_like
        Times in s (shown in ms).
    p : (m,) or (k, m) array_like
        Pressure in Pa; a 2-D array draws one line per row.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure is made when omitted.
    label : str or sequence of str, optional
        Legend label(s), one per line.
    title : str, optional
        Axes title.
    **line_kwargs
        Passed to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Examples
    --------
    >>> import numpy as np
    >>> ax = plot_waveform(np.linspace(0, 1e-3, 5), np.zeros(5), label="silence")
    >>> ax.get_xlabel()
    'time (ms)'
    """
    t = np.asarray(t, dtype=float)
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if p.shape[-1] != t.size:
        from ..._validate import ParameterError

        raise ParameterError("p", f"last axis has {p.shape[-1]} samples, t has {t.size}")
    labels = [label] if label is None or isinstance(label, str) else list(label)
    if len(labels) == 1 and p.shape[0] > 1:
        labels = labels * p.shape[0] if label is None else [label] + [None] * (p.shape[0] - 1)
    with style():
        ax = new_axes(ax)
        for row, lab in zip(p, labels, strict=False):
            ax.plot(t * 1e3, row, label=lab, **line_kwargs)
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
        ax.set_xlabel("time (ms)")
        ax.set_ylabel("sound pressure (Pa)")
        if title:
            ax.set_title(title)
        if any(lab for lab in labels):
            ax.legend()
    return ax
