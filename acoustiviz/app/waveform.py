"""The waveform job: the pressure of one impact at its listeners, its peaks and its files.

Three parts, shared by ``acoustiviz waveform``, a scene's ``[outputs.waveform]`` and Python callers:

* :class:`~acoustiviz.app.settings.waveform.WaveformJob`, the settings, checked once when made;
* :func:`run`, which computes a :class:`WaveformResult` from them (physics only: no files, no printing);
* :meth:`WaveformResult.write`, which writes the files the settings asked for and returns their paths.

Examples
--------
The paper's Figure 2 waveform above a reflecting plane, at 0.7 m and 45°:

>>> import math
>>> from acoustiviz.app.impacts import impact_setup
>>> from acoustiviz.core.geometry import observer_points
>>> setup = impact_setup(radius=0.01905, velocity=1.4, density=7800.0, config="plane")
>>> point = observer_points(setup.geometry, 0.7, math.radians(45.0))[0]
>>> job = WaveformJob(impact=setup.impact, pulses=(setup.pulse,), medium=setup.medium,
...                   geometry=setup.geometry, listeners=(Listener("paper", point),))
>>> result = run(job)
>>> round(result.peak_spl_db[0], 1)
88.8
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.listener import Listener
from .columns import waveform_extremes, write_waveform_csv
from .settings.waveform import WaveformJob

__all__ = ["WaveformJob", "Listener", "WaveformResult", "run", "pressure_columns"]


def pressure_columns(kinds) -> list:
    """The table's pressure columns: ``pressure_pa`` for one pulse, ``pressure_KIND_pa`` for each of several."""
    kinds = list(kinds)
    return ["pressure_pa"] if len(kinds) == 1 else [f"pressure_{k}_pa" for k in kinds]


