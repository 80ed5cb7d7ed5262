"""The range in which an impact, its sound and a damper run stay finite, checked before any work.

Extreme but finite settings (a speed of 1e200 m/s, a radius of 1e-300 m, a sound speed of 1e200
m/s) make a derived quantity (the sphere's mass, the contact time, the compression, the peak
acceleration, the radiated pressure) overflow to ``inf`` or underflow to ``0``, and the
failure would surface far downstream under an internal name. Here each derived quantity is
written as a power law of the impact speed, ``log10 Q = c0 + s log10 v`` (paper eqs 1-4: the
compression ``alpha = (5 m v^2 / 4 K_HZ)^(2/5)``, the contact time ``T = 2.943 alpha / v``, the
peak force ``K_HZ alpha^(3/2)``), so the speeds for which every quantity stays inside
``[1e-290, 1e290]`` (in SI units) form one interval, found without evaluating anything that
could overflow. A speed outside it is refused naming the input at fault: of the speed and the
settings that alone could make it work (the sphere's mass, K_HZ, the free travel, ...), the one
farthest, in decades, outside the range that works for it with the others as given. The error
gives that range: the speeds that work (``velocity``; ``v`` for the damper), or the bound the
setting must meet.

For the damper two physical bounds join the numerical ones: the contact must not compress by
more than the whole free travel ``d`` (a Hertz contact that deep is meaningless), and it must
last less than one period ``2 pi sqrt(M/K)`` of the main mass and more than 1e-12 of the run
(shorter contacts cannot be resolved in double precision).

Errors name API parameters; front-ends rename them (:func:`acoustiviz.app.names.user_terms`).
"""

from __future__ import annotations

import math

from ..constants import (
    HERTZ_DURATION_CONSTANT,
    PAPER_DENSITY,
    PAPER_GAP,
    PAPER_K_HERTZ,
    PAPER_RADIUS,
    TABLE1_PARAMETERS,
)
from ..errors import ParameterError

__all__ = ["LOG_LIMIT", "FORCING_DECADES", "check_sphere_mass", "check_impact", "check_damper",
           "check_forcing_frequencies", "contact_speeds"]

#: Derived quantities must lie within 10**±LOG_LIMIT in SI units (double precision holds ±308;
#: the margin leaves room for the products formed downstream).
LOG_LIMIT = 290.0
#: Lightest impact mass, as a fraction of the main mass, whose contacts the solvers follow
#: (a lighter one is pinned between the walls in ever shorter contacts: the event solver stalls).
MIN_MASS_RATIO = 1e-6
#: Largest contact time in units of the sphere's decay time a/c for which the radiation
#: formulas stay finite.
MAX_DECAY_TIMES_LOG = 100.0
#: Forcing frequencies are accepted within this many decades of the main system's natural
#: frequency sqrt(K/M)/2 pi: three decades above, the main mass moves 1e-6 of its static
#: deflection (there is nothing to damp); three below, it follows the force quasi-statically.
FORCING_DECADES = 3.0


#: The paper's values (Figure 2 sphere, Table 1 damper) an input is put back to when looking for the one at fault.
_ORDINARY = {"k_hertz": PAPER_K_HERTZ, "mass": PAPER_DENSITY * 4.0 / 3.0 * math.pi * PAPER_RADIUS**3,
             "M": TABLE1_PARAMETERS["M"], "K": TABLE1_PARAMETERS["K"], "m": TABLE1_PARAMETERS["m"], "gap": PAPER_GAP}
#: Units of the inputs that may be at fault.
_UNITS = {"k_hertz": "N/m^1.5", "mass": "kg", "M": "kg", "K": "N/m", "m": "kg", "gap": "m"}


def _lg(x: float) -> float:
    return math.log10(x)


def _lg0(x: float) -> float:
    """log10 of ``x`` >= 0, with -inf at 0 and inf at inf."""
    return -math.inf if x == 0 else math.inf if math.isinf(x) else _lg(x)


def _at_fault(works, given: dict, speed: float, lo: float, hi: float):
    """The input at fault: the one of ``given`` (or None: the speed) farthest outside the range that works for it.

    ``works(**{name: value})`` says whether the speed works with one input changed; an input whose
    ordinary value (:data:`_ORDINARY`) does not make it work cannot alone be at fault. Its range
    ends at the bound found by bisection in log10 between its value and the ordinary one; the
    speed's is ``[lo, hi]`` m/s (empty: not the speed). Distances are in decades. Returns
    ``(name, bound)`` (``"kg >= 3.2e-150"``), or None when the speed is farthest out.
    """
    far = max(_lg0(lo) - _lg(speed), _lg(speed) - _lg0(hi)) if lo <= hi else -math.inf
    best = None
    for name, value in given.items():
        ref = _ORDINARY[name]
        if not 0 < value < math.inf or value == ref or not works(**{name: ref}):
            continue
        bad, good = _lg(value), _lg(ref)
        for _ in range(64):
            mid = 0.5 * (bad + good)
            bad, good = (bad, mid) if works(**{name: 10.0**mid}) else (mid, good)
        if abs(good - _lg(value)) > far:
            far = abs(good - _lg(value))
            best = name, f"{'>=' if good > bad else '<='} {10.0**good:.3g} {_UNITS[name]}"
    return best


