"""Directivity balloons: the level of a :class:`~acoustiviz.field.balloon.BalloonData` drawn as a closed surface."""

from __future__ import annotations

import inspect
from pathlib import Path

import numpy as np

from ..._validate import ParameterError, check_positive, check_range
from ...core.reach import view_limit
from ...field.balloon import BalloonData
from ._common import (
    DEFAULT_SIZE,
    _add_bar,
    _add_geometry,
    _check_inputs,
    _check_path,
    _check_size,
    _font,
    _geometries,
    _grab,
    _plotter,
    _scene_extent,
    _scene_label,
    _set_camera,
    _write_png,
    check_backend,
)

__all__ = ["render_balloon"]


def _balloon_mesh(data: BalloonData, size: float, top: float, db_range: float):
    """PolyData of the balloon: radius ``size · clip((L - top + range)/range, 0, 1)`` in m, scalars ``level``."""
    pv = check_backend()
    frac = np.clip((np.nan_to_num(data.level, nan=-np.inf) - (top - db_range)) / db_range, 0.0, 1.0)
    pts = data.anchor + (size * frac)[..., None] * data.directions
    lev = data.level
    if data.grid.region != "sphere":  # close the surface along the floor: a row collapsed onto the anchor
        pts = np.concatenate([np.broadcast_to(data.anchor, pts[:1].shape), pts], axis=0)
        lev = np.concatenate([lev[:1], lev], axis=0)
    if data.grid.region == "quarter":  # and along the plane facing the wall
        cap = np.broadcast_to(data.anchor, pts[:, :1].shape)
        pts = np.concatenate([cap, pts, cap], axis=1)
        lev = np.concatenate([lev[:, :1], lev, lev[:, -1:]], axis=1)
    x, y, z = (pts[..., k].T[..., None] for k in range(3))
    mesh = pv.StructuredGrid(x, y, z)
    mesh.point_data["level"] = np.ascontiguousarray(lev).reshape(-1)
    # vtkDataSetSurfaceFilter: named where pyvista offers a choice of filter, the only one in older pyvista
    named = "algorithm" in inspect.signature(mesh.extract_surface).parameters
    choice = {"algorithm": "dataset_surface"} if named else {}
    surf = mesh.extract_surface(pass_pointid=False, pass_cellid=False, **choice)
    return surf.clean(tolerance=1e-9 * size)


