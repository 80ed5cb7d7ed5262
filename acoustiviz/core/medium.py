"""The acoustic medium: a frozen value passed explicitly to every radiation function."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .._validate import check_positive, check_range
from ..constants import DEFAULT_AIR_DENSITY, DEFAULT_SOUND_SPEED

__all__ = ["Medium", "AIR", "air_at"]


@dataclass(frozen=True)
class Medium:
    """A lossless fluid at rest.

    Parameters
    ----------
    c : float
        Speed of sound in m/s.
    rho : float
        Density in kg/m³.

    Examples
    --------
    >>> water = Medium(c=1481.0, rho=998.0)
    >>> round(water.impedance)
    1478038
    """

    c: float = DEFAULT_SOUND_SPEED
    rho: float = DEFAULT_AIR_DENSITY

    def __post_init__(self):
        check_positive("c", self.c, "m/s")
        check_positive("rho", self.rho, "kg/m^3")

    @property
    def impedance(self) -> float:
        """Characteristic impedance ρc in Pa·s/m (rayl)."""
        return self.rho * self.c


def air_at(temperature: float = 20.0, pressure: float = 101325.0) -> Medium:
    """Dry air at a given temperature and static pressure (ideal gas).

    Parameters
    ----------
    temperature : float
        Temperature in °C, between -50 and 100.
    pressure : float
        Static pressure in Pa, between 5e4 and 2e5.

    Returns
    -------
    Medium
        ``c = 331.3 sqrt(1 + T/273.15)`` m/s and ``rho = p / (287.05 (T + 273.15))`` kg/m³.

    Notes
    -----
    Speed of sound and density of dry air from the ideal-gas law with
    R_specific = 287.05 J/(kg·K) and γ = 1.4 (Kinsler et al., *Fundamentals of
    Acoustics*, 4th ed., §5.6).

    Examples
    --------
    Sound is faster and air thinner on a hot day; 20 °C gives the default :data:`AIR`:

    >>> for t in (0.0, 20.0, 35.0):
    ...     air = air_at(t)
    ...     print(f"{t:4.0f} °C  c = {air.c:.1f} m/s  rho = {air.rho:.3f} kg/m³")
       0 °C  c = 331.3 m/s  rho = 1.292 kg/m³
      20 °C  c = 343.2 m/s  rho = 1.204 kg/m³
      35 °C  c = 351.9 m/s  rho = 1.146 kg/m³
    """
    t = check_range("temperature", temperature, -50.0, 100.0, unit="degC")
    p = check_range("pressure", pressure, 5e4, 2e5, unit="Pa")
    kelvin = t + 273.15
    return Medium(c=331.3 * math.sqrt(kelvin / 273.15), rho=p / (287.05 * kelvin))


#: Dry air at 20 °C and 101.325 kPa: c = 343.2 m/s, rho = 1.204 kg/m³.
AIR = Medium(c=DEFAULT_SOUND_SPEED, rho=DEFAULT_AIR_DENSITY)
