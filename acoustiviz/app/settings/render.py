"""Settings of the 3-D views: ``acoustiviz render balloon|snapshot|animation`` and the scene outputs of the same names.

One table per view; a scene's ``[grids.sphere]`` and ``[grids.plane]`` keys and its
``[outputs.balloon|snapshot|animation]`` keys are the same settings as the command's options.
Where the two front-ends start from different defaults (a scene's planes share one resolution,
the command's views each have their own), the table records both (``scene_default``). Beside the
tables: each view's image size (:data:`SIZES`), the planes (:data:`SECTION_LIST`), a snapshot's
times (:data:`TIMES`), the caption (:data:`TITLE`) and the files, the command's paths
(:data:`VIEW_FILES`) and a scene's switches (:data:`SCENE_FILES`); the jobs of
:mod:`acoustiviz.app.settings.render_job` hold them all.
"""

from __future__ import annotations

import dataclasses
import math

from ...constants import (
    ANIMATION_SIZE,
    BALLOON_METRICS,
    BALLOON_N_THETA_RANGE,
    MAX_SNAPSHOT_TIMES,
    SECTION_PLANES,
    STILL_SIZE,
)
from .base import SIZE_RANGE, Settings, check_size
from .table import Setting

__all__ = ["BALLOON", "SNAPSHOT", "ANIMATION", "MAX_TIMES", "SIZES", "SECTION_LIST", "TIMES", "TITLE", "VIEW_FILES",
           "SCENE_FILES", "BalloonSettings", "SnapshotSettings", "AnimationSettings", "SETTINGS_OF_VIEW"]

#: Most snapshot times drawn side by side.
MAX_TIMES = MAX_SNAPSHOT_TIMES
#: Farthest edge of a field plane and largest balloon radius in m (a render of a field kilometres
#: across shows nothing of an impact).
MAX_EXTENT, MAX_BALLOON_DISTANCE = 1e3, 1e4

BALLOON = (
    Setting("distance", "--distance", "distance_m", "float", 0.7,
            "radius of the measuring sphere around the contact point", "m", low=0.0, high=MAX_BALLOON_DISTANCE,
            low_open=True, table="grids.sphere"),
    Setting("metric", "--metric", "metric", "str", "peak",
            "peak SPL, RMS level or sound exposure level of the closed form, or a weighted level of the pressure "
            "band-limited at 96 kHz (IEC 61672-1: lcpeak, lafmax, laeq = LAeq,1s, sel-a, ...), all dB re 20 uPa",
            choices=BALLOON_METRICS, table="outputs.balloon"),
    Setting("db_range", "--db-range", "db_range", "float", 30.0,
            "level range from the balloon's centre to its largest radius", "dB", low=0.0, high=200.0,
            low_open=True, table="outputs.balloon"),
    Setting("n_theta", "--resolution", "n_theta", "int", 32,
            "polar nodes of the measuring grid (the azimuth gets twice as many)", low=BALLOON_N_THETA_RANGE[0],
            high=BALLOON_N_THETA_RANGE[1],
            table="grids.sphere"),
    Setting("opacity", "--opacity", None, "float", 0.7, "balloon opacity; below 1 the sphere shows through",
            low=0.0, high=1.0, low_open=True),
)

_PLANES = (
    Setting("extent", "--extent", "extent_m", "float", None,
            "distance from the sphere's centre to the far edges of the planes (default: 1.25 x the distance "
            "sound travels by the last time)", "m", low=0.0, high=MAX_EXTENT, low_open=True, table="grids.plane"),
    Setting("clim", "--clim", None, "float", None,
            "colour limit; the diverging map spans [-clim, clim] (default: from the field)", "Pa", low=0.0,
            high=math.inf, low_open=True),
)


def _resolution(default: int) -> Setting:
    return Setting("n_u", "--resolution", "resolution", "int", default,
                   "points along the longer side of each plane", low=8, high=20000, scene_default=200,
                   table="grids.plane")


SNAPSHOT = (*_PLANES, _resolution(241))
ANIMATION = (
    *_PLANES, _resolution(201),
    Setting("frames", "--frames", "frames", "int", 48, "number of frames", low=2, high=2000,
            scene_default=40, table="outputs.animation"),
    Setting("fps", "--fps", "fps", "float", 12.0, "frames per second", "frames/s", low=0.0,
            high=60.0, low_open=True, table="outputs.animation"),
)


def _size(view: str, default: tuple, scene_default=None) -> Setting:
    return Setting("size", "--size", "size_px", "size", default, "image size in pixels, width x height", "px",
                   low=SIZE_RANGE[0], high=SIZE_RANGE[1], scene_default=scene_default or default,
                   table=f"outputs.{view}", metavar="WxH")


