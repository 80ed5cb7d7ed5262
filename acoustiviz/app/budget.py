"""Work bounded before it starts: the memory and output size of a command, estimated up front.

Each estimate counts the arrays a command will hold (time samples x observers x image sources,
grid points x times, frames x pixels, designs x samples) and the bytes of the files it will
write, from the settings alone and without allocating anything. :func:`check_budget` refuses an
estimate above the cap (:data:`acoustiviz.constants.MAX_MEMORY_MB`, 2048 MB, raised or lowered
with ``--max-memory`` on the command line), naming the option whose value set the size, the
estimate and the cap. The estimates are upper bounds within a small factor, not exact counts.

Examples
--------
>>> est = Estimate(memory=3e12, output=0.0, what="1.8e+11 angles", options=("--step",))
>>> try:
...     check_budget(est)
... except ParameterError as exc:
...     print(exc.name)
--step
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

import numpy as np

from .._validate import check_positive
from ..constants import MAX_MEMORY_MB, WAV_RATE
from ..errors import ParameterError

__all__ = [
    "Estimate",
    "check_budget",
    "outer_cap",
    "design_estimate",
    "given_first",
    "memory_cap",
    "waveform_estimate",
    "directivity_estimate",
    "metric_estimate",
    "check_room_order",
    "scene_waveform_estimate",
    "scene_estimates",
    "damper_estimate",
    "wav_estimate",
    "balloon_estimate",
    "snapshot_estimate",
    "animation_estimate",
    "sweep_estimate",
    "range_count",
]

_MB = 2.0**20
_F8 = 8.0  # bytes per float64

#: A cap set around a whole command (:func:`outer_cap`): (MB, the option that sets it), or None.
_OUTER_CAP: ContextVar = ContextVar("acoustiviz_outer_cap", default=None)


@contextmanager
def outer_cap(max_memory_mb=None, cap_name: str = "--max-memory"):
    """Within this block every :func:`check_budget` and :func:`memory_cap` also keeps under ``max_memory_mb``.

    The command line's ``--max-memory`` bounds all of a command's work, that of a scene too, whose own
    cap (``grids.memory_limit_mb``) is checked with it: the smaller of the two applies and errors
    name the one that does. None: no outer cap.
    """
    if max_memory_mb is not None:
        max_memory_mb = check_positive(cap_name, max_memory_mb, "MB")
    token = _OUTER_CAP.set(None if max_memory_mb is None else (float(max_memory_mb), cap_name))
    try:
        yield
    finally:
        _OUTER_CAP.reset(token)


def _cap(max_memory_mb, cap_name: str) -> tuple:
    """The cap in MB that applies and the option or key that sets it (:func:`outer_cap` included)."""
    cap = MAX_MEMORY_MB if max_memory_mb is None else check_positive(cap_name, max_memory_mb, "MB")
    outer = _OUTER_CAP.get()
    if outer is not None and (outer[0] < cap or max_memory_mb is None):
        return outer
    return cap, cap_name


@dataclass(frozen=True)
class Estimate:
    """Memory and output size of a piece of work.

    Attributes
    ----------
    memory : float
        Working memory in bytes (``inf`` when the settings give no finite size).
    output : float
        Bytes of the files written.
    what : str
        What sets the size, in the user's terms (``"3.2e+09 time samples"``).
    options : tuple of str
        The options or scene keys that set the size; the first names the error.
    """

    memory: float
    output: float
    what: str
    options: tuple

    def __add__(self, other: Estimate) -> Estimate:
        return Estimate(max(self.memory, other.memory), self.output + other.output,
                        f"{self.what}; {other.what}", tuple(dict.fromkeys(self.options + other.options)))


def _mb(nbytes: float) -> str:
    if not math.isfinite(nbytes):
        return "an unbounded amount"
    mb = nbytes / _MB
    return f"{mb:,.0f} MB" if 1.0 <= mb < 1e7 else f"{mb:.3g} MB"


def given_first(options, given=()) -> tuple:
    """``options`` with those in ``given`` (the options the user typed) first, each group in its order.

    An estimate's error is named after its first option: this way it names a setting the user
    chose (``--radius 1e-9`` making the contact short) rather than one left at its default.
    """
    given = set(given or ())
    return tuple(o for o in options if o in given) + tuple(o for o in options if o not in given)


def check_budget(estimate: Estimate, max_memory_mb=None, *, cap_name: str = "--max-memory") -> Estimate:
    """Refuse ``estimate`` when its memory or its output exceeds the cap; return it otherwise.

    Parameters
    ----------
    estimate : Estimate
        The work about to start.
    max_memory_mb : float, optional
        Cap in MB (default :data:`~acoustiviz.constants.MAX_MEMORY_MB`); applies to working
        memory and, separately, to the bytes written.
    cap_name : str
        The option or scene key that sets the cap (named in errors about it).

    Raises
    ------
    ParameterError
        Named after the first option of ``estimate``, with the estimate, the cap and what to change.
    """
    cap, cap_name = _cap(max_memory_mb, cap_name)
    limit = cap * _MB
    for amount, noun in ((estimate.memory, "of memory"), (estimate.output, "of output files")):
        if not (amount <= limit):  # also refuses NaN and inf
            others = " or ".join(estimate.options[1:])
            change = f"change it{' (or ' + others + ')' if others else ''}"
            raise ParameterError(
                estimate.options[0],
                f"this would need {_mb(amount)} {noun} for {estimate.what}, over the cap of {cap:g} MB; "
                f"{change}, or raise the cap with {cap_name}")
    return estimate


def memory_cap(max_memory_mb=None) -> float:
    """The cap in bytes (``max_memory_mb`` MB, default :data:`~acoustiviz.constants.MAX_MEMORY_MB`).

    Under :func:`outer_cap`, at most its cap.
    """
    outer = _OUTER_CAP.get()
    cap = MAX_MEMORY_MB if max_memory_mb is None else float(max_memory_mb)
    if outer is not None:
        cap = outer[0] if max_memory_mb is None else min(cap, outer[0])
    return cap * _MB


def _div(a: float, b: float) -> float:
    """A / b, with a division by zero (an underflowed denominator) counting as unbounded."""
    return a / b if b != 0 else math.inf


def _count(x: float) -> float:
    """A count that may be huge or not finite, as a float (never an OverflowError)."""
    return x if math.isfinite(x) and x >= 0 else math.inf


def _image_count(geometry) -> int:
    """The sources of ``geometry``: a room counts its images without building them."""
    n = getattr(geometry, "image_count", None)
    return int(n) if n is not None else len(geometry.images())


def _room_end(pulses, geometry, medium):
    """A bound in s on the end of a room's sound without its window, from its order alone; None elsewhere.

    The farthest image of the room's order (:func:`acoustiviz.core.reverberation._shell_upper_distance`,
    the bound its order is chosen with) plus the longest pulse and 40 decay times a/c, as
    :func:`acoustiviz.field.waveform_span` ends the sound, without building its millions of images.
    """
    if getattr(geometry, "image_order", None) is None:
        return None
    from ..core.reverberation import _shell_upper_distance

    reach = float(_shell_upper_distance(geometry.shoebox, np.float64(geometry.image_order)))
    return reach / medium.c + max(p.duration for p in pulses) + 40.0 * geometry.radius / medium.c


def waveform_estimate(pulses, point, geometry, medium, samples_per_duration,
                      options=("--samples-per-duration", "--distance"), *, window=None) -> Estimate:
    """Time samples of :func:`acoustiviz.app.views.waveform_times` and the CSV of them.

    Memory: times, pressure and per-image temporaries (8 B each per sample) of up to four images
    (beyond them, the compiled uniform-grid kernel holds none), and the geometry the evaluator holds
    per image of the observer (:func:`acoustiviz.field._common.geometry_bytes`: delays, weights,
    distances, 72 B each, which a room's millions of images make the larger part); CSV: about 38 B a
    row (two ``%.12e`` numbers). ``window``: the end in s of the times (a room's window) instead of
    the end of the sound.
    """
    from ..field import waveform_span
    from ..field._common import geometry_bytes

    with np.errstate(all="ignore"):
        end = window if window is not None else _room_end(pulses, geometry, medium)
        if end is None:
            end = max(waveform_span(p, point, geometry, medium=medium)[1] for p in pulses)
        dt = min(p.duration for p in pulses) / float(samples_per_duration)
        n = _count(_div(end, dt) + 2.0)
    nimg = _image_count(geometry)
    memory = _F8 * n * (4 + min(nimg, 4)) * len(pulses) + geometry_bytes(nimg)
    what = f"{n:.3g} time samples" + (f" of {nimg:.3g} images" if nimg > 4 else "")
    return Estimate(memory, 38.0 * n * len(pulses), what, options)


def directivity_estimate(geometry, step_deg: float, options=("--step",), *, pulse=None, medium=None,
                         window_options=("--wall-distance",)) -> Estimate:
    """Angles of :func:`acoustiviz.app.views.directivity_angles`; per angle its point, geometry and metrics.

    Given the ``pulse`` and ``medium``, also the window of samples the RMS takes at every angle:
    from the first arrival to the last image's pulse and decay, sampled at
    :func:`acoustiviz.field.default_sample_interval` (a far wall makes it long; the error is then
    named after ``window_options``).
    """
    top = geometry.polar_limit_deg
    with np.errstate(all="ignore"):
        n = _count(_div(top, float(step_deg)) + 2.0)
    pos = np.asarray(geometry.images().positions, dtype=float)
    per = _F8 * (3 + 12 + 9 * len(pos))
    est = Estimate(per * n, 60.0 * n, f"{n:.3g} angles", options)
    if pulse is None or medium is None:
        return est
    from ..field import default_sample_interval

    reach = getattr(geometry, "duration", None)  # a room: the window its images reach
    with np.errstate(all="ignore"):
        if reach is not None:
            window = float(reach)
        else:  # the largest distance between two sources (bounded by twice the farthest from the real one)
            spread = (float(np.max(np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1))) if len(pos) <= 64
                      else 2.0 * float(np.max(np.linalg.norm(pos - pos[0], axis=1)))) / medium.c
            window = spread + float(pulse.duration) + 40.0 * geometry.radius / medium.c
        m = _count(_div(window, default_sample_interval(pulse, geometry.radius, medium=medium)))
    if _F8 * m <= est.memory:
        return est
    return Estimate(est.memory + _F8 * m, est.output, f"{n:.3g} angles and a window of {m:.3g} samples",
                    tuple(window_options) + tuple(options))


def window_estimate(pulse, radius: float, medium, window: float, samples_per_duration: int,
                    options=("--duration",)) -> Estimate:
    """The time grid alone of a waveform over a room's ``window`` (s): a floor of :func:`waveform_estimate`.

    It counts the samples of ``window`` at ``samples_per_duration`` per contact duration of ``pulse``
    as for a single source (the real sphere, no image), so it needs neither the room's image order
    nor its images: a window too long for any memory is refused before the order is sought.
    """
    from ..core.geometry import geometry

    return waveform_estimate([pulse], np.zeros(3), geometry("free", radius), medium, samples_per_duration,
                             options=options, window=window)


def scene_waveform_estimate(scene, geometry):
    """The memory of a scene's ``[outputs.waveform]``: the largest listener's table, as the run samples it.

    Each listener's times run to the room's window (``configuration.window_s``) or, without one, to
    the end of its sound, at the default samples per contact duration
    (:func:`waveform_estimate`); an error names the window's key in a room,
    else the listener.
    """
    from .settings.impact import WAVEFORM

    kinds = scene.output("waveform")["pulses"] or [scene.section("contact")["pulse"]]
    pulses = [scene.pulse(kind=k) for k in kinds]
    window = getattr(geometry, "duration", None)
    room = getattr(geometry, "image_order", None) is not None
    estimates = [waveform_estimate(pulses, np.asarray(pos, dtype=float), geometry, scene.medium(), WAVEFORM[0].default,
                                   options=("configuration.window_s",) if room else (f"listeners[{i}]",),
                                   window=window)
                 for i, (_, pos) in enumerate(scene.listeners())]
    worst = max(estimates, key=lambda e: e.memory)
    if room and window is None:
        from dataclasses import replace

        worst = replace(worst, what=f"{worst.what}, to the end of the sound of every image (no window_s set)")
    return worst


def scene_estimates(scene, geometry) -> list:
    """What a scene's waveform and weighted directivity hold, as callables checked in turn at its load.

    The waveform's tables (:func:`scene_waveform_estimate`) and, for a directivity of a weighted
    level (``outputs.directivity.metric``), the sound at every angle (:func:`metric_estimate`), on the
    circle through the first listener, as the run computes it. They follow the angles' estimate,
    which bounds the number of points first.
    """
    out = [lambda: scene_waveform_estimate(scene, geometry)] if scene.wants("waveform") else []
    metric = scene.data["outputs"]["directivity"].get("metric", "peak-spl") if scene.wants("directivity") else None
    if metric not in (None, "peak-spl", "rms"):
        def directivity_metric():
            from ..field import circle_points
            from .views import directivity_angles

            (_, pos), *_ = scene.listeners()
            angles = directivity_angles(geometry, scene.data["outputs"]["directivity"]["step_deg"])
            points = circle_points(geometry, float(np.linalg.norm(np.asarray(pos) - geometry.centre)), angles)
            return metric_estimate(scene.pulse(), points, geometry, scene.medium(), metric,
                                   options=("outputs.directivity.step_deg", "outputs.directivity.metric"))
        out.append(directivity_metric)
    return out


def metric_estimate(pulse, points, geometry, medium, metric: str, options=("--step", "--distance")) -> Estimate:
    """A weighted level (``metric``) at ``points``, all at once, as ``points_metric_levels`` computes it.

    Every point's sound (:func:`acoustiviz.sound.impact_levels.points_metric_levels`) is evaluated in
    closed form at the oversampled times of
    :func:`acoustiviz.sound.impact_levels.sound_samples` (8 B each) and decimated by an FFT convolution,
    which holds about four more arrays of that size (its padded input, spectrum, product and
    output); the evaluator adds its geometry for one point (72 B per image). The points must be
    few enough to list (the angles' estimate is checked first).
    """
    from ..field._common import geometry_bytes
    from ..sound.impact_levels import sound_samples

    k = int(np.asarray(points).reshape(-1, 3).shape[0])
    m = float(sound_samples(pulse, points, geometry, medium))
    nimg = _image_count(geometry)
    return Estimate(5.0 * _F8 * k * m + geometry_bytes(nimg) + 6.0 * _F8 * m, 0.0,
                    f"{k} angles x {m:.3g} oversampled samples of the sound each ({metric})", options)


#: A budget in MB no machine has: the order a room's tolerance alone asks for.
_UNCAPPED_MB = 1e9


def check_room_order(geometry, max_memory_mb=None, *, window_option: str = "--duration",
                     cap_name: str = "--max-memory") -> None:
    """Refuse a room whose image order the memory budget cut before its tolerance was met.

    Such a room leaves out more of the energy than its ``tolerance_db`` allows (a rigid room over a
    long window: more than it keeps). The error is named after ``cap_name`` and says what the
    tolerance would take: the order, the images and the budget in MB that builds them
    (:func:`acoustiviz.core.room.max_order_for_memory`), and the settings that shrink the need. A
    room whose order was given (``--image-order``) is the user's choice and passes.
    """
    if not getattr(geometry, "order_capped", False):
        return
    from dataclasses import replace

    from ..core.room import _image_bytes

    full = replace(geometry, max_memory_mb=_UNCAPPED_MB)  # the same room, its order set by the tolerance alone
    need = _image_bytes(full.image_order, None) / 1e6  # MB as the order's cap counts them
    cap = MAX_MEMORY_MB if max_memory_mb is None else float(max_memory_mb)
    lost = geometry.neglected_energy_db
    lost = f"{lost:+.1f} dB" if math.isfinite(lost) else "an unbounded part of it"
    where = ("this room" if geometry.duration is None
             else f"a {geometry.duration:g} s window ({window_option}) in this room")
    raise ParameterError(
        cap_name, f"{where} needs image order {'above ' if full.order_capped else ''}{full.image_order} "
                  f"({full.image_count:.3g} images, {math.ceil(need):,d} MB) to leave out at most "
                  f"{geometry.tolerance_db:g} dB of its energy; the cap of {cap:g} MB allows order "
                  f"{geometry.image_order}, which leaves out {lost}: raise {cap_name} "
                  f"to {math.ceil(need)}, or shorten {window_option}, raise --absorption or --tolerance-db, or "
                  "give --image-order to accept the loss")


def damper_estimate(model, duration: float, *, solver: str = "event", dt=None, per_period: int = 200,
                    options=("--duration",)) -> Estimate:
    """Samples of a damper run: ``per_period`` per main period (dense output, 6 states + energies).

    A Newmark run also steps ``duration / dt`` times; more than 1e10 steps is refused as work
    that does not end (named after ``--dt``).
    """
    period = _div(2.0 * math.pi, model.main_frequency)
    with np.errstate(all="ignore"):
        n = _count(_div(duration, period) * per_period + 1.0)
    if solver == "newmark" and dt is not None:
        with np.errstate(all="ignore"):
            steps = _count(_div(duration, dt))
        if not steps <= 1e10:
            raise ParameterError("dt", f"{steps:.3g} Newmark steps of {dt:g} s over {duration:g} s; the cap is "
                                       "1e10 steps: take a longer step or a shorter run")
    return Estimate(_F8 * 16.0 * n, 0.0, f"{n:.3g} samples of the damper's motion", options)


def wav_estimate(duration: float, sample_rate: float, channels: int, options=("--duration",)) -> Estimate:
    """A rendered sound: float64 working copy and float32 file per channel."""
    with np.errstate(all="ignore"):
        n = _count(duration * sample_rate)
    return Estimate(_F8 * 3.0 * n * channels, 4.0 * n * channels,
                    f"{n:.3g} samples x {channels} channel(s) at {sample_rate:g} Hz", options)


def grid_levels_estimate(duration: float, sample_rate: float, points: int, options=("--grid-points",)) -> Estimate:
    """The levels of a rendered sound at many points at once: five float64 per sample of each point.

    The signal, its A- and C-weighted copies and two temporaries of the level evaluators.
    """
    with np.errstate(all="ignore"):
        n = _count(duration * sample_rate)
    return Estimate(_F8 * 5.0 * n * points, 0.0, f"{n:.3g} samples x {points} point(s) at {sample_rate:g} Hz",
                    options)


def forced_estimate(n_frequencies: int, max_cycles: int, *, noise_seconds: float = 0.0,
                    analysis_rate: float = 96000.0, wav_rate: float = float(WAV_RATE), wav: bool = False,
                    names=None) -> Estimate:
    """A frequency response, and the noise in operation when ``noise_seconds`` > 0.

    The Poincare section and extrema of each run (a few floats per cycle, ``max_cycles`` at
    most), and with the noise in operation a click train per frequency of at least
    ``noise_seconds`` after a 1 s lead-in, rendered at ``analysis_rate`` with about ten filtered copies;
    a WAV of every frequency in turn at ``wav_rate``. ``names`` maps ``max_cycles``, ``frequencies``
    and ``noise_seconds`` to the option or scene key to name (default: the command line's options).
    """
    with np.errstate(all="ignore"):
        runs = _count(float(n_frequencies) * float(max_cycles) * 16.0)
        train = _count((2.0 * float(noise_seconds) + 1.0) * analysis_rate * 11.0) if noise_seconds > 0 else 0.0
        wav_n = _count(float(n_frequencies) * 2.0 * float(noise_seconds) * wav_rate) if wav else 0.0
    from .settings.base import vocabulary
    from .settings.forced import FORCED, FREQUENCIES

    names = {**vocabulary("cli", (*FORCED, FREQUENCIES)), **(names or {})}
    first = "max_cycles" if train <= runs else "noise_seconds"
    opts = (names[first], names["frequencies"])
    return Estimate(_F8 * (runs + train + 3.0 * wav_n), 4.0 * wav_n + 400.0 * n_frequencies,
                    f"{n_frequencies} frequencies, up to {max_cycles} cycles each"
                    + (f", {noise_seconds:g} s of noise each" if noise_seconds > 0 else ""), opts)


def _pixels(size) -> float:
    return float(size[0]) * float(size[1])


def balloon_estimate(n_theta: int, size, n_sources: int, options=("--resolution",)) -> Estimate:
    """A measuring sphere of ``n_theta x 2 n_theta`` nodes and one image of ``size`` pixels."""
    n = 2.0 * float(n_theta) ** 2
    mem = _F8 * n * (20 + 9 * n_sources) + 8.0 * _pixels(size)
    return Estimate(mem, 3.0 * _pixels(size), f"{n:.3g} grid points, {size[0]}x{size[1]} px", options)


def snapshot_estimate(n_u: int, n_sections: int, n_times: int, size, n_sources: int,
                      options=("--resolution", "--time")) -> Estimate:
    """Planes of ``n_u x n_u`` points at each time, and the image tiles."""
    pts = float(n_u) ** 2 * n_sections
    mem = _F8 * pts * (n_times + 6 + 9 * n_sources) + 8.0 * _pixels(size) * n_times
    return Estimate(mem, 3.0 * _pixels(size) * n_times,
                    f"{pts:.3g} grid points x {n_times} time(s), {size[0]}x{size[1]} px", options)


def animation_estimate(frames: int, n_u: int, n_sections: int, size, n_sources: int,
                       options=("--frames", "--size", "--resolution")) -> Estimate:
    """Every frame is held as an RGB image until the file is written; the field one frame at a time."""
    pts = float(n_u) ** 2 * n_sections
    frame = 3.0 * _pixels(size)
    mem = frames * frame + _F8 * pts * (8 + 9 * n_sources)
    return Estimate(mem, frames * frame, f"{frames} frames of {size[0]}x{size[1]} px", options)


def range_count(text) -> float:
    """How many values a swept setting ``VALUE``, ``START:STOP:COUNT`` or ``A,B,C`` holds, without listing them.

    Text that does not parse counts as one value (its own check reports it); a sequence counts its items.
    """
    if isinstance(text, (tuple, list)):
        return float(max(1, len(text)))
    t = str(text).strip()
    if ":" in t:
        parts = t.split(":")
        try:
            n = float(parts[-1])
        except ValueError:
            return 1.0
        return n if math.isfinite(n) and n >= 1 else 1.0
    return float(max(1, len([p for p in t.split(",") if p.strip()])))


def sweep_estimate(swept, model, duration: float, workers: int, options=("--duration",)) -> Estimate:
    """A sweep: every worker holds one design's run; the table about 1 kB per design (row and settings).

    Parameters
    ----------
    swept : mapping of str to str or sequence
        Option (or scene key) -> its text (``VALUE``, ``START:STOP:COUNT`` or ``A,B,C``) or its
        values; the designs are every combination.
    model : DamperModel
        A design, for the samples of one run.
    duration : float
        Simulated time per design in s.
    workers : int
        Designs run at once.
    """
    counts = {k: range_count(v) for k, v in swept.items() if v is not None}
    n = math.prod(counts.values()) if counts else 1.0
    one = damper_estimate(model, duration, options=options)
    biggest = max(counts, key=counts.get) if counts else options[0]
    opts = tuple(dict.fromkeys((biggest,) + tuple(options))) if n * 1024.0 > one.memory * workers else options
    return Estimate(one.memory * max(1, int(workers)) + 1024.0 * n, 400.0 * n,
                    f"{n:.3g} designs, {one.what} each, {workers} worker(s)", opts)


def design_estimate(path, options=("--sweep",)) -> Estimate:
    """Reading a sweep's table at ``path`` (its ``sweep.csv``): the text and its parsed rows, about 4 x its size.

    A table that is missing or unreadable counts as empty (its reader names it).
    """
    import os

    try:
        size = float(os.path.getsize(path))
    except OSError:
        size = 0.0
    return Estimate(4.0 * size + 1.0, 0.0, f"a sweep table of {size:,.0f} B", tuple(options))
