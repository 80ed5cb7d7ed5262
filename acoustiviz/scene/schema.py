"""The scene schema as data: every key with its type, unit, range, default and meaning."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ..app.settings.auralize import ALL as _AURALIZE
from ..app.settings.damper import BALL_START, BALLS, CAVITY, DAMPER
from ..app.settings.design import DESIGN, RANK_BY
from ..app.settings.forced import AMPLITUDE, EXCITATION_KIND, FORCED, FREQUENCIES
from ..app.settings.impact import DIRECTIVITY, IMPACT, WAVEFORM
from ..app.settings.levels import ALL as LEVELS_OPTIONS
from ..app.settings.map import MAP_SCENE_VTK
from ..app.settings.map import MAP_SETTINGS as _MAP_SETTINGS
from ..app.settings.optimize import EXECUTION as _OPT_EXECUTION
from ..app.settings.optimize import OPTIMIZE, SCENE_LEVELS, SCENE_OPERATION, SCENE_VARIABLES
from ..app.settings.render import ANIMATION, BALLOON, SCENE_FILES, SECTION_LIST, SIZES, SNAPSHOT, TIMES
from ..app.settings.room import ROOM
from ..app.settings.run_field import RUN_FIELD
from ..app.settings.scene import CONFIGURATION_KEYS, CONTACT_KEYS, GRIDS, LISTENER_KEYS, OUTPUT_KEYS, SCENE, SPHERE_KEYS
from ..app.settings.sweep import SCENE_SWEEP, SWEEP, SWEEP_DAMPER, SWEEP_SOUND, SWEPT
from ..constants import (
    PAPER_ANGLE_DEG,
    PAPER_DISTANCE,
)

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
    high_open: bool = False


@dataclass(frozen=True)
class Table:
    """A sub-table of keys; ``optional`` tables may be absent (outputs are requested by presence)."""

    keys: dict
    doc: str = ""
    array: bool = False  # [[name]] array of tables


def _key(st) -> Key:
    """The scene key of record ``st``: its scene type, meaning and default where they differ from the command line's.

    An image size is the list ``[width, height]``; a tuple default is the list TOML gives.
    """
    kind, default, length = _KINDS.get(st.key_kind, st.key_kind), st.in_scene, st.length
    if st.key_kind == "size":
        length = 2
    if isinstance(default, tuple):
        default = list(default)
    return Key(kind, st.key_doc, default, st.unit, low=st.low, high=st.high, low_open=st.low_open,
               choices=st.choices, length=length, high_open=st.high_open)


#: A record's kind -> the scene key's.
_KINDS = {"size": "ints"}


def _from_table(settings, table: str, order=None) -> dict:
    """The keys of scene table ``table`` (``"grids.sphere"``) among ``settings``, built from their records.

    The records are the single home of each range, unit, default and meaning
    (:mod:`acoustiviz.app.settings`); the scene takes its own default where it has one. ``order``:
    the keys in this order (default: the records').
    """
    keys = {}
    for st in settings:
        if st.key and st.table == table:
            keys.setdefault(st.key, _key(st))
    return keys if order is None else {k: keys[k] for k in order}


_MEDIUM = _from_table(IMPACT, "medium")

#: The keys of ``[outputs.wav]``: the records of ``acoustiviz auralize`` that have one.
_WAV = _from_table(_AURALIZE, "outputs.wav")

_SPHERE = _from_table(IMPACT + SPHERE_KEYS, "sphere",
                      ("radius_m", "material", "density_kg_m3", "mass_kg", "damper_radius"))

_CONTACT = {
    **_from_table(DAMPER, "contact"),
    **_from_table(IMPACT + CONTACT_KEYS, "contact", ("surface", "pulse", "pulse_mass")),
}

_IMPACT = _from_table(IMPACT, "impact")

_CONFIGURATION = _from_table(IMPACT + ROOM + WAVEFORM + CONFIGURATION_KEYS, "configuration", (
    "kind", "wall_distance_m", "strike", "height_m", "room_m", "absorption", "source_m", "image_order", "tolerance_db",
    "window_s"))

_DAMPER_RECORDS = _from_table(DAMPER, "damper")
_DAMPER = {k: _DAMPER_RECORDS[k] for k in (
    "main_mass_kg", "stiffness_n_m", "damping_n_s_m", "impact_mass_kg", "gap_m", "contact_damping_n_s_m",
    "clip_tensile", "initial_velocity_m_s", "initial_displacement_m", "duration_s", "solver", "tolerance")}
_DAMPER.update(_from_table(BALLS + BALL_START, "damper"))  # several balls in the cavity (acoustiviz damper --balls)
# several cavities on the main mass, each with its balls ([[damper.cavities]]; a scene's only)
_DAMPER["cavities"] = Table(_from_table(CAVITY, "damper.cavities"),
                            "several cavities on the main mass, each a column of equal balls (numbered c1, c2 ... "
                            "in the impact table); damper.balls stays 1", array=True)

_EXCITATION = _from_table((EXCITATION_KIND, AMPLITUDE, FREQUENCIES, *FORCED), "excitation")
# the frequencies are written as text (a range or a list), each value in the record's range
_EXCITATION["frequencies_hz"] = dataclasses.replace(_EXCITATION["frequencies_hz"], kind="frequencies")

_LISTENER = _from_table(LISTENER_KEYS, "listeners")

_SPHERE_GRID = _from_table(BALLOON, "grids.sphere")

_PLANE_GRID = _from_table((*SNAPSHOT, *ANIMATION, SECTION_LIST), "grids.plane")


def _view(view: str, records=()) -> dict:
    """The keys of ``[outputs.<view>]``: its records, its image size and its extra files."""
    return _from_table((*records, SIZES[view], *SCENE_FILES[view]), f"outputs.{view}")


#: ``[outputs.level_map]``: the settings of ``acoustiviz map`` (one definition, acoustiviz.app.maps).
_LEVEL_MAP = _from_table((*_MAP_SETTINGS, MAP_SCENE_VTK), "outputs.level_map")


def _optimize_keys() -> dict:
    """``[outputs.optimize]`` from its records: the variables, objectives, constraints, budget and workers."""
    return _from_table(SCENE_VARIABLES + OPTIMIZE + _OPT_EXECUTION + (SCENE_LEVELS, *SCENE_OPERATION),
                       "outputs.optimize")


_OUT = {
    "waveform": Table(_from_table(OUTPUT_KEYS, "outputs.waveform"), "pressure waveform at each listener"),
    "directivity": Table(_from_table(DIRECTIVITY, "outputs.directivity"),
                         "peak, RMS and SPL (and the chosen metric) against angle at the first listener's distance"),
    "level_map": Table(_LEVEL_MAP, "peak SPL and SEL of the single impact over a plane, as `acoustiviz map` "
                       "(level_map.png, level_map.csv)"),
    "snapshot": Table(_view("snapshot", (TIMES,)),
                      "pressure field on the planar sections at given times (pyvista)"),
    "balloon": Table(_view("balloon", BALLOON), "3-D directivity balloon on the spherical grid (pyvista)"),
    "animation": Table(_view("animation", ANIMATION), "GIF of the wavefront on the planar sections (pyvista)"),
    "damper_history": Table({}, "main-mass displacement with and without damper (paper Figure 5)"),
    "impact_table": Table({}, "one row per contact of the damper run (CSV)"),
    "restitution": Table(_from_table(OUTPUT_KEYS, "outputs.restitution"),
                         "coefficient of restitution against impact mass (paper Figure 7)"),
    "sweep": Table(_from_table(SWEPT + SWEEP + SCENE_SWEEP + SWEEP_DAMPER + SWEEP_SOUND, "outputs.sweep"),
                   "sweep over gap and impact mass (paper Figure 6)"),
    "design_table": Table(_from_table(DESIGN + (RANK_BY,), "outputs.design_table"),
        "quietest design per damping-inclination band (paper Table 2); needs [outputs.sweep]"),
    "optimize": Table(_optimize_keys(), "the damper to build, found by an optimiser over gap and impact mass "
                      "(optimize/evaluations.csv, pareto.csv, optimize.json, pareto.png)"),
    "wav": Table({k: _WAV[k] for k in ("rate_hz", "stereo", "subtype", "struck_wall", "walls", "late_tail",
                                       "tail_seed", "tail_decay", "transition_s", "absorption_bands")},
                 "calibrated WAV of the damper run at each listener (plays without clipping by default)"),
    "levels": Table(_from_table(LEVELS_OPTIONS, "outputs.levels"),
                    "LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL, SEL(A) of the damper run at each listener, "
                    "evaluated at 96 kHz (CSV)"),
    "run_field": Table(_from_table(RUN_FIELD, "outputs.run_field"),
                       "the damper run's levels on a grid of listeners (an arc of directions or a plane: "
                       "run_directivity.csv/.png or run_map.csv/.png, evaluated at 96 kHz), its pressure at each "
                       "listener (run_waveform.csv/.png) and at one instant over a plane (run_snapshot.png/.vtu)"),
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
    "scene": Table(_from_table(SCENE, "scene"), "title"),
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
                    **_from_table(GRIDS, "grids")},
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
    hb = ")" if k.high_open else "]"
    u = f" {k.unit}" if k.unit else ""
    return f"{lb}{k.low:g}, {k.high:g}{hb}{u}"


def _type_name(kind: str) -> str:
    return {"float": "a number", "int": "an integer", "bool": "true or false", "str": "a string",
            "floats": "a list of numbers", "strs": "a list of strings", "texts": "a list of strings",
            "point": "a list of 3 numbers",
            "ints": "a list of integers",
            "range": "a 'start:stop:count' string, 'a,b,c' or one number",
            "frequencies": "a 'start:stop:count' string, 'f1,f2,...' or one number"}[kind]
