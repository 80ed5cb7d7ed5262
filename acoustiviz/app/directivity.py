"""The directivity of one impact: peak SPL, RMS and a further level against angle on a circle (paper Figure 3).

``acoustiviz directivity`` runs :func:`directivity_at` on its
:class:`~acoustiviz.app.settings.impact.DirectivitySettings`, prints :func:`directivity_lines` and
writes :func:`write_directivity_outputs`. Angles in degrees from the acceleration axis (the normal of
the struck surface) on the command line, in rad in the API; the circle's radius in m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import DIRECTIVITY_METRICS

__all__ = ["DirectivityResult", "directivity_at", "directivity_lines", "write_directivity_outputs"]


@dataclass(frozen=True)
class DirectivityResult:
    """A directivity and its further level.

    Attributes
    ----------
    angles : (n,) ndarray
        Polar angles in rad.
    directivity : acoustiviz.field.Directivity
        Peak (Pa), RMS (Pa) and peak SPL (dB) per angle.
    metric : str
        The further level (``"peak-spl"``: none).
    values : (n,) ndarray or None
        The further level in dB per angle.
    """

    angles: np.ndarray
    directivity: object
    metric: str
    values: np.ndarray | None

    @property
    def column(self) -> str | None:
        """The CSV column of the further level (None: none)."""
        return DIRECTIVITY_METRICS[self.metric] if self.metric != "peak-spl" else None


def directivity_at(setup, distance: float, settings, *, max_memory_mb=None) -> DirectivityResult:
    """The directivity of ``setup`` on a circle of radius ``distance`` m, its memory checked first.

    Errors name ``--distance`` and ``--step``. ``settings``: a
    :class:`~acoustiviz.app.settings.impact.DirectivitySettings` (step in degrees, further level).
    """
    from ..field import circle_points, directivity
    from .budget import check_budget, check_room_order, directivity_estimate, memory_cap, metric_estimate
    from .impacts import observer_point
    from .names import IMPACT_OPTIONS, user_terms
    from .views import directivity_angles, directivity_metric

    check_room_order(setup.configuration, max_memory_mb)  # a room short of its tolerance: refused
    with user_terms({"distance": "--distance"}):  # the circle's radius fits in the fluid (a room's walls)
        circle_points(setup.configuration, distance, [0.0])
    with user_terms(IMPACT_OPTIONS):
        observer_point(setup, distance, 0.0)  # the circle's radius checked as --distance
    names = {"step_deg": "--step", "distance": "--distance", "angles": "--step", "memory_limit": "--max-memory"}
    with user_terms(names):
        check_budget(directivity_estimate(setup.configuration, settings.step_deg, pulse=setup.pulse,
                                          medium=setup.medium, window_options=("--wall-distance", "--distance")),
                     max_memory_mb)
        angles = directivity_angles(setup.configuration, settings.step_deg)
        weighted = settings.metric not in ("peak-spl", "rms")
        if weighted:  # the sound at every angle, held together: its memory checked before any work
            check_budget(metric_estimate(setup.pulse, circle_points(setup.configuration, distance, angles),
                                         setup.configuration, setup.medium, settings.metric), max_memory_mb)
        d = directivity(setup.pulse, setup.configuration, distance, angles, medium=setup.medium)
        values = None if settings.metric == "peak-spl" else directivity_metric(
            d, settings.metric, setup.pulse, setup.configuration, setup.medium,
            memory_limit=memory_cap(max_memory_mb) if weighted else None)
    return DirectivityResult(angles, d, settings.metric, values)


def directivity_lines(setup, distance: float, res: DirectivityResult, window=None) -> list:
    """The summary and the table printed by ``acoustiviz directivity``; ``window`` in s: a room's."""
    from .views import metric_label

    imp, conf, d, extra = setup.impact, setup.configuration, res.directivity, res.values is not None
    lines = [f"impact: U0 = {imp.velocity:g} m/s, m = {imp.mass:.4g} kg, K_HZ = {imp.k_hertz:.4g} N/m^1.5 "
             f"({setup.k_hertz_source}), contact {imp.duration * 1e6:.1f} us, pulse {setup.pulse.kind}",
             f"circle: {distance:g} m from the sphere's centre, configuration {conf.caption()}; "
             f"RMS window {d.metrics.window * 1e3:.3f} ms from the first arrival"]
    if window is not None:
        lines.append(f"images: image_order {conf.image_order}, images {conf.image_count}, neglected_energy_db "
                     f"{conf.neglected_energy_db:.1f} (every image that can arrive within the {window:g} s window)")
    if extra and res.metric != "rms":
        lines.append(f"{metric_label(res.metric)}: from the pressure at each angle band-limited flat to 43.2 kHz and "
                     "sampled at 96 kHz (IEC 61672-1 weightings); equivalent levels over 1 s from the first arrival")
    lines.append(f"{'angle_deg':>9} {'peak_pa':>10} {'rms_pa':>10} {'spl_db':>7}"
                 + (f" {res.column:>10}" if extra else ""))
    for k, row in enumerate(zip(np.degrees(res.angles), d.peak, d.rms, d.spl_db, strict=True)):
        lines.append(f"{row[0]:9.2f} {row[1]:10.4g} {row[2]:10.4g} {row[3]:7.2f}"
                     + (f" {res.values[k]:10.2f}" if extra else ""))
    return lines


def write_directivity_outputs(setup, distance: float, res: DirectivityResult, *, csv=None, png=None) -> list:
    """Write the table and the polar figure asked for; return their paths."""
    written = []
    if csv:
        from .columns import write_directivity_csv

        write_directivity_csv(csv, res.directivity, res.column, res.values)
        written.append(csv)
    if png:
        from ..output.plot.directivity import directivity_figure
        from ..output.plot.style import save_figure
        from .views import directivity_metric_figure

        conf, imp = setup.configuration, setup.impact
        half = conf.polar_limit_deg == 90.0
        title = (f"{conf.caption()}: r = {distance:g} m, a = {setup.radius * 1e3:g} mm, "
                 f"U0 = {imp.velocity:g} m/s, {setup.pulse.kind} pulse")
        if res.values is not None:
            fig = directivity_metric_figure(res.directivity, res.values, res.metric, half_space=half, title=title)
        else:
            fig = directivity_figure(res.directivity, half_space=half, title=title)
        save_figure(fig, png)
        written.append(png)
    return written