def _speed_interval(constraints) -> tuple:
    """Speeds (m/s) meeting every ``(c0, s, lo, hi)``: ``lo <= c0 + s log10 v <= hi``; (lo, hi), maybe empty."""
    lo, hi = -math.inf, math.inf
    for c0, s, qlo, qhi in constraints:
        if s == 0:
            if not qlo <= c0 <= qhi:
                return math.inf, -math.inf
            continue
        a, b = (qlo - c0) / s, (qhi - c0) / s
        lo, hi = max(lo, min(a, b)), min(hi, max(a, b))
    return _pow10(lo), _pow10(hi)


def _pow10(x: float) -> float:
    """10**x without overflow: 0 below 1e-320, inf above 1e308."""
    return 0.0 if x < -320 else math.inf if x > 308 else 10.0**x


def _contact_constraints(k_hertz: float, mu: float, mass: float) -> list:
    """Power laws in v of v², q = 5 mu v²/(4 K), the compression, contact time, peak force and acceleration."""
    L = LOG_LIMIT
    q0 = _lg(1.25) + _lg(mu) - _lg(k_hertz)
    return [
        (0.0, 2.0, -L, L),  # v²
        (q0, 2.0, -L, L),  # q
        (0.4 * q0, 0.8, -L, L),  # compression alpha
        (_lg(HERTZ_DURATION_CONSTANT) + 0.4 * q0, -0.2, -L, L),  # contact time
        (_lg(k_hertz) + 0.6 * q0, 1.2, -L, L),  # peak force
        (_lg(k_hertz) + 0.6 * q0 - _lg(mass), 1.2, -L, L),  # peak acceleration
    ]


def contact_speeds(k_hertz: float, mass: float) -> tuple:
    """The interval ``(lo, hi)`` in m/s of approach speeds whose Hertz contact of ``mass`` (kg) stays finite.

    With ``k_hertz`` in N/m^1.5: the compression, contact time, peak force and acceleration within
    ``10**±LOG_LIMIT`` (empty, ``lo > hi``, when no speed works).
    """
    return _speed_interval(_contact_constraints(k_hertz, mass, mass))


def _fmt_range(lo: float, hi: float, unit: str) -> str:
    return f"[{lo:.3g}, {hi:.3g}] {unit}"


def check_sphere_mass(radius: float, density: float, name: str = "radius") -> float:
    """The mass ``density * 4/3 pi radius**3`` in kg, or an error naming ``name`` if it is not representable.

    ``name`` is ``"radius"`` (the range given is of radii at this density) or ``"density"``
    (of densities at this radius).
    """
    lv = _lg(4.0 / 3.0 * math.pi)
    lm = _lg(density) + lv + 3.0 * _lg(radius)
    if -LOG_LIMIT <= lm <= LOG_LIMIT:
        return density * 4.0 / 3.0 * math.pi * radius**3
    if name == "density":
        d_lo, d_hi = (_pow10(s * LOG_LIMIT - lv - 3.0 * _lg(radius)) for s in (-1, 1))
        rng = f"at this radius the density must lie in {_fmt_range(d_lo, d_hi, 'kg/m^3')}"
    else:
        r_lo, r_hi = (_pow10((s * LOG_LIMIT - _lg(density) - lv) / 3.0) for s in (-1, 1))
        rng = f"at this density the radius must lie in {_fmt_range(r_lo, r_hi, 'm')}"
    raise ParameterError(name, f"a radius of {radius:g} m and a density of {density:g} kg/m^3 give a sphere mass "
                               f"of 1e{lm:.0f} kg, beyond what can be computed; {rng}")


