"""The field of a whole damper run: its levels on a grid of listeners, and its waveform at the listeners.

Three parts, shared by ``acoustiviz auralize`` (``--grid``, ``--waveform-csv``), a scene's
``[outputs.run_field]`` and Python callers:

* :class:`~acoustiviz.app.settings.run_field.RunFieldJob`, the settings, checked once when made;
* :func:`run`, which takes the run's sound at the listeners (:func:`acoustiviz.app.auralize.run`, the WAV's
  calibrated pressure) and, with a grid, renders every collision of the run at each grid point as a listener
  (:func:`acoustiviz.app.damper.render_run`, at the levels' rate) and evaluates its levels
  (:func:`acoustiviz.levels.sound_levels`), returning a :class:`RunFieldResult` (no files, no printing);
* :meth:`RunFieldResult.write`, which writes the grid's CSV and figure and the waveform's CSV and figure.

Lengths in m, angles in rad (degrees in the files), times in s, pressures in Pa, levels in dB re 20 µPa.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..levels.weighted import LEVEL_COLUMNS
from .settings.run_field import RunFieldJob, grid_points

__all__ = ["RunFieldJob", "RunFieldResult", "grid_points", "run"]


def heard_points(job: RunFieldJob, points) -> np.ndarray:
    """Which grid points are listeners (True): in the fluid, outside the sphere, the cavity and every column.

    The listeners' own check (:meth:`~acoustiviz.app.settings.auralize.AuralizeJob.check_listeners`) point by
    point; a point it refuses is left out of the evaluation (its levels are blank).
    """
    heard = np.ones(len(points), dtype=bool)
    for i, p in enumerate(points):
        try:
            job.sound.check_listeners(p[None, :])
        except ParameterError:
            heard[i] = False
    return heard


@dataclasses.dataclass(frozen=True, eq=False)
class RunFieldResult:
    """The field of a :class:`RunFieldJob`, ready to write.

    Attributes
    ----------
    settings : RunFieldJob
        What was run.
    sound : acoustiviz.app.auralize.AuralizeResult
        The run's sound at the listeners (the WAV's calibrated pressure, Pa, at the WAV's rate).
    points : (n, 3) ndarray
        The grid's points in m (empty without a grid).
    heard : (n,) ndarray of bool
        Whether each point is a listener (False: inside the sphere, the cavity or a wall; blank levels).
    levels : dict
        :data:`acoustiviz.levels.LEVEL_COLUMNS` name -> (n,) levels in dB at the points (NaN where not heard).
    angle : (n,) ndarray or None
        Directivity: each point's angle in rad from the acceleration axis +z (positive towards +x).
    grid : acoustiviz.field.grids.PlanarGrid or None
        Map: the planar grid.
    sample_rate : float
        Rate in Hz the grid's levels were evaluated at.
    snapshot : (m,) ndarray or None
        The pressure in Pa at instant ``settings.snapshot_time`` at the points of ``snapshot_grid`` (NaN where
        not heard); None: no snapshot.
    snapshot_grid : acoustiviz.field.grids.PlanarGrid or None
        The snapshot's plane.
    """

    settings: RunFieldJob
    sound: object
    points: np.ndarray
    heard: np.ndarray
    levels: dict
    angle: np.ndarray | None = None
    grid: object = None
    sample_rate: float = 0.0
    snapshot: np.ndarray | None = None
    snapshot_grid: object = None

    @property
    def waveform(self) -> tuple:
        """``(t, p, names)``: times in s, the pressure in Pa at each listener (one row each), listener names."""
        r = self.sound.rendering
        return r.signal.times, np.atleast_2d(r.pressure), [lst.name for lst in self.settings.sound.listeners]

    def write(self, folder=None) -> list:
        """Write the files the job asks for into ``folder`` (default: as given); return their paths.

        The grid's CSV and figure, then the waveform's CSV and figure, each atomically.
        """
        s, paths = self.settings, []

        def where(name):
            return Path(name) if folder is None else Path(folder) / name

        if s.grid_csv is not None:
            paths.append(self._grid_csv(where(s.grid_csv)))
        if s.grid_png is not None:
            paths.append(self._grid_figure(where(s.grid_png)))
        if s.waveform_csv is not None:
            paths.append(self._waveform_csv(where(s.waveform_csv)))
        if s.waveform_png is not None:
            paths.append(self._waveform_figure(where(s.waveform_png)))
        if s.snapshot_png is not None:
            paths.append(self._snapshot_figure(where(s.snapshot_png)))
        if s.snapshot_vtk is not None:
            from ..output.vtk import write_map_vtk

            paths += [p for p in write_map_vtk(self.snapshot_grid, {"pressure_pa": self.snapshot},
                                               s.sound.cavity.geometry, where(s.snapshot_vtk)) if p is not None]
        return paths

    def _snapshot_figure(self, path) -> Path:
        """The pressure over the plane at the snapshot's instant, with the sphere and the planes."""
        from ..output.plot.maps import pressure_map_figure
        from ..output.plot.style import save_figure

        section = self.settings.grid_section
        fig = pressure_map_figure(self.snapshot_grid, self.snapshot, self.settings.sound.cavity.geometry,
                                  axes_names=(section[0], section[1]),
                                  title=f"the damper run at t = {self.settings.snapshot_time:g} s")
        return save_figure(fig, path)

    def _grid_csv(self, path) -> Path:
        """One row per point: (angle_deg,) x_m, y_m, z_m, then the levels in dB (blank where not heard)."""
        from ..files import write_text_atomic
        from ..output.tables import csv_number

        head = ["angle_deg"] if self.angle is not None else []
        lines = [",".join([*head, "x_m", "y_m", "z_m", *LEVEL_COLUMNS])]
        for i, p in enumerate(self.points):
            cells = [f"{np.degrees(self.angle[i]):.6g}"] if self.angle is not None else []
            cells += [f"{v:.6g}" for v in p] + [csv_number(self.levels[c][i], ".4f") for c in LEVEL_COLUMNS]
            lines.append(",".join(cells))
        return write_text_atomic(path, "\n".join(lines) + "\n")

    def _grid_figure(self, path) -> Path:
        """Directivity: LAeq, LCpeak, LAFmax and SEL(A) on polar axes; map: peak SPL and SEL over the plane."""
        from ..output.plot.directivity import levels_polar_figure
        from ..output.plot.maps import level_map_figure
        from ..output.plot.style import save_figure

        lv, title = self.levels, f"the damper run ({len(self.sound.sequence)} impacts)"
        if self.angle is not None:
            fig = levels_polar_figure(self.angle, {"LAeq": lv["laeq_db"], "LCpeak": lv["lcpeak_db"],
                                                   "LAFmax": lv["lafmax_db"], "SEL(A)": lv["sel_a_db"]},
                                      title=f"{title} at {self.settings.grid_distance:g} m")
        else:
            section = self.settings.grid_section
            fig = level_map_figure(self.grid, lv["lzpeak_db"], lv["sel_db"], self.settings.sound.cavity.geometry,
                                   axes_names=(section[0], section[1]), title=title)
        return save_figure(fig, path)

    def _waveform_csv(self, path) -> Path:
        """``time_s`` then ``p_<listener>_pa`` per listener."""
        from ..files import write_csv_atomic

        t, p, names = self.waveform
        return write_csv_atomic(path, ["time_s", *(f"p_{n}_pa" for n in names)], [t, *p])

    def _waveform_figure(self, path) -> Path:
        """The pressure at each listener against time."""
        from ..output.plot.style import save_figure, style
        from ..output.plot.waveform import plot_waveform

        t, p, names = self.waveform
        with style():
            ax = plot_waveform(t, p, label=names, title=f"the damper run ({len(self.sound.sequence)} impacts)")
        return save_figure(ax.figure, path)


