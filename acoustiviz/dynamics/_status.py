"""Codes, layouts and messages shared by the compiled impact-damper kernels."""

import numpy as np

#: Entries of the kernels' parameter vector ``p`` (SI; ``clip`` 1.0 or 0.0).
PARAM_COLUMNS = ("M", "K", "C", "m", "half_gap", "k_hertz", "c1", "clip")

#: Columns of the impact array filled by the kernels.
IMPACT_COLUMNS = ("time", "wall", "approach", "separation", "duration", "peak_force", "impulse", "energy_lost")
#: Columns of the dense-output array filled by the kernels.
DENSE_COLUMNS = ("x", "v", "y", "w", "dissipated_C", "dissipated_contact")

STATUS_OK = 0
STATUS_MAX_IMPACTS = 1
STATUS_STEP_UNDERFLOW = 2
STATUS_DIVERGED = 3

#: The impact limit of a free-decay run (:func:`acoustiviz.dynamics.simulate`).
LIMIT_RUN = "max_impacts reached (chattering?); raise max_impacts"
#: The impact limit of a forced run (per forcing cycle).
LIMIT_CYCLE = "too many impacts in one cycle (chattering?)"

_MESSAGES = {
    STATUS_OK: "completed",
    STATUS_STEP_UNDERFLOW: "stopped: contact step size underflow",
    STATUS_DIVERGED: "stopped: the solution diverged",
}


def status_message(status: int, limit: str = LIMIT_RUN) -> str:
    """What a kernel status means; ``limit`` says which impact limit ``STATUS_MAX_IMPACTS`` hit."""
    if status == STATUS_MAX_IMPACTS:
        return "stopped: " + limit
    return _MESSAGES.get(status, f"status {status}")


def kernel_params(model) -> np.ndarray:
    """The parameter vector ``p`` (``PARAM_COLUMNS``) of a :class:`~acoustiviz.dynamics.DamperModel`.

    Masses in kg, K in N/m, C and c1 in N s/m, half the gap in m, k_hertz in N/m^1.5.
    """
    return np.array([model.M, model.K, model.C, model.m, 0.5 * model.gap, model.k_hertz, model.c1,
                     1.0 if model.clip_tensile else 0.0])
