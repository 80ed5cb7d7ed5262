"""Settings of a shoebox room ``[0, LX] x [0, LY] x [0, LZ]`` m (floor ``z = 0``), for every command with ``--room``.

The records hold the options' meaning; the values stay text until
:func:`acoustiviz.app.impacts.room_settings` and :class:`acoustiviz.core.geometry.Room` check them
(the room's own errors name the options through :data:`acoustiviz.app.names.ROOM_OPTIONS`).
"""

from __future__ import annotations

import dataclasses

from ...constants import ROOM_STRIKES
from .base import Settings
from .table import Setting

__all__ = ["ROOM", "RoomOptions"]

ROOM = (
    Setting("room", "--room", None, "str", None,
            "put the sphere in a rectangular room of these dimensions in m (image sources to the order the output "
            "needs; replaces --config)", metavar="LX,LY,LZ"),
    Setting("absorption", "--absorption", None, "str", None,
            "energy absorption coefficient alpha in [0, 1) of every surface, or of x0,x1,y0,y1,z0 (floor),z1 "
            "(default 0: rigid)", metavar="A|A1,...,A6"),
    Setting("source", "--source", None, "str", None,
            "centre of the sphere in m, touching the surface it strikes (one radius from it, z = a for the floor) "
            "and at least its radius from every other (default: the middle of the floor)",
            metavar="X,Y,Z"),
    Setting("room_strike", "--room-strike", None, "str", "floor",
            "the struck surface: floor, ceiling, or x0, x1, y0, y1, z0, z1", choices=ROOM_STRIKES, metavar="SURFACE"),
    Setting("image_order", "--image-order", None, "int", None,
            "image order (default: chosen from --tolerance-db and the window)", metavar="N"),
    Setting("tolerance_db", "--tolerance-db", None, "float", None,
            "largest neglected image energy relative to the total in dB, in [-200, 0) (default -60)", metavar="DB"),
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
