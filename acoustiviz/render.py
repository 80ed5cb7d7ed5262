"""Off-screen 3-D renders with pyvista: directivity balloons, field snapshots and wavefront animations.

Every render builds its own ``pyvista.Plotter(off_screen=True)``, draws, writes one file
atomically and closes the plotter in a ``finally`` block: no global pyvista state is touched,
no display or virtual X server is needed, and nothing leaks from one render to the next. If
VTK cannot open any off-screen OpenGL context a :class:`RuntimeError` says what to install.

* :func:`render_balloon` -- a directivity balloon: a surface around the contact point whose
  radius grows with the level (peak SPL, RMS level or sound exposure level) measured on a
  spherical grid (:mod:`acoustiviz.grids`) at a given distance, coloured by the same level, with
  the sphere, the floor and the wall drawn in. Free field: whole sphere; plane: half space;
  wall-floor corner: quarter space. Several configurations go side by side with one colour
  scale.
* :func:`render_snapshot` -- p(x, t) on one or more planar grids at one or more times, with a
  diverging colour map centred on zero and the time printed on the image.
* :func:`render_animation` -- the wavefront leaving the impact and reflecting, as GIF (always)
  or MP4 (when ``imageio`` and ``imageio-ffmpeg`` are installed). Each frame evaluates the field
  only at the points whose arrival window (:func:`acoustiviz.field.arrival_windows`) holds the
  frame time; the colour range is fixed over all frames.

Lengths are in m, times in s, pressures in Pa, levels in dB re 20 µPa. This module does the
drawing only; paths and argv belong to :mod:`acoustiviz.cli`.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._io import atomic_path
from ._validate import ParameterError, check_choice, check_positive, check_range
from .field import arrival_windows, field_metrics, snapshots, source_geometry
from .grids import PlanarGrid, SphericalGrid, planar_grid, spherical_grid
from .images import Configuration
from .medium import AIR, Medium

__all__ = [
    "METRICS",
    "SECTIONS",
    "DEFAULT_SIZE",
    "BalloonData",
    "balloon_data",
    "section_planes",
    "animation_times",
    "frame_fields",
    "mp4_available",
    "check_backend",
    "render_balloon",
    "render_snapshot",
    "render_animation",
]

#: Balloon metrics: name -> (FieldMetrics attribute, colour-bar title with its unit).
METRICS = {
    "peak": ("peak_spl_db", "peak SPL (dB re 20 µPa)"),
    "rms": ("rms_spl_db", "RMS level (dB re 20 µPa)"),
    "sel": ("sel_db", "SEL (dB re 20 µPa, 1 s)"),
}
#: Section planes of :func:`section_planes`: the vertical plane normal to the wall (``"xz"``),
#: the vertical plane parallel to it through the sphere (``"yz"``), the horizontal plane through
#: the sphere's centre (``"xy"``).
SECTIONS = ("xz", "yz", "xy")
#: Default image size in pixels (width, height).
DEFAULT_SIZE = (1200, 900)
#: Largest image side in pixels accepted by the renders.
MAX_SIDE = 8192
#: Smallest image side in pixels accepted by the renders.
MIN_SIDE = 64

_NO_BACKEND = (
    "no off-screen rendering back-end: VTK could not open an OpenGL context (it tries X, EGL and "
    "OSMesa in turn). On a headless machine install Mesa's EGL or OSMesa libraries (e.g. "
    "'apt-get install libegl1 libgl1' or 'libosmesa6'), or the OSMesa build of VTK "
    "('pip install vtk-osmesa'); no display or Xvfb is needed."
)
_SPHERE_COLOUR = "#b8bcc2"
_PLANE_COLOUR = "#c9b89a"
_WALL_COLOUR = "#9fb3c8"


# --------------------------------------------------------------------------- back-end
def check_backend():
    """Import pyvista, raising an actionable :class:`RuntimeError` if it or VTK is missing.

    Returns
    -------
    module
        The :mod:`pyvista` module.
    """
    try:
        import pyvista
    except ImportError as exc:  # pragma: no cover - pyvista is a dependency
        raise RuntimeError(f"3-D renders need pyvista and VTK ('pip install pyvista'): {exc}") from exc
    return pyvista


def mp4_available() -> bool:
    """True when MP4 files can be written (``imageio`` with the ``imageio-ffmpeg`` plugin)."""
    try:
        import imageio  # noqa: F401
        import imageio_ffmpeg
    except ImportError:
        return False
    try:
        imageio_ffmpeg.get_ffmpeg_exe()
    except (RuntimeError, OSError):  # pragma: no cover - broken ffmpeg install
        return False
    return True


def _check_size(size) -> tuple:
    try:
        w, h = (int(v) for v in size)
        ok = (w, h) == tuple(float(v) for v in size)
    except (TypeError, ValueError):
        raise ParameterError("size", f"expected (width, height) in pixels, got {size!r}") from None
    if not ok or not (MIN_SIDE <= w <= MAX_SIDE and MIN_SIDE <= h <= MAX_SIDE):
        raise ParameterError("size", f"width and height must be integers in [{MIN_SIDE}, {MAX_SIDE}] px, got {size!r}")
    return w, h


@contextlib.contextmanager
def _plotter(size, shape=(1, 1)):
    """Yield a fresh off-screen plotter of ``size`` pixels; always close it."""
    pv = check_backend()
    try:
        pl = pv.Plotter(off_screen=True, window_size=list(size), shape=shape, border=False)
    except Exception as exc:  # noqa: BLE001 - VTK raises assorted errors without a context
        raise RuntimeError(_NO_BACKEND) from exc
    try:
        pl.set_background("white")
        yield pl
    finally:
        pl.close()


def _grab(pl) -> np.ndarray:
    """Render and return the image (h, w, 3) uint8; a blank image means no working back-end."""
    try:
        pl.render()
        img = pl.screenshot(return_img=True)
    except Exception as exc:  # noqa: BLE001
        raise RuntimeError(_NO_BACKEND) from exc
    if img is None or img.size == 0 or int(img.max()) == int(img.min()):
        raise RuntimeError(_NO_BACKEND)
    return np.ascontiguousarray(img[..., :3])


def _write_png(img: np.ndarray, path) -> Path:
    from PIL import Image

    path = Path(path)
    with atomic_path(path) as tmp:
        Image.fromarray(img).save(tmp, format="PNG")
    return path


def _font(size, base: float = 14.0) -> int:
    """Font size in points scaled with the image height (``base`` at 900 px)."""
    return max(6, int(round(base * size[1] / 900.0)))


def _check_path(path, suffixes) -> Path:
    p = Path(path)
    if p.suffix.lower() not in suffixes:
        raise ParameterError("path", f"expected a file name ending in {' or '.join(suffixes)}, got {str(path)!r}")
    return p


def _check_inputs(pulse, config, medium):
    if not isinstance(config, Configuration):
        raise ParameterError("config", f"expected an images.Configuration, got {type(config).__name__}")
    if not isinstance(medium, Medium):
        raise ParameterError("medium", f"expected a Medium, got {type(medium).__name__}")
    if not hasattr(pulse, "duration"):
        raise ParameterError("pulse", f"expected an acceleration pulse, got {type(pulse).__name__}")


def _configs(config) -> list:
    cs = [config] if isinstance(config, Configuration) else list(config)
    if not cs or not all(isinstance(c, Configuration) for c in cs):
        raise ParameterError("config", "expected an images.Configuration or a non-empty sequence of them")
    return cs


# --------------------------------------------------------------------------- scene geometry
def _scene_extent(config: Configuration, half: float):
    """Bounds ``(x0, x1, y0, y1, z0, z1)`` in m of a cube of half-size ``half`` around the sphere, cut by the planes."""
    c = config.centre
    lo = c - half
    hi = c + half
    for p in config.planes:  # the floor bounds z, the wall bounds x
        k = int(np.argmax(np.abs(p.normal)))
        lo[k] = p.point[k]
    return lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]


def _add_geometry(pl, config: Configuration, bounds, *, opacity: float = 0.35):
    """Draw the sphere, and the floor and wall as semi-transparent rectangles spanning ``bounds`` (m)."""
    pv = check_backend()
    a = config.radius
    pl.add_mesh(pv.Sphere(radius=a, center=config.centre, theta_resolution=48, phi_resolution=32),
                color=_SPHERE_COLOUR, smooth_shading=True, specular=0.4)
    x0, x1, y0, y1, z0, z1 = bounds
    for pl_ in config.planes:
        n = pl_.normal
        if abs(n[2]) > 0.5:  # floor
            mesh = pv.Plane(center=((x0 + x1) / 2, (y0 + y1) / 2, pl_.point[2]), direction=n,
                            i_size=x1 - x0, j_size=y1 - y0)
            colour = _PLANE_COLOUR
        else:  # wall
            mesh = pv.Plane(center=(pl_.point[0], (y0 + y1) / 2, (z0 + z1) / 2), direction=n,
                            i_size=z1 - z0, j_size=y1 - y0)
            colour = _WALL_COLOUR
        pl.add_mesh(mesh, color=colour, opacity=opacity, show_edges=False, lighting=False)
        pl.add_mesh(mesh.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False),
                    color="#6b6b6b", line_width=1.5)


def _set_camera(pl, focus, direction, *, zoom: float = 1.0, shift: float = 0.0):
    """Look at ``focus`` from ``direction`` (z up), fit the scene, zoom, and move it left by ``shift``."""
    d = np.asarray(direction, dtype=float)
    d /= np.linalg.norm(d)
    pl.camera_position = [tuple(np.asarray(focus) + d), tuple(focus), (0.0, 0.0, 1.0)]
    pl.reset_camera()
    pl.camera.zoom(zoom)
    if shift:
        pl.camera.SetWindowCenter(shift, 0.0)


def _scene_label(pulse, config: Configuration) -> str:
    parts = [config.name]
    if config.name == "wall-floor":
        parts.append(f"wall at {-config.planes[1].point[0] * 1e3:.3g} mm")
    parts.append(f"a = {config.radius * 1e3:.4g} mm")
    parts.append(f"contact {pulse.duration * 1e6:.0f} µs")
    parts.append(f"{getattr(pulse, 'kind', 'sampled')} pulse")
    return ", ".join(parts)


# --------------------------------------------------------------------------- balloon
@dataclass(frozen=True)
class BalloonData:
    """Levels over a closed lattice of directions around an anchor point, for a balloon.

    Attributes
    ----------
    anchor : (3,) ndarray
        Centre of the balloon in m: the contact point (the sphere's centre in free field).
    directions : (n_t, n_p, 3) ndarray
        Unit directions of a lattice that closes the region: the quadrature grid's nodes
        padded with the poles, the rim on the planes and the seam.
    level : (n_t, n_p) ndarray
        Level in dB at ``anchor + distance * directions`` (see ``label`` for which).
    grid : SphericalGrid
        The quadrature grid (its nodes are the lattice's interior).
    grid_level : (n,) ndarray
        Level in dB at the grid's points.
    distance : float
        Radius in m at which the field was evaluated.
    metric : str
        ``"peak"``, ``"rms"`` or ``"sel"``.
    label : str
        Name and unit of the level, e.g. ``"peak SPL (dB re 20 µPa)"``.
    config_name : str
        Name of the configuration.
    """

    anchor: np.ndarray
    directions: np.ndarray
    level: np.ndarray
    grid: SphericalGrid
    grid_level: np.ndarray
    distance: float
    metric: str
    label: str
    config_name: str

    @property
    def max_level(self) -> float:
        """Largest level in dB."""
        return float(np.nanmax(self.level))

    @property
    def mean_level(self) -> float:
        """Energy average of the level over the region's solid angle, in dB.

        ``10 log10(∫ 10^(L/10) dΩ / Ω)`` with the grid's quadrature weights.
        """
        lin = np.where(np.isfinite(self.grid_level), 10.0 ** (self.grid_level / 10.0), 0.0)
        return float(10.0 * np.log10(self.grid.average(lin)))


def _region(config: Configuration):
    """Region, anchor, polar axis and azimuth origin of the balloon of ``config``."""
    if config.name == "free":
        return "sphere", config.centre, config.axis, np.array([1.0, 0.0, 0.0])
    if config.name == "plane":
        return "half", config.contact_point, config.planes[0].normal, np.array([1.0, 0.0, 0.0])
    floor, wall = config.planes
    return "quarter", config.contact_point, floor.normal, wall.normal


def _closed_lattice(grid: SphericalGrid, up, side) -> np.ndarray:
    """Directions (n_t + 2, n_p + 1 or + 2, 3) closing the grid's region for display."""
    e3 = np.asarray(up, float) / np.linalg.norm(up)
    s = np.asarray(side, float) - np.dot(side, e3) * e3
    e1 = s / np.linalg.norm(s)
    e2 = np.cross(e3, e1)
    d = grid.directions.reshape(grid.n_theta, grid.n_phi, 3)
    mu = d[:, 0, :] @ e3
    phi = np.arctan2(d[0] @ e2, d[0] @ e1)
    if grid.region == "quarter":
        phi = np.r_[-0.5 * math.pi, phi, 0.5 * math.pi]
    else:
        phi = np.r_[np.mod(phi, 2 * math.pi), 2 * math.pi]
    mu = np.r_[-1.0 if grid.region == "sphere" else 0.0, mu, 1.0]
    st = np.sqrt(np.clip(1.0 - mu * mu, 0.0, None))
    return (
        (st[:, None, None] * np.cos(phi)[None, :, None]) * e1
        + (st[:, None, None] * np.sin(phi)[None, :, None]) * e2
        + mu[:, None, None] * e3
    )


def balloon_data(
    pulse,
    config: Configuration,
    *,
    medium: Medium = AIR,
    distance: float = 0.7,
    metric: str = "peak",
    n_theta: int = 32,
) -> BalloonData:
    """Level over a sphere of directions at ``distance`` around the contact point.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Configuration
        ``"free"`` (whole sphere around the sphere's centre), ``"plane"`` (half space around
        the contact point) or ``"wall-floor"`` (quarter space around the contact point,
        bounded by the floor and the wall).
    medium : Medium
        The fluid.
    distance : float
        Radius in m of the measuring sphere; larger than the sphere's diameter.
    metric : {"peak", "rms", "sel"}
        Peak SPL, level of the RMS pressure (same window length everywhere, see
        :func:`acoustiviz.field.field_metrics`), or sound exposure level.
    n_theta : int
        Gauss-Legendre nodes in polar angle (>= 4); azimuth nodes follow
        :func:`acoustiviz.grids.spherical_grid`.

    Returns
    -------
    BalloonData
    """
    _check_inputs(pulse, config, medium)
    check_choice("metric", metric, tuple(METRICS))
    r = check_positive("distance", distance, "m")
    if r <= 2.0 * config.radius * 1.05:
        raise ParameterError("distance", f"must exceed 1.05 × the sphere's diameter ({2.1 * config.radius:g} m), "
                             f"got {r:g} m")
    if int(n_theta) != n_theta or not 4 <= n_theta <= 512:
        raise ParameterError("n_theta", f"must be an integer in [4, 512], got {n_theta!r}")
    region, anchor, up, side = _region(config)
    grid = spherical_grid(r, region=region, centre=anchor, up=up, side=side, n_theta=int(n_theta))
    dirs = _closed_lattice(grid, up, side)
    pts = anchor + r * dirs.reshape(-1, 3)
    if not np.all(config.in_fluid(pts)):
        raise ParameterError("distance", f"{r:g} m puts measuring points inside the sphere or a wall")
    attr, label = METRICS[metric]
    fm = field_metrics(pulse, np.vstack([pts, grid.points]), config, medium=medium)
    lev = np.asarray(getattr(fm, attr), dtype=float)
    n = pts.shape[0]
    return BalloonData(np.asarray(anchor, float), dirs, lev[:n].reshape(dirs.shape[:2]), grid, lev[n:], r,
                       metric, label, config.name)


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
    surf = mesh.extract_surface(pass_pointid=False, pass_cellid=False, algorithm="dataset_surface")
    return surf.clean(tolerance=1e-9 * size)


def render_balloon(
    pulse,
    config,
    path,
    *,
    medium: Medium = AIR,
    distance: float = 0.7,
    metric: str = "peak",
    db_range: float = 30.0,
    n_theta: int = 32,
    size=DEFAULT_SIZE,
    balloon_size=None,
    title=None,
    show_scalar_bar: bool = True,
    cmap: str = "viridis",
    opacity: float = 0.7,
    data=None,
) -> Path:
    """Render a directivity balloon (or several side by side) into a PNG file.

    The balloon is centred on the contact point; in each direction its radius is
    ``balloon_size · (L - L_max + db_range)/db_range`` (clipped at zero), where ``L`` is the
    level at ``distance`` in that direction and ``L_max`` the largest level over all the
    balloons drawn, and its colour is ``L`` itself. The sphere, floor and wall are drawn to
    scale, the planes semi-transparent.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Configuration or sequence of Configuration
        The scene; several are drawn side by side with one colour scale.
    path : path-like
        Output ``.png`` file (written atomically).
    medium : Medium
        The fluid.
    distance : float
        Radius in m of the measuring sphere around the contact point.
    metric : {"peak", "rms", "sel"}
        Level drawn (see :func:`balloon_data`).
    db_range : float
        Range in dB from the balloon's centre to its largest radius, in (0, 200].
    n_theta : int
        Polar resolution of the measuring grid.
    size : (int, int)
        Image width and height in pixels.
    balloon_size : float, optional
        Largest balloon radius in m (default six sphere radii, at least 1.5 × the wall
        distance), i.e. the scale of the drawing, not of the field.
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
    data : BalloonData or sequence of BalloonData, optional
        Levels already computed by :func:`balloon_data` for these configurations (one each);
        by default they are computed here.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> from acoustiviz import Impact, acceleration_pulse
    >>> from acoustiviz.images import configuration
    >>> pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=0.226), "half-sine")
    >>> corner = configuration("wall-floor", 0.01905, wall_distance=0.05)
    >>> render_balloon(pulse, corner, "balloon.png", size=(800, 600))  # doctest: +SKIP
    PosixPath('balloon.png')
    """
    path = _check_path(path, (".png",))
    size = _check_size(size)
    configs = _configs(config)
    for c in configs:
        _check_inputs(pulse, c, medium)
    rng = check_range("db_range", db_range, 0.0, 200.0, unit="dB", low_open=True)
    opacity = check_range("opacity", opacity, 0.0, 1.0, low_open=True)
    if data is None:
        datas = [balloon_data(pulse, c, medium=medium, distance=distance, metric=metric, n_theta=n_theta)
                 for c in configs]
    else:
        datas = [data] if isinstance(data, BalloonData) else list(data)
        if len(datas) != len(configs) or not all(isinstance(d, BalloonData) for d in datas):
            raise ParameterError("data", f"expected {len(configs)} BalloonData, one per configuration")
    top = max(d.max_level for d in datas)
    clim = (top - rng, top)
    if title is None:
        title = f"{datas[0].label.split(' (')[0]} at {datas[0].distance:g} m, {db_range:g} dB from centre to rim"
    with _plotter(size, shape=(1, len(configs))) as pl:
        for i, (c, d) in enumerate(zip(configs, datas, strict=True)):
            pl.subplot(0, i)
            actor = _draw_balloon(pl, pulse, c, d, top, rng, balloon_size, clim, cmap, size, len(configs), opacity)
            if show_scalar_bar and i == len(configs) - 1:
                _add_bar(pl, d.label, size, actor.mapper, n_views=len(configs))
        pl.subplot(0, 0)
        pl.add_text(title, position="upper_left", font_size=_font(size, 13), color="black")
        img = _grab(pl)
    return _write_png(img, path)


def _draw_balloon(pl, pulse, config, data, top, rng, balloon_size, clim, cmap, size, n_views, opacity):
    a = config.radius
    if balloon_size is None:
        wall = -config.planes[1].point[0] if config.name == "wall-floor" else 0.0
        bsize = max(6.0 * a, 1.5 * wall)
    else:
        bsize = check_positive("balloon_size", balloon_size, "m")
    mesh = _balloon_mesh(data, bsize, top, rng)
    actor = pl.add_mesh(mesh, scalars="level", clim=clim, cmap=cmap, smooth_shading=True, split_sharp_edges=True,
                        show_scalar_bar=False,
                        specular=0.25, nan_color="#dddddd", opacity=opacity)
    section = mesh.slice(normal="y", origin=data.anchor)  # the polar pattern in the plane y = 0
    if section.n_points:
        pl.add_mesh(section, color="#202020", line_width=max(1.0, 2.5 * size[1] / 900.0))
    bounds = _scene_extent(config, 1.05 * bsize)
    _add_geometry(pl, config, bounds)
    line = _scene_label(pulse, config) + f"\nmax {data.max_level:.1f} dB, energy mean {data.mean_level:.1f} dB"
    pl.add_text(line, position="lower_left", font_size=_font((size[0] / n_views, size[1]), 11), color="#222222")
    x0, x1, y0, y1, z0, z1 = bounds
    focus = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    direction = (0.9, -1.7, 0.8) if config.name != "free" else (0.9, -1.7, 0.4)
    _set_camera(pl, focus, direction, zoom=1.35 if config.name != "free" else 1.05)
    return actor


def _add_bar(pl, label, size, mapper, *, n_views=1, fmt="%.0f"):
    """A vertical colour bar at the right of the active view, labelled with ``label`` (name and unit)."""
    pl.add_scalar_bar(title=label, mapper=mapper, vertical=True, position_x=0.86 if n_views == 1 else 0.78,
                      position_y=0.22, width=0.05 if n_views == 1 else 0.1, height=0.56,
                      title_font_size=_font(size, 15), label_font_size=_font(size, 13), fmt=fmt, color="black",
                      n_labels=5)


# --------------------------------------------------------------------------- snapshots
def section_planes(config: Configuration, extent: float, *, sections=("xz",), n_u: int = 241) -> list:
    """Planar grids through the sphere for field snapshots, clipped to the fluid's bounding box.

    Parameters
    ----------
    config : Configuration
        The scene.
    extent : float
        Distance in m from the sphere's centre to the far edges of each section.
    sections : sequence of {"xz", "yz", "xy"}
        ``"xz"``: the vertical plane ``y = 0`` (normal to the wall, holding the acceleration
        axis); ``"yz"``: the vertical plane through the centre parallel to the wall; ``"xy"``:
        the horizontal plane through the centre. Each is bounded by the floor and the wall.
    n_u : int
        Points along the longer side (>= 8).

    Returns
    -------
    list of PlanarGrid
    """
    e = check_positive("extent", extent, "m")
    if e <= 2.0 * config.radius:
        raise ParameterError("extent", f"must exceed the sphere's diameter {2 * config.radius:g} m, got {e:g} m")
    if isinstance(sections, str):
        sections = (sections,)
    if int(n_u) != n_u or n_u < 8:
        raise ParameterError("n_u", f"must be an integer >= 8, got {n_u!r}")
    c = config.centre
    lo = c - e
    hi = c + e
    for p in config.planes:  # clip at the floor (z) and the wall (x)
        k = int(np.argmax(np.abs(p.normal)))
        lo[k] = max(lo[k], p.point[k])
    out = []
    for s in sections:
        check_choice("sections", s, SECTIONS)
        i, j = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}[s]
        u = np.zeros(3)
        v = np.zeros(3)
        u[i] = hi[i] - lo[i]
        v[j] = hi[j] - lo[j]
        centre = c.copy()
        centre[i] = 0.5 * (lo[i] + hi[i])
        centre[j] = 0.5 * (lo[j] + hi[j])
        long = max(u[i], v[j])
        nu = max(2, int(round((n_u - 1) * u[i] / long)) + 1)
        nv = max(2, int(round((n_u - 1) * v[j] / long)) + 1)
        out.append(planar_grid(centre, u, v, n_u=nu, n_v=nv))
    return out


def _planes(config, planes, extent, times, medium, n_u, sections=("xz",)):
    if planes is not None:
        ps = [planes] if isinstance(planes, PlanarGrid) else list(planes)
        if not ps or not all(isinstance(p, PlanarGrid) for p in ps):
            raise ParameterError("planes", "expected a PlanarGrid or a non-empty sequence of them")
        return ps
    if extent is None:
        reach = medium.c * float(np.max(times)) + config.radius
        extent = max(8.0 * config.radius, 1.25 * reach)
    return section_planes(config, extent, sections=sections, n_u=n_u)


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


def _snapshot_bounds(planes, config: Configuration):
    """Bounds (m) of the drawn floor/wall: the planes' box, flat axes widened to show the geometry."""
    pts = np.vstack([p.points for p in planes])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = float(np.max(hi - lo))
    for k in range(3):
        if hi[k] - lo[k] < 1e-9 * span:
            lo[k] -= 0.3 * span
            hi[k] += 0.3 * span
    for p in config.planes:
        k = int(np.argmax(np.abs(p.normal)))
        lo[k] = max(lo[k], p.point[k])
    return lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]


