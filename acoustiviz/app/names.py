"""Errors in the user's own words: API parameter names mapped to the options and scene keys of the settings table.

The library names its parameters as the API spells them (``radius``, ``v``, ``k_hertz``); a
front-end's user gave them as options (``--radius``) or scene keys (``sphere.radius_m``). Inside
:func:`user_terms` a :class:`~acoustiviz.errors.ParameterError` about an API parameter is raised
again under the user's name, with the same detail.

Examples
--------
>>> from acoustiviz.errors import ParameterError
>>> try:
...     with user_terms({"radius": "--radius"}):
...         raise ParameterError("radius", "must be > 0 m, got -1 m")
... except ParameterError as exc:
...     print(exc)
--radius: must be > 0 m, got -1 m
"""

from __future__ import annotations

from collections.abc import Mapping

from ..errors import user_terms
from .settings.damper import DAMPER
from .settings.design import DESIGN, DESIGN_RUN
from .settings.forced import FORCED
from .settings.impact import IMPACT, OBSERVER, WAVEFORM
from .settings.room import ROOM
from .settings.scene import CONFIGURATION_KEYS
from .settings.sweep import SCENE_SWEEP, SWEEP_DAMPER, SWEEP_RUN, SWEEP_SOUND, SWEPT
from .settings.sweep_operation import OPERATION_OPTIONS
from .settings.table import by_name

__all__ = ["user_terms", "DAMPER_OPTIONS", "IMPACT_OPTIONS", "ROOM_OPTIONS", "SCENE_IMPACT_KEYS", "SCENE_DAMPER_KEYS",
           "SWEEP_OPTIONS", "SCENE_SWEEP_KEYS", "DESIGN_OPTIONS"]


def _names(attr: str, records, aliases: Mapping[str, str] = {}, lookup=()) -> dict:  # noqa: B006 - read only
    """API parameter -> ``attr`` (``"option"`` or ``"path"``, the scene key) of each record that has one.

    ``aliases`` adds API parameters spelled otherwise than their record (``{"v": "v0"}``), the record
    found in ``lookup``, else among ``records``.
    """
    table = {**by_name(records), **by_name(lookup)}
    names = {s.name: getattr(s, attr) for s in records if getattr(s, attr)}
    names.update({api: getattr(table[name], attr) for api, name in aliases.items()})
    return names


#: :class:`~acoustiviz.dynamics.DamperModel` / :func:`~acoustiviz.dynamics.simulate` parameter -> option.
DAMPER_OPTIONS = _names("option", DAMPER, {"v": "v0"})

#: :func:`acoustiviz.app.impacts.impact_setup` parameter (and the observer's) -> option.
_IMPACT_ALIASES = {"sphere_material": "material", "surface_material": "surface"}
IMPACT_OPTIONS = _names("option", IMPACT + OBSERVER, _IMPACT_ALIASES)

#: :class:`acoustiviz.core.geometry.Room` setting -> option (the window is the waveform's ``--duration``, the
#: sound speed the medium's ``--c``).
ROOM_OPTIONS = _names("option", ROOM, {"dimensions": "room", "strike": "room_strike", "order": "image_order",
                                       "duration": "window", "sound_speed": "c"}, lookup=WAVEFORM + IMPACT)

#: :func:`acoustiviz.app.damper.run_damper` / :class:`~acoustiviz.dynamics.DamperModel` parameter -> scene key.
SCENE_DAMPER_KEYS = _names("path", DAMPER, {"v": "v0"})

#: :func:`acoustiviz.app.impacts.impact_setup` parameter -> scene key (the configuration's kind and struck surface
#: are scene-only records, :mod:`acoustiviz.app.settings.scene`).
SCENE_IMPACT_KEYS = _names("path", IMPACT + CONFIGURATION_KEYS, {"k_hertz": "k_hertz", **_IMPACT_ALIASES},
                           lookup=DAMPER)


#: :class:`~acoustiviz.app.settings.sweep_job.SweepJob` parameter (and the :class:`~acoustiviz.sweep.SweepSpec`'s and
#: :class:`~acoustiviz.sweep.FixedSettings`' it sets) -> ``acoustiviz sweep`` option.
_SWEEP_RECORDS = SWEPT + SWEEP_DAMPER + SWEEP_SOUND + SWEEP_RUN + OPERATION_OPTIONS
_SWEEP_ALIASES = {"angle": "angle_deg", "radius_mode": "radius", "width": "band_width"}
SWEEP_OPTIONS = {**_names("option", _SWEEP_RECORDS, _SWEEP_ALIASES), "max_memory_mb": "--max-memory"}

#: The same parameters -> the scene key they are read from: ``[outputs.sweep]``'s records, the damper's, the
#: sphere's, the contact's and the configuration's keys, and the first listener for the listener's values.
SCENE_SWEEP_KEYS = {
    **{k: v for k, v in SCENE_DAMPER_KEYS.items() if k in ("M", "K", "C", "c1", "v0", "clip_tensile", "rtol",
                                                           "solver", "k_hertz")},
    **{k: v for k, v in SCENE_IMPACT_KEYS.items() if k in ("radius", "density", "wall_distance", "pulse", "config")},
    "material": SCENE_IMPACT_KEYS["sphere_material"], "surface": SCENE_IMPACT_KEYS["surface_material"],
    "c": SCENE_IMPACT_KEYS["c"], "rho": SCENE_IMPACT_KEYS["rho"],
    **_names("path", SWEPT + SWEEP_DAMPER + SWEEP_SOUND + SCENE_SWEEP),
    **{k: "listeners" for k in ("distance", "angle", "angle_deg")},
    "radius_mode": SCENE_IMPACT_KEYS["radius"], "out": "outputs.sweep", "max_memory_mb": "grids.memory_limit_mb",
    # in operation (outputs.sweep.in_operation): the scene's [excitation], as its frequency response reads it
    "force": "excitation.amplitude", "base": "excitation.amplitude", "frequencies": "excitation.frequencies_hz",
    "kind": "excitation.kind", "amplitude": "excitation.amplitude",
    **{r.name: r.path for r in FORCED if r.table == "excitation" and r.name not in ("solver", "rtol")},
}

#: :class:`~acoustiviz.app.design.DesignJob` parameter -> ``acoustiviz design`` option.
DESIGN_OPTIONS = {**_names("option", DESIGN + DESIGN_RUN, {"width": "band_width"}), "max_memory_mb": "--max-memory"}