#: View -> the record of its image size (a scene's snapshot is wide: its times go side by side).
SIZES = {"balloon": _size("balloon", STILL_SIZE), "snapshot": _size("snapshot", STILL_SIZE, (1400, 600)),
         "animation": _size("animation", ANIMATION_SIZE)}

#: The planes of a snapshot or an animation.
SECTION_LIST = Setting("sections", "--sections", "sections", "strs", ("xz",),
                       "planes through the sphere's centre: xz the vertical plane normal to the wall (holding the "
                       "acceleration axis), yz the vertical plane parallel to it, xy the horizontal",
                       choices=SECTION_PLANES, table="grids.plane", metavar="LIST")

#: The times of a snapshot, drawn side by side.
TIMES = Setting("times", "--time", "times_s", "floats", (0.001,),
                f"snapshot time(s) from the start of contact (at most {MAX_SNAPSHOT_TIMES}, drawn side by side)",
                "s", low=0.0, high=10.0, table="outputs.snapshot", metavar="S", length=MAX_SNAPSHOT_TIMES)

#: The caption of a picture (a scene's is always the default).
TITLE = Setting("title", "--title", None, "str", None, "replace the default annotation", metavar="TEXT")

#: The files of the command line's views (a scene names them itself: ``<view>.png``, ``.gif``, ``.vtu``, ``.html``).
VIEW_FILES = {
    "png": Setting("png", "--png", None, "str", None, "output image", metavar="PATH"),
    "gif": Setting("gif", "--gif", None, "str", None, "output GIF", metavar="PATH"),
    "mp4": Setting("mp4", "--mp4", None, "str", None, "output MP4 (needs imageio-ffmpeg)", metavar="PATH"),
    "vtk": Setting("vtk", "--vtk", None, "str", None,
                   "the data behind the picture for ParaView, pyvista or meshio: a .vtu (or .vtkhdf) file, with the "
                   "sphere and planes beside it in PATH_geometry.vtu", metavar="PATH"),
    "html": Setting("html", "--html", None, "str", None,
                    "an interactive 3-D view in one self-contained HTML file (no server needed)", metavar="PATH"),
}

#: The scene's switches of the extra files of a view (``vtk = true``: ``<view>.vtu``), per view.
SCENE_FILES = {
    view: tuple(
        Setting(kind, None, kind, "bool", False, doc, table=f"outputs.{view}")
        for kind, doc in (("vtk", "also write the data as <output>.vtu with the sphere and planes in "
                                  "<output>_geometry.vtu (ParaView, pyvista, meshio)"),
                          ("html", "also write an interactive 3-D view as <output>.html (one self-contained file)"))
        if kind == "vtk" or view != "animation")
    for view in ("balloon", "snapshot", "animation")
}


@dataclasses.dataclass(frozen=True)
class BalloonSettings(Settings):
    """The directivity balloon: measuring sphere, level, colour range and image."""

    TABLE = BALLOON
    distance: float = 0.7
    metric: str = "peak"
    db_range: float = 30.0
    n_theta: int = 32
    opacity: float = 0.7
    size: tuple = STILL_SIZE

    def validate(self) -> None:  # noqa: D102
        object.__setattr__(self, "size", check_size(self.size))


@dataclasses.dataclass(frozen=True)
class SnapshotSettings(Settings):
    """The pressure on planes through the sphere at given times."""

    TABLE = SNAPSHOT
    times: tuple = (0.001,)
    sections: tuple = ("xz",)
    extent: float | None = None
    n_u: int = 241
    clim: float | None = None
    size: tuple = STILL_SIZE

    def validate(self) -> None:  # noqa: D102
        object.__setattr__(self, "times", TIMES.check(self.times))
        object.__setattr__(self, "sections", SECTION_LIST.check(self.sections))
        object.__setattr__(self, "size", check_size(self.size))


@dataclasses.dataclass(frozen=True)
class AnimationSettings(Settings):
    """The wavefront leaving the impact, frame by frame."""

    TABLE = ANIMATION
    frames: int = 48
    fps: float = 12.0
    sections: tuple = ("xz",)
    extent: float | None = None
    n_u: int = 201
    clim: float | None = None
    size: tuple = ANIMATION_SIZE

    def validate(self) -> None:  # noqa: D102
        object.__setattr__(self, "sections", SECTION_LIST.check(self.sections))
        object.__setattr__(self, "size", check_size(self.size))


#: View name -> its settings class.
SETTINGS_OF_VIEW = {"balloon": BalloonSettings, "snapshot": SnapshotSettings, "animation": AnimationSettings}
