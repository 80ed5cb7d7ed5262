"""Design sweeps of the impact damper and the acoustic-versus-vibration design table.

The paper's design rule (its Figure 6 and Table 2): among impact dampers that suppress the
vibration equally well -- the same damping inclination -- choose the quietest. This module runs
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
  (:func:`acoustiviz.contact.acceleration_pulse`), radiated by the sphere and its images
  (:func:`acoustiviz.field.field_metrics`).

Two modelling choices the paper leaves open
-------------------------------------------
Sphere radius (``radius_mode``)
    ``"fixed"`` (default): every impact mass radiates as the paper's Figure 2 sphere,
    a = 19.05 mm, whatever its mass. ``"from-mass"``: a = (3 m / (4 π ρ))^(1/3) from the impact
    mass and a density (default 7800 kg/m³, or the sphere material's). The default follows the
    paper: its levels (about 100-108 dB at 0.7 m) are those of the 19.05 mm sphere; a steel
    sphere of 40.5 g has a radius of about 10.7 mm and is roughly 10-20 dB quieter.
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

Files of a sweep directory
--------------------------
``sweep.json``
    Every setting of the sweep. A sweep resumes only into a directory made with the same
    settings (:class:`SweepMismatch` otherwise, unless ``overwrite=True``).
``sweep.csv``
    One row per finished design, in order of completion, written, flushed and synced one at a
    time. Columns :data:`CSV_COLUMNS` then :data:`EXTRA_COLUMNS`. A torn last line left by a
    kill is dropped on resume; finished designs are never recomputed.

Units are SI throughout (m, kg, s, N/m^1.5, N·s/m, J); angles are in radians in the API and in
degrees in the CSV.
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import math
import os
import time
from concurrent.futures import Executor, as_completed
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from ._validate import ParameterError, check_choice, check_nonnegative, check_positive, check_range
from .images import observer_points

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
    "SweepMismatch",
    "Settings",
    "Design",
    "DesignResult",
    "SweepSpec",
    "SweepTable",
    "Band",
    "DesignChoice",
    "parse_values",
    "value_range",
    "sphere_radius",
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
]

#: The columns every ``sweep.csv`` starts with (the command-line interface promises these).
CSV_COLUMNS = (
    "gap_m",
    "mass_kg",
    "inclination_two_maxima_m_s",
    "inclination_fit_m_s",
    "settling_time_s",
    "n_impacts",
    "max_spl_db",
)
#: Further columns, after :data:`CSV_COLUMNS`.
EXTRA_COLUMNS = (
    "design_id",
    "mass_ratio",
    "c1_n_s_m",
    "k_hertz_n_m1_5",
    "material",
    "v0_m_s",
    "distance_m",
    "angle_deg",
    "config",
    "radius_m",
    "energy_dissipated_contact_j",
    "energy_dissipated_main_j",
    "max_approach_velocity_m_s",
    "fit_window_start_s",
    "fit_window_stop_s",
    "fit_n_maxima",
    "spl_impacts_evaluated",
    "success",
)
_ALL_COLUMNS = CSV_COLUMNS + EXTRA_COLUMNS
_TEXT_COLUMNS = ("material", "config")

#: File names inside a sweep directory.
SWEEP_CSV = "sweep.csv"
SWEEP_JSON = "sweep.json"
DESIGN_TABLE_CSV = "design_table.csv"

RADIUS_MODES = ("fixed", "from-mass")
PULSE_MASSES = ("impact", "effective")
#: Damping-inclination definitions: paper eq 16, or the envelope fit.
DEFINITIONS = ("two-maxima", "fit")
#: Radius in m of the paper's Figure 2 sphere (3/4 inch).
PAPER_RADIUS = 0.01905
#: The paper's Table 2: (damping inclination in m/s, minimum and maximum of the maximum SPL in dB,
#: their difference in dB), for bands 0.1 cm/s wide.
PAPER_TABLE2 = (
    (0.007, 103.0, 105.0, 2.0),
    (0.008, 100.0, 108.0, 8.0),
    (0.009, 100.0, 107.0, 7.0),
    (0.010, 100.0, 107.0, 7.0),
    (0.011, 101.0, 106.0, 5.0),
    (0.012, 104.0, 106.0, 2.0),
)
_CONFIGS = ("free", "plane", "wall-floor")
_SOLVERS = ("event", "impact-map", "newmark")
_FORMAT = "acoustiviz-sweep"
_FORMAT_VERSION = 1


class SweepMismatch(ParameterError):
    """A sweep directory holds results made with other settings."""


# --------------------------------------------------------------------------- values and ranges
def value_range(start: float, stop: float, count: int) -> tuple[float, ...]:
    """``count`` evenly spaced values from ``start`` to ``stop``, both included.

    Parameters
    ----------
    start, stop : float
        First and last value (any unit).
    count : int
        Number of values (>= 1; 1 gives ``(start,)`` and requires ``start == stop``).

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> value_range(0.02, 0.06, 5)
    (0.02, 0.03, 0.04, 0.05, 0.06)
    """
    n = int(count)
    if n != count or n < 1:
        raise ParameterError("count", f"must be an integer >= 1, got {count!r}")
    if n == 1:
        if start != stop:
            raise ParameterError("count", f"a range of 1 value needs start == stop, got {start:g}:{stop:g}")
        return (float(start),)
    return tuple(float(v) for v in np.round(np.linspace(start, stop, n), 15))


def parse_values(name: str, text, kind=float) -> tuple:
    """Parse ``start:stop:count`` (inclusive), ``a,b,c`` or a single value.

    Parameters
    ----------
    name : str
        Name used in error messages (e.g. ``"--gap"``).
    text : str or number or sequence
        The specification.
    kind : type
        ``float`` for numbers, ``str`` for names (ranges are then refused).

    Returns
    -------
    tuple
        The values, in the given order.

    Examples
    --------
    >>> parse_values("--m", "0.02:0.08:4")
    (0.02, 0.04, 0.06, 0.08)
    >>> parse_values("--config", "plane,wall-floor", str)
    ('plane', 'wall-floor')
    """
    if isinstance(text, (list, tuple)):
        items = list(text)
    elif isinstance(text, (int, float)) and kind is float:
        items = [text]
    else:
        s = str(text).strip()
        if not s:
            raise ParameterError(name, "expected a value, start:stop:count or a comma-separated list")
        if ":" in s:
            if kind is not float:
                raise ParameterError(name, f"expected names separated by commas, got {s!r}")
            parts = s.split(":")
            if len(parts) != 3:
                raise ParameterError(name, f"a range is start:stop:count, got {s!r}")
            try:
                start, stop = float(parts[0]), float(parts[1])
                count = int(parts[2])
            except ValueError:
                raise ParameterError(name, f"a range is start:stop:count with an integer count, got {s!r}") from None
            if count < 1:
                raise ParameterError(name, f"the count of {s!r} must be >= 1")
            if count == 1 and start != stop:
                raise ParameterError(name, f"a range of one value needs start == stop, got {s!r}")
            return value_range(start, stop, count)
        items = [p.strip() for p in s.split(",")]
    if not items:
        raise ParameterError(name, "expected at least one value")
    if kind is float:
        out = []
        for it in items:
            try:
                v = float(it)
            except (TypeError, ValueError):
                raise ParameterError(name, f"expected a number, got {it!r}") from None
            if not math.isfinite(v):
                raise ParameterError(name, f"must be finite, got {it!r}")
            out.append(v)
        return tuple(out)
    return tuple(str(it) for it in items)


def _check_all(name, values, check, *args, **kwargs):
    if not isinstance(values, tuple) or not values:
        raise ParameterError(name, f"expected a non-empty tuple of values, got {values!r}")
    for v in values:
        check(name, v, *args, **kwargs)
    if len(set(values)) != len(values):
        raise ParameterError(name, f"values must not repeat, got {values!r}")


# --------------------------------------------------------------------------- specification
@dataclass(frozen=True)
class Settings:
    """What stays fixed across a sweep (defaults: paper Table 1, Figure 5 start, Figure 2 sphere).

    Parameters
    ----------
    M : float
        Main mass in kg (0.5).
    K : float
        Main spring in N/m (500).
    C : float
        Main dashpot in N·s/m (0.05).
    clip_tensile : bool
        Clip the contact force at zero (False: the paper's form).
    duration : float
        Simulated time per design in s (20: the Table 1 run settles after about 15 s).
    solver : {"event", "impact-map", "newmark"}
        Damper solver (:func:`acoustiviz.dynamics.simulate`).
    rtol : float
        Relative tolerance of the solver's contact integration (1e-10: the approach speeds agree
        with the converged solution to about 1e-9, 40 % faster than the solver's default 1e-14;
        the motion is chaotic, so the late impacts -- and the settling time -- are meaningful
        only statistically at any tolerance).
    radius_mode : {"fixed", "from-mass"}
        How the radiating sphere's radius is chosen (see the module notes).
    radius : float
        Sphere radius in m when ``radius_mode="fixed"`` (the paper's 19.05 mm).
    density : float or None
        Sphere density in kg/m³ for ``radius_mode="from-mass"``; None: 7800 kg/m³, or the
        sphere material's density when the sweep names materials.
    surface : str or None
        Surface material (catalogue name) for K_HZ from materials; None: same as the sphere.
    pulse : {"half-sine", "impulse-matched", "hertz"}
        Acceleration pulse of each impact (default the paper's peak-matched half-sine, eq 4).
    pulse_mass : {"impact", "effective"}
        Mass of the pulse: the impact mass alone (paper eq 3) or the effective mass of the
        impact and main masses.
    c, rho : float
        Speed of sound in m/s and density of the air in kg/m³.
    wall_distance : float
        Wall-floor configuration: distance in m from the wall to the sphere's centre.
    n_fastest : int
        Number of fastest distinct impacts evaluated exactly (0: every impact).
    fit_window_fraction : float
        Envelope fit over the maxima still above this fraction of the first (0.3).
    settling_fraction : float
        Settled once every later maximum stays below this fraction of the first (0.05).
    samples_per_period : int
        Samples of x(t) per main period for locating the maxima (200).
    """

    M: float = 0.5
    K: float = 500.0
    C: float = 0.05
    clip_tensile: bool = False
    duration: float = 20.0
    solver: str = "event"
    rtol: float = 1e-10
    radius_mode: str = "fixed"
    radius: float = PAPER_RADIUS
    density: float | None = None
    surface: str | None = None
    pulse: str = "half-sine"
    pulse_mass: str = "impact"
    c: float = 343.2
    rho: float = 1.204
    wall_distance: float = 0.05
    n_fastest: int = 4
    fit_window_fraction: float = 0.3
    settling_fraction: float = 0.05
    samples_per_period: int = 200

    def __post_init__(self):
        check_positive("M", self.M, "kg")
        check_positive("K", self.K, "N/m")
        check_nonnegative("C", self.C, "N s/m")
        if not isinstance(self.clip_tensile, bool):
            raise ParameterError("clip_tensile", f"must be True or False, got {self.clip_tensile!r}")
        check_positive("duration", self.duration, "s")
        check_choice("solver", self.solver, _SOLVERS)
        check_range("rtol", self.rtol, 1e-15, 1e-3)
        check_choice("radius_mode", self.radius_mode, RADIUS_MODES)
        check_positive("radius", self.radius, "m")
        if self.density is not None:
            check_positive("density", self.density, "kg/m^3")
        if self.surface is not None:
            _material("surface", self.surface)
        from .contact import PULSE_KINDS

        check_choice("pulse", self.pulse, PULSE_KINDS)
        check_choice("pulse_mass", self.pulse_mass, PULSE_MASSES)
        check_positive("c", self.c, "m/s")
        check_positive("rho", self.rho, "kg/m^3")
        check_positive("wall_distance", self.wall_distance, "m")
        if int(self.n_fastest) != self.n_fastest or self.n_fastest < 0:
            raise ParameterError("n_fastest", f"must be an integer >= 0 (0: every impact), got {self.n_fastest!r}")
        check_range("fit_window_fraction", self.fit_window_fraction, 0.0, 1.0, low_open=True, high_open=True)
        check_range("settling_fraction", self.settling_fraction, 0.0, 1.0, low_open=True, high_open=True)
        if int(self.samples_per_period) != self.samples_per_period or self.samples_per_period < 8:
            raise ParameterError("samples_per_period", f"must be an integer >= 8, got {self.samples_per_period!r}")


@dataclass(frozen=True)
class Design:
    """One design of a sweep (all SI; the angle in radians).

    Parameters
    ----------
    design_id : int
        Position in the sweep's grid (row-major over :data:`SweepSpec.AXES`).
    gap : float
        Total free travel d in m.
    m : float
        Impact mass in kg.
    c1 : float
        Contact damping in N·s/m.
    k_hertz : float
        Hertz stiffness in N/m^1.5 (from the materials when ``material`` is set).
    material : str
        Sphere material name, or ``""`` when K_HZ was given directly.
    v0 : float
        Initial velocity of the main mass in m/s.
    distance : float
        Listener distance from the sphere's centre in m.
    angle : float
        Listener angle from the sphere's acceleration axis in rad.
    config : str
        ``"free"``, ``"plane"`` or ``"wall-floor"``.
    radius : float
        Radius of the radiating sphere in m.
    """

    design_id: int
    gap: float
    m: float
    c1: float
    k_hertz: float
    material: str
    v0: float
    distance: float
    angle: float
    config: str
    radius: float


@dataclass(frozen=True)
class SweepSpec:
    """A grid of designs: the Cartesian product of the swept values, and the fixed settings.

    Every swept parameter is a tuple of values (one value: held fixed). At most one of ``m``
    and ``mass_ratio``, and at most one of ``k_hertz`` and ``material``, is given (neither:
    Table 1's m = 40.5 g and K_HZ = 5.6e8 N/m^1.5).

    Parameters
    ----------
    gap : tuple of float
        Gaps d in m (default the Figure 5 gap, 0.04 m).
    m : tuple of float, optional
        Impact masses in kg (default Table 1, 0.0405 kg).
    mass_ratio : tuple of float or None
        Mass ratios m/M instead of ``m``.
    c1 : tuple of float
        Contact damping in N·s/m (20).
    k_hertz : tuple of float, optional
        Hertz stiffness in N/m^1.5 (default Table 1, 5.6e8).
    material : tuple of str or None
        Sphere materials (catalogue names) instead of ``k_hertz``: K_HZ from the sphere's radius
        and the materials (paper eq 2), and the density for ``radius_mode="from-mass"``.
    v0 : tuple of float
        Initial velocities of the main mass in m/s (Figure 5: 2 m/s).
    distance : tuple of float
        Listener distances in m from the sphere's centre (0.7 m).
    angle : tuple of float
        Listener angles in rad from the acceleration axis (π/4).
    config : tuple of str
        Configurations (``"plane"``: the paper's reflecting plane).
    settings : Settings
        Everything else.

    Examples
    --------
    >>> spec = SweepSpec(gap=value_range(0.02, 0.06, 5), m=value_range(0.02, 0.08, 4))
    >>> len(spec.designs())
    20
    """

    gap: tuple = (0.04,)
    m: tuple | None = None
    mass_ratio: tuple | None = None
    c1: tuple = (20.0,)
    k_hertz: tuple | None = None
    material: tuple | None = None
    v0: tuple = (2.0,)
    distance: tuple = (0.7,)
    angle: tuple = (math.pi / 4,)
    config: tuple = ("plane",)
    settings: Settings = field(default_factory=Settings)

    #: Order of the grid's axes; the last varies fastest.
    AXES = ("config", "material", "k_hertz", "c1", "v0", "distance", "angle", "gap", "m")

    def __post_init__(self):
        if self.m is not None and self.mass_ratio is not None:
            raise ParameterError("m", "give either m (kg) or mass_ratio (m/M), not both")
        if self.k_hertz is not None and self.material is not None:
            raise ParameterError("k_hertz", "give either k_hertz (N/m^1.5) or material, not both")
        if self.m is None and self.mass_ratio is None:
            object.__setattr__(self, "m", (0.0405,))  # Table 1
        if self.k_hertz is None and self.material is None:
            object.__setattr__(self, "k_hertz", (5.6e8,))  # Table 1
        if not isinstance(self.settings, Settings):
            raise ParameterError("settings", f"expected a Settings, got {type(self.settings).__name__}")
        _check_all("gap", self.gap, check_positive, "m")
        if self.m is not None:
            _check_all("m", self.m, check_positive, "kg")
        else:
            _check_all("mass_ratio", self.mass_ratio, check_positive)
        _check_all("c1", self.c1, check_nonnegative, "N s/m")
        if self.k_hertz is not None:
            _check_all("k_hertz", self.k_hertz, check_positive, "N/m^1.5")
        else:
            _check_all("material", self.material, _material)
        _check_all("v0", self.v0, _check_nonzero)
        _check_all("distance", self.distance, check_positive, "m")
        _check_all("angle", self.angle, check_range, 0.0, math.pi, unit="rad")
        _check_all("config", self.config, check_choice, _CONFIGS)
        for cfg in self.config:
            if cfg != "free":
                for a in self.angle:
                    if a > math.pi / 2 + 1e-12:
                        raise ParameterError(
                            "angle", f"must be <= pi/2 rad (90 deg) with a reflecting surface, got {a:g} rad")
        # build every design now so that bad combinations fail before any work
        self.designs()

    @property
    def masses(self) -> tuple[float, ...]:
        """Impact masses in kg (from ``mass_ratio`` × M when ratios were given)."""
        if self.m is not None:
            return self.m
        return tuple(float(r * self.settings.M) for r in self.mass_ratio)

    @property
    def shape(self) -> tuple[int, ...]:
        """Number of values along each of :attr:`AXES`."""
        return tuple(len(self._axis(a)) for a in self.AXES)

    def _axis(self, name):
        if name == "m":
            return self.masses
        if name == "material":
            return self.material if self.material is not None else ("",)
        if name == "k_hertz":
            return self.k_hertz if self.k_hertz is not None else (math.nan,)
        return getattr(self, name)

    def swept(self) -> tuple[str, ...]:
        """Names of the axes with more than one value."""
        return tuple(a for a, n in zip(self.AXES, self.shape, strict=True) if n > 1)

    def designs(self) -> tuple[Design, ...]:
        """Every design of the grid, in grid order (``design_id`` = position)."""
        s = self.settings
        out = []
        for i, vals in enumerate(itertools.product(*(self._axis(a) for a in self.AXES))):
            cfg, mat, kh, c1, v0, dist, ang, gap, m = vals
            radius = sphere_radius(m, s, mat or None)
            if mat:
                from .contact import hertz_stiffness

                sphere_mat = _material("material", mat)
                surf = _material("surface", s.surface) if s.surface else sphere_mat
                kh = float(hertz_stiffness(radius, sphere_mat, surf))
            if cfg == "wall-floor" and s.wall_distance < radius:
                raise ParameterError(
                    "wall_distance", f"must be >= the sphere radius {radius:g} m, got {s.wall_distance:g} m")
            if dist <= radius:
                raise ParameterError("distance", f"must exceed the sphere radius {radius:g} m, got {dist:g} m")
            out.append(Design(i, float(gap), float(m), float(c1), float(kh), mat, float(v0), float(dist),
                              float(ang), cfg, radius))
        return tuple(out)

    def to_dict(self) -> dict:
        """All settings as plain JSON-able values."""
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "settings"}
        d = {k: (list(v) if v is not None else None) for k, v in d.items()}
        d["settings"] = asdict(self.settings)
        return d

    @classmethod
    def from_dict(cls, d: dict) -> SweepSpec:
        """Inverse of :meth:`to_dict`."""
        d = dict(d)
        settings = Settings(**d.pop("settings"))
        kw = {k: (tuple(v) if v is not None else None) for k, v in d.items()}
        return cls(**kw, settings=settings)


def _check_nonzero(name, v):
    v = float(v)
    if not math.isfinite(v) or v == 0.0:
        raise ParameterError(name, f"must be a finite non-zero velocity in m/s, got {v!r}")


def _material(name, value):
    from .materials import material

    try:
        return material(value)
    except ParameterError as exc:
        raise ParameterError(name, str(exc).split(": ", 1)[-1]) from None


# --------------------------------------------------------------------------- one design
def sphere_radius(mass: float, settings: Settings, material: str | None = None) -> float:
    """Radius in m of the radiating sphere of an impact mass (see the module notes).

    Parameters
    ----------
    mass : float
        Impact mass in kg.
    settings : Settings
        ``radius_mode``, ``radius`` and ``density``.
    material : str, optional
        Sphere material, whose density is used when ``settings.density`` is None.

    Returns
    -------
    float
        ``settings.radius`` (fixed) or ``(3 m / (4 π ρ))^(1/3)`` (from the mass).

    Examples
    --------
    >>> round(sphere_radius(0.0405, Settings(radius_mode="from-mass")), 5)
    0.01077
    """
    if settings.radius_mode == "fixed":
        return float(settings.radius)
    rho = settings.density
    if rho is None:
        rho = _material("material", material).density if material else 7800.0
    return float((3.0 * mass / (4.0 * math.pi * rho)) ** (1.0 / 3.0))


def listener_point(config, distance: float, angle: float) -> np.ndarray:
    """Listener position in m, ``distance`` from the sphere's centre, ``angle`` rad off its axis.

    The listener lies in the plane of the acceleration axis and the horizontal direction away
    from any wall (+x), like the command-line ``--distance``/``--angle`` observer.

    Parameters
    ----------
    config : acoustiviz.images.Configuration
        The sphere and its images.
    distance : float
        Distance in m (> the sphere radius).
    angle : float
        Polar angle in rad from the acceleration axis.

    Returns
    -------
    (1, 3) ndarray
    """
    point = observer_points(config, distance, angle)[0]
    if not bool(config.in_fluid(point[None, :])[0]):
        raise ParameterError("angle", "the listener would lie inside a wall or below the floor")
    return point[None, :]


def impact_spl_db(velocity: float, *, mass: float, partner_mass: float, k_hertz: float, pulse: str,
                  config, point, medium) -> float:
    """Peak sound pressure level in dB re 20 µPa of one impact at one listener.

    Parameters
    ----------
    velocity : float
        Approach speed in m/s.
    mass : float
        Sphere (impact) mass in kg.
    partner_mass : float
        Mass of the struck body in kg (``inf``: an immovable wall, paper eq 3).
    k_hertz : float
        Hertz stiffness in N/m^1.5.
    pulse : str
        Pulse kind (:func:`acoustiviz.contact.acceleration_pulse`).
    config : acoustiviz.images.Configuration
        Sphere and images.
    point : (1, 3) array_like
        Listener in m.
    medium : acoustiviz.medium.Medium
        The air.

    Returns
    -------
    float
        ``20 log10(max|p| / 20 µPa)``.
    """
    from .contact import Impact, acceleration_pulse
    from .field import field_metrics

    imp = Impact(velocity=float(velocity), k_hertz=k_hertz, mass=mass, partner_mass=partner_mass)
    return float(field_metrics(acceleration_pulse(imp, pulse), point, config, medium=medium).peak_spl_db[0])


def max_spl_db(velocities, *, n_fastest: int = 4, **impact_kwargs) -> tuple[float, int]:
    """Largest peak SPL in dB over impacts of the given approach speeds.

    Evaluates the ``n_fastest`` fastest distinct speeds exactly (:func:`impact_spl_db`); the
    level grows with the speed at fixed geometry (module notes), so the fastest is the loudest.
    If the evaluated levels are not ordered like their speeds, every impact is evaluated.

    Parameters
    ----------
    velocities : (n,) array_like
        Approach speeds in m/s of the impacts (non-positive and NaN entries are ignored).
    n_fastest : int
        Number of fastest distinct speeds evaluated; 0 evaluates every impact.
    **impact_kwargs
        Passed to :func:`impact_spl_db`.

    Returns
    -------
    spl : float
        Maximum peak SPL in dB (``-inf`` without impacts).
    n_evaluated : int
        Number of impacts whose level was computed.
    """
    u = np.asarray(velocities, dtype=float)
    u = np.unique(u[np.isfinite(u) & (u > 0)])[::-1]  # distinct, fastest first
    if u.size == 0:
        return -math.inf, 0
    k = u.size if n_fastest == 0 else min(int(n_fastest), u.size)
    levels = [impact_spl_db(v, **impact_kwargs) for v in u[:k]]
    if k < u.size and any(b > a + 1e-9 for a, b in zip(levels, levels[1:], strict=False)):
        levels += [impact_spl_db(v, **impact_kwargs) for v in u[k:]]
        k = u.size
    return float(max(levels)), int(k)


@dataclass(frozen=True)
class DesignResult:
    """What one design gives; one row of ``sweep.csv`` (units in the column names)."""

    design: Design
    inclination_two_maxima: float
    inclination_fit: float
    fit_window_start: float
    fit_window_stop: float
    fit_n_maxima: int
    settling_time: float
    n_impacts: int
    max_spl_db: float
    energy_dissipated_contact: float
    energy_dissipated_main: float
    max_approach_velocity: float
    spl_impacts_evaluated: int
    success: bool
    mass_ratio: float

    def row(self) -> dict:
        """The CSV row as a dict of column name to value."""
        d = self.design
        return {
            "gap_m": d.gap, "mass_kg": d.m,
            "inclination_two_maxima_m_s": self.inclination_two_maxima,
            "inclination_fit_m_s": self.inclination_fit,
            "settling_time_s": self.settling_time, "n_impacts": self.n_impacts,
            "max_spl_db": self.max_spl_db, "design_id": d.design_id, "mass_ratio": self.mass_ratio,
            "c1_n_s_m": d.c1, "k_hertz_n_m1_5": d.k_hertz, "material": d.material, "v0_m_s": d.v0,
            "distance_m": d.distance, "angle_deg": math.degrees(d.angle), "config": d.config,
            "radius_m": d.radius,
            "energy_dissipated_contact_j": self.energy_dissipated_contact,
            "energy_dissipated_main_j": self.energy_dissipated_main,
            "max_approach_velocity_m_s": self.max_approach_velocity,
            "fit_window_start_s": self.fit_window_start, "fit_window_stop_s": self.fit_window_stop,
            "fit_n_maxima": self.fit_n_maxima, "spl_impacts_evaluated": self.spl_impacts_evaluated,
            "success": int(self.success),
        }


def evaluate_design(design: Design, settings: Settings) -> DesignResult:
    """Simulate one damper design and radiate its impacts (the work of one sweep row).

    Parameters
    ----------
    design : Design
        The design.
    settings : Settings
        The sweep's fixed settings.

    Returns
    -------
    DesignResult

    Notes
    -----
    The damper runs with :func:`acoustiviz.dynamics.simulate` from x = 0, dx/dt = ``v0``, the
    impact mass centred at rest (paper Figure 5 start); the maxima of x(t) are located on
    ``samples_per_period`` samples per main period (:mod:`acoustiviz.dynamics.metrics`).
    """
    from .dynamics import DamperModel, InitialState, simulate
    from .dynamics import metrics as dm
    from .images import configuration
    from .medium import Medium

    s = settings
    model = DamperModel(M=s.M, K=s.K, C=s.C, m=design.m, gap=design.gap, k_hertz=design.k_hertz,
                        c1=design.c1, clip_tensile=s.clip_tensile)
    t = dm.sample_times(s.duration, model, s.samples_per_period)
    res = simulate(model, s.duration, solver=s.solver, initial=InitialState(v=design.v0), rtol=s.rtol, t_eval=t)
    metrics = dm.damping_metrics(res.t, res.x, window_fraction=s.fit_window_fraction,
                                 settling_fraction=s.settling_fraction)
    two, fit, settle = metrics.two_maxima, metrics.fit, metrics.settling_time
    conf = configuration(design.config, design.radius,
                         wall_distance=s.wall_distance if design.config == "wall-floor" else None)
    point = listener_point(conf, design.distance, design.angle)
    u = res.impacts.approach_velocity
    spl, n_eval = max_spl_db(
        u, n_fastest=s.n_fastest, mass=design.m,
        partner_mass=math.inf if s.pulse_mass == "impact" else s.M,
        k_hertz=design.k_hertz, pulse=s.pulse, config=conf, point=point, medium=Medium(c=s.c, rho=s.rho),
    )
    return DesignResult(
        design=design,
        inclination_two_maxima=float(two.value),
        inclination_fit=float(fit.value),
        fit_window_start=float(fit.t_start),
        fit_window_stop=float(fit.t_stop),
        fit_n_maxima=int(fit.n_maxima),
        settling_time=float(settle),
        n_impacts=len(res.impacts),
        max_spl_db=spl,
        energy_dissipated_contact=float(res.energy.dissipated_contact),
        energy_dissipated_main=float(res.energy.dissipated_main),
        max_approach_velocity=float(np.max(u)) if u.size else 0.0,
        spl_impacts_evaluated=n_eval,
        success=bool(res.success),
        mass_ratio=design.m / s.M,
    )


def _worker_init(settings: Settings) -> None:
    """Process-pool initializer: leave Ctrl-C to the parent and load the compiled kernels once."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _warm_up(settings)


def _warm_up(settings: Settings) -> None:
    """Run a tiny design so that numba kernels are compiled or loaded from cache before timing."""
    tiny = replace(settings, duration=0.05)
    evaluate_design(Design(-1, 0.04, 0.0405, 20.0, 5.6e8, "", 2.0, 0.7, math.pi / 4, "plane", 0.01905), tiny)


# --------------------------------------------------------------------------- progress
class Progress:
    """A plain-text progress bar with count and ETA, on a text stream (stderr by default).

    Parameters
    ----------
    total : int
        Designs to compute in this run.
    done_before : int
        Designs already finished by earlier runs (shown, not timed).
    stream : text stream, optional
        Where to write; ``None`` writes nothing.
    min_interval : float
        Seconds between redraws (the last one is always drawn).
    """

    def __init__(self, total: int, done_before: int = 0, stream=None, min_interval: float = 0.25):
        self.total = int(total)
        self.done_before = int(done_before)
        self.count = 0
        self.stream = stream
        self.min_interval = float(min_interval)
        self._t0 = time.perf_counter()
        self._last = -math.inf
        self._tty = bool(stream is not None and getattr(stream, "isatty", lambda: False)())
        self._drawn = -1

    def line(self) -> str:
        """The current progress text, e.g. ``[#####-----] 12/24 designs  50%  2.0 s  ETA 2.0 s``."""
        n, tot = self.count, self.total
        frac = n / tot if tot else 1.0
        width = 24
        bar = "#" * int(round(frac * width))
        elapsed = time.perf_counter() - self._t0
        eta = elapsed / n * (tot - n) if n else math.nan
        prev = f" (+{self.done_before} done before)" if self.done_before else ""
        eta_s = f"ETA {_fmt_seconds(eta)}" if n else "ETA --"
        return (f"sweep [{bar:-<{width}}] {n}/{tot} designs{prev} {100 * frac:3.0f}%  "
                f"elapsed {_fmt_seconds(elapsed)}  {eta_s}")

    def update(self, n: int = 1) -> None:
        """Count ``n`` finished designs and redraw if due."""
        self.count += n
        now = time.perf_counter()
        if self.stream is None:
            return
        if self.count >= self.total or now - self._last >= self.min_interval:
            self._last = now
            self._write()

    def _write(self):
        self._drawn = self.count
        if self._tty:
            self.stream.write("\r" + self.line())
        else:
            self.stream.write(self.line() + "\n")
        self.stream.flush()

    def close(self) -> None:
        """Draw the final state and end the line."""
        if self.stream is None:
            return
        if self._drawn != self.count:
            self._write()
        if self._tty:
            self.stream.write("\n")
        self.stream.flush()


def _fmt_seconds(s: float) -> str:
    if not math.isfinite(s):
        return "--"
    if s < 60:
        return f"{s:.1f} s"
    m, sec = divmod(int(round(s)), 60)
    h, m = divmod(m, 60)
    return f"{h}:{m:02d}:{sec:02d}" if h else f"{m}:{sec:02d}"


# --------------------------------------------------------------------------- files
def _spec_json(spec: SweepSpec) -> dict:
    from . import __version__

    return {"format": _FORMAT, "format_version": _FORMAT_VERSION, "written_by": f"acoustiviz {__version__}",
            "spec": spec.to_dict()}


def read_spec(out_dir) -> SweepSpec:
    """The :class:`SweepSpec` stored in ``out_dir/sweep.json``."""
    path = Path(out_dir) / SWEEP_JSON
    if not path.is_file():
        raise ParameterError("sweep", f"{out_dir} holds no {SWEEP_JSON}: not a sweep directory")
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        if doc.get("format") != _FORMAT:
            raise ValueError("not an acoustiviz sweep")
        return SweepSpec.from_dict(doc["spec"])
    except (ValueError, KeyError, TypeError) as exc:
        raise ParameterError("sweep", f"cannot read {path}: {exc}") from None


def _differences(a: dict, b: dict, prefix="") -> list[str]:
    out = []
    for k in sorted(set(a) | set(b)):
        va, vb = a.get(k), b.get(k)
        if isinstance(va, dict) and isinstance(vb, dict):
            out += _differences(va, vb, prefix + k + ".")
        elif va != vb:
            out.append(f"{prefix}{k}: {va!r} there, {vb!r} now")
    return out


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - platforms without directory fds
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(fd)


def _prepare_dir(spec: SweepSpec, out: Path, overwrite: bool) -> None:
    """Create ``out`` with ``sweep.json`` or check that it holds the same settings."""
    from ._io import write_text_atomic

    out.mkdir(parents=True, exist_ok=True)
    path = out / SWEEP_JSON
    want = _spec_json(spec)
    if path.is_file():
        try:
            have = json.loads(path.read_text(encoding="utf-8"))
        except ValueError:
            have = {}
        diffs = _differences(have.get("spec", {}), want["spec"])
        if have.get("format") != _FORMAT:
            diffs = diffs or ["not an acoustiviz sweep.json"]
        if diffs and not overwrite:
            shown = "; ".join(diffs[:4]) + (f"; and {len(diffs) - 4} more" if len(diffs) > 4 else "")
            raise SweepMismatch(
                "out",
                f"{out} holds a sweep made with different settings ({shown}); use another directory, "
                "or overwrite it (--overwrite) to start afresh",
            )
        if not diffs:
            return
        old = out / SWEEP_CSV
        if old.exists():
            os.replace(old, out / "sweep.previous.csv")
        for name in (DESIGN_TABLE_CSV,):
            if (out / name).exists():
                (out / name).unlink()
    elif (out / SWEEP_CSV).exists() and not overwrite:
        raise SweepMismatch("out", f"{out} has a {SWEEP_CSV} but no {SWEEP_JSON}; use another directory or "
                                   "--overwrite")
    elif (out / SWEEP_CSV).exists():
        os.replace(out / SWEEP_CSV, out / "sweep.previous.csv")
    write_text_atomic(path, json.dumps(want, indent=2) + "\n")


def _format_value(v) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    return repr(float(v))


def _read_rows(path: Path, spec: SweepSpec) -> dict[int, dict]:
    """Finished rows of ``sweep.csv`` keyed by design id; a torn last line is cut off the file."""
    if not path.exists():
        return {}
    raw = path.read_bytes()
    if raw and not raw.endswith(b"\n"):  # killed in the middle of a row: drop the partial line
        cut = raw.rfind(b"\n") + 1
        with open(path, "r+b") as f:
            f.truncate(cut)
            f.flush()
            os.fsync(f.fileno())
        raw = raw[:cut]
    text = raw.decode("utf-8")
    lines = text.splitlines()
    if not lines:
        return {}
    header = next(csv.reader([lines[0]]))
    if tuple(header) != _ALL_COLUMNS:
        raise SweepMismatch("out", f"{path} has other columns than this version writes; use another directory")
    designs = spec.designs()
    rows: dict[int, dict] = {}
    for k, line in enumerate(lines[1:], start=2):
        vals = next(csv.reader([line]))
        if len(vals) != len(header):
            raise ParameterError("out", f"{path} line {k} is damaged ({len(vals)} fields, {len(header)} expected)")
        row = dict(zip(header, vals, strict=True))
        try:
            did = int(row["design_id"])
            d = designs[did]
            same = (math.isclose(float(row["gap_m"]), d.gap, rel_tol=1e-12)
                    and math.isclose(float(row["mass_kg"]), d.m, rel_tol=1e-12))
        except (ValueError, IndexError):
            same = False
        if not same:
            raise ParameterError("out", f"{path} line {k} does not match a design of {SWEEP_JSON}")
        rows.setdefault(did, row)
    return rows


def _open_csv(path: Path):
    new = not path.exists() or path.stat().st_size == 0
    f = open(path, "a", encoding="utf-8", newline="")  # noqa: SIM115 - closed by the caller
    if new:
        f.write(",".join(_ALL_COLUMNS) + "\n")
        f.flush()
        os.fsync(f.fileno())
        _fsync_dir(path.parent)
    return f


def _write_row(f, result: DesignResult) -> None:
    row = result.row()
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([_format_value(row[c]) for c in _ALL_COLUMNS])
    f.write(buf.getvalue())
    f.flush()
    os.fsync(f.fileno())


def _make_executor(executor, workers, settings, n_tasks):
    """Return ``(executor, owned, cleanup)``; a local pool has at most ``n_tasks`` processes."""
    if isinstance(executor, Executor):
        return executor, False, None
    if executor is None or executor == "process":
        from concurrent.futures import ProcessPoolExecutor

        n = (os.cpu_count() or 1) if workers is None else int(workers)
        if n < 1:
            raise ParameterError("workers", f"must be >= 1, got {workers}")
        _warm_up(settings)  # forked workers inherit the loaded kernels
        n = max(1, min(n, int(n_tasks)))
        return ProcessPoolExecutor(max_workers=n, initializer=_worker_init, initargs=(settings,)), True, None
    if isinstance(executor, str) and executor.startswith("dask://"):
        address = executor[len("dask://"):]
        if not address:
            raise ParameterError("executor", "expected dask://HOST:PORT")
        try:
            from distributed import Client
        except ImportError:
            raise ParameterError(
                "executor", "dask:// needs the optional dependency: pip install 'acoustiviz[distributed]'") from None
        try:
            client = Client(address if "://" in address else f"tcp://{address}", timeout=20)
        except OSError as exc:
            raise ParameterError("executor", f"cannot reach the Dask scheduler at {address}: {exc}") from None
        return client.get_executor(), True, client.close
    raise ParameterError("executor", f"expected 'process', 'dask://HOST:PORT' or an Executor, got {executor!r}")


def _shutdown_now(ex: Executor) -> None:
    """Shut ``ex`` down without waiting, cancelling what has not started."""
    try:
        ex.shutdown(wait=False, cancel_futures=True)
    except TypeError:  # executors without cancel_futures (e.g. Dask's ClientExecutor)
        ex.shutdown(wait=False)


@dataclass(frozen=True)
class SweepTable:
    """The rows of a sweep, ordered by design id.

    Attributes
    ----------
    spec : SweepSpec
        The sweep's settings.
    columns : dict
        Column name (those of ``sweep.csv``) to a 1-D array; text columns are arrays of str.
    """

    spec: SweepSpec
    columns: dict

    def __len__(self) -> int:
        return int(self.columns["design_id"].size)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    @property
    def complete(self) -> bool:
        """True when every design of the spec has a row."""
        return len(self) == len(self.spec.designs())

    def subset(self, mask) -> SweepTable:
        """The rows where the boolean ``mask`` (one entry per row) is True."""
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != (len(self),):
            raise ParameterError("mask", f"expected {len(self)} booleans, got shape {mask.shape}")
        cols = {}
        for k, v in self.columns.items():
            a = v[mask]
            a.setflags(write=False)
            cols[k] = a
        return SweepTable(self.spec, cols)

    def inclination(self, definition: str = "two-maxima") -> np.ndarray:
        """Damping inclination in m/s by ``definition`` (``"two-maxima"``, paper eq 16, or ``"fit"``)."""
        check_choice("definition", definition, DEFINITIONS)
        return self.columns["inclination_two_maxima_m_s" if definition == "two-maxima" else "inclination_fit_m_s"]

    def grid(self, name: str) -> np.ndarray:
        """Column ``name`` on the gap × mass grid, shape ``(n_gap, n_mass)`` (NaN where missing).

        Only for sweeps whose other axes hold a single value.
        """
        spec = self.spec
        others = [a for a in spec.swept() if a not in ("gap", "m")]
        if others:
            raise ParameterError("table", f"a gap x mass map needs the other axes fixed; swept also: {others}")
        ng, nm = len(spec.gap), len(spec.masses)
        out = np.full(ng * nm, np.nan)
        out[self.columns["design_id"]] = self.columns[name]
        return out.reshape(ng, nm)


def _table_from_rows(spec: SweepSpec, rows: dict[int, dict]) -> SweepTable:
    ids = sorted(rows)
    cols = {}
    for c in _ALL_COLUMNS:
        vals = [rows[i][c] for i in ids]
        if c in _TEXT_COLUMNS:
            cols[c] = np.array(vals, dtype=str)
        elif c in ("design_id", "n_impacts", "fit_n_maxima", "spl_impacts_evaluated", "success"):
            cols[c] = np.array([int(v) for v in vals], dtype=int)
        else:
            cols[c] = np.array([float(v) for v in vals], dtype=float)
    for a in cols.values():
        a.setflags(write=False)
    return SweepTable(spec, cols)


def load_sweep(out_dir) -> SweepTable:
    """Read a sweep directory (finished or not) into a :class:`SweepTable`.

    Parameters
    ----------
    out_dir : path-like
        Directory written by :func:`run_sweep`.
    """
    out = Path(out_dir)
    spec = read_spec(out)
    path = out / SWEEP_CSV
    if not path.is_file():
        raise ParameterError("sweep", f"{out} holds no {SWEEP_CSV}")
    return _table_from_rows(spec, _read_rows(path, spec))


def run_sweep(spec: SweepSpec, out_dir, *, executor=None, workers: int | None = None, progress=None,
              overwrite: bool = False) -> SweepTable:
    """Run (or resume) a sweep, one CSV row per finished design.

    Parameters
    ----------
    spec : SweepSpec
        The designs and settings.
    out_dir : path-like
        Directory for ``sweep.json`` and ``sweep.csv`` (created if needed). If it already holds
        this sweep, only the missing designs are computed; a finished sweep computes nothing.
    executor : None, "process", "dask://HOST:PORT" or concurrent.futures.Executor
        Where designs run. None or ``"process"``: a local process pool of ``workers`` processes
        (default: all cores). ``"dask://HOST:PORT"``: a Dask distributed scheduler (optional
        dependency). An Executor instance is used as given and not shut down.
    workers : int, optional
        Processes of the local pool (default ``os.cpu_count()``).
    progress : text stream, optional
        Where to draw the progress bar (e.g. ``sys.stderr``); None: silent.
    overwrite : bool
        If ``out_dir`` holds a sweep made with other settings, move its ``sweep.csv`` aside to
        ``sweep.previous.csv`` and start afresh (default: refuse with :class:`SweepMismatch`).

    Returns
    -------
    SweepTable
        Every row of the directory.

    Notes
    -----
    Each finished design is appended to ``sweep.csv``, flushed and synced before the next one
    is taken, so a kill loses at most the designs being computed. On ``KeyboardInterrupt`` the
    pending designs are cancelled and the interrupt propagates; the rows written stay.
    """
    if not isinstance(spec, SweepSpec):
        raise ParameterError("spec", f"expected a SweepSpec, got {type(spec).__name__}")
    if workers is not None and (int(workers) != workers or workers < 1):
        raise ParameterError("workers", f"must be an integer >= 1, got {workers!r}")
    out = Path(out_dir)
    _prepare_dir(spec, out, overwrite)
    path = out / SWEEP_CSV
    rows = _read_rows(path, spec)
    designs = spec.designs()
    pending = [d for d in designs if d.design_id not in rows]
    if not pending:
        if progress is not None:
            progress.write(f"sweep: all {len(designs)} designs already in {path}; nothing to compute\n")
            progress.flush()
        return _table_from_rows(spec, rows)
    ex, owned, cleanup = _make_executor(executor, workers, spec.settings, len(pending))
    bar = Progress(len(pending), len(rows), progress)  # timed from here: start-up is not design time
    f = _open_csv(path)
    futures = []
    try:
        futures = [ex.submit(evaluate_design, d, spec.settings) for d in pending]
        for fut in as_completed(futures):
            res = fut.result()
            _write_row(f, res)
            rows[res.design.design_id] = {k: _format_value(v) for k, v in res.row().items()}
            bar.update()
        bar.close()
    except BaseException:
        for fut in futures:
            fut.cancel()
        if owned:
            _shutdown_now(ex)
            owned = False
        if progress is not None:
            progress.write(f"\nsweep: stopped; {len(rows)} of {len(designs)} designs kept in {path}\n")
            progress.flush()
        raise
    finally:
        f.close()
        if owned:
            ex.shutdown(wait=True)
        if cleanup is not None:
            cleanup()
    return _table_from_rows(spec, rows)


# --------------------------------------------------------------------------- design table
@dataclass(frozen=True)
class Band:
    """One row of the design table (paper Table 2).

    Attributes
    ----------
    centre, low, high : float
        Band of damping inclination in m/s: ``low <= e < high``, ``centre`` its middle.
    n_designs : int
        Designs in the band.
    min_spl_db, max_spl_db : float
        Smallest and largest maximum SPL in dB of those designs.
    decrease_db : float
        ``max_spl_db - min_spl_db``: what the acoustic-based choice saves.
    quietest_gap, quietest_mass : float
        Design (m, kg) attaining the minimum.
    loudest_gap, loudest_mass : float
        Design (m, kg) attaining the maximum.
    """

    centre: float
    low: float
    high: float
    n_designs: int
    min_spl_db: float
    max_spl_db: float
    decrease_db: float
    quietest_gap: float
    quietest_mass: float
    loudest_gap: float
    loudest_mass: float


#: Columns of ``design_table.csv``.
DESIGN_TABLE_COLUMNS = (
    "inclination_m_s", "band_low_m_s", "band_high_m_s", "n_designs", "min_max_spl_db", "max_max_spl_db",
    "decrease_db", "quietest_gap_m", "quietest_mass_kg", "loudest_gap_m", "loudest_mass_kg",
)


def design_table(table: SweepTable, *, definition: str = "two-maxima", width: float = 0.001,
                 centres=None) -> tuple[Band, ...]:
    """Paper Table 2: per band of damping inclination, the range of the maximum SPL.

    Parameters
    ----------
    table : SweepTable
        Sweep rows.
    definition : {"two-maxima", "fit"}
        Inclination definition (default paper eq 16).
    width : float
        Band width in m/s (default 0.001 m/s = 0.1 cm/s, as in Table 2).
    centres : array_like, optional
        Band centres in m/s; default every multiple of ``width`` whose band holds a design.

    Returns
    -------
    tuple of Band
        Bands holding at least one design, in increasing inclination. A band is
        ``[centre - width/2, centre + width/2)``.
    """
    w = check_positive("width", width, "m/s")
    e = np.asarray(table.inclination(definition), dtype=float)
    spl = np.asarray(table["max_spl_db"], dtype=float)
    ok = np.isfinite(e) & np.isfinite(spl)
    if centres is None:
        if not np.any(ok):
            return ()
        k = np.floor(e[ok] / w + 0.5)
        centres = np.unique(k) * w
    bands = []
    for c in np.asarray(centres, dtype=float):
        lo, hi = c - w / 2, c + w / 2
        sel = np.flatnonzero(ok & (e >= lo) & (e < hi))
        if sel.size == 0:
            continue
        bands.append(_band(table, sel, spl, float(np.round(c, 12)), float(np.round(lo, 12)),
                           float(np.round(hi, 12))))
    return tuple(bands)


def _band(table, sel, spl, centre, lo, hi) -> Band:
    i_min = sel[np.argmin(spl[sel])]
    i_max = sel[np.argmax(spl[sel])]
    g, m = table["gap_m"], table["mass_kg"]
    return Band(centre, float(lo), float(hi), int(sel.size), float(spl[i_min]), float(spl[i_max]),
                float(spl[i_max] - spl[i_min]), float(g[i_min]), float(m[i_min]), float(g[i_max]), float(m[i_max]))


def write_design_table(bands, path) -> Path:
    """Write bands as ``design_table.csv`` (columns :data:`DESIGN_TABLE_COLUMNS`) atomically."""
    from ._io import write_text_atomic

    lines = [",".join(DESIGN_TABLE_COLUMNS)]
    for b in bands:
        lines.append(",".join(_format_value(v) for v in (
            b.centre, b.low, b.high, b.n_designs, b.min_spl_db, b.max_spl_db, b.decrease_db,
            b.quietest_gap, b.quietest_mass, b.loudest_gap, b.loudest_mass)))
    return write_text_atomic(path, "\n".join(lines) + "\n")


@dataclass(frozen=True)
class DesignChoice:
    """Answer of :func:`design`: the quietest design among those that damp as asked.

    Attributes
    ----------
    inclination, tolerance : float
        Target damping inclination and tolerance in m/s.
    definition : str
        Inclination definition used.
    n_candidates : int
        Designs with ``|e - inclination| <= tolerance``.
    quietest, loudest : dict or None
        Row (column name to value) of the quietest and of the loudest candidate; None when no
        design lies within the tolerance.
    saving_db : float
        Maximum SPL of the loudest minus that of the quietest candidate, in dB (NaN without
        candidates).
    nearest : tuple of dict
        The designs whose inclination is closest to the target (up to three), for a target
        that no design meets.
    span : tuple of float
        Smallest and largest inclination of the sweep in m/s.
    """

    inclination: float
    tolerance: float
    definition: str
    n_candidates: int
    quietest: dict | None
    loudest: dict | None
    saving_db: float
    nearest: tuple = ()
    span: tuple = (math.nan, math.nan)

    def summary(self) -> str:
        """A few lines of plain text for the command line."""
        q, lo = self.quietest, self.loudest
        if q is None:
            lines = [f"no design has a {self.definition} damping inclination within {self.tolerance:g} m/s of "
                     f"{self.inclination:g} m/s; the sweep spans [{self.span[0]:.4g}, {self.span[1]:.4g}] m/s",
                     "nearest designs (widen --tolerance or the sweep to include them):"]
            lines += [f"  m = {r['mass_kg']:.6g} kg, d = {r['gap_m']:.6g} m, inclination {r['inclination']:.6g} m/s, "
                      f"max SPL {r['max_spl_db']:.2f} dB" for r in self.nearest]
            return "\n".join(lines)
        return "\n".join([
            f"designs with {self.definition} damping inclination {self.inclination:g} +/- {self.tolerance:g} m/s: "
            f"{self.n_candidates}",
            f"quietest: m = {q['mass_kg']:.6g} kg, d = {q['gap_m']:.6g} m, max SPL {q['max_spl_db']:.2f} dB, "
            f"inclination {q['inclination']:.6g} m/s",
            f"loudest:  m = {lo['mass_kg']:.6g} kg, d = {lo['gap_m']:.6g} m, max SPL {lo['max_spl_db']:.2f} dB, "
            f"inclination {lo['inclination']:.6g} m/s",
            f"the quietest is {self.saving_db:.2f} dB quieter than the loudest",
        ])


def design(table: SweepTable, inclination: float, tolerance: float, *,
           definition: str = "two-maxima") -> DesignChoice:
    """For a target damping inclination within a tolerance, the quietest (m, d) and its saving.

    Parameters
    ----------
    table : SweepTable
        Sweep rows.
    inclination : float
        Target damping inclination in m/s (e.g. 0.008 m/s = 0.8 cm/s).
    tolerance : float
        Accepted deviation in m/s (>= 0).
    definition : {"two-maxima", "fit"}
        Inclination definition (default paper eq 16).

    Returns
    -------
    DesignChoice

    When no design lies within the tolerance the answer says so: no candidates, and the
    (up to three) designs nearest the target in ``nearest``.

    Raises
    ------
    ParameterError
        If the sweep holds no finished design.
    """
    target = check_range("inclination", inclination, -math.inf, math.inf)
    tol = check_nonnegative("tolerance", tolerance, "m/s")
    e = np.asarray(table.inclination(definition), dtype=float)
    spl = np.asarray(table["max_spl_db"], dtype=float)
    ok = np.isfinite(e) & np.isfinite(spl)
    if not np.any(ok):
        raise ParameterError("sweep", "the sweep holds no finished design")
    span = (float(np.min(e[ok])), float(np.max(e[ok])))

    def row(i):
        d = {c: table[c][i].item() for c in _ALL_COLUMNS}
        d["inclination"] = float(e[i])
        return d

    sel = np.flatnonzero(ok & (np.abs(e - target) <= tol * (1 + 1e-12)))
    if sel.size == 0:
        valid = np.flatnonzero(ok)
        near = valid[np.argsort(np.abs(e[valid] - target), kind="stable")[:3]]
        return DesignChoice(target, tol, definition, 0, None, None, math.nan, tuple(row(i) for i in near), span)
    i_min = sel[np.argmin(spl[sel])]
    i_max = sel[np.argmax(spl[sel])]
    return DesignChoice(target, tol, definition, int(sel.size), row(i_min), row(i_max),
                        float(spl[i_max] - spl[i_min]), (), span)
