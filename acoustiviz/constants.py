"""One home for each fact: physical constants, the paper's defaults and the lists of choices.

Every other module, the command line and the scene schema take these values from here, so a
default cannot differ between two front-ends. Values are SI unless the name says otherwise.

Examples
--------
>>> from acoustiviz import constants
>>> round(constants.HERTZ_DURATION_CONSTANT, 6)
2.943275
>>> constants.STRIKES
('floor', 'wall')
"""

from __future__ import annotations

import math

__all__ = [
    "P_REF",
    "BALLOON_MIN_RADII",
    "STILL_SIZE",
    "ANIMATION_SIZE",
    "WAV_RATE",
    "W_REF",
    "ANALYSIS_RATE",
    "HERTZ_DURATION_CONSTANT",
    "PAPER_DURATION_CONSTANT",
    "PULSES",
    "SOLVERS",
    "SCENE_SOLVERS",
    "BALL_STARTS",
    "STRIKES",
    "CONFIGURATIONS",
    "ROOM_SURFACES",
    "ROOM_STRIKES",
    "EXCITATIONS",
    "FORCED_SOLVERS",
    "FREQUENCY_SWEEPS",
    "SECTION_PLANES",
    "MAX_SNAPSHOT_TIMES",
    "FORCED_TOLERANCE",
    "FORCED_TOLERANCE_RANGE",
    "FORCED_RTOL",
    "FORCED_RTOL_RANGE",
    "FORCED_STARTS",
    "FORCED_MAX_STARTS",
    "FORCED_MAX_CYCLES",
    "FORCED_MIN_CYCLES",
    "PAPER_RADIUS",
    "PAPER_VELOCITY",
    "PAPER_K_HERTZ",
    "PAPER_DENSITY",
    "PAPER_DISTANCE",
    "PAPER_ANGLE_DEG",
    "DEFAULT_WALL_DISTANCE",
    "TABLE1_PARAMETERS",
    "PAPER_GAP",
    "PAPER_V0",
    "DEFAULT_DURATION",
    "DEFAULT_RTOL",
    "DEFAULT_SOUND_SPEED",
    "DEFAULT_AIR_DENSITY",
    "MAX_MEMORY_MB",
]

# --- physical constants -------------------------------------------------------------------

#: Reference sound pressure for levels in air, Pa (ISO 1683): 0 dB = 20 µPa.
#: Every sound pressure level of the package is taken against it (:func:`acoustiviz.field.metrics.spl_db`).
P_REF = 20e-6
#: Reference sound power, W (ISO 1683): a sound power level of 0 dB is 1 pW.
W_REF = 1e-12
#: Hertz contact duration in units of α_max/U0: (4/5)·B(2/5, 1/2) = 2.9432751843...
#: (Johnson, *Contact Mechanics*, 1985, eq 11.24; the paper rounds it to 2.9432).
HERTZ_DURATION_CONSTANT = 0.8 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
#: The paper's rounded constant (Yufang and Zhongfang, 1992), kept for comparison only.
PAPER_DURATION_CONSTANT = 2.9432
#: Speed of sound in air at 20 °C, m/s.
DEFAULT_SOUND_SPEED = 343.2
#: Density of air at 20 °C and 101.325 kPa, kg/m³.
DEFAULT_AIR_DENSITY = 1.204

# --- the choices offered ------------------------------------------------------------------

#: Acceleration pulses: the paper's peak-matched half-sine (eq 4), an impulse-matched half-sine,
#: the exact Hertz pulse.
PULSES = ("half-sine", "impulse-matched", "hertz")
#: Damper solvers of :func:`acoustiviz.dynamics.simulate` (the names it accepts).
SOLVERS = ("event", "newmark", "impact-map")
#: Solvers a scene may name: ``"auto"`` takes the cheapest one whose error suits the tolerance.
SCENE_SOLVERS = ("auto", *SOLVERS)

