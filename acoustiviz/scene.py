"""Scenes: one TOML file describing a situation and the outputs wanted from it.

A scene names the medium, the sphere and its contact, the geometry (free field, a reflecting
plane or a wall-floor corner), optionally an impact damper, listeners, grids, and an
``[outputs]`` table. Only the outputs named there are produced, and only the work they need is
done. Every key carries its unit in its name (``radius_m``, ``duration_s``, ``angle_deg``).

Loading validates everything before any work starts: a wrong type, a value out of range, an
unknown key (with a "did you mean"), a listener without a position, a listener inside the sphere or
behind a surface, or a grid too large for the memory cap raises :class:`SceneError`, whose
message names the file, the key path and the allowed range.

The schema is data (:data:`SCHEMA`), so the documentation (``acoustiviz run --help-scene``)
and the validator cannot drift apart.
"""

from __future__ import annotations

import copy
import difflib
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from types import MappingProxyType

from ._validate import ParameterError

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = [
    "SceneError",
    "Scene",
    "SCHEMA",
    "OUTPUT_KINDS",
    "load_scene",
    "scene_from_dict",
    "scene_from_text",
    "default_scene",
    "shipped_scenes",
    "schema_help",
    "parse_range",
]


class SceneError(ParameterError):
    """A scene is invalid; the message names the file, the key path and what is allowed."""

    def __init__(self, source: str, key: str, message: str):
        self.source = source
        self.key = key
        ValueError.__init__(self, f"{source}: {key}: {message}")
        self.name = key


# --------------------------------------------------------------------------- schema
@dataclass(frozen=True)
class Key:
    """One scene key: its type, unit, allowed range, default and meaning."""

    kind: str  # "float", "int", "bool", "str", "floats", "point", "range"
    doc: str
    default: object = None
    unit: str = ""
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    choices: tuple = ()
    length: int | None = None  # most values of "floats", exact count of "ints"


@dataclass(frozen=True)
class Table:
    """A sub-table of keys; ``optional`` tables may be absent (outputs are requested by presence)."""

    keys: dict
    doc: str = ""
    array: bool = False  # [[name]] array of tables


def _pos(doc, unit, default=None, **kw):
    return Key("float", doc, default, unit, low=0.0, low_open=True, **kw)


PULSES = ("half-sine", "impulse-matched", "hertz")
CONFIGS = ("free", "plane", "wall-floor")
SOLVERS = ("auto", "event", "newmark", "impact-map")

