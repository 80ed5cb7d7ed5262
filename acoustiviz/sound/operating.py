"""The noise the damper makes in operation: weighted levels of its steady click train at a listener.

Each impact of the steady state is a Hertz click of its own approach speed radiated by the rigid
sphere with image sources (:func:`acoustiviz.sound.render`, paper eqs 12-14). The train is
rendered at :data:`NOISE_RATE` (96 kHz: flat to 43.2 kHz, so neither the weightings nor the peaks
are limited by a 48 kHz file) and its levels are those of :func:`acoustiviz.levels.sound_levels`
(IEC 61672-1 A/C weighting and F time weighting of the conformance-tested filter library):

* the interval is a whole number of periods of the steady state (at least ``seconds``), placed so
  that its ends fall in the longest silence between arrivals;
* it is preceded by :data:`F_SETTLE` s of the same periodic train, so the filters and the F time
  weighting (τ = 125 ms) start the interval in their periodic state: after 8 τ the running mean
  square is within ``exp(-8) = 3.4e-4`` (0.0015 dB) of it, which LAFmax needs;
* LAeq and LZeq average over the interval, SEL per cycle is its exposure over the cycles it
  spans, LZpeak, LCpeak and LAFmax are the largest values within it.

A non-periodic motion is not repeated: the cycles of its measured window (128) are rendered
once, the first whole cycles covering :data:`F_SETTLE` (at most half of them) are the lead-in
and the rest the interval, the same window as its amplitude statistics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import ANALYSIS_RATE, PAPER_ANGLE_DEG, PAPER_DISTANCE, PAPER_RADIUS
from ..core.signal import Signal
from ..errors import ParameterError

__all__ = ["NOISE_RATE", "F_SETTLE", "NOISE_COLUMNS", "OperatingNoise", "operating_noise", "default_listener",
           "noise_statement", "check_seconds", "rerun_cycles", "TrainWindow", "train_window", "train_noise"]

#: Rate in Hz at which the click train is rendered for its levels.
NOISE_RATE = ANALYSIS_RATE
#: Lead-in in s before the interval: 8 F time constants (8 × 125 ms), the F-weighted mean square
#: then within exp(-8) = 3.4e-4 (0.0015 dB) of its periodic state.
F_SETTLE = 1.0
#: Level columns of the noise in operation (dB re 20 µPa; SEL per cycle re (20 µPa)² s).
NOISE_COLUMNS = ("laeq_db", "lcpeak_db", "lafmax_db", "lzpeak_db", "lzeq_db", "sel_per_cycle_db",
                 "sel_a_per_cycle_db", "level_interval_s")



def default_listener(radius: float = PAPER_RADIUS) -> np.ndarray:
    """The paper's listener in m: 0.7 m at 45° above the floor from a sphere of ``radius`` resting on it."""
    a = math.radians(PAPER_ANGLE_DEG)
    return np.array([PAPER_DISTANCE * math.cos(a), 0.0, radius + PAPER_DISTANCE * math.sin(a)])


def noise_statement(seconds: float = 1.0) -> str:
    """How the levels of the noise in operation are computed, in one sentence (for help and reports)."""
    return (f"levels at {NOISE_RATE / 1000:g} kHz over a whole number of periods of the steady state "
            f"(at least {seconds:g} s), after a {F_SETTLE:g} s lead-in of the same train so the F time "
            f"weighting (125 ms) has settled")


