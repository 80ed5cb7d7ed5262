"""Design sweeps of the impact damper and the acoustic-versus-vibration design table.

The paper's design rule (its Figure 6 and Table 2): among impact dampers that suppress the
vibration equally well -- the same damping inclination -- choose the quietest. This package runs
the damper (:mod:`acoustiviz.dynamics`) and the radiation of every impact
(:mod:`acoustiviz.field`) over a grid of designs, on any :class:`concurrent.futures.Executor`,
writing one CSV row per design as it finishes, and condenses the rows into the design table.

What one design reports
-----------------------
For each design (gap d, impact mass m, contact damping c1, contact stiffness K_HZ or sphere
material, initial velocity of the main mass, listener distance and angle, configuration):

* the damping inclination, both definitions of :mod:`acoustiviz.dynamics.metrics` (paper eq 16
  from the first two positive maxima, and minus the slope of a line through the decaying maxima,
  with its window), the settling time, the number of impacts and the energy dissipated;
* the maximum sound pressure level at the listener over every impact: each impact is an
  acceleration pulse of the sphere built from its own approach speed
  (:func:`acoustiviz.core.pulses.acceleration_pulse`), radiated by the sphere and its images
  (:func:`acoustiviz.field.field_metrics`);
* optionally (``FixedSettings.levels``), the weighted levels of the whole run at the listener: LAFmax,
  LCpeak and LAeq over the simulated duration, of the click train at 96 kHz computed from the
  clicks alone (:mod:`acoustiviz.sweep.levels`).

Two modelling choices the paper leaves open
-------------------------------------------
Sphere radius (``radius_mode``)
    ``"fixed"`` (default): every impact mass radiates as the paper's Figure 2 sphere,
    a = 19.05 mm, whatever its mass. ``"from-mass"``: a = (3 m / (4 π ρ))^(1/3) from the impact
    mass and a density (default 7800 kg/m³, or the sphere material's). The default follows the
    paper: its levels (about 100-108 dB at 0.7 m) are those of the 19.05 mm sphere; a steel
    sphere of 40.5 g has a radius of 10.74 mm and is roughly 10-20 dB quieter.
Mass in the pulse (``pulse_mass``)
    ``"impact"`` (default): the Hertz pulse of the impact mass alone striking an immovable wall,
    as in paper eq 3 (``K* = 1/m``). ``"effective"``: the two free bodies, effective mass
    m M / (m + M), which is what the dynamics integrates. Over Table 1 masses the two differ by
    a few tenths of a dB.

The maximum over impacts
------------------------
At a fixed geometry the peak pressure of one impact is a function of its approach speed U
alone, and it grows with U: the pulse's velocity change grows like U while its length shrinks
only like U^(-1/5), so the peak grows like U^q with q from 1 (a pulse short against the
sphere's time a/c) to 7/5 (the far field of a long pulse), and more where the near and far
fields or the sphere and its images partly cancel: at least 6 dB per doubling of U, measured
over radii of 2-50 mm, masses of 5-500 g, K_HZ of 1e7-1e10 N/m^1.5, listeners at 0.1-3 m,
every configuration and pulse, and speeds from 1 mm/s to 10 m/s. The maximum over all
impacts is therefore the level of the fastest one. :func:`max_spl_db` evaluates the
``n_fastest`` fastest distinct speeds exactly and checks that their levels are ordered like
their speeds; if they are not, it falls back to every impact. The tests compare it with the
maximum over all impacts and check the monotonicity over a wide range of speeds, radii, masses,
listeners and configurations.

The package
-----------
:mod:`~acoustiviz.sweep.spec`
    the sweep specification: swept values, fixed settings, the grid of designs;
:mod:`~acoustiviz.sweep.values`
    the values of an axis as typed: one value, ``start:stop:count`` or ``a,b,c``;
:mod:`~acoustiviz.sweep.balls`
    several balls in a design: the fill of the cavity and its gap, the multi-ball model;
:mod:`~acoustiviz.sweep.evaluate`
    one design: the damper run (several balls: every collision, through the multi-ball sound),
    the level of its impacts, one row;
:mod:`~acoustiviz.sweep.store`
    the sweep directory: ``sweep.json``, the ``sweep.csv`` journal, resuming, the table of rows;
:mod:`~acoustiviz.sweep.execute`
    running the designs: a local process pool, any Executor, or Dask; failed designs become rows;
:mod:`~acoustiviz.sweep.levels`
    LAFmax, LCpeak and LAeq of a design's click train at the listener (optional, ``levels``);
:mod:`~acoustiviz.sweep.query`
    the design table (paper Table 2) and the quietest design for a target inclination;
:mod:`~acoustiviz.sweep.progress`
    the progress bar (tqdm, on a terminal) and the resume count;
:mod:`~acoustiviz.sweep.operation`
    designs in operation: every attractor of each design under a harmonic excitation over a band,
    condensed into one row of worst-case columns (amplitude, reduction, LCpeak, LAeq, LAFmax), run
    on the same executors;
:mod:`~acoustiviz.sweep.problem`
    an optimisation's variables, objectives and constraints, feasibility and the Pareto filter;
:mod:`~acoustiviz.sweep.modes`
    evaluation modes of an optimisation: a design's variables -> a row of columns (free vibration);
:mod:`~acoustiviz.sweep.optimise`
    running an optimisation: batches asked of Optuna's TPE sampler, evaluated on any executor,
    journalled and resumable (the optional ``optimize`` extra).

Units are SI throughout (m, kg, s, N/m^1.5, N·s/m, J); angles are in radians in the API and in
degrees in the CSV.
"""

