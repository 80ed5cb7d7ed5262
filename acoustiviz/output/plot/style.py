"""House style for acoustiviz figures, applied locally through a context manager."""

from __future__ import annotations

import contextlib

__all__ = ["style", "new_axes", "save_figure", "RC"]

#: rcParams applied inside :func:`style`; never set globally.
RC = {
    "figure.dpi": 110,
    "savefig.dpi": 150,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "font.size": 10,
    "axes.titlesize": 11,
    "legend.frameon": False,
}


@contextlib.contextmanager
def style():
    """Apply the acoustiviz rcParams inside a ``with`` block only."""
    import matplotlib as mpl

    with mpl.rc_context(RC):
        yield


def new_axes(ax=None, *, polar: bool = False, figsize=(6.4, 4.0)):
    """Return ``ax`` or a new Axes on a new Figure (Agg canvas, no pyplot state)."""
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot(projection="polar" if polar else None)


def save_figure(fig, path):
    """Save ``fig`` to ``path`` atomically (write a temporary file, then rename); return the path."""
    from pathlib import Path

    from ..writers import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png")
    return path
