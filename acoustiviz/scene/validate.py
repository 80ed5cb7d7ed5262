"""Validation of scene values against the schema; :class:`SceneError` names the file, key path and range."""

from __future__ import annotations

import copy
import difflib
import math

from ..constants import PULSES
from ..errors import ParameterError, SceneError
from .schema import Key, Table, _fmt_range, _type_name

__all__ = [
    "SceneError",
    "parse_range",
    "scene_frequencies",
]


# --------------------------------------------------------------------------- helpers
def parse_range(text, key: str = "range", source: str = "<range>"):
    """Parse ``start:stop:count`` (inclusive), a comma list ``a,b,c`` or one number into a list of floats.

    The values follow the one rule of every front-end, :func:`acoustiviz.sweep.spec.parse_values`
    (whose ranges are :func:`~acoustiviz.sweep.spec.value_range`), so a scene's sweep grid is the
    grid of the same ``acoustiviz sweep`` options.
    """
    from ..sweep.spec import parse_values

    try:
        return list(parse_values(key, str(text)))
    except ParameterError as exc:
        raise SceneError(source, key, exc.detail) from None


def scene_frequencies(text, key: str = "excitation.frequencies_hz", source: str = "<scene>"):
    """Forcing frequencies in Hz, read as ``acoustiviz forced --freq`` reads them, or a SceneError naming ``key``.

    The one reading is :func:`acoustiviz.app.settings.parse.parse_frequencies`.
    """
    from ..app.settings.parse import parse_frequencies as frequencies

    try:
        return frequencies(text, key)
    except ParameterError as exc:
        raise SceneError(source, key, exc.detail) from None


def _check_number(v, k: Key, src: str, path: str) -> float:
    if not math.isfinite(v):
        raise SceneError(src, path, f"must be finite, got {v}")
    ok_low = v > k.low if k.low_open else v >= k.low
    ok_high = v < k.high if k.high_open else v <= k.high
    if not (ok_low and ok_high):
        raise SceneError(src, path, f"must lie in {_fmt_range(k)}, got {v:g}")
    return v


def _check_float(value, k: Key, src: str, path: str):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneError(src, path, f"expected {_type_name(k.kind)} in {_fmt_range(k)}, got {value!r}")
    return _check_number(float(value), k, src, path)


def _check_int(value, k: Key, src: str, path: str):
    if isinstance(value, bool) or not isinstance(value, int):
        raise SceneError(src, path, f"expected {_type_name(k.kind)} in {_fmt_range(k)}, got {value!r}")
    if k.choices and value not in k.choices:
        raise SceneError(src, path, f"must be one of {', '.join(map(str, k.choices))}"
                                    f"{' ' + k.unit if k.unit else ''}, got {value}")
    return int(_check_number(value, k, src, path))


def _check_bool(value, k: Key, src: str, path: str):
    if not isinstance(value, bool):
        raise SceneError(src, path, f"expected true or false, got {value!r}")
    return value


def _check_str(value, k: Key, src: str, path: str):
    if not isinstance(value, str):
        raise SceneError(src, path, f"expected {_type_name(k.kind)}, got {value!r}")
    if k.choices and value not in k.choices:
        close = difflib.get_close_matches(value, k.choices, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise SceneError(src, path, f"must be one of {', '.join(map(repr, k.choices))}, got {value!r}{hint}")
    return value


def _check_ints(value, k: Key, src: str, path: str):
    if not isinstance(value, list) or len(value) != k.length:
        raise SceneError(src, path, f"expected a list of {k.length} integers in {_fmt_range(k)}, got {value!r}")
    for i, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, int):
            raise SceneError(src, f"{path}[{i}]", f"expected an integer, got {v!r}")
        _check_number(v, k, src, f"{path}[{i}]")
    return list(value)


def _check_floats(value, k: Key, src: str, path: str):
    kind = k.kind
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


def _check_strs(value, k: Key, src: str, path: str):
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value) or not value:
        raise SceneError(src, path, f"expected {_type_name(k.kind)}, got {value!r}")
    allowed = k.choices or PULSES
    for i, v in enumerate(value):
        if v not in allowed:
            raise SceneError(src, f"{path}[{i}]", f"must be one of {', '.join(map(repr, allowed))}, got {v!r}")
    if len(set(value)) != len(value):
        raise SceneError(src, path, f"values must not repeat, got {value!r}")
    return list(value)


def _check_texts(value, k: Key, src: str, path: str):
    """A list of free strings (possibly empty), checked further by the settings object that reads them."""
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise SceneError(src, path, f"expected {_type_name(k.kind)}, got {value!r}")
    return list(value)


def _check_range(value, k: Key, src: str, path: str):
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        value = str(value)
    if not isinstance(value, str):
        raise SceneError(src, path, f"expected {_type_name(k.kind)}, got {value!r}")
    vals = parse_range(value, path, src)
    for v in vals:
        _check_number(v, k, src, path)
    return value


def _check_frequencies(value, k: Key, src: str, path: str):
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        value = str(value)
    if not isinstance(value, str):
        raise SceneError(src, path, f"expected {_type_name(k.kind)}, got {value!r}")
    scene_frequencies(value, path, src)
    return value


#: The check of each kind of key: it returns the value as the scene holds it, or raises SceneError.
_CHECKS = {"float": _check_float, "int": _check_int, "bool": _check_bool, "str": _check_str,
           "ints": _check_ints, "floats": _check_floats, "point": _check_floats, "strs": _check_strs,
           "texts": _check_texts,
           "range": _check_range, "frequencies": _check_frequencies}


