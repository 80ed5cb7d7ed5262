"""The impact damper in operation: harmonic excitation and the periodic steady state.

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

The steady state is found on the Poincaré section at forcing phase 0 (``t = kT``, ``T = 2π/ω``):
the motion is declared period-``n`` when two consecutive section points both return to within
``tolerance`` after ``n`` cycles, distances being measured in the scaled state
``(x/X_s, v/(ω X_s), z/(d/2), (w - v)/(ω d/2))`` with ``X_s = max(|X_lin|, d/2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._validate import ParameterError, check_choice, check_positive, check_range
from ..constants import EXCITATIONS, FORCED_SOLVERS
from . import _forced_driver as fd
from ._newmark import newmark_advance
from ._status import LIMIT_CYCLE, STATUS_OK, status_message
from ._status import kernel_params as _params
from .model import DamperModel

__all__ = [
    "EXCITATIONS",
    "SWEEPS",
    "FrequencyResponse",
    "check_settings",
    "describe",
    "frequency_response",
    "FORCED_SOLVERS",
    "Excitation",
    "SteadyState",
    "linear_start",
    "steady_state",
    "simulate_cycles",
]

#: Default tolerance of the Poincaré return (scaled state, see the module docstring).
DEFAULT_TOLERANCE = 1e-6
#: Longest period (in forcing cycles) looked for.
MAX_PERIOD = 8
#: Impact map: a rebound slower than this fraction of ω d/2 on a wall that presses turns into sticking.
STICK_SPEED_FRACTION = 1e-4
#: Cycles measured when no period is found.
NONPERIODIC_CYCLES = 32


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
    """The steady (or last measured) motion of the forced damper.

    Attributes
    ----------
    regime : str
        ``"periodic-n"`` (period n forcing cycles), ``"non-periodic"`` (no period <= 8 found
        within the cycle limit: chaotic, or a transient too slow for the limit) or ``"failed"``
        (the solver stopped, see ``message``; the amplitude is then NaN).
    converged : bool
        True when a period was found within ``tolerance``.
    period : int
        n (0 when non-periodic).
    cycles : int
        Forcing cycles simulated before the measurement.
    amplitude : float
        Half the peak-to-peak main-mass displacement over the measured cycles, in m.
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
        ``(k, 4)`` last section points ``x, v, z, w - v`` (m, m/s) at forcing phase 0.
    final_state : tuple
        ``(x, v, y, w)`` at the end (forcing phase 0), to continue from.
    message : str
    measured_cycles : int
        Forcing cycles measured (n for period-n, 32 when non-periodic), starting at ``cycles T``.
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
    """Advances one solver cycle by cycle (holds the kernel buffers)."""

    def __init__(self, model, excitation, solver, restitution, rtol, steps_per_cycle, state,
                 max_impacts_per_cycle):
        self.p = _params(model)
        self.fc = excitation.vector(model)
        self.fcs = _together(model, excitation, solver)
        self.T = excitation.period
        self.solver = solver
        self.e = -1.0 if solver == "event" else (-2.0 if restitution is None else float(restitution))
        self.rtol = rtol
        self.nsteps = int(steps_per_cycle)
        self.h = self.T / self.nsteps
        self.st = np.zeros(8)
        self.st[:4] = state
        z = state[2] - state[0]
        hg = 0.5 * model.gap
        if abs(z) > hg:  # a continued run may start inside a contact
            sw = 1.0 if z > 0 else -1.0
            self.st[4:] = (1.0, sw, math.sqrt(abs(z) - hg), sw * (state[3] - state[1]))
        self.cap = int(max_impacts_per_cycle)
        self.imp = np.zeros((self.cap * (MAX_PERIOD + NONPERIODIC_CYCLES + 1), 8))
        self.model = model
        self.k = 0  # cycles done

    def cycle(self, n0, acc, extrema):
        """Advance one forcing period; impacts from row ``n0``. Returns ``(n, status)``."""
        t0 = self.k * self.T
        cap = min(n0 + self.cap, self.imp.shape[0])
        if self.solver == "newmark":
            # no dense output, no turning points (None: compiled out)
            n, status, _, _ = newmark_advance(self.p, self.fc, self.st, t0, self.h, self.nsteps, self.imp, n0,
                                              cap, acc, extrema, None, 0, None, None, None)
            out = (n, status)
        else:
            out = fd.advance(self.p, self.fc, self.fcs, self.st, t0, t0 + self.T, self.e, self.rtol, self.imp,
                             n0, cap, acc, extrema)
        self.k += 1
        return out

    def section(self):
        """Poincaré point ``x, v, z, w - v`` (m, m/s)."""
        x, v, y, w = self.st[:4]
        return np.array([x, v, y - x, w - v])

    def energy(self):
        """Mechanical energy in J (kinetic + spring + Hertz)."""
        x, v, y, w = self.st[:4]
        return float(self.model.energy(x, v, y, w))


