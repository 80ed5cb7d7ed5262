"""The settings of the render jobs: one impact, its surroundings, one 3-D view, its picture and its files.

:class:`SnapshotJob`, :class:`BalloonJob` and :class:`AnimationJob` are the whole of what
:func:`acoustiviz.app.render_job.run` needs, checked once when made (the table's ranges, the view
against the fluid, the memory and output budget, the files to write), so ``acoustiviz render
snapshot|balloon|animation``, a scene's ``[outputs.snapshot|balloon|animation]`` and a Python caller
build the same object and hand it to the same run. Each is its view's settings
(:mod:`acoustiviz.app.settings.render`) with the impact, the caption, the files and the memory cap
added, as keyword arguments.
"""

from __future__ import annotations

import dataclasses

from ...errors import ParameterError
from .impact import ImpactJob
from .render import (
    ANIMATION,
    BALLOON,
    SECTION_LIST,
    SIZES,
    SNAPSHOT,
    TIMES,
    TITLE,
    VIEW_FILES,
    AnimationSettings,
    BalloonSettings,
    SnapshotSettings,
)

__all__ = ["ViewJob", "SnapshotJob", "BalloonJob", "AnimationJob", "JOB_OF_VIEW"]

#: File kind -> the format :func:`acoustiviz.app.outputs.check_output_file` checks it as.
_FORMATS = {"png": "png", "gif": "gif", "mp4": "mp4", "vtk": "vtk", "html": "html"}


@dataclasses.dataclass(frozen=True, kw_only=True)
class ViewJob(ImpactJob):
    """What every render job holds besides its view: an impact job's values, the pulse, the caption and the VTK file.

    The impact, the fluid, the surroundings, the memory cap and the vocabulary are those of
    :class:`~acoustiviz.app.settings.impact.ImpactJob` (here the cap covers the output too).

    Attributes
    ----------
    pulse : pulse
        The acceleration pulse (m/s² against s).
    title : str, optional
        Replaces the default caption of the picture (None: :meth:`caption`).
    vtk : str, optional
        The data behind the picture as a ``.vtu`` (or ``.vtkhdf``) file, with ``<stem>_geometry.vtu``
        beside it; relative to the folder the result's ``write`` is given.
    """

    @classmethod
    def names_for(cls, front: str) -> dict:
        """The job's vocabulary (:meth:`Settings.names_for`); a scene's files are named by ``outputs.<view>``."""
        files = {k: f"outputs.{cls.VIEW}" for k in cls.FILES} if front == "scene" else {}
        return {**super().names_for(front), **files}

    VIEW = ""
    #: The files of the view, in the order they are written.
    FILES = ()
    pulse: object
    title: str | None = None
    vtk: str | None = None

    def files(self) -> dict:
        """``{kind: path}`` of the files asked for (strings), in :attr:`FILES` order."""
        return {k: getattr(self, k) for k in self.FILES if getattr(self, k) is not None}

    def caption(self) -> str:
        """The default caption of a field view: the configuration, the sphere and the impact."""
        imp, geometry = self.impact, self.geometry
        return (f"{geometry.caption(long=True)}: a = {geometry.radius * 1e3:.4g} mm, m = {imp.mass * 1e3:.4g} g, "
                f"U0 = {imp.velocity:g} m/s, K_HZ = {imp.k_hertz:.3g} N/m^1.5, contact {imp.duration * 1e6:.0f} µs, "
                f"{self.pulse.kind} pulse")

    def validate(self) -> None:
        """The view's own checks, then the files, the view in the fluid and the memory and output budget."""
        super().validate()
        self._check_files()
        self._check_fits()
        self._check_budget()

    def _check_files(self) -> None:
        from ...output.vtk import geometry_path
        from ..outputs import check_distinct, check_output_file
        from ..render import check_view_outputs

        check_view_outputs({k: getattr(self, k) for k in self.FILES}, {k: self._name(k) for k in self.FILES},
                           require=False)
        paths = {}
        for key, path in self.files().items():
            paths[self._name(key)] = check_output_file(self._name(key), path, _FORMATS[key])
        if self.vtk is not None:
            name = self._name("vtk")
            paths[f"{name} (geometry)"] = check_output_file(name, geometry_path(self.vtk), "vtk")
        check_distinct(paths)

    def _check_fits(self) -> None:
        from ..render import check_view_fits

        check_view_fits(self.VIEW, self, self.geometry)

    def _check_budget(self) -> None:
        from ..budget import check_budget
        from ..render import render_estimate

        # movies hold every frame; a job naming no file at all is a scene's, checked before the run names
        # its files, and a scene always writes its animation's GIF
        n_files = sum(getattr(self, k, None) is not None for k in ("gif", "mp4")) if self.files() else 1
        est = render_estimate(self.VIEW, self, len(self.geometry.sources), n_files=n_files, options=self.names)
        check_budget(est, self.max_memory_mb, cap_name=self._name("max_memory_mb"))


