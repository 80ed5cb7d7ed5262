"""Interactive 3-D views as self-contained HTML pages: no server, no network, one file.

Each page draws a value computed beforehand by the physics layer (a
:class:`~acoustiviz.field.sections.SectionField` or a :class:`~acoustiviz.field.balloon.BalloonData`)
and evaluates nothing itself. Each page embeds its meshes (base64 float32 arrays), a colour map and a small WebGL viewer
(``_viewer.js``, about 200 lines, inlined): drag to rotate, wheel to zoom, double-click to
reset the view, and a slider through the times of a snapshot series. It opens in any browser
with WebGL from a local file or as an e-mail attachment.

* :func:`write_balloon_html` -- the directivity balloon of :func:`acoustiviz.output.render.render_balloon`
  (same surface, colours and scale), with the sphere and the planes;
* :func:`write_snapshot_html` -- the pressure on the planar sections of
  :func:`acoustiviz.output.render.render_snapshot`, one slider step per time, one colour scale.

Lengths in m, pressures in Pa, levels in dB re 20 µPa.
"""

from __future__ import annotations

import base64
import html as _html
import json
from pathlib import Path

import numpy as np

from .._validate import ParameterError, check_positive, check_range
from ..core.geometry import Geometry
from ..field.balloon import BalloonData
from ..files import write_text_atomic

__all__ = ["page", "write_balloon_html", "write_snapshot_html"]

_SPHERE = "#b8bcc2"
_FLOOR = "#c9b89a"
_WALL = "#9fb3c8"


def _b64(array, dtype) -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).astype(dtype).tobytes()).decode("ascii")


def _lut(cmap: str) -> str:
    from matplotlib import colormaps

    rgb = (255 * colormaps[cmap](np.linspace(0.0, 1.0, 256))[:, :3]).round()
    return _b64(rgb, np.uint8)


def _layer(points, indices, *, kind="triangles", color=None, scalars=None, normals=None, opacity=1.0,
           lit=False) -> dict:
    """One layer of the page: triangles (m, 3) or segments (m, 2) over points (n, 3) in m."""
    layer = {"kind": kind, "positions": _b64(points, "<f4"), "indices": _b64(indices, "<u4"),
             "opacity": float(opacity), "lit": bool(lit), "color": color}
    if normals is not None:
        layer["normals"] = _b64(normals, "<f4")
    if scalars is not None:
        layer["scalars"] = [_b64(s, "<f4") for s in np.atleast_2d(scalars)]
    return layer


def _triangles(mesh) -> np.ndarray:
    tri = mesh.triangulate()
    return np.asarray(tri.faces).reshape(-1, 4)[:, 1:]


def _sphere_layer(geometry: Geometry) -> dict:
    import pyvista as pv

    s = pv.Sphere(radius=geometry.radius, center=geometry.centre, theta_resolution=40, phi_resolution=24)
    s = s.compute_normals(point_normals=True, cell_normals=False)
    return _layer(s.points, _triangles(s), color=_SPHERE, normals=s.point_data["Normals"], lit=True)


def _plane_layers(geometry: Geometry, bounds, opacity: float) -> list:
    """The floor and the wall as semi-transparent rectangles filling ``bounds`` ((2, 3), m), with outlines."""
    lo, hi = np.asarray(bounds, dtype=float)
    out = []
    for p in geometry.planes:
        k = int(np.argmax(np.abs(p.normal)))
        i, j = [a for a in range(3) if a != k]
        c = np.empty((4, 3))
        c[:, k] = p.point[k]
        c[:, i] = [lo[i], hi[i], hi[i], lo[i]]
        c[:, j] = [lo[j], lo[j], hi[j], hi[j]]
        colour = _FLOOR if k == 2 else _WALL
        out.append(_layer(c, [[0, 1, 2], [0, 2, 3]], color=colour, opacity=opacity))
        out.append(_layer(c, [[0, 1], [1, 2], [2, 3], [3, 0]], kind="lines", color="#6b6b6b"))
    return out


