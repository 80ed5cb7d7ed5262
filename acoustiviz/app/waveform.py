"""The pressure waveform of one impact at one observer: tabulated, its peaks, and its files.

``acoustiviz waveform`` runs :func:`waveform_at` on its :class:`~acoustiviz.app.settings.impact.WaveformSettings`
and writes :func:`write_waveform_outputs`; a scene's ``[outputs.waveform]`` shares the times, the
table's format and the rule for the reported peaks (:mod:`acoustiviz.app.columns`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .columns import waveform_extremes, write_waveform_csv

__all__ = ["Waveform", "waveform_at", "waveform_record", "write_waveform_outputs"]


@dataclass(frozen=True)
class Waveform:
    """A tabulated waveform and the peaks it reports.

    Attributes
    ----------
    times : (n,) ndarray
        Times in s from the start of contact.
    pressure : (n,) ndarray
        Pressure in Pa.
    peak_positive, peak_negative : float
        Largest and smallest pressure in Pa (:func:`acoustiviz.app.columns.waveform_extremes`).
    """

    times: np.ndarray
    pressure: np.ndarray
    peak_positive: float
    peak_negative: float

    @property
    def peak_spl_db(self) -> float:
        """Peak SPL ``20 log10(max|p| / 20 µPa)`` in dB."""
        from ..field.metrics import spl_db

        return spl_db(max(self.peak_positive, -self.peak_negative))


def waveform_at(setup, point, settings, *, max_memory_mb=None, size_options=("samples_per_duration",)) -> Waveform:
    """Tabulate the waveform of ``setup`` at ``point`` after checking its memory; return it with its peaks.

    Parameters
    ----------
    setup : acoustiviz.app.impacts.ImpactSetup
        Pulse, configuration and medium.
    point : (3,) ndarray
        Observer in m.
    settings : acoustiviz.app.settings.impact.WaveformSettings
        Samples per contact duration and, in a room, the window in s.
    max_memory_mb : float, optional
        Cap on the working memory (:func:`acoustiviz.app.budget.check_budget`).
    size_options : tuple of str
        The settings that set the number of samples, named by an error about it (the first first).
    """
    from ..field import time_series
    from .budget import check_budget, check_room_order, memory_cap, waveform_estimate
    from .views import waveform_times

    conf, medium, pulse = setup.configuration, setup.medium, setup.pulse
    check_room_order(conf, max_memory_mb)  # a room that leaves out more energy than its tolerance: refused
    check_budget(waveform_estimate([pulse], point, conf, medium, settings.samples_per_duration,
                                   options=size_options, window=settings.window), max_memory_mb)
    t = waveform_times([pulse], point, conf, medium, settings.samples_per_duration, window=settings.window)
    p = time_series(pulse, t, point[None, :], conf, medium=medium, memory_limit=memory_cap(max_memory_mb))[0]
    pmax, pmin = waveform_extremes(pulse, p, point, conf, medium, memory_limit=memory_cap(max_memory_mb))
    return Waveform(t, p, pmax, pmin)


def waveform_record(setup, point, wf: Waveform, settings, csv_name: str) -> dict:
    """The JSON sidecar of a room's waveform table: the images, the settings and the peaks."""
    from .. import __version__

    conf, imp, t = setup.configuration, setup.impact, wf.times
    return {"software": f"acoustiviz {__version__}", "csv": csv_name, "columns": ["time_s", "pressure_pa"],
            "config": conf.name, "radius_m": conf.radius, **conf.settings(), "listener_m": point.tolist(),
            "window_s": settings.window, "sample_interval_s": float(t[1] - t[0]) if t.size > 1 else None,
            "velocity_m_s": imp.velocity, "k_hertz_n_m1_5": imp.k_hertz, "mass_kg": imp.mass,
            "pulse": setup.pulse.kind, "medium": {"c_m_s": setup.medium.c, "rho_kg_m3": setup.medium.rho},
            "peak_positive_pa": wf.peak_positive, "peak_negative_pa": wf.peak_negative}


def write_waveform_outputs(setup, point, wf: Waveform, settings, *, csv=None, png=None, title: str = "") -> list:
    """Write the table (with, in a room, its JSON sidecar ``csv`` + ``.json``) and the figure; return the paths."""
    written = []
    if csv:
        write_waveform_csv(csv, wf.times, [wf.pressure], ["pressure_pa"])
        written.append(csv)
        if getattr(setup.configuration, "image_order", None) is not None:
            import json

            from ..files import write_text_atomic

            side = Path(csv).with_suffix(".json")
            record = waveform_record(setup, point, wf, settings, Path(csv).name)
            write_text_atomic(side, json.dumps(record, indent=2) + "\n")
            written.append(side)
    if png:
        from ..output.plot.style import save_figure, style
        from ..output.plot.waveform import plot_waveform

        with style():
            ax = plot_waveform(wf.times, wf.pressure, label=f"{setup.configuration.name}, {setup.pulse.kind}")
            ax.set_title(title)
            ax.legend()
            save_figure(ax.figure, png)
        written.append(png)
    return written
