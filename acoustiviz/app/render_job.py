"""The render jobs: a snapshot, a balloon or an animation of one impact, computed once and written to every file.

Three parts, shared by ``acoustiviz render snapshot|balloon|animation``, a scene's
``[outputs.snapshot|balloon|animation]`` and Python callers:

* :class:`~acoustiviz.app.settings.render_job.SnapshotJob`, :class:`~acoustiviz.app.settings.render_job.BalloonJob`
  and :class:`~acoustiviz.app.settings.render_job.AnimationJob`, the settings, checked once when made;
* :func:`run`, which computes the view's data once (physics only: no files);
* ``Result.write``, which hands that one value to every file asked for (PNG, GIF, MP4, VTK, HTML).

Examples
--------
>>> from acoustiviz.app.impacts import impact_setup
>>> s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config="plane")
>>> job = SnapshotJob(impact=s.impact, pulse=s.pulse, medium=s.medium, geometry=s.geometry,
...                   times=(0.5e-3, 1e-3), n_u=41)
>>> run(job).field.pressures[0].shape  # (times, points of the xz section)
(2, 902)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .settings.render_job import JOB_OF_VIEW, AnimationJob, BalloonJob, SnapshotJob

__all__ = ["SnapshotJob", "BalloonJob", "AnimationJob", "SnapshotResult", "BalloonResult", "AnimationResult", "run",
           "view_values", "view_job", "snapshot_settings", "balloon_settings", "animation_settings",
           "produce_snapshot", "produce_balloon", "produce_animation", "BALLOON_LONG_POINTS"]

#: A balloon of a weighted level (a signal rendered per point) at more measuring points than this
#: is announced on stderr before it starts.
BALLOON_LONG_POINTS = 100_000


def _paths(settings, folder) -> dict:
    """``{kind: Path}`` of the files asked for, relative names put in ``folder``."""
    return {k: Path(v) if folder is None else Path(folder) / v for k, v in settings.files().items()}


@dataclass(frozen=True, eq=False)
class SnapshotResult:
    """The snapshot of a :class:`SnapshotJob`.

    Attributes
    ----------
    settings : SnapshotJob
        What was computed.
    field : acoustiviz.field.sections.SectionField
        The planes (m), the times (s) and the pressure on them (Pa), read-only.
    """

    settings: SnapshotJob
    field: object

    def write(self, folder=None) -> list:
        """Write the PNG, the VTK file (and its ``_geometry.vtu``) and the HTML page asked for; return their paths.

        Every file is drawn or exported from the one :attr:`field`, atomically.
        """
        from ..output import render

        s, f, files = self.settings, self.field, _paths(self.settings, folder)
        out = []
        if "png" in files:
            out.append(render.render_snapshot(f, s.pulse, s.geometry, files["png"], clim=s.clim,
                                              title=s.title or s.caption(), size=s.size))
        if "vtk" in files:
            from ..output.vtk import write_snapshot_vtk

            out += write_snapshot_vtk(f, s.geometry, files["vtk"])
        if "html" in files:
            from ..output.html import write_snapshot_html

            out.append(write_snapshot_html(f, s.pulse, s.geometry, files["html"], clim=s.clim, title=s.title))
        return [Path(p) for p in out]


@dataclass(frozen=True, eq=False)
class BalloonResult:
    """The balloon of a :class:`BalloonJob`.

    Attributes
    ----------
    settings : BalloonJob
        What was computed.
    data : acoustiviz.field.balloon.BalloonData
        The level in dB over the measuring sphere (directions, distance in m), and every metric of the
        field there when the VTK file wants them (a weighted level's too).
    """

    settings: BalloonJob
    data: object

    def title(self) -> str:
        """The picture's caption: the level, the distance, the range, the speed, the mass and K_HZ."""
        s = self.settings
        if s.title:
            return s.title
        imp = s.impact
        return (f"{self.data.label.split(' (')[0]} at {s.distance:g} m, {s.db_range:g} dB from centre to rim; "
                f"U0 = {imp.velocity:g} m/s, m = {imp.mass * 1e3:.4g} g, K_HZ = {imp.k_hertz:.3g} N/m^1.5")

    def write(self, folder=None) -> list:
        """Write the PNG, the VTK file (and its ``_geometry.vtu``) and the HTML page asked for; return their paths.

        Every file is drawn or exported from the one :attr:`data`, atomically.
        """
        from ..output import render

        s, d, files = self.settings, self.data, _paths(self.settings, folder)
        out = []
        if "png" in files:
            out.append(render.render_balloon(d, s.pulse, s.geometry, files["png"], db_range=s.db_range,
                                             opacity=s.opacity, title=self.title(), size=s.size))
        if "vtk" in files:
            from ..output.vtk import write_balloon_vtk

            out += write_balloon_vtk(d, s.geometry, files["vtk"])
        if "html" in files:
            from ..output.html import write_balloon_html

            out.append(write_balloon_html(d, s.pulse, s.geometry, files["html"], db_range=s.db_range,
                                          title=s.title))
        return [Path(p) for p in out]


@dataclass(frozen=True, eq=False)
class AnimationResult:
    """The frames of an :class:`AnimationJob`.

    Attributes
    ----------
    settings : AnimationJob
        What was computed.
    field : acoustiviz.field.sections.SectionField
        The planes (m), the frame times (s) and the pressure on them (Pa), read-only.
    """

    settings: AnimationJob
    field: object

    def write(self, folder=None) -> list:
        """Write the GIF, the MP4 and the VTK file (and its ``_geometry.vtu``) asked for; return their paths.

        Every file is drawn or exported from the one :attr:`field`, atomically.
        """
        from ..output import render

        s, f, files = self.settings, self.field, _paths(self.settings, folder)
        out = []
        for key in ("gif", "mp4"):
            if key in files:
                out.append(render.render_animation(f, s.pulse, s.geometry, files[key], fps=s.fps, clim=s.clim,
                                                   title=s.title or s.caption(), size=s.size))
        if "vtk" in files:
            from ..output.vtk import write_animation_vtk

            out += write_animation_vtk(f, s.geometry, files["vtk"])
        return [Path(p) for p in out]


def run(settings):
    """Compute the data of a render job once (no files).

    Parameters
    ----------
    settings : SnapshotJob, BalloonJob or AnimationJob
        The job, checked when it was made.

    Returns
    -------
    SnapshotResult, BalloonResult or AnimationResult
    """
    from .names import user_terms

    with user_terms(settings.names):  # an error of the physics in the front end's words
        return _RUNS[settings.VIEW](settings)


def _snapshot(s: SnapshotJob) -> SnapshotResult:
    from ..field.sections import section_field

    return SnapshotResult(s, section_field(s.pulse, s.geometry, list(s.times), medium=s.medium, extent=s.extent,
                                           sections=s.sections, n_u=s.n_u))


def _balloon(s: BalloonJob) -> BalloonResult:
    from .._jit import announce_long_work
    from ..field.balloon import BALLOON_FIELD_METRICS, balloon_data, balloon_metrics
    from .views import balloon_levels

    levels = balloon_levels(s.metric, s.pulse, s.geometry, s.medium)
    points = 2 * s.n_theta**2  # about, the measuring sphere's nodes (budget.balloon_estimate)
    if levels is not None and points > BALLOON_LONG_POINTS:
        name = levels[1] if levels else BALLOON_FIELD_METRICS[s.metric][1]
        announce_long_work(f"balloon: {name.split(' (')[0]} rendered at about {points:.3g} points, a long "
                           "computation (Ctrl-C stops it)")
    data = balloon_data(s.pulse, s.geometry, medium=s.medium, distance=s.distance, metric=s.metric,
                        n_theta=s.n_theta, levels=levels)
    if s.vtk is not None:  # a weighted level: the VTK file's metrics too, here, once
        data = balloon_metrics(s.pulse, s.geometry, data, medium=s.medium)
    return BalloonResult(s, data)


def _animation(s: AnimationJob) -> AnimationResult:
    from ..field.sections import animation_field

    return AnimationResult(s, animation_field(s.pulse, s.geometry, medium=s.medium, frames=s.frames,
                                              extent=s.extent, sections=s.sections, n_u=s.n_u))


_RUNS = {"snapshot": _snapshot, "balloon": _balloon, "animation": _animation}


# --------------------------------------------------------------------------- scenes
def view_values(scene, view: str) -> dict:
    """The settings of view ``view`` a scene gives (``{API name: value}``), read through the job's records.

    Each record with a scene key reads its table (``grids.sphere``, ``grids.plane`` or ``outputs.<view>``;
    an output the scene does not ask for gives its defaults).
    """
    values = {}
    for s in JOB_OF_VIEW[view].TABLE:
        if s.key:
            section, _, sub = s.table.partition(".")
            table = scene.output_or_defaults(sub) if section == "outputs" else scene.data[section][sub]
            value = table[s.key]
            values[s.name] = tuple(value) if isinstance(value, list) else value
    return values


def view_job(scene, view: str, out=None):
    """The scene's ``[outputs.<view>]`` as the view's job; errors name scene keys.

    The files are ``<view>.png`` (an animation's ``animation.gif``) and, with ``vtk = true`` and
    ``html = true``, ``<view>.vtu`` and ``<view>.html`` in folder ``out`` (None: no files, the checks
    of the scene's settings alone, made before the run folder exists).
    """
    cls = JOB_OF_VIEW[view]
    setup, opts = scene.setup(), scene.output_or_defaults(view)
    files = {}
    if out is not None:
        first = cls.FILES[0]
        files[first] = str(Path(out) / f"{view}.{first}")
        for kind, ending in (("vtk", "vtu"), ("html", "html")):
            if opts.get(kind):
                files[kind] = str(Path(out) / f"{view}.{ending}")
    names = cls.names_for("scene")
    return cls(**view_values(scene, view), impact=setup.impact, pulse=setup.pulse, medium=setup.medium,
               geometry=setup.geometry, max_memory_mb=scene.section("grids")["memory_limit_mb"],
               k_hertz_source=setup.k_hertz_source, names=names, **files)


def snapshot_settings(scene, out=None) -> SnapshotJob:
    """The scene's ``[outputs.snapshot]`` as a :class:`SnapshotJob` (:func:`view_job`)."""
    return view_job(scene, "snapshot", out)


def balloon_settings(scene, out=None) -> BalloonJob:
    """The scene's ``[outputs.balloon]`` as a :class:`BalloonJob` (:func:`view_job`)."""
    return view_job(scene, "balloon", out)


def animation_settings(scene, out=None) -> AnimationJob:
    """The scene's ``[outputs.animation]`` as an :class:`AnimationJob` (:func:`view_job`)."""
    return view_job(scene, "animation", out)


def _produce(ctx, view: str, say, figures) -> list:
    """Run and write the scene's ``view``; the products, the first with the result's ``figures``.

    ``say(settings)`` and ``figures(result)`` give the progress line and the summary's figures.
    """
    from .products import Product

    settings = view_job(ctx.scene, view, ctx.out)
    for path in settings.files().values():  # only the files checked before the run
        ctx.path(Path(path).name)
    ctx.progress(say(settings))
    result = run(settings)
    products = []
    for path in result.write():
        kind = "vtk" if path.suffix == ".vtu" else "html" if path.suffix == ".html" else view
        products.append(Product(kind, path, figures(result) if not products else {}))
    return products


def produce_snapshot(ctx) -> list:
    """Scene output ``snapshot``: the pressure on the planar sections at the requested times."""
    return _produce(ctx, "snapshot", lambda s: f"rendering {len(s.times)} snapshot(s)",
                    lambda r: {"times_ms": ", ".join(f"{1e3 * t:g}" for t in r.settings.times)})


def produce_balloon(ctx) -> list:
    """Scene output ``balloon``: the 3-D directivity balloon on the spherical grid around the contact point."""
    return _produce(ctx, "balloon", lambda s: f"rendering the balloon ({s.metric} at {s.distance:g} m)",
                    lambda r: {"metric": r.settings.metric, "max_db": f"{r.data.max_level:.1f}",
                               "mean_db": f"{r.data.mean_level:.1f}", "distance_m": f"{r.settings.distance:g}"})


def produce_animation(ctx) -> list:
    """Scene output ``animation``: a GIF of the wavefront leaving the impact and reflecting."""
    return _produce(ctx, "animation", lambda s: f"rendering {s.frames} animation frames",
                    lambda r: {"frames": str(r.settings.frames), "fps": f"{r.settings.fps:g}"})
