"""Errors in the user's own words.

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

import contextlib
from collections.abc import Mapping

from ..errors import ParameterError

__all__ = ["user_terms", "DAMPER_OPTIONS", "IMPACT_OPTIONS", "ROOM_OPTIONS", "SCENE_IMPACT_KEYS", "SCENE_DAMPER_KEYS"]

#: :class:`~acoustiviz.dynamics.DamperModel` / :func:`~acoustiviz.dynamics.simulate` parameter -> option.
DAMPER_OPTIONS = {
    "M": "--M",
    "K": "--K",
    "C": "--C",
    "m": "--m",
    "gap": "--gap",
    "k_hertz": "--k-hertz",
    "c1": "--c1",
    "v": "--v0",
    "duration": "--duration",
    "solver": "--solver",
    "dt": "--dt",
    "rtol": "--rtol",
}

#: :func:`acoustiviz.app.impacts.impact_setup` parameter -> option.
IMPACT_OPTIONS = {
    "radius": "--radius",
    "velocity": "--velocity",
    "k_hertz": "--k-hertz",
    "sphere_material": "--material",
    "surface_material": "--surface",
    "density": "--density",
    "mass": "--mass",
    "pulse": "--pulse",
    "c": "--c",
    "rho": "--rho",
    "config": "--config",
    "wall_distance": "--wall-distance",
    "strike": "--strike",
    "height": "--height",
    "distance": "--distance",
    "angle_deg": "--angle",
}

#: :class:`acoustiviz.core.geometry.Room` setting -> option.
ROOM_OPTIONS = {
    "dimensions": "--room",
    "absorption": "--absorption",
    "source": "--source",
    "strike": "--room-strike",
    "order": "--image-order",
    "tolerance_db": "--tolerance-db",
    "duration": "--duration",
    "sound_speed": "--c",
}


#: :func:`acoustiviz.app.damper.run_damper` / :class:`~acoustiviz.dynamics.DamperModel` parameter -> scene key.
SCENE_DAMPER_KEYS = {
    "M": "damper.main_mass_kg", "K": "damper.stiffness_n_m", "C": "damper.damping_n_s_m", "m": "damper.impact_mass_kg",
    "gap": "damper.gap_m", "k_hertz": "contact.k_hertz_n_m1_5", "c1": "damper.contact_damping_n_s_m",
    "v": "damper.initial_velocity_m_s", "duration": "damper.duration_s", "rtol": "damper.tolerance",
    "solver": "damper.solver",
}
#: :func:`acoustiviz.app.impacts.impact_setup` parameter -> scene key.
SCENE_IMPACT_KEYS = {
    "radius": "sphere.radius_m",
    "velocity": "impact.velocity_m_s",
    "k_hertz": "contact.k_hertz_n_m1_5",
    "sphere_material": "sphere.material",
    "surface_material": "contact.surface",
    "density": "sphere.density_kg_m3",
    "mass": "sphere.mass_kg",
    "pulse": "contact.pulse",
    "c": "medium.c_m_s",
    "rho": "medium.rho_kg_m3",
    "config": "configuration.kind",
    "wall_distance": "configuration.wall_distance_m",
    "strike": "configuration.strike",
    "height": "configuration.height_m",
}


@contextlib.contextmanager
def user_terms(names: Mapping[str, str]):
    """Re-raise a :class:`ParameterError` about a parameter of ``names`` under the user's name.

    Parameters
    ----------
    names : mapping of str to str
        API parameter name -> the option or scene key the user gave.
    """
    try:
        yield
    except ParameterError as exc:
        if exc.name in names and names[exc.name] != exc.name:
            raise exc.renamed(names[exc.name]) from None
        raise
