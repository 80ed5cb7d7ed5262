"""``acoustiviz directivity``: peak SPL and RMS pressure versus angle on a circle (paper Figure 3).

argv -> :class:`~acoustiviz.app.settings.directivity.DirectivityJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.directivity.run` -> :meth:`~acoustiviz.app.directivity.DirectivityResult.write` -> the summary.
"""

from __future__ import annotations

from ..app.settings.directivity import DIRECTIVITY_OUTPUTS
from ..app.settings.impact import DIRECTIVITY
from ..app.settings.table import add_option
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
    step, metric = DIRECTIVITY
    add_option(p, step, metavar="DEG")
    add_option(p, metric, metavar="NAME", parse_choices=False)  # a bad name: the job's one line, closest name
    for s in DIRECTIVITY_OUTPUTS:
        add_option(p, s)
    p.set_defaults(func=run)


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.directivity.DirectivityJob` of the options; errors name the options."""
    from ..app.settings.directivity import DirectivityJob
    from ._impact import impact_from_args, room_duration

    room_duration(args)  # --duration with --room only, and required there
    setup = impact_from_args(args)
    names = DirectivityJob.names_for("cli")
    return DirectivityJob(impact=setup.impact, pulse=setup.pulse, medium=setup.medium,
                          geometry=setup.geometry, distance=args.distance,
                          step_deg=args.step, metric=args.metric, max_memory_mb=getattr(args, "max_memory", None),
                          csv=args.csv, png=args.png, k_hertz_source=setup.k_hertz_source, names=names)


def run(args) -> int:
    """Compute the directivity, print it, and write the requested files."""
    from ..app.directivity import run as run_job

    result = run_job(settings_from_args(args))
    for line in _summary_lines(result):
        print(line)
    for path in result.write():
        print(f"wrote {path}")
    return 0


def _summary_lines(result) -> list:
    """The impact, the circle (in a room, its images), how a weighted level is made, and the table."""
    import numpy as np

    from ..app.views import metric_label

    s = result.settings
    imp, geometry, d, extra = s.impact, s.geometry, result.directivity, result.levels is not None
    lines = [f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
             f"({s.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, pulse {s.pulse.kind}",
             f"circle: {s.distance:g} m from the sphere's centre, configuration {geometry.caption()}; "
             f"RMS window {d.metrics.window * 1e3:.3f} ms from the first arrival"]
    if s.in_room:
        lines.append(f"images: image_order {geometry.image_order}, images {geometry.image_count}, "
                     f"neglected_energy_db {geometry.neglected_energy_db:.1f} (every image that can arrive within "
                     f"the {s.window:g} s window)")
    if s.weighted:
        lines.append(f"{metric_label(s.metric)}: from the pressure at each angle band-limited flat to 43.2 kHz and "
                     "sampled at 96 kHz (IEC 61672-1 weightings); equivalent levels over 1 s from the first arrival")
    lines.append(f"{'angle_deg':>9} {'peak_pa':>10} {'rms_pa':>10} {'spl_db':>7}"
                 + (f" {result.column:>10}" if extra else ""))
    for k, row in enumerate(zip(np.degrees(result.angles), d.peak, d.rms, d.spl_db, strict=True)):
        lines.append(f"{row[0]:9.2f} {row[1]:10.4g} {row[2]:10.4g} {row[3]:7.2f}"
                     + (f" {result.levels[k]:10.2f}" if extra else ""))
    return lines
