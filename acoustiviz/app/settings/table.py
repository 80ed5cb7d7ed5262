"""One record per setting: the single home of its limit, default, unit and meaning.

A :class:`Setting` names a value three ways (its API name, its command-line option and its scene
key) and holds its type, unit, allowed range, choices, default and one-line meaning. The command
line builds its options from it (:func:`add_option`, the ``--help`` text included), the scene
schema builds its keys from it, and the settings objects of :mod:`acoustiviz.app.settings`
check their values with it (:meth:`Setting.check`), so a limit is written once and the three can
never disagree.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from ..._validate import check_choice, check_range
from ...errors import ParameterError
from .base import check_size, parse_size

__all__ = ["Setting", "SAME", "add_option", "by_name", "check_values"]

#: ``scene_default`` of a setting whose default is the same in a scene as on the command line.
SAME = "same"


@dataclass(frozen=True)
class Setting:
    """One setting: its API name, command-line option, scene key, default, range and meaning.

    Attributes
    ----------
    name : str
        The API parameter (and settings-object field) it sets.
    option : str or None
        The command-line option (None: none).
    key : str or None
        The scene key within its table (None: none).
    kind : {"str", "float", "int", "bool", "range", "strs", "floats", "size", "ints", "point"}
        The type of one value (``"bool"``: a flag on the command line; ``"range"``: numbers given as one
        value, ``START:STOP:COUNT`` or ``A,B,C``, each within the range, checked into a tuple); ``"strs"``
        and ``"floats"``: a tuple of 1 to ``length`` names or numbers, each checked as a ``"str"`` or
        ``"float"`` (typed as a comma list and as several values on the command line); ``"size"``: an
        image's ``(width, height)`` in pixels, each an integer in ``[low, high]`` (typed ``WxH``);
        ``"ints"`` and ``"point"`` (3 numbers): lists only a scene gives.
    default : object
        The default (None: computed from other settings, or absent).
    doc : str
        One line saying what it sets.
    unit : str
        SI unit of a number ("" for counts and names).
    low, high : float
        Allowed interval of a number (``low`` excluded when ``low_open``, ``high`` when ``high_open``).
    choices : tuple
        The allowed names of a string.
    scene_default : object
        The default a scene gives it when it differs from the command line's (:data:`SAME`: the same).
    table : str
        The scene table holding ``key`` (``"outputs.level_map"``, ``"grids.plane"``).
    metavar : str, optional
        How ``--help`` shows the option's value (default: ``M`` for lengths, ``N`` otherwise).
    aliases : tuple of str
        Further command-line spellings of the option (``--replace`` beside ``--force``).
    scene_kind : str, optional
        The scene's type of the value where the command line types it as text (``"floats"``: the
        option ``--room 6,4,3`` is the key ``room_m = [6, 4, 3]``); None: ``kind``.
    length : int, optional
        The number of values of a list: the most of ``"strs"`` and ``"floats"``, exactly that many of
        ``"ints"`` (None: any number).
    scene_doc : str, optional
        The meaning in the scene's words where ``doc`` names other options (None: ``doc``).
    positional : bool
        A positional argument of its command (named by ``option`` in errors and ``--help``), not an option.
    required : bool
        The command line requires the option.
    """

    name: str
    option: str | None
    key: str | None
    kind: str
    default: object
    doc: str
    unit: str = ""
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    choices: tuple = ()
    scene_default: object = SAME
    table: str = ""
    metavar: str | None = None
    aliases: tuple = ()
    scene_kind: str | None = None
    length: int | None = None
    scene_doc: str | None = None
    positional: bool = False
    required: bool = False

    @property
    def path(self) -> str | None:
        """The full scene key (``"grids.plane.resolution"``), None without one."""
        return f"{self.table}.{self.key}" if self.key else None

    @property
    def key_kind(self) -> str:
        """The type of the scene key."""
        return self.scene_kind or self.kind

    @property
    def key_doc(self) -> str:
        """The meaning of the scene key."""
        return self.scene_doc or self.doc

    @property
    def in_scene(self) -> object:
        """The default of the scene key."""
        return self.default if self.scene_default == SAME else self.scene_default

    def range_text(self) -> str:
        """``"(0, 90] deg"``: the allowed interval and unit of a number, ``""`` for a string."""
        if self.kind == "str":
            return ""
        u = f" {self.unit}" if self.unit else ""
        return f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}{u}"

    def check(self, value, name: str | None = None):
        """``value`` in the setting's type, or a :class:`ParameterError` naming ``name`` (default: the API name).

        ``None`` passes unchanged (a setting left to its computed default).
        """
        name = name or self.name
        if value is None:
            return None
        if self.kind in _SEQUENCES:
            return self._check_sequence(value, name)
        if self.kind == "size":
            return parse_size(value, name) if isinstance(value, str) else check_size(value, name)
        if self.kind == "point":
            return self._check_point(value, name)
        if self.kind == "str":
            return check_choice(name, value, self.choices) if self.choices else str(value)
        if self.kind == "range":
            return self._check_range(value, name)
        if self.kind == "bool":
            if not _is_bool(value):
                raise ParameterError(name, f"must be true or false, got {value!r}")
            return bool(value)
        if self.kind == "int":
            if isinstance(value, bool) or not isinstance(value, numbers.Integral) \
                    or not self.low <= value <= self.high:
                raise ParameterError(name, f"must be an integer in [{self.low:g}, {self.high:g}], got {value!r}")
            return int(value)
        return check_range(name, value, self.low, self.high, unit=self.unit, low_open=self.low_open,
                           high_open=self.high_open)

    def _check_point(self, value, name: str) -> tuple:
        """``value`` as three finite numbers ``(x, y, z)``, or a :class:`ParameterError` naming ``name``."""
        try:
            v = tuple(float(x) for x in value) if not isinstance(value, str) else ()
        except (TypeError, ValueError):
            v = ()
        if len(v) != 3 or not all(math.isfinite(x) for x in v):
            unit = f" in {self.unit}" if self.unit else ""
            raise ParameterError(name, f"expected three finite numbers [x, y, z]{unit}, got {value!r}")
        return v

    def _check_range(self, value, name: str) -> tuple:
        """The values of ``value`` (one value, ``START:STOP:COUNT``, ``A,B,C`` or a sequence), each in range."""
        from ...sweep.spec import parse_values

        values = parse_values(name, value)
        for v in values:
            check_range(name, v, self.low, self.high, unit=self.unit, low_open=self.low_open,
                        high_open=self.high_open)
        return values

    def _check_sequence(self, value, name: str) -> tuple:
        """A ``"strs"`` or ``"floats"`` value: a tuple of 1 to ``length`` distinct names, or of ranged numbers."""
        if isinstance(value, str):  # a comma list, as typed
            value = [v.strip() for v in value.split(",") if v.strip()]
        try:
            values = tuple(value)
        except TypeError:
            values = (value,)
        if not values or (self.length and len(values) > self.length):
            most = f"one to at most {self.length} values" if self.length else "at least one value"
            raise ParameterError(name, f"expected {most}, got {len(values)}")
        if self.kind == "floats":
            return tuple(check_range(name, v, self.low, self.high, unit=self.unit, low_open=self.low_open)
                         for v in values)
        if any(not isinstance(v, str) or (self.choices and v not in self.choices) for v in values) \
                or len(set(values)) != len(values):
            allowed = f"a subset of {', '.join(self.choices)}" if self.choices else "distinct names"
            raise ParameterError(name, f"expected {allowed}, got {list(values)!r}")
        return values


#: Kinds holding several values.
_SEQUENCES = ("strs", "floats")
_TYPES = {"str": str, "float": float, "int": int, "range": str, "strs": str, "floats": float, "size": str}


def add_option(group, s: Setting, *, metavar: str | None = None, default=SAME, parse_choices: bool = True,
               **kw) -> None:
    """Add ``s`` to an argparse parser or group: its type, default, choices and help from the table.

    Parameters
    ----------
    group : argparse parser or argument group
    s : Setting
    metavar : str, optional
        Shown for the value (default: the record's, else the choices, ``M`` for lengths, ``N`` otherwise).
    default : object, optional
        The option's default when it is not ``s.default`` (:data:`SAME`).
    parse_choices : bool
        Let argparse refuse a name outside ``s.choices``; False leaves it to the settings object
        (its error is the command's one line naming the option, with the closest name).
    **kw
        Further :meth:`argparse.ArgumentParser.add_argument` arguments (``nargs``; ``type=str`` for a number
        typed as a list, read by its own parser; ``action`` for a flag with its negation,
        :class:`argparse.BooleanOptionalAction`).
    """
    if s.kind == "bool":  # a flag
        kw.setdefault("action", "store_true")
        group.add_argument(s.option, *s.aliases, default=s.default if default == SAME else default,
                           help=s.doc.replace("%", "%%"), **kw)
        return
    if s.positional:  # named by its API name; an optional one takes its default when left out
        more = {} if s.required else {"nargs": "?", "default": s.default if default == SAME else default}
        group.add_argument(s.name, metavar=metavar or s.metavar, help=s.doc.replace("%", "%%"), **more, **kw)
        return
    if s.required:
        kw = {"required": True, **kw}
    bounded = s.kind not in ("str", "strs") and not s.choices and (math.isfinite(s.low) or math.isfinite(s.high))
    rng = f", {'each ' if s.kind == 'range' else ''}in {s.range_text()}" if bounded else ""
    value = s.default if default == SAME else default
    if s.kind == "size" and isinstance(value, tuple):  # as typed: WxH
        value = "{}x{}".format(*value)
    elif s.kind == "strs" and isinstance(value, tuple):  # as typed: a comma list
        value = ",".join(value)
    elif s.kind == "floats":  # several values after the option
        kw.setdefault("nargs", "+")
    shown = " (default %(default)s)" if value is not None else ""
    if s.kind == "floats" and value is not None:
        shown = f" (default {' '.join(f'{v:g}' for v in value)})"
    if s.kind == "strs":
        rng = f", a comma list of {', '.join(s.choices)}" if s.choices else ", a comma list"
    choices = s.choices if parse_choices and s.kind != "strs" else ()
    metavar = metavar or s.metavar
    if metavar is None and not choices:
        metavar = "M" if s.unit == "m" else "N"
    text = f"{s.doc}{rng}{shown}".replace("%", "%%").replace("%%(default)s", "%(default)s")
    kw.setdefault("type", _TYPES[s.kind])
    group.add_argument(s.option, *s.aliases, default=value, choices=choices or None, metavar=metavar, help=text, **kw)


def by_name(settings) -> dict:
    """``{name: Setting}`` of a sequence of settings."""
    return {s.name: s for s in settings}


def check_values(values: dict, records, names=None) -> dict:
    """``values`` (``{name: value}``) with the range of each named record checked.

    Errors name the API parameter, or its word in ``names`` (API name -> option or scene key).
    """
    table, names = by_name(records), names or {}
    return {k: table[k].check(v, names.get(k)) if k in table else v for k, v in values.items()}


def _is_bool(value) -> bool:
    """True for ``True``/``False`` and numpy's booleans (tested by type name: no numpy import here)."""
    return isinstance(value, bool) or (type(value).__module__ == "numpy" and type(value).__name__ in ("bool_", "bool"))
