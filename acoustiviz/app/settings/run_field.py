"""Settings of the field of a whole damper run: its levels on a grid of listeners and its waveform.

The run's sound (the damper run, the cavity, the clicks, the listeners, the room's sound) is an
:class:`~acoustiviz.app.settings.auralize.AuralizeJob`, as ``acoustiviz auralize`` and a scene's
``[outputs.wav]`` build it; :class:`RunFieldJob` adds a grid of listeners (an arc of directions at one
distance, or a planar map) on which the run's levels are evaluated, and the waveform of the run at the
listeners. ``acoustiviz auralize`` takes the records of :data:`RUN_FIELD` as options, a scene as the keys of
``[outputs.run_field]``. Lengths in m, angles in degrees where the user types them, times in s.
"""

from __future__ import annotations

import dataclasses

from .base import Settings
from .table import Setting
from .vocabulary import MEMORY

__all__ = ["RUN_FIELD", "GRID_KINDS", "RunFieldJob", "grid_points", "scene_files"]

_T = "outputs.run_field"

#: The grids of listeners a run's levels are evaluated on.
GRID_KINDS = ("none", "directivity", "map")

RUN_FIELD = (
    Setting("grid", "--grid", "grid", "str", "none",
            "levels of the run (LAeq, LCpeak, LAFmax, SEL(A), ...) on a grid of listeners: an arc of directions "
            "at --grid-distance (directivity) or a plane through the sphere's centre (map)", choices=GRID_KINDS,
            table=_T, scene_doc="levels of the run (LAeq, LCpeak, LAFmax, SEL(A), ...) on a grid of listeners: an "
                                "arc of directions at distance_m (directivity) or a plane through the sphere's "
                                "centre (map)"),
    Setting("grid_distance", "--grid-distance", "distance_m", "float", 0.7,
            "directivity: distance from the sphere's centre to the arc", "m", low=0.0, high=1e4, low_open=True,
            table=_T),
    Setting("grid_arc", "--grid-arc", "arc_deg", "float", 90.0,
            "directivity: the arc, in the xz-plane, spans this angle either side of the acceleration axis (+z on a "
            "floor, +x for a wall strike)",
            "deg", low=0.0, high=180.0, low_open=True, metavar="DEG", table=_T),
    Setting("grid_points", "--grid-points", "points", "int", 19,
            "directivity: points on the arc; map and snapshot: points along the plane's longer side", low=2,
            high=401, table=_T),
    Setting("grid_section", "--grid-section", "section", "str", "xz",
            "map and snapshot: the two axes the plane through the sphere's centre spans", choices=("xz", "xy"),
            table=_T),
    Setting("grid_extent", "--grid-extent", "extent_m", "float", 0.5,
            "map and snapshot: distance from the sphere's centre to the plane's edges (cut at the reflecting planes)",
            "m",
            low=0.0, high=1e3, low_open=True, table=_T),
    Setting("grid_csv", "--grid-csv", None, "str", None,
            "the grid's levels: one row per point, its coordinates in m and its levels in dB", metavar="OUT.csv"),
    Setting("grid_png", "--grid-png", None, "str", None,
            "the grid's levels drawn: a polar plot (directivity) or a map with a colour bar (dB)", metavar="PATH"),
    Setting("waveform", None, "waveform", "bool", False,
            "also the run's pressure p(t) in Pa at each listener (run_waveform.csv and .png)", table=_T),
    Setting("waveform_csv", "--waveform-csv", None, "str", None,
            "the run's pressure p(t) in Pa at each listener, at the WAV's rate (the WAV's calibrated pressure)",
            metavar="OUT.csv"),
    Setting("waveform_png", "--waveform-png", None, "str", None,
            "the run's pressure p(t) at each listener drawn", metavar="PATH"),
    Setting("snapshot_time", "--snapshot-time", "snapshot_time_s", "float", None,
            "the instant of the snapshot: the pressure over the map's plane (--grid-section, --grid-extent, "
            "--grid-points) from every click sounding then, with its images (within the run's duration)", "s",
            low=0.0, high=1e4, metavar="S", table=_T,
            scene_doc="also the snapshot at this instant: the pressure over the plane of section, extent_m and points "
                      "from every click sounding then (run_snapshot.png; within the run's duration)"),
    Setting("snapshot_png", "--snapshot-png", None, "str", None,
            "the snapshot drawn (needs --snapshot-time)", metavar="PATH"),
    Setting("snapshot_vtk", "--snapshot-vtk", None, "str", None,
            "the snapshot for ParaView, pyvista or meshio: a .vtu (or .vtkhdf) file with the point array "
            "pressure_pa, the sphere and planes beside it in <stem>_geometry.vtu (needs --snapshot-time)",
            metavar="OUT.vtu"),
    Setting("vtk", None, "vtk", "bool", False,
            "with snapshot_time_s, also the snapshot as run_snapshot.vtu (and run_snapshot_geometry.vtu)", table=_T),
)

#: The records :class:`RunFieldJob` checks when it is made.
_CHECKED = tuple(s for s in RUN_FIELD if s.name not in ("waveform", "vtk"))


