"""The base of every settings object: a frozen dataclass that checks itself once against its table."""

from __future__ import annotations

import dataclasses

from ...errors import ParameterError, user_terms

__all__ = ["Settings", "check_size", "parse_size", "vocabulary", "SIZE_RANGE", "FRONTS"]

#: Smallest and largest image side in pixels.
SIZE_RANGE = (64, 8192)


#: Front end -> the attribute of a :class:`~acoustiviz.app.settings.table.Setting` its user types: the
#: command-line option or the full scene key.
FRONTS = {"cli": "option", "scene": "path"}


def vocabulary(front: str, records, aliases=None, lookup=()) -> dict:
    """API name -> the option (``front="cli"``) or scene key (``front="scene"``) of each record that has one.

    Parameters
    ----------
    front : {"cli", "scene"}
        The front end whose words are wanted.
    records : sequence of Setting
        The records named after their API parameter.
    aliases : mapping, optional
        API name -> the name of the record it is spelled as (``{"v": "v0"}``), found in ``lookup``,
        else among ``records``; an alias whose record has no word for ``front`` is left out.
    lookup : sequence of Setting
        Further records an alias may point at (they add no name of their own).

    Returns
    -------
    dict
        ``{api_name: option_or_scene_key}``, later records and aliases winning.

    Examples
    --------
    >>> from acoustiviz.app.settings.table import Setting
    >>> v0 = Setting("v0", "--v0", "v0_m_s", "float", 1.0, "start speed", "m/s", table="damper")
    >>> vocabulary("cli", [v0], {"v": "v0"})
    {'v0': '--v0', 'v': '--v0'}
    >>> vocabulary("scene", [v0])
    {'v0': 'damper.v0_m_s'}
    """
    attr = FRONTS[front]
    table = {}
    for s in (*records, *lookup):  # the last record of a name that has a word for the front end
        if getattr(s, attr) or s.name not in table:
            table[s.name] = s
    names = {s.name: getattr(s, attr) for s in records if getattr(s, attr)}
    names.update({api: getattr(table[name], attr) for api, name in (aliases or {}).items()
                  if getattr(table[name], attr)})
    return names


def check_size(size, name: str = "size") -> tuple:
    """``(width, height)`` in pixels, each an integer in :data:`SIZE_RANGE`, or a :class:`ParameterError`."""
    lo, hi = SIZE_RANGE
    try:
        w, h = size
    except (TypeError, ValueError):
        raise ParameterError(name, f"expected (width, height) in pixels, got {size!r}") from None
    for v in (w, h):
        if isinstance(v, bool) or not isinstance(v, int):
            raise ParameterError(name, f"width and height must be integers in [{lo}, {hi}] px, got {size!r}")
    if not (lo <= w <= hi and lo <= h <= hi):
        raise ParameterError(name, f"width and height must lie in [{lo}, {hi}] px, got {w}x{h}")
    return w, h


def parse_size(text: str, name: str = "size") -> tuple:
    """``"1200x900"`` -> ``(1200, 900)``, each side checked (:func:`check_size`); a ParameterError naming ``name``.

    Examples
    --------
    >>> parse_size("800x600")
    (800, 600)
    """
    parts = str(text).lower().replace("\u00d7", "x").split("x")
    try:
        if len(parts) != 2:
            raise ValueError
        w, h = int(parts[0]), int(parts[1])
    except ValueError:
        raise ParameterError(name, f"expected WIDTHxHEIGHT in pixels, e.g. 1200x900, got {text!r}") from None
    return check_size((w, h), name)


@dataclasses.dataclass(frozen=True)
class Settings:
    """A workflow's settings; subclasses list their :class:`Setting` records in ``TABLE``.

    Each field named in ``TABLE`` is checked (and converted to its type) once, when the object is
    made; errors name the API parameter, which the front-ends rename to the option or scene key
    (:meth:`cli_names`, :meth:`scene_names`).
    """

    TABLE = ()
    #: Records of the values the settings are built from beyond ``TABLE`` (the impact, the damper, the room,
    #: the memory cap): their errors too name what the user typed (:meth:`names_for`).
    BUILT_FROM = ()
    #: API name -> the record it is spelled as (:func:`vocabulary`), and the further records those may be in.
    ALIASES = {}
    LOOKUP = ()
    #: Front end (``"cli"``, ``"scene"``) -> API name -> its word, for values that have no record
    #: (:mod:`acoustiviz.app.settings.vocabulary`: the derived names, the output tables of a scene's files).
    DERIVED_NAMES = {}

    def __post_init__(self):
        # a job's ``names`` field (API name -> option or scene key): its errors in the user's words
        with user_terms(getattr(self, "names", None) or {}):
            for s in self.TABLE:
                object.__setattr__(self, s.name, s.check(getattr(self, s.name)))
            self.validate()

    def validate(self) -> None:
        """Checks beyond the table's ranges (subclasses)."""

    @classmethod
    def table(cls) -> dict:
        """``{name: Setting}``."""
        return {s.name: s for s in cls.TABLE}

    @classmethod
    def cli_names(cls) -> dict:
        """API parameter -> command-line option."""
        return {s.name: s.option for s in cls.TABLE if s.option}

    @classmethod
    def scene_names(cls) -> dict:
        """API parameter -> scene key."""
        return {s.name: s.path for s in cls.TABLE if s.key}

    @classmethod
    def names_for(cls, front: str) -> dict:
        """The job's whole vocabulary: API name -> option (``"cli"``) or scene key (``"scene"``).

        Made from ``TABLE``, ``BUILT_FROM`` and ``ALIASES`` alone (:func:`vocabulary`), so no front end writes a
        name map by hand; a front end hands it to the settings as their ``names``.
        """
        return {**vocabulary(front, (*cls.BUILT_FROM, *cls.TABLE), cls.ALIASES, cls.LOOKUP),
                **cls.DERIVED_NAMES.get(front, {})}

    @classmethod
    def from_values(cls, values: dict, *, scene: bool = False, names=None):
        """The settings of ``values`` (``{name: value}``); a missing name takes its table default.

        ``scene``: take the scene's default where it differs from the command line's; ``names``: API name ->
        the option or scene key its errors name (default: the API name).
        """
        fields = {f.name for f in dataclasses.fields(cls)}
        table = cls.table()
        kw = {k: v for k, v in values.items() if k in fields}
        for name, s in table.items():
            if name not in kw and name in fields:
                kw[name] = s.in_scene if scene else s.default
        with user_terms(names or {}):
            return cls(**kw)


