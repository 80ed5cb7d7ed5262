"""The settings of the waveform job: one impact, its surroundings, its listeners, its sampling and its files.

:class:`WaveformJob` is the whole of what :func:`acoustiviz.app.waveform.run` needs, checked once when
it is made (the table's ranges, the listeners in the fluid, the memory budget, the files to write), so
``acoustiviz waveform``, a scene's ``[outputs.waveform]`` and a Python caller build the same object and
hand it to the same run. The records of its command-line options (``--listener``, ``--csv``, ``--png``)
live here beside :data:`~acoustiviz.app.settings.impact.WAVEFORM`'s sampling.
"""

from __future__ import annotations

import dataclasses

from ...errors import ParameterError
from .base import vocabulary
from .impact import OBSERVER, WAVEFORM, ImpactJob
from .table import Setting
from .vocabulary import DERIVED, OUTPUT_TABLES

__all__ = ["WAVEFORM_OUTPUTS", "LISTENER", "PLACEHOLDER", "WaveformJob"]

#: In a file name of a job with several listeners: replaced by each listener's name.
PLACEHOLDER = "{listener}"

#: The observer of ``acoustiviz waveform`` in a room, typed as text.
LISTENER = Setting("listener", "--listener", None, "str", None,
                   "with --room: the observer's position in m, in the room outside the sphere "
                   "(replaces --distance and --angle)", metavar="X,Y,Z")

#: The files of the job (a scene names them itself: ``waveform_NAME.csv`` and ``.png`` in its folder).
WAVEFORM_OUTPUTS = (
    Setting("csv", "--csv", None, "str", None,
            "write columns time_s,pressure_pa (with --room also PATH.json: the image order, the number of "
            "images and the neglected-energy bound)", metavar="PATH"),
    Setting("png", "--png", None, "str", None, "draw the waveform", metavar="PATH"),
)



@dataclasses.dataclass(frozen=True, kw_only=True)
class WaveformJob(ImpactJob):
    """The pressure waveform of one impact at one or more listeners, and the files wanted of it.

    Attributes
    ----------
    impact : acoustiviz.core.contact.Impact
        Speed (m/s), K_HZ (N/m^1.5) and masses (kg) of the impact.
    pulses : tuple of pulse
        The acceleration pulses compared (m/s² against s), the first one reported.
    medium : acoustiviz.core.medium.Medium
        The fluid.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its image sources (in a room, its window in s is the waveform's).
    listeners : tuple of Listener
        Where the pressure is computed (m), each in the fluid (``(name, position)`` pairs are taken too).
    samples_per_duration : int
        Time samples per contact duration of the shortest pulse.
    max_memory_mb : float, optional
        Cap in MB on the working memory (default :data:`acoustiviz.constants.MAX_MEMORY_MB`).
    csv, png : str, optional
        The table (``time_s`` and a pressure column per pulse in Pa; in a room also its JSON sidecar
        beside it) and the figure; relative to the folder :meth:`WaveformResult.write` is given.
        With several listeners each must hold ``{listener}``, replaced by the listener's name.
    k_hertz_source : str
        Where K_HZ came from (reported; not compared).
    size_options : tuple of str
        The settings an error about the number of samples names, the first first (not compared).
    names : dict
        The front end's vocabulary: API parameter -> the option or scene key its errors name
        (not compared; default: the API names).
    """

    TABLE = (WAVEFORM[0], *WAVEFORM_OUTPUTS)
    DERIVED_NAMES = {"scene": OUTPUT_TABLES["waveform"]}

    @classmethod
    def names_for(cls, front: str, *, point: bool = True) -> dict:
        """The job's vocabulary (:meth:`Settings.names_for`), its listeners named as the front end gave them.

        ``point``: the listener was given as a point, else as the observer's distance and angle (its errors
        then name the distance).
        """
        from .scene import OUTPUT_KEYS  # its records import the geometries: not on the way to --help

        listeners = DERIVED[front] if point else vocabulary(front, (), {"listeners": "distance"}, lookup=OBSERVER)
        pulses = vocabulary(front, tuple(s for s in OUTPUT_KEYS if s.name == "pulses"))  # a scene's pulses
        return {**super().names_for(front), **pulses, "listeners": listeners["listeners"]}
    pulses: tuple
    listeners: tuple
    samples_per_duration: int = WAVEFORM[0].default
    csv: str | None = None
    png: str | None = None
    size_options: tuple = dataclasses.field(default=("samples_per_duration",), compare=False, repr=False)

    def files(self, listener) -> dict:
        """``{"csv": path, "json": path, "png": path}`` of one :class:`~acoustiviz.Listener`, as asked (strings)."""
        out = {}
        for key in ("csv", "png"):
            name = getattr(self, key)
            if name is not None:
                out[key] = name.replace(PLACEHOLDER, listener.name)
        if self.in_room and "csv" in out:
            from pathlib import Path

            out["json"] = str(Path(out["csv"]).with_suffix(".json"))
        return out

    def validate(self) -> None:
        """The pulses, the listeners in the fluid, the memory budget and the files, in that order."""
        from ...core.listener import Listener  # numpy: not imported by --help

        object.__setattr__(self, "pulses", tuple(self.pulses))
        object.__setattr__(self, "listeners", tuple(lst if isinstance(lst, Listener) else Listener(*lst)
                                                    for lst in self.listeners))  # or (name, position) pairs
        if not self.pulses:
            raise ParameterError("pulses", "expected at least one pulse")
        if not self.listeners:
            raise ParameterError("listeners", "expected at least one listener")
        names = [lst.name for lst in self.listeners]
        if len(set(names)) != len(names):
            raise ParameterError("listeners", f"listener names must differ, got {names}")
        self._check_listeners()
        self._check_budget()
        self._check_files()

    def _check_listeners(self) -> None:
        import numpy as np

        geometry = self.geometry
        for lst in self.listeners:
            p = np.asarray(lst.position, dtype=float)
            if not np.all(np.isfinite(p)) or np.linalg.norm(p - geometry.centre) <= geometry.radius \
                    or not bool(geometry.in_fluid(p[None, :])[0]):
                raise ParameterError("listeners", f"listener {lst.name!r} at {lst.position.tolist()} m is not in the "
                                                  "fluid (inside the sphere, a wall or below the floor)")

    def _check_budget(self) -> None:
        import numpy as np

        from ..budget import check_budget, check_room_order, waveform_estimate

        check_room_order(self.geometry, self.max_memory_mb)  # a room that leaves out more than its tolerance
        for lst in self.listeners:
            check_budget(waveform_estimate(list(self.pulses), np.asarray(lst.position), self.geometry,
                                           self.medium, self.samples_per_duration, options=self.size_options,
                                           window=self.window), self.max_memory_mb)

    def _check_files(self) -> None:
        from ..outputs import check_distinct, check_output_file

        several = len(self.listeners) > 1
        for key in ("csv", "png"):
            name = getattr(self, key)
            if several and name is not None and PLACEHOLDER not in name:
                raise ParameterError(key, f"with several listeners the file name must hold {PLACEHOLDER}, "
                                          f"got {name!r}")
        paths = {}
        for lst in self.listeners:
            for kind, path in self.files(lst).items():
                key = "csv" if kind == "json" else kind
                check_output_file(key, path, "figure" if kind == "png" else kind)
                paths[f"{self._name(key)} ({lst.name}, {kind})"] = path
        check_distinct(paths)
