"""Settings objects: one frozen dataclass per workflow, checked once against one table of ranges and defaults.

================ ======================================================================================
``table``        the :class:`Setting` record (API name, option, scene key, type, unit, range, default,
                 meaning) and :func:`add_option`, which builds a command-line option from it
``base``         the :class:`Settings` base class that checks its fields against its table, and image sizes
``parse``        a point X,Y,Z, an image size WxH and forcing frequencies typed as text
``impact``       the options of one impact, its waveform and its directivity, and the base of the jobs
                 of one impact (:class:`ImpactJob`)
``waveform``     the waveform job: impact, listeners, sampling and files (:class:`WaveformJob`)
``directivity``  the directivity job: impact, circle, angle step, level and files (:class:`DirectivityJob`)
``damper``       the records of the impact damper (paper eq 15), its start, run and solver; beside it
                 ``damper_job``, the damper job: model, start, run, solver and files (:class:`DamperJob`)
``render``       the balloon, snapshot and animation views, their sizes, planes, times, caption and files;
                 beside it ``render_job``, their jobs: impact, view, caption, files (:class:`SnapshotJob`, ...)
``forced``       the records of the damper in operation: excitation, continuation, solver, noise, files;
                 beside it ``forced_job``, the forced job (:class:`ForcedJob`)
``design``       the target damping inclination and its tolerance, and the design job (:class:`DesignJob`)
``sweep``        the simulated time per design of a sweep, the sweep's options and its sphere radius; beside
                 it ``sweep_job``, the sweep job: swept values, designs, executor, folder (:class:`SweepJob`)
``optimize``     the optimisation job: variables, objectives, constraints, budget, seed, batch, folder
                 (:class:`OptimizeJob`)
``room``         the shoebox room's options
``auralize``     the auralize job: the damper run or the impacts, cavity, listeners, files (:class:`AuralizeJob`),
                 and the command's options as typed (:class:`DamperSettings`, :class:`AuralizeSettings`)
``levels``       the levels job: a calibrated signal, the interval and the CSVs (:class:`LevelsJob`), and
                 the options of ``acoustiviz levels``
``run``          every command's ``--max-memory`` and the options of ``acoustiviz run``
``scene``        the keys only a scene has: its title, listeners, damper radius and pulse mass, the
                 configuration's kind and struck surface, the grids' memory cap, outputs asked by key
================ ======================================================================================

The command line builds its options from the records, the scene schema its keys, and the
settings objects check their values with them; ``acoustiviz --help``, ``acoustiviz run
--help-scene`` and the documentation's reference all print the same ranges and defaults.
"""

from .base import Settings, check_size
from .design import DesignSettings
from .impact import DirectivitySettings, WaveformSettings
from .levels import LevelsSettings
from .parse import parse_point, parse_size
from .render import AnimationSettings, BalloonSettings, SnapshotSettings
from .sweep import SweepSettings
from .table import SAME, Setting, add_option

#: The jobs, each imported when first asked for (``acoustiviz --help`` needs the records alone).
_JOBS = {"DamperJob": "damper_job", "DesignJob": "design", "DirectivityJob": "directivity", "ForcedJob": "forced_job",
         "OptimizeJob": "optimize", "SnapshotJob": "render_job", "BalloonJob": "render_job",
         "AnimationJob": "render_job", "SweepJob": "sweep_job", "WaveformJob": "waveform"}


def __getattr__(name: str):
    if name in _JOBS:
        import importlib

        return getattr(importlib.import_module(f".{_JOBS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["Setting", "SAME", "Settings", "add_option", "check_size", "parse_point", "parse_size",
           "WaveformSettings", "DirectivitySettings", "BalloonSettings", "SnapshotSettings", "AnimationSettings",
           "ForcedJob", "DesignSettings", "SweepSettings", "LevelsSettings", "WaveformJob",
           "DamperJob", "DirectivityJob", "DesignJob", "SweepJob", "SnapshotJob", "BalloonJob", "AnimationJob",
           "OptimizeJob"]