#: How the balls of a cavity start (at rest): ``spaced`` splits the free travel into N + 1 equal spaces,
#: ``low`` packs them against ``wall-`` (the free travel all above), ``high`` against ``wall+``, ``random``
#: splits it at N uniform random points (:class:`acoustiviz.dynamics.BallState`).
BALL_STARTS = ("spaced", "low", "high", "random")
#: Which surface of a wall-floor corner the sphere strikes.
STRIKES = ("floor", "wall")
#: Geometries built from a sphere radius alone, with default settings: the ``--config`` choices
#: (the registry :data:`acoustiviz.core.geometry.GEOMETRIES` adds the room, which needs its dimensions).
CONFIGURATIONS = ("free", "plane", "wall-floor")
#: The six surfaces of a shoebox room, by the coordinate plane each lies in (x = 0, x = Lx, ...).
ROOM_SURFACES = ("x0", "x1", "y0", "y1", "z0", "z1")
#: Names of the surface a sphere in a room strikes: the floor, the ceiling, or one of the six by name.
ROOM_STRIKES = ("floor", "ceiling", *ROOM_SURFACES)
#: Harmonic excitations of the damper: a force on the main mass, or a base displacement.
EXCITATIONS = ("force", "base")
#: Solvers of the forced damper (acoustiviz.dynamics.forced).
FORCED_SOLVERS = ("event", "impact-map", "newmark")
#: Frequency sweeps: continuation up, down or both, or independent runs.
FREQUENCY_SWEEPS = ("up", "down", "both", "independent")
#: Planes through the sphere's centre a field view (snapshot, animation) may show, named by the two
#: axes each holds: the vertical plane normal to the wall, the vertical plane parallel to it, the
#: horizontal plane.
SECTION_PLANES = ("xz", "yz", "xy")
#: Most snapshot times of one field view, drawn side by side in a render, its VTK files and its HTML page.
MAX_SNAPSHOT_TIMES = 12

# --- settings of the forced damper's steady states (API, CLI and scenes share these) -------

#: Newton residual below which a periodic orbit counts as converged: the largest component of
#: ``P^n(z) - z`` on the Poincaré section, displacements in m and velocities in m/s.
FORCED_TOLERANCE = 1e-9
#: Tolerance range accepted for :data:`FORCED_TOLERANCE` (m, m/s).
FORCED_TOLERANCE_RANGE = (1e-14, 1e-3)
#: Relative tolerance of the event solver's contact integration (DOP853).
FORCED_RTOL = 1e-10
#: Range accepted for :data:`FORCED_RTOL`.
FORCED_RTOL_RANGE = (1e-14, 1e-4)
#: Starts per frequency looking for coexisting attractors (the linear start, rest, and the impact
#: mass spread over the cavity), besides the states continued from the neighbouring frequencies.
FORCED_STARTS = 6
#: Largest number of starts per frequency.
FORCED_MAX_STARTS = 256
#: Forcing cycles each start is run directly before its motion is measured as non-periodic.
FORCED_MAX_CYCLES = 500
#: Least cycle limit accepted.
FORCED_MIN_CYCLES = 18

# --- the paper's Figure 2 impact ----------------------------------------------------------

#: Sphere radius a of the paper's Figure 2, m (a 1.5 inch ball).
PAPER_RADIUS = 0.01905
#: Impact speed U0 of Figure 2, m/s.
PAPER_VELOCITY = 1.4
#: Hertz stiffness K_HZ of Figure 2 and Table 1, N/m^1.5.
PAPER_K_HERTZ = 5.6e8
#: Density of a steel sphere, kg/m³.
PAPER_DENSITY = 7800.0
#: Listener distance of Figure 2, m.
PAPER_DISTANCE = 0.7
#: Listener angle of Figure 2, degrees from the acceleration axis.
PAPER_ANGLE_DEG = 45.0
#: Distance in m from the wall to the sphere's centre in a wall-floor corner when none is given.
DEFAULT_WALL_DISTANCE = 0.05

# --- the paper's Table 1 damper ------------------------------------------------------------

