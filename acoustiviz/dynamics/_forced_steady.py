"""The impact damper in operation: the excitation, one solver advanced cycle by cycle, and its settings.

The two-degree-of-freedom model of the paper (eq 15) with an excitation of the main mass:

* ``kind="force"``: a force ``F0 cos(ωt)`` on the main mass (``amplitude`` = F0 in N);
* ``kind="base"``: a base (support) displacement ``x_b = B cos(ωt)`` acting through the spring
  ``K`` and the dashpot ``C`` (``amplitude`` = B in m); ``x`` is then the absolute displacement
  and the base acts on the main mass with ``K x_b + C dx_b/dt = K B cos(ωt) - C ω B sin(ωt)``.

Either way the main mass carries ``F(t) = P cos(ωt) + Q sin(ωt)``::

    M x'' + C x' + K x = F(t) + (contact force, eq 15)
    m y''              =       - (contact force)

Solvers: ``"event"`` (closed-form forced free flight with the particular solution, exactly
bracketed contact onset, contacts by adaptive DOP853 with Hertz stiffness and damping c1),
``"impact-map"`` (instantaneous impacts of restitution ``e``; with ``restitution=None`` the
restitution of the compliant contact at each approach speed; a Zeno train of rebounds on a wall
that presses ends in sticking, the two masses moving together until the wall stops pushing, see
:mod:`._forced_driver`) and ``"newmark"`` (the paper's
average-acceleration Newmark-beta at a fixed step, an independent second method).

This module holds the nouns and the integration; the periodic orbits (shooting, Floquet
multipliers) are in :mod:`._shooting`, the attractors of one frequency in :mod:`._attractors`
and the frequency response in :mod:`._forced_response`; :mod:`.forced` gathers the public names.
Imports point one way: ``forced -> _forced_response -> _attractors -> _shooting -> _forced_steady``, and
``_forced_steady -> _forced_direct`` (the driver's compiled entry) ``-> _forced_driver``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._validate import ParameterError, check_choice, check_positive, check_range
from ..constants import (
    EXCITATIONS,
    FORCED_MAX_CYCLES,
    FORCED_MAX_STARTS,
    FORCED_MIN_CYCLES,
    FORCED_RTOL,
    FORCED_RTOL_RANGE,
    FORCED_SOLVERS,
    FORCED_STARTS,
    FORCED_TOLERANCE,
    FORCED_TOLERANCE_RANGE,
)
from ._forced_direct import MODE_CARRY, MODE_PLAIN, run_plain
from ._newmark import newmark_advance
from ._records import NmBooks, params_record
from ._status import LIMIT_CYCLE, STATUS_OK, status_message
from ._status import kernel_params as _params
from .model import DamperModel

__all__ = [
    "EXCITATIONS",
    "FORCED_SOLVERS",
    "Excitation",
    "SteadyStateOptions",
    "SteadyState",
    "check_settings",
    "default_steps_per_cycle",
    "linear_start",
    "simulate_cycles",
]

def section_of(state):
    """Poincaré section point ``(x, v, z, u)`` = ``(x, v, y - x, w - v)`` of a state ``(x, v, y, w)`` (m, m/s)."""
    x, v, y, w = state
    return np.array([x, v, y - x, w - v])


#: Longest period (in forcing cycles) looked for.
MAX_PERIOD = 8
#: Impact map: a rebound slower than this fraction of ω d/2 on a wall that presses turns into sticking.
STICK_SPEED_FRACTION = 1e-4
#: Non-periodic motion is measured over this many batches of :data:`BATCH_CYCLES` cycles (batch means).
WINDOW_BATCHES = 8
#: Cycles per batch of a non-periodic window.
BATCH_CYCLES = 16
#: Cycles measured when no period is found (the window).
NONPERIODIC_CYCLES = WINDOW_BATCHES * BATCH_CYCLES
#: Regimes reported.
REGIMES = ("periodic-N", "quasi-periodic", "chaotic", "unresolved")


@dataclass(frozen=True)
class SteadyStateOptions:
    """How a steady state is looked for (SI; the same defaults for the API, CLI and scenes).

    Attributes
    ----------
    solver : {"event", "impact-map", "newmark"}
    restitution : float or None
        Impact-map restitution in (0, 1]; None: the compliant contact's at each approach speed.
    tolerance : float
        Newton residual below which a periodic orbit is converged: the largest component of
        ``P^n(z) - z``, displacements in m and velocities in m/s
        (:data:`acoustiviz.constants.FORCED_TOLERANCE`).
    rtol : float
        Relative tolerance of the event solver's contact integration.
    max_cycles : int
        Cycles each start is run directly before its motion is measured as non-periodic.
    starts : int
        Starts per frequency (:func:`._attractors.start_states`).
    steps_per_cycle : int or None
        Newmark steps per forcing period (None: :func:`default_steps_per_cycle`).
    max_impacts_per_cycle : int
        More impacts per cycle stop the run (chattering).
    checkpoint_return : float
        Scaled return distance below which a start's best period guess is tried by shooting at the
        checkpoints of :mod:`._attractors` (> 0; inf, the default: at every checkpoint;
        :data:`._attractors.SCREENED_CHECKPOINT_RETURN` screens out the points far from any orbit).
    reuse_known : bool
        A start whose shooting converges onto a stable periodic orbit already found at its frequency ends
        on it without measuring the orbit and its Floquet multipliers again (False, the default: it is
        measured again, then recognised; see :mod:`._attractors`).
    transient_rtol : float or None
        Relative tolerance of the direct runs of the starts (their transients), in [rtol, 1e-4]; the
        shooting and every measurement stay at ``rtol``. None, the default: ``rtol`` throughout. A looser
        transient changes which attractors a few starts reach (``benchmarks/results/operation.md``), so no
        search turns it on by default.
    """

    solver: str = "event"
    restitution: float | None = None
    tolerance: float = FORCED_TOLERANCE
    rtol: float = FORCED_RTOL
    max_cycles: int = FORCED_MAX_CYCLES
    starts: int = FORCED_STARTS
    steps_per_cycle: int | None = None
    max_impacts_per_cycle: int = 200
    checkpoint_return: float = math.inf
    reuse_known: bool = False
    transient_rtol: float | None = None

    def describe(self) -> dict:
        """The settings as a flat dict (for CSV and summaries)."""
        return {"solver": self.solver, "restitution": self.restitution, "tolerance": self.tolerance,
                "rtol": self.rtol, "max_cycles": self.max_cycles, "starts": self.starts}


@dataclass(frozen=True)
class Excitation:
    """A harmonic excitation of the main mass.

    Parameters
    ----------
    frequency : float
        Forcing frequency in Hz (> 0).
    amplitude : float
        Force amplitude F0 in N (``kind="force"``) or base displacement amplitude B in m
        (``kind="base"``), >= 0.
    kind : {"force", "base"}
    """

    frequency: float
    amplitude: float
    kind: str = "force"

    def __post_init__(self):
        check_positive("frequency", self.frequency, "Hz")
        check_range("amplitude", self.amplitude, 0.0, math.inf, unit="N or m")
        check_choice("kind", self.kind, EXCITATIONS)

    @property
    def omega(self) -> float:
        """Angular frequency ω in rad/s."""
        return 2.0 * math.pi * self.frequency

    @property
    def period(self) -> float:
        """Forcing period T in s."""
        return 1.0 / self.frequency

    def at(self, frequency: float) -> Excitation:
        """The same excitation at another ``frequency`` in Hz."""
        return Excitation(frequency, self.amplitude, self.kind)

    def force_coefficients(self, model: DamperModel) -> tuple[float, float]:
        """``(P, Q)`` in N: the main mass carries ``P cos(ωt) + Q sin(ωt)``."""
        if self.kind == "force":
            return float(self.amplitude), 0.0
        return model.K * self.amplitude, -model.C * self.omega * self.amplitude

    def linear_response(self, model: DamperModel) -> complex:
        """Complex amplitude X in m of the main mass alone: ``x = Re(X e^{iωt})``.

        ``X = (P - iQ) / (K - M ω² + i C ω)``: the steady state of the primary system without the
        impact mass (no damper).
        """
        p, q = self.force_coefficients(model)
        w = self.omega
        den = complex(model.K - model.M * w * w, model.C * w)
        if den == 0:
            raise ParameterError("frequency", "undamped resonance (C = 0 at sqrt(K/M)): no steady state")
        return complex(p, -q) / den

    def vector(self, model: DamperModel) -> np.ndarray:
        """Kernel forcing vector ``[ω, P, Q, A_c, A_s]`` (rad/s, N, N, m, m)."""
        p, q = self.force_coefficients(model)
        x = self.linear_response(model)
        return np.array([self.omega, p, q, x.real, -x.imag])


@dataclass(frozen=True)
class SteadyState:
    """One steady motion (an attractor, or an unstable periodic orbit) of the forced damper.

    Attributes
    ----------
    regime : str
        ``"periodic-n"`` (a periodic orbit of period n forcing cycles found by shooting),
        ``"chaotic"`` (largest Lyapunov exponent positive beyond three standard errors),
        ``"quasi-periodic"`` (no periodic orbit, exponent zero within a tight error bar) or
        ``"unresolved"`` (none of these shown; ``message`` gives the reason, also when the solver
        stopped, ``success=False``, with a NaN amplitude).
    converged : bool
        True when the Newton residual of the periodic orbit is below ``settings["tolerance"]``.
    period : int
        n (0 when not periodic).
    cycles : int
        Forcing cycles run directly from the start before the orbit was refined or measured.
    amplitude : float
        Half the peak-to-peak main-mass displacement in m: over one period of a periodic orbit,
        the mean over the batches of the window of a non-periodic motion.
    amplitude_std_err : float
        Standard error of ``amplitude`` in m from the batch means (0 for a periodic orbit).
    x_max, x_min : float
        Largest and smallest main-mass displacement over the measured cycles, in m.
    impacts_per_cycle : float
        Impacts in the measured cycles divided by their number (k / n for period-n).
    impact_times : ndarray
        Contact start time of each measured impact in s (from t = 0 of the run).
    impact_phases : ndarray
        Forcing phase ``ωt mod 2π`` of each measured impact, in rad.
    impact_speeds : ndarray
        Relative approach speed of each measured impact in m/s.
    impact_walls : ndarray
        Wall (+1 or -1) of each measured impact.
    impact_peak_forces : ndarray
        Peak contact force of each measured impact in N (0 for instantaneous impacts).
    impact_durations : ndarray
        Contact durations in s (0 for instantaneous impacts).
    work_input, dissipated_main, dissipated_contact, energy_change : float
        Over the measured cycles, in J: work of the excitation on the main mass, energy dissipated
        by C and in the contacts, change of mechanical energy.
    poincare : ndarray
        ``(k, 4)`` section points ``x, v, z, w - v`` (m, m/s) at forcing phase 0: the n points of
        a period-n orbit, the window's points of a non-periodic motion.
    final_state : tuple
        ``(x, v, y, w)`` at the end (forcing phase 0), to continue from.
    message : str
    measured_cycles : int
        Forcing cycles measured (n for period-n, :data:`NONPERIODIC_CYCLES` otherwise).
    residual : float
        Largest component of ``P^n(z) - z`` at the orbit (m and m/s); NaN when not periodic.
    floquet : ndarray
        Floquet multipliers (complex): the eigenvalues of the monodromy matrix ``dP^n/dz``.
    stable : bool
        Periodic: every multiplier inside the unit circle. Non-periodic: True (an attractor).
    newton_iterations : int
        Newton steps of the shooting that converged.
    cycles_integrated : int
        Forcing cycles integrated in all (direct run, shooting and its Jacobians, measurement).
    lyapunov, lyapunov_std_err : float
        Largest Lyapunov exponent in 1/s over the window of a non-periodic motion, and its
        standard error from batch means (NaN for a periodic orbit: see ``floquet``).
    """

    excitation: Excitation
    model: DamperModel
    solver: str
    regime: str
    converged: bool
    period: int
    cycles: int
    amplitude: float
    x_max: float
    x_min: float
    impacts_per_cycle: float
    impact_times: np.ndarray
    impact_phases: np.ndarray
    impact_speeds: np.ndarray
    impact_walls: np.ndarray
    impact_peak_forces: np.ndarray
    impact_durations: np.ndarray
    work_input: float
    dissipated_main: float
    dissipated_contact: float
    energy_change: float
    poincare: np.ndarray
    final_state: tuple
    message: str
    success: bool = True
    settings: dict = field(default_factory=dict)
    measured_cycles: int = 1
    amplitude_std_err: float = 0.0
    residual: float = math.nan
    floquet: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=complex))
    stable: bool = True
    newton_iterations: int = 0
    cycles_integrated: int = 0
    lyapunov: float = math.nan
    lyapunov_std_err: float = math.nan

    @property
    def periodic(self) -> bool:
        """True for a periodic orbit (``regime`` periodic-n)."""
        return self.period > 0

    @property
    def max_floquet_modulus(self) -> float:
        """Largest modulus of the Floquet multipliers (NaN when not periodic)."""
        return float(np.max(np.abs(self.floquet))) if self.floquet.size else math.nan

    @property
    def energy_closure(self) -> float:
        """``(work - dissipated - ΔE) / work`` over the measured cycles (0 = closed)."""
        if self.work_input == 0.0:
            return 0.0
        return (self.work_input - self.dissipated_main - self.dissipated_contact
                - self.energy_change) / self.work_input

    @property
    def amplitude_without_damper(self) -> float:
        """Steady amplitude |X| in m of the main mass alone (no impact mass)."""
        return abs(self.excitation.linear_response(self.model))

    @property
    def reduction_db(self) -> float:
        """``20 log10(amplitude without / with damper)`` in dB (positive = the damper helps)."""
        if self.amplitude <= 0.0:
            return math.inf
        return 20.0 * math.log10(self.amplitude_without_damper / self.amplitude)


def linear_start(model: DamperModel, excitation: Excitation) -> tuple[float, float, float, float]:
    """Start ``(x, v, y, w)`` at t = 0 in m and m/s: the main mass on its linear steady state.

    The impact mass is at rest at ``y = 0`` (the cavity's centre at rest), moved to the nearest
    wall if the main mass is farther than d/2 from rest.
    """
    xc = excitation.linear_response(model)
    hg = 0.5 * model.gap
    x0 = xc.real
    return x0, -excitation.omega * xc.imag, min(max(0.0, x0 - hg), x0 + hg), 0.0


def _check_common(model, excitation, solver, restitution):
    if not isinstance(model, DamperModel):
        raise ParameterError("model", f"expected a DamperModel, got {type(model).__name__}")
    if not isinstance(excitation, Excitation):
        raise ParameterError("excitation", f"expected an Excitation, got {type(excitation).__name__}")
    check_choice("solver", solver, FORCED_SOLVERS)
    if solver != "newmark" and not model.underdamped:
        raise ParameterError("C", f"the {solver} solver needs C < 2 sqrt(K M) = "
                             f"{2 * math.sqrt(model.K * model.M):g} N s/m; use solver='newmark'")
    if restitution is not None:
        if solver != "impact-map":
            raise ParameterError("restitution", "applies to solver='impact-map' only")
        check_range("restitution", restitution, 0.0, 1.0, low_open=True)
    excitation.linear_response(model)  # refuses an undamped resonance


def _together(model, excitation, solver) -> np.ndarray:
    """Forcing vector of the two masses moving together, with the sticking speed (impact map only)."""
    import dataclasses

    try:
        vec = excitation.vector(dataclasses.replace(model, M=model.M + model.m))
    except ParameterError:  # undamped resonance of the pair: no sticking phase in closed form
        return np.zeros(6)
    u_stick = STICK_SPEED_FRACTION * excitation.omega * 0.5 * model.gap if solver == "impact-map" else 0.0
    return np.append(vec, u_stick)


class _Runner:
    """Advances one solver a forcing cycle at a time, or a stretch of cycles in one call (holds the kernel buffers).

    ``rows`` impact rows are kept (the caller passes a start row to :meth:`cycle`); one spare row
    at the end receives the remainder of a contact already open at the start.
    """

    def __init__(self, model, excitation, settings, state, rows=None):
        self.p = _params(model)
        self.prm = params_record(self.p)
        self.fc = excitation.vector(model)
        self.fcs = _together(model, excitation, settings.solver)
        self.T = excitation.period
        self.solver = settings.solver
        r = settings.restitution
        # the driver's restitution: None compliant contacts (event solver), -2 the compliant contact's
        # restitution at each speed, else the impact map's coefficient
        self.e = None if self.solver == "event" else (-2.0 if r is None else float(r))
        self.rtol = settings.rtol
        spc = settings.steps_per_cycle
        self.nsteps = int(spc if spc is not None else default_steps_per_cycle(model, excitation))
        self.h = self.T / self.nsteps
        self.hg = 0.5 * model.gap
        self.st = np.zeros(8)
        self.cap = int(settings.max_impacts_per_cycle)
        rows = self.cap * (MAX_PERIOD + 1) if rows is None else int(rows)
        self.imp = np.zeros((rows + 1, 8))
        self.model = model
        self.k = 0  # cycles done since the last set_state
        self.total = 0  # cycles integrated in all
        self.set_state(state)

    def set_state(self, state, k=0):
        """Restart from ``(x, v, y, w)`` (m, m/s) at forcing phase 0, inside a contact if ``|y - x| > d/2``."""
        self.st[:] = 0.0
        self.st[:4] = state
        z = state[2] - state[0]
        if abs(z) > self.hg:  # a continued run may start inside a contact
            sw = 1.0 if z > 0 else -1.0
            self.st[4:] = (1.0, sw, math.sqrt(abs(z) - self.hg), sw * (state[3] - state[1]))
        self.k = int(k)

    def cycle(self, n0, acc, extrema):
        """Advance one forcing period; impacts from row ``n0``. Returns ``(n, status)``."""
        t0 = self.k * self.T
        cap = min(n0 + self.cap, self.imp.shape[0] - 1)
        if self.solver == "newmark":
            # no dense output, no turning points (None: compiled out)
            n, status, _, _ = newmark_advance(self.prm, self.fc, self.st, t0, self.h, self.nsteps, n0,
                                              NmBooks(self.imp, cap, acc, extrema), None, None)
            out = (n, status)
        else:
            # one cycle through the driver's one compiled entry (its search arguments unused)
            _, status, n = self.kernel(n0, acc, extrema, MODE_PLAIN, 1, None)
            out = (n, status)
        self.k += 1
        self.total += 1
        return out

    def cycles(self, count, n0, acc, extrema, states=None):
        """Advance ``count`` forcing periods, as ``count`` calls of :meth:`cycle` do, bit for bit.

        With ``states`` None each cycle writes its impacts from row ``n0`` (a Poincaré map); else each
        from the row the cycle before ended on (from ``n0``), and row ``j`` of ``states`` (count, 4)
        receives ``(x, v, y, w)`` (m, m/s) after cycle ``j``. The event solver and the impact map run
        them in one compiled call. Stops after the first cycle the solver stops.

        Returns
        -------
        tuple of int
            ``(n, status, done)``: the next free impact row, the status of the last cycle run and the
            cycles run (that one included).
        """
        count = int(count)
        if self.solver == "newmark":
            n, status = n0, STATUS_OK
            for j in range(count):
                n, status = self.cycle(n0 if states is None else n, acc, extrema)
                if states is not None:
                    states[j] = self.st[:4]
                if status != STATUS_OK:
                    return n, status, j + 1
            return n, status, count
        mode = MODE_PLAIN if states is None else MODE_CARRY
        k, status, n = self.kernel(n0, acc, extrema, mode, count, states)
        self.k += k
        self.total += k
        return n, status, k

    def kernel(self, n0, acc, extrema, mode, count, pts):
        """Cycles ``1..count`` from here (:func:`._forced_direct.run_plain`); ``self.k``, ``self.total`` left alone."""
        return run_plain(self.solver, self.prm, self.fc, self.fcs, self.st, self.k, self.T, self.e, self.rtol, self.imp,
                         n0, self.cap, acc, extrema, mode, count, pts)

    def state(self):
        """``(x, v, y, w)`` now (m, m/s)."""
        return self.st[:4].copy()

    def section(self):
        """Poincaré point ``x, v, z, w - v`` (m, m/s)."""
        return section_of(self.st[:4])

    def energy(self):
        """Mechanical energy in J (kinetic + spring + Hertz)."""
        x, v, y, w = self.st[:4]
        return float(self.model.energy(x, v, y, w))


def check_settings(model, excitation, settings=None, **kwargs) -> SteadyStateOptions:
    """Check ``settings`` (or build them from ``**kwargs``) without running; return them, checked.

    Errors name the parameter and the allowed range.
    """
    if settings is None:
        unknown = set(kwargs) - set(SteadyStateOptions.__dataclass_fields__)
        if unknown:
            raise ParameterError(sorted(unknown)[0], "unknown setting of the forced damper")
        settings = SteadyStateOptions(**kwargs)
    elif kwargs:
        raise ParameterError(sorted(kwargs)[0], "give either settings or keywords, not both")
    solver, restitution = settings.solver, settings.restitution
    _check_common(model, excitation, solver, restitution)
    tol = check_range("tolerance", settings.tolerance, *FORCED_TOLERANCE_RANGE, unit="m, m/s")
    rtol = check_range("rtol", settings.rtol, *FORCED_RTOL_RANGE)
    ints = {}
    for name, low, high in (("max_cycles", FORCED_MIN_CYCLES, 10_000_000), ("starts", 1, FORCED_MAX_STARTS),
                            ("max_impacts_per_cycle", 1, 1_000_000)):
        v = getattr(settings, name)
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) and not (
                isinstance(v, float) and v.is_integer()):
            raise ParameterError(name, f"expected an integer in [{low}, {high}], got {v!r}")
        if not low <= int(v) <= high:
            raise ParameterError(name, f"must lie in [{low}, {high}], got {v}")
        ints[name] = int(v)
    spc = settings.steps_per_cycle
    if spc is not None and int(spc) < 8:
        raise ParameterError("steps_per_cycle", f"must be >= 8, got {spc}")
    ret = settings.checkpoint_return
    if not (isinstance(ret, float) and ret == math.inf):  # inf: every checkpoint tried
        ret = check_range("checkpoint_return", ret, 0.0, math.inf, low_open=True)
    if not isinstance(settings.reuse_known, bool):
        raise ParameterError("reuse_known", f"must be True or False, got {settings.reuse_known!r}")
    transient = settings.transient_rtol
    if transient is not None:  # no tighter than the search's rtol
        transient = check_range("transient_rtol", transient, rtol, FORCED_RTOL_RANGE[1])
    return SteadyStateOptions(solver=solver, restitution=restitution, tolerance=tol, rtol=rtol,
                              steps_per_cycle=None if spc is None else int(spc), checkpoint_return=ret,
                              reuse_known=settings.reuse_known, transient_rtol=transient, **ints)


def _start(model, excitation, initial) -> tuple:
    """The checked start ``(x, v, y, w)``: ``initial`` or :func:`linear_start`.

    A start outside the cavity is refused; a contact penetration of up to 1 % of the gap is
    allowed (a continued sweep may stop inside a contact).
    """
    if initial is None:
        return linear_start(model, excitation)
    try:
        state = tuple(float(s) for s in initial)
    except (TypeError, ValueError):
        state = ()
    if len(state) != 4 or not all(math.isfinite(s) for s in state):
        raise ParameterError("initial", "expected (x, v, y, w) finite, in m and m/s")
    hg = 0.5 * model.gap
    if abs(state[2] - state[0]) > hg + 0.01 * model.gap:
        raise ParameterError("initial", f"the impact mass must start in the cavity, |y - x| <= {hg:g} m "
                             "(plus a contact penetration below 1 % of the gap)")
    return state


def default_steps_per_cycle(model: DamperModel, excitation: Excitation) -> int:
    """Newmark steps per forcing period: 1/50 of the Hertz contact at speed ``2 ω X_s + 2 ω d/2``.

    ``X_s = max(|X_lin|, d/2)``; the largest relative speed of a forced impact is of that order.
    """
    xs = max(abs(excitation.linear_response(model)), 0.5 * model.gap)
    u = 2.0 * excitation.omega * (xs + 0.5 * model.gap)
    return int(math.ceil(50.0 * excitation.period / model.contact_duration(u)))


def simulate_cycles(
    model: DamperModel,
    excitation: Excitation,
    cycles: int,
    *,
    solver: str = "event",
    restitution: float | None = None,
    initial=None,
    rtol: float = FORCED_RTOL,
    steps_per_cycle: int | None = None,
    max_impacts_per_cycle: int = 200,
):
    """Run ``cycles`` forcing periods and return the section points and every impact.

    Returns
    -------
    points : ndarray
        ``(cycles + 1, 4)``: ``x, v, z, w - v`` at t = kT (m, m/s).
    impacts : ndarray
        ``(n, 8)`` rows: time s, wall, approach and separation speed m/s, duration s, peak force N,
        impulse N s, energy lost J.
    energy : ndarray
        ``[work of the excitation, dissipated by C, dissipated in contacts, ΔE]`` in J.
    """
    _check_common(model, excitation, solver, restitution)
    state = _start(model, excitation, initial)
    settings = SteadyStateOptions(solver=solver, restitution=restitution, rtol=rtol, steps_per_cycle=steps_per_cycle,
                                  max_impacts_per_cycle=max_impacts_per_cycle)
    run = _Runner(model, excitation, settings, state, rows=int(max_impacts_per_cycle) * int(cycles))
    run.cap = run.imp.shape[0] - 1
    pts = [run.section()]
    acc = np.array([0.0, 0.0, 0.0, -np.inf, np.inf])
    e0 = run.energy()
    n = 0
    for _ in range(int(cycles)):
        n, status = run.cycle(n, acc, False)
        pts.append(run.section())
        if status != STATUS_OK:
            raise ParameterError("cycles", f"{status_message(status, LIMIT_CYCLE)} after {run.k} cycles")
    return np.array(pts), run.imp[:n].copy(), np.array([acc[0], acc[1], acc[2], run.energy() - e0])
