"""The damper job: one run of the impact damper (paper eq 15), its damping and its files.

Three parts, shared by ``acoustiviz damper``, a scene's ``[outputs.damper_history]`` and
``[outputs.impact_table]`` (whose one run the scene's WAV, levels and spectrum reuse), ``acoustiviz
auralize`` and Python callers:

* :class:`~acoustiviz.app.settings.damper_job.DamperJob`, the settings, checked once when made;
* :func:`run`, which simulates and measures a :class:`DamperResult` (physics only: no files, no printing);
* :meth:`DamperResult.write`, which writes the files the settings asked for and returns their paths.

Defaults: Table 1 and the Figure 5 start (:mod:`acoustiviz.constants`). SI units throughout.

Examples
--------
>>> job = DamperJob(damper_model(), duration=1.0)
>>> result = run(job)
>>> result.result.solver, len(result.result.impacts) > 0
('event', True)
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

from .. import dynamics
from .._validate import ParameterError, check_choice, check_finite
from ..constants import DEFAULT_RTOL, PAPER_GAP, PAPER_V0, SCENE_SOLVERS, SOLVER_RTOL_RANGE, TABLE1_PARAMETERS
from ..dynamics import DamperModel, InitialState, cheapest_solver, solver_method
from ..dynamics.metrics import DampingMetrics, damping_metrics, sample_times
from .settings.damper_job import DamperCavity, DamperJob

__all__ = ["DamperJob", "DamperCavity", "DamperResult", "run", "damper_model", "balls_model", "check_damper_run",
           "choose_solver", "run_damper", "damper_description", "damping_figures", "check_click_fits"]


def damper_model(*, M: float = TABLE1_PARAMETERS["M"], K: float = TABLE1_PARAMETERS["K"],
                 C: float = TABLE1_PARAMETERS["C"], m: float = TABLE1_PARAMETERS["m"], gap: float = PAPER_GAP,
                 k_hertz: float = TABLE1_PARAMETERS["k_hertz"], c1: float = TABLE1_PARAMETERS["c1"],
                 clip_tensile: bool = False, names=None) -> DamperModel:
    """The damper of paper eq 15 (defaults: Table 1 with d = 4 cm); see :class:`~acoustiviz.dynamics.DamperModel`.

    ``names``: API parameter -> the option or scene key its errors name (default: the API parameter).
    """
    from ..errors import user_terms

    with user_terms(names or {}):
        return DamperModel(M=M, K=K, C=C, m=m, gap=gap, k_hertz=k_hertz, c1=c1, clip_tensile=bool(clip_tensile))


def choose_solver(solver: str, model: DamperModel, initial: InitialState, tolerance: float = DEFAULT_RTOL) -> tuple:
    """The solver to use and why: ``solver`` itself, or for ``"auto"`` the cheapest that suits ``tolerance``.

    Returns
    -------
    name : str
        ``"event"``, ``"newmark"`` or ``"impact-map"``.
    reason : str
        Empty unless ``solver`` was ``"auto"``.
    """
    check_choice("solver", solver, SCENE_SOLVERS)
    if solver != "auto":
        return solver, ""
    return cheapest_solver(model, initial, tolerance)


@dataclass(frozen=True, eq=False)
class DamperResult:
    """A damper run of a :class:`DamperJob`, with what every front end reports about it.

    Attributes
    ----------
    settings : DamperJob
        What was run.
    result : SimulationResult
        Time histories, impact table, energy balance (:func:`acoustiviz.dynamics.simulate`).
    metrics : DampingMetrics
        Damping inclination (eq 16 and envelope fit) and settling time from the exact maxima.
    warnings : tuple of str
        Accuracy warnings the solver raised.
    seconds : float
        Wall-clock time of the simulation in s.
    solver_reason : str
        Why ``"auto"`` chose the solver it did (empty when the solver was named).
    """

    settings: DamperJob
    result: object
    metrics: DampingMetrics
    warnings: tuple
    seconds: float
    solver_reason: str = ""

    @property
    def initial(self) -> InitialState:
        """The start of the run (m, m/s)."""
        return self.settings.initial

    def write(self, folder=None, *, only=None) -> list:
        """Write the files the settings ask for into ``folder``; return their paths.

        The impact table (:func:`acoustiviz.output.tables.write_impact_table`), the time history
        (``time_s, x_m, v_m_s, y_m, w_m_s``) and the Figure 5 plot, in that order, each atomically.

        Parameters
        ----------
        folder : path-like, optional
            Where relative file names are put (default: as given, the current folder).
        only : iterable of str, optional
            Write only these of the settings' files (``"impacts_csv"``, ``"history_csv"``, ``"png"``):
            a scene's outputs each write their own files of the one run.

        Returns
        -------
        list of Path
        """
        from pathlib import Path

        files = {k: Path(v) if folder is None else Path(folder) / v for k, v in self.settings.files().items()
                 if only is None or k in only}
        if self.settings.balls > 1 or self.settings.cavities:
            return _write_balls(self, files)
        res, written = self.result, []
        if "impacts_csv" in files:
            from ..output.tables import write_impact_table

            written.append(write_impact_table(files["impacts_csv"], res.impacts))
        if "history_csv" in files:
            from ..files import write_csv_atomic

            written.append(write_csv_atomic(files["history_csv"], ["time_s", "x_m", "v_m_s", "y_m", "w_m_s"],
                                            [res.t, res.x, res.v, res.y, res.w]))
        if "png" in files:
            from ..output.plot.dynamics import plot_free_vibration
            from ..output.plot.style import save_figure

            written.append(save_figure(plot_free_vibration(res).figure, files["png"]))
        return [Path(p) for p in written]


def run(settings: DamperJob) -> DamperResult:
    """Simulate the damper of ``settings`` and measure its damping (no files, no printing).

    Parameters
    ----------
    settings : DamperJob
        The job, checked when it was made.

    Returns
    -------
    DamperResult
    """
    from .names import user_terms

    s = settings
    if s.balls > 1 or s.cavities:
        return _run_balls(s)
    with user_terms(s.names):  # an error of the physics in the front end's words
        method = solver_method(s.solver)
        name, reason = choose_solver(s.solver, s.model, s.initial, s.rtol)
        kwargs = {"dt": s.dt} if name == "newmark" else {"rtol": method.run_rtol(s.rtol)}
        start = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = dynamics.simulate(s.model, s.duration, solver=name, initial=s.initial,
                                       t_eval=sample_times(s.duration, s.model), **kwargs)
        seconds = time.perf_counter() - start
        metrics = damping_metrics(result)
    return DamperResult(s, result, metrics, tuple(str(w.message) for w in caught), seconds, reason)


def balls_model(settings: DamperJob):
    """The :class:`~acoustiviz.dynamics.MultiBallModel` of a job: ``balls`` spheres of the impact mass.

    With ``cavities``, one :class:`~acoustiviz.dynamics.Cavity` of equal spheres per cavity, in order,
    each value it leaves out the model's; the ball-wall contact is the model's in every cavity. The balls'
    material: a cavity's own, else the job's ``ball_material``.
    """
    from ..dynamics import MultiBallModel, equal_balls

    s, model, material = settings, settings.model, settings.ball_material
    if not s.cavities:
        return MultiBallModel.from_damper(model, s.balls, k_ball=s.k_hertz_ball, c_ball=s.c1_ball,
                                          material=material)
    cavities = tuple(equal_balls(c.balls, model.m if c.m is None else c.m, model.gap if c.gap is None else c.gap,
                                 model.k_hertz, model.c1, k_ball=c.k_hertz_ball, c_ball=c.c1_ball,
                                 material=material if c.material is None else c.material)
                     for c in s.cavities)
    return MultiBallModel(cavities, model.M, model.K, model.C, model.clip_tensile)


def _run_balls(s: DamperJob) -> DamperResult:
    """Several balls: the multi-ball solver, the damping measured on the sampled motion of the main mass."""
    from ..dynamics import BallState, simulate_balls
    from .names import user_terms

    with user_terms(s.names):
        model = balls_model(s)
        start = time.perf_counter()
        starts = tuple(c.start or s.ball_start for c in s.cavities) if s.cavities else s.ball_start
        initial = BallState(x=s.initial.x, v=s.initial.v, start=starts, seed=s.ball_seed)
        result = simulate_balls(model, s.duration, initial=initial,
                                rtol=min(s.rtol, SOLVER_RTOL_RANGE[1]), t_eval=sample_times(s.duration, s.model))
        seconds = time.perf_counter() - start
        metrics = damping_metrics(result.t, result.x)
    reason = "several balls: the event method of the multi-ball solver" if s.solver == "auto" else ""
    return DamperResult(s, result, metrics, (), seconds, reason)


def _write_balls(damper: DamperResult, files: dict) -> list:
    """The files of a multi-ball run: impacts with the two bodies of each, every ball's history, Figure 5."""
    from pathlib import Path

    from ..files import write_csv_atomic

    res, written = damper.result, []
    if "impacts_csv" in files:
        from ..output.tables import write_ball_impact_table

        written.append(write_ball_impact_table(files["impacts_csv"], res.impacts))
    if "history_csv" in files:
        header = ["time_s", "x_m", "v_m_s", *(f"{b}_m" for b in _ball_columns(res.model, "y")),
                  *(f"{b}_m_s" for b in _ball_columns(res.model, "w"))]
        written.append(write_csv_atomic(files["history_csv"], header,
                                        [res.t, res.x, res.v, *res.y.T, *res.w.T]))
    if "png" in files:
        from types import SimpleNamespace

        from ..output.plot.dynamics import plot_free_vibration
        from ..output.plot.style import save_figure

        # the plot reads the main mass's motion and the damper's figures: those of the one-ball model
        view = SimpleNamespace(t=res.t, x=res.x, impacts=res.impacts, model=damper.settings.model,
                               initial=damper.settings.initial, solver=f"{damper.settings.total_balls()} balls")
        written.append(save_figure(plot_free_vibration(view).figure, files["png"]))
    return [Path(p) for p in written]


