"""``acoustiviz render``: off-screen 3-D pictures of one impact (balloon, snapshot, animation)."""

from __future__ import annotations

from ..app.settings.render import ANIMATION, BALLOON, SNAPSHOT
from ..app.settings.table import add_option
from ..constants import ANIMATION_SIZE, MAX_SNAPSHOT_TIMES, STILL_SIZE
from ._impact import add_impact_options, add_room_options

#: Output options of the views.
_OUTPUTS = ("png", "gif", "mp4", "vtk", "html")
#: Settings fields without a table entry -> their option.
_MORE_NAMES = {"size": "--size", "times": "--time", "time": "--time", "sections": "--sections"}
_METAVARS = {"distance": "M", "db_range": "DB", "opacity": "X", "extent": "M", "clim": "PA", "fps": "F"}


#: ``--size`` default of the still views, as typed.
_STILL = "{}x{}".format(*STILL_SIZE)

def _options(p, table, *, size: str) -> None:
    add_impact_options(p)
    add_room_options(p, duration=True)
    g = p.add_argument_group("image")
    g.add_argument("--size", default=size, metavar="WxH",
                   help="image size in pixels, width x height, each 64..8192 (default %(default)s)")
    g.add_argument("--title", default=None, metavar="TEXT", help="replace the default annotation")
    g = p.add_argument_group("view (SI units)")
    if table is not BALLOON:
        g.add_argument("--sections", default="xz", metavar="LIST",
                       help="comma-separated planes through the sphere: xz (vertical, normal to the wall), yz "
                            "(vertical, parallel to the wall), xy (horizontal through the centre) "
                            "(default %(default)s)")
    for s in table:
        add_option(g, s, metavar=_METAVARS.get(s.name))


def _outputs(p, *, png: bool, html: bool, movie: bool = False) -> None:
    g = p.add_argument_group("outputs (at least one)")
    if png:
        g.add_argument("--png", default=None, metavar="PATH", help="output image")
    if movie:
        g.add_argument("--gif", default=None, metavar="PATH", help="output GIF")
        g.add_argument("--mp4", default=None, metavar="PATH", help="output MP4 (needs imageio-ffmpeg)")
    g.add_argument("--vtk", default=None, metavar="PATH",
                   help="the data behind the picture for ParaView, pyvista or meshio: a .vtu (or .vtkhdf) file, "
                        "with the sphere and planes beside it in PATH_geometry.vtu")
    if html:
        g.add_argument("--html", default=None, metavar="PATH",
                       help="an interactive 3-D view in one self-contained HTML file (no server needed)")


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
    _options(b, BALLOON, size=_STILL)
    _outputs(b, png=True, html=True)
    s = views.add_parser(
        "snapshot", help="pressure p(x, t) on planes through the sphere at given times (PNG, VTK, HTML)",
        description="The pressure field on planes through the sphere at one or more times after the start of "
        "contact, diverging colours centred on zero; several times go side by side with one colour scale.")
    _options(s, SNAPSHOT, size=_STILL)
    s.add_argument("--time", type=float, nargs="+", default=[0.001], metavar="S",
                   help=f"snapshot time(s) in s from the start of contact, at most {MAX_SNAPSHOT_TIMES}, "
                   "each in [0, 10] (default 0.001)")
    _outputs(s, png=True, html=True)
    a = views.add_parser(
        "animation", help="the wavefront leaving the impact and reflecting (GIF, MP4 with imageio-ffmpeg, VTK)",
        description="Frames of the pressure on planes through the sphere, from the impact until the last "
        "wavefront (image sources included) has crossed the planes, with a fixed colour range. Each frame "
        "evaluates the field only where it is non-zero.")
    _options(a, ANIMATION, size="{}x{}".format(*ANIMATION_SIZE))
    _outputs(a, png=False, html=False, movie=True)
    for q in (p, b, s, a):
        q.set_defaults(func=run)


def _settings(args):
    """The view's settings object from the options (errors name the options)."""
    from ..app.names import user_terms
    from ..app.settings.parse import parse_size
    from ..app.settings.render import SETTINGS_OF_VIEW

    cls = SETTINGS_OF_VIEW[args.view]
    values = {s.name: getattr(args, s.option[2:].replace("-", "_")) for s in cls.TABLE}
    values["size"] = parse_size(args.size, "--size")
    if args.view != "balloon":
        values["sections"] = tuple(n.strip() for n in str(args.sections).split(",") if n.strip())
    if args.view == "snapshot":
        values["times"] = tuple(args.time)
    with user_terms({**cls.cli_names(), **_MORE_NAMES}):
        return cls.from_values(values)


def run(args) -> int:
    """Render the requested view; return the exit status."""
    import sys

    from ..app.budget import check_budget
    from ..app.names import user_terms
    from ..app.outputs import check_distinct, check_output_file
    from ..app.render import check_view_fits, check_view_outputs, render_estimate, render_files
    from ._impact import impact_from_args, room_duration

    if not getattr(args, "view", None):
        print("acoustiviz render: error: choose a view: balloon, snapshot or animation", file=sys.stderr)
        return 2
    settings = _settings(args)
    room_duration(args)
    paths = check_view_outputs({k: getattr(args, k) for k in _OUTPUTS if hasattr(args, k)})
    if args.view == "animation" and paths.get("mp4"):
        from .._validate import ParameterError
        from ..output.render import mp4_available

        if not mp4_available():
            raise ParameterError("--mp4", "writing MP4 needs imageio and imageio-ffmpeg ('pip install "
                                          "imageio-ffmpeg'); use --gif instead")
    for k, path in paths.items():
        check_output_file(f"--{k}", path, k)
    files = {f"--{k}": v for k, v in paths.items()}
    if paths.get("vtk"):  # the sphere and planes beside the data (OUT_geometry.vtu)
        from ..output.vtk import geometry_path

        files["--vtk (geometry)"] = check_output_file("--vtk", geometry_path(paths["vtk"]), "vtk")
    check_distinct(files)
    setup = impact_from_args(args)
    n_files = bool(paths.get("gif")) + bool(paths.get("mp4"))
    names = {**type(settings).cli_names(), **_MORE_NAMES}
    with user_terms(names):
        check_view_fits(args.view, settings, setup)  # a balloon's sphere inside a room's walls
    est = render_estimate(args.view, settings, len(setup.configuration.images()), n_files=n_files, options=names)
    check_budget(est, getattr(args, "max_memory", None))
    try:
        with user_terms(names):
            outputs = render_files(args.view, settings, setup, paths, title=args.title)
    except RuntimeError as exc:
        print(f"acoustiviz render: error: {exc}", file=sys.stderr)
        return 1
    for out in outputs:
        print(f"wrote {out}")
    return 0