def render_balloon(
    data,
    pulse,
    geometry,
    path,
    *,
    db_range: float = 30.0,
    size=DEFAULT_SIZE,
    balloon_size=None,
    title=None,
    show_scalar_bar: bool = True,
    cmap: str = "viridis",
    opacity: float = 0.7,
) -> Path:
    """Render a directivity balloon (or several side by side) into a PNG file.

    The balloon is centred on the contact point; in each direction its radius is
    ``balloon_size · (L - L_max + db_range)/db_range`` (clipped at zero), where ``L`` is the
    level at ``distance`` in that direction and ``L_max`` the largest level over all the
    balloons drawn, and its colour is ``L`` itself. The sphere, floor and wall are drawn to
    scale, the planes semi-transparent.

    Parameters
    ----------
    data : BalloonData or sequence of BalloonData
        The levels computed by :func:`acoustiviz.field.balloon.balloon_data`, one per configuration.
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (named in the caption).
    geometry : acoustiviz.core.geometry.Geometry or sequence of them
        The scene of ``data``; several are drawn side by side with one colour scale.
    path : path-like
        Output ``.png`` file (written atomically).
    db_range : float
        Range in dB from the balloon's centre to its largest radius, in (0, 200].
    size : (int, int)
        Image width and height in pixels.
    balloon_size : float, optional
        Largest balloon radius in m (default six sphere radii, at least 1.5 × the wall
        distance; in a room at most the distance to the walls the balloon faces), i.e. the scale of the
        drawing, not of the field.
    title : str, optional
        Text at the top left (default: the metric and the distance).
    show_scalar_bar : bool
        Draw the labelled colour bar.
    cmap : str
        Matplotlib colour map of the level.
    opacity : float
        Opacity of the balloon in (0, 1]; below 1 the sphere shows through. The balloon's
        outline in the plane ``y = 0`` (the polar pattern of ``acoustiviz directivity``) is
        drawn as a dark line.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> from acoustiviz import Impact, acceleration_pulse
    >>> from acoustiviz.core.geometry import geometry
    >>> from acoustiviz.field.balloon import balloon_data
    >>> pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=0.226), "half-sine")
    >>> corner = geometry("wall-floor", 0.01905, wall_distance=0.05)
    >>> data = balloon_data(pulse, corner, distance=0.5)  # doctest: +SKIP
    >>> render_balloon(data, pulse, corner, "balloon.png", size=(800, 600))  # doctest: +SKIP
    PosixPath('balloon.png')
    """
    path = _check_path(path, (".png",))
    size = _check_size(size)
    geometries = _geometries(geometry)
    for c in geometries:
        _check_inputs(pulse, c)
    rng = check_range("db_range", db_range, 0.0, 200.0, unit="dB", low_open=True)
    opacity = check_range("opacity", opacity, 0.0, 1.0, low_open=True)
    datas = [data] if isinstance(data, BalloonData) else list(data)
    if len(datas) != len(geometries) or not all(isinstance(d, BalloonData) for d in datas):
        raise ParameterError("data", f"expected {len(geometries)} BalloonData, one per configuration")
    top = max(d.max_level for d in datas)
    clim = (top - rng, top)
    if title is None:
        title = f"{datas[0].label.split(' (')[0]} at {datas[0].distance:g} m, {db_range:g} dB from centre to rim"
    with _plotter(size, shape=(1, len(geometries))) as pl:
        for i, (c, d) in enumerate(zip(geometries, datas, strict=True)):
            pl.subplot(0, i)
            actor = _draw_balloon(pl, pulse, c, d, top, rng, balloon_size, clim, cmap, size, len(geometries), opacity)
            if show_scalar_bar and i == len(geometries) - 1:
                _add_bar(pl, d.label, size, actor.mapper, n_views=len(geometries))
        pl.subplot(0, 0)
        pl.add_text(title, position="upper_left", font_size=_font(size, 13), color="black")
        img = _grab(pl)
    return _write_png(img, path)


def _draw_balloon(pl, pulse, geometry, data, top, rng, balloon_size, clim, cmap, size, n_views, opacity):
    a = geometry.radius
    if balloon_size is None:
        bsize = min(max(6.0 * a, 1.5 * geometry.feature_distance), view_limit(geometry))  # inside a room's walls
    else:
        bsize = check_positive("balloon_size", balloon_size, "m")
    mesh = _balloon_mesh(data, bsize, top, rng)
    actor = pl.add_mesh(mesh, scalars="level", clim=clim, cmap=cmap, smooth_shading=True, split_sharp_edges=True,
                        show_scalar_bar=False,
                        specular=0.25, nan_color="#dddddd", opacity=opacity)
    section = mesh.slice(normal="y", origin=data.anchor)  # the polar pattern in the plane y = 0
    if section.n_points:
        pl.add_mesh(section, color="#202020", line_width=max(1.0, 2.5 * size[1] / 900.0))
    bounds = _scene_extent(geometry, 1.05 * bsize)
    _add_geometry(pl, geometry, bounds)
    line = _scene_label(pulse, geometry) + f"\nmax {data.max_level:.1f} dB, energy mean {data.mean_level:.1f} dB"
    pl.add_text(line, position="lower_left", font_size=_font((size[0] / n_views, size[1]), 11), color="#222222")
    x0, x1, y0, y1, z0, z1 = bounds
    focus = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    bounded = bool(geometry.planes)  # look down on a floor; all round a sphere in free field
    direction = (0.9, -1.7, 0.8) if bounded else (0.9, -1.7, 0.4)
    _set_camera(pl, focus, direction, zoom=1.35 if bounded else 1.05)
    return actor
