"""The noise the damper makes in operation, for the front ends: tables, WAV files, design maps.

The physics (the steady click train of each attractor rendered at a listener and its weighted
levels) is :mod:`acoustiviz.sound.operating`; this module fills the frequency-response rows with
it, marks the worst case and writes the scene's CSV and WAV.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass

import numpy as np

from ..constants import PAPER_RADIUS, WAV_RATE
from ..core.listener import Listener
from ..core.signal import Signal
from ..dynamics import DamperModel
from ..sound.operating import (
    F_SETTLE,
    NOISE_COLUMNS,
    NOISE_RATE,
    OperatingNoise,
    default_listener,
    noise_statement,
    operating_noise,
)

__all__ = ["NOISE_RATE", "F_SETTLE", "NOISE_COLUMNS", "OperatingNoise", "operating_noise", "default_listener",
           "mark_worst_case", "check_listener", "add_operating_noise", "write_operating_wav", "DesignMap", "design_map",
           "noise_statement", "write_noise_csv"]

def mark_worst_case(rows: list) -> None:
    """Fill ``worst_case`` of ``rows``: per frequency, the attractor of largest amplitude and of largest LCpeak."""
    by_f: dict = {}
    for row in rows:
        by_f.setdefault(row["frequency_hz"], []).append(row)
    for group in by_f.values():
        marks = {id(r): [] for r in group}
        for key, label in (("amplitude_m", "amplitude"), ("lcpeak_db", "lcpeak")):
            vals = [(r[key], r) for r in group if r.get(key) is not None and not math.isnan(r[key])]
            if vals:
                marks[id(max(vals, key=lambda t: t[0])[1])].append(label)
        for r in group:
            r["worst_case"] = "+".join(marks[id(r)])


def check_listener(model, listener=None, *, config: str = "plane", radius: float = PAPER_RADIUS,
                   name: str = "--listener", settings=None, positions=None,
                   positions_name: str = "positions[{k}]") -> np.ndarray:
    """Check (before any run) that ``listener`` (m) lies outside the cavity's sphere and above its surfaces.

    ``model`` a :class:`~acoustiviz.dynamics.DamperModel`, or a :class:`~acoustiviz.dynamics.MultiBallModel`
    whose cavities are placed at ``positions`` (errors naming ``positions_name``) and the listener kept out
    of every column of balls (:func:`acoustiviz.sound.balls_sound.check_ball_scene`).
    """
    from ..dynamics import MultiBallModel
    from ..sound import check_listeners
    from .wav import cavity

    pts = default_listener(radius) if listener is None else np.asarray(listener, dtype=float)
    if isinstance(model, MultiBallModel):
        from ..sound.balls_sound import check_ball_scene

        room = cavity(config, radius, model.cavities[0].gap, **(settings or {}))
        return check_ball_scene(model, room, pts, positions, name=name, positions_name=positions_name)[2][0]
    return check_listeners(pts, cavity(config, radius, model.gap, **(settings or {})), name=name)[0]


def add_operating_noise(rows: list, steady_states, *, positions=None, **kwargs) -> list:
    """Fill the level columns of ``rows`` (one per attractor, :data:`acoustiviz.app.forced.FORCED_CSV_COLUMNS`).

    ``steady_states`` holds the :class:`~acoustiviz.dynamics.forced.SteadyState` of each row. Rows of
    failed runs keep empty levels; the worst case per frequency is marked again with the levels.
    Returns the :class:`OperatingNoise` list (None where failed); ``**kwargs`` go to :func:`operating_noise`,
    or for several balls (a :class:`~acoustiviz.dynamics.MultiBallModel`), with the cavities' offsets
    ``positions`` in m, to :func:`acoustiviz.sound.balls_operating.balls_operating_noise`.
    """
    from ..dynamics import MultiBallModel
    from ..sound.balls_operating import balls_operating_noise

    noises = []
    for row, r in zip(rows, steady_states, strict=True):
        nz = None
        if r.success:
            several = isinstance(r.model, MultiBallModel)
            nz = balls_operating_noise(r, positions=positions, **kwargs) if several else operating_noise(r, **kwargs)
        if nz is not None:
            row.update(nz.levels())
        noises.append(nz)
    mark_worst_case(rows)
    return noises


def write_operating_wav(noises, path, *, sample_rate: int = WAV_RATE, listener=None, radius: float = PAPER_RADIUS):
    """One WAV (and JSON sidecar) of the damper in operation: each frequency's interval in turn.

    Each train is rendered again at ``sample_rate`` Hz when its levels were taken at another rate.
    Returns the written record list of :func:`acoustiviz.app.wav.write_wav_files`.
    """
    from .wav import WavFile, write_wav_files

    ok = [n for n in noises if n is not None]
    parts = [n.interval_pressure(sample_rate) for n in ok]
    pressure = np.concatenate(parts) if parts else np.zeros(1)
    pts = default_listener(radius) if listener is None else np.asarray(listener, dtype=float)
    wav = WavFile(path, Signal(pressure, sample_rate), [Listener("listener1", pts)], ["mono"])
    from ..sound.synthesis import band_limit

    # the levels' rendering (at its own rate) re-rendered at the file's rate: its band limit is the file's
    rendering = {k: v for k, v in ok[0].rendering.items() if k not in ("levels", "internal_rate_hz")} if ok else {}
    rendering["band_limit"] = band_limit(sample_rate)
    rendering["operating_sequence"] = [{"frequency_hz": n.frequency_hz, "duration_s": n.duration,
                                        "laeq_db": n.laeq_db, "lafmax_db": n.lafmax_db, "lcpeak_db": n.lcpeak_db}
                                       for n in ok]
    return write_wav_files([wav], rendering=rendering,
                           radius_source="default: the paper's sphere")


@dataclass(frozen=True)
class DesignMap:
    """Amplitude reduction and operating noise over impact mass and gap at one forcing.

    Attributes
    ----------
    masses, gaps : ndarray
        Impact masses in kg and gaps in m (the axes).
    reduction_db : ndarray
        ``(n_mass, n_gap)`` amplitude reduction in dB (positive: the damper helps).
    laeq_db : ndarray
        ``(n_mass, n_gap)`` LAeq of the click train at the listener in dB re 20 µPa (-inf: no impacts).
    lzeq_db : ndarray
        The same unweighted (Leq).
    lafmax_db, lcpeak_db : ndarray
        LAFmax and LCpeak in dB re 20 µPa.
    regime : ndarray of str
        ``(n_mass, n_gap)`` regimes.
    """

    masses: np.ndarray
    gaps: np.ndarray
    reduction_db: np.ndarray
    laeq_db: np.ndarray
    lzeq_db: np.ndarray
    lafmax_db: np.ndarray
    lcpeak_db: np.ndarray
    regime: np.ndarray


def design_map(model: DamperModel, masses, gaps, frequency: float, amplitude: float, *, kind: str = "force",
               listener=None, config: str = "plane", radius: float = PAPER_RADIUS, seconds: float = 1.0,
               **kwargs) -> DesignMap:
    """Amplitude reduction against operating noise (LAeq) over impact mass (kg) and gap (m).

    Each design runs from the linear start at ``frequency`` Hz to its steady state
    (:func:`acoustiviz.dynamics.forced.steady_state`, ``**kwargs``) and its click train is
    rendered at ``listener`` (:func:`operating_noise`, 96 kHz, at least ``seconds`` s) by a
    sphere of ``radius`` m (held fixed as the mass changes: the mass enters through the Hertz
    contact and the impact speeds).
    """
    from dataclasses import replace

    from ..dynamics.forced import Excitation, steady_state

    masses = np.atleast_1d(np.asarray(masses, dtype=float))
    gaps = np.atleast_1d(np.asarray(gaps, dtype=float))
    red = np.full((masses.size, gaps.size), np.nan)
    lv = {c: np.full_like(red, np.nan) for c in ("laeq_db", "lzeq_db", "lafmax_db", "lcpeak_db")}
    reg = np.empty(red.shape, dtype=object)
    ex = Excitation(frequency, amplitude, kind)
    for i, m in enumerate(masses):
        for j, g in enumerate(gaps):
            r = steady_state(replace(model, m=float(m), gap=float(g)), ex, **kwargs)
            reg[i, j] = r.regime if r.success else "failed"
            if r.success:
                red[i, j] = r.reduction_db
                nz = operating_noise(r, listener=listener, kind=config, radius=radius, seconds=seconds)
                for c, a in lv.items():
                    a[i, j] = getattr(nz, c)
    return DesignMap(masses, gaps, red, regime=reg, **lv)


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, (float, np.floating)):
        from ..output.tables import csv_number

        return csv_number(v, ".10g")
    return str(v)


def write_noise_csv(path, steady_states, noises):
    """Write the levels of each attractor (``frequency_hz, regime, impacts_per_cycle`` and :data:`NOISE_COLUMNS`).

    ``noises`` holds the :class:`OperatingNoise` of each of ``steady_states`` (None: its run failed, the
    levels left empty). Written atomically; returns the path.
    """
    from ..files import write_text_atomic

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(("frequency_hz", "regime", "impacts_per_cycle", *NOISE_COLUMNS))
    for r, n in zip(steady_states, noises, strict=True):
        levels = n.levels() if n is not None else {}
        w.writerow([_cell(v) for v in (r.excitation.frequency, r.regime, r.impacts_per_cycle,
                                       *(levels.get(c) for c in NOISE_COLUMNS))])
    return write_text_atomic(path, buf.getvalue())