#: Table 1: main mass M (kg), spring K (N/m), dashpot C (N s/m), impact mass m (kg), Hertz
#: stiffness k_hertz (N/m^1.5) and contact damping c1 (N s/m), by name; the damper model built
#: from them is :data:`acoustiviz.dynamics.TABLE1`.
TABLE1_PARAMETERS = {"M": 0.5, "K": 500.0, "C": 0.05, "m": 0.0405, "k_hertz": PAPER_K_HERTZ, "c1": 20.0}
#: Total free travel d of the impact mass in Figure 5, m.
PAPER_GAP = 0.04
#: Initial main-mass velocity of Figure 5, m/s.
PAPER_V0 = 2.0
#: Simulated time of a damper run, s: the Table 1 damper settles in about 15 s.
DEFAULT_DURATION = 20.0
#: The event solver's relative tolerance on each contact, used by every front-end and by
#: :func:`acoustiviz.dynamics.simulate`. At 1e-13 the first 40 impact times of the Table 1 run
#: (Figure 5 start) are within 2e-9 s of the converged reference (4.8e-8 s at 1e-12), measured by
#: ``benchmarks/bench_dynamics.py``; its cost over 1e-12: ``benchmarks/results/design_timings.md``.
DEFAULT_RTOL = 1e-13
#: Relative tolerance the event solver (and the impact map's restitution table) integrates a contact at:
#: below 1e-15 double precision cannot follow, above 1e-3 the restitution is no longer converged.
SOLVER_RTOL_RANGE = (1e-15, 1e-3)
#: The accuracy (relative, on impact times and speeds) that solver ``"auto"`` may be asked for; it picks the
#: cheapest solver that suits it and runs it at ``min(tolerance, SOLVER_RTOL_RANGE[1])``.
AUTO_TOLERANCE_RANGE = (1e-15, 0.5)

# --- levels ---------------------------------------------------------------------------------

#: Rate in Hz at which computed signals are rendered for their weighted levels (not limited by a
#: 48 kHz file): flat to 43.2 kHz, so the weightings, the 20 kHz band and the peaks see the whole click.
ANALYSIS_RATE = 96000
#: Weighted level name (``--metric``) -> its column in level tables (IEC 61672-1 weightings:
#: Z/C peak, A fast/slow maximum, A/Z equivalent level, unweighted and A-weighted sound exposure level).
LEVEL_METRICS = {"lzpeak": "lzpeak_db", "lcpeak": "lcpeak_db", "lafmax": "lafmax_db", "lasmax": "lasmax_db",
                 "laeq": "laeq_db", "lzeq": "lzeq_db", "sel": "sel_db", "sel-a": "sel_a_db"}
#: ``--metric`` of a directivity -> its CSV column: the peak SPL, the RMS level over the window, and
#: the weighted levels of :data:`LEVEL_METRICS`.
DIRECTIVITY_METRICS = {"peak-spl": "spl_db", "rms": "rms_db", **LEVEL_METRICS}
#: What a balloon may show: the closed form's peak SPL, RMS level and SEL, or a weighted level of
#: :data:`LEVEL_METRICS` (its unweighted ``sel`` is the closed form's).
BALLOON_METRICS = ("peak", "rms", "sel", *(m for m in LEVEL_METRICS if m != "sel"))
#: Smallest and largest polar node count of a balloon's measuring grid (the azimuth gets twice as many).
BALLOON_N_THETA_RANGE = (4, 512)

# --- views ---------------------------------------------------------------------------------

#: Smallest radius of a directivity balloon's sphere, in sphere radii: 1.05 times the sphere's
#: diameter, so the grid clears the sphere and the surfaces it touches.
BALLOON_MIN_RADII = 2.1
#: Default size in pixels (width, height) of a still render (balloon, snapshot).
STILL_SIZE = (1200, 900)
#: Default size in pixels (width, height) of an animation's frames.
ANIMATION_SIZE = (800, 600)

# --- limits on work -----------------------------------------------------------------------

#: Cap in MB on a command's estimated working memory and, separately, on the bytes it writes
#: (:mod:`acoustiviz.app.budget`); ``--max-memory`` overrides it.
MAX_MEMORY_MB = 2048.0

#: Output sample rates in Hz of rendered sound (WAV files, levels): the rule of every front-end.
SAMPLE_RATES = (44100, 48000, 96000)
#: Largest target damping inclination and tolerance in m/s of a design choice (both must be > 0).
MAX_INCLINATION = 10.0
#: Default seed of the random generator of a room WAV's statistical tail: the same WAV every run.
TAIL_SEED = 20261126
#: Default sample rate in Hz of rendered sound and its WAV files (one of :data:`SAMPLE_RATES`).
WAV_RATE = 48000
