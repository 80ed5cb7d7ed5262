"""The scene schema as data: every key with its type, unit, range, default and meaning."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..app.settings.base import SIZE_RANGE
from ..app.settings.damper import BALLS, DAMPER
from ..app.settings.design import DESIGN
from ..app.settings.forced import AMPLITUDE, FORCED, FREQUENCIES
from ..app.settings.impact import DIRECTIVITY, IMPACT, WAVEFORM
from ..app.settings.map import MAP_SETTINGS as _MAP_SETTINGS
from ..app.settings.render import ANIMATION, BALLOON, MAX_TIMES, SNAPSHOT
from ..app.settings.sweep import SWEEP
from ..constants import (
    ANIMATION_SIZE,
    EXCITATIONS,
    PAPER_ANGLE_DEG,
    PAPER_DISTANCE,
    PULSES,
    ROOM_STRIKES,
    SAMPLE_RATES,
    STILL_SIZE,
    WAV_RATE,
)
from ..core.geometry import GEOMETRIES

__all__ = [
    "SCHEMA",
    "OUTPUT_KINDS",
    "schema_help",
]


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

def _from_table(settings, table: str) -> dict:
    """The keys of scene table ``table`` (``"grids.sphere"``) among ``settings``, built from their records.

    The records are the single home of each range, unit, default and meaning
    (:mod:`acoustiviz.app.settings`); the scene takes its own default where it has one.
    """
    keys = {}
    for st in settings:
        if st.key and st.table == table:
            keys.setdefault(st.key, Key(st.kind, st.doc, st.in_scene, st.unit, low=st.low,
                                                          high=st.high, low_open=st.low_open, choices=st.choices))
    return keys


_MEDIUM = {
    **_from_table(IMPACT, "medium"),
}

_SPHERE = {
    "radius_m": _from_table(IMPACT, "sphere")["radius_m"],
    "material": Key("str", "sphere material from the catalogue (sets density; with contact.surface, K_HZ)", None),
    "density_kg_m3": _from_table(IMPACT, "sphere")["density_kg_m3"],
    "mass_kg": _from_table(IMPACT, "sphere")["mass_kg"],
    "damper_radius": Key("str", "sphere radius for damper impacts: 'given' keeps radius_m (the paper's choice), "
                         "'from-mass' derives it from the impact mass and the density", "given",
                         choices=("given", "from-mass")),
}

_CONTACT = {
    **_from_table(DAMPER, "contact"),
    "surface": Key("str", "surface material from the catalogue (K_HZ from sphere and surface materials)", None),
    "pulse": Key("str", "acceleration pulse", "half-sine", choices=PULSES),
    "pulse_mass": Key("str", "mass in the pulse: the impact mass alone or the effective mass of the two bodies",
                      "impact", choices=("impact", "effective")),
}

_IMPACT = {
    **_from_table(IMPACT, "impact"),
}

_CONFIGURATION = {
    "kind": Key("str", "free field, reflecting plane (floor z = 0), wall-floor corner, or a shoebox room "
                "(also written [geometry])", "plane", choices=tuple(GEOMETRIES)),
    "wall_distance_m": _from_table(IMPACT, "configuration")["wall_distance_m"],
    "strike": Key("str", "wall-floor: struck surface (a wall strike puts the sphere against the wall, "
                  "accelerating along +x); room: floor, ceiling or x0, x1, y0, y1, z0, z1", "floor",
                  choices=("floor", "wall") + ROOM_STRIKES[1:]),
    "height_m": _from_table(IMPACT, "configuration")["height_m"],
    "room_m": Key("floats", "room: dimensions [Lx, Ly, Lz] of the room [0, Lx] x [0, Ly] x [0, Lz], floor z = 0",
                  None, "m", length=3),
    "absorption": Key("floats", "room: energy absorption coefficient alpha in [0, 1), one value or six "
                      "(x0, x1, y0, y1, z0 floor, z1 ceiling); default 0, rigid", None, length=6),
    "source_m": Key("point", "room: centre of the sphere, touching the surface it strikes (default: the middle of "
                             "the floor)", None, "m"),
    "image_order": Key("int", "room: image order (default: from tolerance_db and window_s)", None, low=0,
                       high=10000),
    "tolerance_db": Key("float", "room: largest neglected image energy relative to the total (default -60)",
                        None, "dB", low=-200.0, high=0.0),
    **_from_table(WAVEFORM, "configuration"),
}

_DAMPER_RECORDS = _from_table(DAMPER, "damper")
_DAMPER = {k: _DAMPER_RECORDS[k] for k in (
    "main_mass_kg", "stiffness_n_m", "damping_n_s_m", "impact_mass_kg", "gap_m", "contact_damping_n_s_m",
    "clip_tensile", "initial_velocity_m_s", "initial_displacement_m", "duration_s", "solver", "tolerance")}
_DAMPER.update(_from_table(BALLS, "damper"))  # several balls in the cavity (acoustiviz damper --balls)

_EXCITATION = {
    "kind": Key("str", "a harmonic force F0 cos(wt) on the main mass, or a base displacement B cos(wt) acting "
                "through K and C", "force", choices=EXCITATIONS),
    **_from_table((AMPLITUDE,), "excitation"),
    "frequencies_hz": Key("frequencies", FREQUENCIES.doc, FREQUENCIES.in_scene, FREQUENCIES.unit, low=FREQUENCIES.low,
                          high=FREQUENCIES.high, low_open=FREQUENCIES.low_open),
    **_from_table(FORCED, "excitation"),
}

_LISTENER = {
    "name": Key("str", "label used in file names (default listenerN): unique, 1-64 letters, digits, '_', '-', '.' "
                       "and inner spaces, starting with a letter, digit or '_'", None),
    "distance_m": _pos("distance from the sphere's centre (with angle_deg)", "m", None, high=1e4),
    "angle_deg": Key("float", "angle from the acceleration axis (with distance_m)", None, "deg", low=0.0, high=180.0),
    "position_m": Key("point", "position [x, y, z] in the scene frame (instead of distance/angle)", None, "m"),
}

def _swept(name: str, doc: str, default: str) -> Key:
    """A swept damper value of ``[outputs.sweep]``: each value in the range of the damper's record ``name``."""
    r = next(s for s in DAMPER if s.name == name)
    return Key("range", doc, default, r.unit, low=r.low, high=r.high, low_open=r.low_open)