def _ball_columns(model, letter: str) -> list:
    """``y1 ... yN`` of the balls in axis order; with several cavities ``c1_y1 ...``, numbered per cavity."""
    several = len(model.cavities) > 1
    return [f"c{ic}_{letter}{i}" if several else f"{letter}{i}"
            for ic, cav in enumerate(model.cavities, start=1) for i in range(1, cav.n_balls + 1)]


def run_damper(model: DamperModel, duration: float, *, solver: str = "event", v0: float = PAPER_V0,
               x0: float = 0.0, rtol: float = DEFAULT_RTOL, dt=None) -> DamperResult:
    """Simulate ``model`` for ``duration`` s from the Figure 5 start (x = x0, dx/dt = v0, impact mass centred, at rest).

    A shorthand for ``run(DamperJob(model, InitialState(x=x0, v=v0), duration, solver, rtol, dt))``.

    Parameters
    ----------
    model : DamperModel
        The damper.
    duration : float
        Simulated time in s.
    solver : {"event", "newmark", "impact-map", "auto"}
        ``"auto"`` takes the cheapest solver whose error suits ``rtol``.
    v0, x0 : float
        Initial velocity (m/s) and displacement (m) of the main mass.
    rtol : float
        Relative tolerance of the event solver and of the impact map's restitution table; for
        ``"auto"`` the accuracy wanted. Each solver checks its own range
        (:data:`acoustiviz.dynamics.METHODS`).
    dt : float, optional
        Newmark step in s.

    Returns
    -------
    DamperResult

    Raises
    ------
    ParameterError
        Before any work, for settings whose run cannot be computed or measured
        (:func:`acoustiviz.core.limits.check_damper`).
    """
    check_finite("v", v0)
    return run(DamperJob(model, InitialState(x=x0, v=v0), duration, solver, rtol, dt))


