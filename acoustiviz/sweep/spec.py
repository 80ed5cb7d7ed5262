"""What a sweep computes: the values of each axis, the fixed settings and the grid of designs.

A :class:`SweepSpec` is the Cartesian product of the swept values (gap, impact mass, contact
damping, stiffness or material, initial velocity, listener distance and angle, configuration)
and one :class:`FixedSettings` of everything held fixed. Everything is validated when the spec is
built, so that a bad combination fails before any design runs. SI units; angles in radians.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import asdict, dataclass, field, fields

from .._validate import check_choice, check_nonnegative, check_positive, check_range
from ..constants import (
    DEFAULT_AIR_DENSITY,
    DEFAULT_DURATION,
    DEFAULT_RTOL,
    DEFAULT_SOUND_SPEED,
    DEFAULT_WALL_DISTANCE,
    PAPER_DENSITY,
    PAPER_GAP,
    PAPER_RADIUS,
    PAPER_V0,
    PULSES,
    SOLVERS,
    TABLE1_PARAMETERS,
)
from ..core.geometry import GEOMETRIES, Geometry, geometry
from ..errors import ParameterError

__all__ = [
    "RADIUS_MODES",
    "PULSE_MASSES",
    "PAPER_RADIUS",
    "FixedSettings",
    "Design",
    "SweepSpec",
    "MAX_RANGE_COUNT",
    "parse_start_stop_count",
    "parse_values",
    "value_range",
    "sweep_sphere_radius",
]

#: How the radiating sphere's radius is chosen: the paper's fixed sphere, or from the impact mass.
RADIUS_MODES = ("fixed", "from-mass")
#: Mass in the pulse of an impact: the impact mass alone (paper eq 3) or the two bodies' effective mass.
PULSE_MASSES = ("impact", "effective")


# --------------------------------------------------------------------------- values and ranges
#: Most values a ``start:stop:count`` range may hold.
MAX_RANGE_COUNT = 10000


def value_range(start: float, stop: float, count: int) -> tuple[float, ...]:
    """``count`` evenly spaced values from ``start`` to ``stop``, both included: the one range rule.

    Value i is ``start + i (stop - start) / (count - 1)`` rounded to 15 significant digits of
    the larger end, so that decimal steps give decimal values (0.03, not 0.030000000000000002)
    and a residue of cancellation gives 0; the ends are ``start`` and ``stop`` exactly. Every
    front-end (``acoustiviz sweep`` options and scene keys) builds its grids with this rule, so
    the same range is the same grid -- and one run can resume another's folder.

    Parameters
    ----------
    start, stop : float
        First and last value (any unit).
    count : int
        Number of values (1 to :data:`MAX_RANGE_COUNT`; 1 gives ``(start,)`` and requires
        ``start == stop``; more require ``stop > start``: a range is given in increasing order,
        by every front-end).

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> value_range(0.02, 0.06, 5)
    (0.02, 0.03, 0.04, 0.05, 0.06)
    >>> value_range(-0.1, 0.2, 4)
    (-0.1, 0.0, 0.1, 0.2)
    """
    n = int(count)
    if n != count or not 1 <= n <= MAX_RANGE_COUNT:
        raise ParameterError("count", f"must be an integer in [1, {MAX_RANGE_COUNT}], got {count!r}")
    start, stop = float(start), float(stop)
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise ParameterError("count", f"a range needs finite ends, got {start!r}:{stop!r}")
    if n == 1:
        if start != stop:
            raise ParameterError("count", f"a range of 1 value needs start == stop, got {start:g}:{stop:g}")
        return (start,)
    if not stop > start:
        raise ParameterError("count", f"a range of {n} values needs stop > start (give it in increasing order), "
                                      f"got {start:g}:{stop:g}")
    scale = max(abs(start), abs(stop))
    digits = 14 - math.floor(math.log10(scale)) if scale > 0 else 0
    inner = (round(start + i * (stop - start) / (n - 1), digits) + 0.0 for i in range(1, n - 1))
    return (start, *inner, stop)


def parse_start_stop_count(name: str, text: str) -> tuple[float, ...]:
    """Parse ``start:stop:count`` (both ends included) with :func:`value_range`.

    Parameters
    ----------
    name : str
        The option or key, named by errors (e.g. ``"--gap"`` or ``"outputs.sweep.gap_m"``).
    text : str
        The range.

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> parse_start_stop_count("--m", "0.02:0.08:4")
    (0.02, 0.04, 0.06, 0.08)
    """
    s = str(text).strip()
    parts = s.split(":")
    if len(parts) != 3:
        raise ParameterError(name, f"a range is 'start:stop:count' (both ends included), got {s!r}")
    try:
        start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise ParameterError(name, f"a range is 'start:stop:count' with an integer count, got {s!r}") from None
    try:
        return value_range(start, stop, count)
    except ParameterError as exc:
        raise ParameterError(name, f"{exc.detail} (in {s!r})") from None


def parse_values(name: str, text, kind=float) -> tuple:
    """Parse ``start:stop:count`` (inclusive, :func:`parse_start_stop_count`), ``a,b,c`` or a single value.

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
            return parse_start_stop_count(name, s)
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