@dataclass(frozen=True, eq=False)
class WaveformResult:
    """The waveforms of a :class:`WaveformJob` and the peaks they report.

    Attributes
    ----------
    settings : WaveformJob
        What was computed.
    times : tuple of (n,) ndarray
        Times in s from the start of contact, one array per listener.
    pressures : tuple of (n_pulses, n) ndarray
        Pressure in Pa per listener, one row per pulse of ``settings.pulses``.
    peak_positive, peak_negative : tuple of float
        Largest and smallest pressure in Pa of the first pulse at each listener
        (:func:`acoustiviz.app.columns.waveform_extremes`: in a room the largest samples of the window,
        elsewhere the peaks of the continuous waveform).
    images : dict
        In a room, its image model (``image_order``, ``images``, ``neglected_energy_db``); empty elsewhere.
    """

    settings: WaveformJob
    times: tuple
    pressures: tuple
    peak_positive: tuple
    peak_negative: tuple
    images: dict

    @property
    def peak_spl_db(self) -> tuple:
        """Peak SPL ``20 log10(max|p| / 20 µPa)`` in dB at each listener."""
        from ..field.metrics import spl_db

        return tuple(spl_db(max(a, -b)) for a, b in zip(self.peak_positive, self.peak_negative, strict=True))

    def write(self, folder=None) -> list:
        """Write the files the settings ask for into ``folder``; return their paths.

        Per listener: the table (``time_s`` and one pressure column per pulse, :func:`pressure_columns`),
        in a room its JSON sidecar beside it (:func:`record`), and the figure; each atomically.

        Parameters
        ----------
        folder : path-like, optional
            Where relative file names are put (default: as given, the current folder).

        Returns
        -------
        list of Path
        """
        s, written = self.settings, []
        for i, lst in enumerate(s.listeners):
            files = {k: Path(v) if folder is None else Path(folder) / v for k, v in s.files(lst).items()}
            if "csv" in files:
                written.append(write_waveform_csv(files["csv"], self.times[i], list(self.pressures[i]),
                                                  pressure_columns(p.kind for p in s.pulses)))
            if "json" in files:
                import json

                from ..files import write_text_atomic

                written.append(write_text_atomic(files["json"], json.dumps(self.record(i, files["csv"].name),
                                                                           indent=2) + "\n"))
            if "png" in files:
                written.append(self._figure(i, files["png"]))
        return [Path(p) for p in written]

    def title(self, i: int = 0) -> str:
        """The figure's title at listener ``i``: the configuration, the listener's distance, the sphere and speed."""
        s = self.settings
        geometry = s.geometry
        r = float(np.linalg.norm(np.asarray(s.listeners[i].position) - geometry.centre))
        return (f"{geometry.name}, listener {s.listeners[i].name!r} at r = {r:.4g} m, "
                f"a = {geometry.radius * 1e3:g} mm, U0 = {s.impact.velocity:g} m/s")

    def record(self, i: int, csv_name: str) -> dict:
        """The JSON sidecar of a room's table at listener ``i``: the images, the settings and the peaks."""
        from .. import __version__

        s, t = self.settings, self.times[i]
        geometry, imp = s.geometry, s.impact
        return {"software": f"acoustiviz {__version__}", "csv": csv_name,
                "columns": ["time_s", *pressure_columns(p.kind for p in s.pulses)],
                "config": geometry.name, "radius_m": geometry.radius, **geometry.settings(),
                "listener_m": s.listeners[i].position.tolist(), "window_s": s.window,
                "sample_interval_s": float(t[1] - t[0]) if t.size > 1 else None,
                "velocity_m_s": imp.velocity, "k_hertz_n_m1_5": imp.k_hertz, "mass_kg": imp.mass,
                "pulse": s.pulses[0].kind, "medium": {"c_m_s": s.medium.c, "rho_kg_m3": s.medium.rho},
                "peak_positive_pa": self.peak_positive[i], "peak_negative_pa": self.peak_negative[i]}

    def _figure(self, i: int, path: Path) -> Path:
        """The waveform of every pulse at listener ``i``, titled and labelled from the settings alone."""
        from ..output.plot.style import save_figure, style
        from ..output.plot.waveform import plot_waveform
        from .products import new_figure

        t = self.times[i]
        with style():
            fig = new_figure()
            ax = fig.add_subplot()
            for pulse, p in zip(self.settings.pulses, self.pressures[i], strict=True):
                plot_waveform(t, p, ax=ax, label=f"{pulse.kind}: max {p.max():.3g} Pa, min {p.min():.3g} Pa")
            ax.set_title(self.title(i))
            ax.legend(fontsize=8)
            return save_figure(fig, path)


def run(settings: WaveformJob) -> WaveformResult:
    """Compute the waveforms of ``settings`` at each listener and the peaks they report (no files).

    Parameters
    ----------
    settings : WaveformJob
        The job, checked when it was made.

    Returns
    -------
    WaveformResult
    """
    from .names import user_terms

    with user_terms(settings.names):  # an error of the physics (its memory cap) in the front end's words
        return _run(settings)


def _run(s: WaveformJob) -> WaveformResult:
    from ..field import time_series
    from .budget import memory_cap
    from .views import waveform_times

    geometry, medium, pulses = s.geometry, s.medium, list(s.pulses)
    cap = memory_cap(s.max_memory_mb)  # the cap its estimate was checked against
    times, pressures, highs, lows = [], [], [], []
    for lst in s.listeners:
        point = np.asarray(lst.position, dtype=float)
        t = waveform_times(pulses, point, geometry, medium, s.samples_per_duration, window=s.window)
        p = np.array([time_series(pulse, t, point[None, :], geometry, medium=medium, memory_limit=cap)[0]
                      for pulse in pulses])
        high, low = waveform_extremes(pulses[0], p[0], point, geometry, medium, memory_limit=cap)
        times.append(t)
        pressures.append(p)
        highs.append(high)
        lows.append(low)
    images = {}
    if s.in_room:
        images = {"image_order": geometry.image_order, "images": geometry.image_count,
                  "neglected_energy_db": geometry.neglected_energy_db}
    return WaveformResult(s, tuple(times), tuple(pressures), tuple(highs), tuple(lows), images)