def damper_description(model: DamperModel, run: DamperResult, duration: float) -> dict:
    """The settings of a run as recorded in sidecars and summaries (SI units in the key names)."""
    return {"M_kg": model.M, "K_n_m": model.K, "C_n_s_m": model.C, "m_kg": model.m, "gap_m": model.gap,
            "k_hertz_n_m1_5": model.k_hertz, "c1_n_s_m": model.c1, "v0_m_s": run.initial.v,
            "x0_m": run.initial.x, "duration_s": duration, "solver": run.result.solver,
            "solver_settings": dict(run.result.settings), "clip_tensile": model.clip_tensile}


def damping_figures(run: DamperResult) -> dict:
    """The key figures of a run as short strings: impacts, inclinations (cm/s), settling time (s).

    ``solver_ms`` is the simulation's wall time without the kernels' compilation, ``compile_ms``
    that compilation (a first run on an installation) or the loading of the compiled kernels.
    """
    two, fit, ts = run.metrics.two_maxima, run.metrics.fit, run.metrics.settling_time
    return {"impacts": str(len(run.result.impacts)),
            "inclination_two_maxima_cm_s": f"{100 * two.value:.3f}",
            "inclination_fit_cm_s": f"{100 * fit.value:.3f}",
            "settling_time_s": "not settled" if ts != ts else f"{ts:.2f}",
            "solver": run.result.solver,
            # the run alone, and apart the kernels' compilation (or loading from numba's cache)
            "solver_ms": f"{1e3 * max(run.seconds - run.result.compile_time, 0.0):.1f}",
            "compile_ms": f"{1e3 * run.result.compile_time:.1f}"}