def _check_nonzero(name, v):
    v = float(v)
    if not math.isfinite(v) or v == 0.0:
        raise ParameterError(name, f"must be a finite non-zero velocity in m/s, got {v!r}")


def _material(name, value):
    from ..core.materials import material

    try:
        return material(value)
    except ParameterError as exc:
        raise exc.renamed(name) from None


# --------------------------------------------------------------------------- specification
@dataclass(frozen=True)
class FixedSettings:
    """What stays fixed across a sweep (defaults: paper Table 1, Figure 5 start, Figure 2 sphere).

    The defaults are those of :mod:`acoustiviz.constants`, shared with every front-end.

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
    solver : {"event", "newmark", "impact-map"}
        Damper solver (:func:`acoustiviz.dynamics.simulate`).
    rtol : float
        Relative tolerance of the solver's contact integration
        (:data:`~acoustiviz.constants.DEFAULT_RTOL`; the motion is chaotic, so the late impacts --
        and the settling time -- are meaningful only statistically at any tolerance).
    radius_mode : {"fixed", "from-mass"}
        How the radiating sphere's radius is chosen (see :mod:`acoustiviz.sweep`).
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
    levels : bool
        Also report the LAFmax, LCpeak and LAeq of each run's click train at the listener over the
        run (:mod:`acoustiviz.sweep.levels`; about as costly as the motion, measured by
        ``benchmarks/bench_sweep.py``, so off by default: the columns are then empty).
    room : mapping or sequence of (key, value), optional
        The settings of a geometry that needs more than a radius (a shoebox room,
        :class:`acoustiviz.core.room_geometry.Room`: ``dimensions``, ``absorption``, ``source``,
        ``order``, ``tolerance_db``, ``duration``, ...); kept as sorted ``(key, value)`` pairs with
        tuples for sequences. Designs whose configuration is such a geometry are built with them.
    """

    M: float = TABLE1_PARAMETERS["M"]
    K: float = TABLE1_PARAMETERS["K"]
    C: float = TABLE1_PARAMETERS["C"]
    clip_tensile: bool = False
    duration: float = DEFAULT_DURATION
    solver: str = "event"
    rtol: float = DEFAULT_RTOL
    radius_mode: str = "fixed"
    radius: float = PAPER_RADIUS
    density: float | None = None
    surface: str | None = None
    pulse: str = "half-sine"
    pulse_mass: str = "impact"
    c: float = DEFAULT_SOUND_SPEED
    rho: float = DEFAULT_AIR_DENSITY
    wall_distance: float = DEFAULT_WALL_DISTANCE
    n_fastest: int = 4
    fit_window_fraction: float = 0.3
    settling_fraction: float = 0.05
    levels: bool = False
    room: tuple | None = None

    def __post_init__(self):
        check_positive("M", self.M, "kg")
        check_positive("K", self.K, "N/m")
        check_nonnegative("C", self.C, "N s/m")
        if not isinstance(self.clip_tensile, bool):
            raise ParameterError("clip_tensile", f"must be True or False, got {self.clip_tensile!r}")
        check_positive("duration", self.duration, "s")
        from ..dynamics import METHODS

        METHODS[check_choice("solver", self.solver, SOLVERS)].check_rtol(self.rtol)
        check_choice("radius_mode", self.radius_mode, RADIUS_MODES)
        check_positive("radius", self.radius, "m")
        if self.density is not None:
            check_positive("density", self.density, "kg/m^3")
        if self.surface is not None:
            _material("surface", self.surface)
        check_choice("pulse", self.pulse, PULSES)
        check_choice("pulse_mass", self.pulse_mass, PULSE_MASSES)
        check_positive("c", self.c, "m/s")
        check_positive("rho", self.rho, "kg/m^3")
        check_positive("wall_distance", self.wall_distance, "m")
        if int(self.n_fastest) != self.n_fastest or self.n_fastest < 0:
            raise ParameterError("n_fastest", f"must be an integer >= 0 (0: every impact), got {self.n_fastest!r}")
        check_range("fit_window_fraction", self.fit_window_fraction, 0.0, 1.0, low_open=True, high_open=True)
        check_range("settling_fraction", self.settling_fraction, 0.0, 1.0, low_open=True, high_open=True)
        if not isinstance(self.levels, bool):
            raise ParameterError("levels", f"must be True or False, got {self.levels!r}")
        if self.room is not None:
            items = self.room.items() if isinstance(self.room, dict) else self.room
            object.__setattr__(self, "room", tuple(sorted((str(k), _frozen(v)) for k, v in items)))

    @property
    def geometry_settings(self) -> dict:
        """The settings a design's geometry is built with beyond its radius (the room's and the sound speed)."""
        if self.room is None:
            return {"wall_distance": self.wall_distance}
        return {"wall_distance": self.wall_distance, "sound_speed": self.c, **dict(self.room)}


