"""The settings of the sweep job: the swept values, the damper and sound of every design, where they run, the folder.

:class:`SweepJob` is the whole of what :func:`acoustiviz.app.sweep.run` needs, checked once when it is made
(the records' ranges, the memory budget, the grid of designs, the executor and the folder: new, resumable, or
another sweep replaced only with ``overwrite``), so ``acoustiviz sweep``, a scene's ``[outputs.sweep]`` and a
Python caller build the same object and hand it to the same run. :func:`sweep_job` builds it from values as
the user typed them (one value, ``START:STOP:COUNT`` or ``A,B,C``; the angle in degrees).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

from ...constants import (
    DEFAULT_AIR_DENSITY,
    DEFAULT_DURATION,
    DEFAULT_RTOL,
    DEFAULT_SOUND_SPEED,
    DEFAULT_WALL_DISTANCE,
    PAPER_ANGLE_DEG,
    PAPER_DISTANCE,
    PAPER_GAP,
    PAPER_RADIUS,
    PAPER_V0,
    TABLE1_PARAMETERS,
)
from ...errors import ParameterError, user_terms
from .base import Settings
from .damper import BALLS, MODEL, RUN
from .sweep import SWEEP_RUN, SWEPT, sweep_radius
from .table import by_name

__all__ = ["SweepJob", "sweep_job", "INCLINATION_MAP", "SPL_MAP", "REPORTS"]

#: File names of the Figure 6 maps inside a sweep folder.
INCLINATION_MAP = "inclination_map.png"
SPL_MAP = "max_spl_map.png"
#: The reports a sweep writes in its folder after its designs: file name -> format.
REPORTS = {"design_table.csv": "csv", INCLINATION_MAP: "png", SPL_MAP: "png"}

#: The job's own records: the swept damper values (each a tuple) and where and how the sweep runs.
_JOB_RECORDS = tuple(s for s in SWEPT if s.kind == "range") + tuple(
    s for s in SWEEP_RUN if s.name in ("out", "executor", "workers", "overwrite", "definition", "band_width"))


@dataclasses.dataclass(frozen=True)
class SweepJob(Settings):
    """A grid of damper designs (paper Figure 6), where it runs, its folder and its design report.

    Attributes
    ----------
    gap, m, mass_ratio, c1, k_hertz, material, v0, distance, angle, config, balls, fill : tuple
        The values of each axis (:class:`acoustiviz.sweep.SweepSpec`, SI units, the angle in rad); ``m`` or
        ``mass_ratio``, ``k_hertz`` or ``material``, ``gap`` or ``fill`` (None: the other; both None: Table
        1's m and K_HZ, the Figure 5 gap); ``balls`` None: one ball.
    settings : acoustiviz.sweep.FixedSettings
        The damper, solver, sphere and sound of every design (duration in s, the levels on or off).
    out : str, optional
        The sweep folder (None: no folder, the checks of the settings alone).
    executor : str
        ``"process"`` or ``"dask://HOST:PORT"``.
    workers : int, optional
        Processes of the local pool (None: every core).
    overwrite : bool
        Move a folder's sweep with other settings aside and start afresh.
    definition : {"two-maxima", "fit"}
        Damping inclination of the design table and of map A.
    band_width : float
        Width of the design table's bands in m/s.
    max_memory_mb : float, optional
        Cap in MB on the estimated memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).
    operation : acoustiviz.sweep.Operation, optional
        Evaluate every design in operation under this excitation over its band
        (:mod:`acoustiviz.app.settings.sweep_operation`); None: free vibration from ``v0``.
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name (not compared).
    spec : acoustiviz.sweep.SweepSpec
        The grid, built by :meth:`validate` (not compared: it follows from the rest).
    """

    TABLE = _JOB_RECORDS
    gap: tuple | None = None
    m: tuple | None = None
    mass_ratio: tuple | None = None
    c1: tuple = (TABLE1_PARAMETERS["c1"],)
    k_hertz: tuple | None = None
    material: tuple | None = None
    v0: tuple = (PAPER_V0,)
    distance: tuple = (PAPER_DISTANCE,)
    angle: tuple = (math.radians(PAPER_ANGLE_DEG),)
    config: tuple = ("plane",)
    balls: tuple | None = None
    fill: tuple | None = None
    settings: object = None
    out: str | None = None
    executor: str = "process"
    workers: int | None = None
    overwrite: bool = False
    definition: str = "two-maxima"
    band_width: float = 0.001
    max_memory_mb: float | None = None
    operation: object = None
    names: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)
    spec: object = dataclasses.field(default=None, init=False, compare=False, repr=False)

    def validate(self) -> None:
        """The damper's ranges, the memory budget, the grid, the executor, the operation, then the folder."""
        from ...sweep import FixedSettings, Operation

        if self.settings is None:
            object.__setattr__(self, "settings", FixedSettings())
        # neither masses nor ratios, neither K_HZ nor materials: Table 1's, so equal sweeps are equal jobs
        if self.m is None and self.mass_ratio is None:
            object.__setattr__(self, "m", (TABLE1_PARAMETERS["m"],))
        if self.k_hertz is None and self.material is None:
            object.__setattr__(self, "k_hertz", (TABLE1_PARAMETERS["k_hertz"],))
        if self.gap is None and self.fill is None:
            object.__setattr__(self, "gap", (PAPER_GAP,))
        if self.operation is not None and not isinstance(self.operation, Operation):
            raise ParameterError("operation", f"expected an Operation, got {type(self.operation).__name__}")
        self._check_ranges()
        self._check_budget()
        object.__setattr__(self, "spec", self._build_spec())
        from ...sweep.execute import check_executor_form

        check_executor_form(self.executor)
        if self.operation is not None:
            from ...sweep.operation import check_operation

            check_operation(self.spec.designs(), self.settings, self.operation)
        if self.out is not None:
            self._check_folder()

    def _check_ranges(self) -> None:
        """M, K, C and the masses of mass ratios in the damper records' ranges; the configurations; the angles."""
        from ...core.geometry import geometry_class

        records = by_name(MODEL + RUN + BALLS)
        for name in ("M", "K", "C", "k_hertz_ball", "c1_ball"):
            if getattr(self.settings, name) is not None:
                records[name].check(getattr(self.settings, name), name)
        for ratio in self.mass_ratio or ():
            mass = ratio * self.settings.M
            try:
                records["m"].check(mass, "m")
            except ParameterError as exc:
                raise ParameterError("mass_ratio", f"{ratio:g} gives an impact mass m = ratio x M = {mass:g} kg, "
                                                   f"but the impact mass {exc.detail}") from None
        from ..._validate import check_choice, check_range
        from ...sweep.spec import sweepable

        for cfg in self.config:  # the geometries the fixed settings can build (a room needs its settings)
            check_choice("config", cfg, sweepable(self.settings))
        # the paper's geometries bound the angle by their class; a room by where its sphere is (SweepSpec checks)
        limits = [lim for c in self.config if isinstance(lim := geometry_class(c).polar_limit_deg, float)]
        for a in self.angle:
            check_range("angle_deg", math.degrees(a), 0.0, min(limits, default=180.0), unit="deg")

    def _check_budget(self) -> None:
        """The designs at once and the table within the memory cap, counted before the grid is built."""
        from ...dynamics import DamperModel
        from ..budget import check_budget, sweep_estimate

        s = self.settings
        if self.operation is not None:  # the attractor searches and click trains of each design at once
            from ..budget import forced_estimate

            op = self.operation
            est = forced_estimate(len(op.frequencies), op.max_cycles, noise_seconds=op.noise_seconds or 1.0)
            api = {"--max-cycles": "max_cycles", "--freq": "frequencies", "--noise-seconds": "noise_seconds"}
            n = self.workers or 2  # designs at once, as the free sweep's estimate counts them
            est = dataclasses.replace(est, memory=n * est.memory, what=f"{est.what}; {n} designs at once",
                                      options=tuple(self._name(api.get(o, o)) for o in est.options))
            check_budget(est, self.max_memory_mb, cap_name=self._name("max_memory_mb"))
            return
        swept = {self._name(a): getattr(self, a) for a in ("gap", "m", "mass_ratio", "c1", "k_hertz", "material",
                                                           "v0", "distance", "angle", "config", "balls", "fill")}
        option = self._name("duration")
        check_budget(sweep_estimate(swept, DamperModel(M=s.M, K=s.K, C=s.C), s.duration, self.workers or 2,
                                    options=(option,)),
                     self.max_memory_mb, cap_name=self._name("max_memory_mb"))

    def _build_spec(self):
        from ...sweep import SweepSpec

        return SweepSpec(gap=self.gap, m=self.m, mass_ratio=self.mass_ratio, c1=self.c1, k_hertz=self.k_hertz,
                         material=self.material, v0=self.v0, distance=self.distance, angle=self.angle,
                         config=self.config, balls=self.balls, fill=self.fill, settings=self.settings)

    def _check_folder(self) -> None:
        """A folder that takes files; a new sweep's reports replace no file unasked; a resumed one is this sweep."""
        from ...sweep import SWEEP_JSON
        from ...sweep.store import check_dir
        from ..outputs import check_output_dir, check_output_file

        name = self._name("out")
        out = check_output_dir(name, self.out)
        if not (out / SWEEP_JSON).exists() and self.operation is None:  # a new sweep's reports replace none
            for report, kind in REPORTS.items():
                if (out / report).exists() or (out / report).is_symlink():
                    check_output_file(name, out / report, kind)
        with user_terms({"out": name}):
            if self.operation is None:
                check_dir(self.spec, out, self.overwrite)
            else:
                from ...sweep.in_operation import operation_document
                from ...sweep.operation import operation_columns

                check_dir(self.spec, out, self.overwrite, operation_document(self.operation),
                          operation_columns(self.spec.with_balls))

    def folder(self) -> Path:
        """The sweep folder, or a :class:`ParameterError` naming ``out`` when there is none."""
        if self.out is None:
            raise ParameterError(self._name("out"), "a sweep needs a folder for its journal")
        return Path(self.out)

    def _name(self, api: str) -> str:
        """The option or scene key of API parameter ``api`` (itself without one)."""
        return self.names.get(api, api)


