"""Level maps: peak SPL and SEL of one impact over a plane, side by side (``acoustiviz map``)."""

from __future__ import annotations

import math

import numpy as np

from ..._validate import ParameterError
from .style import style

__all__ = ["plot_level_map", "level_map_figure", "pressure_map_figure", "DB_RANGE"]

#: Widest range in dB of a colour scale: from the 0.5th to the 99.5th percentile of the map (the
#: few points next to the sphere saturate instead of washing out the rest), at most this wide.
DB_RANGE = 60.0
_AXIS = {"x": 0, "y": 1, "z": 2}
_WALL = dict(facecolor="0.75", hatch="///", edgecolor="0.35", lw=0.8, zorder=3)
_LABEL = dict(fontsize=8, zorder=5, bbox=dict(facecolor="white", alpha=0.7, lw=0, pad=1.0))


def _limits(values) -> tuple:
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return 0.0, 1.0
    top = float(np.percentile(v, 99.5))
    low = max(float(np.percentile(v, 0.5)), top - DB_RANGE)
    return (low, top) if top > low else (top - 1.0, top + 1.0)


def _draw_geometry(ax, geometry, axes_names, offset: float, box) -> None:
    """The sphere's section and the reflecting planes seen edge-on (hatched), in the map's coordinates."""
    from matplotlib.patches import Circle, Rectangle

    i, j = (_AXIS[a] for a in axes_names)
    k = 3 - i - j
    c = np.asarray(geometry.centre, dtype=float)
    d = offset - c[k]
    if abs(d) < geometry.radius:
        r = math.sqrt(geometry.radius**2 - d * d)
        ax.add_patch(Circle((c[i], c[j]), r, facecolor="0.45", edgecolor="k", lw=0.8, zorder=4))
    x0, x1, y0, y1 = box
    band = 0.04 * max(x1 - x0, y1 - y0)
    ext = {(i, 1): 0.0, (i, -1): 0.0, (j, 1): 0.0, (j, -1): 0.0}  # room for the bands beyond the box
    for p in geometry.planes:
        n = int(np.argmax(np.abs(p.normal)))
        at = float(p.point[n])
        up = 1 if p.normal[n] > 0 else -1  # the fluid lies above (+1) or below (-1) the plane on its axis
        lo_, hi_ = (x0, x1) if n == i else (y0, y1)
        if n in (i, j) and not lo_ - 1e-9 * (hi_ - lo_) <= at <= hi_ + 1e-9 * (hi_ - lo_):
            continue  # a room's wall beyond the map
        if n == i:  # a plane across the horizontal axis: a vertical band on its solid side
            ax.add_patch(Rectangle((at - band if up > 0 else at, y0 - band), band, y1 - y0 + 2 * band, clip_on=False,
                                   **_WALL))
            ax.text(at + up * 0.01 * (x1 - x0), y1 - 0.02 * (y1 - y0), p.label, rotation=90,
                    ha="left" if up > 0 else "right", va="top", **_LABEL)
            ext[(i, up)] = band
        elif n == j:  # a plane across the vertical axis: a horizontal band on its solid side
            ax.add_patch(Rectangle((x0 - band, at - band if up > 0 else at), x1 - x0 + 2 * band, band, clip_on=False,
                                   **_WALL))
            ax.text(x1 - 0.02 * (x1 - x0), at + up * 0.01 * (y1 - y0), p.label, ha="right",
                    va="bottom" if up > 0 else "top", **_LABEL)
            ext[(j, up)] = band
    ax.set_xlim(x0 - ext[(i, 1)], x1 + ext[(i, -1)])
    ax.set_ylim(y0 - ext[(j, 1)], y1 + ext[(j, -1)])


def _check_axes_names(axes_names) -> None:
    """Refuse map directions other than ``("x", "z")`` (vertical) and ``("x", "y")`` (horizontal)."""
    if tuple(axes_names) not in (("x", "z"), ("x", "y")):
        raise ParameterError("axes_names", f"must be ('x', 'z') or ('x', 'y'), got {axes_names!r}")


def _extent(grid, axes_names) -> tuple:
    """``(left, right, bottom, top)`` in m of a planar grid seen along ``axes_names``."""
    i, j = (_AXIS[a] for a in axes_names)
    x0, y0 = float(grid.origin[i]), float(grid.origin[j])
    return x0, x0 + float(grid.u[i]), y0, y0 + float(grid.v[j])


def _dress_map(ax, im, grid, geometry, axes_names, box, label: str) -> None:
    """Around a map's image ``im``: the sphere and planes in the grid's plane, equal axes in m, a colour bar."""
    i, j = (_AXIS[a] for a in axes_names)
    _draw_geometry(ax, geometry, axes_names, float(grid.points[0, 3 - i - j]), box)
    ax.set_aspect("equal")
    ax.grid(False)
    ax.set_xlabel(f"{axes_names[0]} (m)")
    ax.set_ylabel(f"{axes_names[1]} (m)")
    cb = ax.figure.colorbar(im, ax=ax, shrink=0.85, extend="both")
    cb.set_label(label)