def check_damper_run(*, solver: str, rtol: float, M: float, K: float, m: float, gap: float, k_hertz: float,
                     v: float, duration: float, c1: float, names=None) -> None:
    """Refuse a damper run that cannot be computed or measured.

    First the tolerance in the range of ``solver`` (:data:`acoustiviz.dynamics.METHODS`), then the physics'
    limits (:func:`acoustiviz.core.limits.check_damper`). SI units (kg, N/m, m, N/m^1.5, m/s, s, N s/m);
    ``names``: API parameter -> the option or scene key its errors name (default: the API parameter).
    """
    from ..core.limits import check_damper
    from ..errors import user_terms

    with user_terms(names or {}):
        solver_method(solver).check_rtol(rtol)
        check_damper(M=M, K=K, m=m, gap=gap, k_hertz=k_hertz, v=v, duration=duration, c1=c1)


def check_click_fits(seq, k_hertz: float, mass: float, duration: float, *, names=None) -> None:
    """Refuse a sound in which the click of the slowest impact would outlast the sound itself.

    The contact, hence the click, of an impact lasts ``T = 2.943 alpha / v`` (paper eqs 1-4),
    longest for the slowest impact; a click longer than the sound cannot be heard whole.

    Parameters
    ----------
    seq : acoustiviz.sound.ImpactSequence
        The impacts heard.
    k_hertz : float
        Hertz contact stiffness in N/m^1.5.
    mass : float
        Impact mass in kg.
    duration : float
        Length of the sound in s.
    names : dict, optional
        ``m``, ``k_hertz``, ``duration`` and ``velocities`` (the impacts' speeds) -> the option or
        scene key named in the error (default the API names). A speed whose contact cannot be
        computed (:func:`acoustiviz.core.limits.contact_speeds`) is refused naming ``velocities``.
    """
    import math

    import numpy as np

    from ..core.contact import contact_duration
    from ..errors import ParameterError

    if not len(seq):
        return
    from ..core.limits import contact_speeds

    n = {"m": "m", "k_hertz": "k_hertz", "duration": "duration", "velocities": "velocities", **(names or {})}
    slowest, fastest = float(seq.velocities.min()), float(seq.velocities.max())
    lo, hi = contact_speeds(k_hertz, mass)
    for v in (slowest, fastest):
        if not lo <= v <= hi:
            raise ParameterError(n["velocities"], f"an approach speed of {v:g} m/s makes the contact of the "
                                                  f"{mass:g} kg impact mass with {n['k_hertz']} {k_hertz:g} overflow "
                                                  f"or vanish; with these the speeds must lie in [{lo:.3g}, {hi:.3g}] "
                                                  "m/s")
    with np.errstate(all="ignore"):
        tau = float(contact_duration(slowest, k_hertz, mass)) if slowest > 0 else math.inf
    if not tau <= duration:
        raise ParameterError(n["m"], f"an impact mass of {mass:g} kg with {n['k_hertz']} {k_hertz:g} makes the "
                                     f"click of the slowest impact ({slowest:.3g} m/s) last {tau:.3g} s, longer "
                                     f"than the {duration:g} s sound; use a lighter mass, a stiffer contact or a "
                                     f"longer {n['duration']}")


