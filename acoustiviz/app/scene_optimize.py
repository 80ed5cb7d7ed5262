"""A scene's ``[outputs.optimize]``: the same :class:`~acoustiviz.app.settings.optimize.OptimizeJob` as the command.

The variables are the table's ``gap_m`` (or ``fill``), ``mass_kg`` and ``balls``, read as the command
line's ``--gap``, ``--fill``, ``--m`` and ``--balls`` (``equal_total_mass`` as ``--equal-total-mass``);
everything else (the damper, its solver, the sphere, the contact, the first listener and the
configuration) is the scene's, read through
:func:`acoustiviz.app.sweep.sweep_settings`, the reading of a scene's sweep; with ``in_operation`` (or
``mode = "operation"``) the designs are evaluated in operation under the scene's ``[excitation]``, as a
scene's sweep in operation is.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..constants import PAPER_GAP, TABLE1_PARAMETERS
from .settings.optimize import EXECUTION, OPTIMIZE, SCENE_LEVELS, SCENE_OPERATION, SCENE_VARIABLES, OptimizeJob

__all__ = ["optimize_settings", "produce_optimize", "OPTIMIZE_FOLDER"]

#: The folder of the optimisation inside a scene's run folder.
OPTIMIZE_FOLDER = "optimize"
#: FixedSettings fields given to :func:`acoustiviz.app.sweep.sweep_spec` under their own names.
_SAME = ("M", "K", "C", "clip_tensile", "duration", "solver", "rtol", "surface", "pulse", "pulse_mass", "c", "rho",
         "wall_distance", "n_fastest", "levels", "room", "equal_total_mass", "k_hertz_ball", "c1_ball")


class _AsSweep:
    """The scene as its sweep reads it: ``[outputs.sweep]`` the optimisation's duration, levels and operation."""

    def __init__(self, scene, opts: dict):
        self._scene = scene
        # a sweep in free vibration on every core, with the optimisation's duration and levels
        self._sweep = {"gap_m": PAPER_GAP, "mass_kg": TABLE1_PARAMETERS["m"], "duration_s": opts["duration_s"],
                       "levels": opts["levels"], "workers": 0, "equal_total_mass": opts["equal_total_mass"],
                       "in_operation": opts["in_operation"] or opts["mode"] == "operation",
                       "noise_seconds": opts["noise_seconds"]}

    def output(self, kind: str) -> dict:
        return dict(self._sweep) if kind == "sweep" else self._scene.output(kind)

    def __getattr__(self, name):
        return getattr(self._scene, name)


def _given(spec) -> dict:
    """The :func:`acoustiviz.app.sweep.sweep_spec` parameters of a one-design spec's fixed values."""
    s = spec.settings
    given = {k: getattr(s, k) for k in _SAME}
    given["room"] = dict(s.room) if s.room else None
    given.update(radius="mass" if s.radius_mode == "from-mass" else s.radius, density=s.density,
                 c1=spec.c1[0], v0=spec.v0[0], distance=spec.distance[0], config=spec.config[0],
                 angle_deg=math.degrees(spec.angle[0]))
    given.update({"k_hertz": spec.k_hertz[0]} if spec.material is None else {"material": spec.material[0]})
    return given


def optimize_settings(scene, out=None) -> OptimizeJob:
    """The scene's ``[outputs.optimize]`` as an :class:`OptimizeJob` writing into ``out/optimize`` (None: no folder)."""
    from .names import DERIVED, SCENE_SWEEP_KEYS, vocabulary
    from .optimize import optimize_variables
    from .sweep import sweep_settings

    opts = scene.output("optimize")
    records = (*OPTIMIZE, *SCENE_VARIABLES, *SCENE_OPERATION, *EXECUTION)
    names = {**vocabulary("scene", records, {"variables": "gap"}), "angle_deg": DERIVED["scene"]["angle_deg"]}
    # the sweep's checks of the optimisation's duration, levels and level interval name [outputs.optimize]'s keys
    sweep = sweep_settings(_AsSweep(scene, opts), names={**SCENE_SWEEP_KEYS, **vocabulary(
        "scene", (), {"duration": "duration", "levels": "levels", "noise_seconds": "noise_seconds"},
        lookup=(*records, SCENE_LEVELS))})
    spec, operation = sweep.spec, sweep.operation
    given = {**_given(spec), "gap": opts["gap_m"], "m": opts["mass_kg"], "balls": opts["balls"],
             "fill": opts["fill"]}
    variables, fixed = optimize_variables(given, names)
    return OptimizeJob(variables, fixed, minimize=tuple(opts["minimize"]), maximize=tuple(opts["maximize"]),
                       constraints=tuple(opts["constraints"]), evaluations=opts["evaluations"], seed=opts["seed"],
                       batch=opts["batch"], mode="operation" if operation is not None else opts["mode"],
                       operation=operation,
                       out=None if out is None else str(Path(out) / OPTIMIZE_FOLDER), workers=opts["workers"],
                       names=names)


def produce_optimize(ctx):
    """Scene output ``optimize``: ``optimize/evaluations.csv``, ``pareto.csv``, ``optimize.json``, ``pareto.png``.

    In operation also ``optimize/confirmation.csv``.
    """
    from .optimize import run
    from .products import Product

    job = optimize_settings(ctx.scene, ctx.out)
    ctx.path(OPTIMIZE_FOLDER)  # the folder checked before the run
    each = f"{job.fixed.duration:g} s of motion" if job.operation is None else \
        f"{len(job.operation.frequencies)} frequencies in operation"
    ctx.progress(f"optimising: {job.evaluations} designs, {each} each")
    result = run(job, progress=ctx.stream)
    figs = {"evaluations": str(len(result.records)), "feasible": str(int(result.feasible.sum()))}
    if len(job.problem.objectives) > 1:
        figs["pareto_designs"] = str(int(result.pareto.sum()))
    elif result.pareto.any():
        o = job.problem.objectives[0]
        figs[f"best_{o.column}"] = f"{result.best()[0][o.column]:.6g}"
    if result.confirmation is not None:
        figs["confirmation_agrees"] = str(result.confirmation["agree"]).lower()
    paths = result.write()
    return [Product("optimize", p, figs if i == 0 else {}) for i, p in enumerate(paths)]
