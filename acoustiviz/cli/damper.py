r"""``acoustiviz damper``: simulate the impact damper, print its damping, write impacts and a plot.

Example::

    acoustiviz damper --M 0.5 --K 500 --C 0.05 --m 0.0405 --gap 0.04 --k-hertz 5.6e8 --c1 20 \\
        --v0 2 --duration 20 --solver event --impacts-csv OUT.csv --png OUT.png
"""

from __future__ import annotations

from ._damper import add_damper_options, damper_from_args


def add_parser(subparsers):
    """Register the ``damper`` subcommand."""
    p = subparsers.add_parser(
        "damper",
        help="simulate the impact damper (paper eq 15) and report its damping",
        description=(
            "Simulate the impact damper of the paper (eq 15; defaults: Table 1, d = 4 cm, "
            "Figure 5 start: x = 0, dx/dt = V0, impact mass centred and at rest). Prints the "
            "damping inclination (eq 16 from the first two positive maxima, and a linear fit of "
            "the maxima envelope), the settling time, the number of impacts and the solver time."
        ),
    )
    add_damper_options(p)
    o = p.add_argument_group("outputs")
    o.add_argument("--impacts-csv", metavar="PATH", default=None,
                   help="write the impact table (one row per contact) as CSV; a contact still under way "
                        "when the run ends (the last row) has nan separation_velocity_m_s and restitution, "
                        "and its duration_s is the time it lasted until then")
    o.add_argument("--png", metavar="PATH", default=None,
                   help="plot x(t) with and without the damper (Figure 5) as PNG")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    """Run the ``damper`` subcommand; return the exit status."""
    from ..app.outputs import check_distinct, check_output_file

    if args.impacts_csv is not None:
        check_output_file("--impacts-csv", args.impacts_csv, "csv")
    if args.png is not None:
        check_output_file("--png", args.png, "figure")
    check_distinct({"--impacts-csv": args.impacts_csv, "--png": args.png})
    _, damper = damper_from_args(args)
    result = damper.result
    for msg in damper.warnings:
        print(f"warning: {msg}")
    metrics = damper.metrics
    two, fit, ts = metrics.two_maxima, metrics.fit, metrics.settling_time
    settings = ", ".join(f"{k} {v:g}" for k, v in result.settings.items())
    print(f"solver: {result.solver} ({settings}); {result.message}")
    print(f"impacts: {len(result.impacts)}")
    print(f"damping inclination (eq 16, first two positive maxima at {two.t_start:.4f} s and "
          f"{two.t_stop:.4f} s): {100 * two.value:.4f} cm/s")
    print(f"damping inclination (linear fit of {fit.n_maxima} positive maxima, {fit.t_start:.3f}-"
          f"{fit.t_stop:.3f} s, down to 30% of the first): {100 * fit.value:.4f} cm/s")
    if ts == ts:
        print(f"settling time (positive maxima below 5% of the first): {ts:.3f} s")
    else:
        print("settling time (positive maxima below 5% of the first): not settled within the run")
    if result.energy.initial > 0:
        print(f"energy closure: {result.energy.relative_closure_error:.2e} of the initial "
              f"{result.energy.initial:.4g} J")
    else:
        print("energy closure: no initial energy, nothing to close")
    print(f"solver time: {round(1000 * result.solver_time)} ms")
    print(f"kernel compile (or cache load) time: {round(1000 * result.compile_time)} ms")
    if args.impacts_csv:
        from ..output.tables import write_impact_table

        path = write_impact_table(args.impacts_csv, result.impacts)
        print(f"wrote {path}")
        cut = _unfinished_contact(result.impacts)
        if cut is not None:
            print(f"note: the last contact (from {cut:.6g} s) was still under way when the run ended: its "
                  f"separation velocity and restitution in {path} are nan")
    if args.png:
        from ..output.plot.dynamics import plot_free_vibration
        from ..output.plot.style import save_figure

        ax = plot_free_vibration(result)
        path = save_figure(ax.figure, args.png)
        print(f"wrote {path}")
    return 0 if result.success else 1


def _unfinished_contact(impacts):
    """The start in s of a last contact the end of the run cut (its separation speed is NaN), else None."""
    import math

    if len(impacts) == 0 or not math.isnan(float(impacts.separation_velocity[-1])):
        return None
    return float(impacts.time[-1])
