r"""``acoustiviz damper``: simulate the impact damper, print its damping, write impacts and a plot.

argv -> :class:`~acoustiviz.app.settings.damper_job.DamperJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.damper.run` -> the summary -> :meth:`~acoustiviz.app.damper.DamperResult.write`.

Example::

    acoustiviz damper --M 0.5 --K 500 --C 0.05 --m 0.0405 --gap 0.04 --k-hertz 5.6e8 --c1 20 \\
        --v0 2 --duration 20 --solver event --impacts-csv OUT.csv --png OUT.png
"""

from __future__ import annotations

from ..app.settings.damper import BALL_START, BALLS
from ..app.settings.damper_job import DAMPER_OUTPUTS
from ..app.settings.table import add_option
from ._damper import add_damper_options


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
    b = p.add_argument_group("several balls (a column of equal spheres of mass --m; --gap is their free travel)")
    for s in BALLS + BALL_START:
        add_option(b, s)
    o = p.add_argument_group("outputs")
    for s in DAMPER_OUTPUTS:
        add_option(o, s)
    p.set_defaults(func=run)
    return p


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.damper_job.DamperJob` of the options; errors name the options."""
    from ..app.damper import damper_model
    from ..app.settings.damper import DAMPER, RUN, check_values
    from ..app.settings.damper_job import DamperJob
    from ..dynamics import InitialState

    names = DamperJob.names_for("cli")
    d = check_values({s.name: getattr(args, s.name) for s in DAMPER if hasattr(args, s.name)}, DAMPER, names)
    model = damper_model(**{k: d[k] for k in ("M", "K", "C", "m", "gap", "k_hertz", "c1", "clip_tensile")},
                         names=names)
    start = InitialState(x=d.get("x0", RUN[0].default), v=d["v0"])
    return DamperJob(model, start, d["duration"], d["solver"], d["rtol"], d["dt"], getattr(args, "max_memory", None),
                     impacts_csv=args.impacts_csv, history_csv=args.history_csv, png=args.png, balls=args.balls,
                     k_hertz_ball=args.k_hertz_ball, c1_ball=args.c1_ball,
                     **{s.name: getattr(args, s.name) for s in BALL_START}, names=names)


def run(args) -> int:
    """Run the ``damper`` subcommand: argv -> settings -> run -> summary -> files; return the exit status."""
    from ..app.damper import run as run_job

    settings = settings_from_args(args)
    result = run_job(settings)
    _print_summary(result)
    for path in result.write():
        print(f"wrote {path}")
    cut = _unfinished_contact(result.result.impacts)
    if settings.impacts_csv and cut is not None:
        print(f"note: the last contact (from {cut:.6g} s) was still under way when the run ended: its "
              f"separation velocity and restitution in {settings.impacts_csv} are nan")
    return 0 if result.result.success else 1


def _unfinished_contact(impacts):
    """The start in s of a last contact the end of the run cut (its separation speed is NaN), else None."""
    import math

    if len(impacts) == 0 or not math.isnan(float(impacts.separation_velocity[-1])):
        return None
    return float(impacts.time[-1])


def _print_summary(damper) -> None:
    """The solver's warnings, the impacts, the damping inclinations, the settling time, the energy and the times."""
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
