"""Settings of a shoebox room ``[0, LX] x [0, LY] x [0, LZ]`` m (floor ``z = 0``), for every command with ``--room``.

The records hold the options' meaning and the scene's ``[configuration]`` keys of the room (a list
of numbers where the command line types text: ``--room 6,4,3`` is ``room_m = [6, 4, 3]``); the values
stay text until :func:`acoustiviz.app.impacts.room_settings` and :class:`acoustiviz.core.geometry.Room`
check them (the room's own errors name the options through :data:`acoustiviz.app.names.ROOM_OPTIONS`).
The struck surface is one scene key with the wall-floor corner's (:mod:`acoustiviz.app.settings.scene`).
"""

from __future__ import annotations

import dataclasses

from ...constants import ROOM_STRIKES
from .base import Settings
from .table import Setting

__all__ = ["ROOM", "RoomOptions"]

#: The scene table of the room's keys.
_TABLE = "configuration"

ROOM = (
    Setting("room", "--room", "room_m", "str", None,
            "put the sphere in a rectangular room of these dimensions in m (image sources to the order the output "
            "needs; replaces --config)", "m", metavar="LX,LY,LZ", table=_TABLE, scene_kind="floats", length=3,
            scene_doc="room: dimensions [Lx, Ly, Lz] of the room [0, Lx] x [0, Ly] x [0, Lz], floor z = 0"),
    Setting("absorption", "--absorption", "absorption", "str", None,
            "energy absorption coefficient alpha in [0, 1) of every surface, or of x0,x1,y0,y1,z0 (floor),z1 "
            "(default 0: rigid)", metavar="A|A1,...,A6", table=_TABLE, scene_kind="floats", length=6,
            scene_doc="room: energy absorption coefficient alpha in [0, 1), one value or six (x0, x1, y0, y1, "
            "z0 floor, z1 ceiling); default 0, rigid"),
    Setting("source", "--source", "source_m", "str", None,
            "centre of the sphere in m, touching the surface it strikes (one radius from it, z = a for the floor) "
            "and at least its radius from every other (default: the middle of the floor)", "m",
            metavar="X,Y,Z", table=_TABLE, scene_kind="point",
            scene_doc="room: centre of the sphere, touching the surface it strikes (default: the middle of the "
            "floor)"),
    Setting("room_strike", "--room-strike", None, "str", "floor",
            "the struck surface: floor, ceiling, or x0, x1, y0, y1, z0, z1", choices=ROOM_STRIKES, metavar="SURFACE"),
    Setting("image_order", "--image-order", "image_order", "int", None,
            "image order (default: chosen from --tolerance-db and the window)", low=0, high=10000, metavar="N",
            table=_TABLE, scene_doc="room: image order (default: from tolerance_db and window_s)"),
    Setting("tolerance_db", "--tolerance-db", "tolerance_db", "float", None,
            "largest neglected image energy relative to the total (default -60 dB)", "dB", low=-200.0, high=0.0,
            high_open=True, metavar="DB", table=_TABLE,
            scene_doc="room: largest neglected image energy relative to the total (default -60)"),
)


@dataclasses.dataclass(frozen=True)
class RoomOptions(Settings):
    """The shoebox room as given (text, checked by :class:`acoustiviz.core.geometry.Room`); no ``room``: none."""

    room: str | None = None
    absorption: str | None = None
    source: str | None = None
    room_strike: str = "floor"
    image_order: int | None = None
    tolerance_db: float | None = None
