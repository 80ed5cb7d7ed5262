"""Design sweeps from a user's settings, and the files and report of a finished sweep.

``acoustiviz sweep``, ``acoustiviz design`` and a scene's ``[outputs.sweep]`` and
``[outputs.design_table]`` all call these functions: :func:`sweep_spec` turns settings (numbers,
``start:stop:count`` ranges or comma lists) into a :class:`~acoustiviz.sweep.SweepSpec` with the
defaults of :mod:`acoustiviz.constants`; :func:`scene_sweep_spec` reads a scene through the very
same function, so the same settings give the same ``sweep.json`` -- and either front-end resumes
the other's folder; :func:`run_sweep_outputs` runs (or resumes) a sweep and writes the design
table and the Figure 6 maps. Errors name the API parameter; front-ends translate the names with
:func:`acoustiviz.app.names.user_terms` (:data:`SWEEP_OPTIONS` for the command line). SI units;
angles in degrees where a name says ``_deg``.

Examples
--------
>>> spec = sweep_spec(gap="0.02:0.06:5", m="0.02,0.04", duration=1.0)
>>> spec.gap, spec.m, spec.settings.rtol
((0.02, 0.03, 0.04, 0.05, 0.06), (0.02, 0.04), 1e-13)
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

from .._validate import check_choice, check_positive, check_range
from ..constants import (
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
from ..core.geometry import geometry_class
from ..errors import ParameterError
from ..sweep import (
    DEFINITIONS,
    DESIGN_TABLE_CSV,
    PAPER_TABLE2,
    RANK_COLUMNS,
    SWEEP_CSV,
    SWEEP_JSON,
    FixedSettings,
    SweepSpec,
    design,
    design_table,
    load_sweep,
    parse_values,
    run_sweep,
    write_design_table,
)
from ..sweep.spec import sweepable
from .settings.damper import MODEL, RUN
from .settings.design import DEFAULT_TOLERANCE
from .settings.sweep import SWEPT, sweep_radius
from .settings.table import by_name

__all__ = ["SWEEP_OPTIONS", "DESIGN_OPTIONS", "INCLINATION_MAP", "SPL_MAP", "SweepRun", "sweep_spec",
           "scene_sweep_spec", "write_sweep_outputs", "run_sweep_outputs", "sweep_summary", "design_report",
           "check_executor", "check_sweep_work", "sweep_workflow", "with_room", "check_ranges"]

#: :func:`sweep_spec` / :func:`run_sweep_outputs` parameter -> ``acoustiviz sweep`` option.
SWEEP_OPTIONS = {
    "gap": "--gap", "m": "--m", "mass_ratio": "--mass-ratio", "c1": "--c1", "k_hertz": "--k-hertz",
    "material": "--material", "v0": "--v0", "distance": "--distance", "angle": "--angle", "angle_deg": "--angle",
    "config": "--config", "M": "--M", "K": "--K", "C": "--C", "clip_tensile": "--clip-tensile",
    "duration": "--duration", "solver": "--solver", "rtol": "--rtol", "radius": "--radius",
    "radius_mode": "--radius", "density": "--density", "surface": "--surface", "pulse": "--pulse",
    "pulse_mass": "--pulse-mass", "c": "--c", "rho": "--rho", "wall_distance": "--wall-distance",
    "n_fastest": "--spl-fastest", "levels": "--levels", "out": "--out", "executor": "--executor",
    "workers": "--workers",
    "definition": "--definition", "width": "--band-width", "band_width": "--band-width",
}
#: :func:`design_report` parameter -> ``acoustiviz design`` option.
DESIGN_OPTIONS = {"sweep": "--sweep", "out": "--sweep", "inclination": "--inclination", "tolerance": "--tolerance",
                  "definition": "--definition", "width": "--band-width", "band_width": "--band-width",
                  "rank_by": "--rank-by"}

#: File names of the Figure 6 maps inside a sweep directory.
INCLINATION_MAP = "inclination_map.png"
SPL_MAP = "max_spl_map.png"


def sweep_spec(*, gap=PAPER_GAP, m=None, mass_ratio=None, c1=TABLE1_PARAMETERS["c1"], k_hertz=None, material=None,
               v0=PAPER_V0, distance=PAPER_DISTANCE, angle_deg=PAPER_ANGLE_DEG, config="plane",
               M=TABLE1_PARAMETERS["M"], K=TABLE1_PARAMETERS["K"], C=TABLE1_PARAMETERS["C"], clip_tensile=False,
               duration=DEFAULT_DURATION,
               solver="event", rtol=DEFAULT_RTOL, radius=PAPER_RADIUS, density=None, surface=None,
               pulse="half-sine", pulse_mass="impact", c=DEFAULT_SOUND_SPEED, rho=DEFAULT_AIR_DENSITY,
               wall_distance=DEFAULT_WALL_DISTANCE, n_fastest=4, levels=False, room=None) -> SweepSpec:
    """The sweep of the given settings; swept ones take a value, ``start:stop:count`` or ``a,b,c``.

    Parameters
    ----------
    gap, m, mass_ratio, c1, k_hertz, v0, distance : number, str or sequence
        Swept values: gap d (m), impact mass (kg) or mass ratio m/M instead, contact damping
        (N·s/m), Hertz stiffness (N/m^1.5), initial main-mass velocity (m/s), listener distance
        (m). Defaults: paper Table 1 and Figure 5 (m = 40.5 g, K_HZ = 5.6e8).
    material : str or sequence of str, optional
        Sphere materials instead of ``k_hertz`` (K_HZ from paper eq 2).
    angle_deg : number, str or sequence
        Listener angles in degrees from the acceleration axis (<= 90 with a reflecting surface).
    config : str or sequence of str
        ``"free"``, ``"plane"`` or ``"wall-floor"``.
    M, K, C, clip_tensile, duration, solver, rtol
        The damper and its solver (:class:`~acoustiviz.sweep.FixedSettings`; ``rtol`` defaults to
        :data:`~acoustiviz.constants.DEFAULT_RTOL`, as for every damper run).
    radius : float or "mass"
        Radius of the radiating sphere in m, or ``"mass"``: from the impact mass and ``density``.
    density : float, optional
        Sphere density in kg/m³; only with ``radius="mass"`` (default 7800 or the material's).
    surface, pulse, pulse_mass, c, rho, wall_distance, n_fastest, levels
        See :class:`~acoustiviz.sweep.FixedSettings`.
    room : dict, optional
        The settings of a shoebox room (:class:`acoustiviz.core.room_geometry.Room`), for
        ``config="room"`` (:attr:`acoustiviz.sweep.FixedSettings.room`).

    Returns
    -------
    SweepSpec
    """
    if m is not None and mass_ratio is not None:
        raise ParameterError("m", "give either the impact mass or the mass ratio, not both")
    if k_hertz is not None and material is not None:
        raise ParameterError("k_hertz", "give either K_HZ or the sphere material, not both")
    radius_mode, radius = sweep_radius(radius)
    if radius_mode == "fixed":
        if density is not None:
            raise ParameterError("density", "sets the sphere's radius from the impact mass; it needs a radius "
                                            "from the mass (--radius mass)")
    settings = FixedSettings(M=M, K=K, C=C, clip_tensile=bool(clip_tensile), duration=duration, solver=solver,
                             rtol=rtol, radius_mode=radius_mode, radius=radius, density=density, surface=surface,
                             pulse=pulse, pulse_mass=pulse_mass, c=c, rho=rho, wall_distance=wall_distance,
                             n_fastest=n_fastest, levels=bool(levels), room=room)
    configs = parse_values("config", config, str)
    for cfg in configs:
        check_choice("config", cfg, sweepable(settings))
    angles = parse_values("angle_deg", angle_deg)
    # the paper's geometries bound the angle by their class; a room by where its sphere is (SweepSpec checks)
    limits = [lim for c in configs if isinstance(lim := geometry_class(c).polar_limit_deg, float)]
    for a in angles:
        check_range("angle_deg", a, 0.0, min(limits, default=180.0), unit="deg")
    spec = SweepSpec(
        gap=parse_values("gap", gap),
        m=None if mass_ratio is not None else parse_values("m", TABLE1_PARAMETERS["m"] if m is None else m),
        mass_ratio=None if mass_ratio is None else parse_values("mass_ratio", mass_ratio),
        c1=parse_values("c1", c1),
        k_hertz=None if material is not None else parse_values(
            "k_hertz", TABLE1_PARAMETERS["k_hertz"] if k_hertz is None else k_hertz),
        material=None if material is None else parse_values("material", material, str),
        v0=parse_values("v0", v0),
        distance=parse_values("distance", distance),
        angle=tuple(math.radians(a) for a in angles),
        config=configs,
        settings=settings,
    )
    check_ranges(spec)
    return spec


def check_ranges(spec: SweepSpec) -> None:
    """Refuse a value of ``spec`` outside the range of its damper record, naming its axis (or setting).

    The records of :mod:`acoustiviz.app.settings.damper` hold the ranges ``acoustiviz damper`` and a
    scene's ``[damper]`` check, so a sweep refuses what they refuse: the swept gap, impact mass,
    contact damping, Hertz stiffness and initial velocity, and the fixed M, K and C. Impact masses
    given as mass ratios are checked as masses, the error naming ``mass_ratio``.
    """
    records = by_name(MODEL + RUN)
    for name in ("M", "K", "C"):
        records[name].check(getattr(spec.settings, name), name)
    if spec.mass_ratio is not None:
        for ratio, mass in zip(spec.mass_ratio, spec.masses, strict=True):
            try:
                records["m"].check(mass, "m")
            except ParameterError as exc:
                raise ParameterError("mass_ratio", f"{ratio:g} gives an impact mass m = ratio x M = {mass:g} kg, "
                                                   f"but the impact mass {exc.detail}") from None
    for name in ("gap", "m", "c1", "k_hertz", "v0"):
        for value in getattr(spec, name) or ():
            records[name].check(value, name)


#: :func:`sweep_spec` parameter -> the scene key it is read from (errors name the key).
SCENE_KEYS = {"gap": "outputs.sweep.gap_m", "m": "outputs.sweep.mass_kg", "duration": "outputs.sweep.duration_s",
              "c1": "damper.contact_damping_n_s_m", "v0": "damper.initial_velocity_m_s",
              "M": "damper.main_mass_kg", "K": "damper.stiffness_n_m", "C": "damper.damping_n_s_m",
              "rtol": "damper.tolerance", "solver": "damper.solver", "radius": "sphere.radius_m",
              "density": "sphere.density_kg_m3", "material": "sphere.material", "surface": "contact.surface",
              "k_hertz": "contact.k_hertz_n_m1_5", "wall_distance": "configuration.wall_distance_m",
              "distance": "listeners", "angle": "listeners", "angle_deg": "listeners",
              "config": "configuration.kind"}


def scene_sweep_spec(scene, solver: str | None = None) -> SweepSpec:
    """The :class:`~acoustiviz.sweep.SweepSpec` of a scene's ``[outputs.sweep]`` (gap × impact mass).

    The scene's settings go through :func:`sweep_spec`, the function behind ``acoustiviz sweep``,
    so a scene and the command with the same settings make the same sweep. The listener is the
    scene's first; ``solver`` is the damper solver the scene resolved (its ``"auto"`` choice).
    """
    from ..dynamics import solver_method
    from ..errors import SceneError
    from .names import user_terms

    opts = scene.output("sweep")
    d, s, c = scene.section("damper"), scene.section("sphere"), scene.section("contact")
    conf = scene.section("configuration")
    if scene.geometry_settings().get("strike", "floor") != "floor":
        raise SceneError(scene.source, "configuration.strike", "sweeps support floor strikes only")
    listener = scene.data["listeners"][0]
    if listener["position_m"] is None:
        distance, angle_deg = listener["distance_m"], listener["angle_deg"]
    else:  # a listener given by position: its distance and angle from the sphere's centre
        import numpy as np

        (_, pos), *_ = scene.listeners()
        geom = scene.configuration()
        rel = np.asarray(pos) - np.asarray(geom.centre)
        distance = float(np.linalg.norm(rel))
        angle_deg = math.degrees(math.acos(max(-1.0, min(1.0, float(rel @ np.asarray(geom.axis)) / distance))))
    if solver is None:
        from .products import damper_solver

        solver = damper_solver(scene)
    medium = scene.medium()
    from_mass = s["damper_radius"] == "from-mass"
    stiffness = {"material": s["material"]} if (s["material"] and c["k_hertz_n_m1_5"] is None) else \
        {"k_hertz": scene.k_hertz()}
    with user_terms(SCENE_KEYS):
        return sweep_spec(
            gap=opts["gap_m"], m=opts["mass_kg"], c1=d["contact_damping_n_s_m"], v0=d["initial_velocity_m_s"],
            distance=distance, angle_deg=angle_deg, config=conf["kind"], M=d["main_mass_kg"], K=d["stiffness_n_m"],
            C=d["damping_n_s_m"], clip_tensile=d["clip_tensile"], duration=opts["duration_s"],
            solver=solver, rtol=solver_method(d["solver"]).run_rtol(d["tolerance"]),
            radius="mass" if from_mass else s["radius_m"], density=s["density_kg_m3"] if from_mass else None,
            surface=c["surface"], pulse=c["pulse"], pulse_mass=c["pulse_mass"], c=medium.c, rho=medium.rho,
            wall_distance=conf["wall_distance_m"], levels=opts["levels"],
            room=scene.geometry_settings().get("room"), **stiffness)


def check_executor(executor, workers=None):
    """Check the ``executor`` text (``"process"`` or ``"dask://HOST:PORT"``) and ``workers`` before any work."""
    if workers is not None and (int(workers) != workers or workers < 1):
        raise ParameterError("workers", f"must be an integer >= 1, got {workers}")
    from ..sweep.execute import check_executor_form

    check_executor_form(executor)


def write_sweep_outputs(table, out_dir, *, definition: str = "two-maxima", band_width: float = 0.001):
    """Write ``design_table.csv`` and, for gap × mass sweeps, the two Figure 6 maps.

    Returns
    -------
    bands : tuple of Band
        The design table (paper Table 2).
    paths : list of Path
        Files written.
    others : list of str
        Swept axes besides gap and mass (the maps are drawn only for gap × mass sweeps).
    """
    from ..output.plot.style import save_figure

    out = Path(out_dir)
    bands = design_table(table, definition=definition, width=band_width)
    paths = [write_design_table(bands, out / DESIGN_TABLE_CSV)]
    others = [a for a in table.spec.swept() if a not in ("gap", "m")]
    if not others and len(table):
        from ..output.plot.design import plot_inclination_map, plot_spl_map

        ax = plot_inclination_map(table, definition=definition)
        paths.append(save_figure(ax.figure, out / INCLINATION_MAP))
        ax = plot_spl_map(table)
        paths.append(save_figure(ax.figure, out / SPL_MAP))
    return bands, paths, others


@dataclass(frozen=True)
class SweepRun:
    """A sweep run (or resumed) with its outputs.

    Attributes
    ----------
    table : SweepTable
        Every row of the directory.
    bands : tuple of Band
        The design table.
    paths : list of Path
        Files written besides ``sweep.json`` and ``sweep.csv``.
    others : list of str
        Swept axes besides gap and mass (no maps for those sweeps).
    seconds : float
        Wall time of this run in s.
    out : Path
        The sweep directory.
    definition : str
        Damping-inclination definition of the design table and the maps.
    """

    table: object
    bands: tuple
    paths: list
    others: list
    seconds: float
    out: Path
    definition: str

    @property
    def journal(self) -> Path:
        """``sweep.csv``."""
        return self.out / SWEEP_CSV


def run_sweep_outputs(spec: SweepSpec, out, *, executor="process", workers=None, progress=None, bar=None,
                      overwrite: bool = False, definition: str = "two-maxima",
                      band_width: float = 0.001) -> SweepRun:
    """Run (or resume) ``spec`` into folder ``out`` and write its design table and maps.

    Parameters
    ----------
    spec : SweepSpec
        The sweep.
    out : path-like
        The sweep directory.
    executor, workers, progress, bar, overwrite
        See :func:`acoustiviz.sweep.run_sweep`.
    definition : {"two-maxima", "fit"}
        Damping inclination of the design table and of map A.
    band_width : float
        Width of the design table's bands in m/s.

    Returns
    -------
    SweepRun
    """
    check_choice("definition", definition, DEFINITIONS)
    check_positive("band_width", band_width, "m/s")
    check_executor(executor, workers)
    t0 = time.perf_counter()
    table = run_sweep(spec, out, executor=executor, workers=workers, progress=progress, bar=bar,
                      overwrite=bool(overwrite))
    seconds = time.perf_counter() - t0
    bands, paths, others = write_sweep_outputs(table, out, definition=definition, band_width=band_width)
    return SweepRun(table, bands, paths, others, seconds, Path(out), definition)


def sweep_summary(run: SweepRun) -> list[str]:
    """Lines reporting a sweep run: designs, failures, files, the largest acoustic saving."""
    table = run.table
    lines = [f"sweep: {len(table)} designs in {run.out} ({run.seconds:.1f} s this run)"]
    n_failed = int(table.failed.sum())
    if n_failed:
        ids = ", ".join(str(i) for i in table["design_id"][table.failed][:10])
        lines.append(f"failed designs: {n_failed} (design_id {ids}{', ...' if n_failed > 10 else ''}; "
                     f"reasons in the error column of {run.journal})")
    lines += [f"wrote {p}" for p in run.paths]
    if run.others:
        lines.append(f"maps skipped: they need only --gap and --m swept (also swept: {', '.join(run.others)})")
    best = max(run.bands, key=lambda b: b.decrease_db, default=None)
    if best is not None:
        lines.append(f"largest acoustic saving at equal damping ({run.definition}): {best.decrease_db:.1f} dB in "
                     f"the band {100 * best.low:.3g}-{100 * best.high:.3g} cm/s ({best.n_designs} designs)")
    return lines


def design_report(sweep, inclination: float, tolerance: float = DEFAULT_TOLERANCE, *, definition: str = "two-maxima",
                  table: bool = False, band_width: float = 0.001, rank_by: str = "max_spl_db") -> list[str]:
    """Lines answering the design query of a sweep directory (paper Table 2).

    Parameters
    ----------
    sweep : path-like
        A sweep directory.
    inclination, tolerance : float
        Target damping inclination and accepted deviation in m/s.
    definition : {"two-maxima", "fit"}
        Damping-inclination definition.
    table : bool
        Also give the design table of the whole sweep.
    band_width : float
        Band width of the table in m/s.
    rank_by : str
        The column ranking the candidates (:data:`acoustiviz.sweep.RANK_COLUMNS`; default
        ``max_spl_db``; ``lafmax_db``, ``lcpeak_db``, ``laeq_db`` for a sweep run with levels).
    """
    from ..sweep.query import check_target

    check_target(inclination, tolerance)
    if rank_by not in RANK_COLUMNS:
        raise ParameterError("rank_by", f"must be one of {', '.join(RANK_COLUMNS)}; got {rank_by!r}")
    check_positive("band_width", band_width, "m/s")
    check_choice("definition", definition, DEFINITIONS)
    if not Path(sweep).is_dir():
        raise ParameterError("sweep", f"no such directory: {sweep}")
    rows = load_sweep(sweep)
    lines = []
    if not rows.complete:
        lines.append(f"note: the sweep is unfinished ({len(rows)} of {len(rows.spec.designs())} designs)")
    lines += design(rows, inclination, tolerance, definition=definition, rank_by=rank_by).summary().splitlines()
    if table:
        lines += ["", f"design table ({definition} damping inclination, bands of {100 * band_width:g} cm/s):",
                  f"{'e (cm/s)':>9} {'n':>4} {'min SPLmax':>11} {'max SPLmax':>11} {'decrease':>9}  quietest (m, d)"]
        for b in design_table(rows, definition=definition, width=band_width):
            ranges = "".join(f"; {name} {lo:.1f}-{hi:.1f} dB" for name, (lo, hi) in
                             zip(("LAFmax", "LCpeak", "LAeq"), (b.level_ranges or {}).values(), strict=False)
                             if math.isfinite(lo))
            lines.append(f"{100 * b.centre:9.2f} {b.n_designs:4d} {b.min_spl_db:11.1f} {b.max_spl_db:11.1f} "
                         f"{b.decrease_db:9.1f}  {1000 * b.quietest_mass:.1f} g, {100 * b.quietest_gap:.2f} cm"
                         f"{ranges}")
    return lines


def scene_design_table(table, out_dir, *, inclination=None, tolerance: float = DEFAULT_TOLERANCE):
    """A scene's ``[outputs.design_table]``: the Table 2 figure beside the paper's, and the choice for a target.

    Returns
    -------
    bands : tuple of Band
    png : Path
        ``design_table.png``.
    choice : DesignChoice or None
        The answer for ``inclination`` (None without a target).
    """
    from ..output.plot.design import plot_design_table
    from ..output.plot.style import save_figure

    bands = design_table(table)
    ax = plot_design_table(bands, paper=PAPER_TABLE2)
    png = save_figure(ax.figure, Path(out_dir) / "design_table.png")
    choice = None if inclination is None else design(table, inclination, tolerance)
    return bands, png, choice


def check_sweep_work(given: dict, *, workers=None, max_memory_mb=None, names=None) -> None:
    """Refuse a sweep whose memory or output would exceed the cap, before anything is built or run.

    Parameters
    ----------
    given : dict
        The :func:`sweep_spec` parameters given (absent ones take their defaults).
    workers : int, optional
        Designs run at once (default: counted as 2).
    max_memory_mb : float, optional
        The cap (:func:`acoustiviz.app.budget.check_budget`).
    names : dict, optional
        Parameter -> the option or scene key named in errors (default :data:`SWEEP_OPTIONS`).
    """
    from ..dynamics import DamperModel
    from .budget import check_budget, sweep_estimate
    from .names import user_terms

    names = SWEEP_OPTIONS if names is None else names
    swept = {names.get(s.name, s.name): given.get(s.name) for s in SWEPT}
    from .settings.sweep import SweepSettings

    with user_terms({"duration": names.get("duration", "duration")}):
        duration = SweepSettings(given.get("duration", DEFAULT_DURATION)).duration
    records = by_name(MODEL)  # the damper's ranges first, as check_ranges does for the sweep
    try:
        model = DamperModel(**{k: records[k].check(given.get(k, TABLE1_PARAMETERS[k])) for k in ("M", "K", "C")})
    except ParameterError as exc:
        raise exc.renamed(names.get(exc.name, exc.name)) from None
    check_budget(sweep_estimate(swept, model, duration, workers or 2, options=(names.get("duration", "duration"),)),
                 max_memory_mb)


def sweep_workflow(given: dict, out, *, executor: str = "process", workers=None, max_memory_mb=None,
                   names=None, **run) -> list:
    """Check, build and run (or resume) a sweep into folder ``out``; return its summary lines.

    The output folder, the memory and output size, the settings and the executor are checked
    before any design runs; errors name :data:`SWEEP_OPTIONS` (or ``names``).

    Parameters
    ----------
    given : dict
        The :func:`sweep_spec` parameters given (absent ones take their defaults).
    out : path-like
        The sweep folder (resumed when it holds the same sweep).
    executor, workers
        Where the designs run (:func:`run_sweep_outputs`).
    max_memory_mb : float, optional
        The cap (:func:`check_sweep_work`).
    names : dict, optional
        Parameter -> the option or scene key named in errors.
    **run
        Further :func:`run_sweep_outputs` arguments (``progress``, ``bar``, ``overwrite``,
        ``definition``, ``band_width``).
    """
    from .names import user_terms
    from .outputs import check_output_dir, check_output_file

    names = SWEEP_OPTIONS if names is None else names
    check_output_dir(names["out"], out)
    if not (Path(out) / SWEEP_JSON).exists():  # a new sweep: its files must not replace others' unasked
        for name, kind in ((DESIGN_TABLE_CSV, "csv"), (INCLINATION_MAP, "png"), (SPL_MAP, "png")):
            if (Path(out) / name).exists() or (Path(out) / name).is_symlink():
                check_output_file(names["out"], Path(out) / name, kind)
    check_sweep_work(given, workers=workers, max_memory_mb=max_memory_mb, names=names)
    with user_terms(names):
        spec = sweep_spec(**given)
        check_executor(executor, workers)
        result = run_sweep_outputs(spec, out, executor=executor, workers=workers, **run)
    return sweep_summary(result)


def with_room(given: dict, room: dict | None) -> dict:
    """The :func:`sweep_spec` parameters ``given`` with a shoebox room's, the room checked before any work.

    Parameters
    ----------
    given : dict
        The :func:`sweep_spec` parameters given.
    room : dict or None
        The room's settings (:func:`acoustiviz.app.impacts.room_settings`: dimensions in m,
        absorption, source in m, the window ``duration`` in s, ...); None: ``given`` unchanged.

    Returns
    -------
    dict
        ``given`` with ``room`` and, unless a configuration is given, ``config="room"``. The room
        is built once around the sweep's sphere (the paper's radius when it follows the mass), so
        a source too close to a wall or a window without images fails here; errors name the room's
        parameters (the caller renames them).
    """
    if room is None:
        return given
    from ..core.geometry import geometry
    from ..core.room_geometry import Room

    geometry(Room.name, sweep_radius(given.get("radius", PAPER_RADIUS))[1], **room)
    return {**given, "config": given.get("config") or Room.name, "room": room}
