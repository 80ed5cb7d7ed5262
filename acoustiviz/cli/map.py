"""``acoustiviz map``: peak SPL and SEL of one impact over a plane (PNG, CSV, VTK).

argv -> :class:`~acoustiviz.app.settings.map_job.MapJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.maps.run` -> :meth:`~acoustiviz.app.maps.MapResult.write` -> the summary.
"""

from __future__ import annotations

import sys

from ..app.settings.map import MAP_SETTINGS
from ..app.settings.map_job import MAP_OUTPUTS
from ..app.settings.table import add_option
from ._impact import add_impact_options, add_room_options


def add_parser(subparsers) -> None:
    """Register the ``map`` subcommand."""
    p = subparsers.add_parser(
        "map",
        help="peak SPL and SEL of one impact over a plane: where it is loud (PNG, CSV, VTK)",
        description="Peak sound pressure level (dB re 20 uPa) and sound exposure level (dB re (20 uPa)^2 s) "
        "of one impact at every point of a plane through the scene, from the continuous pressure in closed "
        "form (no time steps). Points inside the sphere are left blank; the map is cut at the floor and "
        "the wall. Impact, configuration and room options are those of 'acoustiviz waveform' (in a room "
        "the levels hold every image that arrives within --duration); lengths in m.",
    )
    add_impact_options(p)
    add_room_options(p, duration=True)
    g = p.add_argument_group("map plane")
    for s in MAP_SETTINGS:
        add_option(g, s)
    o = p.add_argument_group("outputs")
    for s in MAP_OUTPUTS:
        add_option(o, s)
    p.set_defaults(func=run)


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.map_job.MapJob` of the options; errors name the options."""
    from ..app.settings.map_job import MapJob
    from ._impact import impact_from_args, room_duration

    room_duration(args)  # --duration with --room only, and required there
    setup = impact_from_args(args)
    names = MapJob.names_for("cli")
    return MapJob(impact=setup.impact, pulse=setup.pulse, medium=setup.medium, geometry=setup.geometry,
                  plane=args.plane,
                  height=args.plane_height, extent=args.extent, resolution=args.resolution,
                  max_memory_mb=getattr(args, "max_memory", None), png=args.png, csv=args.csv, vtk=args.vtk,
                  k_hertz_source=setup.k_hertz_source, names=names)


def run(args) -> int:
    """Check every input and output, compute the map, print a summary and write the requested files."""
    import time

    from ..app.map_job import run as run_job
    from ..app.maps import points_bar

    settings = settings_from_args(args)
    t0 = time.perf_counter()
    with points_bar(sys.stderr) as bar:
        result = run_job(settings, progress=bar)
    for line in _summary_lines(result, time.perf_counter() - t0):
        print(line)
    for path in result.write():
        print(f"wrote {path}")
    return 0


def _summary_lines(result, seconds: float) -> list:
    """The impact, the grid and the ranges of peak SPL and SEL with where each is largest."""
    import numpy as np

    from ..app.maps import map_title

    s, level = result.settings, result.level
    imp, g = s.impact, level.grid
    ok = np.isfinite(level.peak_pa)
    a, b = level.in_plane()
    lines = [f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
             f"({s.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, pulse {s.pulse.kind}",
             f"map: {map_title(level, s.geometry)}, {g.n_u} x {g.n_v} points along {a} and {b}, "
             f"spacing {np.linalg.norm(g.u) / (g.n_u - 1) * 1e3:.3g} mm, {int(ok.sum())} in the fluid, "
             f"{seconds:.2f} s"]
    if ok.any():
        for name, values, unit in (("peak SPL", level.peak_spl_db, "dB re 20 uPa"),
                                   ("SEL", level.sel_db, "dB re (20 uPa)^2 s")):
            i = int(np.nanargmax(values))
            j = int(np.nanargmin(values))
            lines.append(f"{name}: {values[j]:.1f} to {values[i]:.1f} {unit} (largest at ({g.points[i, 0]:.4f}, "
                         f"{g.points[i, 1]:.4f}, {g.points[i, 2]:.4f}) m)")
    return lines
