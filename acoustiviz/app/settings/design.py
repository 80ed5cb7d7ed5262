"""Settings of a design choice: ``acoustiviz design`` and a scene's ``[outputs.design_table]``."""

from __future__ import annotations

import dataclasses

from ...constants import MAX_INCLINATION
from .base import Settings
from .table import Setting

__all__ = ["DESIGN", "DesignSettings", "DEFAULT_TOLERANCE"]

#: Half-width in m/s of the inclination band around a target: half the paper's 0.1 cm/s bands of Table 2.
DEFAULT_TOLERANCE = 0.0005

DESIGN = (
    Setting("inclination", "--inclination", "inclination_m_s", "float", None, "target damping inclination",
            "m/s", low=0.0, high=MAX_INCLINATION, low_open=True, table="outputs.design_table"),
    Setting("tolerance", "--tolerance", "tolerance_m_s", "float", DEFAULT_TOLERANCE,
            "accepted deviation from the target: the half-width of the inclination band", "m/s", low=0.0,
            high=MAX_INCLINATION, low_open=True, table="outputs.design_table"),
)


@dataclasses.dataclass(frozen=True)
class DesignSettings(Settings):
    """The target damping inclination and the band around it in which designs are compared."""

    TABLE = DESIGN
    inclination: float | None = None
    tolerance: float = DEFAULT_TOLERANCE
