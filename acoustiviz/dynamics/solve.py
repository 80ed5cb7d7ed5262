"""One interface to the impact-damper solvers: :func:`simulate`.

Solvers (chosen by name):

``"event"``
    Event-driven. Between contacts the motion is in closed form (the impact mass flies freely, the
    main mass is a damped linear oscillator). Contact onset is located by exact bracketing of the
    gap function (between zeros of the main-mass acceleration the relative velocity is monotone,
    so no grazing contact can be missed) and Brent's method. Each contact is integrated with an
    adaptive Dormand-Prince 8(5,3) scheme under relative tolerance ``rtol`` in a transformed time
    σ (dt = sqrt(δ) dσ, with sqrt(δ) a state variable) in which the Hertz force is the polynomial
    K_HZ sqrt(δ)³: the δ^{3/2} singularities at contact onset and end vanish and the 8th-order
    steps stay long up to both ends. The end of contact and the peak force are located by root
    finding on full Runge-Kutta steps. Cost grows with the number of impacts, not with time.
``"newmark"``
    The paper's average-acceleration Newmark-beta (γ = 1/2, β = 1/4) at a fixed step ``dt`` with
    Newton iterations on the contact force. Unconditionally stable, second order; its accuracy
    depends on ``dt`` relative to the contact duration (default: 1/50 of the shortest possible
    Hertz contact).
``"impact-map"``
    Instantaneous impacts with the restitution of the compliant contact at each approach speed
    (the same damped Hertz contact, integrated alone, without the main spring and dashpot),
    tabulated once per run at 40 speeds over four decades and interpolated (cubic in ln speed;
    slower impacts are integrated directly).
    Fastest and approximate: it neglects the motion of the main spring during the contact, an
    error of the order of (contact duration × main frequency); see the benchmark.

Requesting a Newmark step longer than the shortest possible contact raises
:class:`~acoustiviz.errors.ParameterError`; a step coarser than 1/20 of it warns.

Each solver is a :class:`Solver` in the registry :data:`METHODS` (``"auto"`` too, which only
picks one of the others, :func:`cheapest_solver`): it checks its own settings and says at which
tolerance it runs, so every front-end states and enforces the same range for the same solver.
"""

from __future__ import annotations

import math
import time
import warnings
from types import MappingProxyType

import numpy as np

from .._jit import announce_long_work, compile_for
from .._validate import ParameterError, check_choice, check_positive, check_range
from ..constants import AUTO_TOLERANCE_RANGE, DEFAULT_RTOL, SOLVER_RTOL_RANGE, SOLVERS
from ..errors import AccuracyWarning
from . import _kernels as kern
from ._status import kernel_params as _params
from ._status import status_message
from .model import TABLE1, DamperModel, InitialState
from .result import EnergyBalance, Extrema, ImpactTable, SimulationResult

__all__ = [
    "SOLVERS",
    "AccuracyWarning",
    "simulate",
    "default_step",
    "shortest_contact",
    "explicit_step_limit",
    "central_difference_excursion",
    "cheapest_solver",
    "METHODS",
    "Solver",
    "solver_method",
]

#: Newmark steps coarser than this fraction of the shortest contact trigger an AccuracyWarning.
NEWMARK_WARN_FRACTION = 1.0 / 20.0
#: Default Newmark step as a fraction of the shortest contact.
NEWMARK_DEFAULT_FRACTION = 1.0 / 50.0
#: Nodes of the impact map's restitution table (uniform in ln(speed) over four decades).
IMPACT_MAP_NODES = 40
#: A Newmark run of more steps is announced on stderr before it starts (a run this long takes
#: seconds; it runs in batches of steps, so Ctrl-C stops it).
NEWMARK_LONG_STEPS = 100_000_000
#: CPU time in s of the event solver's first compilation with its callees, quoted to the user when
#: it happens (:func:`acoustiviz._jit.compile_for`); measured by ``benchmarks/bench_startup.py``
#: (figures: ``benchmarks/results/design_timings.md``).
EVENT_SOLVER_COMPILE_S = 5.0
#: The impact map warns when (shortest contact × main angular frequency) exceeds this.
IMPACT_MAP_WARN_PRODUCT = 0.05


