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
from .balls import ball_radius, fill_of, gap_of_fill
from .values import MAX_RANGE_COUNT, parse_start_stop_count, parse_values, value_range

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


def _check_all(name, values, check, *args, **kwargs):
    if not isinstance(values, tuple) or not values:
        raise ParameterError(name, f"expected a non-empty tuple of values, got {values!r}")
    for v in values:
        check(name, v, *args, **kwargs)
    if len(set(values)) != len(values):
        raise ParameterError(name, f"values must not repeat, got {values!r}")


def _check_count(name, v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or int(v) != v or v < 1:
        raise ParameterError(name, f"must be a whole number of balls >= 1, got {v!r}")


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
    equal_total_mass : bool
        With several balls, divide each swept mass ``m`` among the ``balls`` of a design (each ball
        ``m / balls``), so that designs of different ball counts carry the same total mass; False
        (default): ``m`` is the mass of each ball, as ``acoustiviz damper --balls``.
    k_hertz_ball, c1_ball : float or None
        With several balls, the Hertz stiffness in N/m^1.5 and the contact damping in N·s/m between
        two balls (None: paper eq 2 for the two balls' radii and material, and ``c1``; as
        :func:`acoustiviz.dynamics.equal_balls`).
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
    equal_total_mass: bool = False
    k_hertz_ball: float | None = None
    c1_ball: float | None = None

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
        if self.k_hertz_ball is not None:
            check_positive("k_hertz_ball", self.k_hertz_ball, "N/m^1.5")
        if self.c1_ball is not None:
            check_nonnegative("c1_ball", self.c1_ball, "N s/m")
        for flag in ("levels", "equal_total_mass"):
            if not isinstance(getattr(self, flag), bool):
                raise ParameterError(flag, f"must be True or False, got {getattr(self, flag)!r}")
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
        Total free travel d in m (with several balls: the cavity's length less their diameters).
    m : float
        Impact mass in kg (with several balls: the mass of each).
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
        Radius of the radiating sphere in m (several balls: each ball's own,
        :func:`acoustiviz.sweep.balls.ball_radius`).
    balls : int
        Number of equal balls in the cavity (1: the paper's damper).
    fill : float or None
        Fraction of the cavity's length the balls take (:mod:`acoustiviz.sweep.balls`); None when the sweep
        names neither balls nor fills (its ``sweep.csv`` then has no ``balls`` and ``fill`` columns).
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
    balls: int = 1
    fill: float | None = None

    def geometry(self, settings: FixedSettings) -> Geometry:
        """The design's geometry: its configuration around its sphere, with the sweep's wall distance."""
        return geometry(self.config, self.radius, lenient=True, **settings.geometry_settings)


@dataclass(frozen=True)
class SweepSpec:
    """A grid of designs: the Cartesian product of the swept values, and the fixed settings.

    Every swept parameter is a tuple of values (one value: held fixed). At most one of ``m``
    and ``mass_ratio``, at most one of ``k_hertz`` and ``material``, and at most one of ``gap`` and
    ``fill`` is given (neither: Table 1's m = 40.5 g and K_HZ = 5.6e8 N/m^1.5, the Figure 5 gap).

    Parameters
    ----------
    gap : tuple of float
        Gaps d in m (default the Figure 5 gap, 0.04 m): with several balls, the cavity's length less
        their diameters.
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
    balls : tuple of int, optional
        Numbers of equal balls in the cavity (None: one ball, and no ``balls``/``fill`` columns);
        several balls are evaluated by :func:`acoustiviz.sweep.balls.evaluate_balls`.
    fill : tuple of float, optional
        Fractions in (0, 1) of the cavity's length the balls take, instead of ``gap``: each design's gap
        is ``N D (1 - fill) / fill`` (:func:`acoustiviz.sweep.balls.gap_of_fill`).
    settings : FixedSettings
        Everything else.

    Examples
    --------
    >>> spec = SweepSpec(gap=value_range(0.02, 0.06, 5), m=value_range(0.02, 0.08, 4))
    >>> len(spec.designs())
    20
    """

    gap: tuple | None = None
    m: tuple | None = None
    mass_ratio: tuple | None = None
    c1: tuple = (TABLE1_PARAMETERS["c1"],)
    k_hertz: tuple | None = None
    material: tuple | None = None
    v0: tuple = (PAPER_V0,)
    distance: tuple = (0.7,)
    angle: tuple = (math.pi / 4,)
    config: tuple = ("plane",)
    balls: tuple | None = None
    fill: tuple | None = None
    settings: FixedSettings = field(default_factory=FixedSettings)

    #: Order of the grid's axes; the last varies fastest (the ``gap`` axis holds the fills when given).
    AXES = ("balls", "config", "material", "k_hertz", "c1", "v0", "distance", "angle", "gap", "m")

    def __post_init__(self):
        if self.gap is not None and self.fill is not None:
            raise ParameterError("fill", "give either gap (m) or fill (the balls' fraction of the cavity), not both")
        if self.gap is None and self.fill is None:
            object.__setattr__(self, "gap", (PAPER_GAP,))
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
        if self.fill is None:
            _check_all("gap", self.gap, check_positive, "m")
        else:
            _check_all("fill", self.fill, check_range, 0.0, 1.0, low_open=True, high_open=True)
        if self.balls is not None:
            _check_all("balls", self.balls, _check_count)
            object.__setattr__(self, "balls", tuple(int(n) for n in self.balls))
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

    @property
    def with_balls(self) -> bool:
        """True when the designs name their balls and fill (``balls``, ``fill`` or ``equal_total_mass`` set)."""
        return self.balls is not None or self.fill is not None or self.settings.equal_total_mass

    def _axis(self, name):
        if name == "balls":
            return self.balls or (1,)
        if name == "gap" and self.fill is not None:
            return self.fill
        if name == "m":
            return self.masses
        if name == "material":
            return self.material if self.material is not None else ("",)
        if name == "k_hertz":
            return self.k_hertz if self.k_hertz is not None else (math.nan,)
        return getattr(self, name)

    def swept(self) -> tuple[str, ...]:
        """Names of the axes with more than one value."""
        names = tuple(a for a, n in zip(self.AXES, self.shape, strict=True) if n > 1)
        return tuple("fill" if a == "gap" and self.fill is not None else a for a in names)

    def designs(self) -> tuple[Design, ...]:
        """Every design of the grid, in grid order (``design_id`` = position)."""
        s = self.settings
        out = []
        for i, vals in enumerate(itertools.product(*(self._axis(a) for a in self.AXES))):
            n, cfg, mat, kh, c1, v0, dist, ang, gap, m = vals
            n, m = int(n), m / n if s.equal_total_mass else m
            gap, fill = self._gap_fill(n, m, mat, gap)
            radius = sweep_sphere_radius(m, s, mat or None) if n == 1 else ball_radius(m, mat)
            if mat:
                from ..core.contact import hertz_stiffness

                sphere_mat = _material("material", mat)
                surf = _material("surface", s.surface) if s.surface else sphere_mat
                kh = float(hertz_stiffness(radius, sphere_mat, surf))
            if dist <= radius:
                raise ParameterError("distance", f"must exceed the sphere radius {radius:g} m, got {dist:g} m")
            design = Design(i, float(gap), float(m), float(c1), float(kh), mat, float(v0), float(dist),
                            float(ang), cfg, radius, n, fill)
            geom = design.geometry(s)  # a wall closer than the radius fails here
            limit = geom.polar_limit_deg
            if ang > math.radians(limit) + 1e-12:
                raise ParameterError("angle", f"must be <= {math.radians(limit):.6g} rad ({limit:g} deg) with the "
                                              f"{cfg} configuration, got {ang:g} rad")
            out.append(design)
        return tuple(out)

    def _gap_fill(self, n: int, m: float, material: str, value: float) -> tuple:
        """``(gap, fill)`` of ``n`` balls of ``m`` kg from the gap axis' ``value`` (a gap, or a fill when given)."""
        if not self.with_balls:
            return value, None
        diameter = 2.0 * ball_radius(m, material)
        if self.fill is None:
            return value, fill_of(n, diameter, value)
        return gap_of_fill(n, diameter, value), float(value)

    def to_dict(self) -> dict:
        """All settings as plain JSON-able values."""
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "settings"}
        d = {k: (list(v) if v is not None else None) for k, v in d.items()}
        for name in ("balls", "fill"):  # a sweep of one ball reads as before balls were swept
            if d[name] is None:
                del d[name]
        d["settings"] = asdict(self.settings)
        if d["settings"]["room"] is None:  # a sweep without a room reads as before rooms were swept
            del d["settings"]["room"]
        for name, unset in (("equal_total_mass", False), ("k_hertz_ball", None), ("c1_ball", None)):
            if d["settings"][name] is unset:  # a sweep of one ball reads as before balls were swept
                del d["settings"][name]
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
