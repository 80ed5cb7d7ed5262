"""Settings of a design sweep: ``acoustiviz sweep`` and a scene's ``[outputs.sweep]``.

:data:`SWEEP` holds the settings object's records; :data:`SWEPT`, :data:`SWEEP_DAMPER` and
:data:`SWEEP_SOUND` the options of the command, each given only when typed (the defaults named
in their help are :class:`~acoustiviz.app.settings.sweep_job.SweepJob`'s); :data:`SWEEP_RUN` where
the designs run, the folder and its design report; :data:`SCENE_SWEEP` the keys of a scene's
``[outputs.sweep]`` that the command spells otherwise. :data:`RADIUS` is the sphere's radius in m,
which a sweep also takes as ``"mass"`` (:func:`sweep_radius`).
"""

from __future__ import annotations

import dataclasses

from ...constants import (
    DEFAULT_AIR_DENSITY,
    DEFAULT_DURATION,
    DEFAULT_RTOL,
    DEFAULT_SOUND_SPEED,
    DEFAULT_WALL_DISTANCE,
    PAPER_ANGLE_DEG,
    PAPER_DISTANCE,
    PAPER_GAP,
    PAPER_RADIUS,
    PAPER_V0,
    PULSES,
    SOLVER_RTOL_RANGE,
    SOLVERS,
    TABLE1_PARAMETERS,
)
from ...errors import ParameterError
from .base import Settings
from .damper import BALLS, MODEL, RUN
from .design import BAND_WIDTH, DEFINITION
from .forced import FORCED
from .table import Setting, by_name

__all__ = ["SWEEP", "SWEPT", "SWEEP_DAMPER", "SWEEP_SOUND", "SWEEP_RUN", "SCENE_SWEEP", "RADIUS", "SweepSettings",
           "sweep_radius"]

SWEEP = (
    # A scene's sweep is a quick look (5 s of motion per design); the command runs the paper's 20 s.
    Setting("duration", "--duration", "duration_s", "float", DEFAULT_DURATION, "simulated time per design", "s",
            low=0.0, high=1e4, low_open=True, scene_default=5.0, table="outputs.sweep"),
)

#: The radius of the radiating sphere (the scene's ``sphere.radius_m``).
RADIUS = Setting("radius", "--radius", "radius_m", "float", PAPER_RADIUS, "sphere radius", "m", low=0.0, high=1.0,
                 low_open=True, table="sphere")


#: The damper's records, whose ranges the swept values and the fixed M, K and C obey
#: (:class:`acoustiviz.app.settings.sweep_job.SweepJob` checks them).
_DAMPER = by_name(MODEL + RUN)


def _swept(name, option, doc, key=None, scene_default=None):
    if name in _DAMPER:  # each value in the damper record's range
        r = _DAMPER[name]
        return Setting(name, option, key, "range", None, doc, r.unit, low=r.low, high=r.high, low_open=r.low_open,
                       metavar="RANGE", scene_default=scene_default, table="outputs.sweep" if key else "")
    return Setting(name, option, None, "str", None, doc, metavar="NAMES" if option in ("--material", "--config")
                   else "RANGE")


def _fixed(name, doc):
    r = _DAMPER[name]
    return Setting(name, r.option, None, "float", None, doc, r.unit, low=r.low, high=r.high, low_open=r.low_open,
                   metavar=name)


