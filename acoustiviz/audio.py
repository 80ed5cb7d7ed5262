"""Auralisation: impact sequences rendered into band-limited, calibrated WAV files.

Each impact of a sequence (a time, the wall it strikes and its approach speed) becomes a Hertz
acceleration pulse of the impact mass (:mod:`acoustiviz.contact`); the rigid-sphere radiation
model (:mod:`acoustiviz.radiation`) and the image sources of the scene (:mod:`acoustiviz.images`)
give its pressure at each listener; the clicks are placed at their exact (sub-sample) times and
summed. The result is in pascals.

Band-limiting
-------------
A click has energy far above audio rates (contact times of a few hundred microseconds,
``l = c/a`` of tens of kilohertz, and a kink at the start and the end of the half-sine pulse).
Point-sampling it at 48 kHz would alias. Each click is therefore evaluated exactly (closed form)
on an internal grid ``L`` times finer than the output, aligned with the output samples, and
decimated with one linear-phase Kaiser-window FIR low-pass filter: passband flat to
``0.45 fs`` (ripple < 1e-5), at least 110 dB of attenuation from ``fs/2`` up, so nothing above
the output Nyquist frequency folds back. ``L`` is chosen so the internal rate is at least
16 times the output rate and 200 samples per shortest contact. The filter has zero delay (its
centre tap is aligned), so a click's timing is exact to the internal step's rounding -- and
no rounding happens at all: the internal samples are the closed form at the exact retarded
times ``t - t_k - (r - a)/c``.

How impacts map to sources
--------------------------
The damper's axis of motion (``x`` in :mod:`acoustiviz.dynamics`) is the axis ``n`` of the
configuration's real sphere (the normal of the struck surface, ``+z`` for ``"free"`` and
``"plane"``). The cavity's two walls are perpendicular to it:

* the **struck wall** (``struck_wall``, default ``-1``) lies on the configuration's struck
  surface (``z = 0`` for ``"plane"``). Its impacts are exactly the configuration: the sphere at
  ``(0, 0, a)`` accelerating along ``+n`` and its images in the configuration's planes (paper
  eq 14 for ``"plane"``).
* the **far wall** (the other one) lies ``gap + 2a`` further along ``n``: its impacts put the
  sphere's centre at ``(0, 0, a + gap)`` accelerating along ``-n`` (it rebounds back towards the
  struck wall). The far wall is taken as acoustically small (a lid, smaller than the
  wavelengths of the click) and does not reflect; the configuration's planes still do, so the
  far-wall sphere has its own images in them (its image in ``z = 0`` sits at ``(0, 0, -a - gap)``
  with axis ``+n``).

With ``walls="one"`` every impact is heard as a strike on the struck wall (the paper's own
view, in which every impact is a sphere hitting the reflecting plane; an upper bound).
Wall ``-1`` is struck when the impact mass reaches ``y - x = -gap/2``, so with ``struck_wall=-1``
the damper's ``+x`` is ``+n``; with ``struck_wall=+1`` it is ``-n``. The cavity is at rest in
this frame: the main mass's displacement (a few cm) is neglected, as in the paper.

Calibration
-----------
:func:`write_wav` writes a float32 WAV (``subtype="FLOAT"``) in pascals by default: a sample
value 1.0 is 1 Pa (94 dB SPL). The alternative is normalised ``"PCM_24"`` with one scale (Pa
per full scale) shared by all files of a run (:func:`shared_scale`). Nothing is clipped
silently: a PCM sample beyond full scale raises a :class:`ClippingWarning` saying by how many dB
and is recorded in the sidecar. A JSON sidecar (``OUT.json`` beside ``OUT.wav``) records the
scale, rate, subtype, listeners, scene, pulse, modelling choices, impact count and peak SPL.

All quantities are SI (s, m, kg, m/s, Pa, Hz) unless a name says otherwise (``_db``).
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._io import atomic_path
from ._validate import ParameterError, check_choice, check_points, check_positive
from .contact import PULSE_KINDS, Impact, acceleration_pulse
from .images import CONFIGURATIONS, Configuration, ImageSource, configuration, images_of
from .medium import AIR, Medium
from .radiation import arrival_time, pulse_response, radiation_coefficients

__all__ = [
    "P_REF",
    "SAMPLE_RATES",
    "SUBTYPES",
    "PASSBAND_FRACTION",
    "STOPBAND_ATTENUATION_DB",
    "MASS_MODELS",
    "WALL_MODELS",
    "ClippingWarning",
    "ImpactSequence",
    "CavityScene",
    "ClickModel",
    "Rendering",
    "sphere_radius",
    "spl",
    "oversampling_factor",
    "decimation_filter",
    "wall_sources",
    "check_listeners",
    "ear_positions",
    "render",
    "shared_scale",
    "write_wav",
    "write_sidecar",
    "sidecar_path",
]

#: Reference pressure in Pa for sound pressure levels (dB re 20 µPa).
P_REF = 20e-6
#: Output sample rates in Hz.
SAMPLE_RATES = (44100, 48000, 96000)
#: WAV sample formats: float32 in Pa, or normalised 24-bit integers.
SUBTYPES = ("FLOAT", "PCM_24")
#: Upper edge of the flat passband as a fraction of the output rate (0.45 fs).
PASSBAND_FRACTION = 0.45
#: Minimum attenuation in dB of the decimation filter at and above the output Nyquist frequency.
STOPBAND_ATTENUATION_DB = 110.0
#: Which mass decelerates in the Hertz contact: the impact mass alone against a fixed wall
#: (the paper, eq 3) or the effective mass m M / (m + M) of the two free bodies.
MASS_MODELS = ("impact", "effective")
#: ``"both"``: impacts on the far wall radiate from the far wall; ``"one"``: all from the struck wall.
WALL_MODELS = ("both", "one")

_MIN_OVERSAMPLING = 16
_SAMPLES_PER_CONTACT = 200
#: response tails are kept until exp(-c t / a) < 1e-8 (-160 dB of the click)
_TAIL_DECADES = 8.0


class ClippingWarning(UserWarning):
    """Samples went beyond the full scale of an integer WAV and were clipped."""


# --------------------------------------------------------------------------- small helpers
def sphere_radius(mass: float, density: float) -> float:
    """Radius in m of a solid sphere of ``mass`` kg and ``density`` kg/m³: ``(3 m / (4 π ρ))^{1/3}``.

    Examples
    --------
    >>> round(sphere_radius(0.0405, 7800.0) * 1e3, 2)  # the paper's 40.5 g impact mass in steel, mm
    10.74
    """
    m = check_positive("mass", mass, "kg")
    rho = check_positive("density", density, "kg/m^3")
    return (3.0 * m / (4.0 * math.pi * rho)) ** (1.0 / 3.0)


def spl(pressure) -> float:
    """Peak sound pressure level ``20 log10(max|p| / 20 µPa)`` in dB of a signal in Pa (-inf if silent)."""
    peak = float(np.max(np.abs(np.asarray(pressure, dtype=float)), initial=0.0))
    return 20.0 * math.log10(peak / P_REF) if peak > 0 else -math.inf


# --------------------------------------------------------------------------- inputs
@dataclass(frozen=True)
class ImpactSequence:
    """The impacts to render: contact start times, walls and approach speeds.

    Parameters
    ----------
    times : (n,) array_like
        Contact start times in s (>= 0, any order).
    walls : (n,) array_like of int
        The wall struck, -1 or +1 (the convention of :mod:`acoustiviz.dynamics`).
    velocities : (n,) array_like
        Relative approach speeds in m/s (> 0).

    Examples
    --------
    >>> seq = ImpactSequence([0.01, 0.2], [-1, 1], [1.3, 0.9])
    >>> len(seq), seq.count(+1)
    (2, 1)
    """

    times: np.ndarray
    walls: np.ndarray
    velocities: np.ndarray

    def __post_init__(self):
        t = np.array(self.times, dtype=float).reshape(-1)
        v = np.array(self.velocities, dtype=float).reshape(-1)
        try:
            w = np.array(self.walls, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ParameterError("walls", "expected -1 or +1 for every impact") from None
        if not (t.size == w.size == v.size):
            raise ParameterError("times", f"times ({t.size}), walls ({w.size}) and velocities ({v.size}) "
                                          "must have the same length")
        if not np.all(np.isfinite(t)) or np.any(t < 0):
            raise ParameterError("times", "impact times must be finite and >= 0 s")
        if not np.all(np.isin(w, (-1.0, 1.0))):
            raise ParameterError("walls", f"every wall must be -1 or +1, got {sorted(set(w.tolist()))}")
        if not np.all(np.isfinite(v)) or np.any(v <= 0):
            raise ParameterError("velocities", "approach speeds must be finite and > 0 m/s")
        wi = w.astype(np.int8)
        for name, arr in (("times", t), ("walls", wi), ("velocities", v)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def __len__(self) -> int:
        return int(self.times.size)

    def count(self, wall: int) -> int:
        """Number of impacts on ``wall`` (-1 or +1)."""
        return int(np.count_nonzero(self.walls == wall))

    @classmethod
    def from_table(cls, table) -> ImpactSequence:
        """Build from an impact table with ``times``/``time``, ``walls``/``wall`` and approach speeds.

        Accepts any object (or mapping) exposing the contact start times in s, the wall (-1/+1)
        and the relative approach speed in m/s under the names used by
        :mod:`acoustiviz.dynamics` (``time``, ``wall``, ``approach_velocity``, singular or plural).
        Speeds are taken as magnitudes.
        """

        def get(*names):
            for nm in names:
                if isinstance(table, dict) and nm in table:
                    return table[nm]
                if hasattr(table, nm):
                    return getattr(table, nm)
            raise ParameterError("table", f"the impact table has none of {names}")

        t = get("times", "time", "time_s", "start", "t")
        w = get("walls", "wall")
        v = get("approach_velocities", "approach_velocity", "approach_velocity_m_s", "approach_speed",
                "velocity_in")
        return cls(t, w, np.abs(np.asarray(v, dtype=float)))


@dataclass(frozen=True)
class CavityScene:
    """Where the cavity sits and which surfaces reflect.

    Parameters
    ----------
    config : {"free", "plane", "wall-floor"}
        The image configuration of the struck wall (:func:`acoustiviz.images.configuration`).
    radius : float
        Sphere (impact mass) radius a in m.
    gap : float
        Total free travel d of the impact mass in the cavity in m; the far wall lies ``gap + 2a``
        from the struck one.
    struck_wall : {-1, +1}
        The damper wall lying on the configuration's struck surface.
    walls : {"both", "one"}
        ``"both"``: far-wall impacts radiate from the far wall with the reversed axis;
        ``"one"``: every impact is heard as a strike on the struck wall.
    wall_distance : float, optional
        ``"wall-floor"`` only: distance in m of the sphere's centre from the side wall.
    strike : {"floor", "wall"}
        ``"wall-floor"`` only: the struck surface.
    height : float, optional
        ``"wall-floor"`` with ``strike="wall"``: height in m of the centre above the floor.
    medium : Medium
        The fluid.
    """

    config: str = "plane"
    radius: float = 0.01905
    gap: float = 0.04
    struck_wall: int = -1
    walls: str = "both"
    wall_distance: float | None = None
    strike: str = "floor"
    height: float | None = None
    medium: Medium = AIR
    configuration: Configuration = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        check_choice("config", self.config, CONFIGURATIONS)
        check_positive("radius", self.radius, "m")
        check_positive("gap", self.gap, "m")
        if self.struck_wall not in (-1, 1):
            raise ParameterError("struck_wall", f"must be -1 or +1, got {self.struck_wall!r}")
        check_choice("walls", self.walls, WALL_MODELS)
        if not isinstance(self.medium, Medium):
            raise ParameterError("medium", f"expected a Medium, got {type(self.medium).__name__}")
        cfg = configuration(self.config, self.radius, wall_distance=self.wall_distance, strike=self.strike,
                            height=self.height)
        object.__setattr__(self, "configuration", cfg)

    @property
    def axis(self) -> np.ndarray:
        """Unit normal n of the struck surface (the damper's axis of motion), into the fluid."""
        return np.asarray(self.configuration.axis, dtype=float)

    @property
    def far_centre(self) -> np.ndarray:
        """Centre in m of the sphere when it touches the far wall: ``c0 + gap n``."""
        return np.asarray(self.configuration.centre, dtype=float) + self.gap * self.axis

    def sources(self, wall: int) -> tuple:
        """Image sources radiating an impact on damper wall ``wall`` (-1 or +1); see :func:`wall_sources`."""
        return wall_sources(self, wall)

    def describe(self) -> dict:
        """A JSON-ready description of the scene and of how impacts map to sources."""
        cfg = self.configuration
        far = -self.struck_wall
        out = {
            "config": self.config,
            "radius_m": self.radius,
            "gap_m": self.gap,
            "struck_wall": self.struck_wall,
            "walls": self.walls,
            "planes": [{"label": p.label, "point_m": p.point.tolist(), "normal": p.normal.tolist()}
                       for p in cfg.planes],
            "medium": {"c_m_s": self.medium.c, "rho_kg_m3": self.medium.rho},
            "sources": {},
        }
        if self.config == "wall-floor":
            out.update(wall_distance_m=self.wall_distance, strike=self.strike, height_m=self.height)
        for w in (self.struck_wall, far):
            out["sources"][f"{w:+d}"] = [
                {"label": s.label, "order": s.order, "position_m": s.position.tolist(), "axis": s.axis.tolist()}
                for s in self.sources(w)
            ]
        return out


def wall_sources(scene: CavityScene, wall: int) -> tuple:
    """Image sources radiating an impact on damper wall ``wall``.

    Parameters
    ----------
    scene : CavityScene
        The scene.
    wall : {-1, +1}
        The damper wall struck.

    Returns
    -------
    tuple of ImageSource
        For the struck wall (or any wall with ``walls="one"``): the configuration's sources.
        For the far wall: the sphere at ``c0 + gap n`` with axis ``-n``, then its images in the
        configuration's planes (labels prefixed ``"far "``).

    Examples
    --------
    >>> sc = CavityScene("plane", radius=0.01, gap=0.04)
    >>> [(float(s.position[2]), float(s.axis[2])) for s in wall_sources(sc, +1)]
    [(0.05, -1.0), (-0.05, 1.0)]
    """
    if wall not in (-1, 1):
        raise ParameterError("wall", f"must be -1 or +1, got {wall!r}")
    cfg = scene.configuration
    if wall == scene.struck_wall or scene.walls == "one":
        return tuple(cfg.sources)
    real = ImageSource(scene.far_centre, -scene.axis, 0, "far")
    imgs = images_of(real, cfg.planes)
    return tuple(ImageSource(s.position, s.axis, s.order, "far" if s.order == 0 else f"far {s.label}")
                 for s in imgs)


def check_listeners(points, scene: CavityScene, *, name: str = "listeners") -> np.ndarray:
    """Validate listener positions; return them as an ``(n, 3)`` array in m.

    A listener must be in the fluid of the configuration (not below the floor, not behind a
    wall, not inside the sphere) and, with ``walls="both"``, not inside the cavity (within a
    radius of the segment the sphere's centre travels between the two walls).

    Parameters
    ----------
    points : (n, 3) or (3,) array_like
        Positions in m in the configuration's frame.
    scene : CavityScene
        The scene.
    name : str
        Parameter name used in error messages (e.g. ``"--listener"``).

    Raises
    ------
    ParameterError
        Naming ``name``, the offending position and why it is not allowed.
    """
    pts = check_points(name, points)
    cfg = scene.configuration
    a = scene.radius
    tol = 1e-12 * a
    c0 = np.asarray(cfg.centre, dtype=float)
    for p in pts:
        where = f"({p[0]:g}, {p[1]:g}, {p[2]:g}) m"
        if np.linalg.norm(p - c0) < a - tol:
            raise ParameterError(name, f"listener {where} is inside the sphere (radius {a:g} m)")
        for pl in cfg.planes:
            if (p - pl.point) @ pl.normal < -tol:
                side = "below the floor" if pl.label == "floor" else f"behind the {pl.label}"
                raise ParameterError(name, f"listener {where} is {side} (the fluid is where "
                                           f"(x - {pl.point.tolist()}) . {pl.normal.tolist()} >= 0)")
        if scene.walls == "both":
            n = scene.axis
            s = float(np.clip((p - c0) @ n, 0.0, scene.gap))
            if np.linalg.norm(p - (c0 + s * n)) < a - tol:
                raise ParameterError(name, f"listener {where} is inside the cavity (within {a:g} m of the "
                                           f"sphere's path between the walls)")
    return pts


def ear_positions(centre, scene: CavityScene, *, spacing: float = 0.18) -> np.ndarray:
    """Two ear (or microphone) positions ``spacing`` m apart, centred on ``centre``, facing the damper.

    The ears lie on the horizontal line (perpendicular to ``+z``) perpendicular to the direction
    from ``centre`` to the struck wall's contact point; the first row is the left ear of a listener
    facing the damper, the second the right ear. No head is modelled (two free-field microphones).

    Parameters
    ----------
    centre : (3,) array_like
        Centre of the head in m.
    scene : CavityScene
        The scene (gives the contact point).
    spacing : float
        Distance between the ears in m (default 0.18).

    Returns
    -------
    (2, 3) ndarray
        Left and right ear positions in m.
    """
    c = check_points("centre", centre)[0]
    d = check_positive("spacing", spacing, "m")
    look = np.asarray(scene.configuration.contact_point, dtype=float) - c
    up = np.array([0.0, 0.0, 1.0])
    side = np.cross(up, look)  # points to the listener's left when facing the damper
    if np.linalg.norm(side) < 1e-12:  # listener straight above: use +y as the left
        side = np.array([0.0, 1.0, 0.0])
    side = side / np.linalg.norm(side)
    return np.stack([c + 0.5 * d * side, c - 0.5 * d * side])


@dataclass(frozen=True)
class ClickModel:
    """How an approach speed becomes an acceleration pulse of the impact mass.

    Parameters
    ----------
    k_hertz : float
        Hertz contact stiffness K_HZ in N/m^1.5.
    mass : float
        Impact mass m in kg.
    main_mass : float
        Main mass M in kg (used by ``mass_model="effective"``).
    mass_model : {"impact", "effective"}
        ``"impact"``: the paper's eq 3, the impact mass against a fixed wall. ``"effective"``:
        approach and duration from the effective mass m M / (m + M) of two free bodies; the
        acceleration is the peak force over m.
    pulse : {"half-sine", "impulse-matched", "hertz"}
        The pulse shape (:func:`acoustiviz.contact.acceleration_pulse`); the paper's half-sine by default.
    hertz_samples : int
        Samples of the exact Hertz pulse (``pulse="hertz"`` only); 513 keeps the pressure within
        about 2e-5 of the converged pulse's.
    """

    k_hertz: float = 5.6e8
    mass: float = 0.0405
    main_mass: float = 0.5
    mass_model: str = "impact"
    pulse: str = "half-sine"
    hertz_samples: int = 513

    def __post_init__(self):
        check_positive("k_hertz", self.k_hertz, "N/m^1.5")
        check_positive("mass", self.mass, "kg")
        check_positive("main_mass", self.main_mass, "kg")
        check_choice("mass_model", self.mass_model, MASS_MODELS)
        check_choice("pulse", self.pulse, PULSE_KINDS)

    def impact(self, velocity: float) -> Impact:
        """The :class:`~acoustiviz.contact.Impact` at approach speed ``velocity`` in m/s."""
        partner = self.main_mass if self.mass_model == "effective" else math.inf
        return Impact(velocity=float(velocity), k_hertz=self.k_hertz, mass=self.mass, partner_mass=partner)

    def pulse_for(self, velocity: float):
        """The acceleration pulse (m/s², starting at 0 s) at approach speed ``velocity`` in m/s."""
        return acceleration_pulse(self.impact(velocity), self.pulse, n_samples=self.hertz_samples)

    def describe(self) -> dict:
        """A JSON-ready description."""
        return {"k_hertz_n_m1_5": self.k_hertz, "impact_mass_kg": self.mass, "main_mass_kg": self.main_mass,
                "mass_model": self.mass_model, "pulse": self.pulse,
                "contact_damping": "ignored: undamped Hertz pulses (paper eqs 3-4)"}


# --------------------------------------------------------------------------- band-limiting
def oversampling_factor(sample_rate: float, shortest_contact: float) -> int:
    """Internal-to-output rate ratio L: at least 16 and at least 200 internal samples per contact.

    Parameters
    ----------
    sample_rate : float
        Output rate in Hz.
    shortest_contact : float
        Shortest contact duration of the sequence in s.
    """
    fs = check_positive("sample_rate", sample_rate, "Hz")
    tau = check_positive("shortest_contact", shortest_contact, "s")
    return max(_MIN_OVERSAMPLING, math.ceil(_SAMPLES_PER_CONTACT / (tau * fs)))


def decimation_filter(oversampling: int) -> np.ndarray:
    """Linear-phase low-pass FIR for decimation by ``oversampling`` (taps at the internal rate).

    Kaiser-window design: gain 1 at 0 Hz, flat (ripple < 1e-5) to ``0.45 fs``, at least
    :data:`STOPBAND_ATTENUATION_DB` dB of attenuation from ``fs/2`` up, where ``fs`` is the output
    rate. The length is ``2 K L + 1`` (odd, centre tap ``K L``) so the decimated output has zero delay.

    Parameters
    ----------
    oversampling : int
        Decimation factor L (>= 2).

    Returns
    -------
    ndarray
        Filter taps (sum 1).
    """
    from scipy.signal import firwin, kaiser_beta

    L = int(oversampling)
    if L < 2 or L != oversampling:
        raise ParameterError("oversampling", f"must be an integer >= 2, got {oversampling!r}")
    width = (0.5 - PASSBAND_FRACTION) / L * 2.0  # transition width as a fraction of the internal Nyquist
    atten = STOPBAND_ATTENUATION_DB + 3.0  # Kaiser's formulas are approximate: design with a margin
    numtaps = math.ceil((atten - 7.95) / (2.285 * math.pi * width)) + 1
    k = math.ceil((numtaps - 1) / (2 * L))
    cutoff = (PASSBAND_FRACTION + 0.5) / 2.0 / L * 2.0  # mid-transition, fraction of the internal Nyquist
    h = firwin(2 * k * L + 1, cutoff, window=("kaiser", kaiser_beta(atten)))
    return h / h.sum()


# --------------------------------------------------------------------------- synthesis
@dataclass(frozen=True)
class Rendering:
    """Band-limited pressure signals at the listeners.

    Attributes
    ----------
    pressure : (n_listeners, n_samples) ndarray
        Sound pressure in Pa; sample ``n`` is at time ``n / sample_rate`` s.
    sample_rate : int
        Output rate in Hz.
    internal_rate : float
        Rate in Hz at which the clicks were evaluated before decimation.
    listeners : (n_listeners, 3) ndarray
        Listener positions in m.
    sequence : ImpactSequence
        The impacts rendered.
    scene : CavityScene
        Geometry and medium.
    model : ClickModel
        Contact and pulse model.
    """

    pressure: np.ndarray
    sample_rate: int
    internal_rate: float
    listeners: np.ndarray
    sequence: ImpactSequence
    scene: CavityScene
    model: ClickModel

    @property
    def n_samples(self) -> int:
        """Number of samples per listener."""
        return int(self.pressure.shape[1])

    @property
    def time(self) -> np.ndarray:
        """Sample times in s."""
        return np.arange(self.n_samples) / self.sample_rate

    @property
    def peak(self) -> np.ndarray:
        """Largest |p| in Pa per listener (of the band-limited samples)."""
        return np.max(np.abs(self.pressure), axis=1, initial=0.0)

    @property
    def peak_spl(self) -> np.ndarray:
        """Peak SPL in dB re 20 µPa per listener (of the band-limited samples)."""
        return np.array([spl(row) for row in self.pressure])

    def describe(self) -> dict:
        """A JSON-ready record of everything that made this rendering (without file details)."""
        seq = self.sequence
        return {
            "sample_rate_hz": self.sample_rate,
            "internal_rate_hz": self.internal_rate,
            "band_limit": {"passband_hz": PASSBAND_FRACTION * self.sample_rate,
                           "stopband_from_hz": 0.5 * self.sample_rate,
                           "stopband_attenuation_db": STOPBAND_ATTENUATION_DB,
                           "filter": "linear-phase Kaiser FIR, zero delay"},
            "duration_s": self.n_samples / self.sample_rate,
            "impact_count": len(seq),
            "impact_count_by_wall": {"-1": seq.count(-1), "+1": seq.count(1)},
            "approach_speed_range_m_s": ([float(seq.velocities.min()), float(seq.velocities.max())]
                                         if len(seq) else None),
            "scene": self.scene.describe(),
            "click_model": self.model.describe(),
        }


def _source_geometry(points: np.ndarray, sources, radius: float, medium: Medium):
    """Delays ``(r - a)/c`` in s and complex weights ``P0 C`` in Pa·s/m of each source at each point.

    Returns arrays shaped ``(n_points, n_sources)``.
    """
    pos = np.stack([s.position for s in sources])
    ax = np.stack([s.axis for s in sources])
    d = points[:, None, :] - pos[None, :, :]
    r = np.linalg.norm(d, axis=2)
    ct = np.einsum("psk,sk->ps", d, ax) / r
    p0, cc = radiation_coefficients(r, ct, radius=radius, medium=medium)
    return arrival_time(r, radius=radius, medium=medium), p0 * cc


def render(sequence: ImpactSequence, scene: CavityScene, model: ClickModel, listeners, *,
           sample_rate: int = 48000, duration: float | None = None, oversampling: int | None = None) -> Rendering:
    """Render an impact sequence into band-limited pressure signals at the listeners.

    Parameters
    ----------
    sequence : ImpactSequence
        Contact start times (s), walls (-1/+1) and approach speeds (m/s).
    scene : CavityScene
        Where the cavity sits, the image configuration and the medium.
    model : ClickModel
        Impact mass, Hertz stiffness, mass model and pulse kind.
    listeners : (n, 3) or (3,) array_like
        Listener positions in m (see :func:`check_listeners`).
    sample_rate : {44100, 48000, 96000}
        Output rate in Hz.
    duration : float, optional
        Minimum signal length in s; the signal is extended to the end of the last click's tail
        (never cut short).
    oversampling : int, optional
        Internal rate over output rate; default :func:`oversampling_factor`.

    Returns
    -------
    Rendering
        Pressure in Pa at each listener.

    Notes
    -----
    For impact k on wall w with pulse ``A_k`` the pressure at a listener is
    ``Σ_j P0_j Re[C_j Y_k(t - t_k - (r_j - a)/c)]`` over the wall's sources j
    (:func:`acoustiviz.radiation.pulse_response`, paper eqs 12-14). It is evaluated in closed form
    on the internal grid over the click's window (arrival to a tail of ``exp(-c t/a) < 1e-8``),
    filtered by :func:`decimation_filter` and decimated, and added into the output. Cost grows
    with the number of impacts, not with the signal's length.

    Examples
    --------
    >>> seq = ImpactSequence([0.001], [-1], [1.4])
    >>> out = render(seq, CavityScene("plane"), ClickModel(), [0.495, 0.0, 0.514])
    >>> out.pressure.shape[0], round(float(out.peak_spl[0]))
    (1, 102)
    """
    from scipy.signal import fftconvolve

    if not isinstance(sequence, ImpactSequence):
        raise ParameterError("sequence", f"expected an ImpactSequence, got {type(sequence).__name__}")
    if not isinstance(scene, CavityScene):
        raise ParameterError("scene", f"expected a CavityScene, got {type(scene).__name__}")
    if not isinstance(model, ClickModel):
        raise ParameterError("model", f"expected a ClickModel, got {type(model).__name__}")
    if sample_rate not in SAMPLE_RATES:
        raise ParameterError("sample_rate", f"must be one of {SAMPLE_RATES} Hz, got {sample_rate!r}")
    fs = int(sample_rate)
    pts = check_listeners(listeners, scene)
    if duration is not None:
        duration = check_positive("duration", duration, "s")
    a, medium = scene.radius, scene.medium
    pulses = [model.pulse_for(v) for v in sequence.velocities]
    taus = np.array([p.duration for p in pulses]) if pulses else np.array([1.0])
    if oversampling is None:
        L = oversampling_factor(fs, float(taus.min()))
    else:
        L = int(oversampling)
        if L < 2 or L != oversampling:
            raise ParameterError("oversampling", f"must be an integer >= 2, got {oversampling!r}")
    h = decimation_filter(L)
    half = (h.size - 1) // (2 * L)  # filter half-length in output samples
    f_int = float(L * fs)
    tail = _TAIL_DECADES * math.log(10.0) * a / medium.c
    geom = {w: _source_geometry(pts, wall_sources(scene, w), a, medium) for w in (-1, 1)}

    end = 0.0
    for w, (delay, _) in geom.items():
        sel = sequence.walls == w
        if np.any(sel):
            end = max(end, float(np.max(sequence.times[sel] + taus[sel])) + float(delay.max()) + tail)
    n_out = max(math.ceil(end * fs) + half + 1, math.ceil((duration or 0.0) * fs))
    out = np.zeros((pts.shape[0], n_out))
    for k, pulse in enumerate(pulses):  # loop over impacts ...
        tk = float(sequence.times[k])
        delay_all, weight_all = geom[int(sequence.walls[k])]
        for i in range(pts.shape[0]):  # ... and listeners; vectorised over sources and samples
            delay, weight = delay_all[i], weight_all[i]
            n0 = math.floor((tk + delay.min()) * fs)
            m_stop = math.ceil((tk + delay.max() + pulse.duration + tail) * f_int) + 1
            idx = np.arange(n0 * L, m_stop)
            t_loc = (idx - tk * f_int) / f_int  # time since contact start, s
            y = pulse_response(pulse, t_loc[None, :] - delay[:, None], radius=a, medium=medium)
            x = np.real(weight[:, None] * y).sum(axis=0)
            z = fftconvolve(x, h)[::L]  # = upfirdn(h, x, down=L); FFT is faster for these lengths
            lo = n0 - half
            s0, s1 = max(lo, 0), min(lo + z.size, n_out)
            if s1 > s0:
                out[i, s0:s1] += z[s0 - lo:s1 - lo]
    return Rendering(out, fs, f_int, pts, sequence, scene, model)


# --------------------------------------------------------------------------- files
def shared_scale(signals, *, headroom_db: float = 1.0) -> float:
    """One scale in Pa per full scale for all signals of a run (normalised PCM).

    Parameters
    ----------
    signals : iterable of array_like
        Pressure signals in Pa (any shapes).
    headroom_db : float
        The largest |p| of all signals lands this many dB below full scale (>= 0).

    Returns
    -------
    float
        Pa per full scale: a sample value v stands for ``v * scale`` Pa. 1.0 if all are silent.
    """
    hr = float(headroom_db)
    if not (math.isfinite(hr) and hr >= 0):
        raise ParameterError("headroom_db", f"must be finite and >= 0 dB, got {headroom_db!r}")
    peak = max((float(np.max(np.abs(np.asarray(s, dtype=float)), initial=0.0)) for s in signals), default=0.0)
    return peak * 10.0 ** (hr / 20.0) if peak > 0 else 1.0


def sidecar_path(wav_path) -> Path:
    """The JSON sidecar of a WAV file: ``OUT.json`` for ``OUT.wav``."""
    return Path(wav_path).with_suffix(".json")


def write_wav(path, pressure, sample_rate: int, *, subtype: str = "FLOAT", scale: float = 1.0) -> dict:
    """Write pressure signals to a WAV file atomically; return what was written.

    Parameters
    ----------
    path : path-like
        Output ``.wav`` file.
    pressure : (n_samples,) or (n_channels, n_samples) array_like
        Pressure in Pa.
    sample_rate : int
        Rate in Hz.
    subtype : {"FLOAT", "PCM_24"}
        ``"FLOAT"``: 32-bit float, sample value = pressure / scale (default scale 1: values in Pa;
        nothing is clipped, values beyond ±1 are stored as they are). ``"PCM_24"``: 24-bit integers of
        pressure / scale; samples beyond full scale are clipped with a :class:`ClippingWarning`.
    scale : float
        Pa per full scale (see :func:`shared_scale`).

    Returns
    -------
    dict
        ``path``, ``subtype``, ``channels``, ``frames``, ``sample_rate_hz``, ``pa_per_full_scale``,
        ``peak_full_scale`` (largest |sample| before any clipping), ``over_full_scale_db`` (dB by which it
        exceeds full scale, or 0), ``clipped_samples``.
    """
    import soundfile as sf

    check_choice("subtype", subtype, SUBTYPES)
    sc = check_positive("scale", scale, "Pa")
    fs = check_positive("sample_rate", sample_rate, "Hz")
    p = np.asarray(pressure, dtype=float)
    if p.ndim == 1:
        p = p[None, :]
    if p.ndim != 2 or not np.all(np.isfinite(p)):
        raise ParameterError("pressure", "expected a finite (n_channels, n_samples) array in Pa")
    data = (p / sc).T
    peak = float(np.max(np.abs(data), initial=0.0))
    over_db = 20.0 * math.log10(peak) if peak > 1.0 else 0.0
    clipped = 0
    if subtype == "PCM_24":
        top = 1.0 - 2.0**-23
        clipped = int(np.count_nonzero((data > top) | (data < -1.0)))
        if clipped:
            warnings.warn(f"{path}: {clipped} samples clipped at full scale ({scale:g} Pa); the peak was "
                          f"{over_db:.2f} dB over full scale", ClippingWarning, stacklevel=2)
            data = np.clip(data, -1.0, top)
        out = data
    else:
        out = data.astype(np.float32)
    with atomic_path(path) as tmp:
        sf.write(str(tmp), out, int(fs), subtype=subtype, format="WAV")
    return {"path": str(path), "subtype": subtype, "channels": int(p.shape[0]), "frames": int(p.shape[1]),
            "sample_rate_hz": int(fs), "pa_per_full_scale": sc, "peak_full_scale": peak,
            "over_full_scale_db": over_db, "clipped_samples": clipped}


def write_sidecar(wav_path, record: dict) -> Path:
    """Write ``record`` as JSON beside ``wav_path`` (``OUT.json`` for ``OUT.wav``), atomically."""
    path = sidecar_path(wav_path)
    text = json.dumps(_finite(record), indent=2, default=_json_default, allow_nan=False)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text + "\n", encoding="utf-8")
    return path


def _finite(obj):
    """``obj`` with arrays as lists and non-finite floats (a silent signal's -inf dB) as None."""
    if isinstance(obj, dict):
        return {str(k): _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [_finite(v) for v in (obj.tolist() if isinstance(obj, np.ndarray) else obj)]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _json_default(obj):
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