def _axis(given: dict, name: str, default, kind=float):
    from ...sweep import parse_values

    value = given.get(name, default)
    return None if value is None else parse_values(name, value, kind)


def _fixed_settings(given: dict):
    """The :class:`~acoustiviz.sweep.FixedSettings` of ``given`` (absent ones take the constants' defaults)."""
    from ...sweep import FixedSettings

    radius_mode, radius = sweep_radius(given.get("radius", PAPER_RADIUS))
    if radius_mode == "fixed" and given.get("density") is not None:
        raise ParameterError("density", "sets the sphere's radius from the impact mass; it needs a radius "
                                        "from the mass (--radius mass)")
    return FixedSettings(
        M=given.get("M", TABLE1_PARAMETERS["M"]), K=given.get("K", TABLE1_PARAMETERS["K"]),
        C=given.get("C", TABLE1_PARAMETERS["C"]), clip_tensile=bool(given.get("clip_tensile", False)),
        duration=given.get("duration", DEFAULT_DURATION), solver=given.get("solver", "event"),
        rtol=given.get("rtol", DEFAULT_RTOL), radius_mode=radius_mode, radius=radius, density=given.get("density"),
        surface=given.get("surface"), pulse=given.get("pulse", "half-sine"),
        pulse_mass=given.get("pulse_mass", "impact"), c=given.get("c", DEFAULT_SOUND_SPEED),
        rho=given.get("rho", DEFAULT_AIR_DENSITY), wall_distance=given.get("wall_distance", DEFAULT_WALL_DISTANCE),
        n_fastest=given.get("n_fastest", 4), levels=bool(given.get("levels", False)), room=given.get("room"),
        equal_total_mass=bool(given.get("equal_total_mass", False)), k_hertz_ball=given.get("k_hertz_ball"),
        c1_ball=given.get("c1_ball"))


