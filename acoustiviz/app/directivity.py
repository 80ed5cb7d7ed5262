"""The directivity job: peak SPL, RMS and a further level of one impact against angle on a circle (paper Figure 3).

Three parts, shared by ``acoustiviz directivity``, a scene's ``[outputs.directivity]`` and Python callers:

* :class:`~acoustiviz.app.settings.directivity.DirectivityJob`, the settings, checked once when made;
* :func:`run`, which computes a :class:`DirectivityResult` from them (physics only: no files, no printing);
* :meth:`DirectivityResult.write`, which writes the files the settings asked for and returns their paths.

Angles are in rad from the acceleration axis (the normal of the struck surface) in the API, in degrees
on the command line and in the table; the circle's radius in m.

Examples
--------
The paper's Figure 3 above a reflecting plane, at 0.7 m every 45°:

>>> from acoustiviz.app.impacts import impact_setup
>>> setup = impact_setup(radius=0.01905, velocity=1.4, density=7800.0, config="plane")
>>> job = DirectivityJob(impact=setup.impact, pulse=setup.pulse, medium=setup.medium,
...                      geometry=setup.geometry, distance=0.7, step_deg=45.0)
>>> result = run(job)
>>> result.angles_deg.round(6).tolist(), result.spl_db.round(1).tolist()
([0.0, 45.0, 90.0], [93.2, 88.8, 68.2])
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..constants import DIRECTIVITY_METRICS
from .settings.directivity import DirectivityJob

__all__ = ["DirectivityJob", "DirectivityResult", "run"]


@dataclass(frozen=True, eq=False)
class DirectivityResult:
    """The directivity of a :class:`DirectivityJob` and its further level.

    Attributes
    ----------
    settings : DirectivityJob
        What was computed.
    directivity : acoustiviz.field.Directivity
        Peak (Pa), RMS (Pa) and peak SPL (dB) per angle, with the circle's points (m) and the RMS window (s).
    levels : (n,) ndarray or None
        The further level ``settings.metric`` in dB per angle (None for ``"peak-spl"``).
    """

    settings: DirectivityJob
    directivity: object
    levels: np.ndarray | None

    @property
    def angles(self) -> np.ndarray:
        """Polar angles in rad from the acceleration axis."""
        return np.asarray(self.directivity.angle, dtype=float)

    @property
    def angles_deg(self) -> np.ndarray:
        """Polar angles in degrees from the acceleration axis."""
        return np.asarray(self.directivity.angle_deg, dtype=float)

    @property
    def peak(self) -> np.ndarray:
        """Peak pressure ``max|p|`` in Pa per angle."""
        return np.asarray(self.directivity.peak, dtype=float)

    @property
    def rms(self) -> np.ndarray:
        """RMS pressure in Pa over the window per angle."""
        return np.asarray(self.directivity.rms, dtype=float)

    @property
    def spl_db(self) -> np.ndarray:
        """Peak SPL ``20 log10(max|p| / 20 µPa)`` in dB per angle."""
        return np.asarray(self.directivity.spl_db, dtype=float)

    @property
    def column(self) -> str | None:
        """The table's column of the further level (None: none)."""
        return DIRECTIVITY_METRICS[self.settings.metric] if self.levels is not None else None

    def loudest(self) -> int:
        """The index of the angle of the largest peak SPL."""
        return int(np.nanargmax(self.spl_db))

    def title(self) -> str:
        """The figure's title: the configuration, the circle's radius, the sphere, the speed and the pulse."""
        s = self.settings
        return (f"{s.geometry.caption()}: r = {s.distance:g} m, a = {s.geometry.radius * 1e3:g} mm, "
                f"U0 = {s.impact.velocity:g} m/s, {s.pulse.kind} pulse")

    def write(self, folder=None) -> list:
        """Write the files the settings ask for into ``folder``; return their paths.

        The table (``angle_deg, peak_pa, rms_pa, spl_db`` and the further level's column,
        :func:`acoustiviz.app.columns.write_directivity_csv`) and the polar figure, each atomically.

        Parameters
        ----------
        folder : path-like, optional
            Where relative file names are put (default: as given, the current folder).

        Returns
        -------
        list of Path
        """
        files = {k: Path(v) if folder is None else Path(folder) / v for k, v in self.settings.files().items()}
        written = []
        if "csv" in files:
            from .columns import write_directivity_csv

            written.append(write_directivity_csv(files["csv"], self.directivity, self.column, self.levels))
        if "png" in files:
            written.append(self._figure(files["png"]))
        return [Path(p) for p in written]

    def _figure(self, path: Path) -> Path:
        """Peak SPL and RMS (and the further level) against angle, polar, titled from the settings alone."""
        from ..output.plot.directivity import directivity_figure
        from ..output.plot.style import save_figure
        from .views import directivity_metric_figure

        half = self.settings.geometry.polar_limit_deg == 90.0
        if self.levels is not None:
            fig = directivity_metric_figure(self.directivity, self.levels, self.settings.metric, half_space=half,
                                            title=self.title())
        else:
            fig = directivity_figure(self.directivity, half_space=half, title=self.title())
        return save_figure(fig, path)


def run(settings: DirectivityJob) -> DirectivityResult:
    """Compute the directivity of ``settings`` and its further level (no files).

    Parameters
    ----------
    settings : DirectivityJob
        The job, checked when it was made.

    Returns
    -------
    DirectivityResult
    """
    from .names import user_terms

    with user_terms(settings.names):  # an error of the physics in the front end's words
        return _run(settings)


def _run(s: DirectivityJob) -> DirectivityResult:
    from ..field import directivity
    from .budget import memory_cap
    from .views import directivity_angles, directivity_metric

    geometry = s.geometry
    angles = directivity_angles(geometry, s.step_deg)
    d = directivity(s.pulse, geometry, s.distance, angles, medium=s.medium)
    levels = None
    if s.metric != "peak-spl":  # the sound at every angle within the cap its estimate was checked against
        levels = directivity_metric(d, s.metric, s.pulse, geometry, s.medium,
                                    memory_limit=memory_cap(s.max_memory_mb) if s.weighted else None)
    return DirectivityResult(s, d, levels)