#: The swept options: one value, START:STOP:COUNT (both ends included) or a comma list A,B,C.
SWEPT = (
    _swept("gap", "--gap", f"total free travel d in m (default {PAPER_GAP:g} on the command line)", "gap_m",
           "0.02:0.06:5"),
    _swept("m", "--m", f"impact mass in kg (default {TABLE1_PARAMETERS['m']:g} on the command line)", "mass_kg",
           "0.02:0.08:4"),
    _swept("mass_ratio", "--mass-ratio", f"mass ratio m/M instead of --m (m = ratio x M within "
           f"{by_name(MODEL)['m'].range_text()})"),
    _swept("c1", "--c1", f"contact damping in N s/m (default {TABLE1_PARAMETERS['c1']:g})"),
    _swept("k_hertz", "--k-hertz", f"Hertz contact stiffness in N/m^1.5 (default {TABLE1_PARAMETERS['k_hertz']:g})"),
    _swept("material", "--material", "sphere material(s) from the catalogue instead of --k-hertz: K_HZ from the "
           "sphere radius and the materials (paper eq 2), density for --radius mass"),
    _swept("v0", "--v0", f"initial main-mass velocity in m/s (default {PAPER_V0:g})"),
    _swept("distance", "--distance", f"listener distance in m from the sphere's centre (default {PAPER_DISTANCE:g})"),
    _swept("angle_deg", "--angle", f"listener angle in degrees from the surface normal (default {PAPER_ANGLE_DEG:g})"),
    _swept("config", "--config", "free, plane (reflecting plane, default) or wall-floor; a comma list sweeps them"),
    # several balls (free vibration and in operation): N equal spheres in a column, as acoustiviz damper --balls N
    Setting("balls", "--balls", "balls", "range", None, "numbers of equal balls in the cavity, whole numbers, each of "
            "mass --m (with --equal-total-mass: --m / N); default 1, and no balls and fill columns",
            low=BALLS[0].low, high=BALLS[0].high, metavar="RANGE", table="outputs.sweep"),
    Setting("fill", "--fill", "fill", "range", None, "fraction of the cavity's length the balls take, "
            "instead of --gap: gap = N D (1 - fill) / fill, D each ball's diameter (steel or --material)",
            low=0.0, high=1.0, low_open=True, high_open=True, metavar="RANGE", table="outputs.sweep"),
)

#: The damper of every design (before the duration, :data:`SWEEP`) and its solver (after it).
SWEEP_DAMPER = (
    _fixed("M", f"main mass in kg (default {TABLE1_PARAMETERS['M']:g})"),
    _fixed("K", f"main spring in N/m (default {TABLE1_PARAMETERS['K']:g})"),
    _fixed("C", f"main dashpot in N s/m (default {TABLE1_PARAMETERS['C']:g})"),
    Setting("clip_tensile", "--clip-tensile", None, "bool", None,
            "clip the contact force at zero (default: the paper's form, which may pull)"),
    SWEEP[0],
    Setting("solver", "--solver", None, "str", None, "damper solver (default event)", choices=SOLVERS),
    Setting("rtol", "--rtol", None, "float", None,
            f"relative tolerance of the event and impact-map solvers' contacts (default {DEFAULT_RTOL:g})",
            low=SOLVER_RTOL_RANGE[0], high=SOLVER_RTOL_RANGE[1], metavar="RTOL"),
    Setting("equal_total_mass", "--equal-total-mass", "equal_total_mass", "bool", None,
            "divide each --m among the --balls of a design (each ball m / N): designs of every ball count carry "
            "the same total mass (default: --m is each ball's mass, as acoustiviz damper --balls)",
            scene_default=False, table="outputs.sweep"),
    *BALLS[1:],  # between two balls, as acoustiviz damper --balls (a scene's [damper] keys)
)