def heard_sequence(result):
    """The impacts on the cavity's walls of a run (:class:`~acoustiviz.sound.ImpactSequence`).

    One ball: every impact. Several balls (a :class:`~acoustiviz.dynamics.MultiBallResult`, in one cavity or
    several): the contacts of a ball with a wall, times in s, walls -1/+1, approach speeds in m/s; the
    ball-ball contacts stay in the impact table (:func:`render_run` hears them too).
    """
    import numpy as np

    from ..sound import ImpactSequence

    imp = result.impacts
    if hasattr(imp, "sequence"):
        return imp.sequence()
    first = np.array([str(b).rpartition(":")[2] for b in imp.first])  # several cavities: c2:wall- is a wall
    second = np.array([str(b).rpartition(":")[2] for b in imp.second])
    on_wall = (first == "wall-") | (second == "wall+")
    walls = np.where(first[on_wall] == "wall-", -1, 1)
    return ImpactSequence(imp.time[on_wall], walls, np.abs(imp.approach_velocity[on_wall]))


def cavity_positions(settings) -> tuple | None:
    """Per cavity of a :class:`DamperJob` (or None) the offset in m its sound comes from, None for the default.

    None without ``cavities`` (one cavity, in the scene's place).
    """
    cavities = getattr(settings, "cavities", ())
    return tuple(c.position for c in cavities) if cavities else None


def render_run(result, sequence, cavity, click, points, *, sample_rate: int, duration: float, room_sound=None,
               positions=None):
    """The sound in Pa of a damper run at the listeners ``points`` (m): the one home of that choice.

    One ball: :func:`acoustiviz.sound.render` of ``sequence`` (the run's impacts). Several balls, in one
    cavity or several: every collision of the run, ball-wall and ball-ball, each cavity from its place
    ``positions`` (:func:`acoustiviz.sound.render_balls`, :func:`cavity_positions`); ``click`` is the
    ball-wall contact. In a room every sphere has the room's images to its order and tolerance; a room's
    late tail or absorption bands (``room_sound``) are refused with several balls.
    """
    from ..dynamics import MultiBallResult
    from ..sound import render, render_balls

    if isinstance(result, MultiBallResult) and result.model.n_balls > 1:
        if room_sound is not None:
            raise ParameterError("room_sound", "several balls in a room are heard with every image to the room's "
                                               "tolerance: no late tail and no absorption bands")
        return render_balls(result, cavity, click, points, positions=positions, sample_rate=sample_rate,
                            duration=duration)
    return render(sequence, cavity, click, points, sample_rate=sample_rate, duration=duration,
                  room_sound=room_sound)


def snapshot_run(result, sequence, cavity, click, points, t: float, *, positions=None):
    """The pressure in Pa of a damper run at ``points`` (m) at instant ``t`` (s): every click sounding then.

    The same choice as :func:`render_run`: one ball, :func:`acoustiviz.sound.snapshot.snapshot_pressure` of
    ``sequence``; several balls (in one cavity or several, each from its place ``positions``), every
    collision's spheres (:func:`acoustiviz.sound.snapshot.snapshot_balls` of the run's
    :func:`~acoustiviz.sound.balls_sound.ball_clicks`).
    """
    from ..dynamics import MultiBallResult
    from ..sound.balls_sound import ball_clicks, cavity_places, column_scene
    from ..sound.snapshot import snapshot_balls, snapshot_pressure

    if isinstance(result, MultiBallResult) and result.model.n_balls > 1:
        scene = column_scene(cavity, result.model.cavities[0])
        places = cavity_places(result.model, scene, positions)
        return snapshot_balls(t, ball_clicks(result, scene, click, positions=places), scene, points)
    return snapshot_pressure(t, sequence, cavity, click, points)