class Solver:
    """A damper solver of :func:`simulate`: its name, the tolerance it takes and the settings it checks.

    Subclasses set :attr:`name` and :attr:`rtol_range` and override :meth:`settings`; the registry
    :data:`METHODS` holds one of each.
    """

    #: The name :func:`simulate` and the front-ends know it by.
    name = ""
    #: Closed interval of the relative tolerance it takes (None: it takes none).
    rtol_range = SOLVER_RTOL_RANGE
    #: What the tolerance means to it when not the relative tolerance of each contact (for messages).
    rtol_meaning = ""

    def check_rtol(self, rtol, name: str = "rtol") -> float:
        """``rtol`` as a float if this solver takes it, else a :class:`ParameterError` naming ``name`` and the range.

        A solver that takes no tolerance (:attr:`rtol_range` None) lets any value pass unchanged.
        """
        if self.rtol_range is None:
            return rtol
        lo, hi = self.rtol_range
        try:
            return check_range(name, rtol, lo, hi)
        except ParameterError:
            meaning = f" ({self.rtol_meaning})" if self.rtol_meaning else ""
            raise ParameterError(name, f"must lie in [{lo:g}, {hi:g}] with the {self.name} solver{meaning}, "
                                       f"got {rtol!r}") from None

    def run_rtol(self, rtol: float) -> float:
        """The tolerance the solver runs at when asked for ``rtol``."""
        return rtol

    def settings(self, model, initial, duration: float, rtol: float, dt) -> dict:
        """The solver's settings for :func:`simulate` (refused or warned about); subclasses."""
        raise NotImplementedError


class EventSolver(Solver):
    """The event-driven solver: exact free flight, adaptive contacts (needs an underdamped main oscillator)."""

    name = "event"

    def settings(self, model, initial, duration, rtol, dt) -> dict:  # noqa: D102
        if not model.underdamped:
            raise ParameterError(
                "C",
                f"the {self.name} solver needs an underdamped main oscillator, C < 2 sqrt(K M) = "
                f"{2 * math.sqrt(model.K * model.M):g} N s/m, got {model.C:g} N s/m; use solver='newmark'",
            )
        return {"rtol": rtol}


class ImpactMapSolver(EventSolver):
    """Instantaneous impacts with the compliant contact's restitution; warns when contacts are long."""

    name = "impact-map"

    def settings(self, model, initial, duration, rtol, dt) -> dict:  # noqa: D102
        out = super().settings(model, initial, duration, rtol, dt)
        tau_min = shortest_contact(model, initial)
        prod = tau_min * model.main_frequency
        if prod > IMPACT_MAP_WARN_PRODUCT:
            warnings.warn(
                f"contacts last up to {tau_min:.3g} s, {prod:.2g} rad of the main oscillation: "
                "the instantaneous impact map will be inaccurate; use solver='event'",
                AccuracyWarning,
                stacklevel=3,
            )
        return out


class NewmarkSolver(Solver):
    """The paper's fixed-step Newmark scheme: it takes a step ``dt`` in s, no tolerance."""

    name = "newmark"
    rtol_range = None

    def settings(self, model, initial, duration, rtol, dt) -> dict:
        """``{"dt": step in s, "steps": count}``: a step longer than the shortest contact is refused."""
        tau_min = shortest_contact(model, initial)
        if dt is None:
            dt = default_step(model, initial)
        dt = check_positive("dt", dt, "s")
        if dt > tau_min:
            raise ParameterError(
                "dt",
                f"a step of {dt:g} s is longer than the shortest possible contact ({tau_min:.3g} s);"
                f" use dt <= {NEWMARK_WARN_FRACTION * tau_min:.3g} s",
            )
        if dt > NEWMARK_WARN_FRACTION * tau_min:
            warnings.warn(
                f"Newmark step {dt:g} s is coarser than 1/20 of the shortest contact "
                f"({tau_min:.3g} s): restitution and impact times will be inaccurate",
                AccuracyWarning,
                stacklevel=3,
            )
        nsteps = max(int(round(duration / dt)), 1)
        return {"dt": duration / nsteps, "steps": nsteps}  # land exactly on the duration