def _frozen(value):
    """``value`` with every list or tuple (recursively) a tuple: hashable and equal after a JSON round trip."""
    if isinstance(value, (list, tuple)):
        return tuple(_frozen(v) for v in value)
    return value


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
        Geometry name (:data:`acoustiviz.core.geometry.GEOMETRIES`, e.g. ``"plane"``).
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

    def geometry(self, settings: FixedSettings) -> Geometry:
        """The design's geometry: its configuration around its sphere, with the sweep's wall distance."""
        return geometry(self.config, self.radius, lenient=True, **settings.geometry_settings)


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
    settings : FixedSettings
        Everything else.

    Examples
    --------
    >>> spec = SweepSpec(gap=value_range(0.02, 0.06, 5), m=value_range(0.02, 0.08, 4))
    >>> len(spec.designs())
    20
    """

    gap: tuple = (PAPER_GAP,)
    m: tuple | None = None
    mass_ratio: tuple | None = None
    c1: tuple = (TABLE1_PARAMETERS["c1"],)
    k_hertz: tuple | None = None
    material: tuple | None = None
    v0: tuple = (PAPER_V0,)
    distance: tuple = (0.7,)
    angle: tuple = (math.pi / 4,)
    config: tuple = ("plane",)
    settings: FixedSettings = field(default_factory=FixedSettings)

    #: Order of the grid's axes; the last varies fastest.
    AXES = ("config", "material", "k_hertz", "c1", "v0", "distance", "angle", "gap", "m")

    def __post_init__(self):
        if self.m is not None and self.mass_ratio is not None:
            raise ParameterError("m", "give either m (kg) or mass_ratio (m/M), not both")
        if self.k_hertz is not None and self.material is not None:
            raise ParameterError("k_hertz", "give either k_hertz (N/m^1.5) or material, not both")
        if self.m is None and self.mass_ratio is None:
            object.__setattr__(self, "m", (TABLE1_PARAMETERS["m"],))
        if self.k_hertz is None and self.material is None:
            object.__setattr__(self, "k_hertz", (TABLE1_PARAMETERS["k_hertz"],))
        if not isinstance(self.settings, FixedSettings):
            raise ParameterError("settings", f"expected a FixedSettings, got {type(self.settings).__name__}")
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
        _check_all("config", self.config, check_choice, sweepable(self.settings))
        # build every design now so that bad combinations (an angle beyond the fluid) fail before any work
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
            radius = sweep_sphere_radius(m, s, mat or None)
            if mat:
                from ..core.contact import hertz_stiffness

                sphere_mat = _material("material", mat)
                surf = _material("surface", s.surface) if s.surface else sphere_mat
                kh = float(hertz_stiffness(radius, sphere_mat, surf))
            if dist <= radius:
                raise ParameterError("distance", f"must exceed the sphere radius {radius:g} m, got {dist:g} m")
            design = Design(i, float(gap), float(m), float(c1), float(kh), mat, float(v0), float(dist),
                            float(ang), cfg, radius)
            limit = design.geometry(s).polar_limit_deg  # a wall closer than the radius fails here
            if ang > math.radians(limit) + 1e-12:
                raise ParameterError("angle", f"must be <= {math.radians(limit):.6g} rad ({limit:g} deg) with the "
                                              f"{cfg} configuration, got {ang:g} rad")
            out.append(design)
        return tuple(out)

    def to_dict(self) -> dict:
        """All settings as plain JSON-able values."""
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "settings"}
        d = {k: (list(v) if v is not None else None) for k, v in d.items()}
        d["settings"] = asdict(self.settings)
        if d["settings"]["room"] is None:  # a sweep without a room reads as before rooms were swept
            del d["settings"]["room"]
        return d

    @classmethod
    def from_dict(cls, d: dict) -> SweepSpec:
        """Inverse of :meth:`to_dict`."""
        d = dict(d)
        settings = FixedSettings(**d.pop("settings"))
        kw = {k: (tuple(v) if v is not None else None) for k, v in d.items()}
        return cls(**kw, settings=settings)


def sweepable(settings: FixedSettings) -> tuple:
    """Names of the geometries a sweep with ``settings`` can build: those whose required settings it has."""
    given = dict(settings.room or ())
    return tuple(n for n, c in GEOMETRIES.items() if all(k in given for k in c.REQUIRED))


def sweep_sphere_radius(mass: float, settings: FixedSettings, material: str | None = None) -> float:
    """Radius in m of the radiating sphere of an impact mass (see :mod:`acoustiviz.sweep`).

    Parameters
    ----------
    mass : float
        Impact mass in kg.
    settings : FixedSettings
        ``radius_mode``, ``radius`` and ``density``.
    material : str, optional
        Sphere material, whose density is used when ``settings.density`` is None.

    Returns
    -------
    float
        ``settings.radius`` (fixed) or ``(3 m / (4 π ρ))^(1/3)`` from the mass
        (:func:`acoustiviz.core.materials.sphere_radius`).

    Examples
    --------
    A steel ball of the Table 1 impact mass, 40.5 g at 7800 kg/m³:

    >>> round(sweep_sphere_radius(0.0405, FixedSettings(radius_mode="from-mass")), 5)
    0.01074
    """
    from ..core.materials import sphere_radius as radius_of

    if settings.radius_mode == "fixed":
        return float(settings.radius)
    rho = settings.density
    if rho is None:
        rho = _material("material", material).density if material else PAPER_DENSITY
    return float(radius_of(mass, rho))