def _size(default) -> Key:
    return Key("ints", "image width and height", default, "px", low=SIZE_RANGE[0], high=SIZE_RANGE[1], length=2)


_SPHERE_GRID = _from_table(BALLOON, "grids.sphere")

_PLANE_GRID = {
    **_from_table(SNAPSHOT + ANIMATION, "grids.plane"),
    "sections": Key("strs", "sections through the sphere's centre: 'xz' the vertical plane normal to the wall "
                    "(holding the acceleration axis), 'yz' the vertical plane parallel to it, 'xy' the horizontal",
                    ["xz"], choices=("xz", "yz", "xy")),
}

#: Shared by the 3-D outputs: also write the data behind the picture (acoustiviz.output.vtk).
_VTK = Key("bool", "also write the data as <output>.vtu with the sphere and planes in <output>_geometry.vtu "
           "(ParaView, pyvista, meshio)", False)

#: ``[outputs.level_map]``: the settings of ``acoustiviz map`` (one definition, acoustiviz.app.maps).
_LEVEL_MAP = _from_table(_MAP_SETTINGS, "outputs.level_map")
_LEVEL_MAP["vtk"] = Key("bool", "also write the map as level_map.vtu with the sphere and planes in "
                        "level_map_geometry.vtu (ParaView, pyvista, meshio)", False)