@dataclass(frozen=True)
class OperatingNoise:
    """The steady click train of the damper in operation at one listener, and its levels.

    Attributes
    ----------
    frequency_hz : float
        Forcing frequency in Hz.
    signal : Signal
        Sound pressure in Pa, one channel from 0 s, at :data:`NOISE_RATE` Hz unless asked otherwise:
        lead-in, interval and one trailing period. :attr:`pressure` and :attr:`sample_rate` are
        its samples and its rate.
    start, stop : float
        The interval in s on the signal's time axis.
    cycles : int
        Forcing cycles in the interval.
    duration : float
        ``stop - start`` in s.
    settled : bool
        True when the lead-in lasted at least :data:`F_SETTLE` s.
    laeq_db, lzeq_db : float
        A- and Z-weighted equivalent continuous level over the interval, dB re 20 µPa (-inf: silent).
    lcpeak_db, lzpeak_db : float
        C- and Z-weighted peak level within the interval, dB re 20 µPa.
    lafmax_db : float
        Largest A-weighted F-time-weighted level within the interval, dB re 20 µPa.
    sel_per_cycle_db, sel_a_per_cycle_db : float
        Z- and A-weighted sound exposure of one forcing cycle, dB re (20 µPa)² s.
    sequence : acoustiviz.sound.ImpactSequence
        The impacts rendered (times in s from the start of ``pressure``).
    rendering : dict
        How the sound and the levels were computed (JSON-ready).
    balls : acoustiviz.sound.BallClicks, optional
        Several balls: the radiating spheres of the train
        (:func:`acoustiviz.sound.balls_operating.balls_operating_noise`), rendered by
        :func:`acoustiviz.sound.render_clicks`; None for one ball (``sequence`` rendered by
        :func:`acoustiviz.sound.render`).
    """

    frequency_hz: float
    signal: Signal
    start: float
    stop: float
    cycles: int
    settled: bool
    laeq_db: float
    lzeq_db: float
    lcpeak_db: float
    lzpeak_db: float
    lafmax_db: float
    sel_per_cycle_db: float
    sel_a_per_cycle_db: float
    sequence: object
    scene: object
    clicks: object
    listener: np.ndarray
    rendering: dict
    balls: object = None

    @property
    def pressure(self) -> np.ndarray:
        """``(n_samples,)`` read-only sound pressure in Pa (the samples of :attr:`signal`)."""
        return self.signal.pressure

    @property
    def sample_rate(self) -> int:
        """Rate in Hz of :attr:`signal` (a whole number)."""
        return int(self.signal.sample_rate)

    @property
    def duration(self) -> float:
        """Length of the interval in s."""
        return self.stop - self.start

    def levels(self) -> dict:
        """:data:`NOISE_COLUMNS` -> value."""
        return {c: (self.duration if c == "level_interval_s" else getattr(self, c)) for c in NOISE_COLUMNS}

    def interval_pressure(self, sample_rate: int | None = None) -> np.ndarray:
        """The interval of the train in Pa at ``sample_rate`` Hz (re-rendered when it differs)."""
        fs = self.sample_rate if sample_rate is None else int(sample_rate)
        p = self.pressure
        if fs != self.sample_rate:
            from .balls_sound import render_clicks
            from .synthesis import render

            length = self.pressure.size / self.sample_rate
            p = (render(self.sequence, self.scene, self.clicks, self.listener, sample_rate=fs, duration=length)
                 if self.balls is None else
                 render_clicks(self.balls, self.scene, self.clicks, self.listener, sample_rate=fs, duration=length)
                 ).pressure[0]
        return p[int(round(self.start * fs)): int(round(self.stop * fs))]


def _quiet_offset(arrivals: np.ndarray, window: float) -> float:
    """Offset in [0, window) s of the middle of the longest silence between periodic arrivals."""
    if arrivals.size == 0:
        return 0.0
    a = np.sort(np.mod(arrivals, window))
    gaps = np.diff(np.append(a, a[0] + window))
    k = int(np.argmax(gaps))
    return float(np.mod(a[k] + gaps[k] / 2, window))


def operating_noise(steady, *, listener=None, kind: str = "plane", radius: float = PAPER_RADIUS,
                    seconds: float = 1.0, sample_rate: int = NOISE_RATE, settings=None) -> OperatingNoise:
    """Render the steady-state impacts of ``steady`` at a listener and give their weighted levels.

    Parameters
    ----------
    steady : acoustiviz.dynamics.forced.SteadyState
    listener : (3,) array_like, optional
        Position in m (default :func:`default_listener`, 0.7 m at 45° above the plane).
    kind : {"free", "plane", "wall-floor", "room"}
        The configuration kind of the surroundings (:func:`acoustiviz.core.geometry.geometry`).
    radius : float
        Sphere radius in m (default: the paper's 19.05 mm).
    settings : dict, optional
        The geometry's settings (:func:`acoustiviz.sound.sources.cavity`: ``wall_distance``, ``strike``,
        ``height``, or ``room``, the settings of a shoebox room), as a scene gives them
        (:meth:`acoustiviz.scene.Scene.geometry_settings`).
    seconds : float
        Least length of the interval in s, (0, 60]; it spans whole periods of the motion.
    sample_rate : {44100, 48000, 96000}
        Rate of the rendering and the levels in Hz (default 96 kHz).

    Notes
    -----
    For a period-n motion with window ``W = n T`` (T the forcing period) the impacts of one window
    are repeated ``L + N + 1`` times, ``L = ceil(F_SETTLE / W)`` windows of lead-in,
    ``N = ceil(seconds / W)`` measured and one trailing; the interval is
    ``[L W + δ, (L + N) W + δ]`` with δ the middle of the longest silence between arrivals, so
    LAeq is exactly the energy average of the periodic train (eq: LAeq = 10 lg(Σ_k E_A,k / (W p_ref²))
    over the impacts k of one window) and LAFmax its periodic maximum.
    """
    from .sources import ImpactSequence, cavity, periodic_train
    from .synthesis import ClickModel, render

    seconds = check_seconds(seconds)
    model = steady.model
    period = steady.excitation.period
    scene = cavity(kind, radius, model.gap, **(settings or {}))
    pts = default_listener(radius) if listener is None else np.asarray(listener, dtype=float)
    clicks = ClickModel(k_hertz=model.k_hertz, mass=model.m, main_mass=model.M)
    measured = ImpactSequence.from_steady_state(steady, origin=steady.cycles * period)  # from the measured cycles
    base, walls, speeds = measured.times, measured.walls, measured.velocities
    delay = float(np.linalg.norm(pts - np.asarray(scene.geometry.centre))) / scene.medium.c
    w = train_window(steady, base + delay, seconds)
    seq = periodic_train(base, walls, speeds, w.window, w.total) if w.total else measured
    out = render(seq, scene, clicks, pts, sample_rate=sample_rate, duration=w.end)
    return train_noise(steady, out, w, seconds, sequence=seq, scene=scene, clicks=clicks, listener=pts)