def _grid_levels(job: RunFieldJob, sound, points, heard) -> tuple:
    """``(levels, rate)``: the run rendered at each heard point as a listener and its levels (dB; NaN: not heard).

    The points are rendered in groups as large as the memory cap allows (:func:`~.budget.grid_levels_estimate`
    per point). Every point's signal is as long as the whole grid's would be in one rendering (a rendering
    lasts the run, or to the last click's tail at its farthest point if later): a group rendered shorter is
    rendered again to that length, so the levels do not depend on the grouping.
    """
    from ..levels import sound_levels
    from .budget import grid_levels_estimate, memory_cap
    from .levels import ANALYSIS_RATE

    levels = {c: np.full(len(points), np.nan) for c in LEVEL_COLUMNS}
    if not heard.any():
        raise ParameterError(job.name("grid"), "no point of the grid lies in the fluid outside the cavity: move or "
                                               "enlarge it")
    s = job.sound
    index = np.flatnonzero(heard)
    size = max(1, int(memory_cap(s.max_memory_mb) // grid_levels_estimate(s.duration, ANALYSIS_RATE, 1).memory))
    groups = [index[lo:lo + size] for lo in range(0, index.size, size)]

    def evaluate(group, duration) -> int:
        """Render ``group`` lasting at least ``duration`` s, keep its levels; return its length in samples."""
        signal = _render_points(sound, points[group], ANALYSIS_RATE, duration).signal
        lv = sound_levels(signal)
        for c in LEVEL_COLUMNS:
            levels[c][group] = getattr(lv, c)
        return signal.n_samples

    lengths = [evaluate(group, s.duration) for group in groups]
    longest = max(lengths)
    for group, n in zip(groups, lengths, strict=True):
        if n < longest:  # half a sample short of the longest: rendered to exactly its length
            evaluate(group, (longest - 0.5) / ANALYSIS_RATE)
    return levels, float(ANALYSIS_RATE)


def _render_points(sound, points, rate: int, duration: float):
    """The run's sound at ``points`` (m) at ``rate`` Hz lasting at least ``duration`` s: :func:`.damper.render_run`."""
    from .damper import cavity_positions, render_run

    s = sound.settings
    return render_run(sound.damper.result if sound.damper is not None else None, sound.sequence, s.cavity, s.click,
                      points, sample_rate=rate, duration=duration, room_sound=s.room_sound,
                      positions=cavity_positions(s.damper))


def run(job: RunFieldJob, *, damper=None, sound=None) -> RunFieldResult:
    """The run's sound at the listeners and, with a grid, its levels at every grid point.

    Physics only: no file is written and nothing printed.

    Parameters
    ----------
    job : RunFieldJob
        The job, checked when it was made.
    damper : acoustiviz.app.damper.DamperResult, optional
        The run of ``job.sound.damper`` already simulated (a scene's one damper run).
    sound : acoustiviz.app.auralize.AuralizeResult, optional
        The run's sound already rendered at the listeners (``acoustiviz auralize``'s result for ``job.sound``).

    Returns
    -------
    RunFieldResult
    """
    from .auralize import run as run_sound

    if sound is None:
        sound = run_sound(job.sound, damper=damper)
    points, angle, grid = grid_points(job)
    heard = heard_points(job, points)
    levels, rate = ({c: np.zeros(0) for c in LEVEL_COLUMNS}, 0.0) if job.grid == "none" else \
        _grid_levels(job, sound, points, heard)
    plane, snapshot = None, None
    if job.snapshot_time is not None:
        plane, snapshot = _snapshot(job, sound)
    return RunFieldResult(job, sound, points, heard, levels, angle, grid, rate, snapshot, plane)


def _snapshot(job: RunFieldJob, sound) -> tuple:
    """``(plane, pressure)``: the run's pressure in Pa over the plane at the snapshot's instant (NaN: not heard)."""
    from .damper import cavity_positions, snapshot_run
    from .settings.run_field import plane_grid

    s, plane = sound.settings, plane_grid(job)
    heard = heard_points(job, plane.points)
    pressure = np.full(len(plane.points), np.nan)
    pressure[heard] = snapshot_run(sound.damper.result if sound.damper is not None else None, sound.sequence,
                                   s.cavity, s.click, plane.points[heard], job.snapshot_time,
                                   positions=cavity_positions(s.damper))
    return plane, pressure
