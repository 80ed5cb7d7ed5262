"""One place that builds and runs an impact-damper model, for every front-end.

``acoustiviz damper``, ``acoustiviz auralize`` and scene files describe a damper the same way
(paper eq 15, defaults of Table 1 and Figure 5 from :mod:`acoustiviz.constants`); they all call
:func:`damper_model` and :func:`run_damper`, so the same settings give the same impact sequence
whichever front-end asked. SI units throughout.

Examples
--------
>>> model = damper_model()
>>> run = run_damper(model, 1.0, v0=2.0)
>>> run.result.solver, len(run.result.impacts) > 0
('event', True)
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

from .. import dynamics
from .._validate import check_choice, check_finite, check_positive
from ..constants import DEFAULT_RTOL, PAPER_GAP, PAPER_V0, SCENE_SOLVERS, TABLE1
from ..core.limits import check_damper
from ..dynamics import DamperModel, InitialState, cheapest_solver, solver_method
from ..dynamics.metrics import DampingMetrics, damping_metrics, sample_times

__all__ = ["DamperRun", "damper_model", "choose_solver", "run_damper", "run_damper_settings", "damper_description",
           "damping_figures", "check_click_fits"]


def damper_model(*, M: float = TABLE1["M"], K: float = TABLE1["K"], C: float = TABLE1["C"], m: float = TABLE1["m"],
                 gap: float = PAPER_GAP, k_hertz: float = TABLE1["k_hertz"], c1: float = TABLE1["c1"],
                 clip_tensile: bool = False) -> DamperModel:
    """The damper of paper eq 15 (defaults: Table 1 with d = 4 cm); see :class:`~acoustiviz.dynamics.DamperModel`."""
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


@dataclass(frozen=True)
class DamperRun:
    """A damper simulation with what every front-end reports about it.

    Attributes
    ----------
    result : SimulationResult
        Time histories, impact table, energy balance (:func:`acoustiviz.dynamics.simulate`).
    metrics : DampingMetrics
        Damping inclination (eq 16 and envelope fit) and settling time from the exact maxima.
    initial : InitialState
        The start of the run.
    warnings : tuple of str
        Accuracy warnings the solver raised.
    seconds : float
        Wall-clock time of the simulation in s.
    solver_reason : str
        Why ``"auto"`` chose the solver it did (empty when the solver was named).
    """

    result: object
    metrics: DampingMetrics
    initial: InitialState
    warnings: tuple
    seconds: float
    solver_reason: str = ""


def run_damper(model: DamperModel, duration: float, *, solver: str = "event", v0: float = PAPER_V0,
               x0: float = 0.0, rtol: float = DEFAULT_RTOL, dt=None) -> DamperRun:
    """Simulate ``model`` for ``duration`` s from the Figure 5 start (x = x0, dx/dt = v0, impact mass centred, at rest).

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
    DamperRun

    Raises
    ------
    ParameterError
        Before any work, for settings whose run cannot be computed or measured
        (:func:`acoustiviz.core.limits.check_damper`).
    """
    initial = InitialState(x=x0, v=v0)
    method = solver_method(solver)
    rtol = method.check_rtol(rtol)
    check_positive("duration", duration, "s")
    check_damper(M=model.M, K=model.K, m=model.m, gap=model.gap, k_hertz=model.k_hertz, v=check_finite("v", v0),
                 duration=duration, c1=model.c1)
    name, reason = choose_solver(solver, model, initial, rtol)
    kwargs = {"dt": dt} if name == "newmark" else {"rtol": method.run_rtol(rtol)}
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = dynamics.simulate(model, duration, solver=name, initial=initial, t_eval=sample_times(duration, model),
                          **kwargs)
    seconds = time.perf_counter() - start
    metrics = damping_metrics(result)
    return DamperRun(result, metrics, initial, tuple(str(w.message) for w in caught), seconds, reason)


def damper_description(model: DamperModel, run: DamperRun, duration: float) -> dict:
    """The settings of a run as recorded in sidecars and summaries (SI units in the key names)."""
    return {"M_kg": model.M, "K_n_m": model.K, "C_n_s_m": model.C, "m_kg": model.m, "gap_m": model.gap,
            "k_hertz_n_m1_5": model.k_hertz, "c1_n_s_m": model.c1, "v0_m_s": run.initial.v,
            "x0_m": run.initial.x, "duration_s": duration, "solver": run.result.solver,
            "solver_settings": dict(run.result.settings), "clip_tensile": model.clip_tensile}


def damping_figures(run: DamperRun) -> dict:
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


def run_damper_settings(settings, max_memory_mb=None) -> tuple:
    """Build and run the damper of a :class:`~acoustiviz.app.settings.auralize.DamperSettings`, errors naming options.

    The working memory is checked first (:func:`acoustiviz.app.budget.damper_estimate`, capped at
    ``max_memory_mb`` MB). Returns ``(model, run)``: the :class:`~acoustiviz.dynamics.DamperModel`
    and its :class:`DamperRun`.
    """
    from .budget import check_budget, damper_estimate
    from .names import DAMPER_OPTIONS, user_terms

    d = settings
    with user_terms(DAMPER_OPTIONS):
        model = damper_model(M=d.M, K=d.K, C=d.C, m=d.m, gap=d.gap, k_hertz=d.k_hertz, c1=d.c1,
                             clip_tensile=bool(d.clip_tensile))
        check_budget(damper_estimate(model, d.duration, solver=d.solver, dt=d.dt, options=("--duration",)),
                     max_memory_mb)
        run = run_damper(model, d.duration, solver=d.solver, x0=d.x0, v0=d.v0, rtol=d.rtol, dt=d.dt)
    return model, run