#: The sound of every impact at the listener.
SWEEP_SOUND = (
    Setting("radius", "--radius", None, "str", None,
            f"radius of the radiating sphere in m (default {PAPER_RADIUS:g}, the paper's Figure 2 sphere, whose "
            "levels match the paper's), or 'mass': from the impact mass and --density", metavar="M|mass"),
    Setting("density", "--density", None, "float", None,
            "sphere density for --radius mass (default 7800 or the material's)", metavar="KG/M^3"),
    Setting("surface", "--surface", None, "str", None,
            "surface material for K_HZ from --material (default: same as the sphere)", metavar="NAME"),
    Setting("pulse", "--pulse", None, "str", None,
            "acceleration pulse of each impact (default the paper's peak-matched half-sine)", choices=PULSES),
    Setting("pulse_mass", "--pulse-mass", None, "str", None,
            "mass in the pulse: the impact mass alone against a fixed wall (default, paper eq 3) or the effective "
            "mass m M/(m+M) of the two bodies", choices=("impact", "effective")),
    Setting("c", "--c", None, "float", None, f"speed of sound (default {DEFAULT_SOUND_SPEED:g})", metavar="M/S"),
    Setting("rho", "--rho", None, "float", None, f"air density (default {DEFAULT_AIR_DENSITY:g})",
            metavar="KG/M^3"),
    Setting("wall_distance", "--wall-distance", None, "float", None,
            f"wall-floor: distance from the wall to the sphere's centre in m (default {DEFAULT_WALL_DISTANCE:g})",
            metavar="M"),
    Setting("n_fastest", "--spl-fastest", None, "int", None,
            "evaluate the N fastest impacts exactly (the loudest is the fastest); 0: all (default 4)", metavar="N"),
    Setting("levels", "--levels", "levels", "bool", None,
            "also report the LAFmax, LCpeak and LAeq of each run's click train at the listener at 96 kHz "
            "over the run (columns lafmax_db, lcpeak_db, laeq_db; about as costly as the motion, so off by "
            "default)", scene_default=False, table="outputs.sweep"),
)

#: Where the designs run, the folder and its design report (the command's ``execution and outputs``).
SWEEP_RUN = (
    Setting("room_window", "--room-window", None, "float", None,
            "with --room: the window in s from the start of each impact whose images the peak SPL takes (required "
            "when a surface is rigid and --image-order is not given)", "s", metavar="S"),
    Setting("out", "--out", None, "str", None, "output directory (resumed if it exists)", metavar="DIR"),
    Setting("executor", "--executor", None, "str", "process", "local process pool or a Dask distributed scheduler",
            metavar="process|dask://HOST:PORT"),
    Setting("workers", "--workers", None, "int", None,
            "processes of the local pool (default: all cores; a Dask cluster has its own)", low=1, metavar="N"),
    Setting("overwrite", "--overwrite", None, "bool", False,
            "if DIR holds a sweep with other settings, move its sweep.csv and sweep.json aside "
            "(sweep.previous-N.csv and .json, N = 1, 2, ...) and start afresh"),
    DEFINITION,
    BAND_WIDTH,
    Setting("quiet", "--quiet", None, "bool", False,
            "no progress bar (it is drawn only on a terminal anyway; the resume count is still shown)"),
)

#: The keys of a scene's ``[outputs.sweep]`` the command spells otherwise (its --workers has no 0; the command
#: sweeps in operation when given --force or --base).
SCENE_SWEEP = (
    Setting("workers", None, "workers", "int", 0, "worker processes (0: all cores)", low=0, high=1024,
            table="outputs.sweep"),
    Setting("in_operation", None, "in_operation", "bool", False,
            "evaluate every design in operation under the scene's [excitation] (its kind, amplitude, frequencies "
            "and search) instead of in free vibration", table="outputs.sweep"),
    dataclasses.replace(by_name(FORCED)["noise_seconds"], option=None, key="noise_seconds", table="outputs.sweep"),
)


def sweep_radius(value, name: str = "radius") -> tuple:
    """``("from-mass", PAPER_RADIUS)`` for ``"mass"``, else ``("fixed", radius in m)`` checked against :data:`RADIUS`.

    Examples
    --------
    >>> sweep_radius("mass")[0], sweep_radius("0.01")
    ('from-mass', ('fixed', 0.01))
    """
    if isinstance(value, str) and value.strip().lower() == "mass":
        return "from-mass", PAPER_RADIUS
    try:
        radius = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"expected a radius in {RADIUS.range_text()} or 'mass', got {value!r}") from None
    return "fixed", RADIUS.check(radius, name)


@dataclasses.dataclass(frozen=True)
class SweepSettings(Settings):
    """How long each design of a sweep runs."""

    TABLE = SWEEP
    duration: float = DEFAULT_DURATION
