"""Weighted levels of one design: its damper run rendered as a click train at the sweep's listener.

A design's maximum SPL (:func:`acoustiviz.sweep.max_spl_db`) is the peak of its loudest impact. How
loud the run sounds to people and to standards is asked of the whole click train:
:func:`design_levels` renders every impact of the run (:func:`acoustiviz.output.audio.render`) at
the listener, at :data:`acoustiviz.constants.ANALYSIS_RATE` (96 kHz: each click evaluated in closed
form at >= 1.5 MHz and band-limited flat to 43.2 kHz), and evaluates with
:func:`acoustiviz.levels.sound_levels` (IEC 61672-1 weightings of the conformance-tested library):

* ``lafmax_db``: the largest A-weighted, F (125 ms) time-weighted level over the run;
* ``lcpeak_db``: the largest |p| of the C-weighted signal;
* ``laeq_db``: the A-weighted energy average over the run, ``LAeq,T`` with ``T`` the simulated
  duration (from t = 0, the start of the run, to ``duration``).

Every impact is heard as a strike on the configuration's struck surface (``walls="one"`` of
:class:`acoustiviz.output.audio.CavityScene`), the view the maximum SPL takes, so the two describe
the same sound. Levels in dB re 20 µPa. The render and the filters cost many times the rest of a
design (``benchmarks/bench_sweep.py`` measures both), so a sweep computes them only when
:attr:`acoustiviz.sweep.Settings.levels` is set.
"""

from __future__ import annotations

import math

from ..constants import ANALYSIS_RATE

__all__ = ["LEVEL_COLUMNS", "LEVEL_METRICS", "design_levels", "NO_LEVELS"]

#: The level columns of ``sweep.csv``, in order.
LEVEL_COLUMNS = ("lafmax_db", "lcpeak_db", "laeq_db")
#: Column -> metric name of :func:`acoustiviz.levels.metric_levels`.
LEVEL_METRICS = {"lafmax_db": "lafmax", "lcpeak_db": "lcpeak", "laeq_db": "laeq"}
#: The level columns of a design whose levels were not computed.
NO_LEVELS = dict.fromkeys(LEVEL_COLUMNS, math.nan)


def design_levels(impacts, *, scene, model, point, duration: float, sample_rate: int = ANALYSIS_RATE):
    """LAFmax, LCpeak and LAeq,T of a damper run's click train at one listener.

    Parameters
    ----------
    impacts : acoustiviz.dynamics.ImpactTable
        The run's impacts (contact start times in s, walls, approach speeds in m/s).
    scene : acoustiviz.output.audio.CavityScene
        The cavity and its surroundings (the sweep uses ``walls="one"``).
    model : acoustiviz.output.audio.ClickModel
        How an approach speed becomes an acceleration pulse.
    point : (3,) or (1, 3) array_like
        Listener position in m.
    duration : float
        The run's simulated duration in s: the interval ``[0, duration]`` of LAeq,T and of the maxima.
    sample_rate : int
        Rendering rate in Hz (default :data:`~acoustiviz.constants.ANALYSIS_RATE`).

    Returns
    -------
    levels : dict
        ``lafmax_db``, ``lcpeak_db``, ``laeq_db`` in dB re 20 µPa (``-inf`` for a run without impacts).
    pressure : (n_samples,) ndarray
        The rendered pressure in Pa at ``sample_rate`` (for checks and plots).

    Notes
    -----
    ``LAeq,T = 10 log10((1/T) ∫_0^T p_A² dt / p_ref²)``, ``LCpeak = 20 log10(max|p_C| / p_ref)``,
    ``LAFmax = max_t 10 log10(p_AF²(t) / p_ref²)`` (IEC 61672-1:2013, 3.8-3.9 and 3.12).
    """
    import numpy as np

    from ..levels import sound_levels
    from ..output.audio import ImpactSequence, render

    n = int(round(duration * sample_rate))
    if len(impacts) == 0:
        return dict.fromkeys(LEVEL_COLUMNS, -math.inf), np.zeros(n)
    out = render(ImpactSequence.from_table(impacts), scene, model, np.reshape(point, (1, 3)),
                 sample_rate=sample_rate, duration=duration)
    p = out.pressure[0]
    lv = sound_levels(p, sample_rate, start=0.0, stop=n / sample_rate)
    return {c: float(getattr(lv, c)[0]) for c in LEVEL_COLUMNS}, p