@dataclasses.dataclass(frozen=True, kw_only=True)
class SnapshotJob(ViewJob, SnapshotSettings):
    """The pressure on planes through the sphere at given times, as a PNG, a VTK file and an HTML page.

    The view's settings are those of :class:`~acoustiviz.app.settings.render.SnapshotSettings`
    (``times`` in s, ``sections``, ``extent`` in m, ``n_u``, ``clim`` in Pa, ``size`` in px); the
    rest those of :class:`ViewJob`; ``png`` and ``html`` name the picture and the page.
    """

    TABLE = (*SNAPSHOT, TIMES, SECTION_LIST, SIZES["snapshot"], TITLE, *(VIEW_FILES[k] for k in ("png", "vtk", "html")))
    VIEW = "snapshot"
    FILES = ("png", "vtk", "html")
    png: str | None = None
    html: str | None = None


@dataclasses.dataclass(frozen=True, kw_only=True)
class BalloonJob(ViewJob, BalloonSettings):
    """The directivity balloon around the contact point, as a PNG, a VTK file and an HTML page.

    The view's settings are those of :class:`~acoustiviz.app.settings.render.BalloonSettings`
    (``distance`` in m, ``metric``, ``db_range`` in dB, ``n_theta``, ``opacity``, ``size`` in px); the
    rest those of :class:`ViewJob`; ``png`` and ``html`` name the picture and the page.
    """

    TABLE = (*BALLOON, SIZES["balloon"], TITLE, *(VIEW_FILES[k] for k in ("png", "vtk", "html")))
    VIEW = "balloon"
    FILES = ("png", "vtk", "html")
    png: str | None = None
    html: str | None = None


@dataclasses.dataclass(frozen=True, kw_only=True)
class AnimationJob(ViewJob, AnimationSettings):
    """The wavefront leaving the impact, frame by frame, as a GIF, an MP4 and a VTK file.

    The view's settings are those of :class:`~acoustiviz.app.settings.render.AnimationSettings`
    (``frames``, ``fps`` in frames/s, ``sections``, ``extent`` in m, ``n_u``, ``clim`` in Pa, ``size``
    in px); the rest those of :class:`ViewJob`; ``gif`` and ``mp4`` name the movies (an MP4 needs
    ``imageio-ffmpeg``).
    """

    TABLE = (*ANIMATION, SECTION_LIST, SIZES["animation"], TITLE, *(VIEW_FILES[k] for k in ("gif", "mp4", "vtk")))
    VIEW = "animation"
    FILES = ("gif", "mp4", "vtk")
    gif: str | None = None
    mp4: str | None = None

    def _check_files(self) -> None:
        super()._check_files()
        if self.mp4 is not None:
            from ...output.render import mp4_available

            if not mp4_available():
                raise ParameterError(self._name("mp4"), "writing MP4 needs imageio and imageio-ffmpeg ('pip install "
                                                       "imageio-ffmpeg'); use a GIF instead")


#: View name -> its job class.
JOB_OF_VIEW = {"snapshot": SnapshotJob, "balloon": BalloonJob, "animation": AnimationJob}
