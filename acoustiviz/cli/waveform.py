"""``acoustiviz waveform``: the pressure waveform of one impact at one observer."""

from __future__ import annotations

from ..app.settings.impact import WAVEFORM
from ..app.settings.table import add_option
from ._impact import add_impact_options, add_observer_options, add_room_options

#: What the number of samples grows with: an error about it names the first of these the user typed.
_SIZE_OPTIONS = ("--samples-per-duration", "--distance", "--radius", "--velocity", "--k-hertz", "--density",
                 "--material", "--surface", "--c")


def add_parser(subparsers) -> None:
    """Register the ``waveform`` subcommand."""
    p = subparsers.add_parser(
        "waveform",
        help="pressure waveform of one impact at one observer (CSV and PNG)",
        description="Pressure in Pa radiated by a sphere striking a surface, at one observer. "
        "Time runs from the start of contact. Defaults: the paper's Figure 2 scene.",
    )
    add_impact_options(p)
    add_observer_options(p)
    add_room_options(p, duration=True)
    p.add_argument("--listener", default=None, metavar="X,Y,Z",
                   help="with --room: the observer's position in m, in the room outside the sphere "
                        "(replaces --distance and --angle)")
    add_option(p, WAVEFORM[0])
    p.add_argument("--csv", default=None, metavar="PATH",
                   help="write columns time_s,pressure_pa (with --room also PATH.json: the image order, the "
                        "number of images and the neglected-energy bound)")
    p.add_argument("--png", default=None, metavar="PATH", help="draw the waveform")
    p.set_defaults(func=run)


def run(args) -> int:
    """Compute, print a summary, and write the requested files."""
    from ..app.budget import given_first
    from ..app.names import user_terms
    from ..app.settings.impact import WaveformSettings
    from ..app.waveform import waveform_at, write_waveform_outputs
    from ._impact import impact_from_args, observer_point_from_options

    names = {**WaveformSettings.cli_names(), "memory_limit": "--max-memory"}
    with user_terms(names):
        settings = WaveformSettings(args.samples_per_duration, args.duration)
    _check_outputs(args)
    listener = _room_listener(args)
    setup = impact_from_args(args)
    if listener is not None:
        point = setup.configuration.in_room("--listener", listener[None, :])[0]
    else:
        point = observer_point_from_options(setup, args.distance, args.angle)
    with user_terms(names):
        wf = waveform_at(setup, point, settings, max_memory_mb=getattr(args, "max_memory", None),
                         size_options=given_first(_SIZE_OPTIONS, args.given_options))
    imp = setup.impact
    print(f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
          f"({setup.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, peak acceleration "
          f"{imp.peak_acceleration:.4g} m/s^2, pulse {setup.pulse.kind}")
    _print_observer(args, setup, point)
    how = "largest samples in the window" if listener is not None else "peaks of the continuous waveform"
    print(f"pressure: max {wf.peak_positive:.10g} Pa, min {wf.peak_negative:.10g} Pa ({how}), peak SPL "
          f"{wf.peak_spl_db:.1f} dB re 20 uPa")
    title = (f"r = {args.distance:g} m, θ = {args.angle:g}°, a = {setup.radius * 1e3:g} mm, "
             f"U0 = {imp.velocity:g} m/s")
    for path in write_waveform_outputs(setup, point, wf, settings, csv=args.csv, png=args.png, title=title):
        print(f"wrote {path}")
    return 0


def _check_outputs(args) -> None:
    """The files asked for: each writable, none twice (a room's table has its JSON sidecar beside it)."""
    from pathlib import Path

    from ..app.outputs import check_distinct, check_output_file

    if args.csv is not None:
        check_output_file("--csv", args.csv, "csv")
    if args.png is not None:
        check_output_file("--png", args.png, "figure")
    check_distinct({"--csv": args.csv, "--png": args.png})
    if args.room is not None and args.csv is not None:
        side = str(Path(args.csv).with_suffix(".json"))
        check_output_file("--csv", side, "json")
        check_distinct({"--csv": args.csv, "--csv (sidecar)": side, "--png": args.png})


def _room_listener(args):
    """The ``--listener`` point in a room (m), with ``--duration`` given; None without ``--room``."""
    from .._validate import ParameterError
    from ._impact import room_duration

    room_duration(args)
    if args.room is None:
        if args.listener is not None:
            raise ParameterError("--listener", "only applies with --room LX,LY,LZ")
        return None
    from ..app.settings.parse import parse_point

    if args.listener is None:
        raise ParameterError("--listener", "required with --room: the observer's position X,Y,Z in m")
    return parse_point(args.listener)


def _print_observer(args, setup, point) -> None:
    """Where the observer is (and, in a room, the images that reach it)."""
    import math

    import numpy as np

    conf = setup.configuration
    if args.room is None:
        print(f"observer: {args.distance:g} m at {args.angle:g} deg, configuration {conf.name}, "
              f"point ({point[0]:.4f}, {point[1]:.4f}, {point[2]:.4f}) m")
        return
    print(f"observer: point ({point[0]:.4f}, {point[1]:.4f}, {point[2]:.4f}) m, {conf.caption()}, "
          f"{np.linalg.norm(point - conf.centre):.4g} m from the sphere's centre")
    neg = conf.neglected_energy_db
    print(f"images: image_order {conf.image_order}, images {conf.image_count}, neglected_energy_db {neg:.1f} "
          f"(every image that can arrive within the {args.duration:g} s window"
          + (")" if neg == -math.inf else f"; tolerance {conf.tolerance_db:g} dB)")
          + (" [capped by the memory budget]" if conf.order_capped else ""))