def _check_key(value, k: Key, src: str, path: str):
    return _CHECKS[k.kind](value, k, src, path)


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
        if isinstance(spec, Table) and spec.array and path:  # [[table.key]]: a list of tables, each checked
            if not isinstance(value, list) or not value:
                raise SceneError(src, sub, f"expected one or more [[{sub}]] tables, got {value!r}")
            out[key] = [_validate_table(item, spec, src, f"{sub}[{i}]") for i, item in enumerate(value)]
        elif isinstance(spec, Table):
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


#: Geometry settings -> their keys in ``[configuration]``.
_GEOMETRY_KEYS = {"wall_distance": "wall_distance_m", "strike": "strike", "height": "height_m",
                  "dimensions": "room_m", "absorption": "absorption", "source": "source_m", "order": "image_order",
                  "tolerance_db": "tolerance_db", "duration": "window_s"}


def _geometry_settings(table: dict) -> dict:
    """The settings of a ``[configuration]`` table that apply to its ``kind``."""
    from ..core.geometry import relevant_settings

    return relevant_settings(table["kind"], **{k: table[v] for k, v in _GEOMETRY_KEYS.items()})


def check_configuration(data: dict, source: str) -> None:
    """The sphere above the floor, no room key without a room, and the geometry's settings valid for its kind."""
    from ..core.geometry import geometry

    radius = data["sphere"]["radius_m"]
    table = data["configuration"]
    _check_room_keys(table, source)
    if table["height_m"] is not None and table["height_m"] < radius:
        raise SceneError(source, "configuration.height_m", f"the sphere would cut the floor: must be >= radius = "
                                                           f"{radius:g} m, got {table['height_m']:g} m")
    try:
        geometry(table["kind"], radius, **_geometry_settings(table))
    except ParameterError as exc:
        raise SceneError(source, f"configuration.{_GEOMETRY_KEYS.get(exc.name, exc.name)}", exc.detail) from None


def _check_room_keys(table: dict, source: str) -> None:
    """Refuse a room's own key (``room_m``, ``source_m``, ``absorption``, ...) in a configuration that is no room.

    The command line refuses the same settings without ``--room`` (:func:`acoustiviz.app.impacts.room_settings`);
    a scene would otherwise ignore them without a word. The strike is shared with the wall-floor corner.
    """
    from ..core.geometry import GEOMETRIES, geometry_class

    if geometry_class(table["kind"]).enclosed:
        return
    rooms = [name for name, cls in GEOMETRIES.items() if cls.enclosed]
    for setting in GEOMETRIES[rooms[0]].SETTINGS:
        key = _GEOMETRY_KEYS.get(setting)
        if setting != "strike" and key is not None and table[key] is not None:
            raise SceneError(source, f"configuration.{key}", f'only applies with kind = "{rooms[0]}" (a shoebox '
                                                             f'room); kind "{table["kind"]}" would ignore it')


def check_damper_physics(scene) -> None:
    """Refuse, at load, a ``[damper]`` whose run cannot be computed or measured (``core.limits.check_damper``).

    The tolerance is checked first, in the range of the solver named (:data:`acoustiviz.dynamics.METHODS`).

    The same limits the run checks, with the K_HZ of the damper's sphere, raised as a
    :class:`SceneError` naming the key (``damper.impact_mass_kg``) and what is allowed.
    """
    from ..app.damper import check_damper_run
    from ..app.names import SCENE_DAMPER_KEYS

    d = scene.data["damper"]
    try:
        check_damper_run(solver=d["solver"], rtol=d["tolerance"], M=d["main_mass_kg"], K=d["stiffness_n_m"],
                         m=d["impact_mass_kg"], gap=d["gap_m"], k_hertz=scene.k_hertz(scene.damper_sphere_radius()),
                         v=d["initial_velocity_m_s"], duration=d["duration_s"], c1=d["contact_damping_n_s_m"],
                         names=SCENE_DAMPER_KEYS)
    except SceneError:
        raise
    except ParameterError as exc:
        raise SceneError(scene.source, exc.name, exc.detail) from None


def check_window(data: dict, raw: dict, source: str, setup) -> None:
    """A room's waveform window within ``grids.memory_limit_mb``, before the room's image order is sought.

    The time grid alone (:func:`acoustiviz.app.budget.window_estimate`) of a very long window exceeds
    any cap, and seeking the image order of such a window takes long; the full estimate follows.
    ``setup(data)`` builds the impact of a scene's ``data`` (here in the free field, so without the room).
    """
    from ..core.geometry import geometry_class

    table = data["configuration"]
    outputs = raw.get("outputs")
    if table.get("window_s") is None or not isinstance(outputs, dict) or "waveform" not in outputs \
            or not geometry_class(table["kind"]).enclosed:
        return
    from ..app.budget import check_budget, window_estimate
    from ..app.settings.impact import WAVEFORM

    try:
        free = setup({**data, "configuration": {**table, "kind": "free"}})
    except ParameterError:
        return  # an impact refused here is named by the checks that follow
    try:
        check_budget(window_estimate(free.pulse, free.radius, free.medium, table["window_s"], WAVEFORM[0].default,
                                     options=("configuration.window_s",)),
                     data["grids"]["memory_limit_mb"], cap_name="grids.memory_limit_mb")
    except ParameterError as exc:
        raise SceneError(source, exc.name, exc.detail) from None
