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
    kind : {"str", "float", "int", "bool"}
        The type of one value (``"bool"``: a flag on the command line).
    default : object
        The default (None: computed from other settings, or absent).
    doc : str
        One line saying what it sets.
    unit : str
        SI unit of a number ("" for counts and names).
    low, high : float
        Allowed interval of a number (``low`` excluded when ``low_open``).
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
    choices: tuple = ()
    scene_default: object = SAME
    table: str = ""
    metavar: str | None = None
    aliases: tuple = ()

    @property
    def path(self) -> str | None:
        """The full scene key (``"grids.plane.resolution"``), None without one."""
        return f"{self.table}.{self.key}" if self.key else None

    @property
    def in_scene(self) -> object:
        """The default of the scene key."""
        return self.default if self.scene_default == SAME else self.scene_default

    def range_text(self) -> str:
        """``"(0, 90] deg"``: the allowed interval and unit of a number, ``""`` for a string."""
        if self.kind == "str":
            return ""
        u = f" {self.unit}" if self.unit else ""
        return f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}]{u}"

    def check(self, value, name: str | None = None):
        """``value`` in the setting's type, or a :class:`ParameterError` naming ``name`` (default: the API name).

        ``None`` passes unchanged (a setting left to its computed default).
        """
        name = name or self.name
        if value is None:
            return None
        if self.kind == "str":
            return check_choice(name, value, self.choices) if self.choices else str(value)
        if self.kind == "bool":
            if not _is_bool(value):
                raise ParameterError(name, f"must be true or false, got {value!r}")
            return bool(value)
        if self.kind == "int":
            if isinstance(value, bool) or not isinstance(value, numbers.Integral) \
                    or not self.low <= value <= self.high:
                raise ParameterError(name, f"must be an integer in [{self.low:g}, {self.high:g}], got {value!r}")
            return int(value)
        return check_range(name, value, self.low, self.high, unit=self.unit, low_open=self.low_open)


_TYPES = {"str": str, "float": float, "int": int}


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
    bounded = s.kind != "str" and not s.choices and (math.isfinite(s.low) or math.isfinite(s.high))
    rng = f", in {s.range_text()}" if bounded else ""
    value = s.default if default == SAME else default
    shown = " (default %(default)s)" if value is not None else ""
    choices = s.choices if parse_choices else ()
    metavar = metavar or s.metavar
    if metavar is None and not choices:
        metavar = "M" if s.unit == "m" else "N"
    text = f"{s.doc}{rng}{shown}".replace("%", "%%").replace("%%(default)s", "%(default)s")
    kw.setdefault("type", _TYPES[s.kind])
    group.add_argument(s.option, *s.aliases, default=value, choices=choices or None, metavar=metavar, help=text, **kw)


def by_name(settings) -> dict:
    """``{name: Setting}`` of a sequence of settings."""
    return {s.name: s for s in settings}


def check_values(values: dict, records) -> dict:
    """``values`` (``{name: value}``) with the range of each named record checked; errors name the API parameter."""
    table = by_name(records)
    return {k: table[k].check(v) if k in table else v for k, v in values.items()}


def _is_bool(value) -> bool:
    """True for ``True``/``False`` and numpy's booleans (tested by type name: no numpy import here)."""
    return isinstance(value, bool) or (type(value).__module__ == "numpy" and type(value).__name__ in ("bool_", "bool"))