class AutoSolver(Solver):
    """No solver of its own: the cheapest whose error suits the accuracy wanted (:func:`cheapest_solver`).

    Its tolerance is the accuracy wanted, which may be coarser than any solver's; the solver it
    picks runs at that accuracy capped at the top of :data:`~acoustiviz.constants.SOLVER_RTOL_RANGE`.
    """

    name = "auto"
    rtol_range = AUTO_TOLERANCE_RANGE
    rtol_meaning = (f"the accuracy wanted; the solver it picks runs at min(rtol, {SOLVER_RTOL_RANGE[1]:g})")

    def run_rtol(self, rtol: float) -> float:  # noqa: D102
        return min(rtol, SOLVER_RTOL_RANGE[1])

    def settings(self, model, initial, duration, rtol, dt) -> dict:  # noqa: D102
        raise ParameterError("solver", "'auto' only picks a solver (cheapest_solver); simulate takes the one picked")


#: The registry: solver name -> its :class:`Solver` (``"auto"`` included, :func:`simulate` runs the others).
METHODS = MappingProxyType({s.name: s for s in (EventSolver(), NewmarkSolver(), ImpactMapSolver(), AutoSolver())})


def solver_method(name: str) -> Solver:
    """The :class:`Solver` registered as ``name``, or a :class:`ParameterError` naming ``solver``."""
    return METHODS[check_choice("solver", name, tuple(METHODS))]


def cheapest_solver(model: DamperModel = TABLE1, initial: InitialState | None = None,
                    tolerance: float = 1e-10) -> tuple[str, str]:
    """The cheapest solver whose error suits a relative ``tolerance``, and why.

    The impact map neglects the main spring's motion during each contact, a relative error of
    the order of (shortest contact duration × main angular frequency) on every impact (for
    Table 1 about 6e-3 rad, measured 1e-4 to 2e-3 on approach speeds); it serves when the
    tolerance is at least that product and at least 1e-2. Otherwise the event solver, at
    ``rtol = tolerance``, is both the most accurate and, per impact, the fastest compliant
    solver; Newmark is never the cheapest.

    Parameters
    ----------
    model : DamperModel
        The damper.
    initial : InitialState, optional
        The start (default: the paper's Figure 5).
    tolerance : float
        Relative accuracy wanted on impact times and speeds, in
        :data:`~acoustiviz.constants.AUTO_TOLERANCE_RANGE`.

    Returns
    -------
    name : str
        ``"impact-map"`` or ``"event"``.
    reason : str
        One sentence for logs and summaries.
    """
    tol = METHODS["auto"].check_rtol(tolerance, "tolerance")
    prod = shortest_contact(model, initial) * model.main_frequency
    if tol >= max(prod, 1e-2):
        return "impact-map", (f"tolerance {tol:g} >= contact time x main frequency = {prod:.2g}: "
                              "instantaneous impacts suffice")
    return "event", (f"tolerance {tol:g} < max(contact time x main frequency = {prod:.2g}, 0.01): "
                     "compliant contacts integrated")


def shortest_contact(model: DamperModel = TABLE1, initial: InitialState | None = None) -> float:
    """Shortest possible Hertz contact duration in s for this start.

    Evaluated at the largest relative speed the initial energy allows
    (:meth:`InitialState.max_relative_speed`); the Hertz duration falls as speed^(-1/5).
    """
    initial = InitialState() if initial is None else initial
    return model.contact_duration(initial.max_relative_speed(model))


def default_step(model: DamperModel = TABLE1, initial: InitialState | None = None) -> float:
    """Default Newmark step in s: 1/50 of :func:`shortest_contact`."""
    return NEWMARK_DEFAULT_FRACTION * shortest_contact(model, initial)


def explicit_step_limit(model: DamperModel = TABLE1, initial: InitialState | None = None) -> float:
    """Stability limit ``2 / ω_contact`` in s of an explicit (central-difference) scheme.

    ``ω_contact`` is the linearised contact frequency at the deepest penetration of the fastest
    possible impact (:meth:`DamperModel.contact_frequency`).
    """
    initial = InitialState() if initial is None else initial
    return 2.0 / model.contact_frequency(initial.max_relative_speed(model))


def central_difference_excursion(model: DamperModel, duration: float, dt: float,
                                 initial: InitialState | None = None) -> float:
    """Largest ``|y - x|`` in m reached by explicit central differences (inf if it blew up).

    A demonstration of where explicit schemes fail (not a solver offered by :func:`simulate`):
    with ``dt`` above :func:`explicit_step_limit` the contact makes the scheme unstable.

    Parameters
    ----------
    model : DamperModel
    duration : float
        Simulated time in s.
    dt : float
        Fixed step in s.
    initial : InitialState, optional
    """
    initial = InitialState() if initial is None else initial
    check_positive("duration", duration, "s")
    check_positive("dt", dt, "s")
    s0 = np.array(initial.as_tuple(model))
    return float(kern.central_difference(_params(model), s0, float(dt), int(math.ceil(duration / dt))))


