"""What every off-screen render shares: the pyvista back-end, plotters, sizes, cameras, the drawn geometry."""

from __future__ import annotations

import contextlib
import os
import sys
from pathlib import Path

import numpy as np

from ..._validate import ParameterError
from ...constants import STILL_SIZE as DEFAULT_SIZE
from ...core.geometry import Geometry
from ...files import atomic_path

__all__ = [
    "DEFAULT_SIZE",
    "mp4_available",
    "check_backend",
]


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
    _headless_window()
    try:
        import pyvista
    except ImportError as exc:  # pragma: no cover - pyvista is a dependency
        raise RuntimeError(f"3-D renders need pyvista and VTK ('pip install pyvista'): {exc}") from exc
    return pyvista


def _headless_window() -> None:
    """On Linux without a display, make VTK open its EGL off-screen window first.

    VTK's default render window on Linux is the X one; with no X server it logs a coloured
    ``vtkXOpenGLRenderWindow ... bad X server connection`` warning to stderr before falling back to EGL.
    Asking for EGL first (``VTK_DEFAULT_OPENGL_WINDOW``, read when a window is created) skips the
    attempt and the warning; a choice already made in the environment is kept.
    """
    headless = not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    if sys.platform.startswith("linux") and headless:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


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


def _check_inputs(pulse, geometry):
    """Check the scene drawn around the data and the pulse named in its caption."""
    if not isinstance(geometry, Geometry):
        raise ParameterError("geometry",
                             f"expected a geometry (acoustiviz.core.geometry), got {type(geometry).__name__}")
    if not hasattr(pulse, "duration"):
        raise ParameterError("pulse", f"expected an acceleration pulse, got {type(pulse).__name__}")


def _geometries(geometry) -> list:
    cs = [geometry] if isinstance(geometry, Geometry) else list(geometry)
    if not cs or not all(isinstance(c, Geometry) for c in cs):
        raise ParameterError("geometry",
                             "expected a geometry (acoustiviz.core.geometry) or a non-empty sequence of them")
    return cs


# --------------------------------------------------------------------------- scene geometry
def _scene_extent(geometry: Geometry, half: float):
    """Bounds ``(x0, x1, y0, y1, z0, z1)`` in m of a cube of half-size ``half`` around the sphere, cut by the planes."""
    c = geometry.centre
    lo = c - half
    hi = c + half
    for p in geometry.planes:  # each plane bounds its axis on the side away from the fluid
        k = int(np.argmax(np.abs(p.normal)))
        if p.normal[k] > 0:
            lo[k] = p.point[k]
        else:
            hi[k] = p.point[k]
    return lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]


def _add_geometry(pl, geometry: Geometry, bounds, *, opacity: float = 0.35):
    """Draw the sphere, and the floor and wall as semi-transparent rectangles spanning ``bounds`` (m)."""
    pv = check_backend()
    a = geometry.radius
    pl.add_mesh(pv.Sphere(radius=a, center=geometry.centre, theta_resolution=48, phi_resolution=32),
                color=_SPHERE_COLOUR, smooth_shading=True, specular=0.4)
    x0, x1, y0, y1, z0, z1 = bounds
    for pl_ in geometry.planes:
        n = pl_.normal
        if abs(n[2]) > 0.5:  # floor
            mesh = pv.Plane(center=((x0 + x1) / 2, (y0 + y1) / 2, pl_.point[2]), direction=n,
                            i_size=x1 - x0, j_size=y1 - y0)
            colour = _PLANE_COLOUR
        elif abs(n[0]) > 0.5:  # wall across x
            mesh = pv.Plane(center=(pl_.point[0], (y0 + y1) / 2, (z0 + z1) / 2), direction=n,
                            i_size=z1 - z0, j_size=y1 - y0)
            colour = _WALL_COLOUR
        else:  # wall across y: the rectangle spanning x and z
            mesh = pv.Rectangle([[x0, pl_.point[1], z0], [x1, pl_.point[1], z0], [x1, pl_.point[1], z1]])
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


def _scene_label(pulse, geometry: Geometry) -> str:
    parts = [geometry.caption()]
    parts.append(f"a = {geometry.radius * 1e3:.4g} mm")
    parts.append(f"contact {pulse.duration * 1e6:.0f} µs")
    parts.append(f"{getattr(pulse, 'kind', 'sampled')} pulse")
    return ", ".join(parts)


def _add_bar(pl, label, size, mapper, *, n_views=1, fmt="%.0f"):
    """A vertical colour bar at the right of the active view, labelled with ``label`` (name and unit)."""
    pl.add_scalar_bar(title=label, mapper=mapper, vertical=True, position_x=0.86 if n_views == 1 else 0.78,
                      position_y=0.22, width=0.05 if n_views == 1 else 0.1, height=0.56,
                      title_font_size=_font(size, 15), label_font_size=_font(size, 13), fmt=fmt, color="black",
                      n_labels=5)
