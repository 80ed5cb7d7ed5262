"""``acoustiviz render``: off-screen 3-D pictures of one impact (balloon, snapshot, animation)."""

from __future__ import annotations

from ..constants import BALLOON_METRICS
from ._impact import add_impact_options, add_room_options

#: Library parameter names -> the option that sets them, for error messages.
_OPTION = {
    "size": "--size",
    "distance": "--distance",
    "metric": "--metric",
    "db_range": "--db-range",
    "n_theta": "--resolution",
    "n_u": "--resolution",
    "opacity": "--opacity",
    "time": "--time",
    "times": "--time",
    "extent": "--extent",
    "sections": "--sections",
    "clim": "--clim",
    "frames": "--frames",
    "fps": "--fps",
}


def _common(p, *, size: str) -> None:
    add_impact_options(p)
    add_room_options(p, duration=True)
    g = p.add_argument_group("image")
    g.add_argument("--size", default=size, metavar="WxH",
                   help="image size in pixels, width x height, each 64..8192 (default %(default)s)")
    g.add_argument("--title", default=None, metavar="TEXT", help="replace the default annotation")


def _section_options(p, *, resolution: int) -> None:
    g = p.add_argument_group("field planes")
    g.add_argument("--sections", default="xz", metavar="LIST",
                   help="comma-separated planes through the sphere: xz (vertical, normal to the wall), yz "
                        "(vertical, parallel to the wall), xy (horizontal through the centre) (default %(default)s)")
    g.add_argument("--extent", type=float, default=None, metavar="M",
                   help="distance in m from the sphere's centre to the far edges of the planes (default: 1.25 x "
                        "the distance sound travels by the last time)")
    g.add_argument("--resolution", type=int, default=resolution, metavar="N",
                   help="points along the longer side of each plane, 8..2001 (default %(default)s)")
    g.add_argument("--clim", type=float, default=None, metavar="PA",
                   help="colour limit in Pa; the diverging map spans [-PA, PA] (default: from the field)")


def _output_options(p, *, png: bool, html: bool) -> None:
    g = p.add_argument_group("outputs (at least one)")
    if png:
        g.add_argument("--png", default=None, metavar="PATH", help="output image")
    g.add_argument("--vtk", default=None, metavar="PATH",
                   help="the data behind the picture for ParaView, pyvista or meshio: a .vtu (or .vtkhdf) file, "
                        "with the sphere and planes beside it in PATH_geometry.vtu")
    if html:
        g.add_argument("--html", default=None, metavar="PATH",
                       help="an interactive 3-D view in one self-contained HTML file (no server needed)")


def add_parser(subparsers) -> None:
    """Register the ``render`` subcommand and its ``balloon``, ``snapshot`` and ``animation`` views."""
    p = subparsers.add_parser(
        "render",
        help="3-D pictures rendered off-screen: directivity balloon, field snapshot, wavefront animation",
        description="Off-screen 3-D renders with pyvista (no display needed), the data behind them as VTK "
        "files for ParaView (--vtk) and interactive self-contained HTML pages (--html). Impact, configuration "
        "and room options are those of 'acoustiviz directivity'; lengths in m, times in s.",
    )
    views = p.add_subparsers(dest="view", metavar="VIEW")

    b = views.add_parser(
        "balloon",
        help="directivity balloon around the contact point (PNG, VTK, HTML)",
        description="A surface around the contact point whose radius grows with the level measured on a "
        "sphere of radius --distance (whole sphere in free field, half space above the plane, quarter space "
        "in the wall-floor corner), coloured by the same level; the sphere, floor and wall drawn in.",
    )
    _common(b, size="1200x900")
    g = b.add_argument_group("balloon")
    g.add_argument("--distance", type=float, default=0.7, metavar="M",
                   help="radius in m of the measuring sphere around the contact point (default %(default)s)")
    g.add_argument("--metric", default="peak", choices=BALLOON_METRICS,
                   help="peak SPL, RMS level or sound exposure level of the closed form, or a weighted level of "
                        "the pressure band-limited at 96 kHz (IEC 61672-1: lcpeak, lafmax, laeq = LAeq,1s, sel-a, "
                        "...), all dB re 20 uPa (default %(default)s)")
    g.add_argument("--db-range", type=float, default=30.0, metavar="DB",
                   help="level range in dB from the balloon's centre to its largest radius (default %(default)s)")
    g.add_argument("--resolution", type=int, default=32, metavar="N",
                   help="polar nodes of the measuring grid, 4..512 (default %(default)s)")
    g.add_argument("--opacity", type=float, default=0.7, metavar="X",
                   help="balloon opacity in (0, 1]; below 1 the sphere shows through (default %(default)s)")
    _output_options(b, png=True, html=True)
    b.set_defaults(func=run)

    s = views.add_parser(
        "snapshot",
        help="pressure p(x, t) on planes through the sphere at given times (PNG, VTK, HTML)",
        description="The pressure field on planes through the sphere at one or more times after the start of "
        "contact, diverging colours centred on zero; several times go side by side with one colour scale.",
    )
    _common(s, size="1200x900")
    s.add_argument("--time", type=float, nargs="+", default=[0.001], metavar="S",
                   help="snapshot time(s) in s from the start of contact (default 0.001)")
    _section_options(s, resolution=241)
    _output_options(s, png=True, html=True)
    s.set_defaults(func=run)

    a = views.add_parser(
        "animation",
        help="the wavefront leaving the impact and reflecting (GIF, MP4 with imageio-ffmpeg, VTK)",
        description="Frames of the pressure on planes through the sphere, from the impact until the last "
        "wavefront (image sources included) has crossed the planes, with a fixed colour range. Each frame "
        "evaluates the field only where it is non-zero.",
    )
    _common(a, size="800x600")
    a.add_argument("--frames", type=int, default=48, metavar="N",
                   help="number of frames, 2..2000 (default %(default)s)")
    a.add_argument("--fps", type=float, default=12.0, metavar="F",
                   help="frames per second, (0, 60] (default %(default)s)")
    _section_options(a, resolution=201)
    a.add_argument("--gif", default=None, metavar="PATH", help="output GIF")
    a.add_argument("--mp4", default=None, metavar="PATH", help="output MP4 (needs imageio-ffmpeg)")
    _output_options(a, png=False, html=False)
    a.set_defaults(func=run)
    p.set_defaults(func=run)


