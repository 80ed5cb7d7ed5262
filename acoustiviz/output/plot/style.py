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
    """Save ``fig`` to ``path`` atomically (write a temporary file, then rename); return the path.

    A PNG of a figure with a layout engine (constrained layout) is drawn once: the layout is
    computed at the saving resolution first, then the figure is drawn with the layout held
    (:func:`_layout_at`). ``Figure.savefig`` would draw it twice, once without rendering only to
    run the layout, and the second draw would place every artist where the first one did.
    """
    from pathlib import Path

    from ...files import atomic_path

    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or "png"
    with atomic_path(path) as tmp:
        if fmt == "png" and fig.get_layout_engine() is not None:
            with _layout_at(fig) as dpi:
                fig.savefig(tmp, format=fmt, dpi=dpi)
        else:
            fig.savefig(tmp, format=fmt)
    return path


@contextlib.contextmanager
def _layout_at(fig):
    """Run ``fig``'s layout engine at ``savefig.dpi`` on an Agg canvas and hold it; yield that dpi.

    The same renderer (Agg at the saving dpi) and the same layout call as the first draw of
    ``Figure.savefig``; inside, the figure has no layout engine, so ``savefig`` draws only once.
    The figure's dpi and layout engine are restored on exit.
    """
    import matplotlib as mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    engine, dpi0, canvas0 = fig.get_layout_engine(), fig.dpi, fig.canvas
    dpi = mpl.rcParams["savefig.dpi"]
    dpi = dpi0 if dpi == "figure" else dpi
    FigureCanvasAgg(fig)  # the canvas savefig would switch to for a PNG
    try:
        fig.dpi = dpi
        if fig.axes:  # as Figure.draw: no layout without axes, and a failed one leaves the figure as it is
            with contextlib.suppress(ValueError):
                engine.execute(fig)
        with mpl.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)  # no engine at all: "none" would leave a place-holder engine
        yield dpi
    finally:
        fig.set_layout_engine(engine)
        fig.dpi = dpi0
        fig.set_canvas(canvas0)