def _draw_snapshot(pl, config, planes, fields, t, clim, cmap, size, label, show_bar, n_views):
    """Draw one snapshot in the active view; return the plane meshes and the time annotation."""
    meshes = [_plane_mesh(g, f) for g, f in zip(planes, fields, strict=True)]
    actor = None
    pv = check_backend()
    for g, m in zip(planes, meshes, strict=True):
        actor = pl.add_mesh(m, scalars="p", cmap=cmap, clim=(-clim, clim), show_scalar_bar=False,
                            nan_color=_SPHERE_COLOUR, lighting=False)
        corners = g.origin + np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]) @ np.vstack([g.u, g.v])
        pl.add_mesh(pv.lines_from_points(corners), color="#505050", line_width=max(1.0, 1.5 * size[1] / 900.0))
    _add_geometry(pl, config, _snapshot_bounds(planes, config), opacity=0.25)
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


def _time_label(t: float) -> str:
    return f"t = {t * 1e3:.3f} ms"


def render_snapshot(
    pulse,
    config: Configuration,
    time,
    path,
    *,
    medium: Medium = AIR,
    planes=None,
    extent=None,
    sections=("xz",),
    n_u: int = 241,
    size=DEFAULT_SIZE,
    clim=None,
    title=None,
    show_scalar_bar: bool = True,
    cmap: str = "RdBu_r",
) -> Path:
    """Render the pressure p(x, t) on planar grids at one or more times into a PNG file.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Configuration
        The scene.
    time : float or sequence of float
        Snapshot time(s) in s from the start of contact, at most 12; several go side by side
        (up to three in a row, four and more on a near-square grid) with one colour scale.
    path : path-like
        Output ``.png`` file (written atomically).
    medium : Medium
        The fluid.
    planes : PlanarGrid or sequence of PlanarGrid, optional
        Where to evaluate the field (default :func:`section_planes` with ``sections``).
    extent : float, optional
        Half-size in m of the default sections (default 1.25 × the distance sound travels
        by the last time, at least eight sphere radii).
    sections : sequence of {"xz", "yz", "xy"}
        Default sections to draw (ignored with ``planes``).
    n_u : int
        Points along the longer side of each default section.
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
    >>> render_snapshot(pulse, configuration("plane", 0.01905), [0.5e-3, 1e-3], "p.png")  # doctest: +SKIP
    PosixPath('p.png')
    """
    path = _check_path(path, (".png",))
    size = _check_size(size)
    _check_inputs(pulse, config, medium)
    times = np.atleast_1d(np.asarray(time, dtype=float))
    if times.ndim != 1 or times.size == 0 or times.size > 12 or not np.all(np.isfinite(times)) or np.any(times < 0):
        raise ParameterError("time", f"expected 1 to 12 finite times >= 0 s, got {time!r}")
    grids = _planes(config, planes, extent, times, medium, n_u, sections)
    fields = [snapshots(pulse, times, g.points, config, medium=medium) for g in grids]  # each (k, n)
    lim = _symmetric_limit(fields) if clim is None else check_positive("clim", clim, "Pa")
    cols = times.size if times.size <= 3 else int(math.ceil(math.sqrt(times.size)))
    rows = int(math.ceil(times.size / cols))
    label = _scene_label(pulse, config) if title is None else title
    with _plotter(size, shape=(rows, cols)) as pl:
        for q, tq in enumerate(times):
            pl.subplot(q // cols, q % cols)
            _draw_snapshot(pl, config, grids, [f[q] for f in fields], tq, lim, cmap, (size[0], size[1] / rows),
                           label if q == 0 else None, show_scalar_bar and q == times.size - 1, cols)
        img = _grab(pl)
    return _write_png(img, path)


# --------------------------------------------------------------------------- animation
def animation_times(pulse, config: Configuration, points, *, medium: Medium = AIR, frames: int = 48) -> np.ndarray:
    """Frame times in s from the start of contact until the last wavefront crosses ``points``.

    The last time is the latest arrival, over the points and the image sources, of the end of
    the pulse ``max (r_j - a)/c + T``.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Configuration
        The scene.
    points : (n, 3) array_like
        Points in m (e.g. the planar grids' points).
    medium : Medium
        The fluid.
    frames : int
        Number of frames (>= 2).

    Returns
    -------
    (frames,) ndarray
    """
    if int(frames) != frames or not 2 <= frames <= 2000:
        raise ParameterError("frames", f"must be an integer in [2, 2000], got {frames!r}")
    delay, _, _, _ = source_geometry(points, config, medium=medium)
    ok = config.in_fluid(points)
    end = float(np.max(delay[ok])) + pulse.duration
    return np.linspace(0.5 * pulse.duration, end, int(frames))


def frame_fields(pulse, config: Configuration, times, points, *, medium: Medium = AIR) -> np.ndarray:
    """Pressure (k, n) in Pa at ``times`` (k,), evaluating each frame only where it is non-zero.

    Points outside their arrival window at a frame time (:func:`acoustiviz.field.arrival_windows`)
    are set to zero without evaluation; points outside the fluid are NaN.
    """
    pts = np.asarray(points, dtype=float)
    tt = np.atleast_1d(np.asarray(times, dtype=float))
    start, stop = arrival_windows(pulse, pts, config, medium=medium)
    out = np.zeros((tt.size, pts.shape[0]))
    out[:, ~config.in_fluid(pts)] = np.nan
    for q, tq in enumerate(tt):
        live = (start <= tq) & (tq <= stop)
        if np.any(live):
            out[q, live] = snapshots(pulse, [tq], pts[live], config, medium=medium)[0]
    return out


def _write_frames(frames, path: Path, fps: float):
    if path.suffix.lower() == ".gif":
        from PIL import Image

        imgs = [Image.fromarray(f).quantize(colors=255, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
                for f in frames]
        with atomic_path(path) as tmp:
            imgs[0].save(tmp, format="GIF", save_all=True, append_images=imgs[1:], duration=int(round(1000 / fps)),
                         loop=0, optimize=False)
        return path
    import imageio.v2 as imageio

    with atomic_path(path) as tmp:
        with imageio.get_writer(tmp, fps=fps, codec="libx264", quality=7, macro_block_size=2,
                                ffmpeg_log_level="error") as w:
            for f in frames:
                w.append_data(f)
    return path


def render_animation(
    pulse,
    config: Configuration,
    path,
    *,
    medium: Medium = AIR,
    times=None,
    frames: int = 48,
    fps: float = 12.0,
    planes=None,
    extent=None,
    sections=("xz",),
    n_u: int = 201,
    size=(800, 600),
    clim=None,
    title=None,
    cmap: str = "RdBu_r",
) -> Path:
    """Render the wavefront leaving the impact and reflecting as a GIF or MP4 animation.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Configuration
        The scene.
    path : path-like
        Output ``.gif`` (always available) or ``.mp4`` (needs ``imageio-ffmpeg``), written
        atomically.
    medium : Medium
        The fluid.
    times : (k,) array_like, optional
        Frame times in s (default :func:`animation_times` over the planes, ``frames`` of them).
    frames : int
        Number of frames when ``times`` is not given.
    fps : float
        Frames per second, in (0, 60].
    planes, extent, sections, n_u
        Where the field is drawn, as for :func:`render_snapshot`.
    size : (int, int)
        Frame width and height in pixels (even numbers for MP4).
    clim : float, optional
        Colour limit in Pa, fixed over all frames (default: the median over the frames of
        each frame's 99.5th percentile of |p|; larger values saturate).
    title : str, optional
        Text at the lower left of every frame.
    cmap : str
        A diverging colour map, centred on zero.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> render_animation(pulse, corner, "wavefront.gif", frames=60, fps=15)  # doctest: +SKIP
    PosixPath('wavefront.gif')
    """
    path = _check_path(path, (".gif", ".mp4"))
    size = _check_size(size)
    _check_inputs(pulse, config, medium)
    rate = check_range("fps", fps, 0.0, 60.0, unit="frames/s", low_open=True)
    if path.suffix.lower() == ".mp4":
        if not mp4_available():
            raise ParameterError("path", "writing MP4 needs imageio and imageio-ffmpeg ('pip install imageio-ffmpeg'); "
                                         "write a .gif instead")
        size = (size[0] + size[0] % 2, size[1] + size[1] % 2)
    if times is None:
        probe = _planes(config, planes, extent, [_reach_time(config, medium, extent)], medium, n_u, sections)
        times = animation_times(pulse, config, np.vstack([g.points for g in probe]), medium=medium, frames=frames)
        grids = probe
    else:
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if times.ndim != 1 or times.size < 2 or not np.all(np.isfinite(times)):
            raise ParameterError("times", "expected at least two finite frame times in s")
        grids = _planes(config, planes, extent, times, medium, n_u, sections)
    fields = [frame_fields(pulse, config, times, g.points, medium=medium) for g in grids]
    lim = _symmetric_limit(fields) if clim is None else check_positive("clim", clim, "Pa")
    label = _scene_label(pulse, config) if title is None else title
    images = []
    with _plotter(size) as pl:
        meshes, clock = _draw_snapshot(pl, config, grids, [f[0] for f in fields], times[0], lim, cmap, size, label,
                                       True, 1)
        for q, tq in enumerate(times):
            for m, f in zip(meshes, fields, strict=True):
                m.point_data["p"][:] = f[q]
                m.Modified()
            clock.SetText(2, _time_label(tq))
            images.append(_grab(pl))
    return _write_frames(images, path, rate)


def _reach_time(config: Configuration, medium: Medium, extent) -> float:
    """A time in s whose default extent frames the scene (used before the frame times exist)."""
    if extent is not None:
        return max(0.0, (float(extent) / 1.25 - config.radius) / medium.c)
    wall = -config.planes[1].point[0] if config.name == "wall-floor" else 0.0
    return max(12.0 * config.radius, 6.0 * wall) / medium.c