def parse_size(text: str) -> tuple:
    """``"1200x900"`` -> ``(1200, 900)``; a ParameterError naming ``--size`` otherwise."""
    from .._validate import ParameterError

    parts = str(text).lower().replace("×", "x").split("x")
    try:
        if len(parts) != 2:
            raise ValueError
        w, h = int(parts[0]), int(parts[1])
    except ValueError:
        raise ParameterError("--size", f"expected WIDTHxHEIGHT in pixels, e.g. 1200x900, got {text!r}") from None
    if not (64 <= w <= 8192 and 64 <= h <= 8192):
        raise ParameterError("--size", f"width and height must lie in [64, 8192] px, got {w}x{h}")
    return w, h


def _sections(text: str) -> tuple:
    from .._validate import ParameterError

    names = tuple(s.strip() for s in str(text).split(",") if s.strip())
    bad = [n for n in names if n not in ("xz", "yz", "xy")]
    if not names or bad or len(set(names)) != len(names):
        raise ParameterError("--sections", f"expected a comma-separated subset of xz,yz,xy, got {text!r}")
    return names


def _check_outputs(args) -> None:
    """At least one output, each with its file name ending."""
    from .._validate import ParameterError

    endings = {"png": (".png",), "gif": (".gif",), "mp4": (".mp4",), "vtk": (".vtu", ".vtkhdf"),
               "html": (".html", ".htm")}
    given = [k for k in endings if getattr(args, k, None)]
    if not given:
        offered = [f"--{k}" for k in endings if hasattr(args, k)]
        raise ParameterError(offered[0], f"give at least one output: {', '.join(offered)}")
    for k in given:
        path = str(getattr(args, k))
        if not path.lower().endswith(endings[k]):
            raise ParameterError(f"--{k}", f"expected a file name ending in {' or '.join(endings[k])}, got {path!r}")


def _check_common(args):
    """Validate the render options before any work; return the image size."""
    import math

    from .._validate import ParameterError, check_range
    from ..app.impacts import MAX_DISTANCE
    from ._impact import room_duration

    size = parse_size(args.size)
    _check_outputs(args)
    room_duration(args)
    if args.view == "balloon":
        check_range("--db-range", args.db_range, 0.0, 200.0, unit="dB", low_open=True)
        check_range("--opacity", args.opacity, 0.0, 1.0, low_open=True)
        if not 4 <= args.resolution <= 512:
            raise ParameterError("--resolution", f"must lie in [4, 512], got {args.resolution}")
        check_range("--distance", args.distance, 0.0, MAX_DISTANCE, unit="m", low_open=True)
        return size
    if not 8 <= args.resolution <= 2001:
        raise ParameterError("--resolution", f"must lie in [8, 2001], got {args.resolution}")
    if args.extent is not None:
        check_range("--extent", args.extent, 0.0, MAX_DISTANCE, unit="m", low_open=True)
    if args.clim is not None:
        check_range("--clim", args.clim, 0.0, math.inf, unit="Pa", low_open=True)
    _sections(args.sections)
    if args.view == "snapshot":
        if len(args.time) > 12:
            raise ParameterError("--time", f"at most 12 times, got {len(args.time)}")
        for t in args.time:
            check_range("--time", t, 0.0, 10.0, unit="s")
    else:
        if not 2 <= args.frames <= 2000:
            raise ParameterError("--frames", f"must lie in [2, 2000], got {args.frames}")
        check_range("--fps", args.fps, 0.0, 60.0, unit="frames/s", low_open=True)
        if args.mp4:
            from ..output.render import mp4_available

            if not mp4_available():
                raise ParameterError("--mp4", "writing MP4 needs imageio and imageio-ffmpeg "
                                              "('pip install imageio-ffmpeg'); use --gif instead")
    return size


