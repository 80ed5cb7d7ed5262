"""Wavefront animations (GIF, or MP4 with the ``video`` extra) with one colour range over all frames."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..._validate import ParameterError, check_positive, check_range
from ...constants import ANIMATION_SIZE
from ...core.geometry import Geometry
from ...core.medium import AIR, Medium
from ...field import arrival_windows, snapshots, source_geometry
from ...field.sections import SectionField, section_grids
from ...files import atomic_path
from ._common import _check_inputs, _check_path, _check_size, _grab, _plotter, _scene_label, mp4_available
from .snapshot import _draw_snapshot, _symmetric_limit, _time_label

__all__ = [
    "animation_times",
    "frame_fields",
    "animation_field",
    "render_animation",
]


# --------------------------------------------------------------------------- animation
def animation_times(pulse, config: Geometry, points, *, medium: Medium = AIR, frames: int = 48) -> np.ndarray:
    """Frame times in s from the start of contact until the last wavefront crosses ``points``.

    The last time is the latest arrival, over the points and the image sources, of the end of
    the pulse ``max (r_j - a)/c + T``.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Geometry
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


def frame_fields(pulse, config: Geometry, times, points, *, medium: Medium = AIR) -> np.ndarray:
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


def animation_field(pulse, config: Geometry, *, medium: Medium = AIR, times=None, frames: int = 48, planes=None,
                    extent=None, sections=("xz",), n_u: int = 201, min_times: int = 2) -> SectionField:
    """Every frame of a wavefront animation: its grids, frame times and pressures, evaluated once.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Geometry
        The scene.
    medium : Medium
        The fluid.
    times : (k,) array_like, optional
        Frame times in s (default :func:`animation_times` over the planes, ``frames`` of them).
    frames : int
        Number of frames when ``times`` is not given.
    planes, extent, sections, n_u
        Where the field is evaluated, as for :func:`render_snapshot`.
    min_times : int
        Fewest frame times accepted in ``times`` (an animation needs two; a data file one).

    Returns
    -------
    acoustiviz.field.sections.SectionField
        Pressures in Pa by :func:`frame_fields` (zero where no wave has arrived or all have
        passed, NaN inside the sphere).
    """
    if times is None:
        grids = section_grids(config, planes, extent, [_reach_time(config, medium, extent)], medium, n_u, sections)
        times = animation_times(pulse, config, np.vstack([g.points for g in grids]), medium=medium, frames=frames)
    else:
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if times.ndim != 1 or times.size < min_times or not np.all(np.isfinite(times)):
            least = "at least two " if min_times == 2 else ""
            raise ParameterError("times", f"expected {least}finite frame times in s")
        grids = section_grids(config, planes, extent, times, medium, n_u, sections)
    fields = tuple(frame_fields(pulse, config, times, g.points, medium=medium) for g in grids)
    return SectionField.of(grids, times, fields)


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
    config: Geometry,
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
    size=ANIMATION_SIZE,
    clim=None,
    title=None,
    cmap: str = "RdBu_r",
    field=None,
) -> Path:
    """Render the wavefront leaving the impact and reflecting as a GIF or MP4 animation.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    config : Geometry
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
    field : SectionField, optional
        The frames already evaluated by :func:`animation_field` (``times``, ``frames``,
        ``medium``, ``planes``, ``extent``, ``sections`` and ``n_u`` are then taken from it); by
        default they are evaluated here.

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
    if field is None:
        field = animation_field(pulse, config, medium=medium, times=times, frames=frames, planes=planes, extent=extent,
                                sections=sections, n_u=n_u)
    elif not isinstance(field, SectionField):
        raise ParameterError("field", f"expected a SectionField, got {type(field).__name__}")
    grids, times, fields = field.grids, field.times, field.pressures
    lim = _symmetric_limit(fields) if clim is None else check_positive("clim", clim, "Pa")
    label = _scene_label(pulse, config) if title is None else title
    images = []
    with _plotter(size) as pl:
        # the meshes own their values (frames are copied into them): the field is never written
        meshes, clock = _draw_snapshot(pl, config, grids, [np.array(f[0]) for f in fields], times[0], lim, cmap, size,
                                       label, True, 1)
        for q, tq in enumerate(times):
            for m, f in zip(meshes, fields, strict=True):
                m.point_data["p"][:] = f[q]
                m.Modified()
            clock.SetText(2, _time_label(tq))
            images.append(_grab(pl))
    return _write_frames(images, path, rate)


def _reach_time(config: Geometry, medium: Medium, extent) -> float:
    """A time in s whose default extent frames the scene (used before the frame times exist)."""
    if extent is not None:
        return max(0.0, (float(extent) / 1.25 - config.radius) / medium.c)
    return max(12.0 * config.radius, 6.0 * config.feature_distance) / medium.c
