"""One design: simulate the damper, radiate its impacts, report one row of the sweep.

:func:`evaluate_design` is the work of one ``sweep.csv`` row; it runs in a worker of any
executor. :func:`evaluate_or_fail` wraps it so that an exception inside a design becomes a
failed row with its reason instead of stopping the sweep. SI units; angles in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..constants import ANALYSIS_RATE, P_REF, SOLVER_RTOL_RANGE
from ..core.geometry import observer_points
from ..errors import ParameterError
from .levels import NO_LEVELS, SWEEP_LEVEL_COLUMNS, design_levels
from .spec import PAPER_RADIUS, Design, FixedSettings

__all__ = ["DesignResult", "listener_point", "sound_setup", "impact_spl_db", "max_spl_db", "evaluate_design",
           "evaluate_or_fail", "failed_result", "warm_up", "evaluate_balls", "collision_spl_db"]


def listener_point(geometry, distance: float, angle: float) -> np.ndarray:
    """Listener position in m, ``distance`` from the sphere's centre, ``angle`` rad off its axis.

    The listener lies in the plane of the acceleration axis and the horizontal direction away
    from any wall (+x), like the command-line ``--distance``/``--angle`` observer
    (:func:`acoustiviz.core.geometry.Geometry.observer_points`).

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    distance : float
        Distance in m (> the sphere radius).
    angle : float
        Polar angle in rad from the acceleration axis.

    Returns
    -------
    (1, 3) ndarray
    """
    point = observer_points(geometry, distance, angle)[0]
    if not bool(geometry.in_fluid(point[None, :])[0]):
        raise ParameterError("angle", "the listener would lie inside a wall or below the floor")
    return point[None, :]


def impact_spl_db(velocity: float, *, mass: float, partner_mass: float, k_hertz: float, pulse: str,
                  geometry, point, medium) -> float:
    """Peak sound pressure level in dB re 20 µPa of one impact at one listener.

    Parameters
    ----------
    velocity : float
        Approach speed in m/s.
    mass : float
        Sphere (impact) mass in kg.
    partner_mass : float
        Mass of the struck body in kg (``inf``: an immovable wall, paper eq 3).
    k_hertz : float
        Hertz stiffness in N/m^1.5.
    pulse : str
        Pulse kind (:func:`acoustiviz.core.pulses.acceleration_pulse`).
    geometry : acoustiviz.core.geometry.Geometry
        Sphere and images.
    point : (1, 3) array_like
        Listener in m.
    medium : acoustiviz.core.medium.Medium
        The air.

    Returns
    -------
    float
        ``20 log10(max|p| / 20 µPa)``; in a room, over the images that arrive within its window
        (:func:`acoustiviz.field.directivity.room_window`).
    """
    from ..core.contact import Impact, acceleration_pulse
    from ..field import field_metrics
    from ..field.directivity import room_window

    imp = Impact(velocity=float(velocity), k_hertz=k_hertz, mass=mass, partner_mass=partner_mass)
    window = room_window(geometry, np.atleast_2d(point), medium)  # a room: the images arriving within its window
    return float(field_metrics(acceleration_pulse(imp, pulse), point, geometry, medium=medium,
                               window=window).peak_spl_db[0])


def max_spl_db(velocities, *, n_fastest: int = 4, **impact_kwargs) -> tuple[float, int]:
    """Largest peak SPL in dB over impacts of the given approach speeds.

    Evaluates the ``n_fastest`` fastest distinct speeds exactly (:func:`impact_spl_db`); the
    level grows with the speed at fixed geometry (:mod:`acoustiviz.sweep`), so the fastest is
    the loudest. If the evaluated levels are not ordered like their speeds, every impact is
    evaluated.

    Parameters
    ----------
    velocities : (n,) array_like
        Approach speeds in m/s of the impacts (non-positive and NaN entries are ignored).
    n_fastest : int
        Number of fastest distinct speeds evaluated; 0 evaluates every impact.
    **impact_kwargs
        Passed to :func:`impact_spl_db`.

    Returns
    -------
    spl : float
        Maximum peak SPL in dB (``-inf`` without impacts).
    n_evaluated : int
        Number of impacts whose level was computed.
    """
    u = np.asarray(velocities, dtype=float)
    u = np.unique(u[np.isfinite(u) & (u > 0)])[::-1]  # distinct, fastest first
    if u.size == 0:
        return -math.inf, 0
    k = u.size if n_fastest == 0 else min(int(n_fastest), u.size)
    levels = [impact_spl_db(v, **impact_kwargs) for v in u[:k]]
    if k < u.size and any(b > a + 1e-9 for a, b in zip(levels, levels[1:], strict=False)):
        levels += [impact_spl_db(v, **impact_kwargs) for v in u[k:]]
        k = u.size
    return float(max(levels)), int(k)


@dataclass(frozen=True)
class DesignResult:
    """What one design gives; one row of ``sweep.csv`` (units in the column names).

    A design that could not be evaluated has ``error`` set to the reason, NaN values and
    ``success`` False.
    """

    design: Design
    inclination_two_maxima: float
    inclination_fit: float
    fit_window_start: float
    fit_window_stop: float
    fit_n_maxima: int
    settling_time: float
    n_impacts: int
    max_spl_db: float
    energy_dissipated_contact: float
    energy_dissipated_main: float
    max_approach_velocity: float
    spl_impacts_evaluated: int
    success: bool
    mass_ratio: float
    error: str = ""
    levels: dict = field(default_factory=lambda: dict(NO_LEVELS))

    def row(self) -> dict:
        """The CSV row as a dict of column name to value."""
        d = self.design
        return {
            "gap_m": d.gap, "mass_kg": d.m,
            "inclination_two_maxima_m_s": self.inclination_two_maxima,
            "inclination_fit_m_s": self.inclination_fit,
            "settling_time_s": self.settling_time, "n_impacts": self.n_impacts,
            "max_spl_db": self.max_spl_db, "design_id": d.design_id, "mass_ratio": self.mass_ratio,
            "c1_n_s_m": d.c1, "k_hertz_n_m1_5": d.k_hertz, "material": d.material, "v0_m_s": d.v0,
            "distance_m": d.distance, "angle_deg": math.degrees(d.angle), "config": d.config,
            "radius_m": d.radius, **({} if d.fill is None else {"balls": d.balls, "fill": d.fill}),
            "energy_dissipated_contact_j": self.energy_dissipated_contact,
            "energy_dissipated_main_j": self.energy_dissipated_main,
            "max_approach_velocity_m_s": self.max_approach_velocity,
            "fit_window_start_s": self.fit_window_start, "fit_window_stop_s": self.fit_window_stop,
            "fit_n_maxima": self.fit_n_maxima, "spl_impacts_evaluated": self.spl_impacts_evaluated,
            **{c: self.levels.get(c, math.nan) for c in SWEEP_LEVEL_COLUMNS},
            "success": int(self.success), "error": self.error,
        }


def evaluate_design(design: Design, settings: FixedSettings) -> DesignResult:
    """Simulate one damper design and radiate its impacts (the work of one sweep row).

    Parameters
    ----------
    design : Design
        The design.
    settings : FixedSettings
        The sweep's fixed settings.

    Returns
    -------
    DesignResult

    Notes
    -----
    The damper runs with :func:`acoustiviz.dynamics.simulate` from x = 0, dx/dt = ``v0``, the
    impact mass centred at rest (paper Figure 5 start); eq 16, the envelope fit and the settling
    time use the exact maxima of x(t) (:func:`acoustiviz.dynamics.maxima.exact_maxima`), not samples.
    With ``settings.levels`` the run's click train is rendered at the listener and its LAFmax,
    LCpeak and LAeq over ``[0, duration]`` are reported (:func:`acoustiviz.sweep.levels.design_levels`).
    A design of several balls is evaluated by :func:`acoustiviz.sweep.balls.evaluate_balls`.
    """
    if design.balls > 1:
        return evaluate_balls(design, settings)
    from ..core.medium import Medium
    from ..dynamics import DamperModel, InitialState, simulate
    from ..dynamics import metrics as dm

    s = settings
    model = DamperModel(M=s.M, K=s.K, C=s.C, m=design.m, gap=design.gap, k_hertz=design.k_hertz,
                        c1=design.c1, clip_tensile=s.clip_tensile)
    res = simulate(model, s.duration, solver=s.solver, initial=InitialState(v=design.v0), rtol=s.rtol)
    metrics = dm.damping_metrics(res, window_fraction=s.fit_window_fraction, settling_fraction=s.settling_fraction)
    two, fit, settle = metrics.two_maxima, metrics.fit, metrics.settling_time
    geometry = design.geometry(s)
    point = listener_point(geometry, design.distance, design.angle)
    u = res.impacts.approach_velocity
    medium = Medium(c=s.c, rho=s.rho)
    spl, n_eval = max_spl_db(
        u, n_fastest=s.n_fastest, mass=design.m,
        partner_mass=math.inf if s.pulse_mass == "impact" else s.M,
        k_hertz=design.k_hertz, pulse=s.pulse, geometry=geometry, point=point, medium=medium,
    )
    levels = dict(NO_LEVELS)
    if s.levels:
        scene, model = sound_setup(design, s, medium)
        levels = design_levels(res.impacts, scene=scene, model=model, point=point, duration=s.duration)
    return DesignResult(
        design=design,
        inclination_two_maxima=float(two.value),
        inclination_fit=float(fit.value),
        fit_window_start=float(fit.t_start),
        fit_window_stop=float(fit.t_stop),
        fit_n_maxima=int(fit.n_maxima),
        settling_time=float(settle),
        n_impacts=len(res.impacts),
        max_spl_db=spl,
        energy_dissipated_contact=float(res.energy.dissipated_contact),
        energy_dissipated_main=float(res.energy.dissipated_main),
        max_approach_velocity=float(np.max(u)) if u.size else 0.0,
        spl_impacts_evaluated=n_eval,
        success=bool(res.success),
        mass_ratio=design.m / s.M,
        levels=levels,
    )


def sound_setup(design: Design, settings: FixedSettings, medium=None):
    """``(cavity scene, click model)`` rendering a design's run as its maximum SPL hears it.

    Every impact strikes the geometry's struck surface (``walls="one"``); the pulse and its
    mass are the sweep's (``pulse``, ``pulse_mass``).
    """
    from ..core.medium import Medium
    from ..sound import CavityScene, ClickModel

    s = settings
    medium = Medium(c=s.c, rho=s.rho) if medium is None else medium
    scene = CavityScene(design.geometry(s), gap=design.gap, walls="one", medium=medium)
    model = ClickModel(k_hertz=design.k_hertz, mass=design.m, main_mass=s.M, mass_model=s.pulse_mass, pulse=s.pulse)
    return scene, model


def failed_result(design: Design, settings: FixedSettings, reason: str) -> DesignResult:
    """The row of a design that could not be evaluated: NaN values, ``success`` False, ``reason``."""
    nan = math.nan
    one_line = " ".join(str(reason).split()) or "unknown error"
    return DesignResult(design, nan, nan, nan, nan, 0, nan, 0, nan, nan, nan, nan, 0, False,
                        design.balls * design.m / settings.M, one_line)


def evaluate_or_fail(design: Design, settings: FixedSettings) -> DesignResult:
    """:func:`evaluate_design`, or a failed row naming the exception that stopped it.

    Any exception of the design (an overflow, a solver error...) becomes a failed row, so that
    one bad design does not stop a sweep. ``KeyboardInterrupt`` and ``SystemExit`` still propagate.
    """
    try:
        return evaluate_design(design, settings)
    except Exception as exc:  # noqa: BLE001 - any failure of one design is recorded in its row
        return failed_result(design, settings, f"{type(exc).__name__}: {exc}")


def warm_up(settings: FixedSettings) -> None:
    """Run a tiny design so that numba kernels are compiled or loaded from cache before timing."""
    tiny = replace(settings, duration=0.05)
    evaluate_or_fail(Design(-1, 0.04, 0.0405, 20.0, 5.6e8, "", 2.0, 0.7, math.pi / 4, "plane", PAPER_RADIUS), tiny)


def collision_spl_db(result, scene, click, point, *, sample_rate: int = ANALYSIS_RATE) -> tuple:
    """Peak SPL in dB re 20 µPa of each collision of a multi-ball run at one listener.

    Parameters
    ----------
    result : acoustiviz.dynamics.MultiBallResult
        The run (one cavity), sampled.
    scene : acoustiviz.sound.CavityScene
        The column's scene (:func:`acoustiviz.sound.balls_sound.column_scene`).
    click : acoustiviz.sound.ClickModel
        The ball-wall contact.
    point : (1, 3) array_like
        Listener in m.
    sample_rate : int
        Rate in Hz of each collision's rendering.

    Returns
    -------
    rows : (k,) ndarray of int
        The impact-table rows of the collisions heard (a contact made at rest is silent).
    spl : (k,) ndarray
        The peak of each one's clicks rendered alone (:func:`acoustiviz.sound.balls_sound.render_clicks`),
        on the sample grid of the whole run (its start moved by a whole number of samples).
    """
    from dataclasses import replace

    from ..sound.balls_sound import ball_clicks, render_clicks

    clicks = ball_clicks(result, scene, click)
    rows = np.unique(clicks.collision)
    spl = np.empty(rows.size)
    for i, k in enumerate(rows):
        one = clicks.take(clicks.collision == k)
        # rendered from its own start, moved by whole samples so that its peak is the one of the whole run's grid
        one = replace(one, times=one.times - math.floor(one.times[0] * sample_rate) / sample_rate)
        p = render_clicks(one, scene, click, point, sample_rate=sample_rate).pressure[0]
        spl[i] = 20.0 * math.log10(max(float(np.max(np.abs(p))), 1e-300) / P_REF)
    return rows, spl


def evaluate_balls(design, settings):
    """Simulate a design of several balls and hear its collisions (the work of one sweep row).

    Parameters
    ----------
    design : acoustiviz.sweep.Design
        The design (``balls > 1``).
    settings : acoustiviz.sweep.FixedSettings
        The sweep's fixed settings (the solver is the multi-ball event method whatever ``solver``).

    Returns
    -------
    acoustiviz.sweep.evaluate.DesignResult
    """
    from ..core.medium import Medium
    from ..dynamics import BallState, simulate_balls
    from ..dynamics.metrics import damping_metrics, sample_times
    from ..sound.balls_sound import column_scene
    from ..sound.sources import check_listeners
    from .balls import design_balls_model

    s = settings
    damper, model = design_balls_model(design, s)
    res = simulate_balls(model, s.duration, initial=BallState(v=design.v0), rtol=min(s.rtol, SOLVER_RTOL_RANGE[1]),
                         t_eval=sample_times(s.duration, damper))
    metrics = damping_metrics(res.t, res.x, window_fraction=s.fit_window_fraction,
                              settling_fraction=s.settling_fraction)
    two, fit = metrics.two_maxima, metrics.fit
    medium = Medium(c=s.c, rho=s.rho)
    scene, click = sound_setup(design, s, medium)
    cavity = model.cavities[0]
    scene = column_scene(scene, cavity)
    point = listener_point(scene.geometry, design.distance, design.angle)
    check_listeners(point, scene, name="distance", column=cavity)
    _, spl = collision_spl_db(res, scene, click, point)
    levels = dict(NO_LEVELS)
    if s.levels:
        levels = _levels(res, scene, click, point, s.duration)
    u = np.abs(res.impacts.approach_velocity)
    return DesignResult(
        design=design, inclination_two_maxima=float(two.value), inclination_fit=float(fit.value),
        fit_window_start=float(fit.t_start), fit_window_stop=float(fit.t_stop), fit_n_maxima=int(fit.n_maxima),
        settling_time=float(metrics.settling_time), n_impacts=len(res.impacts),
        max_spl_db=float(spl.max()) if spl.size else -math.inf,
        energy_dissipated_contact=float(res.energy.dissipated_contact),
        energy_dissipated_main=float(res.energy.dissipated_main),
        max_approach_velocity=float(u.max()) if u.size else 0.0, spl_impacts_evaluated=int(spl.size),
        success=bool(res.success), mass_ratio=design.balls * design.m / s.M, levels=levels)


def _levels(result, scene, click, point, duration: float) -> dict:
    """LAFmax, LCpeak and LAeq over ``[0, duration]`` of the run's click train at the listener."""
    from ..core.signal import Signal
    from ..levels import sound_levels
    from ..sound.balls_sound import render_balls

    if len(result.impacts) == 0:
        return dict.fromkeys(SWEEP_LEVEL_COLUMNS, -math.inf)
    out = render_balls(result, scene, click, point, sample_rate=ANALYSIS_RATE, duration=duration)
    n = int(round(duration * ANALYSIS_RATE))
    lv = sound_levels(Signal(out.pressure[0], ANALYSIS_RATE), start=0.0, stop=n / ANALYSIS_RATE)
    return {c: float(getattr(lv, c)[0]) for c in SWEEP_LEVEL_COLUMNS}