def check_settings(model, excitation, *, solver="event", restitution=None, tolerance=DEFAULT_TOLERANCE,
                   max_cycles=2000, rtol=1e-10, steps_per_cycle=None, max_impacts_per_cycle=200):
    """Check the settings of :func:`steady_state` without running; return (tolerance, rtol, max_cycles)."""
    _check_common(model, excitation, solver, restitution)
    tol = check_range("tolerance", tolerance, 1e-12, 1e-2)
    rtol = check_range("rtol", rtol, 1e-14, 1e-4)
    try:
        max_cycles = int(max_cycles)
    except (TypeError, ValueError):
        raise ParameterError("max_cycles", f"expected an integer, got {max_cycles!r}") from None
    if max_cycles < 2 * MAX_PERIOD + 2:
        raise ParameterError("max_cycles", f"must be >= {2 * MAX_PERIOD + 2}, got {max_cycles}")
    if steps_per_cycle is not None and int(steps_per_cycle) < 8:
        raise ParameterError("steps_per_cycle", f"must be >= 8, got {steps_per_cycle}")
    if int(max_impacts_per_cycle) < 1:
        raise ParameterError("max_impacts_per_cycle", f"must be >= 1, got {max_impacts_per_cycle}")
    return tol, rtol, max_cycles


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


def _find_period(points, k, scale, tol):
    """Smallest n <= MAX_PERIOD with points k and k-1 returning after n cycles within ``tol``.

    A period n > 1 also needs its points distinct (closest pair farther than 1000 ``tol``): a
    slowly spiralling transient returns close to itself after a few cycles without being periodic.
    """
    for n in range(1, MAX_PERIOD + 1):
        if k - 1 - n < 0:
            return 0
        d0 = np.max(np.abs(points[k] - points[k - n]) / scale)
        d1 = np.max(np.abs(points[k - 1] - points[k - 1 - n]) / scale)
        if d0 <= tol and d1 <= tol:
            if n > 1:
                lag = min(np.max(np.abs(points[k] - points[k - j]) / scale) for j in range(1, n))
                if lag <= 1e3 * tol:
                    return 0
            return n
    return 0