_MEDIUM = {
    "c_m_s": Key("float", "speed of sound", 343.2, "m/s", low=1.0, high=1e5),
    "rho_kg_m3": Key("float", "fluid density", 1.204, "kg/m^3", low=1e-3, high=1e5),
}
_SPHERE = {
    "radius_m": _pos("sphere radius", "m", 0.01905, high=1.0),
    "material": Key("str", "sphere material from the catalogue (sets density; with contact.surface, K_HZ)", None),
    "density_kg_m3": _pos("sphere density (default 7800, or the material's)", "kg/m^3", None, high=1e5),
    "mass_kg": _pos("sphere mass; replaces the density", "kg", None, high=1e4),
    "damper_radius": Key("str", "sphere radius for damper impacts: 'given' keeps radius_m (the paper's choice), "
                         "'from-mass' derives it from the impact mass and the density", "given",
                         choices=("given", "from-mass")),
}
_CONTACT = {
    "k_hertz_n_m1_5": _pos("Hertz stiffness K_HZ (default 5.6e8, or from sphere.material and surface)",
                           "N/m^1.5", None, high=1e14),
    "surface": Key("str", "surface material from the catalogue (K_HZ from sphere and surface materials)", None),
    "pulse": Key("str", "acceleration pulse", "half-sine", choices=PULSES),
    "pulse_mass": Key("str", "mass in the pulse: the impact mass alone or the effective mass of the two bodies",
                      "impact", choices=("impact", "effective")),
}
_IMPACT = {
    "velocity_m_s": _pos("approach speed of the single impact used by waveform, directivity and renders",
                         "m/s", 1.4, high=1e3),
}
_CONFIGURATION = {
    "kind": Key("str", "free field, reflecting plane (floor z = 0) or wall-floor corner", "plane", choices=CONFIGS),
    "wall_distance_m": _pos("wall-floor: distance from the wall (x = -wall_distance) to the sphere's centre",
                            "m", 0.05, high=100.0),
    "strike": Key("str", "wall-floor: struck surface (a wall strike puts the sphere against the wall, "
                  "accelerating along +x)", "floor", choices=("floor", "wall")),
    "height_m": _pos("wall strike: height of the sphere's centre above the floor (default: the radius)", "m",
                     None, high=100.0),
}
_DAMPER = {
    "main_mass_kg": _pos("main mass M", "kg", 0.5, high=1e6),
    "stiffness_n_m": _pos("spring stiffness K", "N/m", 500.0, high=1e12),
    "damping_n_s_m": Key("float", "viscous damping C", 0.05, "N s/m", low=0.0, high=1e9),
    "impact_mass_kg": _pos("impact mass m", "kg", 0.0405, high=1e5),
    "gap_m": _pos("total free travel d of the impact mass", "m", 0.04, high=10.0),
    "contact_damping_n_s_m": Key("float", "contact damping c1", 20.0, "N s/m", low=0.0, high=1e9),
    "clip_tensile": Key("bool", "clip the contact force at zero (no pull as the bodies part)", False),
    "initial_velocity_m_s": Key("float", "initial velocity of the main mass", 2.0, "m/s", low=-1e3, high=1e3),
    "initial_displacement_m": Key("float", "initial displacement of the main mass", 0.0, "m", low=-10, high=10),
    "duration_s": _pos("simulated time", "s", 20.0, high=1e4),
    "solver": Key("str", "damper solver; 'auto' takes the cheapest whose error suits the tolerance "
                  "(acoustiviz.dynamics.cheapest_solver)", "auto", choices=SOLVERS),
    "tolerance": _pos("relative accuracy wanted on impact times and speeds (the event solver's rtol)", "", 1e-10,
                      high=0.5),
}
_LISTENER = {
    "name": Key("str", "label used in file names", None),
    "distance_m": _pos("distance from the sphere's centre (with angle_deg)", "m", None, high=1e4),
    "angle_deg": Key("float", "angle from the acceleration axis (with distance_m)", None, "deg", low=0.0, high=180.0),
    "position_m": Key("point", "position [x, y, z] in the scene frame (instead of distance/angle)", None, "m"),
}
_SPHERE_GRID = {
    "distance_m": _pos("radius of the spherical grid (balloon) around the sphere's centre", "m", 0.7, high=1e4),
    "n_theta": Key("int", "polar samples (the azimuth gets twice as many)", 32, low=3, high=2000),
}
_PLANE_GRID = {
    "extent_m": _pos("distance from the sphere's centre to the far edges of each section (default: the distance "
                     "sound travels by the last time, x 1.25)", "m", None, high=1e3),
    "resolution": Key("int", "points along the longer side of each section", 200, low=8, high=20000),
    "sections": Key("strs", "sections through the sphere's centre: 'xz' the vertical plane normal to the wall "
                    "(holding the acceleration axis), 'yz' the vertical plane parallel to it, 'xy' the horizontal",
                    ["xz"], choices=("xz", "yz", "xy")),
}
_OUT = {
    "waveform": Table({"pulses": Key("strs", "pulses to compare", None, choices=PULSES)},
                      "pressure waveform at each listener"),
    "directivity": Table({"step_deg": Key("float", "angle step", 5.0, "deg", low=0.1, high=45.0, low_open=False)},
                         "peak, RMS and SPL against angle at the first listener's distance"),
    "snapshot": Table({"times_s": Key("floats", "snapshot times (at most 12, drawn side by side)", [0.001], "s",
                                      low=0.0, high=10.0, length=12),
                       "size_px": Key("ints", "image width and height", [1400, 600], "px", low=64, high=8192,
                                      length=2)},
                      "pressure field on the planar sections at given times (pyvista)"),
    "balloon": Table({"metric": Key("str", "balloon colour/radius", "peak", choices=("peak", "rms", "sel")),
                      "db_range": _pos("level range from the rim to the centre of the balloon", "dB", 30.0,
                                       high=200.0),
                      "size_px": Key("ints", "image width and height", [1200, 900], "px", low=64, high=8192,
                                     length=2)},
                     "3-D directivity balloon on the spherical grid (pyvista)"),
    "animation": Table({"frames": Key("int", "frames", 40, low=2, high=2000),
                        "fps": Key("int", "frames per second", 12, low=1, high=60),
                        "size_px": Key("ints", "image width and height", [800, 600], "px", low=64, high=4096,
                                       length=2)},
                       "GIF of the wavefront on the planar sections (pyvista)"),
    "damper_history": Table({}, "main-mass displacement with and without damper (paper Figure 5)"),
    "impact_table": Table({}, "one row per contact of the damper run (CSV)"),
    "restitution": Table({
        "masses_kg": Key("floats", "impact masses", [0.01, 0.02, 0.04, 0.06, 0.08, 0.1], "kg", low=1e-6, high=1e4),
        "velocities_m_s": Key("floats", "approach speeds", [0.5, 1.0, 2.0], "m/s", low=1e-4, high=1e3)},
        "coefficient of restitution against impact mass (paper Figure 7)"),
    "sweep": Table({
        "gap_m": Key("range", "gap range start:stop:count", "0.02:0.06:5", "m", low=0.0, low_open=True, high=10),
        "mass_kg": Key("range", "impact-mass range start:stop:count", "0.02:0.08:4", "kg", low=0.0, low_open=True,
                       high=1e4),
        "duration_s": _pos("simulated time per design", "s", 5.0, high=1e4),
        "workers": Key("int", "worker processes (0: all cores)", 0, low=0, high=1024)},
        "sweep over gap and impact mass (paper Figure 6)"),
    "design_table": Table({
        "inclination_m_s": Key("float", "target damping inclination", None, "m/s", low=0.0, high=10.0),
        "tolerance_m_s": _pos("half-width of the inclination band", "m/s", 0.001, high=10.0)},
        "quietest design per damping-inclination band (paper Table 2); needs [outputs.sweep]"),
    "wav": Table({"rate_hz": Key("int", "sample rate", 48000, "Hz", low=8000, high=384000),
                  "stereo": Key("bool", "one stereo file from the first two listeners", False),
                  "subtype": Key("str", "FLOAT: float32 in pascals (1.0 = 1 Pa); PCM_24: normalised, one shared "
                                 "scale recorded in the sidecar", "FLOAT", choices=("FLOAT", "PCM_24")),
                  "struck_wall": Key("int", "damper wall lying on the struck surface z = 0", -1, low=-1, high=1),
                  "walls": Key("str", "'both': impacts on the far wall radiate from it with the reversed axis; "
                               "'one': every impact is heard as a strike on z = 0", "both", choices=("both", "one"))},
                 "calibrated WAV (Pa) of the damper run at each listener"),
}
#: The outputs a scene may ask for, in the order they are produced.
OUTPUT_KINDS = tuple(_OUT)

