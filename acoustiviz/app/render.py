"""The rules of the 3-D views of one impact (balloon, snapshot, animation): their files, fit and memory estimate.

The render jobs (:mod:`acoustiviz.app.settings.render_job`, :mod:`acoustiviz.app.render_job`) check
themselves with these rules, whichever front end built them: the file name endings of each output
(:func:`check_view_outputs`), a balloon inside the fluid (:func:`check_view_fits`) and the memory and
output size (:func:`render_estimate`), also checked when a scene is loaded.
"""

from __future__ import annotations

from .budget import animation_estimate, balloon_estimate, snapshot_estimate
from .outputs import FORMATS

__all__ = ["OUTPUT_ENDINGS", "check_view_outputs", "check_view_fits", "render_estimate"]

#: Output kind of a view -> the file name endings it accepts.
OUTPUT_ENDINGS = {k: FORMATS[k] for k in ("png", "gif", "mp4", "vtk", "html")}


def check_view_outputs(offered: dict, names: dict | None = None, *, require: bool = True) -> dict:
    """The outputs asked for (``{kind: path}`` of those given), each with its file name ending.

    ``offered``: ``{kind: path or None}`` of every output the view has; ``names``: kind -> the option or
    scene key its errors name (default ``--kind``); ``require``: refuse none at all (a command asked
    for nothing to write).
    """
    from ..errors import ParameterError

    names = {k: (names or {}).get(k, f"--{k}") for k in offered}
    paths = {k: v for k, v in offered.items() if v}
    if require and not paths:
        first = next(iter(offered))
        raise ParameterError(names[first], f"give at least one output: {', '.join(names.values())}")
    for k, path in paths.items():
        ends = OUTPUT_ENDINGS[k]
        if not str(path).lower().endswith(ends):
            raise ParameterError(names[k], f"expected a file name ending in {' or '.join(ends)}, got {str(path)!r}")
    return paths


def check_view_fits(view: str, settings, geometry) -> None:
    """Refuse a balloon whose measuring sphere leaves the fluid (a room's walls), before any work.

    The sphere of radius ``settings.distance`` (m) must clear the struck sphere of ``geometry``
    (more than 2.1 radii from its centre) and stay within the fluid
    (:func:`acoustiviz.core.reach.check_view_radius`); errors name ``distance``. The planes of a
    snapshot or an animation are cut at the walls and need no check.
    """
    if view == "balloon":
        from ..constants import BALLOON_MIN_RADII
        from ..core.reach import check_view_radius

        check_view_radius(geometry, settings.distance, BALLOON_MIN_RADII * geometry.radius)


def render_estimate(view: str, settings, n_sources: int, *, n_files: int = 1, options: dict | None = None):
    """The memory and output size of one view (:class:`acoustiviz.app.budget.Estimate`).

    Parameters
    ----------
    view : {"balloon", "snapshot", "animation"}
    settings : BalloonSettings, SnapshotSettings or AnimationSettings (or their jobs)
    n_sources : int
        Sources of the configuration (the sphere and its images).
    n_files : int
        Animation files written from the same frames (GIF and MP4).
    options : dict, optional
        API name -> the option or scene key the error should name (default: the API names).
    """
    names = options or {}

    def named(*keys):
        return tuple(names.get(k, k) for k in keys)

    s = settings
    if view == "balloon":
        return balloon_estimate(s.n_theta, s.size, n_sources, options=named("n_theta"))
    if view == "snapshot":
        return snapshot_estimate(s.n_u, len(s.sections), len(s.times), s.size, n_sources,
                                 options=named("n_u", "times"))
    return animation_estimate(s.frames * n_files, s.n_u, len(s.sections), s.size, n_sources,
                              options=named("frames", "size", "n_u"))
