"""Wavefront animations (GIF, or MP4 with the ``video`` extra) with one colour range over all frames."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..._validate import ParameterError, check_positive, check_range
from ...constants import ANIMATION_SIZE
from ...core.geometry import Geometry
from ...field.sections import SectionField
from ...files import atomic_path
from ._common import _check_inputs, _check_path, _check_size, _grab, _plotter, _scene_label, mp4_available
from .snapshot import _check_field, _draw_snapshot, _symmetric_limit, _time_label

__all__ = ["render_animation"]


# --------------------------------------------------------------------------- animation
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
    field: SectionField,
    pulse,
    geometry: Geometry,
    path,
    *,
    fps: float = 12.0,
    size=ANIMATION_SIZE,
    clim=None,
    title=None,
    cmap: str = "RdBu_r",
) -> Path:
    """Render the wavefront leaving the impact and reflecting as a GIF or MP4 animation.

    Parameters
    ----------
    field : acoustiviz.field.sections.SectionField
        The frames evaluated by :func:`acoustiviz.field.sections.animation_field`: the planes, the
        frame times and the pressure on them.
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (named in the caption).
    geometry : acoustiviz.core.geometry.Geometry
        The scene of ``field``.
    path : path-like
        Output ``.gif`` (always available) or ``.mp4`` (needs ``imageio-ffmpeg``), written
        atomically.
    fps : float
        Frames per second, in (0, 60].
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
    >>> field = animation_field(pulse, corner, frames=60)  # doctest: +SKIP
    >>> render_animation(field, pulse, corner, "wavefront.gif", fps=15)  # doctest: +SKIP
    PosixPath('wavefront.gif')
    """
    path = _check_path(path, (".gif", ".mp4"))
    size = _check_size(size)
    _check_inputs(pulse, geometry)
    rate = check_range("fps", fps, 0.0, 60.0, unit="frames/s", low_open=True)
    if path.suffix.lower() == ".mp4":
        if not mp4_available():
            raise ParameterError("path", "writing MP4 needs imageio and imageio-ffmpeg ('pip install imageio-ffmpeg'); "
                                         "write a .gif instead")
        size = (size[0] + size[0] % 2, size[1] + size[1] % 2)
    field = _check_field(field)
    grids, times, fields = field.grids, field.times, field.pressures
    lim = _symmetric_limit(fields) if clim is None else check_positive("clim", clim, "Pa")
    label = _scene_label(pulse, geometry) if title is None else title
    images = []
    with _plotter(size) as pl:
        # the meshes own their values (frames are copied into them): the field is never written
        meshes, clock = _draw_snapshot(pl, geometry, grids, [np.array(f[0]) for f in fields], times[0], lim, cmap, size,
                                       label, True, 1)
        for q, tq in enumerate(times):
            for m, f in zip(meshes, fields, strict=True):
                m.point_data["p"][:] = f[q]
                m.Modified()
            clock.SetText(2, _time_label(tq))
            images.append(_grab(pl))
    return _write_frames(images, path, rate)