def scene_files(grid: str, waveform: bool, snapshot: bool = False, vtk: bool = False) -> dict:
    """The files of a scene's ``[outputs.run_field]`` by API name: ``run_<grid>.*``, ``run_waveform.*``, ..."""
    files = {} if grid == "none" else {"grid_csv": f"run_{grid}.csv", "grid_png": f"run_{grid}.png"}
    if waveform:
        files.update(waveform_csv="run_waveform.csv", waveform_png="run_waveform.png")
    if snapshot:
        files["snapshot_png"] = "run_snapshot.png"
        if vtk:
            files["snapshot_vtk"] = "run_snapshot.vtu"
    return files


def _arc(job: RunFieldJob) -> tuple:
    """``(points, angles)``: the arc of directions in the xz-plane around the sphere's centre (m, rad).

    The angle is measured from the acceleration axis (the struck surface's normal: +z on a floor, +x for a
    wall strike) towards +x (towards +z for a wall strike).
    """
    import numpy as np

    geometry = job.sound.cavity.geometry
    centre, axis = np.asarray(geometry.centre, dtype=float), np.asarray(geometry.axis, dtype=float)
    side = np.array([0.0, 0.0, 1.0]) if abs(axis[0]) > abs(axis[2]) else np.array([1.0, 0.0, 0.0])
    half = np.radians(job.grid_arc)
    angle = np.linspace(-half, half, job.grid_points)
    d = np.outer(np.cos(angle), axis) + np.outer(np.sin(angle), side)
    d[np.abs(d) < 1e-15] = 0.0  # cos(90 deg) is 6e-17, not 0: the points on a plane's axis lie on it
    return centre + job.grid_distance * d, angle


def grid_points(job: RunFieldJob) -> tuple:
    """``(points, angles or None, planar grid or None)`` of the job's grid of listeners (m, rad).

    Directivity: ``grid_points`` directions from ``-grid_arc`` to ``+grid_arc`` degrees from the acceleration
    axis in the xz-plane (:func:`_arc`), at ``grid_distance`` from the sphere's centre. Map: the plane ``grid_section``
    through the sphere's centre reaching ``grid_extent`` from it, cut at the reflecting planes
    (:func:`acoustiviz.field.grids.section_grid`). ``grid = "none"``: no point.
    """
    import numpy as np

    if job.grid == "directivity":
        points, angle = _arc(job)
        return points, angle, None
    if job.grid == "map":
        grid = plane_grid(job)
        return grid.points, None, grid
    return np.zeros((0, 3)), None, None


def plane_grid(job: RunFieldJob):
    """The plane of the map and the snapshot: ``grid_section`` through the sphere's centre, to ``grid_extent``.

    :func:`acoustiviz.field.grids.section_grid`, cut at the reflecting planes, ``grid_points`` along its longer
    side.
    """
    from ...errors import user_terms
    from ...field.grids import section_grid

    with user_terms({k: job.name(f"grid_{k}") for k in ("section", "extent")}):
        return section_grid(job.sound.cavity.geometry, job.grid_section, job.grid_extent, job.grid_points)