SCHEMA = {
    "scene": Table({"name": Key("str", "short name", "scene"), "description": Key("str", "what it shows", "")},
                   "title"),
    "medium": Table(_MEDIUM, "the fluid (default air at 20 degC)"),
    "sphere": Table(_SPHERE, "the impacting sphere"),
    "contact": Table(_CONTACT, "Hertz contact and the acceleration pulse"),
    "impact": Table(_IMPACT, "a single impact"),
    "configuration": Table(_CONFIGURATION, "surfaces around the impact; frame: struck surface z = 0"),
    "damper": Table(_DAMPER, "the impact damper (paper Table 1 defaults)"),
    "listeners": Table(_LISTENER, "listeners ([[listeners]], each with distance_m and angle_deg, or position_m)",
                       array=True),
    "grids": Table({"sphere": Table(_SPHERE_GRID, "spherical grid"), "plane": Table(_PLANE_GRID, "planar grid"),
                    "memory_limit_mb": _pos("memory cap of grid evaluations", "MiB", 256.0, high=1e6)},
                   "evaluation grids"),
    "outputs": Table(_OUT, "what to produce; only these are computed"),
}

DEFAULT_LISTENER = {"name": "paper", "distance_m": 0.7, "angle_deg": 45.0}


# --------------------------------------------------------------------------- helpers
def parse_range(text: str, key: str = "range", source: str = "<range>"):
    """Parse ``start:stop:count`` (inclusive) into a list of floats; one number is a single value."""
    parts = str(text).split(":")
    try:
        if len(parts) == 1:
            return [float(parts[0])]
        if len(parts) != 3:
            raise ValueError
        start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise SceneError(source, key, f"expected 'start:stop:count' (inclusive) or one number, got {text!r}") from None
    if count < 1 or count > 10000:
        raise SceneError(source, key, f"count must lie in [1, 10000], got {count}")
    if count == 1:
        if start != stop:
            raise SceneError(source, key, "a count of 1 needs start == stop")
        return [start]
    step = (stop - start) / (count - 1)
    return [start + i * step for i in range(count)]