def _check_t_eval(t_eval, duration):
    if t_eval is None:
        return np.empty(0)
    t = np.atleast_1d(np.asarray(t_eval, dtype=float))
    if t.ndim != 1 or not np.all(np.isfinite(t)):
        raise ParameterError("t_eval", "must be a 1-D array of finite times in s")
    if t.size and (t[0] < 0 or t[-1] > duration):
        raise ParameterError("t_eval", f"times must lie in [0, {duration:g}] s")
    if np.any(np.diff(t) < 0):
        raise ParameterError("t_eval", "times must be non-decreasing")
    return np.ascontiguousarray(t)


def _run_kernel(solver, p, state0, duration, rtol, dt, nsteps, t_eval, n_max, n_ext_cap, model, initial):
    """Compile (or load) a solver, then run it; return its counts, wall times and filled arrays.

    Returns ``(n_impacts, status, t_end, seconds, compile seconds, impacts, dense, final, extrema,
    n_extrema)``.
    """
    impacts = np.empty((n_max, 8))
    dense = np.empty((t_eval.size, 6))
    final = np.zeros(7)
    ext = np.empty((n_ext_cap, 3))
    n_ext = np.zeros(1, np.int64)
    if solver == "newmark":
        # compiled (or loaded from the cache) apart, so that the solver time is the solver alone
        compiled = kern.compile_newmark(p, float(dt), t_eval, int(n_max), impacts, dense, ext, n_ext)
        if nsteps > NEWMARK_LONG_STEPS:
            announce_long_work(f"newmark: {nsteps:.3g} steps of {dt:.3g} s for {duration:g} s of motion, a long "
                               "run (Ctrl-C stops it)")
        t0 = time.perf_counter()
        n, status, t_end = kern.newmark(p, state0, dt, nsteps, t_eval, n_max, impacts, dense, final, ext, n_ext)
        elapsed = time.perf_counter() - t0
        if status == kern.STATUS_OK:
            t_end = duration
    else:
        imap = solver == "impact-map"
        compiled = 0.0
        lnu = table = None  # the event solver: its kernel is compiled without the impact map's branch
        if imap:
            # restitution table over 4 decades of approach speed below the largest possible one
            umax = initial.max_relative_speed(model)
            lnu = np.linspace(math.log(umax) - math.log(1e4), math.log(umax) + 0.05, IMPACT_MAP_NODES)
            table = np.empty((lnu.size, 3))
            compiled = compile_for(kern.restitution_table, (p, lnu, float(rtol), table))
        compiled += compile_for(kern.event_solver, (p, state0, float(duration), float(rtol), t_eval, int(n_max),
                                                    impacts, dense, final, lnu, table, ext, n_ext),
                                "impact-map solver" if imap else "event solver", EVENT_SOLVER_COMPILE_S)
        t0 = time.perf_counter()
        if imap:
            kern.restitution_table(p, lnu, rtol, table)
        n, status, t_end = kern.event_solver(p, state0, duration, rtol, t_eval, n_max, impacts, dense,
                                             final, lnu, table, ext, n_ext)
        elapsed = time.perf_counter() - t0
    return n, status, t_end, elapsed, compiled, impacts, dense, final, ext, int(n_ext[0])