def check_impact(velocity: float, k_hertz: float, mass: float, partner_mass: float = math.inf, *,
                 radius: float, c: float, rho: float) -> None:
    """Refuse an impact speed whose contact or radiated sound is not representable.

    Parameters
    ----------
    velocity : float
        Impact speed in m/s (> 0, finite).
    k_hertz : float
        Hertz stiffness in N/m^1.5.
    mass, partner_mass : float
        Sphere mass and struck mass in kg (``inf``: an immovable wall).
    radius, c, rho : float
        Sphere radius (m), sound speed (m/s) and fluid density (kg/m³): the radiated pressure
        is of order ``rho a A`` and the formulas need the contact time below 1e100 decay times ``a/c``.

    Raises
    ------
    ParameterError
        Named ``mass`` or ``k_hertz`` when that one alone is at fault (with its bound), else
        ``velocity``, giving the speeds that work with the other settings.
    """
    lo, hi = _impact_speeds(k_hertz, mass, partner_mass, radius, c, rho)
    if lo <= velocity <= hi:
        return
    inputs = (f"a sphere of {radius:g} m and {mass:.4g} kg, K_HZ {k_hertz:.4g} N/m^1.5, sound speed {c:g} m/s "
              f"and fluid density {rho:g} kg/m^3")

    def works(**change):
        kw = {"k_hertz": k_hertz, "mass": mass, **change}
        a, b = _impact_speeds(kw["k_hertz"], kw["mass"], partner_mass, radius, c, rho)
        return a <= velocity <= b

    given = {"mass": mass, "k_hertz": k_hertz}
    fault = _at_fault(works, given, velocity, lo, hi)
    if fault is not None:
        name, bound = fault
        raise ParameterError(name, f"{given[name]:g} {_UNITS[name]} makes the contact at {velocity:g} m/s or its "
                                   f"sound overflow or vanish (with {inputs}); with the other settings it must be "
                                   f"{bound}")
    if lo > hi:
        raise ParameterError("velocity", f"no impact speed gives a finite contact and sound with {inputs}; bring "
                                         "these settings towards ordinary values")
    raise ParameterError("velocity", f"{velocity:g} m/s makes the contact time, compression, peak acceleration or "
                                     f"radiated pressure overflow or vanish; with {inputs} the speed must lie in "
                                     f"{_fmt_range(lo, hi, 'm/s')}")


def _impact_speeds(k_hertz, mass, partner_mass, radius, c, rho) -> tuple:
    """The interval of impact speeds (m/s) whose contact and radiated sound stay finite (maybe empty)."""
    mu = mass if math.isinf(partner_mass) else mass * partner_mass / (mass + partner_mass)
    cons = _contact_constraints(k_hertz, mu, mass)
    q0 = _lg(1.25) + _lg(mu) - _lg(k_hertz)
    L = LOG_LIMIT
    cons.append((_lg(rho) + _lg(radius) + _lg(k_hertz) + 0.6 * q0 - _lg(mass), 1.2, -L, L))  # pressure ~ rho a A
    cons.append((_lg(c / radius) + _lg(HERTZ_DURATION_CONSTANT) + 0.4 * q0, -0.2, -math.inf,
                 MAX_DECAY_TIMES_LOG))  # contact time in decay times
    return _speed_interval(cons)


