"""Errors in the user's own words: API parameter names mapped to the options and scene keys of the settings table.

Every name map is made here, from the records alone (:func:`~acoustiviz.app.settings.base.vocabulary`): the
groups of records a job is built from (the impact, the damper, the room, the memory cap), the aliases of API
parameters spelled otherwise than their record (:data:`ALIASES`), and the few derived values that have no
record (:data:`DERIVED`), all three in :mod:`acoustiviz.app.settings.vocabulary`. A settings object's
:meth:`~acoustiviz.app.settings.base.Settings.names_for` gives its whole vocabulary; the constants below are
those of the values the jobs share.

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

from ..errors import user_terms
from .settings.base import vocabulary
from .settings.damper import DAMPER
from .settings.design import DESIGN, DESIGN_RUN
from .settings.forced import FORCED
from .settings.impact import IMPACT, OBSERVER, WAVEFORM
from .settings.room import ROOM
from .settings.scene import CONFIGURATION_KEYS
from .settings.sweep import SCENE_SWEEP, SWEEP_DAMPER, SWEEP_RUN, SWEEP_SOUND, SWEPT
from .settings.sweep_operation import OPERATION_OPTIONS
from .settings.vocabulary import ALIASES, DERIVED, MEMORY

__all__ = ["user_terms", "vocabulary", "MEMORY", "ALIASES", "DERIVED", "DAMPER_OPTIONS", "IMPACT_OPTIONS",
           "ROOM_OPTIONS", "SCENE_IMPACT_KEYS", "SCENE_DAMPER_KEYS", "SWEEP_OPTIONS", "SWEEP_ROOM_OPTIONS",
           "SCENE_SWEEP_KEYS", "DESIGN_OPTIONS"]

#: :class:`~acoustiviz.dynamics.DamperModel` / :func:`~acoustiviz.dynamics.simulate` parameter -> option.
DAMPER_OPTIONS = vocabulary("cli", DAMPER, ALIASES["damper"])

#: :func:`acoustiviz.app.impacts.impact_setup` parameter (and the observer's) -> option.
IMPACT_OPTIONS = vocabulary("cli", IMPACT + OBSERVER, ALIASES["impact"])

#: :class:`acoustiviz.core.geometry.Room` setting -> option.
ROOM_OPTIONS = vocabulary("cli", ROOM, ALIASES["room"], lookup=WAVEFORM + IMPACT)

#: :func:`acoustiviz.app.damper.run_damper` / :class:`~acoustiviz.dynamics.DamperModel` parameter -> scene key.
SCENE_DAMPER_KEYS = vocabulary("scene", DAMPER, ALIASES["damper"])

#: :func:`acoustiviz.app.impacts.impact_setup` parameter -> scene key (the configuration's kind and struck surface
#: are scene-only records, :mod:`acoustiviz.app.settings.scene`; the contact's stiffness is the damper's key).
SCENE_IMPACT_KEYS = vocabulary("scene", IMPACT + CONFIGURATION_KEYS, {"k_hertz": "k_hertz", **ALIASES["impact"]},
                               lookup=DAMPER)

#: :class:`~acoustiviz.app.settings.sweep_job.SweepJob` parameter (and the :class:`~acoustiviz.sweep.SweepSpec`'s and
#: :class:`~acoustiviz.sweep.FixedSettings`' it sets) -> ``acoustiviz sweep`` option.
_SWEEP_RECORDS = SWEPT + SWEEP_DAMPER + SWEEP_SOUND + SWEEP_RUN + OPERATION_OPTIONS + MEMORY
SWEEP_OPTIONS = vocabulary("cli", _SWEEP_RECORDS, ALIASES["sweep"])

#: The same, and the room a sweep is run in (:func:`acoustiviz.app.sweep.with_room`): the window its images
#: reach is ``--room-window``.
SWEEP_ROOM_OPTIONS = vocabulary("cli", _SWEEP_RECORDS + ROOM,
                                {**ALIASES["sweep"], **ALIASES["room"], "duration": "room_window"},
                                lookup=WAVEFORM + IMPACT + SWEEP_RUN)

#: The same parameters -> the scene key they are read from: ``[outputs.sweep]``'s records, the damper's, the
#: sphere's, the contact's and the configuration's keys, and the first listener for the listener's values.
SCENE_SWEEP_KEYS = {
    **{k: v for k, v in SCENE_DAMPER_KEYS.items() if k in ("M", "K", "C", "c1", "v0", "clip_tensile", "rtol",
                                                           "solver", "k_hertz")},
    **{k: v for k, v in SCENE_IMPACT_KEYS.items() if k in ("radius", "density", "wall_distance", "pulse", "config")},
    **vocabulary("scene", (), {"material": "material", "surface": "surface", "c": "c", "rho": "rho",
                               "radius_mode": "radius"}, lookup=IMPACT),
    **vocabulary("scene", SWEPT + SWEEP_DAMPER + SWEEP_SOUND + SCENE_SWEEP),
    **DERIVED["scene"], **vocabulary("scene", MEMORY),
    # in operation (outputs.sweep.in_operation): the scene's [excitation], as its frequency response reads it
    "force": "excitation.amplitude", "base": "excitation.amplitude", "frequencies": "excitation.frequencies_hz",
    "kind": "excitation.kind", "amplitude": "excitation.amplitude",
    **{r.name: r.path for r in FORCED if r.table == "excitation" and r.name not in ("solver", "rtol")},
}

#: :class:`~acoustiviz.app.design.DesignJob` parameter -> ``acoustiviz design`` option.
DESIGN_OPTIONS = vocabulary("cli", DESIGN + DESIGN_RUN + MEMORY, {"width": "band_width"})