def _fmt_range(k: Key) -> str:
    lb = "(" if k.low_open else "["
    u = f" {k.unit}" if k.unit else ""
    return f"{lb}{k.low:g}, {k.high:g}]{u}"


def _type_name(kind: str) -> str:
    return {"float": "a number", "int": "an integer", "bool": "true or false", "str": "a string",
            "floats": "a list of numbers", "strs": "a list of strings", "point": "a list of 3 numbers",
            "ints": "a list of integers",
            "range": "a 'start:stop:count' string"}[kind]


def _check_number(v, k: Key, src: str, path: str) -> float:
    if not math.isfinite(v):
        raise SceneError(src, path, f"must be finite, got {v}")
    ok_low = v > k.low if k.low_open else v >= k.low
    if not (ok_low and v <= k.high):
        raise SceneError(src, path, f"must lie in {_fmt_range(k)}, got {v:g}")
    return v


def _check_key(value, k: Key, src: str, path: str):
    kind = k.kind
    if kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SceneError(src, path, f"expected {_type_name(kind)} in {_fmt_range(k)}, got {value!r}")
        return _check_number(float(value), k, src, path)
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise SceneError(src, path, f"expected {_type_name(kind)} in {_fmt_range(k)}, got {value!r}")
        return int(_check_number(value, k, src, path))
    if kind == "bool":
        if not isinstance(value, bool):
            raise SceneError(src, path, f"expected true or false, got {value!r}")
        return value
    if kind == "str":
        if not isinstance(value, str):
            raise SceneError(src, path, f"expected {_type_name(kind)}, got {value!r}")
        if k.choices and value not in k.choices:
            close = difflib.get_close_matches(value, k.choices, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise SceneError(src, path, f"must be one of {', '.join(map(repr, k.choices))}, got {value!r}{hint}")
        return value
    if kind == "ints":
        if not isinstance(value, list) or len(value) != k.length:
            raise SceneError(src, path, f"expected a list of {k.length} integers in {_fmt_range(k)}, got {value!r}")
        for i, v in enumerate(value):
            if isinstance(v, bool) or not isinstance(v, int):
                raise SceneError(src, f"{path}[{i}]", f"expected an integer, got {v!r}")
            _check_number(v, k, src, f"{path}[{i}]")
        return list(value)
    if kind in ("floats", "point"):
        if not isinstance(value, list) or not value:
            raise SceneError(src, path, f"expected {_type_name(kind)}, got {value!r}")
        if kind == "point" and len(value) != 3:
            raise SceneError(src, path, f"expected {_type_name(kind)}, got {len(value)} values")
        limit = k.length or 10000
        if kind == "floats" and len(value) > limit:
            raise SceneError(src, path, f"at most {limit} values, got {len(value)}")
        out = []
        for i, v in enumerate(value):
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise SceneError(src, f"{path}[{i}]", f"expected a number, got {v!r}")
            out.append(_check_number(float(v), k, src, f"{path}[{i}]") if kind == "floats" else float(v))
            if kind == "point" and not math.isfinite(out[-1]):
                raise SceneError(src, f"{path}[{i}]", f"must be finite, got {v}")
        return out
    if kind == "strs":
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value) or not value:
            raise SceneError(src, path, f"expected {_type_name(kind)}, got {value!r}")
        allowed = k.choices or PULSES
        for i, v in enumerate(value):
            if v not in allowed:
                raise SceneError(src, f"{path}[{i}]", f"must be one of {', '.join(map(repr, allowed))}, got {v!r}")
        if len(set(value)) != len(value):
            raise SceneError(src, path, f"values must not repeat, got {value!r}")
        return list(value)
    if kind == "range":
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            value = str(value)
        if not isinstance(value, str):
            raise SceneError(src, path, f"expected {_type_name(kind)}, got {value!r}")
        vals = parse_range(value, path, src)
        for v in vals:
            _check_number(v, k, src, path)
        return value
    raise AssertionError(kind)  # pragma: no cover


