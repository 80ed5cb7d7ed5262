"""The 3-D views of one impact (balloon, snapshot, animation): their memory estimate and their files.

Both front-ends take a view's settings object (:mod:`acoustiviz.app.settings.render`): the
command line from its options, a scene from ``[grids]`` and ``[outputs.<view>]``. The estimate
of the memory and output size is one rule (:func:`render_estimate`) whichever front-end asks,
and :func:`render_files` writes the files of the command line's view.
"""

from __future__ import annotations

from .budget import animation_estimate, balloon_estimate, snapshot_estimate

__all__ = ["OUTPUT_ENDINGS", "check_view_outputs", "check_view_fits", "render_estimate", "annotation", "render_files"]

#: Output kind of a view -> the file name endings it accepts.
OUTPUT_ENDINGS = {"png": (".png",), "gif": (".gif",), "mp4": (".mp4",), "vtk": (".vtu", ".vtkhdf"),
                  "html": (".html", ".htm")}


def check_view_outputs(offered: dict) -> dict:
    """The outputs asked for (``{kind: path}`` of those given), at least one, each with its file name ending.

    ``offered``: ``{kind: path or None}`` of every output the view has; errors name ``--kind``.
    """
    from ..errors import ParameterError

    paths = {k: v for k, v in offered.items() if v}
    if not paths:
        raise ParameterError(f"--{next(iter(offered))}", f"give at least one output: "
                                                         f"{', '.join('--' + k for k in offered)}")
    for k, path in paths.items():
        ends = OUTPUT_ENDINGS[k]
        if not str(path).lower().endswith(ends):
            raise ParameterError(f"--{k}", f"expected a file name ending in {' or '.join(ends)}, got {path!r}")
    return paths


def check_view_fits(view: str, settings, setup) -> None:
    """Refuse a balloon whose measuring sphere leaves the fluid (a room's walls), before any work.

    The sphere of radius ``settings.distance`` (m) must clear the struck sphere (more than 2.1
    radii from its centre) and stay within the fluid (:func:`acoustiviz.core.reach.check_view_radius`);
    errors name ``distance``. The planes of a snapshot or an animation are cut at the walls and need
    no check.
    """
    if view == "balloon":
        from ..constants import BALLOON_MIN_RADII
        from ..core.reach import check_view_radius

        check_view_radius(setup.configuration, settings.distance, BALLOON_MIN_RADII * setup.radius)