_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="acoustiviz">
<title>{title}</title>
<style>
  html, body {{ margin: 0; height: 100%; font-family: system-ui, sans-serif; background: #fff; color: #111; }}
  header {{ position: absolute; top: 0; left: 0; right: 0; padding: 8px 14px; pointer-events: none; }}
  header h1 {{ font-size: 17px; margin: 0 0 2px 0; font-weight: 600; }}
  header p {{ font-size: 13px; margin: 0; color: #333; }}
  #view {{ position: absolute; top: 0; left: 0; width: 100%; height: 100%; display: block; cursor: grab; }}
  #bar {{ position: absolute; right: 12px; top: 50%; transform: translateY(-50%); text-align: left; }}
  #colourbar-title {{ font-size: 13px; max-width: 140px; margin-bottom: 4px; }}
  #controls {{ position: absolute; left: 14px; bottom: 10px; font-size: 13px; color: #333; }}
  #controls input {{ width: 260px; vertical-align: middle; }}
  #frame-label {{ font-weight: 600; margin-left: 8px; }}
  #nogl {{ display: none; position: absolute; top: 45%; width: 100%; text-align: center; font-size: 16px; }}
  #status {{ display: none; }}
</style>
</head>
<body>
<canvas id="view"></canvas>
<header><h1>{title}</h1><p>{subtitle}</p></header>
<div id="bar"><div id="colourbar-title"></div><canvas id="colourbar" width="90" height="300"></canvas></div>
<div id="controls"><input id="frame" type="range" min="0" max="0" value="0" step="1"><span
 id="frame-label"></span><br>drag to rotate, wheel to zoom, double-click to reset</div>
<div id="nogl">This view needs a browser with WebGL.</div>
<p id="status">loading</p>
<script type="application/json" id="scene-data">{data}</script>
<script>
{viewer}
</script>
</body>
</html>
"""


def page(layers, *, title: str, subtitle: str = "", colorbar: str = "", clim=(0.0, 1.0), cmap: str = "viridis",
         frame_labels=("",), target=(0.0, 0.0, 0.0), radius: float = 1.0, direction=(0.9, -1.7, 0.8)) -> str:
    """The HTML text of a self-contained interactive page showing ``layers``.

    Parameters
    ----------
    layers : list of dict
        Meshes made by ``_layer``: points in m, triangles or segments, a fixed colour or one
        scalar array per frame (mapped through ``cmap`` over ``clim``; NaN drawn grey).
    title, subtitle : str
        Heading and the line under it.
    colorbar : str
        Colour-bar title with its unit (empty: no colour bar).
    clim : (float, float)
        Scalar range of the colour map, in the scalars' unit.
    cmap : str
        Matplotlib colour map name.
    frame_labels : sequence of str
        One label per frame; a slider appears when there are several.
    target : (3,) array_like
        Point in m the camera orbits.
    radius : float
        Size in m of the scene; the camera starts 2.6 radii from ``target``.
    direction : (3,) array_like
        Direction from ``target`` to the camera at the start (z is up).

    Returns
    -------
    str
    """
    from matplotlib.colors import to_rgb

    scene = {"layers": layers, "lut": _lut(cmap), "clim": [float(clim[0]), float(clim[1])],
             "nan_color": list(to_rgb(_SPHERE)), "colorbar": colorbar, "frame_labels": list(frame_labels),
             "target": [float(x) for x in target], "radius": float(radius),
             "direction": [float(x) for x in direction]}
    data = json.dumps(scene, separators=(",", ":")).replace("</", "<\\/")
    viewer = (Path(__file__).with_name("_viewer.js")).read_text(encoding="utf-8")
    return _TEMPLATE.format(title=_html.escape(title), subtitle=_html.escape(subtitle), data=data, viewer=viewer)


def _check_html_path(path) -> Path:
    p = Path(path)
    if p.suffix.lower() not in (".html", ".htm"):
        raise ParameterError("path", f"expected a file name ending in .html, got {str(path)!r}")
    return p


def write_balloon_html(data, pulse, geometry: Geometry, path, *, db_range: float = 30.0, opacity: float = 0.85,
                       balloon_size=None, title=None) -> Path:
    """Write an interactive page of a directivity balloon (see :func:`acoustiviz.output.render.render_balloon`).

    Parameters
    ----------
    data : acoustiviz.field.balloon.BalloonData
        The levels computed by :func:`acoustiviz.field.balloon.balloon_data`.
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (named in the subtitle).
    geometry : acoustiviz.core.geometry.Geometry
        The scene of ``data``.
    path : path-like
        Output ``.html`` file (written atomically).
    db_range : float
        Range in dB from the balloon's centre to its largest radius, in (0, 200].
    opacity : float
        Opacity of the balloon in (0, 1].
    balloon_size : float, optional
        Largest balloon radius in m (default six sphere radii, at least 1.5 × the wall distance).
    title : str, optional
        Heading of the page.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from .render._common import _scene_extent, _scene_label
    from .render.balloon import _balloon_mesh

    path = _check_html_path(path)
    rng = check_range("db_range", db_range, 0.0, 200.0, unit="dB", low_open=True)
    opacity = check_range("opacity", opacity, 0.0, 1.0, low_open=True)
    if not isinstance(data, BalloonData):
        raise ParameterError("data", f"expected a BalloonData, got {type(data).__name__}")
    if balloon_size is None:
        bsize = max(6.0 * geometry.radius, 1.5 * geometry.feature_distance)
    else:
        bsize = check_positive("balloon_size", balloon_size, "m")
    top = data.max_level
    mesh = _balloon_mesh(data, bsize, top, rng).compute_normals(point_normals=True, cell_normals=False,
                                                                 auto_orient_normals=False)
    layers = [_layer(mesh.points, _triangles(mesh), scalars=mesh.point_data["level"],
                     normals=mesh.point_data["Normals"], opacity=opacity, lit=True), _sphere_layer(geometry)]
    x0, x1, y0, y1, z0, z1 = _scene_extent(geometry, 1.05 * bsize)
    layers += _plane_layers(geometry, [[x0, y0, z0], [x1, y1, z1]], 0.35)
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2])
    head = title or f"{data.label.split(' (')[0]} at {data.distance:g} m, {rng:g} dB from centre to rim"
    sub = _scene_label(pulse, geometry) + f"; max {data.max_level:.1f} dB, energy mean {data.mean_level:.1f} dB"
    text = page(layers, title=head, subtitle=sub, colorbar=data.label, clim=(top - rng, top), cmap="viridis",
                target=centre, radius=0.5 * float(np.linalg.norm([x1 - x0, y1 - y0, z1 - z0])),
                direction=(0.9, -1.7, 0.8) if geometry.planes else (0.9, -1.7, 0.4))
    return write_text_atomic(path, text)


def write_snapshot_html(field, pulse, geometry: Geometry, path, *, clim=None, title=None, cmap: str = "RdBu_r") -> Path:
    """Write an interactive page of the pressure on planar sections at one or more times.

    The points and values are those :func:`acoustiviz.output.render.render_snapshot` draws from the
    same ``field``; several times share one colour scale and a slider.

    Parameters
    ----------
    field : acoustiviz.field.sections.SectionField
        The pressure evaluated by :func:`acoustiviz.field.sections.section_field`.
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (named in the subtitle).
    geometry : acoustiviz.core.geometry.Geometry
        The scene of ``field``.
    path : path-like
        Output ``.html`` file (written atomically).
    clim : float, optional
        Colour limit in Pa; the map spans ``[-clim, clim]`` (default as for the render).
    title : str, optional
        Heading of the page.
    cmap : str
        A diverging colour map, centred on zero.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from .render._common import _scene_label
    from .render.snapshot import _check_field, _symmetric_limit
    from .vtk import _bounds, _quads

    path = _check_html_path(path)
    field = _check_field(field)
    grids, times, fields = field.grids, field.times, field.pressures
    lim = _symmetric_limit(fields) if clim is None else check_positive("clim", clim, "Pa")
    layers = []
    for g, f in zip(grids, fields, strict=True):
        q = _quads(g.n_u, g.n_v)
        layers.append(_layer(g.points, np.vstack([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]), scalars=f))
        corners = g.origin + np.array([[0, 0], [1, 0], [1, 1], [0, 1]]) @ np.vstack([g.u, g.v])
        layers.append(_layer(corners, [[0, 1], [1, 2], [2, 3], [3, 0]], kind="lines", color="#505050"))
    layers.append(_sphere_layer(geometry))
    box = _bounds(geometry, np.vstack([g.points for g in grids]))
    layers += _plane_layers(geometry, box, 0.25)
    labels = [f"t = {t * 1e3:.3f} ms" for t in times]
    text = page(layers, title=title or "Sound pressure p(x, t)", subtitle=_scene_label(pulse, geometry),
                colorbar="sound pressure (Pa)", clim=(-lim, lim), cmap=cmap, frame_labels=labels,
                target=box.mean(axis=0), radius=0.5 * float(np.linalg.norm(box[1] - box[0])),
                direction=(0.35, -1.0, 0.35))
    return write_text_atomic(path, text)