def steady_state(
    model: DamperModel,
    excitation: Excitation,
    *,
    solver: str = "event",
    restitution: float | None = None,
    initial=None,
    tolerance: float = DEFAULT_TOLERANCE,
    max_cycles: int = 2000,
    rtol: float = 1e-10,
    steps_per_cycle: int | None = None,
    max_impacts_per_cycle: int = 200,
) -> SteadyState:
    """Run the forced damper until its motion is periodic, then measure one period.

    Parameters
    ----------
    model : DamperModel
        The damper (paper eq 15, Table 1).
    excitation : Excitation
        Harmonic force or base motion.
    solver : {"event", "impact-map", "newmark"}
        See the module docstring.
    restitution : float, optional
        Coefficient of restitution in (0, 1] of the impact map's instantaneous impacts (default:
        the compliant contact's restitution at each approach speed).
    initial : tuple, optional
        ``(x, v, y, w)`` at t = 0 in m and m/s (default :func:`linear_start`); a previous
        :attr:`SteadyState.final_state` continues a frequency sweep.
    tolerance : float
        Poincaré return tolerance in the scaled state (module docstring), in [1e-12, 1e-2].
    max_cycles : int
        Cycle limit; reached without a period the regime is ``"non-periodic"`` and the last
        32 cycles are measured (``converged=False``).
    rtol : float
        Relative tolerance of the contact integration (event solver), in [1e-14, 1e-4].
    steps_per_cycle : int, optional
        Newmark steps per forcing period (default: 1/50 of the Hertz contact at the largest
        relative speed ``2 ω X_s``, see :func:`simulate_cycles`).
    max_impacts_per_cycle : int
        Refuse (``success=False``) more impacts per cycle (chattering).

    Returns
    -------
    SteadyState

    Notes
    -----
    Periodic motion of an impact oscillator with impacts of restitution e: Masri and Caughey
    (1966); the closed-form reference is :func:`acoustiviz.dynamics.periodic.masri_caughey`.
    """
    tol, rtol, max_cycles = check_settings(model, excitation, solver=solver, restitution=restitution,
                                           tolerance=tolerance, max_cycles=max_cycles, rtol=rtol)
    state = _start(model, excitation, initial)
    hg = 0.5 * model.gap
    xs = max(abs(excitation.linear_response(model)), hg)
    om = excitation.omega
    scale = np.array([xs, om * xs, hg, om * hg])
    if steps_per_cycle is None:
        steps_per_cycle = default_steps_per_cycle(model, excitation)
    run = _Runner(model, excitation, solver, restitution, rtol, steps_per_cycle, state,
                  max_impacts_per_cycle)
    points = np.empty((max_cycles + 1, 4))
    points[0] = run.section()
    acc = np.zeros(5)
    period = 0
    status = STATUS_OK
    for k in range(1, max_cycles + 1):
        n, status = run.cycle(0, acc, False)
        points[k] = run.section()
        if status != STATUS_OK:
            break
        period = _find_period(points, k, scale, tol)
        if period:
            break
    cycles = run.k
    if status != STATUS_OK:
        return _measured(run, excitation, model, solver, 0, cycles, points[: cycles + 1], 0, status,
                         np.array([0.0, 0.0, 0.0, -np.inf, np.inf]), 0.0, tol,
                         f"{status_message(status, LIMIT_CYCLE)} after {cycles} cycles")
    measure = period if period else NONPERIODIC_CYCLES
    e0 = run.energy()
    acc = np.array([0.0, 0.0, 0.0, -np.inf, np.inf])
    n = 0
    for _ in range(measure):
        n, status = run.cycle(n, acc, True)
        if status != STATUS_OK:
            break
    de = run.energy() - e0
    msg = (f"period {period} found after {cycles} cycles (tolerance {tol:g})" if period else
           f"no period <= {MAX_PERIOD} within {cycles} cycles (tolerance {tol:g}); "
           f"last {measure} cycles measured")
    if status != STATUS_OK:
        msg = f"{status_message(status, LIMIT_CYCLE)} while measuring"
    return _measured(run, excitation, model, solver, period, cycles, points[: cycles + 1], n, status, acc, de,
                     tol, msg, measure)


def _measured(run, excitation, model, solver, period, cycles, points, n, status, acc, de, tol, msg,
              measure=1):
    imp = run.imp[:n]
    regime = f"periodic-{period}" if period else "non-periodic"
    if status != STATUS_OK:
        regime = "failed"
    phases = np.mod(excitation.omega * imp[:, 0], 2.0 * math.pi)
    x_max, x_min = float(acc[3]), float(acc[4])
    amp = 0.5 * (x_max - x_min) if math.isfinite(x_max) else math.nan
    return SteadyState(
        excitation=excitation, model=model, solver=solver, regime=regime, converged=bool(period),
        period=int(period), cycles=int(cycles), amplitude=float(amp), x_max=x_max, x_min=x_min,
        impacts_per_cycle=n / measure, impact_times=imp[:, 0].copy(), impact_phases=phases,
        impact_speeds=imp[:, 2].copy(),
        impact_walls=imp[:, 1].copy(), impact_peak_forces=imp[:, 5].copy(),
        impact_durations=imp[:, 4].copy(), work_input=float(acc[0]), dissipated_main=float(acc[1]),
        dissipated_contact=float(acc[2]), energy_change=float(de),
        poincare=np.array(points[-max(NONPERIODIC_CYCLES, 1):]),
        final_state=tuple(float(s) for s in run.st[:4]), message=msg, success=status == STATUS_OK,
        settings={"tolerance": tol, "rtol": run.rtol, "steps_per_cycle": run.nsteps},
        measured_cycles=int(measure),
    )


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
    rtol: float = 1e-10,
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
    if steps_per_cycle is None:
        steps_per_cycle = default_steps_per_cycle(model, excitation)
    run = _Runner(model, excitation, solver, restitution, rtol, steps_per_cycle, state,
                  max_impacts_per_cycle)
    run.imp = np.zeros((int(max_impacts_per_cycle) * int(cycles), 8))
    run.cap = run.imp.shape[0]
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


# the frequency response builds on the steady state above
from ._forced_response import SWEEPS, FrequencyResponse, describe, frequency_response  # noqa: E402