_OUT = {
    "waveform": Table({"pulses": Key("strs", "pulses to compare", None, choices=PULSES)},
                      "pressure waveform at each listener"),
    "directivity": Table(_from_table(DIRECTIVITY, "outputs.directivity"),
                         "peak, RMS and SPL (and the chosen metric) against angle at the first listener's distance"),
    "level_map": Table(_LEVEL_MAP, "peak SPL and SEL of the single impact over a plane, as `acoustiviz map` "
                       "(level_map.png, level_map.csv)"),
    "snapshot": Table({"times_s": Key("floats", f"snapshot times (at most {MAX_TIMES}, drawn side by side)",
                                      [0.001], "s", low=0.0, high=10.0, length=MAX_TIMES),
                       "size_px": _size([1400, 600]),
                       "vtk": _VTK},
                      "pressure field on the planar sections at given times (pyvista)"),
    "balloon": Table({**_from_table(BALLOON, "outputs.balloon"), "size_px": _size(list(STILL_SIZE)), "vtk": _VTK},
                     "3-D directivity balloon on the spherical grid (pyvista)"),
    "animation": Table({**_from_table(ANIMATION, "outputs.animation"), "size_px": _size(list(ANIMATION_SIZE)),
                        "vtk": _VTK},
                       "GIF of the wavefront on the planar sections (pyvista)"),
    "damper_history": Table({}, "main-mass displacement with and without damper (paper Figure 5)"),
    "impact_table": Table({}, "one row per contact of the damper run (CSV)"),
    "restitution": Table({
        "masses_kg": Key("floats", "impact masses", [0.01, 0.02, 0.04, 0.06, 0.08, 0.1], "kg", low=1e-6, high=1e4),
        "velocities_m_s": Key("floats", "approach speeds", [0.5, 1.0, 2.0], "m/s", low=1e-4, high=1e3)},
        "coefficient of restitution against impact mass (paper Figure 7)"),
    "sweep": Table({
        "gap_m": _swept("gap", "gap range start:stop:count", "0.02:0.06:5"),
        "mass_kg": _swept("m", "impact-mass range start:stop:count", "0.02:0.08:4"),
        **_from_table(SWEEP, "outputs.sweep"),
        "workers": Key("int", "worker processes (0: all cores)", 0, low=0, high=1024),
        "levels": Key("bool", "also LAFmax, LCpeak and LAeq of each design's run at the listener, rendered at "
                      "96 kHz (about 0.3 s more per 20 s design)", False)},
        "sweep over gap and impact mass (paper Figure 6)"),
    "design_table": Table(_from_table(DESIGN, "outputs.design_table"),
        "quietest design per damping-inclination band (paper Table 2); needs [outputs.sweep]"),
    "wav": Table({"rate_hz": Key("int", "sample rate", WAV_RATE, "Hz", low=min(SAMPLE_RATES), high=max(SAMPLE_RATES),
                                 choices=SAMPLE_RATES),
                  "stereo": Key("bool", "one stereo file from the first two listeners", False),
                  "subtype": Key("str", "PCM_24: normalised to peak 1 dB below full scale, one shared scale "
                                 "(Pa per full scale) recorded in the sidecar; FLOAT: float32 in pascals (1.0 = 1 Pa)",
                                 "PCM_24", choices=("PCM_24", "FLOAT")),
                  "struck_wall": Key("int", "damper wall lying on the struck surface z = 0", -1, low=-1, high=1),
                  "walls": Key("str", "'both': impacts on the far wall radiate from it with the reversed axis; "
                               "'one': every impact is heard as a strike on z = 0", "both", choices=("both", "one")),
                  "late_tail": Key("bool", "room: images exactly only until the transition time, then a seeded "
                                   "statistical tail (noise decaying per band, Eyring's T60 by default) until "
                                   "configuration.tolerance_db of the energy", False),
                  "tail_seed": Key("int", "room: seed of the tail's noise", 20261126, low=0, high=2**63 - 1),
                  "tail_decay": Key("str", "room: the tail's decay, Eyring's T60 per band or the image sum's own",
                                    "eyring", choices=("eyring", "images")),
                  "transition_s": _pos("room, late_tail: transition time from the start of contact (default: "
                                       "max(sqrt(V) ms, one reflection per contact duration))", "s", None, high=10.0),
                  "absorption_bands": Key("str", "room: absorption per octave band instead of configuration."
                                          "absorption, 'F:A,F:A,...' (centre F in Hz in [16, 20000], increasing; "
                                          "alpha A in [0, 1)) or 'F:A1/A2/A3/A4/A5/A6,...' per surface; the "
                                          "room's other outputs use each surface's least absorbing band", None)},
                 "calibrated WAV of the damper run at each listener (plays without clipping by default)"),
    "levels": Table({"loudness": Key("bool", "also ISO 532-1 loudness and DIN 45692 sharpness (needs mosqito)",
                                     False)},
                    "LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL, SEL(A) of the damper run at each listener, "
                    "evaluated at 96 kHz (CSV)"),
    "spectrum": Table({}, "1/3-octave band Leq and LFmax of the damper run at each listener (CSV and PNG)"),
    "frequency_response": Table({}, "steady-state amplitude with and without the damper, regimes and "
                                "hysteresis over the [excitation] frequencies (CSV, PNG)"),
    "bifurcation": Table({}, "main-mass displacement at forcing phase 0 against forcing frequency (PNG)"),
    "operating_noise": Table(_from_table(FORCED, "outputs.operating_noise"),
                             "LAeq, LCpeak, LAFmax, LZpeak, LZeq and SEL per cycle of the steady click train at "
                             "the first listener per forcing frequency, at 96 kHz over whole periods after a 1 s "
                             "lead-in (CSV; also the level columns of frequency_response), and a WAV of the "
                             "frequencies in turn"),
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
    "excitation": Table(_EXCITATION, "harmonic excitation of the damper in operation"),
    "listeners": Table(_LISTENER, "listeners ([[listeners]], each with distance_m and angle_deg, or position_m)",
                       array=True),
    "grids": Table({"sphere": Table(_SPHERE_GRID, "spherical grid"), "plane": Table(_PLANE_GRID, "planar grid"),
                    "memory_limit_mb": _pos("memory cap of grid evaluations", "MiB", 256.0, high=1e6)},
                   "evaluation grids"),
    "outputs": Table(_OUT, "what to produce; only these are computed"),
}

