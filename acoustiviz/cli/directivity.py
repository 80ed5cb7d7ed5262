"""``acoustiviz directivity``: peak SPL and RMS pressure versus angle on a circle (paper Figure 3)."""

from __future__ import annotations

from ._impact import add_impact_options, add_observer_options, add_room_options


def add_parser(subparsers) -> None:
    """Register the ``directivity`` subcommand."""
    p = subparsers.add_parser(
        "directivity",
        help="peak SPL and RMS pressure versus angle around the sphere (CSV and PNG)",
        description="Pressure radiated by one impact, on a circle around the sphere's centre. Angles "
        "are in degrees from the acceleration axis (the normal of the struck surface): 0 to 90 for "
        "--config plane and wall-floor (the circle lies in the plane through the centre normal to the "
        "wall, on the side away from it), 0 to 180 for free. peak_pa is max|p|, spl_db = "
        "20 log10(peak_pa / 20e-6), and rms_pa is the RMS over a window of the same length at every "
        "angle, starting at the first arrival and holding the whole pulse from every image plus ten "
        "decay times a/c of the sphere. With --room the circle lies in the room (0 to 90 degrees for a sphere on "
        "the struck surface, else 0 to 180), its radius --distance at most the distance from the sphere's centre "
        "to the walls it would cross, and the levels include every image that arrives within the window: each "
        "angle's window starts at its first arrival and ends by --duration from the start of contact.",
    )
    add_impact_options(p)
    add_observer_options(p, angle=False)
    add_room_options(p, duration=True)
    p.add_argument(
        "--step", type=float, default=5.0, metavar="DEG", help="angle step in degrees, in (0, 90] (default %(default)s)"
    )
    p.add_argument("--metric", default="peak-spl", metavar="NAME",
                   help="level shown against angle: peak-spl (default, max|p|), rms (RMS level over the window), "
                        "or a weighted level computed from the impact's pressure at each angle, band-limited at "
                        "96 kHz: lcpeak, lafmax, laeq (over 1 s from the first arrival), sel-a, lzpeak, lasmax, "
                        "lzeq, sel")
    p.add_argument("--csv", default=None, metavar="PATH",
                   help="write columns angle_deg,peak_pa,rms_pa,spl_db and, for another --metric, its column "
                        "(rms_db, lcpeak_db, lafmax_db, laeq_db, sel_a_db, ...)")
    p.add_argument("--png", default=None, metavar="PATH", help="draw SPL and RMS polar plots")
    p.set_defaults(func=run)


def run(args) -> int:
    """Compute the directivity, print it, and write the requested files."""
    import numpy as np

    from .._validate import check_range
    from ..app.budget import check_budget, directivity_estimate
    from ..app.names import user_terms
    from ..app.outputs import check_distinct, check_output_file
    from ..app.views import DIRECTIVITY_METRICS, directivity_angles, directivity_metric, metric_label
    from ..errors import ParameterError
    from ..field import circle_points, directivity
    from ._impact import impact_from_args, observer_point, room_duration

    if args.metric not in DIRECTIVITY_METRICS:
        raise ParameterError("--metric", f"must be one of {', '.join(DIRECTIVITY_METRICS)}, got {args.metric!r}")
    if args.csv is not None:
        check_output_file("--csv", args.csv, "csv")
    if args.png is not None:
        check_output_file("--png", args.png, "figure")
    check_distinct({"--csv": args.csv, "--png": args.png})
    room_duration(args)
    setup = impact_from_args(args)
    a = setup.radius
    with user_terms({"distance": "--distance"}):  # the circle's radius fits in the fluid (a room's walls)
        circle_points(setup.configuration, args.distance, [0.0])
    observer_point(setup, args.distance, 0.0)  # the circle's radius checked as --distance
    with user_terms({"step_deg": "--step", "distance": "--distance", "angles": "--step"}):
        check_range("step_deg", args.step, 0.0, 90.0, unit="deg", low_open=True)
        check_budget(directivity_estimate(setup.configuration, args.step, pulse=setup.pulse, medium=setup.medium,
                                          window_options=("--wall-distance", "--distance")),
                     getattr(args, "max_memory", None))
        angles = directivity_angles(setup.configuration, args.step)
        d = directivity(setup.pulse, setup.configuration, args.distance, angles, medium=setup.medium)
        extra = args.metric != "peak-spl"
        column = DIRECTIVITY_METRICS[args.metric]
        values = directivity_metric(d, args.metric, setup.pulse, setup.configuration, setup.medium) if extra else None
    deg = np.degrees(angles)
    top = setup.configuration.polar_limit_deg
    imp = setup.impact
    print(
        f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
        f"({setup.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, pulse {setup.pulse.kind}"
    )
    print(
        f"circle: {args.distance:g} m from the sphere's centre, configuration {setup.configuration.caption()}; "
        f"RMS window {d.metrics.window * 1e3:.3f} ms from the first arrival"
    )
    if args.room is not None:
        conf = setup.configuration
        print(f"images: image_order {conf.image_order}, images {conf.image_count}, neglected_energy_db "
              f"{conf.neglected_energy_db:.1f} (every image that can arrive within the {args.duration:g} s window)")
    if extra and args.metric not in ("rms",):
        print(f"{metric_label(args.metric)}: from the pressure at each angle band-limited flat to 43.2 kHz and "
              "sampled at 96 kHz (IEC 61672-1 weightings); equivalent levels over 1 s from the first arrival")
    print(f"{'angle_deg':>9} {'peak_pa':>10} {'rms_pa':>10} {'spl_db':>7}" + (f" {column:>10}" if extra else ""))
    for k, row in enumerate(zip(deg, d.peak, d.rms, d.spl_db, strict=True)):
        print(f"{row[0]:9.2f} {row[1]:10.4g} {row[2]:10.4g} {row[3]:7.2f}" + (f" {values[k]:10.2f}" if extra else ""))
    if args.csv:
        from ..app.views import write_directivity_csv

        write_directivity_csv(args.csv, d, args.metric, values)
        print(f"wrote {args.csv}")
    if args.png:
        from ..app.views import directivity_metric_figure
        from ..output.plot.directivity import directivity_figure
        from ..output.plot.style import save_figure

        title = (f"{setup.configuration.caption()}: r = {args.distance:g} m, a = {a * 1e3:g} mm, "
                 f"U0 = {imp.velocity:g} m/s, {setup.pulse.kind} pulse")
        if extra:
            fig = directivity_metric_figure(d, values, args.metric, half_space=top == 90.0, title=title)
        else:
            fig = directivity_figure(d, half_space=top == 90.0, title=title)
        save_figure(fig, args.png)
        print(f"wrote {args.png}")
    return 0