from __future__ import annotations

from .evaluate import DesignResult, evaluate_design, impact_spl_db, listener_point, max_spl_db
from .execute import run_sweep
from .levels import SWEEP_LEVEL_COLUMNS, design_levels
from .operation import OPERATION_COLUMNS, Operation, WarmStart, evaluate_in_operation, run_operation
from .progress import Progress
from .query import (
    DESIGN_TABLE_COLUMNS,
    PAPER_TABLE2,
    RANK_COLUMNS,
    Band,
    DesignChoice,
    design,
    design_table,
    write_design_table,
)
from .spec import (
    MAX_RANGE_COUNT,
    PAPER_RADIUS,
    PULSE_MASSES,
    RADIUS_MODES,
    Design,
    FixedSettings,
    SweepSpec,
    parse_start_stop_count,
    parse_values,
    sweep_sphere_radius,
    value_range,
)
from .store import (
    CSV_COLUMNS,
    DEFINITIONS,
    DESIGN_TABLE_CSV,
    EXTRA_COLUMNS,
    SWEEP_CSV,
    SWEEP_JSON,
    SweepMismatch,
    SweepTable,
    load_sweep,
    read_spec,
)

__all__ = [
    "CSV_COLUMNS",
    "EXTRA_COLUMNS",
    "SWEEP_CSV",
    "SWEEP_JSON",
    "DESIGN_TABLE_CSV",
    "RADIUS_MODES",
    "PULSE_MASSES",
    "DEFINITIONS",
    "PAPER_RADIUS",
    "PAPER_TABLE2",
    "DESIGN_TABLE_COLUMNS",
    "RANK_COLUMNS",
    "SWEEP_LEVEL_COLUMNS",
    "design_levels",
    "SweepMismatch",
    "FixedSettings",
    "Design",
    "DesignResult",
    "SweepSpec",
    "SweepTable",
    "Band",
    "DesignChoice",
    "MAX_RANGE_COUNT",
    "parse_start_stop_count",
    "parse_values",
    "value_range",
    "sweep_sphere_radius",
    "listener_point",
    "impact_spl_db",
    "max_spl_db",
    "evaluate_design",
    "run_sweep",
    "load_sweep",
    "read_spec",
    "design_table",
    "write_design_table",
    "design",
    "Progress",
    "OPERATION_COLUMNS",
    "Operation",
    "WarmStart",
    "evaluate_in_operation",
    "run_operation",
]