def rerun_cycles(steady, seconds: float) -> int:
    """Cycles of a non-periodic motion to run again for its levels: the lead-in and ``seconds`` s, at most its measured.

    A periodic motion: its measured cycles (one window).
    """
    period = steady.excitation.period
    if steady.period > 0:
        return steady.measured_cycles
    wanted = math.ceil(F_SETTLE / period - 1e-9) + max(1, math.ceil(seconds / period - 1e-9))
    return min(steady.measured_cycles, wanted)


def check_seconds(seconds) -> float:
    """The least length in s of the level interval, checked to lie in (0, 60]."""
    seconds = float(seconds)
    if not 0.0 < seconds <= 60.0:
        raise ParameterError("seconds", f"must lie in (0, 60] s, got {seconds:g}")
    return seconds


@dataclass(frozen=True)
class TrainWindow:
    """Where the levels of a steady click train are taken (:func:`train_window`), times in s.

    ``window`` is the repeated part (the measured cycles), ``total`` the copies of it rendered (0: a
    non-periodic motion, its measured cycles rendered once), ``[start, stop]`` the interval, ``end`` the
    least length of the signal, ``cycles`` the forcing cycles in the interval and ``settled`` whether
    the lead-in lasted at least :data:`F_SETTLE`.
    """

    window: float
    total: int
    start: float
    stop: float
    end: float
    cycles: int
    settled: bool


def train_window(steady, arrivals, seconds: float, *, cycles: int | None = None) -> TrainWindow:
    """The interval of the levels of ``steady``'s click train (the rules of :func:`operating_noise`'s Notes).

    ``arrivals`` are the times in s at the listener of the impacts of one window (from the start of the
    measured cycles): a periodic train's interval has its ends in their longest silence. ``cycles``: a
    non-periodic motion's cycles rendered once (default its measured cycles).
    """
    period = steady.excitation.period
    if steady.period > 0:
        window = steady.measured_cycles * period
        lead = math.ceil(F_SETTLE / window - 1e-9)
        reps = max(1, math.ceil(seconds / window - 1e-9))
        total = lead + reps + 1
        offset = _quiet_offset(np.asarray(arrivals, dtype=float), window)
        return TrainWindow(window, total, lead * window + offset, (lead + reps) * window + offset, total * window,
                           reps * steady.measured_cycles, True)
    n = steady.measured_cycles if cycles is None else int(cycles)
    lead = min(math.ceil(F_SETTLE / period - 1e-9), n // 2)
    return TrainWindow(n * period, 0, lead * period, n * period, n * period, n - lead,
                       lead * period >= F_SETTLE * (1 - 1e-9))


def train_noise(steady, out, w: TrainWindow, seconds: float, **parts) -> OperatingNoise:
    """The :class:`OperatingNoise` of a rendering ``out`` of ``steady``'s train over the interval of ``w``.

    ``parts``: the :class:`OperatingNoise` fields ``sequence``, ``scene``, ``clicks``, ``listener`` (and
    ``balls`` for several balls) that rendered it.
    """
    from ..levels.train import signal_levels

    sig = Signal(out.pressure[0], out.sample_rate)
    lv = signal_levels(sig, start=w.start, stop=w.stop)  # sound_levels, from the clicks alone
    start, stop = lv.start, lv.stop  # on the sample grid
    cycles = w.cycles

    def one(x):
        return float(x[0])

    per_cycle = 10.0 * math.log10(cycles)
    rendering = {**out.describe(), "levels": {
        **lv.describe(), "interval_cycles": cycles, "lead_in_s": start, "f_time_weighting_settled": w.settled,
        "steady_state": steady.regime,
        "method": noise_statement(seconds) if steady.period > 0 else
        f"non-periodic motion: its {steady.measured_cycles} measured cycles rendered once, levels over "
        f"the last {cycles} after a {start:.3g} s lead-in"}}
    return OperatingNoise(
        frequency_hz=steady.excitation.frequency, signal=sig, start=start, stop=stop,
        cycles=cycles, settled=w.settled, laeq_db=one(lv.laeq_db), lzeq_db=one(lv.lzeq_db),
        lcpeak_db=one(lv.lcpeak_db), lzpeak_db=one(lv.lzpeak_db), lafmax_db=one(lv.lafmax_db),
        sel_per_cycle_db=one(lv.sel_db) - per_cycle, sel_a_per_cycle_db=one(lv.sel_a_db) - per_cycle,
        rendering=rendering, **parts)
