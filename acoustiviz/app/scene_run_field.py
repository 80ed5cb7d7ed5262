"""Scene output ``run_field``: the damper run's levels on a grid of listeners and its waveform at the listeners.

:func:`run_field_settings` turns ``[outputs.run_field]`` and the scene's sound (the auralize job of
:func:`acoustiviz.app.scene_wav.wav_settings`: the damper run, cavity, clicks, listeners, room's sound and
the memory cap ``grids.memory_limit_mb``) into the :class:`~acoustiviz.app.settings.run_field.RunFieldJob`
that ``acoustiviz auralize --grid ...`` builds from its options; :func:`run_field_products` runs it on the
scene's one damper run and turns its files into the summary's products.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ParameterError
from .scene_wav import wav_settings
from .settings.run_field import RunFieldJob, scene_files

__all__ = ["run_field_settings", "run_field_products"]

#: ``[outputs.run_field]`` key -> the job's API name.
_KEYS = {"grid": "grid", "distance_m": "grid_distance", "arc_deg": "grid_arc", "points": "grid_points",
         "section": "grid_section", "extent_m": "grid_extent", "snapshot_time_s": "snapshot_time"}


def run_field_settings(scene, out=None, damper=None) -> RunFieldJob:
    """The scene's ``[outputs.run_field]`` as a :class:`~acoustiviz.app.settings.run_field.RunFieldJob`.

    ``damper``: the scene's damper run's :class:`~acoustiviz.app.settings.damper_job.DamperJob`; the files
    (:func:`~acoustiviz.app.settings.run_field.scene_files`) are put in folder ``out`` (None: no files, the
    checks of the scene's settings alone, made before the run folder exists); errors name scene keys.
    """
    opts = scene.output("run_field")
    if opts["vtk"] and opts["snapshot_time_s"] is None:
        raise ParameterError("outputs.run_field.vtk", "needs outputs.run_field.snapshot_time_s: the instant to store")
    files = scene_files(opts["grid"], opts["waveform"], opts["snapshot_time_s"] is not None, opts["vtk"])
    if not files:
        raise ParameterError("outputs.run_field", "asks for nothing: set grid (directivity or map), waveform = true "
                                                  "or snapshot_time_s")
    names = RunFieldJob.names_for("scene")
    paths = {} if out is None else {k: str(Path(out) / v) for k, v in files.items()}
    return RunFieldJob(wav_settings(scene, None, damper), **{api: opts[key] for key, api in _KEYS.items()},
                       names=names, **paths)


def run_field_products(ctx, job: RunFieldJob) -> list:
    """Run ``job`` on the scene's one damper run, write its files and return the summary's products."""
    from .products import Product
    from .run_field import run

    for path in (getattr(job, k) for k in job.FILES):
        if path is not None:  # only the files checked before the run
            ctx.path(Path(path).name)
    if job.snapshot_vtk is not None:
        from ..output.vtk import geometry_path

        ctx.path(geometry_path(job.snapshot_vtk).name)
    if job.grid != "none":
        ctx.progress(f"the damper run's levels on the {job.grid} grid, rendered at each point at 96 kHz")
    result = run(job, damper=ctx.damper)
    products = []
    for path in result.write():
        figures = {}
        if path.suffix == ".csv" and str(path) == job.grid_csv:
            lv = result.levels
            figures = {"points_heard": str(int(result.heard.sum())),
                       **{f"max_{c}": f"{np.nanmax(lv[c]):.1f}" for c in ("laeq_db", "lcpeak_db", "lafmax_db",
                                                                          "sel_a_db")}}
        products.append(Product("run_field", path, figures))
    return products