def render_estimate(view: str, settings, n_sources: int, *, n_files: int = 1, options: dict | None = None):
    """The memory and output size of one view (:class:`acoustiviz.app.budget.Estimate`).

    Parameters
    ----------
    view : {"balloon", "snapshot", "animation"}
    settings : BalloonSettings, SnapshotSettings or AnimationSettings
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


def annotation(setup) -> str:
    """The default caption of a field view: the configuration, the sphere and the impact."""
    imp = setup.impact
    where = setup.configuration.caption(long=True)
    return (f"{where}: a = {setup.radius * 1e3:.4g} mm, m = {imp.mass * 1e3:.4g} g, U0 = {imp.velocity:g} m/s, "
            f"K_HZ = {imp.k_hertz:.3g} N/m^1.5, contact {imp.duration * 1e6:.0f} µs, {setup.pulse.kind} pulse")


#: A balloon of a weighted level (a signal rendered per point) at more measuring points than this
#: is announced on stderr before it starts.
BALLOON_LONG_POINTS = 100_000


def _balloon(s, setup, paths, title) -> list:
    from .._jit import announce_long_work
    from ..output import render
    from .views import balloon_levels

    pulse, conf, medium = setup.pulse, setup.configuration, setup.medium
    levels = balloon_levels(s.metric, pulse, conf, medium)
    name = levels[1] if levels else render.BALLOON_FIELD_METRICS[s.metric][1]
    imp = setup.impact
    head = title or (f"{name.split(' (')[0]} at {s.distance:g} m, {s.db_range:g} dB from centre to rim; "
                     f"U0 = {imp.velocity:g} m/s, m = {imp.mass * 1e3:.4g} g, K_HZ = {imp.k_hertz:.3g} N/m^1.5")
    points = 2 * s.n_theta**2  # about, the measuring sphere's nodes (budget.balloon_estimate)
    if levels is not None and points > BALLOON_LONG_POINTS:
        announce_long_work(f"balloon: {name.split(' (')[0]} rendered at about {points:.3g} points, a long "
                           "computation (Ctrl-C stops it)")
    data = render.balloon_data(pulse, conf, medium=medium, distance=s.distance, metric=s.metric, n_theta=s.n_theta,
                               levels=levels)
    outs = []
    if paths.get("png"):
        outs.append(render.render_balloon(pulse, conf, paths["png"], db_range=s.db_range, opacity=s.opacity,
                                          title=head, data=data, medium=medium, size=s.size))
    if paths.get("vtk"):
        from ..output.vtk import write_balloon_vtk

        outs += write_balloon_vtk(pulse, conf, paths["vtk"], medium=medium, data=data)
    if paths.get("html"):
        from ..output.html import write_balloon_html

        outs.append(write_balloon_html(pulse, conf, paths["html"], medium=medium, db_range=s.db_range, title=title,
                                       data=data))
    return outs


def _snapshot(s, setup, paths, title) -> list:
    from ..field.sections import section_field
    from ..output import render

    pulse, conf, medium = setup.pulse, setup.configuration, setup.medium
    times = s.times[0] if len(s.times) == 1 else list(s.times)
    field = section_field(pulse, conf, times, medium=medium, extent=s.extent, sections=s.sections, n_u=s.n_u)
    outs = []
    if paths.get("png"):
        outs.append(render.render_snapshot(pulse, conf, times, paths["png"], clim=s.clim,
                                           title=title or annotation(setup), size=s.size, field=field))
    if paths.get("vtk"):
        from ..output.vtk import write_snapshot_vtk

        outs += write_snapshot_vtk(pulse, conf, times, paths["vtk"], field=field)
    if paths.get("html"):
        from ..output.html import write_snapshot_html

        outs.append(write_snapshot_html(pulse, conf, times, paths["html"], clim=s.clim, title=title, field=field))
    return outs


def _animation(s, setup, paths, title) -> list:
    from ..output import render
    from ..output.render.animation import animation_field

    pulse, conf, medium = setup.pulse, setup.configuration, setup.medium
    field = animation_field(pulse, conf, medium=medium, frames=s.frames, extent=s.extent, sections=s.sections,
                            n_u=s.n_u)  # once for the GIF, the MP4 and the VTK file
    outs = []
    for key in ("gif", "mp4"):
        if paths.get(key):
            outs.append(render.render_animation(pulse, conf, paths[key], fps=s.fps, clim=s.clim,
                                                title=title or annotation(setup), size=s.size, field=field))
    if paths.get("vtk"):
        from ..output.vtk import write_animation_vtk

        outs += write_animation_vtk(pulse, conf, paths["vtk"], field=field)
    return outs


_VIEWS = {"balloon": _balloon, "snapshot": _snapshot, "animation": _animation}


def render_files(view: str, settings, setup, paths: dict, *, title: str | None = None) -> list:
    """Write the files of one view; return their paths.

    Parameters
    ----------
    view : {"balloon", "snapshot", "animation"}
    settings : BalloonSettings, SnapshotSettings or AnimationSettings
    setup : acoustiviz.app.impacts.ImpactSetup
        The pulse, configuration and medium.
    paths : dict
        ``{"png"|"gif"|"mp4"|"vtk"|"html": path}`` of the files to write (absent or None: not written).
    title : str, optional
        Replaces the default caption.
    """
    return _VIEWS[view](settings, setup, paths, title)
