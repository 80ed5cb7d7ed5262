"""The settings of the directivity job: one impact, its surroundings, the circle, the angles, the level and the files.

:class:`DirectivityJob` is the whole of what :func:`acoustiviz.app.directivity.run` needs, checked once
when it is made (the table's ranges, the circle in the fluid, the memory budget, the files to write), so
``acoustiviz directivity``, a scene's ``[outputs.directivity]`` and a Python caller build the same object
and hand it to the same run. The records of its files (``--csv``, ``--png``) live here beside
:data:`~acoustiviz.app.settings.impact.DIRECTIVITY`'s step and level.
"""

from __future__ import annotations

import dataclasses

from .impact import DIRECTIVITY, IMPACT, OBSERVER, WAVEFORM, ImpactJob
from .room import ROOM
from .table import Setting
from .vocabulary import ALIASES, MEMORY, OUTPUT_TABLES

__all__ = ["DIRECTIVITY_OUTPUTS", "DirectivityJob"]

#: The files of the job (a scene names them itself: ``directivity.csv`` and ``.png`` in its folder).
DIRECTIVITY_OUTPUTS = (
    Setting("csv", "--csv", None, "str", None,
            "write columns angle_deg,peak_pa,rms_pa,spl_db and, for another --metric, its column "
            "(rms_db, lcpeak_db, lafmax_db, laeq_db, sel_a_db, ...)", metavar="PATH"),
    Setting("png", "--png", None, "str", None, "draw SPL and RMS polar plots", metavar="PATH"),
)


@dataclasses.dataclass(frozen=True, kw_only=True)
class DirectivityJob(ImpactJob):
    """Peak, RMS and peak SPL (and a further level) of one impact against angle on a circle, and its files.

    Attributes
    ----------
    impact : acoustiviz.core.contact.Impact
        Speed (m/s), K_HZ (N/m^1.5) and masses (kg) of the impact.
    pulse : pulse
        The acceleration pulse (m/s² against s).
    medium : acoustiviz.core.medium.Medium
        The fluid.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its image sources (in a room, its window in s ends each angle's).
    distance : float
        Radius in m of the circle around the sphere's centre, in the fluid.
    step_deg : float
        Angle step in degrees, in (0, 90] (the angles run from the acceleration axis to the
        geometry's polar limit, :func:`acoustiviz.app.views.directivity_angles`).
    metric : str
        The further level shown against angle (:data:`acoustiviz.constants.DIRECTIVITY_METRICS`;
        ``"peak-spl"``: none).
    max_memory_mb : float, optional
        Cap in MB on the working memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).
    csv, png : str, optional
        The table and the polar figure, relative to the folder :meth:`DirectivityResult.write` is given.
    k_hertz_source : str
        Where K_HZ came from (reported; not compared).
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name
        (not compared; default: the API names).
    """

    TABLE = (*DIRECTIVITY, *DIRECTIVITY_OUTPUTS)
    BUILT_FROM = (*IMPACT, OBSERVER[0], *ROOM, *MEMORY)  # the impact, the circle's radius, the room, the memory cap
    ALIASES = {**ALIASES["impact"], **ALIASES["room"], **ALIASES["memory"], "angles": "step_deg", "window": "window"}
    LOOKUP = WAVEFORM + IMPACT
    DERIVED_NAMES = {"scene": OUTPUT_TABLES["directivity"]}
    pulse: object
    distance: float
    step_deg: float = DIRECTIVITY[0].default
    metric: str = DIRECTIVITY[1].default
    csv: str | None = None
    png: str | None = None

    @property
    def weighted(self) -> bool:
        """True for a level computed from the sound at every angle (not peak SPL or RMS)."""
        return self.metric not in ("peak-spl", "rms")

    def files(self) -> dict:
        """``{"csv": path, "png": path}`` as asked (strings)."""
        return {key: getattr(self, key) for key in ("csv", "png") if getattr(self, key) is not None}

    def validate(self) -> None:
        """The circle in the fluid (reached within a room's window), the memory budget and the files, in that order."""
        import math

        from ..._validate import check_range
        from ...field.directivity import circle_points, room_window
        from ..budget import check_room_order
        from ..impacts import MAX_DISTANCE
        from ..outputs import check_distinct, check_output_file

        check_room_order(self.geometry, self.max_memory_mb, window_option=self._name("window"),
                         cap_name=self._name("max_memory_mb"))  # a room short of its tolerance: refused
        points = circle_points(self.geometry, self.distance, [0.0, math.pi / 2])  # the circle in the fluid
        object.__setattr__(self, "distance", float(check_range("distance", self.distance, self.geometry.radius,
                                                               MAX_DISTANCE, unit="m", low_open=True)))
        room_window(self.geometry, points, self.medium)  # a room: the sound reaches the circle in its window
        self._check_budget()
        for key, path in self.files().items():
            check_output_file(self._name(key), path, "figure" if key == "png" else key)
        check_distinct({self._name(key): path for key, path in self.files().items()})

    def _check_budget(self) -> None:
        from ...field import circle_points
        from ..budget import check_budget, directivity_estimate, metric_estimate
        from ..views import directivity_angles

        geometry, cap = self.geometry, self._name("max_memory_mb")
        step, distance = self._name("step_deg"), self._name("distance")
        check_budget(directivity_estimate(geometry, self.step_deg, (step,), pulse=self.pulse, medium=self.medium,
                                          window_options=(self._name("wall_distance"), distance)),
                     self.max_memory_mb, cap_name=cap)
        if self.weighted:  # the sound at every angle, held together: its memory checked before any work
            points = circle_points(geometry, self.distance, directivity_angles(geometry, self.step_deg))
            check_budget(metric_estimate(self.pulse, points, geometry, self.medium, self.metric,
                                         options=(step, distance)), self.max_memory_mb, cap_name=cap)
