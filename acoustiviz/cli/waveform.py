"""``acoustiviz waveform``: the pressure waveform of one impact at one observer.

argv -> :class:`~acoustiviz.app.settings.waveform.WaveformJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.waveform.run` -> :meth:`~acoustiviz.app.waveform.WaveformResult.write` -> the summary.
"""

from __future__ import annotations

from ..app.settings.impact import WAVEFORM
from ..app.settings.table import add_option
from ..app.settings.waveform import LISTENER, WAVEFORM_OUTPUTS
from ._impact import add_impact_options, add_observer_options, add_room_options

#: What the number of samples grows with: an error about it names the first of these the user typed.
_SIZE_OPTIONS = ("--samples-per-duration", "--distance", "--radius", "--velocity", "--k-hertz", "--density",
                 "--material", "--surface", "--c")

#: The name of the command line's one listener.
LISTENER_NAME = "listener"


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
    for s in (LISTENER, WAVEFORM[0], *WAVEFORM_OUTPUTS):
        add_option(p, s)
    p.set_defaults(func=run)


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.waveform.WaveformJob` of the options; errors name the options."""
    from ..app.budget import given_first
    from ..app.settings.waveform import WaveformJob
    from ..core.listener import Listener
    from ._impact import impact_from_args, observer_point_from_options

    WAVEFORM[0].check(args.samples_per_duration, WAVEFORM[0].option)
    WAVEFORM[1].check(args.duration, WAVEFORM[1].option)
    listener = _room_listener(args)
    setup = impact_from_args(args)
    if listener is not None:
        point = setup.geometry.in_room("--listener", listener[None, :])[0]
    else:
        point = observer_point_from_options(setup, args.distance, args.angle)
    names = WaveformJob.names_for("cli", point=listener is not None)
    return WaveformJob(impact=setup.impact, pulses=(setup.pulse,), medium=setup.medium,
                       geometry=setup.geometry, listeners=(Listener(LISTENER_NAME, point),),
                       samples_per_duration=args.samples_per_duration,
                       max_memory_mb=getattr(args, "max_memory", None), csv=args.csv, png=args.png,
                       k_hertz_source=setup.k_hertz_source, names=names,
                       size_options=given_first(_size_options(args), args.given_options))


def _size_options(args) -> tuple:
    """The options the number of samples grows with: in a room, the window ``--duration`` first."""
    return ("--duration", *_SIZE_OPTIONS) if args.room is not None else _SIZE_OPTIONS


def run(args) -> int:
    """Compute, print a summary, and write the requested files."""
    from ..app.waveform import run as run_job

    settings = settings_from_args(args)
    result = run_job(settings)
    _print_summary(args, result)
    for path in result.write():
        print(f"wrote {path}")
    return 0


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


def _print_summary(args, result) -> None:
    """The impact, where the observer is (in a room, the images that reach it) and the reported peaks."""
    import math

    import numpy as np

    s = result.settings
    imp, geometry, pulse = s.impact, s.geometry, s.pulses[0]
    point = np.asarray(s.listeners[0].position)
    print(f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
          f"({s.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, peak acceleration "
          f"{imp.peak_acceleration:.4g} m/s^2, pulse {pulse.kind}")
    if not s.in_room:
        print(f"observer: {args.distance:g} m at {args.angle:g} deg, configuration {geometry.name}, "
              f"point ({point[0]:.4f}, {point[1]:.4f}, {point[2]:.4f}) m")
    else:
        print(f"observer: point ({point[0]:.4f}, {point[1]:.4f}, {point[2]:.4f}) m, {geometry.caption()}, "
              f"{np.linalg.norm(point - geometry.centre):.4g} m from the sphere's centre")
        neg = geometry.neglected_energy_db
        print(f"images: image_order {geometry.image_order}, images {geometry.image_count}, "
              f"neglected_energy_db {neg:.1f} "
              f"(every image that can arrive within the {s.window:g} s window"
              + (")" if neg == -math.inf else f"; tolerance {geometry.tolerance_db:g} dB)")
              + (" [capped by the memory budget]" if geometry.order_capped else ""))
    how = "largest samples in the window" if s.in_room else "peaks of the continuous waveform"
    print(f"pressure: max {result.peak_positive[0]:.10g} Pa, min {result.peak_negative[0]:.10g} Pa ({how}), "
          f"peak SPL {result.peak_spl_db[0]:.1f} dB re 20 uPa")
