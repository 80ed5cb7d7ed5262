"""Hertz contact of a sphere with a plane or a second body (paper eqs 1-4).

The approach α of the two bodies obeys ``m_eff α'' = -K α^{3/2} - c1 α'``
(paper eqs 1 and 15), with ``m_eff = m M / (m + M)`` and ``K`` the Hertz
stiffness (eq 2). Without damping the solution scales onto one universal curve:
with ``α = α_max s`` and ``t = (α_max / U0) θ`` it reads ``s'' = -(5/4) s^{3/2}``,
``s(0) = 0``, ``s'(0) = 1``, whose inverse ``θ(s)`` is an incomplete beta
function. The exact Hertz pulse is therefore evaluated in closed form with
:func:`scipy.special.betaincinv` rather than integrated per call.

All quantities are SI: m, s, kg, N, m/s, m/s², N/m^1.5, N·s/m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_nonnegative, check_positive
from ..constants import HERTZ_DURATION_CONSTANT, PAPER_DURATION_CONSTANT
from .materials import Material, reduced_modulus
from .pulses import PULSE_KINDS, HalfSinePulse, HertzPulse, SampledPulse, acceleration_pulse, hertz_pulse_shape

__all__ = [
    "HERTZ_DURATION_CONSTANT",
    "PAPER_DURATION_CONSTANT",
    "PULSE_KINDS",
    "Impact",
    "HalfSinePulse",
    "SampledPulse",
    "HertzPulse",
    "DampedContact",
    "hertz_stiffness",
    "sphere_pair_stiffness",
    "effective_mass",
    "max_approach",
    "contact_duration",
    "peak_force",
    "peak_acceleration",
    "acceleration_pulse",
    "hertz_pulse_shape",
    "damped_contact",
    "restitution",
]

def hertz_stiffness(radius: float, sphere: Material, surface: Material) -> float:
    """Hertz contact stiffness of a sphere on a flat surface (paper eq 2).

    Parameters
    ----------
    radius : float
        Sphere radius a in m.
    sphere, surface : Material
        Elastic constants of the sphere and of the surface (half-space).

    Returns
    -------
    float
        ``K_HZ = (4/3) sqrt(a) E*`` in N/m^1.5, with E* the reduced modulus.

    Notes
    -----
    Paper eq 2 (Akay and Hodgson, 1978); Johnson, *Contact Mechanics* (1985), eq 4.23.

    Examples
    --------
    >>> from acoustiviz.core.materials import material
    >>> k = hertz_stiffness(0.01, material("steel"), material("steel"))
    >>> f"{k:.3g}"
    '1.54e+10'
    """
    a = check_positive("radius", radius, "m")
    return 4.0 / 3.0 * math.sqrt(a) * reduced_modulus(sphere, surface)


def sphere_pair_stiffness(radius_a: float, radius_b: float, material_a: Material, material_b: Material) -> float:
    """Hertz contact stiffness of two spheres touching (paper eq 2 with both radii).

    Parameters
    ----------
    radius_a, radius_b : float
        The two radii in m.
    material_a, material_b : Material
        Elastic constants of the two spheres.

    Returns
    -------
    float
        ``K_HZ = (4/3) sqrt(R) E*`` in N/m^1.5 with the relative radius ``R = a b / (a + b)``
        (a sphere on a plane, ``b`` -> infinity, gives :func:`hertz_stiffness`).

    Notes
    -----
    Johnson, *Contact Mechanics* (1985), eqs 4.22-4.23: two spheres make the contact of one sphere
    of radius R on a plane.

    Examples
    --------
    >>> from acoustiviz.core.materials import material
    >>> steel = material("steel")
    >>> f"{sphere_pair_stiffness(0.01, 0.01, steel, steel) / hertz_stiffness(0.01, steel, steel):.4f}"
    '0.7071'
    """
    a = check_positive("radius_a", radius_a, "m")
    b = check_positive("radius_b", radius_b, "m")
    return hertz_stiffness(a * b / (a + b), material_a, material_b)


def effective_mass(mass, partner_mass=math.inf):
    """Effective mass ``m M / (m + M)`` in kg of two free bodies (``M = inf``: a fixed wall)."""
    m = np.asarray(mass, dtype=float)
    mp = np.asarray(partner_mass, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(np.isinf(mp), m, m * mp / (m + mp))
    return out[()] if out.ndim == 0 else out


def max_approach(velocity, k_hertz, mass):
    """Maximum approach ``α_max = (5 m U0² / (4 K))^{2/5}`` in m.

    Parameters
    ----------
    velocity : float or array_like
        Approach speed U0 in m/s.
    k_hertz : float
        Hertz stiffness in N/m^1.5.
    mass : float
        Effective mass in kg (the sphere mass for a fixed wall).

    Returns
    -------
    float or ndarray
        α_max in m, shaped like ``velocity``.

    Examples
    --------
    The paper's Figure 2 sphere (radius 19.05 mm, steel of 7800 kg/m³: 0.2259 kg) striking at
    1.4 m/s with K = 5.6e8 N/m^1.5 squeezes the contact by a quarter of a millimetre:

    >>> mass = 7800.0 * 4.0 / 3.0 * math.pi * 0.01905**3
    >>> round(float(max_approach(1.4, 5.6e8, mass)) * 1e3, 4)  # mm
    0.25
    """
    u = np.asarray(velocity, dtype=float)
    return (5.0 * mass * u**2 / (4.0 * k_hertz)) ** 0.4


def contact_duration(velocity, k_hertz, mass):
    """Hertz contact duration ``τ = 2.943275 α_max / U0`` in s.

    The constant is (4/5)·B(2/5, 1/2) (:data:`HERTZ_DURATION_CONSTANT`); the paper rounds it to 2.9432.
    Arguments as in :func:`max_approach`.

    Examples
    --------
    The paper's Figure 2 impact (19.05 mm radius steel sphere, 1.4 m/s, K = 5.6e8 N/m^1.5) lasts
    about half a millisecond; the duration falls as ``U0^(-1/5)``, so a faster impact is shorter:

    >>> mass = 7800.0 * 4.0 / 3.0 * math.pi * 0.01905**3
    >>> tau = contact_duration(np.array([0.5, 1.4, 5.0]), 5.6e8, mass)
    >>> np.round(tau * 1e6, 1)  # µs
    array([645.8, 525.6, 407.4])
    >>> round(float(tau[0] / tau[2]), 4), round(10.0**0.2, 4)  # (5.0/0.5)^(1/5)
    (1.5849, 1.5849)
    """
    u = np.asarray(velocity, dtype=float)
    return HERTZ_DURATION_CONSTANT * max_approach(u, k_hertz, mass) / u


def peak_force(velocity, k_hertz, mass):
    """Peak Hertz force ``K α_max^{3/2}`` in N. Arguments as in :func:`max_approach`."""
    return k_hertz * max_approach(velocity, k_hertz, mass) ** 1.5


def peak_acceleration(velocity, k_hertz, mass, partner_mass=math.inf):
    """Peak acceleration of the sphere in m/s² (paper eq 3).

    Parameters
    ----------
    velocity : float or array_like
        Approach speed U0 in m/s.
    k_hertz : float
        Hertz stiffness in N/m^1.5.
    mass : float
        Sphere mass m in kg.
    partner_mass : float, optional
        Mass of the struck body in kg; ``inf`` (default) is a fixed wall, as in the paper.

    Notes
    -----
    ``A_max = (K/m) (5 U0² / (4 K* K))^{3/5}`` with ``K* = 1/m_eff`` (paper eq 3, where
    ``m_eff = m``), i.e. the peak force divided by the sphere's own mass.

    Examples
    --------
    The paper's Figure 2 sphere (0.2259 kg) at 1.4 m/s on a fixed wall peaks near 1000 g; on a
    free body of its own mass the contact is softer (``m_eff = m/2``) and the peak lower:

    >>> mass = 7800.0 * 4.0 / 3.0 * math.pi * 0.01905**3
    >>> round(float(peak_acceleration(1.4, 5.6e8, mass)))  # m/s²
    9800
    >>> round(float(peak_acceleration(1.4, 5.6e8, mass, partner_mass=mass)))
    6466
    """
    meff = effective_mass(mass, partner_mass)
    return peak_force(velocity, k_hertz, meff) / mass


@dataclass(frozen=True)
class Impact:
    """One collision of a sphere with a surface or a second body.

    Parameters
    ----------
    velocity : float
        Approach speed U0 in m/s (> 0).
    k_hertz : float
        Hertz stiffness K_HZ in N/m^1.5 (> 0).
    mass : float
        Sphere mass m in kg (> 0).
    partner_mass : float, optional
        Mass of the struck body in kg; ``inf`` (default) is a fixed wall.
    damping : float, optional
        Linear contact damping c1 in N·s/m (paper eq 15); 0 is the elastic Hertz impact.
    clip_tensile : bool, optional
        If True the contact force is clipped at zero (no pull as the bodies part);
        the paper's form (False) lets the damping force turn tensile.

    Examples
    --------
    The paper's Figure 2 impact: a 19.05 mm radius steel sphere (0.2259 kg) at 1.4 m/s on a
    fixed wall, K = 5.6e8 N/m^1.5. The undamped contact returns twice the momentum:

    >>> imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800.0 * 4.0 / 3.0 * math.pi * 0.01905**3)
    >>> round(imp.duration * 1e6, 1), round(imp.peak_force), round(imp.impulse, 4)  # µs, N, N·s
    (525.6, 2214, 0.6324)
    >>> round(imp.impulse / (2.0 * imp.mass * imp.velocity), 12)
    1.0
    """

    velocity: float
    k_hertz: float
    mass: float
    partner_mass: float = math.inf
    damping: float = 0.0
    clip_tensile: bool = False

    def __post_init__(self):
        check_positive("velocity", self.velocity, "m/s")
        check_positive("k_hertz", self.k_hertz, "N/m^1.5")
        check_positive("mass", self.mass, "kg")
        if not (self.partner_mass > 0):
            raise ParameterError("partner_mass", f"must be > 0 kg or inf, got {self.partner_mass}")
        check_nonnegative("damping", self.damping, "N s/m")

    @property
    def effective_mass(self) -> float:
        """Effective mass m M/(m + M) in kg."""
        return float(effective_mass(self.mass, self.partner_mass))

    @property
    def max_approach(self) -> float:
        """Maximum approach α_max in m (undamped Hertz)."""
        return float(max_approach(self.velocity, self.k_hertz, self.effective_mass))

    @property
    def duration(self) -> float:
        """Contact duration τ in s (undamped Hertz)."""
        return float(contact_duration(self.velocity, self.k_hertz, self.effective_mass))

    @property
    def peak_force(self) -> float:
        """Peak contact force in N (undamped Hertz)."""
        return float(peak_force(self.velocity, self.k_hertz, self.effective_mass))

    @property
    def peak_acceleration(self) -> float:
        """Peak acceleration of the sphere in m/s² (paper eq 3)."""
        return self.peak_force / self.mass

    @property
    def impulse(self) -> float:
        """Impulse of the undamped contact force, 2 m_eff U0, in N·s."""
        return 2.0 * self.effective_mass * self.velocity

    @property
    def damping_ratio(self) -> float:
        """Dimensionless contact damping ζ = c1 α_max / (m_eff U0) that alone sets the restitution."""
        return self.damping * self.max_approach / (self.effective_mass * self.velocity)


# --------------------------------------------------------------------------- damping
@dataclass(frozen=True)
class DampedContact:
    """Time history of one damped Hertz contact (see :func:`damped_contact`).

    Attributes
    ----------
    time : ndarray
        Times in s from first touch.
    approach, approach_rate : ndarray
        α in m and dα/dt in m/s.
    force : ndarray
        Contact force in N (positive pushes the bodies apart).
    restitution : float
        Separation speed / approach speed.
    duration : float
        Contact duration in s.
    peak_force : float
        Largest contact force in N (the maximum of the dense solution, not of the samples).
    clip_tensile : bool
        Whether the force was clipped at zero.
    """

    time: np.ndarray
    approach: np.ndarray
    approach_rate: np.ndarray
    force: np.ndarray
    restitution: float
    duration: float
    peak_force: float
    clip_tensile: bool


def _damped_contact_dimensionless(zeta: float, clip: bool, dense: bool, rtol: float = 1e-11):
    """Solve s'' + ζ s' + (5/4) s^{3/2} = 0, s(0)=0, s'(0)=1 until the contact ends."""
    from scipy.integrate import solve_ivp

    k = 0.8 * zeta  # damping force / Hertz peak force, per unit s'

    def rhs(_t, y):
        s, v = y
        return (v, -zeta * v - 1.25 * max(s, 0.0) ** 1.5)

    def ended(_t, y):
        s, v = y
        if clip:
            return max(s, 0.0) ** 1.5 + k * v  # force crosses zero
        return s

    ended.terminal = True
    ended.direction = -1
    # the force is positive at t=0+ when clipping (k*1 > 0); start the event check just after 0
    sol = solve_ivp(
        rhs,
        (0.0, 1e4),
        (0.0, 1.0),
        method="DOP853",
        rtol=rtol,
        atol=1e-14,
        events=ended,
        dense_output=dense,
        first_step=1e-6,
    )
    if sol.status != 1:
        return sol, math.nan, 0.0
    te = float(sol.t_events[0][0])
    ve = float(sol.y_events[0][0][1])
    return sol, te, max(-ve, 0.0)


def damped_contact(impact: Impact, *, n_output: int = 513) -> DampedContact:
    """Integrate one contact with Hertz stiffness and linear damping (paper eq 15).

    ``m_eff α'' + c1 α' + K α^{3/2} = 0`` from ``α(0) = 0, α'(0) = U0`` until α returns to zero
    (or, with ``impact.clip_tensile``, until the force ``K α^{3/2} + c1 α'`` falls to zero).

    Parameters
    ----------
    impact : Impact
        The collision, including its ``damping`` c1 and ``clip_tensile`` choice.
    n_output : int, optional
        Number of output samples over the contact.

    Returns
    -------
    DampedContact
    """
    from scipy.optimize import minimize_scalar

    zeta = impact.damping_ratio
    sol, te, ve = _damped_contact_dimensionless(zeta, impact.clip_tensile, dense=True)
    if not math.isfinite(te):
        raise RuntimeError(f"contact did not end within 1e4 time units (damping ratio {zeta:g})")
    am, u0 = impact.max_approach, impact.velocity
    tscale = am / u0
    th = np.linspace(0.0, te, int(n_output))
    s, v = sol.sol(th)
    alpha = am * s
    rate = u0 * v
    force = impact.k_hertz * np.maximum(alpha, 0.0) ** 1.5 + impact.damping * rate
    if impact.clip_tensile:
        force = np.maximum(force, 0.0)
    k, fh, fd = int(np.argmax(force)), impact.k_hertz * am**1.5, impact.damping * u0  # refine the peak:
    pk = minimize_scalar(lambda t: -(fh * max(float(sol.sol(t)[0]), 0.0) ** 1.5 + fd * float(sol.sol(t)[1])),
                         bounds=(th[max(k - 1, 0)], th[min(k + 1, th.size - 1)]), options={"xatol": 1e-14})
    return DampedContact(
        time=th * tscale,
        approach=alpha,
        approach_rate=rate,
        force=force,
        restitution=ve,
        duration=te * tscale,
        peak_force=max(float(force[k]), -float(pk.fun)),
        clip_tensile=impact.clip_tensile,
    )


def restitution(velocity, k_hertz, mass, partner_mass=math.inf, damping=0.0, clip_tensile=False):
    """Coefficient of restitution of a damped Hertz contact (paper eq 15).

    Parameters
    ----------
    velocity : float or array_like
        Approach speed U0 in m/s (> 0).
    k_hertz : float
        Hertz stiffness in N/m^1.5.
    mass : float
        Sphere (impact) mass m in kg.
    partner_mass : float, optional
        Mass of the struck body M in kg (``inf``: a fixed wall).
    damping : float, optional
        Linear contact damping c1 in N·s/m.
    clip_tensile : bool, optional
        Clip the contact force at zero (contact ends when it vanishes).

    Returns
    -------
    float or ndarray
        Separation speed / approach speed, shaped like ``velocity``.

    Notes
    -----
    Scaling α by α_max and t by α_max/U0 leaves one parameter, ζ = c1 α_max / (m_eff U0), so
    e depends on U0, m, M, K and c1 only through ζ. With the paper's linear damping ζ falls as
    U0^{-1/5} m_eff^{-3/5}, so the restitution *rises* with impact velocity and with mass.

    Examples
    --------
    Without damping the Hertz contact is elastic; the paper's Table 1 impact mass (0.0405 kg,
    c1 = 20 N·s/m) rebounds with e ≈ 0.91-0.93, higher the faster it strikes (paper Figure 7):

    >>> float(restitution(1.4, 5.6e8, 0.0405))
    1.0
    >>> np.round(restitution([0.5, 2.0], 5.6e8, 0.0405, damping=20.0), 4)
    array([0.914 , 0.9343])
    """
    u = np.atleast_1d(np.asarray(velocity, dtype=float))
    if np.any(~(u > 0)) or not np.all(np.isfinite(u)):
        raise ParameterError("velocity", "approach speeds must be finite and > 0 m/s")
    check_positive("k_hertz", k_hertz, "N/m^1.5")
    check_positive("mass", mass, "kg")
    c1 = check_nonnegative("damping", damping, "N s/m")
    meff = float(effective_mass(mass, partner_mass))
    am = max_approach(u, k_hertz, meff)
    zetas = c1 * am / (meff * u)
    out = np.empty_like(u)
    for i, z in enumerate(zetas):
        if z == 0.0:
            out[i] = 1.0
            continue
        _, _, ve = _damped_contact_dimensionless(float(z), bool(clip_tensile), dense=False)
        out[i] = ve
    return out[0] if np.ndim(velocity) == 0 else out.reshape(np.shape(velocity))
