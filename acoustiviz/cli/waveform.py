"""``acoustiviz waveform``: the pressure waveform of one impact at one observer."""

from __future__ import annotations

from ._impact import add_impact_options, add_observer_options, add_room_options


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
    p.add_argument("--samples-per-duration", type=int, default=400, metavar="N",
                   help="time samples per contact duration (>= 200, default %(default)s)")
    p.add_argument("--csv", default=None, metavar="PATH",
                   help="write columns time_s,pressure_pa (with --room also PATH.json: the image order, the "
                        "number of images and the neglected-energy bound)")
    p.add_argument("--png", default=None, metavar="PATH", help="draw the waveform")
    p.set_defaults(func=run)


def run(args) -> int:
    """Compute, print a summary, and write the requested files."""
    import math

    import numpy as np

    from ..app.budget import check_budget, given_first, memory_cap, waveform_estimate
    from ..app.names import user_terms
    from ..app.outputs import check_distinct, check_output_file
    from ..app.views import check_samples_per_duration, waveform_peaks, waveform_times
    from ..field import time_series
    from ._impact import impact_from_args, observer_point

    if args.csv is not None:
        check_output_file("--csv", args.csv, "csv")
    if args.png is not None:
        check_output_file("--png", args.png, "figure")
    check_distinct({"--csv": args.csv, "--png": args.png})
    room = args.room is not None
    listener = _room_listener(args)
    setup = impact_from_args(args)
    if room:
        point = setup.configuration.in_room("--listener", listener[None, :])[0]
    else:
        point = observer_point(setup, args.distance, args.angle)
    with user_terms({"samples_per_duration": "--samples-per-duration"}):
        check_samples_per_duration(args.samples_per_duration)
        # the samples are the waveform's span over contact time / N: any of these settings sets their number
        size_options = given_first(("--samples-per-duration", "--distance", "--radius", "--velocity", "--k-hertz",
                                    "--density", "--material", "--surface", "--c"), args.given_options)
        check_budget(waveform_estimate([setup.pulse], point, setup.configuration, setup.medium,
                                       args.samples_per_duration, options=size_options, window=args.duration),
                     getattr(args, "max_memory", None))
        t = waveform_times([setup.pulse], point, setup.configuration, setup.medium, args.samples_per_duration,
                           window=args.duration)
    p = time_series(setup.pulse, t, point[None, :], setup.configuration, medium=setup.medium,
                    memory_limit=memory_cap(getattr(args, "max_memory", None)))[0]
    imp = setup.impact
    print(f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
          f"({setup.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, peak acceleration "
          f"{imp.peak_acceleration:.4g} m/s^2, pulse {setup.pulse.kind}")
    _print_observer(args, setup, point)
    with user_terms({"memory_limit": "--max-memory"}):  # refined peaks, not the largest samples
        if room:  # the peaks within the window
            pmax, pmin = float(np.max(p)), float(np.min(p))
        else:
            pmax, pmin = waveform_peaks(setup.pulse, point, setup.configuration, setup.medium,
                                        memory_limit=memory_cap(getattr(args, "max_memory", None)))
    peak = max(pmax, -pmin)
    how = "largest samples in the window" if room else "peaks of the continuous waveform"
    print(f"pressure: max {pmax:.10g} Pa, min {pmin:.10g} Pa ({how}), peak SPL "
          f"{20 * math.log10(peak / 20e-6):.1f} dB re 20 uPa")
    if args.csv:
        _write_csv(args, setup, point, t, p, pmax, pmin)
    if args.png:
        _write_png(args, setup, t, p)
    return 0


def _room_listener(args):
    """The ``--listener`` point in a room (m), its ``--duration`` and sidecar checked; None without ``--room``."""
    from .._validate import ParameterError
    from ..app.outputs import check_distinct, check_output_file
    from ._impact import room_duration

    room_duration(args)
    if args.room is None:
        if args.listener is not None:
            raise ParameterError("--listener", "only applies with --room LX,LY,LZ")
        return None
    from .auralize import parse_point

    if args.listener is None:
        raise ParameterError("--listener", "required with --room: the observer's position X,Y,Z in m")
    listener = parse_point(args.listener)
    if args.csv is not None:
        from pathlib import Path

        check_output_file("--csv", Path(args.csv).with_suffix(".json"), "json")
        check_distinct({"--csv": args.csv, "--csv (sidecar)": str(Path(args.csv).with_suffix(".json")),
                        "--png": args.png})
    return listener


def _print_observer(args, setup, point) -> None:
    """Where the observer is (and, in a room, the images that reach it)."""
    import math

    import numpy as np

    conf = setup.configuration
    if args.room is not None:
        print(f"observer: point ({point[0]:.4f}, {point[1]:.4f}, {point[2]:.4f}) m, {conf.caption()}, "
              f"{np.linalg.norm(point - conf.centre):.4g} m from the sphere's centre")
        neg = conf.neglected_energy_db
        print(f"images: image_order {conf.image_order}, images {conf.image_count}, neglected_energy_db {neg:.1f} "
              f"(every image that can arrive within the {args.duration:g} s window"
              + (")" if neg == -math.inf else f"; tolerance {conf.tolerance_db:g} dB)")
              + (" [capped by the memory budget]" if conf.order_capped else ""))
    else:
        print(f"observer: {args.distance:g} m at {args.angle:g} deg, configuration {conf.name}, "
              f"point ({point[0]:.4f}, {point[1]:.4f}, {point[2]:.4f}) m")


def _write_csv(args, setup, point, t, p, pmax, pmin) -> None:
    """``time_s,pressure_pa``; in a room, a JSON sidecar with the images and the settings."""
    from ..output.writers import write_csv_atomic

    conf, imp = setup.configuration, setup.impact
    write_csv_atomic(args.csv, ["time_s", "pressure_pa"], [t, p], fmt=["%.12e", "%.10e"])
    print(f"wrote {args.csv}")
    if args.room is not None:
        import json
        from pathlib import Path

        from .. import __version__
        from ..output.writers import write_text_atomic

        record = {"software": f"acoustiviz {__version__}", "csv": Path(args.csv).name,
                  "columns": ["time_s", "pressure_pa"], "config": conf.name, "radius_m": conf.radius,
                  **conf.settings(), "listener_m": point.tolist(), "window_s": args.duration,
                  "sample_interval_s": float(t[1] - t[0]) if t.size > 1 else None,
                  "velocity_m_s": imp.velocity, "k_hertz_n_m1_5": imp.k_hertz, "mass_kg": imp.mass,
                  "pulse": setup.pulse.kind, "medium": {"c_m_s": setup.medium.c, "rho_kg_m3": setup.medium.rho},
                  "peak_positive_pa": pmax, "peak_negative_pa": pmin}
        side = Path(args.csv).with_suffix(".json")
        write_text_atomic(side, json.dumps(record, indent=2) + "\n")
        print(f"wrote {side}")


def _write_png(args, setup, t, p) -> None:
    """The waveform as a figure."""
    from ..output.plot.style import save_figure, style
    from ..output.plot.waveform import plot_waveform

    with style():
        ax = plot_waveform(t, p, label=f"{setup.configuration.name}, {setup.pulse.kind}")
        ax.set_title(f"r = {args.distance:g} m, θ = {args.angle:g}°, a = {setup.radius * 1e3:g} mm, "
                     f"U0 = {setup.impact.velocity:g} m/s")
        ax.legend()
        save_figure(ax.figure, args.png)
    print(f"wrote {args.png}")