def sweep_job(given: dict, *, names=None, **job) -> SweepJob:
    """The :class:`SweepJob` of values as typed: swept ones one value, ``START:STOP:COUNT`` or ``A,B,C``.

    Parameters
    ----------
    given : dict
        The values given (absent ones take the paper's: Table 1, the Figure 5 start, the Figure 2 sphere and
        listener): ``gap``, ``m`` or ``mass_ratio``, ``c1``, ``k_hertz`` or ``material``, ``v0``, ``distance``
        (m), ``angle_deg`` (degrees), ``config``; the damper ``M``, ``K``, ``C``, ``clip_tensile``,
        ``duration``, ``solver``, ``rtol``; the sound ``radius`` (m or ``"mass"``), ``density``, ``surface``,
        ``pulse``, ``pulse_mass``, ``c``, ``rho``, ``wall_distance``, ``n_fastest``, ``levels``, ``room``; in
        operation (:func:`~acoustiviz.app.settings.sweep_operation.split_operation`) ``force`` or ``base``,
        ``frequencies`` and the search settings, ``solver`` and ``rtol`` then the search's.
    names : dict, optional
        API parameter -> the option or scene key errors name.
    **job
        The other :class:`SweepJob` fields (``out``, ``executor``, ``workers``, ``overwrite``, ``definition``,
        ``band_width``, ``max_memory_mb``).

    Returns
    -------
    SweepJob
    """
    from .sweep_operation import split_operation

    names = names or {}
    with user_terms(names):
        operation, given = split_operation(given)
        if given.get("m") is not None and given.get("mass_ratio") is not None:
            raise ParameterError("m", "give either the impact mass or the mass ratio, not both")
        if given.get("k_hertz") is not None and given.get("material") is not None:
            raise ParameterError("k_hertz", "give either K_HZ or the sphere material, not both")
        fill = given.get("fill")
        if given.get("gap") is not None and fill is not None:
            raise ParameterError("fill", f"give either {names.get('gap', 'gap')} (the free travel) or "
                                         f"{names.get('fill', 'fill')} (the balls' fraction of the cavity), not both")
        settings = _fixed_settings(given)
        ratio, material = given.get("mass_ratio"), given.get("material")
        axes = dict(
            gap=None if fill is not None else _axis(given, "gap", PAPER_GAP),
            m=None if ratio is not None else _axis(given, "m", TABLE1_PARAMETERS["m"]),
            mass_ratio=_axis(given, "mass_ratio", None),
            c1=_axis(given, "c1", TABLE1_PARAMETERS["c1"]),
            k_hertz=None if material is not None else _axis(given, "k_hertz", TABLE1_PARAMETERS["k_hertz"]),
            material=_axis(given, "material", None, str),
            v0=_axis(given, "v0", PAPER_V0),
            distance=_axis(given, "distance", PAPER_DISTANCE),
            angle=tuple(math.radians(a) for a in _axis(given, "angle_deg", PAPER_ANGLE_DEG)),
            config=_axis(given, "config", "plane", str),
            balls=_axis(given, "balls", None),
            fill=_axis(given, "fill", None),
        )
    return SweepJob(**axes, settings=settings, names=names, operation=operation, **job)