def simulate(
    model: DamperModel = TABLE1,
    duration: float = 20.0,
    *,
    solver: str = "event",
    initial: InitialState | None = None,
    rtol: float = DEFAULT_RTOL,
    dt: float | None = None,
    t_eval=None,
    max_impacts: int = 100_000,
) -> SimulationResult:
    """Simulate the impact damper (paper eq 15) from ``initial`` for ``duration`` s.

    Parameters
    ----------
    model : DamperModel, optional
        The damper (default: the paper's Table 1 with d = 4 cm).
    duration : float, optional
        Simulated time in s (default 20 s: the Table 1 run settles after about 15 s).
    solver : {"event", "newmark", "impact-map"}
        See the module docstring.
    initial : InitialState, optional
        Start (default: the paper's Figure 5, x = 0, dx/dt = 2 m/s, impact mass centred at rest).
    rtol : float, optional
        Relative tolerance of the contact integration (event solver; the impact map's
        restitution integration), in :data:`~acoustiviz.constants.SOLVER_RTOL_RANGE`
        (Newmark takes none: ``dt``). The default
        :data:`~acoustiviz.constants.DEFAULT_RTOL` (1e-13) keeps the first 40 impact times of the
        chaotic Table 1 run within 1e-8 s of the converged reference (1e-12 does not).
    dt : float, optional
        Newmark step in s (default :func:`default_step`). Refused if longer than the shortest
        possible contact; warns (:class:`AccuracyWarning`) above 1/20 of it.
    t_eval : array_like, optional
        Non-decreasing times in s in [0, duration] at which to report x, v, y, w and the
        dissipated energies.
    max_impacts : int, optional
        Stop (``success=False``) after this many contacts.

    Returns
    -------
    SimulationResult

    Examples
    --------
    >>> r = simulate(duration=1.0)
    >>> r.success, len(r.impacts) > 0
    (True, True)
    """
    if not isinstance(model, DamperModel):
        raise ParameterError("model", f"expected a DamperModel, got {type(model).__name__}")
    initial = InitialState() if initial is None else initial
    if not isinstance(initial, InitialState):
        raise ParameterError("initial", f"expected an InitialState, got {type(initial).__name__}")
    method = METHODS[check_choice("solver", solver, SOLVERS)]
    duration = check_positive("duration", duration, "s")
    rtol = method.check_rtol(rtol)
    if int(max_impacts) < 1:
        raise ParameterError("max_impacts", f"must be >= 1, got {max_impacts}")
    state0 = np.array(initial.as_tuple(model))
    t_eval = _check_t_eval(t_eval, duration)
    p = _params(model)
    settings = method.settings(model, initial, duration, rtol, dt)
    dt, nsteps = settings.get("dt", dt), settings.get("steps", 0)

    n_max = int(max_impacts)
    # capacity for the turning points of x: about one per main half-period, plus at most about one
    # per flight and per contact (grown and re-run should it ever not be enough)
    n_ext_cap = 2 * int(math.ceil(duration * model.main_frequency / math.pi)) + 2 * n_max + 64
    while True:
        out = _run_kernel(solver, p, state0, duration, rtol, dt, nsteps,
                          t_eval, n_max, n_ext_cap, model, initial)
        if out[-1] <= n_ext_cap:
            break
        n_ext_cap = int(out[-1])
    n, status, t_end, elapsed, compiled, impacts, dense, final, ext, n_ext = out
    extrema = Extrema(ext[:n_ext, 0], ext[:n_ext, 1], ext[:n_ext, 2])

    x0, v0, y0, w0 = state0
    e0 = float(model.energy(x0, v0, y0, w0))
    xf, vf, yf, wf, ecf, enf, df = final
    energy = EnergyBalance(
        initial=e0,
        kinetic=0.5 * model.M * vf**2 + 0.5 * model.m * wf**2,
        spring=0.5 * model.K * xf**2,
        hertz=0.4 * model.k_hertz * max(df, 0.0) ** 2.5,
        dissipated_main=float(ecf),
        dissipated_contact=float(enf),
    )
    nd = dense.shape[0]
    if status != kern.STATUS_OK:  # stopped early: drop dense rows that were never filled
        nd = int(np.searchsorted(t_eval, t_end, side="right"))
    cols = [np.array(dense[:nd, i]) for i in range(6)]
    for c in cols:
        c.setflags(write=False)
    tt = np.array(t_eval[:nd])
    tt.setflags(write=False)
    return SimulationResult(
        solver=solver,
        settings=MappingProxyType(settings),
        model=model,
        initial=initial,
        duration=duration,
        t_end=float(t_end),
        impacts=ImpactTable.from_rows(impacts[:n]),
        t=tt,
        x=cols[0],
        v=cols[1],
        y=cols[2],
        w=cols[3],
        dissipated_main=cols[4],
        dissipated_contact=cols[5],
        energy=energy,
        success=status == kern.STATUS_OK,
        message=status_message(status) + f" at t = {t_end:.6g} s",
        solver_time=elapsed,
        compile_time=compiled,
        final_state=(float(xf), float(vf), float(yf), float(wf)),
        extrema=extrema,
    )
