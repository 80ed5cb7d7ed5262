"""Field snapshots: a :class:`~acoustiviz.field.sections.SectionField` drawn on a diverging map centred on 0 Pa."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..._validate import ParameterError, check_positive
from ...core.geometry import Geometry
from ...field.grids import PlanarGrid, fluid_box
from ...field.sections import SectionField
from ._common import (
    _SPHERE_COLOUR,
    DEFAULT_SIZE,
    _add_bar,
    _add_geometry,
    _check_inputs,
    _check_path,
    _check_size,
    _font,
    _grab,
    _plotter,
    _scene_label,
    _set_camera,
    _write_png,
    check_backend,
)

__all__ = ["render_snapshot"]


# --------------------------------------------------------------------------- snapshots
def _plane_mesh(grid: PlanarGrid, values):
    mesh = grid.to_pyvista()
    mesh.point_data["p"] = np.asarray(values, dtype=float)
    return mesh


def _symmetric_limit(fields) -> float:
    """Symmetric colour limit in Pa shared by k frames.

    The median over the frames of each frame's 99.5th percentile of |p|: early frames, close
    to the sphere, saturate rather than wash out the rest. ``fields`` is a list (one per
    plane) of (k, n) arrays.
    """
    per_frame = []
    for q in range(fields[0].shape[0]):
        vals = np.abs(np.concatenate([np.ravel(f[q]) for f in fields]))
        vals = vals[np.isfinite(vals) & (vals > 0)]
        if vals.size:
            per_frame.append(float(np.percentile(vals, 99.5)))
    lim = float(np.median(per_frame)) if per_frame else 0.0
    return lim if lim > 0 else 1.0


def _snapshot_bounds(planes, geometry: Geometry):
    """Bounds (m) of the drawn floor/wall: the planes' box, flat axes widened to show the geometry."""
    pts = np.vstack([p.points for p in planes])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = float(np.max(hi - lo))
    for k in range(3):
        if hi[k] - lo[k] < 1e-9 * span:
            lo[k] -= 0.3 * span
            hi[k] += 0.3 * span
    lo, hi = fluid_box(geometry, lo, hi)
    return lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]


def _draw_snapshot(pl, geometry, planes, fields, t, clim, cmap, size, label, show_bar, n_views):
    """Draw one snapshot in the active view; return the plane meshes and the time annotation."""
    meshes = [_plane_mesh(g, f) for g, f in zip(planes, fields, strict=True)]
    actor = None
    pv = check_backend()
    for g, m in zip(planes, meshes, strict=True):
        actor = pl.add_mesh(m, scalars="p", cmap=cmap, clim=(-clim, clim), show_scalar_bar=False,
                            nan_color=_SPHERE_COLOUR, lighting=False)
        corners = g.origin + np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]) @ np.vstack([g.u, g.v])
        pl.add_mesh(pv.lines_from_points(corners), color="#505050", line_width=max(1.0, 1.5 * size[1] / 900.0))
    _add_geometry(pl, geometry, _snapshot_bounds(planes, geometry), opacity=0.25)
    vsize = (size[0] / n_views, size[1])
    clock = pl.add_text(_time_label(t), position="upper_left", font_size=_font(vsize, 18), color="black")
    if label:
        pl.add_text(label, position="lower_left", font_size=_font(vsize, 12), color="#222222")
    pts = np.vstack([p.points for p in planes])
    focus = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    normals = np.array([p.normal for p in planes])
    vertical = np.abs(normals[:, 2]) < 0.1
    if np.all(~vertical):  # horizontal planes only: look down
        direction = (0.25, -0.5, 1.0)
    elif np.sum(vertical) > 1:  # crossing vertical planes: look into the open quadrant
        direction = (0.5, -1.0, 0.45)
    else:
        direction = (0.35, -1.0, 0.35)
    # every view of a series gets the same camera, leaving room for the colour bar of the last one
    if n_views == 1:
        _set_camera(pl, focus, direction, zoom=1.3, shift=0.18 if show_bar else 0.0)
    else:
        aspect = size[0] / n_views / size[1]  # width / height of one view
        if aspect >= 1.3:
            _set_camera(pl, focus, direction, zoom=1.2, shift=0.2)
        elif aspect >= 1.0:
            _set_camera(pl, focus, direction, zoom=1.1, shift=0.3)
        else:  # tall, narrow views: the wide sections must shrink to fit their width
            _set_camera(pl, focus, direction, zoom=1.1 * aspect, shift=0.1)
    if show_bar:
        _add_bar(pl, "sound pressure (Pa)", size, actor.mapper, n_views=n_views, fmt="%.3g")
    return meshes, clock


def _check_field(field) -> SectionField:
    """``field`` if it is a :class:`SectionField`, else an error naming ``field``."""
    if not isinstance(field, SectionField):
        raise ParameterError("field", f"expected a SectionField, got {type(field).__name__}")
    return field


def _time_label(t: float) -> str:
    return f"t = {t * 1e3:.3f} ms"



def render_snapshot(
    field: SectionField,
    pulse,
    geometry: Geometry,
    path,
    *,
    size=DEFAULT_SIZE,
    clim=None,
    title=None,
    show_scalar_bar: bool = True,
    cmap: str = "RdBu_r",
) -> Path:
    """Render the pressure p(x, t) on planar grids at one or more times into a PNG file.

    Parameters
    ----------
    field : acoustiviz.field.sections.SectionField
        The pressure evaluated by :func:`acoustiviz.field.sections.section_field` on its planes at
        one or more times (at most 12); several times go side by side (up to three in a row, four
        and more on a near-square grid) with one colour scale.
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (named in the caption).
    geometry : acoustiviz.core.geometry.Geometry
        The scene of ``field``.
    path : path-like
        Output ``.png`` file (written atomically).
    size : (int, int)
        Image width and height in pixels.
    clim : float, optional
        Colour limit in Pa: the map spans ``[-clim, clim]`` (default: the median over the
        snapshots of each one's 99.5th percentile of |p|; larger values saturate).
    title : str, optional
        Text at the top left (default: the configuration and the pulse).
    show_scalar_bar : bool
        Draw the labelled colour bar.
    cmap : str
        A diverging matplotlib colour map; it is centred on zero.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> plane = geometry("plane", 0.01905)  # doctest: +SKIP
    >>> field = section_field(pulse, plane, [0.5e-3, 1e-3])  # doctest: +SKIP
    >>> render_snapshot(field, pulse, plane, "p.png")  # doctest: +SKIP
    PosixPath('p.png')
    """
    path = _check_path(path, (".png",))
    size = _check_size(size)
    _check_inputs(pulse, geometry)
    field = _check_field(field)
    grids, times, fields = field.grids, field.times, field.pressures
    lim = _symmetric_limit(fields) if clim is None else check_positive("clim", clim, "Pa")
    cols = times.size if times.size <= 3 else int(math.ceil(math.sqrt(times.size)))
    rows = int(math.ceil(times.size / cols))
    label = _scene_label(pulse, geometry) if title is None else title
    with _plotter(size, shape=(rows, cols)) as pl:
        for q, tq in enumerate(times):
            pl.subplot(q // cols, q % cols)
            _draw_snapshot(pl, geometry, grids, [f[q] for f in fields], tq, lim, cmap, (size[0], size[1] / rows),
                           label if q == 0 else None, show_scalar_bar and q == times.size - 1, cols)
        img = _grab(pl)
    return _write_png(img, path)