@dataclasses.dataclass(frozen=True, eq=False)
class RunFieldJob(Settings):
    """The whole of what :func:`acoustiviz.app.run_field.run` needs: a damper run's levels on a grid, its waveform.

    ``acoustiviz auralize`` (with ``--grid`` or ``--waveform-csv``), a scene's ``[outputs.run_field]`` and
    Python callers build it; the ranges of :data:`RUN_FIELD` are checked when it is made, then :meth:`validate`
    checks the files and the memory the grid needs before any work.

    Attributes
    ----------
    sound : acoustiviz.app.settings.auralize.AuralizeJob
        The run and its sound: the damper run, cavity, clicks, listeners, room's sound, rate (Hz) and memory cap.
    grid : {"none", "directivity", "map"}
        The grid of listeners the levels are evaluated on.
    grid_distance : float
        Directivity: radius of the arc in m around the sphere's centre.
    grid_arc : float
        Directivity: half-opening of the arc in degrees from the acceleration axis, in the xz-plane.
    grid_points : int
        Points on the arc, or along the longer side of the map.
    grid_section : {"xz", "yz", "xy"}
        Map: the plane through the sphere's centre.
    grid_extent : float
        Map: distance in m from the sphere's centre to the map's edges.
    snapshot_time : float or None
        The instant in s of the snapshot over the plane (None: none).
    grid_csv, grid_png, waveform_csv, waveform_png, snapshot_png, snapshot_vtk : str or None
        The files to write (None: not written).
    names : dict
        API parameter -> the option or scene key named in errors.

    Two jobs are equal when they evaluate the same sound (:meth:`AuralizeJob.same_sound
    <acoustiviz.app.settings.auralize.AuralizeJob.same_sound>`: the WAV files and levels of the command that
    carries the options are its own) on the same grid into the same files.
    """

    TABLE = _CHECKED
    BUILT_FROM = (*RUN_FIELD, *MEMORY)
    #: The files a job may write, with their formats.
    FILES = {"grid_csv": "csv", "grid_png": "figure", "waveform_csv": "csv", "waveform_png": "figure",
             "snapshot_png": "figure", "snapshot_vtk": "vtk"}
    DERIVED_NAMES = {"scene": {k: _T for k in FILES}}

    sound: object
    grid: str = "none"
    grid_distance: float = 0.7
    grid_arc: float = 90.0
    grid_points: int = 19
    grid_section: str = "xz"
    grid_extent: float = 0.5
    grid_csv: str | None = None
    grid_png: str | None = None
    waveform_csv: str | None = None
    waveform_png: str | None = None
    snapshot_time: float | None = None
    snapshot_png: str | None = None
    snapshot_vtk: str | None = None
    names: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)

    def __eq__(self, other):
        if not isinstance(other, RunFieldJob):
            return NotImplemented
        fields = [f.name for f in dataclasses.fields(self) if f.name not in ("sound", "names")]
        return self.sound.same_sound(other.sound) and all(getattr(self, k) == getattr(other, k) for k in fields)

    __hash__ = None

    @classmethod
    def from_namespace(cls, ns: dict, sound):
        """The job of ``acoustiviz auralize``'s options (``vars(args)``) around its ``sound``, naming the options."""
        from ...errors import ParameterError

        values = {s.name: ns[s.name] for s in RUN_FIELD if s.option is not None and s.name in ns}
        names = cls.names_for("cli")
        if values.get("snapshot_time") is not None and values.get("snapshot_png") is values.get("snapshot_vtk") is None:
            raise ParameterError(names["snapshot_time"], f"needs {names['snapshot_png']} or {names['snapshot_vtk']}")
        return cls(sound, names=names, **values)

    def name(self, key: str) -> str:
        """The user's name of setting ``key`` (the API name when the front end gave none)."""
        return self.names.get(key, key)

    @property
    def wanted(self) -> bool:
        """Whether any file is asked for."""
        return any(getattr(self, k) is not None for k in self.FILES)

    def validate(self) -> None:
        """The grid's files only with a grid, every file writable and distinct, the grid within the memory cap."""
        from ...errors import ParameterError
        from ..outputs import check_distinct, check_output_file

        if self.grid == "none":
            for key in ("grid_csv", "grid_png"):
                if getattr(self, key) is not None:
                    raise ParameterError(self.name(key), f"needs a grid: {self.name('grid')} directivity or map")
        self._check_snapshot()
        outputs = {}
        for key, kind in self.FILES.items():
            if getattr(self, key) is not None:
                outputs[self.name(key)] = check_output_file(self.name(key), getattr(self, key), kind)
        if self.snapshot_vtk is not None:
            from ...output.vtk import geometry_path

            name = self.name("snapshot_vtk")
            outputs[f"{name} (geometry)"] = check_output_file(name, geometry_path(self.snapshot_vtk), "vtk")
        check_distinct({**outputs, **{f"{self.sound.name('wav_files')} {p}": p for p in self.sound.wav_files}})
        if self.grid != "none":
            self._check_budget()
        if self.snapshot_time is not None:
            self._check_snapshot_budget()

    def _check_snapshot(self) -> None:
        """A snapshot's figure with its instant, the instant within the run."""
        from ...errors import ParameterError

        for key in ("snapshot_png", "snapshot_vtk"):
            if getattr(self, key) is not None and self.snapshot_time is None:
                raise ParameterError(self.name(key), f"needs {self.name('snapshot_time')}")
        if self.snapshot_time is None:
            return
        sound = self.sound
        several = sound.damper is not None and sound.damper.total_balls() > 1
        if sound.room_sound is not None or (several and sound.cavity.geometry.enclosed):
            raise ParameterError(self.name("snapshot_time"), "the snapshot of a room with a late tail or absorption "
                                                             "bands, or of several balls in a room, is not offered")
        if self.snapshot_time > self.sound.duration:
            raise ParameterError(self.name("snapshot_time"), f"{self.snapshot_time:g} s is outside the run: give an "
                                                             f"instant in [0, {self.sound.duration:g}] s")

    def _check_snapshot_budget(self) -> None:
        """The snapshot's plane times each click's sources (the sphere and its images) within the memory cap."""
        from ..budget import Estimate, check_budget

        n, k = len(plane_grid(self).points), 2 * len(self.sound.cavity.geometry.images())
        # per point and source: the delay, amplitude and shape, the pulse's response and the product (complex)
        check_budget(Estimate(8.0 * 8 * n * k, 0.0, f"{n} points x {k} sources", (self.name("grid_points"),)),
                     self.sound.max_memory_mb, cap_name=self.sound.name("max_memory_mb"))

    def _check_budget(self) -> None:
        """The run's sound at one grid point, at the levels' rate, within the memory cap.

        The points are evaluated in groups as large as the cap allows (:func:`acoustiviz.app.run_field.run`).
        """
        from ..budget import check_budget, grid_levels_estimate
        from ..levels import ANALYSIS_RATE

        check_budget(grid_levels_estimate(self.sound.duration, ANALYSIS_RATE, 1,
                                          options=(self.sound.name("duration"), self.name("grid"))),
                     self.sound.max_memory_mb, cap_name=self.sound.name("max_memory_mb"))
