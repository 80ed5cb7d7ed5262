"""Tables of physics results written as CSV files (atomically, see :mod:`acoustiviz.files`).

The physics layers return arrays and small dataclasses; this module decides how they look on disk.

Examples
--------
>>> import tempfile, pathlib
>>> from acoustiviz.dynamics import simulate
>>> run = simulate(duration=0.5)
>>> with tempfile.TemporaryDirectory() as folder:
...     path = write_impact_table(pathlib.Path(folder) / "impacts.csv", run.impacts)
...     header = path.read_text().splitlines()[0]
>>> header == ",".join(IMPACT_COLUMNS)
True
"""

from __future__ import annotations

import math
from pathlib import Path

from ..files import write_csv_atomic

__all__ = ["IMPACT_COLUMNS", "EXTRA_IMPACT_COLUMNS", "BALL_IMPACT_COLUMNS", "write_impact_table",
           "write_ball_impact_table", "csv_number"]

#: Columns of an impact table file, in order (``acoustiviz damper --impacts-csv`` promises these):
#: contact start time (s), wall struck (+1 or -1), approach and separation speeds (m/s),
#: restitution (dimensionless), contact duration (s) and peak contact force (N).
IMPACT_COLUMNS = (
    "time_s",
    "wall",
    "approach_velocity_m_s",
    "separation_velocity_m_s",
    "restitution",
    "duration_s",
    "peak_force_n",
)
#: Further columns written with ``extra=True``: contact impulse (N s) and energy lost (J).
EXTRA_IMPACT_COLUMNS = ("impulse_n_s", "energy_lost_j")

# ImpactTable attribute of each column
_FIELDS = {
    "time_s": "time",
    "wall": "wall",
    "approach_velocity_m_s": "approach_velocity",
    "separation_velocity_m_s": "separation_velocity",
    "restitution": "restitution",
    "duration_s": "duration",
    "peak_force_n": "peak_force",
    "impulse_n_s": "impulse",
    "energy_lost_j": "energy_lost",
}


def write_impact_table(path, impacts, *, extra: bool = False) -> Path:
    """Write an impact table (one row per contact) as CSV atomically; return the path.

    Parameters
    ----------
    path : path-like
        Output file.
    impacts : acoustiviz.dynamics.ImpactTable
        The contacts of a damper run (``SimulationResult.impacts``).
    extra : bool
        Also write :data:`EXTRA_IMPACT_COLUMNS`.

    Returns
    -------
    pathlib.Path
        Columns :data:`IMPACT_COLUMNS` (then :data:`EXTRA_IMPACT_COLUMNS`), values to 17
        significant digits (the wall as an integer).

    Examples
    --------
    The first contact of the paper's Table 1 damper (started at 2 m/s): the impact mass strikes
    the wall at -gap/2 at 1.9 m/s and rebounds with e = 0.93 after a 0.24 ms contact:

    >>> import csv, tempfile
    >>> from acoustiviz.dynamics import simulate
    >>> run = simulate(duration=0.5)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = write_impact_table(Path(folder) / "impacts.csv", run.impacts)
    ...     with path.open(newline="") as f:
    ...         rows = list(csv.DictReader(f))
    >>> first = rows[0]
    >>> first["wall"], round(float(first["approach_velocity_m_s"]), 4), round(float(first["restitution"]), 4)
    ('-1', 1.8953, 0.9306)
    >>> round(float(first["duration_s"]) * 1e3, 4)  # ms
    0.2428
    """
    header = IMPACT_COLUMNS + (EXTRA_IMPACT_COLUMNS if extra else ())
    cols = [getattr(impacts, _FIELDS[name]) for name in header]
    fmt = ["%.17g", "%d"] + ["%.17g"] * (len(header) - 2)
    return write_csv_atomic(path, header, cols, fmt=fmt)


#: Columns of a multi-ball impact table file (``acoustiviz damper --balls N --impacts-csv``): the start time
#: (s), the two bodies in axis order (``wall-``, ``ball1`` ... ``ballN``, ``wall+``; ``c2:ball1`` with several
#: cavities), the pair's approach and separation speeds (m/s), restitution, duration (s), peak force (N),
#: impulse (N s) and the work of the dissipative force (J).
BALL_IMPACT_COLUMNS = ("time_s", "first", "second", "approach_velocity_m_s", "separation_velocity_m_s",
                       "restitution", "duration_s", "peak_force_n", "impulse_n_s", "energy_lost_j")


def write_ball_impact_table(path, impacts) -> Path:
    """Write a multi-ball impact table (one row per collision) as CSV atomically; return the path.

    Parameters
    ----------
    path : path-like
        Output file.
    impacts : acoustiviz.dynamics.BallImpactTable
        The collisions of a multi-ball run.

    Returns
    -------
    pathlib.Path
        Columns :data:`BALL_IMPACT_COLUMNS`, numbers to 17 significant digits (``nan`` for a contact
        still under way at the end of the run, as in :func:`write_impact_table`).
    """
    from ..files import write_text_atomic

    nums = ("approach_velocity", "separation_velocity", "restitution", "duration", "peak_force", "impulse",
            "energy_lost")
    lines = [",".join(BALL_IMPACT_COLUMNS)]
    cols = [getattr(impacts, n) for n in nums]
    for i in range(len(impacts)):
        cells = [f"{impacts.time[i]:.17g}", str(impacts.first[i]), str(impacts.second[i])]
        lines.append(",".join(cells + [f"{c[i]:.17g}" for c in cols]))
    return write_text_atomic(path, "\n".join(lines) + "\n")


def csv_number(value, spec: str) -> str:
    """A number as a cell of the CSV files: ``format(value, spec)``, ``inf``/``-inf``, or empty for NaN.

    The one rule of every CSV file: an infinite level is written out (``-inf``, the level of
    silence, which numpy and pandas read back as a float), a value that was not computed (NaN)
    is an empty cell.

    Examples
    --------
    >>> [csv_number(v, ".4f") for v in (93.97940008, float("-inf"), float("nan"))]
    ['93.9794', '-inf', '']
    """
    v = float(value)
    if math.isnan(v):
        return ""
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return format(v, spec)

