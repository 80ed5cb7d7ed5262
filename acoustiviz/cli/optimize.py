r"""``acoustiviz optimize``: which damper to build, found by an optimiser over the sweep's variables.

Example::

    acoustiviz optimize --gap 0.01:0.06 --m 0.01:0.08 --minimize max_spl_db \\
        --constraint 'inclination_two_maxima_m_s>=0.004' --constraint 'inclination_two_maxima_m_s<=0.006' \\
        --evaluations 90 --duration 1 --out DIR

In operation (``--force F0`` or ``--base B`` and ``--freq START:STOP:COUNT``, the options of a sweep in
operation) the objectives and constraints name the worst-case columns, and the chosen design's worst case is
confirmed by ``acoustiviz forced`` with twice the starts (``DIR/confirmation.csv``)::

    acoustiviz optimize --gap 0.01:0.06 --m 0.01:0.08 --force 20 --freq 4:6:3 --minimize worst_laeq_db \\
        --constraint 'min_reduction_db>=6' --evaluations 40 --out DIR

argv -> :class:`~acoustiviz.app.settings.optimize.OptimizeJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.optimize.run` -> :meth:`~acoustiviz.app.optimize.OptimizeResult.write` -> the summary.
"""

from __future__ import annotations

from ..app.settings.optimize import EXECUTION, OPTIMIZE, REPEATED, VARIABLES
from ..app.settings.sweep import SWEEP_DAMPER, SWEEP_SOUND
from ..app.settings.sweep_operation import OPERATION_OPTIONS, SEARCH
from ..app.settings.table import add_option
from .sweep import add_room, given_with_room


def add_parser(subparsers):
    """Register the ``optimize`` subcommand."""
    p = subparsers.add_parser(
        "optimize",
        help="find the damper to build: an optimiser over the sweep's variables (objectives, constraints)",
        description=(
            "Search the designs of `acoustiviz sweep` with Optuna's TPE sampler (the 'optimize' extra): each "
            "variable is LO:HI, log:LO:HI, A,B,C or one value; objectives and constraints name columns of "
            "sweep.csv. Writes OUT/evaluations.csv, OUT/pareto.csv, OUT/optimize.json and OUT/pareto.png; the "
            "same command resumes an interrupted run. A design that fails is a row with its reason."
        ),
    )
    g = p.add_argument_group("variables (LO:HI, log:LO:HI, A,B,C or one value; SI units)")
    for s in VARIABLES:
        add_option(g, s, dest=s.name)
    o = p.add_argument_group("objectives, constraints and budget")
    for s in OPTIMIZE[:-1]:
        add_option(o, s, dest=s.name, **({"action": "append"} if s.name in REPEATED else {}))
    d = p.add_argument_group("damper (SI units)")
    for s in SWEEP_DAMPER:  # the sweep's, with its --duration
        add_option(d, s, dest=s.name, **({"metavar": "DURATION"} if s.option == "--duration" else {}))
    snd = p.add_argument_group("sound (SI units)")
    for s in SWEEP_SOUND:
        add_option(snd, s, dest=s.name)
    op = p.add_argument_group("in operation (as acoustiviz sweep; --solver and --rtol then set the search's, "
                              f"default {SEARCH['solver'].default} and {SEARCH['rtol'].default:g})")
    for s in OPERATION_OPTIONS:
        add_option(op, s, dest=s.name)
    add_room(p)  # the sweep's room, with its --room-window
    e = p.add_argument_group("execution and outputs")
    for s in EXECUTION:
        add_option(e, s, dest=s.name, **({"required": True} if s.name == "out" else {}))
    p.set_defaults(func=run)
    return p


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.optimize.OptimizeJob` of the options; errors name the options."""
    from ..app.optimize import operation_of, optimize_variables
    from ..app.settings.optimize import OptimizeJob

    names = OptimizeJob.names_for("cli")
    given = {s.name: getattr(args, s.name) for s in (*VARIABLES, *SWEEP_DAMPER, *SWEEP_SOUND, *OPERATION_OPTIONS)
             if getattr(args, s.name) is not None}
    given = given_with_room(args, given)
    for s in OPTIMIZE[3:6]:
        s.check(getattr(args, s.name), s.option)
    operation, given = operation_of(given, names)
    variables, fixed = optimize_variables(given, names)
    return OptimizeJob(variables, fixed, minimize=tuple(args.minimize or ()), maximize=tuple(args.maximize or ()),
                       constraints=tuple(args.constraints or ()), evaluations=args.evaluations, seed=args.seed,
                       batch=args.batch, mode="operation" if operation is not None else args.mode,
                       operation=operation, out=args.out, executor=args.executor,
                       workers=args.workers, names=names)


def run(args) -> int:
    """Run the ``optimize`` subcommand; return the exit status."""
    import sys

    from ..app.optimize import run as run_job
    from ..app.optimize import summary

    job = settings_from_args(args)
    result = run_job(job, progress=sys.stderr)
    for path in result.write():
        print(f"wrote {path}")
    for line in summary(result):
        print(line)
    return 0
