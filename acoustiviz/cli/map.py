"""``acoustiviz map``: peak SPL and SEL of one impact over a plane (PNG, CSV, VTK)."""

from __future__ import annotations

import sys

from ..app.settings.map import MAP_SETTINGS
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
    o.add_argument("--png", default=None, metavar="PATH",
                   help="two panels, peak SPL and SEL, with the sphere and planes")
    o.add_argument("--csv", default=None, metavar="PATH",
                   help="columns x_m,y_m,z_m,peak_pa,peak_spl_db,sel_db,time_of_peak_s, one row per grid point "
                        "(nan inside the sphere)")
    o.add_argument("--vtk", default=None, metavar="PATH",
                   help="the map for ParaView, pyvista or meshio: a .vtu (or .vtkhdf) file with point arrays "
                        "peak_pa, peak_spl_db, sel_db, time_of_peak_s, exposure_pa2s, and the sphere and planes "
                        "beside it in PATH_geometry.vtu")
    p.set_defaults(func=run)


def run(args) -> int:
    """Check every input and output, compute the map, print a summary and write the requested files."""
    import time

    import numpy as np

    from ..app.maps import CLI_NAMES, level_map, map_title, points_bar, write_map_outputs
    from ..app.outputs import check_distinct, check_output_file
    from ._impact import impact_from_args, room_duration

    kinds = {"--png": "figure", "--csv": "csv", "--vtk": "vtk"}
    paths = {opt: getattr(args, opt[2:]) for opt in kinds}
    for opt, path in paths.items():
        if path is not None:
            check_output_file(opt, path, kinds[opt])
    if paths["--vtk"] is not None:
        from ..output.vtk import geometry_path

        paths["--vtk (geometry)"] = check_output_file("--vtk", geometry_path(paths["--vtk"]), "vtk")
    check_distinct(paths)
    room_duration(args)
    setup = impact_from_args(args)
    t0 = time.perf_counter()
    with points_bar(sys.stderr) as bar:
        level = level_map(setup.pulse, setup.configuration, medium=setup.medium, plane=args.plane,
                          height=args.plane_height, extent=args.extent, resolution=args.resolution,
                          max_memory_mb=getattr(args, "max_memory", None), names=CLI_NAMES, progress=bar)
    seconds = time.perf_counter() - t0
    imp = setup.impact
    print(f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
          f"({setup.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, pulse {setup.pulse.kind}")
    g = level.grid
    ok = np.isfinite(level.peak_pa)
    a, b = level.in_plane()
    print(f"map: {map_title(level, setup.configuration)}, {g.n_u} x {g.n_v} points along {a} and {b}, "
          f"spacing {np.linalg.norm(g.u) / (g.n_u - 1) * 1e3:.3g} mm, {int(ok.sum())} in the fluid, "
          f"{seconds:.2f} s")
    if ok.any():
        for name, values, unit in (("peak SPL", level.peak_spl_db, "dB re 20 uPa"),
                                   ("SEL", level.sel_db, "dB re (20 uPa)^2 s")):
            i = int(np.nanargmax(values))
            j = int(np.nanargmin(values))
            print(f"{name}: {values[j]:.1f} to {values[i]:.1f} {unit} (largest at ({g.points[i, 0]:.4f}, "
                  f"{g.points[i, 1]:.4f}, {g.points[i, 2]:.4f}) m)")
    title = map_title(level, setup.configuration,
                      f"U0 = {imp.velocity:g} m/s, a = {setup.radius * 1e3:g} mm, {setup.pulse.kind} pulse")
    for path in write_map_outputs(level, setup.configuration, png=args.png, csv=args.csv, vtk=args.vtk, title=title):
        print(f"wrote {path}")
    return 0
