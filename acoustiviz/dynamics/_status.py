"""Codes and column layouts shared by the compiled impact-damper kernels."""

#: Columns of the impact array filled by the kernels.
IMPACT_COLUMNS = ("time", "wall", "approach", "separation", "duration", "peak_force", "impulse", "energy_lost")
#: Columns of the dense-output array filled by the kernels.
DENSE_COLUMNS = ("x", "v", "y", "w", "dissipated_C", "dissipated_contact")

STATUS_OK = 0
STATUS_MAX_IMPACTS = 1
STATUS_STEP_UNDERFLOW = 2
STATUS_DIVERGED = 3