DEFAULT_LISTENER = {"name": "paper", "distance_m": PAPER_DISTANCE, "angle_deg": PAPER_ANGLE_DEG}


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
                numbers = ("float", "int", "floats", "range", "frequencies")
                rng = f" in {_fmt_range(spec)}" if spec.kind in numbers else ""
                ch = f" one of {', '.join(map(str, spec.choices))}" if spec.choices else ""
                lines.append(f"{'  ' * depth}{key} = {_type_name(spec.kind)}{rng}{ch}; default {spec.default!r}: "
                             f"{spec.doc}")

    for name, table in SCHEMA.items():
        lines.append(f"[[{name}]]" if table.array else f"[{name}]  {table.doc}")
        walk(table, name, 1)
    return "\n".join(lines)


def _fmt_range(k: Key) -> str:
    lb = "(" if k.low_open else "["
    u = f" {k.unit}" if k.unit else ""
    return f"{lb}{k.low:g}, {k.high:g}]{u}"


def _type_name(kind: str) -> str:
    return {"float": "a number", "int": "an integer", "bool": "true or false", "str": "a string",
            "floats": "a list of numbers", "strs": "a list of strings", "point": "a list of 3 numbers",
            "ints": "a list of integers",
            "range": "a 'start:stop:count' string, 'a,b,c' or one number",
            "frequencies": "a 'start:stop:count' string, 'f1,f2,...' or one number"}[kind]