def _annotation(setup) -> str:
    imp = setup.impact
    conf = setup.configuration
    where = conf.caption(long=True)
    return (f"{where}: a = {setup.radius * 1e3:.4g} mm, m = {imp.mass * 1e3:.4g} g, U0 = {imp.velocity:g} m/s, "
            f"K_HZ = {imp.k_hertz:.3g} N/m^1.5, contact {imp.duration * 1e6:.0f} µs, {setup.pulse.kind} pulse")


def run(args) -> int:
    """Render the requested view; return the exit status."""
    import sys

    from ..app.names import user_terms

    if not getattr(args, "view", None):
        print("acoustiviz render: error: choose a view: balloon, snapshot or animation", file=sys.stderr)
        return 2
    size = _check_common(args)
    from ..app.budget import animation_estimate, balloon_estimate, check_budget, snapshot_estimate
    from ..app.outputs import check_distinct, check_output_file
    from ..core.reach import check_view_radius
    from ._impact import impact_from_args

    outputs = {f"--{k}": getattr(args, k, None) for k in ("png", "gif", "mp4", "vtk", "html")}
    for opt, path in outputs.items():
        if path:
            check_output_file(opt, path, opt[2:])
    check_distinct({k: v for k, v in outputs.items() if v})
    setup = impact_from_args(args)
    n_src = len(setup.configuration.images())
    if args.view == "balloon":  # the measuring sphere inside a room's walls, before any work
        with user_terms({"distance": "--distance"}):
            check_view_radius(setup.configuration, args.distance, 2.1 * setup.radius)
        est = balloon_estimate(args.resolution, size, n_src)
    elif args.view == "snapshot":
        est = snapshot_estimate(args.resolution, len(_sections(args.sections)), len(args.time), size, n_src)
    else:
        n_files = bool(args.gif) + bool(args.mp4)
        est = animation_estimate(args.frames * n_files, args.resolution, len(_sections(args.sections)), size, n_src)
    check_budget(est, getattr(args, "max_memory", None))
    try:
        with user_terms(_OPTION):
            outputs = _render(args, setup, size)
    except RuntimeError as exc:
        print(f"acoustiviz render: error: {exc}", file=sys.stderr)
        return 1
    for out in outputs:
        print(f"wrote {out}")
    return 0


def _render(args, setup, size) -> list:
    from ..output import render

    common = dict(medium=setup.medium, size=size)
    title = args.title
    outs = []
    if args.view == "balloon":
        imp = setup.impact
        from ..app.views import balloon_levels

        levels = balloon_levels(args.metric, setup.pulse, setup.configuration, setup.medium)
        name = levels[1] if levels else render.METRICS[args.metric][1]
        head = title or (f"{name.split(' (')[0]} at {args.distance:g} m, "
                         f"{args.db_range:g} dB from centre to rim; U0 = {imp.velocity:g} m/s, "
                         f"m = {imp.mass * 1e3:.4g} g, K_HZ = {imp.k_hertz:.3g} N/m^1.5")
        data = render.balloon_data(setup.pulse, setup.configuration, medium=setup.medium, distance=args.distance,
                                   metric=args.metric, n_theta=args.resolution, levels=levels)
        if args.png:
            outs.append(render.render_balloon(setup.pulse, setup.configuration, args.png, db_range=args.db_range,
                                              opacity=args.opacity, title=head, data=data, **common))
        if args.vtk:
            from ..output.vtk import write_balloon_vtk

            outs += write_balloon_vtk(setup.pulse, setup.configuration, args.vtk, medium=setup.medium, data=data)
        if args.html:
            from ..output.html import write_balloon_html

            outs.append(write_balloon_html(setup.pulse, setup.configuration, args.html, medium=setup.medium,
                                           db_range=args.db_range, title=title, data=data))
        return outs
    planes = dict(extent=args.extent, sections=_sections(args.sections), n_u=args.resolution)
    if args.view == "snapshot":
        times = args.time[0] if len(args.time) == 1 else args.time
        if args.png:
            outs.append(render.render_snapshot(setup.pulse, setup.configuration, times, args.png, clim=args.clim,
                                               title=title or _annotation(setup), **planes, **common))
        if args.vtk:
            from ..output.vtk import write_snapshot_vtk

            outs += write_snapshot_vtk(setup.pulse, setup.configuration, times, args.vtk, medium=setup.medium,
                                       **planes)
        if args.html:
            from ..output.html import write_snapshot_html

            outs.append(write_snapshot_html(setup.pulse, setup.configuration, times, args.html, medium=setup.medium,
                                            clim=args.clim, title=title, **planes))
        return outs
    for path in (args.gif, args.mp4):
        if path:
            outs.append(render.render_animation(setup.pulse, setup.configuration, path, frames=args.frames,
                                                fps=args.fps, clim=args.clim, title=title or _annotation(setup),
                                                **planes, **common))
    if args.vtk:
        from ..output.vtk import write_animation_vtk

        outs += write_animation_vtk(setup.pulse, setup.configuration, args.vtk, medium=setup.medium,
                                    frames=args.frames, **planes)
    return outs