def _unknown(src, path, key, allowed):
    close = difflib.get_close_matches(str(key), list(allowed), n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    where = f"{path}.{key}" if path else str(key)
    raise SceneError(src, where, f"unknown key{hint}; allowed here: {', '.join(allowed)}")


def _validate_table(data, table: Table, src: str, path: str, fill_defaults: bool = True) -> dict:
    if not isinstance(data, dict):
        raise SceneError(src, path, f"expected a table, got {data!r}")
    out = {}
    for key, value in data.items():
        if key not in table.keys:
            _unknown(src, path, key, table.keys)
        spec = table.keys[key]
        sub = f"{path}.{key}" if path else key
        if isinstance(spec, Table):
            out[key] = _validate_table(value, spec, src, sub)
        else:
            out[key] = _check_key(value, spec, src, sub)
    if fill_defaults:
        for key, spec in table.keys.items():
            if key in out:
                continue
            if isinstance(spec, Table) and not spec.array and path not in ("outputs",):
                out[key] = _validate_table({}, spec, src, f"{path}.{key}" if path else key)
            elif isinstance(spec, Key):
                out[key] = copy.deepcopy(spec.default)
    return out


# --------------------------------------------------------------------------- the scene
@dataclass(frozen=True)
class Scene:
    """A validated scene: every section filled with its defaults. Build it with :func:`load_scene`."""

    data: MappingProxyType
    source: str = "<scene>"
    outputs: tuple = field(default=())

    def section(self, name: str) -> dict:
        """A deep copy of one validated section (``"sphere"``, ``"damper"``, ...)."""
        return copy.deepcopy(self.data[name])

    @property
    def name(self) -> str:
        """The scene's short name."""
        return self.data["scene"]["name"]

    def wants(self, kind: str) -> bool:
        """Whether the scene asks for output ``kind``."""
        return kind in self.outputs

    def output(self, kind: str) -> dict:
        """Options of one requested output."""
        return copy.deepcopy(self.data["outputs"][kind])

    # -- physics objects (imports are local: the scene layer sits on top of the core)
    def sphere_mass(self) -> float:
        """Sphere mass in kg: ``mass_kg``, else density (or the material's) times volume."""
        s = self.data["sphere"]
        if s["mass_kg"] is not None:
            return s["mass_kg"]
        return self.sphere_density() * 4.0 / 3.0 * math.pi * s["radius_m"] ** 3

    def sphere_density(self) -> float:
        """Sphere density in kg/m³ (given, the material's, or 7800)."""
        s = self.data["sphere"]
        if s["density_kg_m3"] is not None:
            return s["density_kg_m3"]
        if s["material"]:
            from .materials import material

            return material(s["material"]).density
        return 7800.0

    def k_hertz(self, radius: float | None = None) -> float:
        """Hertz stiffness in N/m^1.5: given, else from the materials (sphere of ``radius``), else 5.6e8."""
        c, s = self.data["contact"], self.data["sphere"]
        if c["k_hertz_n_m1_5"] is not None:
            return c["k_hertz_n_m1_5"]
        if s["material"] or c["surface"]:
            from .contact import hertz_stiffness
            from .materials import material

            sm = material(s["material"] or "steel")
            fm = material(c["surface"]) if c["surface"] else sm
            return hertz_stiffness(s["radius_m"] if radius is None else radius, sm, fm)
        return 5.6e8

    def damper_sphere_radius(self) -> float:
        """Radius in m of the sphere used for damper impacts (see ``sphere.damper_radius``)."""
        s = self.data["sphere"]
        if s["damper_radius"] == "given":
            return s["radius_m"]
        m = self.data["damper"]["impact_mass_kg"]
        return (3.0 * m / (4.0 * math.pi * self.sphere_density())) ** (1.0 / 3.0)

    def medium(self):
        """The fluid as a :class:`~acoustiviz.medium.Medium`."""
        from .medium import Medium

        m = self.data["medium"]
        return Medium(c=m["c_m_s"], rho=m["rho_kg_m3"])

    def configuration(self, radius: float | None = None):
        """The surfaces and image sources (:func:`acoustiviz.images.configuration`) for a sphere of ``radius``."""
        from .images import configuration

        c = self.data["configuration"]
        a = self.data["sphere"]["radius_m"] if radius is None else radius
        if c["kind"] != "wall-floor":
            return configuration(c["kind"], a)
        if c["strike"] == "wall":
            return configuration("wall-floor", a, wall_distance=a, strike="wall", height=c["height_m"] or a)
        return configuration("wall-floor", a, wall_distance=c["wall_distance_m"])

    def impact(self, velocity: float | None = None):
        """The single impact (or one at ``velocity`` m/s) as an :class:`~acoustiviz.contact.Impact`."""
        from .contact import Impact

        u = self.data["impact"]["velocity_m_s"] if velocity is None else velocity
        partner = math.inf
        if self.data["contact"]["pulse_mass"] == "effective":
            partner = self.data["damper"]["main_mass_kg"]
        return Impact(velocity=u, k_hertz=self.k_hertz(), mass=self.sphere_mass(), partner_mass=partner)

    def pulse(self, velocity: float | None = None, kind: str | None = None):
        """The acceleration pulse of :meth:`impact`."""
        from .contact import acceleration_pulse

        return acceleration_pulse(self.impact(velocity), kind or self.data["contact"]["pulse"])

    def listeners(self, radius: float | None = None):
        """Listener names and positions: a list of ``(name, (3,) ndarray in m)``.

        Listeners given by distance and angle are placed from the centre of a sphere of
        ``radius`` (default ``sphere.radius_m``) touching the struck surface.
        """
        import numpy as np

        from .images import observer_points

        conf = self.configuration(radius)
        out = []
        for i, lst in enumerate(self.data["listeners"]):
            name = lst["name"] or f"listener{i + 1}"
            if lst["position_m"] is not None:
                pos = np.asarray(lst["position_m"], dtype=float)
            else:
                pos = observer_points(conf, lst["distance_m"], math.radians(lst["angle_deg"]))[0]
            out.append((name, pos))
        return out


def _validate_listeners(raw, src, radius):
    if raw is None:
        return [dict(DEFAULT_LISTENER, position_m=None)]
    if not isinstance(raw, list) or not raw:
        raise SceneError(src, "listeners", "expected one or more [[listeners]] tables")
    out = []
    for i, item in enumerate(raw):
        path = f"listeners[{i}]"
        lst = _validate_table(item, SCHEMA["listeners"], src, path)
        polar = lst["distance_m"] is not None or lst["angle_deg"] is not None
        if lst["position_m"] is not None and polar:
            raise SceneError(src, path, "give either position_m or distance_m with angle_deg, not both")
        if lst["position_m"] is None:
            if lst["distance_m"] is None or lst["angle_deg"] is None:
                raise SceneError(src, path, "needs distance_m and angle_deg, or position_m")
            if lst["distance_m"] <= radius:
                raise SceneError(src, f"{path}.distance_m", f"listener inside the sphere: must be > radius = "
                                                            f"{radius:g} m, got {lst['distance_m']:g} m")
        out.append(lst)
    return out


def scene_from_dict(raw: dict, source: str = "<scene>") -> Scene:
    """Validate a parsed scene mapping and fill in every default.

    Parameters
    ----------
    raw : dict
        The parsed TOML document.
    source : str
        Name of the file (for messages).

    Raises
    ------
    SceneError
        On the first invalid entry, naming ``source``, the key path and the allowed values.
    """
    if not isinstance(raw, dict):
        raise SceneError(source, "<root>", "expected a TOML table")
    for key in raw:
        if key not in SCHEMA:
            _unknown(source, "", key, SCHEMA)
    data = {}
    for name, table in SCHEMA.items():
        if name == "listeners":
            continue
        if name == "outputs":
            continue
        data[name] = _validate_table(raw.get(name, {}), table, source, name)
    radius = data["sphere"]["radius_m"]
    s = data["sphere"]
    if s["mass_kg"] is not None and s["density_kg_m3"] is not None:
        raise SceneError(source, "sphere.mass_kg", "give either mass_kg or density_kg_m3, not both")
    from .materials import material

    for path, name in (("sphere.material", s["material"]), ("contact.surface", data["contact"]["surface"])):
        if name is not None:
            try:
                material(name)
            except ParameterError as exc:
                raise SceneError(source, path, str(exc).split(": ", 1)[1]) from None
    if data["contact"]["k_hertz_n_m1_5"] is not None and data["contact"]["surface"] is not None:
        raise SceneError(source, "contact.k_hertz_n_m1_5", "give either k_hertz_n_m1_5 or surface, not both")
    conf = data["configuration"]
    if conf["height_m"] is not None and conf["height_m"] < radius:
        raise SceneError(source, "configuration.height_m", f"the sphere would cut the floor: must be >= radius = "
                                                           f"{radius:g} m, got {conf['height_m']:g} m")
    if conf["kind"] == "wall-floor" and conf["strike"] == "floor" and conf["wall_distance_m"] < radius:
        raise SceneError(source, "configuration.wall_distance_m",
                         f"the sphere would cut the wall: must be >= radius = {radius:g} m, "
                         f"got {conf['wall_distance_m']:g} m")
    data["listeners"] = _validate_listeners(raw.get("listeners"), source, radius)

    outs_raw = raw.get("outputs", {})
    if not isinstance(outs_raw, dict):
        raise SceneError(source, "outputs", f"expected a table, got {outs_raw!r}")
    outputs = {}
    for kind, value in outs_raw.items():
        if kind not in _OUT:
            _unknown(source, "outputs", kind, _OUT)
        if value is False:
            continue
        if value is True:
            value = {}
        outputs[kind] = _validate_table(value, _OUT[kind], source, f"outputs.{kind}")
    if "wav" in outputs:
        if outputs["wav"]["struck_wall"] not in (-1, 1):
            raise SceneError(source, "outputs.wav.struck_wall",
                             f"must be -1 or +1, got {outputs['wav']['struck_wall']}")
        if outputs["wav"]["stereo"] and len(data["listeners"]) < 2:
            raise SceneError(source, "outputs.wav.stereo", "needs two [[listeners]] (left, right)")
    if "design_table" in outputs and "sweep" not in outputs:
        raise SceneError(source, "outputs.design_table", "needs [outputs.sweep] in the same scene")
    data["outputs"] = outputs
    order = tuple(k for k in OUTPUT_KINDS if k in outputs)
    scene = Scene(MappingProxyType(data), source, order)
    _check_geometry(scene)
    return scene


def _check_geometry(scene: Scene) -> None:
    """Listeners in the fluid; grids within the memory cap."""
    src = scene.source
    conf = scene.configuration()
    import numpy as np

    for i, (_name, pos) in enumerate(scene.listeners()):
        if not bool(conf.in_fluid(np.asarray(pos)[None, :])[0]):
            key = f"listeners[{i}]"
            lst = scene.data["listeners"][i]
            key += ".position_m" if lst["position_m"] is not None else ".angle_deg"
            raise SceneError(src, key, "listener inside the sphere, below the floor or behind the wall "
                                       f"(configuration {conf.name!r}; the fluid is z > 0"
                                       + (", x > -wall_distance" if conf.name == "wall-floor" else "") + ")")
    grids = scene.data["grids"]
    cap = grids["memory_limit_mb"] * 2**20
    n_plane = grids["plane"]["resolution"] ** 2
    n_sphere = 2 * grids["sphere"]["n_theta"] ** 2
    checks = []
    if scene.wants("snapshot"):
        checks.append(("grids.plane.resolution", n_plane * len(scene.data["outputs"]["snapshot"]["times_s"]) * 8))
    if scene.wants("animation"):
        checks.append(("grids.plane.resolution", n_plane * scene.data["outputs"]["animation"]["frames"] * 8))
    if scene.wants("balloon"):
        checks.append(("grids.sphere.n_theta", n_sphere * 8 * 8))
    for key, need in checks:
        if need > cap:
            raise SceneError(src, key, f"the grid needs {need / 2**20:.4g} MiB, more than "
                                       f"grids.memory_limit_mb = {grids['memory_limit_mb']:g} MiB; "
                                       "lower the resolution or frames, or raise the cap")


def scene_from_text(text: str, source: str = "<scene>") -> Scene:
    """Parse TOML text and validate it (see :func:`scene_from_dict`)."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(source, "<toml>", f"not valid TOML: {exc}") from None
    return scene_from_dict(raw, source)


def load_scene(path) -> Scene:
    """Load and validate a scene file (TOML).

    Raises
    ------
    SceneError
        If the file cannot be read or anything in it is invalid.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(str(p), "<file>", f"cannot read the scene: {exc.strerror or exc}") from None
    return scene_from_text(text, str(p))


def shipped_scenes() -> dict:
    """Names and texts of the scenes shipped in ``assets/scenes`` (installed with the package)."""
    folder = resources.files("acoustiviz").joinpath("assets/scenes")
    return {f.name.removesuffix(".toml"): f.read_text("utf-8")
            for f in sorted(folder.iterdir(), key=lambda f: f.name) if f.name.endswith(".toml")}


def default_scene() -> Scene:
    """The built-in default scene: the paper's Table 1 damper striking a plane, listener at 0.7 m, 45°."""
    return scene_from_text(shipped_scenes()["default"], "<built-in default scene>")


def schema_help() -> str:
    """Human-readable description of every scene key, unit, range and default."""
    lines = []

    def walk(table: Table, path: str, depth: int):
        for key, spec in table.keys.items():
            sub = f"{path}.{key}" if path else key
            if isinstance(spec, Table):
                head = f"[[{sub}]]" if spec.array else f"[{sub}]"
                lines.append(f"{'  ' * depth}{head}  {spec.doc}")
                walk(spec, sub, depth + 1)
            else:
                rng = f" in {_fmt_range(spec)}" if spec.kind in ("float", "int", "floats", "range") else ""
                ch = f" one of {', '.join(spec.choices)}" if spec.choices else ""
                lines.append(f"{'  ' * depth}{key} = {_type_name(spec.kind)}{rng}{ch}; default {spec.default!r}: "
                             f"{spec.doc}")

    for name, table in SCHEMA.items():
        lines.append(f"[[{name}]]" if table.array else f"[{name}]  {table.doc}")
        walk(table, name, 1)
    return "\n".join(lines)
