"""Settings objects: one frozen dataclass per workflow, checked once against one table of ranges and defaults.

``table``   the :class:`Setting` record (API name, option, scene key, type, unit, range, default, meaning)
``base``    the :class:`Settings` base class that checks its fields against its table, and image sizes
``parse``   a point X,Y,Z and an image size WxH typed as text
``render``  the balloon, snapshot and animation views
``impact``  the waveform and directivity of one impact
"""

from .base import Settings, check_size
from .parse import parse_point, parse_size
from .table import SAME, Setting, add_option

__all__ = ["Setting", "SAME", "Settings", "add_option", "check_size", "parse_point", "parse_size"]