def plot_level_map(grid, values, geometry, *, axes_names=("x", "z"), label: str = "level (dB)", cmap: str = "magma",
                   ax=None, contours: float = 10.0):
    """Draw a level in dB over a planar grid, with the sphere and the reflecting planes.

    Parameters
    ----------
    grid : acoustiviz.field.grids.PlanarGrid
        Points in m; ``u`` along the first of ``axes_names``, ``v`` along the second.
    values : (n,) array_like
        Level in dB at the points (NaN: left blank).
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its planes, drawn in grey.
    axes_names : (str, str)
        Scene axes of the map's horizontal and vertical directions, ``("x", "z")`` or ``("x", "y")``.
    label : str
        Colour-bar label, with its unit.
    cmap : str
        Colour map.
    ax : matplotlib.axes.Axes, optional
        Where to draw (default a new figure).
    contours : float
        Spacing in dB of the labelled contour lines (0: none).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from .style import new_axes

    _check_axes_names(axes_names)
    v = np.asarray(values, dtype=float)
    if v.shape != (grid.points.shape[0],):
        raise ParameterError("values", f"expected {grid.points.shape[0]} values, got shape {v.shape}")
    ax = new_axes(ax, figsize=(6.4, 5.0))
    img = grid.image(v)
    box = _extent(grid, axes_names)
    lo, hi = _limits(v)
    im = ax.imshow(img, origin="lower", extent=box, cmap=cmap, vmin=lo, vmax=hi, interpolation="nearest")
    if contours > 0 and np.isfinite(img).sum() > 4:
        levels = np.arange(math.ceil(lo / contours) * contours, hi + 1e-9, contours)
        if levels.size:
            xs = np.linspace(box[0], box[1], grid.n_u)
            ys = np.linspace(box[2], box[3], grid.n_v)
            cs = ax.contour(xs, ys, img, levels=levels, colors="white", linewidths=0.6, alpha=0.8)
            ax.clabel(cs, fmt="%g", fontsize=7)
    _dress_map(ax, im, grid, geometry, axes_names, box, label)
    return ax


def level_map_figure(grid, peak_spl_db, sel_db, geometry, *, axes_names=("x", "z"), title: str = ""):
    """Peak SPL and SEL side by side over a planar grid.

    Parameters
    ----------
    grid : acoustiviz.field.grids.PlanarGrid
        Points in m.
    peak_spl_db, sel_db : (n,) array_like
        Peak SPL in dB re 20 µPa and SEL in dB re (20 µPa)²·s at the points (NaN: blank).
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its planes.
    axes_names : (str, str)
        ``("x", "z")`` for a vertical map, ``("x", "y")`` for a horizontal one.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    with style():
        u, v = float(np.linalg.norm(grid.u)), float(np.linalg.norm(grid.v))
        width = 12.0
        height = min(9.0, max(3.2, 0.5 * width * v / u * 0.95 + 1.0))
        fig = Figure(figsize=(width, height), layout="constrained")
        a1, a2 = fig.subplots(1, 2)
        plot_level_map(grid, peak_spl_db, geometry, axes_names=axes_names, ax=a1,
                       label="peak SPL (dB re 20 µPa)")
        a1.set_title("peak sound pressure level")
        plot_level_map(grid, sel_db, geometry, axes_names=axes_names, ax=a2, cmap="viridis",
                       label="SEL (dB re (20 µPa)²·s)")
        a2.set_title("sound exposure level")
        if title:
            fig.suptitle(title)
    return fig


def pressure_map_figure(grid, pressure, geometry, *, axes_names=("x", "z"), title: str = ""):
    """The sound pressure over a planar grid at one instant, a diverging colour scale symmetric about 0 Pa.

    Parameters
    ----------
    grid : acoustiviz.field.grids.PlanarGrid
        Points in m; ``u`` along the first of ``axes_names``, ``v`` along the second.
    pressure : (n,) array_like
        Pressure in Pa at the points (NaN: left blank).
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its planes, drawn in grey.
    axes_names : (str, str)
        ``("x", "z")`` for a vertical map, ``("x", "y")`` for a horizontal one.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    _check_axes_names(axes_names)
    p = np.asarray(pressure, dtype=float)
    finite = np.abs(p[np.isfinite(p)])
    top = float(np.percentile(finite, 99.5)) if finite.size else 0.0
    top = top if top > 0 else 1.0
    with style():
        u, v = float(np.linalg.norm(grid.u)), float(np.linalg.norm(grid.v))
        fig = Figure(figsize=(6.4, min(9.0, max(3.2, 5.4 * v / u + 1.0))), layout="constrained")
        ax = fig.add_subplot()
        box = _extent(grid, axes_names)
        im = ax.imshow(grid.image(p), origin="lower", extent=box, cmap="RdBu_r", vmin=-top, vmax=top,
                       interpolation="nearest")
        _dress_map(ax, im, grid, geometry, axes_names, box, "sound pressure (Pa)")
        if title:
            ax.set_title(title, fontsize=10)
    return fig
