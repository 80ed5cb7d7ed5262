"""``acoustiviz design``: the quietest design of a sweep for a target damping inclination.

Example::

    acoustiviz design --sweep DIR --inclination 0.008 --tolerance 0.001

Among the designs of ``DIR/sweep.csv`` whose damping inclination lies within the tolerance of
the target, prints the quietest (m, d), its maximum SPL, and by how many dB it is quieter than
the loudest (the acoustic-based design of the paper, Table 2); ``--rank-by lafmax_db`` (or any
numeric column) ranks by another level; ``--png`` and ``--choice`` also write the design table's
figure and the answer, as a scene's ``[outputs.design_table]`` does. A sweep in operation
(``acoustiviz sweep --force``) has no damping inclination: ``acoustiviz design --sweep DIR --rank-by
worst_laeq_db`` lists its designs best first by that column (``min_reduction_db``: largest first).

argv -> :class:`~acoustiviz.app.settings.design.DesignJob` (:func:`settings_from_args`) ->
:func:`acoustiviz.app.design.run` -> the printed report and
:meth:`~acoustiviz.app.design.DesignTableResult.write`.
"""

from __future__ import annotations

from ..app.settings.design import DESIGN, DESIGN_RUN
from ..app.settings.table import add_option


def add_parser(subparsers):
    """Register the ``design`` subcommand."""
    p = subparsers.add_parser(
        "design",
        help="quietest damper design of a sweep for a target damping inclination (paper Table 2)",
        description=(
            "Read a sweep directory (acoustiviz sweep --out DIR) and answer: among the designs whose "
            "damping inclination is within TOLERANCE of INCLINATION, which (m, d) is quietest, and by "
            "how many dB over the loudest. Inclinations in m/s (0.008 m/s = 0.8 cm/s)."
        ),
    )
    for s in (*DESIGN, *DESIGN_RUN):
        required = s.name == "sweep"  # --inclination too, unless the sweep is in operation (settings_from_args)
        add_option(p, s, **({"metavar": "M/S"} if s.unit == "m/s" else {}), **({"required": True} if required else {}))
    p.set_defaults(func=run)
    return p


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.design.DesignJob` of the options; errors name the options."""
    from ..app.settings.design import DesignJob
    from ..errors import ParameterError

    job = DesignJob(inclination=args.inclination, tolerance=args.tolerance, sweep=args.sweep,
                    definition=args.definition, table=args.table, band_width=args.band_width, rank_by=args.rank_by,
                    png=args.png, choice=args.choice, max_memory_mb=getattr(args, "max_memory", None),
                    names=DesignJob.names_for("cli"))
    if args.inclination is None and job.operation is None:
        raise ParameterError("--inclination", "is required for a sweep of free vibration (a sweep in operation is "
                                              "ranked by --rank-by alone)")
    return job


def run(args) -> int:
    """Check every input and output, answer from the sweep, print the report and write the requested files."""
    from ..app.design import run as run_job

    result = run_job(settings_from_args(args))
    for line in result.lines():
        print(line)
    for path in result.write():
        print(f"wrote {path}")
    return 0