def check_damper(*, M: float, K: float, m: float, gap: float, k_hertz: float, v: float, duration: float,
                 c1: float = 0.0) -> None:
    """Refuse damper settings whose run cannot be computed or measured (see the module notes).

    Parameters
    ----------
    M, K, m, gap, k_hertz : float
        Main mass (kg), main spring (N/m), impact mass (kg), free travel d (m), Hertz stiffness (N/m^1.5).
    c1 : float
        Contact damping in N s/m: its relaxation time ``mu / c1`` must be at least 1e-4 of the
        contact time at ``|v|`` (a stiffer dashpot cannot be resolved by the solvers).
    v : float
        Initial velocity of the main mass in m/s (the impact mass starts at rest).
    duration : float
        Simulated time in s.

    Raises
    ------
    ParameterError
        Named ``duration`` (shorter than the damping measures need), ``m``, ``gap`` or ``k_hertz``
        when that one alone is at fault (with its bound), else ``v`` (with the range of initial
        speeds that works).
    """
    L = LOG_LIMIT
    lperiod = _lg(2.0 * math.pi) + 0.5 * (_lg(M) - _lg(K))
    if not -L <= lperiod <= L:
        raise ParameterError("M", f"a main mass of {M:g} kg on a spring of {K:g} N/m has a period of "
                                  f"1e{lperiod:.0f} s, beyond what can be computed; bring M/K towards ordinary values")
    period = 10.0**lperiod
    if duration < period / 100.0:
        raise ParameterError("duration", f"{duration:g} s is too short to measure the damping: it must be at least "
                                         f"1/100 of the main period 2 pi sqrt(M/K) = {period:.4g} s, i.e. "
                                         f">= {period / 100.0:.4g} s")
    if m < MIN_MASS_RATIO * M:
        raise ParameterError("m", f"an impact mass of {m:g} kg is lighter than {MIN_MASS_RATIO:g} of the main mass "
                                  f"({M:g} kg), below which the solvers cannot follow its contacts; it must be "
                                  f">= {MIN_MASS_RATIO * M:.3g} kg")
    if M < MIN_MASS_RATIO * m:  # the mirror: a main mass too light to carry the contacts it takes part in
        raise ParameterError("M", f"a main mass of {M:g} kg is lighter than {MIN_MASS_RATIO:g} of the impact mass "
                                  f"({m:g} kg), below which the solvers cannot follow the contacts; it must be "
                                  f">= {MIN_MASS_RATIO * m:.3g} kg")
    if v == 0:
        return
    lo, hi, mu, ltau0 = _damper_speeds(M, m, gap, k_hertz, duration, lperiod)
    speed = abs(v)
    if lo <= speed <= hi:
        tau = _pow10(ltau0 - 0.2 * _lg(speed))
        c1_max = 1e4 * mu / tau
        if c1 > c1_max:
            raise ParameterError("c1", f"{c1:g} N s/m relaxes the contact in {mu / c1:.3g} s, under 1e-4 of its "
                                       f"{tau:.3g} s duration at {speed:g} m/s: the contact is overdamped beyond "
                                       f"what the solvers resolve; with these masses and K_HZ it must be <= "
                                       f"{c1_max:.3g} N s/m")
        return
    inputs = (f"an impact mass of {m:g} kg (main mass {M:g} kg), K_HZ {k_hertz:.4g} N/m^1.5, a free travel of "
              f"{gap:g} m and a run of {duration:g} s")
    why = ("the contact must compress by less than the free travel, last less than a main period "
           f"({period:.4g} s) and more than 1e-12 of the run, and stay finite")
    given = {"m": m, "gap": gap, "k_hertz": k_hertz}

    def works(**change):
        kw = {**given, **change}
        a, b = _damper_speeds(M, kw["m"], kw["gap"], kw["k_hertz"], duration, lperiod)[:2]
        return a <= speed <= b

    fault = _at_fault(works, given, speed, lo, hi)
    if fault is not None:
        name, bound = fault
        raise ParameterError(name, f"{given[name]:g} {_UNITS[name]} leaves no contact that can be computed at "
                                   f"{speed:g} m/s with {inputs} ({why}); with the other settings it must be {bound}")
    if lo > hi:
        raise ParameterError("v", f"no initial speed gives a contact that can be computed with {inputs}: {why}")
    raise ParameterError("v", f"{v:g} m/s is outside the range that can be simulated with {inputs}: the speed "
                              f"(either sign) must lie in {_fmt_range(lo, hi, 'm/s')} ({why})")


def _reduced_mass(m: float, M: float) -> float:
    """``m M / (m + M)`` in kg without overflow or underflow: the smaller mass over ``1 + small / large``.

    >>> _reduced_mass(0.0405, 0.5) == 0.0405 * 0.5 / 0.5405
    True
    >>> _reduced_mass(0.0405, 5e-324) > 0  # the product m M would underflow to 0
    True
    """
    small, large = min(m, M), max(m, M)
    return small / (1.0 + small / large)


def _damper_speeds(M, m, gap, k_hertz, duration, lperiod) -> tuple:
    """``(lo, hi, mu, log10 of the contact time at 1 m/s)``: the initial speeds (m/s) whose contacts can be computed."""
    mu = _reduced_mass(m, M)
    q0 = _lg(1.25) + _lg(mu) - _lg(k_hertz)
    ltau0 = _lg(HERTZ_DURATION_CONSTANT) + 0.4 * q0
    cons = _contact_constraints(k_hertz, mu, m)
    cons += [
        (0.4 * q0, 0.8, -math.inf, _lg(gap)),  # compression within the free travel
        (ltau0, -0.2, _lg(duration) - 12.0, lperiod),  # contact time: resolvable, shorter than a period
    ]
    lo, hi = _speed_interval(cons)
    return lo, hi, mu, ltau0


def check_forcing_frequencies(frequencies, *, M: float, K: float) -> None:
    """Refuse forcing frequencies far from the main system's natural frequency (:data:`FORCING_DECADES`).

    Parameters
    ----------
    frequencies : array_like
        Forcing frequencies in Hz.
    M, K : float
        Main mass (kg) and main spring (N/m).

    Raises
    ------
    ParameterError
        Named ``frequencies``, with the accepted range in Hz and why.
    """
    f0 = math.sqrt(K / M) / (2.0 * math.pi)
    lo, hi = f0 * 10.0**-FORCING_DECADES, f0 * 10.0**FORCING_DECADES
    bad = [float(f) for f in frequencies if not lo <= float(f) <= hi]
    if bad:
        raise ParameterError("frequencies", f"{bad[0]:g} Hz is outside {_fmt_range(lo, hi, 'Hz')}: forcing "
                                            f"frequencies must lie within a factor {10**FORCING_DECADES:g} of the "
                                            f"main system's natural frequency sqrt(K/M)/2 pi = {f0:.4g} Hz (far "
                                            "above it the main mass does not move, far below it follows the "
                                            "force statically: the damper has nothing to act on)")
