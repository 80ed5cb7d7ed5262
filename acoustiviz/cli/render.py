"""``acoustiviz render``: off-screen 3-D pictures of one impact (balloon, snapshot, animation).

argv -> the view's job (:func:`settings_from_args`, :mod:`acoustiviz.app.settings.render_job`) ->
:func:`acoustiviz.app.render_job.run` -> ``write`` -> the files written.
"""

from __future__ import annotations

from ..app.settings.render import ANIMATION, BALLOON, SECTION_LIST, SIZES, SNAPSHOT, TIMES, TITLE, VIEW_FILES
from ..app.settings.render_job import JOB_OF_VIEW
from ..app.settings.table import add_option
from ._impact import add_impact_options, add_room_options

_METAVARS = {"distance": "M", "db_range": "DB", "opacity": "X", "extent": "M", "clim": "PA", "fps": "F"}


def _options(p, view: str, table) -> None:
    add_impact_options(p)
    add_room_options(p, duration=True)
    g = p.add_argument_group("image")
    add_option(g, SIZES[view])
    add_option(g, TITLE)
    g = p.add_argument_group("view (SI units)")
    if view != "balloon":
        add_option(g, SECTION_LIST)
    for s in table:
        add_option(g, s, metavar=_METAVARS.get(s.name))
    if view == "snapshot":
        add_option(g, TIMES)
    g = p.add_argument_group("outputs (at least one)")
    for kind in JOB_OF_VIEW[view].FILES:
        add_option(g, VIEW_FILES[kind])


def add_parser(subparsers) -> None:
    """Register the ``render`` subcommand and its ``balloon``, ``snapshot`` and ``animation`` views."""
    p = subparsers.add_parser(
        "render", help="3-D pictures rendered off-screen: directivity balloon, field snapshot, wavefront animation",
        description="Off-screen 3-D renders with pyvista (no display needed), the data behind them as VTK "
        "files for ParaView (--vtk) and interactive self-contained HTML pages (--html). Impact, configuration "
        "and room options are those of 'acoustiviz directivity'; lengths in m, times in s.")
    views = p.add_subparsers(dest="view", metavar="VIEW")
    b = views.add_parser(
        "balloon", help="directivity balloon around the contact point (PNG, VTK, HTML)",
        description="A surface around the contact point whose radius grows with the level measured on a "
        "sphere of radius --distance (whole sphere in free field, half space above the plane, quarter space "
        "in the wall-floor corner), coloured by the same level; the sphere, floor and wall drawn in.")
    _options(b, "balloon", BALLOON)
    s = views.add_parser(
        "snapshot", help="pressure p(x, t) on planes through the sphere at given times (PNG, VTK, HTML)",
        description="The pressure field on planes through the sphere at one or more times after the start of "
        "contact, diverging colours centred on zero; several times go side by side with one colour scale.")
    _options(s, "snapshot", SNAPSHOT)
    a = views.add_parser(
        "animation", help="the wavefront leaving the impact and reflecting (GIF, MP4 with imageio-ffmpeg, VTK)",
        description="Frames of the pressure on planes through the sphere, from the impact until the last "
        "wavefront (image sources included) has crossed the planes, with a fixed colour range. Each frame "
        "evaluates the field only where it is non-zero.")
    _options(a, "animation", ANIMATION)
    for q in (p, b, s, a):
        q.set_defaults(func=run)


def settings_from_args(args):
    """The view's job (:mod:`acoustiviz.app.settings.render_job`) of the options; errors name the options."""
    from ..app.render import check_view_outputs
    from ._impact import impact_from_args, room_duration

    cls = JOB_OF_VIEW[args.view]
    names = cls.names_for("cli")
    check_view_outputs({k: getattr(args, k) for k in cls.FILES})  # the command writes at least one file
    room_duration(args)
    setup = impact_from_args(args)
    values = {s.name: getattr(args, s.option[2:].replace("-", "_")) for s in cls.TABLE}
    return cls(**values, impact=setup.impact, pulse=setup.pulse, medium=setup.medium,
               geometry=setup.geometry, max_memory_mb=getattr(args, "max_memory", None),
               k_hertz_source=setup.k_hertz_source, names=names)


def run(args) -> int:
    """Render the requested view; return the exit status."""
    import sys

    from ..app.render_job import run as run_job

    if not getattr(args, "view", None):
        print("acoustiviz render: error: choose a view: balloon, snapshot or animation", file=sys.stderr)
        return 2
    settings = settings_from_args(args)
    try:
        result = run_job(settings)
        written = result.write()
    except RuntimeError as exc:  # no off-screen rendering back-end
        print(f"acoustiviz render: error: {exc}", file=sys.stderr)
        return 1
    for out in written:
        print(f"wrote {out}")
    return 0
