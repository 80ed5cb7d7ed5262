"""The two-degree-of-freedom impact damper of the paper (eq 15, Table 1, Figure 4).

A main mass ``M`` on a spring ``K`` and a dashpot ``C`` carries a cavity in which an impact mass
``m`` moves freely. ``x`` is the displacement of the main mass and ``y`` that of the impact mass
(both in m, from the rest position of the main mass with the impact mass centred), ``z = y - x``.
The gap ``d`` is the total free travel: the impact mass touches a wall when ``|z| = d/2``.

Walls
-----
Wall ``+1`` is struck when ``z = y - x`` reaches ``+d/2`` (the impact mass moving in ``+x``
relative to the main mass); wall ``-1`` when ``z`` reaches ``-d/2``.

Contact
-------
With the wall ``s = ±1`` and the penetration ``δ = s z - d/2 > 0`` the contact force, pushing the
bodies apart, is ``F = K_HZ δ^{3/2} + c1 dδ/dt`` (paper eq 15). The main mass receives ``+s F``
and the impact mass ``-s F``. As written in the paper, ``F`` may turn tensile as the contact ends
(the damping term pulls); ``clip_tensile=True`` clips it at zero.

All quantities are SI: kg, N/m, N·s/m, N/m^1.5, m, m/s, s, J.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .._validate import ParameterError, check_finite, check_nonnegative, check_positive
from ..constants import PAPER_GAP, TABLE1_PARAMETERS
from ..core.contact import contact_duration, effective_mass, max_approach

__all__ = ["DamperModel", "InitialState", "TABLE1"]


@dataclass(frozen=True)
class DamperModel:
    """Parameters of the impact damper (paper eq 15); defaults are the paper's Table 1.

    Parameters
    ----------
    M : float
        Main mass in kg (Table 1: 0.5 kg).
    K : float
        Main spring stiffness in N/m (500 N/m).
    C : float
        Main dashpot in N·s/m (0.05 N·s/m).
    m : float
        Impact mass in kg (40.5 g).
    gap : float
        Total free travel d of the impact mass in the cavity, in m (Figure 5: 4 cm).
    k_hertz : float
        Hertz contact stiffness K_HZ in N/m^1.5 (5.6e8 N/m^1.5).
    c1 : float
        Linear contact damping in N·s/m (20 N·s/m).
    clip_tensile : bool
        Clip the contact force at zero (False, the paper's form, lets it pull as contact ends).

    Examples
    --------
    >>> DamperModel().main_frequency  # rad/s
    31.6227...
    """

    M: float = TABLE1_PARAMETERS["M"]
    K: float = TABLE1_PARAMETERS["K"]
    C: float = TABLE1_PARAMETERS["C"]
    m: float = TABLE1_PARAMETERS["m"]
    gap: float = PAPER_GAP
    k_hertz: float = TABLE1_PARAMETERS["k_hertz"]
    c1: float = TABLE1_PARAMETERS["c1"]
    clip_tensile: bool = False

    def __post_init__(self):
        check_positive("M", self.M, "kg")
        check_positive("K", self.K, "N/m")
        check_nonnegative("C", self.C, "N s/m")
        check_positive("m", self.m, "kg")
        check_positive("gap", self.gap, "m")
        check_positive("k_hertz", self.k_hertz, "N/m^1.5")
        check_nonnegative("c1", self.c1, "N s/m")
        if not isinstance(self.clip_tensile, bool):
            raise ParameterError("clip_tensile", f"must be True or False, got {self.clip_tensile!r}")

    # ------------------------------------------------------------------ derived quantities
    @property
    def effective_mass(self) -> float:
        """Effective mass m M / (m + M) of a contact, in kg."""
        return float(effective_mass(self.m, self.M))

    @property
    def main_frequency(self) -> float:
        """Undamped natural angular frequency sqrt(K/M) of the main mass in rad/s."""
        return math.sqrt(self.K / self.M)

    @property
    def main_damping_ratio(self) -> float:
        """Damping ratio C / (2 sqrt(K M)) of the main oscillator (dimensionless)."""
        return self.C / (2.0 * math.sqrt(self.K * self.M))

    @property
    def underdamped(self) -> bool:
        """True when the main oscillator is underdamped (needed by the closed-form solvers)."""
        return self.main_damping_ratio < 1.0

    def contact_duration(self, velocity: float) -> float:
        """Undamped Hertz contact duration in s at relative approach speed ``velocity`` in m/s."""
        return float(contact_duration(velocity, self.k_hertz, self.effective_mass))

    def max_approach(self, velocity: float) -> float:
        """Undamped Hertz maximum penetration in m at relative approach speed ``velocity`` in m/s."""
        return float(max_approach(velocity, self.k_hertz, self.effective_mass))

    def contact_frequency(self, velocity: float) -> float:
        """Highest linearised contact angular frequency in rad/s at approach speed ``velocity``.

        ``sqrt(1.5 K_HZ α_max^{1/2} / m_eff)``: the tangent stiffness at the deepest penetration over
        the effective mass. An explicit scheme (central difference) is stable only for steps below
        ``2 / contact_frequency``.
        """
        kt = 1.5 * self.k_hertz * math.sqrt(self.max_approach(velocity))
        return math.sqrt(kt / self.effective_mass)

    def energy(self, x, v, y, w):
        """Mechanical energy in J: kinetic + spring + Hertz (``2/5 K_HZ δ^{5/2}``).

        Parameters
        ----------
        x, v : float or ndarray
            Main-mass displacement in m and velocity in m/s.
        y, w : float or ndarray
            Impact-mass displacement in m and velocity in m/s.
        """
        import numpy as np

        delta = np.maximum(np.abs(np.asarray(y) - np.asarray(x)) - 0.5 * self.gap, 0.0)
        return (
            0.5 * self.M * np.asarray(v) ** 2
            + 0.5 * self.m * np.asarray(w) ** 2
            + 0.5 * self.K * np.asarray(x) ** 2
            + 0.4 * self.k_hertz * delta**2.5
        )


#: The paper's Table 1 damper with the Figure 5 gap (4 cm).
TABLE1 = DamperModel()


@dataclass(frozen=True)
class InitialState:
    """Initial displacements in m and velocities in m/s.

    The default is the paper's Figure 5 start: ``x(0) = 0``, ``dx/dt(0) = 2 m/s``, the impact mass
    centred in the cavity (``y(0) = x(0)``) and at rest (``dy/dt(0) = 0``, an absolute velocity).

    Parameters
    ----------
    x : float
        Main-mass displacement in m.
    v : float
        Main-mass velocity in m/s.
    y : float or None
        Impact-mass displacement in m; None centres it (``y = x``).
    w : float
        Impact-mass velocity in m/s.

    Examples
    --------
    The paper's start on its Table 1 damper (gap 40 mm): the main mass closes the 20 mm half-gap
    at nearly 2 m/s and strikes after about 10 ms. Started at 0.5 m/s it swings only
    ``0.5 / sqrt(K/M)`` = 15.8 mm and never strikes:

    >>> from acoustiviz.dynamics import DamperModel, simulate
    >>> model = DamperModel()
    >>> InitialState().as_tuple(model)  # x, v, y, w in m and m/s
    (0.0, 2.0, 0.0, 0.0)
    >>> round(float(simulate(model, 0.5).impacts.time[0]) * 1e3, 2)  # ms
    10.18
    >>> len(simulate(model, 0.5, initial=InitialState(v=0.5)).impacts)
    0
    """

    x: float = 0.0
    v: float = 2.0
    y: float | None = None
    w: float = 0.0

    def __post_init__(self):
        check_finite("x", self.x)
        check_finite("v", self.v)
        if self.y is not None:
            check_finite("y", self.y)
        check_finite("w", self.w)

    def as_tuple(self, model: DamperModel) -> tuple[float, float, float, float]:
        """Return ``(x, v, y, w)`` in m and m/s, checking the impact mass starts inside the cavity."""
        y = self.x if self.y is None else float(self.y)
        if abs(y - self.x) > 0.5 * model.gap:
            raise ParameterError(
                "initial.y",
                f"the impact mass must start inside the cavity, |y - x| <= gap/2 = {0.5 * model.gap:g} m,"
                f" got {abs(y - self.x):g} m",
            )
        return float(self.x), float(self.v), y, float(self.w)

    def max_relative_speed(self, model: DamperModel) -> float:
        """Upper bound in m/s of any relative approach speed, from the initial energy.

        The relative kinetic energy ``m_eff u² / 2`` cannot exceed the initial mechanical energy.
        """
        x, v, y, w = self.as_tuple(model)
        e0 = float(model.energy(x, v, y, w))
        return max(math.sqrt(2.0 * e0 / model.effective_mass), abs(w - v), 1e-12)
