"""Settings only a scene file has: its title, listeners, the damper's sphere and pulse, the grids' cap, outputs.

The scene's other keys come from the records of the settings they set
(:mod:`acoustiviz.app.settings.impact`, :mod:`acoustiviz.app.settings.room`,
:mod:`acoustiviz.app.settings.damper`, ...), shared with the command line; these have no option: a scene names several
listeners, lets a damper's pulse carry the effective mass, and asks for outputs by key.
"""

from __future__ import annotations

from ...constants import PULSES, ROOM_STRIKES
from ...core.geometry import GEOMETRIES
from .run import MEMORY_LIMIT
from .table import Setting

__all__ = ["SCENE", "LISTENER_KEYS", "SPHERE_KEYS", "CONTACT_KEYS", "CONFIGURATION_KEYS", "GRIDS", "OUTPUT_KEYS"]

#: ``[scene]``: its title.
SCENE = (
    Setting("scene_name", None, "name", "str", "scene", "short name", table="scene"),
    Setting("description", None, "description", "str", "", "what it shows", table="scene"),
)

#: ``[sphere]``: the radius damper impacts radiate with.
SPHERE_KEYS = (
    Setting("damper_radius", None, "damper_radius", "str", "given",
            "sphere radius for damper impacts: 'given' keeps radius_m (the paper's choice), 'from-mass' derives it "
            "from the impact mass and the density", choices=("given", "from-mass"), table="sphere"),
)

#: ``[contact]``: the mass in a damper impact's pulse.
CONTACT_KEYS = (
    Setting("pulse_mass", None, "pulse_mass", "str", "impact",
            "mass in the pulse: the impact mass alone or the effective mass of the two bodies",
            choices=("impact", "effective"), table="contact"),
)

#: ``[configuration]``: the surroundings, a room among them, and the struck surface of a corner or a room
#: (the command line's ``--config``, ``--strike`` and ``--room-strike``).
CONFIGURATION_KEYS = (
    Setting("config", None, "kind", "str", "plane",
            "free field, reflecting plane (floor z = 0), wall-floor corner, or a shoebox room (also written "
            "[geometry])", choices=tuple(GEOMETRIES), table="configuration"),
    Setting("strike", None, "strike", "str", "floor",
            "wall-floor: struck surface (a wall strike puts the sphere against the wall, accelerating along +x); "
            "room: floor, ceiling or x0, x1, y0, y1, z0, z1", choices=("floor", "wall") + ROOM_STRIKES[1:],
            table="configuration"),
)

#: ``[[listeners]]``: each listener's name and place.
LISTENER_KEYS = (
    Setting("name", None, "name", "str", None,
            "label used in file names (default listenerN): unique, 1-64 letters, digits, '_', '-', '.' and inner "
            "spaces, starting with a letter, digit or '_'", table="listeners"),
    Setting("distance", None, "distance_m", "float", None, "distance from the sphere's centre (with angle_deg)", "m",
            low=0.0, high=1e4, low_open=True, table="listeners"),
    Setting("angle_deg", None, "angle_deg", "float", None, "angle from the acceleration axis (with distance_m)",
            "deg", low=0.0, high=180.0, table="listeners"),
    Setting("position", None, "position_m", "point", None,
            "position [x, y, z] in the scene frame (instead of distance/angle)", "m", table="listeners"),
)

#: ``[grids]``: the memory cap of a scene's grid evaluations.
GRIDS = (MEMORY_LIMIT,)

#: The keys of outputs a scene asks for by name.
OUTPUT_KEYS = (
    Setting("pulses", None, "pulses", "strs", None, "pulses to compare", choices=PULSES, table="outputs.waveform"),
    Setting("masses", None, "masses_kg", "floats", [0.01, 0.02, 0.04, 0.06, 0.08, 0.1], "impact masses", "kg",
            low=1e-6, high=1e4, table="outputs.restitution"),
    Setting("velocities", None, "velocities_m_s", "floats", [0.5, 1.0, 2.0], "approach speeds", "m/s", low=1e-4,
            high=1e3, table="outputs.restitution"),
)
