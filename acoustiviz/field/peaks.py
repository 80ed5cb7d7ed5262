"""Peaks and exposure of the continuous pressure at many points without a time loop.

With ``a_j = P0_j C_j`` and delays ``d_j`` (:mod:`acoustiviz.field.sources`) the pressure at a
point is a small sum of shifted copies of one observer-independent function (paper eqs 12-14)::

    p(t) = Σ_j Re[a_j Y(t - d_j)] = Σ_j (Re a_j) Yr(t - d_j) - (Im a_j) Yi(t - d_j).

The peaks of ``p`` are found in three steps:

1. **Coarse pass.** ``Yr`` and ``Yi`` are tabulated once per pulse on a fine uniform grid of step
   ``h = H / fine`` and stored by residue (``fine`` interleaved tables of step ``H``). Each delay
   is rounded to the fine grid, so that on the point's coarse grid ``t_k = d_min + k H`` every
   image reads a contiguous run of one table: ``p`` at ``t_k`` costs two multiply-adds per image,
   over each image's window, from its arrival to ``TAIL_STEPS`` coarse steps after its pulse
   ends (windows that meet are merged; far from a wall the arrivals come in separate windows and
   the stretches between them are not sampled). The rounding moves each image by at most ``h/2``
   in time (``H/512`` by default).
2. **Candidates.** Every local maximum of the coarse samples (of ``p`` for the positive peak, of
   ``-p`` for the negative one) gets a parabolic estimate of its height; those within ``margin``
   (relative to the largest coarse ``|p|``, plus the bound ``h/2 · Σ|a_j| max|Y'|`` of the
   rounding) of the best estimate are refined, best first, until no remaining estimate can beat
   the best refined value. Newton starts at the maximum of the cubic through four coarse samples.
3. **Refinement on the closed form.** A safeguarded Newton iteration on ``p'(t) = 0`` within one
   coarse step either side, with ``p``, ``p'`` and ``p''`` from the exact ``Y`` (Taylor tables of
   the exact Hertz pulse and of the half-sine, :func:`acoustiviz.core.radiation.hertz_response_table`
   and :func:`~acoustiviz.core.radiation.half_sine_response_table`, exact to about 1e-15, evaluated
   by Horner; a sampled pulse over its piecewise-linear form), to ``2e-3`` of a coarse step, the
   value then being the Newton model's (``O(step³ p''')`` from the maximum, about 1e-11 relative).
   An interval holding the start or end of an image's pulse (where ``p''`` may jump) is split
   there; each piece is searched on its own. Where the pulse starts or ends at a non-zero
   acceleration ``p'`` jumps there too, and each such breakpoint is a candidate as well (searched
   between its two coarse neighbours); where it starts and ends at zero (half-sine, Hertz) ``p`` is
   continuously differentiable there, but two maxima on either side of such a breakpoint can be
   closer than a coarse step and nearly equal (the samples then show one hump): a candidate within
   three coarse steps of a breakpoint has its bracket widened to two steps either side of it.

After a window, until the next one (or for ever after the last), every image that has arrived
is in its free decay and ``p(t) = Re[B exp(s t)]``: its extremes there are those of one damped
sinusoid, in closed form (the ends and the first two stationary points; later ones are
``exp(-π)`` smaller each), computed only when the bound ``Σ|a_j| |Y(T)| exp(Re(s) v)`` can beat
a peak found. The
exposure ``∫ p² dt`` comes from the pulse correlations of :mod:`acoustiviz.field.exposure` in the
same pass, with the geometry computed once per point. Times in s, pressures in Pa.

With many sources (a room's images, more than :data:`PULSE_TABLE_ABOVE`) the same search runs
over one window of sorted arrivals (:mod:`acoustiviz.field._peak_dense`): the table covers the
pulse only, the images' free decays past it are one running sum, a candidate is refined from the
images near its bracket, and the exposure sums the pairs further apart than the pulse as one
running sum (:func:`acoustiviz.field.exposure._exposure_sorted`): ``O(n log n + n T/H + K)`` per
point for ``n`` images and ``K`` coarse samples instead of ``O(n K)``, the same peaks to the
refinement's accuracy.

Limits: the search is not a proof. It assumes that between the pulse starts and ends ``p`` has
no two maxima within one coarse step (12 per ``min(T, a/c)`` by default) and ``p''`` changes sign
at most once per piece of a bracket; two maxima closer than that arise at a pulse's start or end
and are separated there. The tests and ``benchmarks/bench_field.py`` check it against the refined
:func:`acoustiviz.field.field_metrics` on random points of the three configurations, near the
sphere and the planes included, and on 1e6 corner points against a second search with another
coarse step (17 per ``min(T, a/c)``, delays rounded to 1/64 of it), every disagreement settled by
a dense scan of the closed form.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from .._jit import compile_for
from .._validate import ParameterError, check_points
from ..constants import P_REF
from ..core.geometry import Geometry
from ..core.medium import AIR, Medium
from ..core.radiation import pulse_response
from ._common import PeakCorrelations, PeakSampling, PeakSources, check_geometry, check_pulse, pulse_args
from ._exposure_closed import ClosedPairs, closed_tables
from ._peak_dense import _dense_kernel
from ._peak_kernels import TAIL_STEPS, _peaks_kernel
from ._peak_refine import taylor_pulse
from .exposure import PulseCorrelations, pulse_correlations
from .metrics import spl_db

__all__ = ["PeakTable", "PeakExposure", "peak_table", "fast_peaks"]

#: CPU time in s of the peak search's first compilation with its callees, quoted to the user when
#: it happens (:func:`acoustiviz._jit.compile_for`); measured by ``benchmarks/bench_startup.py``
#: (figures: ``benchmarks/results/design_timings.md``).
PEAKS_COMPILE_S = 9.0

#: Coarse samples per ``min(T, a/c)`` and fine steps per coarse step (defaults of :func:`peak_table`).
DEFAULT_SAMPLES = 12
DEFAULT_FINE = 256
#: Relative margin (of the largest coarse |p|) within which coarse local maxima are refined.
DEFAULT_MARGIN = 0.002
#: Above this many sources (a room's images) the tables cover the pulse only and the search runs
#: over the sorted arrivals (:mod:`acoustiviz.field._peak_dense`).
PULSE_TABLE_ABOVE = 64
#: Fewest points per thread when :func:`fast_peaks` chooses its number of threads.
POINTS_PER_THREAD = 1024
#: Fewest points per block when :func:`fast_peaks` reports its progress.
PROGRESS_BLOCK = 64




@dataclass(frozen=True)
class PeakTable:
    """Observer-independent tables of one pulse, sphere and geometry for :func:`fast_peaks`.

    Attributes
    ----------
    coarse_step : float
        Coarse time step H in s.
    fine : int
        Fine steps per coarse step.
    pad : int
        Fine steps of zeros before ``Y``'s start (a multiple of ``fine``).
    y_real, y_imag : (fine, K) ndarray
        ``Yr`` and ``Yi`` in m/s at ``u = (k fine + r - pad) h``, row ``r``, column ``k``.
    slope_bound : float
        ``max |Y'|`` in m/s², for the rounding bound.
    spread : float
        Delay span in s the tables cover besides the pulse: the largest difference of two images'
        delays (source separation / c), 0 when the tables cover the pulse only.
    pulse_only : bool
        The tables cover the pulse only (more than :data:`PULSE_TABLE_ABOVE` sources): each
        image's free decay past it is computed in closed form (:mod:`acoustiviz.field._peak_dense`).
    """

    coarse_step: float
    fine: int
    pad: int
    y_real: np.ndarray
    y_imag: np.ndarray
    slope_bound: float
    spread: float
    pulse_only: bool = False


@dataclass(frozen=True)
class PeakExposure:
    """Peaks, their times and the exposure of the pressure at each point.

    Attributes
    ----------
    peak_positive, peak_negative : (n,) ndarray
        Largest and smallest pressure in Pa of the continuous pressure (``peak_negative <= 0``).
    time_positive, time_negative : (n,) ndarray
        Their times in s from the start of contact.
    exposure : (n,) ndarray
        ``∫ p² dt`` in Pa²·s over all time (NaN when not asked for).
    refinements : (n,) ndarray of int
        Candidates refined on the closed form at each point (both signs).
    """

    peak_positive: np.ndarray
    peak_negative: np.ndarray
    time_positive: np.ndarray
    time_negative: np.ndarray
    exposure: np.ndarray
    refinements: np.ndarray

    @property
    def peak(self) -> np.ndarray:
        """Largest absolute pressure max |p| in Pa."""
        return np.maximum(self.peak_positive, -self.peak_negative)

    @property
    def peak_spl_db(self) -> np.ndarray:
        """Peak sound pressure level in dB re 20 µPa."""
        return spl_db(self.peak)

    @property
    def sel_db(self) -> np.ndarray:
        """Sound exposure level ``10 log10(∫p² dt / (p_ref² · 1 s))`` in dB."""
        with np.errstate(divide="ignore"):
            return 10.0 * np.log10(self.exposure / P_REF**2)


def _source_arrays(geometry: Geometry):
    """Image centres, weighted axes (the reflection weight folded into the axis), sphere centre, planes."""
    imgs = geometry.images()
    if geometry.planes:
        ppt = np.ascontiguousarray([p.point for p in geometry.planes], dtype=float)
        pnm = np.ascontiguousarray([p.normal for p in geometry.planes], dtype=float)
    else:
        ppt = np.zeros((0, 3))
        pnm = np.zeros((0, 3))
    return imgs.positions, imgs.weighted_axes, np.asarray(geometry.centre, dtype=float), ppt, pnm


def peak_table(pulse, geometry: Geometry, *, medium: Medium = AIR, samples: int = DEFAULT_SAMPLES,
               fine: int = DEFAULT_FINE) -> PeakTable:
    """Tabulate ``Y`` for :func:`fast_peaks` (once per pulse, sphere and geometry).

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse (m/s²) starting at t = 0.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images (their separation sets the table's length).
    medium : Medium
        The fluid.
    samples : int
        Coarse samples per ``min(T, a/c)`` (>= 2).
    fine : int
        Fine steps per coarse step (>= 1): the delays are rounded to ``H / fine``.

    Returns
    -------
    PeakTable
    """
    check_pulse(pulse)
    check_geometry(geometry)
    if int(samples) != samples or samples < 2:
        raise ParameterError("samples", f"must be an integer >= 2, got {samples}")
    if int(fine) != fine or fine < 1:
        raise ParameterError("fine", f"must be an integer >= 1, got {fine}")
    samples, fine = int(samples), int(fine)
    pa = pulse_args(pulse, geometry.radius, medium)
    end = float(pulse.duration) if pa.kind == 0 else float(pa.xi[-1])
    big_h = min(float(pulse.duration), geometry.radius / medium.c) / samples
    h = big_h / fine
    pos = geometry.images().positions
    pulse_only = pos.shape[0] > PULSE_TABLE_ABOVE
    if pulse_only:  # the pulse only: each image's decay past it is computed in closed form
        spread = 0.0
        pad = 2 * fine
        ncol = pad // fine + int(math.ceil(end / big_h)) + 4
    else:
        spread = float(np.max(np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1))) / medium.c
        pad = (int(math.ceil(spread / h)) + 2 * fine) // fine * fine
        ncol = pad // fine + int(math.ceil((spread + end) / big_h)) + 4 + TAIL_STEPS
    u = (np.arange(ncol)[None, :] * fine + np.arange(fine)[:, None] - pad) * h
    y = pulse_response(pulse, u, radius=geometry.radius, medium=medium)
    # max |Y'| = max |s Y + A|: bounded by the samples plus one fine step of |Y''| <= |s| max|Y'| + max|A'|
    flat = np.abs(np.diff(y.T.ravel())) / h
    slope = float(flat.max()) * (1.0 + abs(pa.s) * h) + 1e-300
    return PeakTable(big_h, fine, pad, np.ascontiguousarray(y.real), np.ascontiguousarray(y.imag), slope, spread,
                     pulse_only)


def fast_peaks(pulse, points, geometry: Geometry, *, medium: Medium = AIR, exposure: bool = True,
               table: PeakTable | None = None, correlations: PulseCorrelations | None = None,
               margin: float = DEFAULT_MARGIN, chunk: int = 65536, workers: int | None = None,
               progress=None) -> PeakExposure:
    """Positive and negative peak pressure (and exposure) of the continuous pressure, without a time loop.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere (m/s²) starting at t = 0.
    points : (n, 3) array_like
        Observer positions in m; points outside the fluid get NaN.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    exposure : bool
        Also return ``∫ p² dt`` (Pa²·s) of the whole response (:func:`acoustiviz.field.exposure`).
    table : PeakTable, optional
        From :func:`peak_table` for this pulse, sphere and geometry, to reuse between calls.
    correlations : PulseCorrelations, optional
        From :func:`acoustiviz.field.pulse_correlations`, to reuse between calls.
    margin : float
        Coarse local maxima whose parabolic estimate is within ``margin`` times the largest coarse
        ``|p|`` (plus the rounding bound) of the best are refined on the closed form.
    chunk : int
        Points per block.
    workers : int, optional
        Threads sharing the points (the kernels run without Python's lock); each point's result is
        the same whatever the number. Default: one per CPU this process may use, at most one per
        :data:`POINTS_PER_THREAD` points.
    progress : callable, optional
        Called as ``progress(done, total)`` in the calling thread each time a block of points is
        finished (the points done so far and all points); the blocks are then at most about 1 % of
        the points.

    Returns
    -------
    PeakExposure

    Notes
    -----
    Paper eqs 12-14; see the module notes. The peaks are those of the continuous pressure over all
    time (as :func:`acoustiviz.field.field_metrics` with its default window and refinement), to
    about 1e-11 relative; each point costs a coarse pass of about ``(T + 2 a/c)/H`` samples per
    window of arrivals (one window unless a wall is far) of two multiply-adds per image, and a few
    Newton steps on the closed form.
    """
    check_pulse(pulse)
    check_geometry(geometry)
    pts = check_points("points", points)
    if not (margin >= 0.0 and math.isfinite(margin)):
        raise ParameterError("margin", f"must be a finite number >= 0, got {margin}")
    threads = _threads(workers, pts.shape[0])
    if table is None and correlations is None:
        # the observer-independent tables, built once per pulse, geometry and medium
        tb, tp, cargs, lag_terms, cusps, sources = _observer_tables(_Keyed(pulse), _Keyed(geometry), _Keyed(medium),
                                                         bool(exposure))
    else:
        tb, tp, cargs, lag_terms, cusps, sources = _build_tables(pulse, geometry, medium, bool(exposure), table,
                                                                 correlations)
    spos, saxis, centre, ppt, pnm = sources
    n = pts.shape[0]
    if tb.pulse_only and lag_terms.size:  # the exponentials of the half-sine's closed-form exposure
        exp_tables = closed_tables(float(cargs[0]), complex(cargs[1]))
    else:
        exp_tables = (np.zeros(1, complex), np.zeros(1, complex))
    res = np.empty((n, 6))
    step = max(1, int(chunk))
    if threads > 1:  # a few blocks per thread: the points' costs differ (inside the sphere: none)
        step = min(step, max(1, -(-n // (4 * threads))))
    if progress is not None:  # about a hundred reports
        step = min(step, max(PROGRESS_BLOCK, -(-n // 100)))
    src = PeakSources(spos, saxis, centre, ppt, pnm, float(geometry.radius), float(medium.rho), float(medium.c))
    smp = PeakSampling(tb.coarse_step, tb.fine, tb.pad, tb.y_real, tb.y_imag, tb.slope_bound, float(margin), cusps)
    corr = PeakCorrelations(bool(exposure), *cargs)
    if tb.pulse_only:  # the half-sine's exposure in closed form (lag_terms), others by the table
        kernel = _dense_kernel
        tail = (src, smp, tp, corr, ClosedPairs(lag_terms, *exp_tables))
    else:
        kernel = _peaks_kernel
        tail = (src, smp, tp, corr)
    blocks = [(res[lo:min(lo + step, n)], np.ascontiguousarray(pts[lo:min(lo + step, n)])) + tail
              for lo in range(0, n, step)]
    if blocks:  # say so once if the peak search's kernels are compiled now
        compile_for(kernel, blocks[0], "peak-search", PEAKS_COMPILE_S)
    _run_blocks(kernel, blocks, threads, progress, n)
    # the columns are views of the kernel's output (no second copy of the result)
    return PeakExposure(res[:, 0], res[:, 1], res[:, 2], res[:, 3], res[:, 4], res[:, 5].astype(np.int64))


def _run_blocks(kernel, blocks: list, threads: int, progress, n: int) -> None:
    """Run ``kernel`` on each block of arguments (its first: the block's rows of the result), on ``threads``.

    ``progress(done, n)`` after each block, in the calling thread; interrupted, the blocks not
    started are dropped and the running ones finish.
    """
    done = 0
    if threads > 1 and len(blocks) > 1:
        pool = ThreadPoolExecutor(max_workers=threads)
        try:
            for args, job in [(args, pool.submit(kernel, *args)) for args in blocks]:
                job.result()
                done += args[0].shape[0]
                if progress is not None:
                    progress(done, n)
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
        return
    for args in blocks:
        kernel(*args)
        done += args[0].shape[0]
        if progress is not None:
            progress(done, n)


def _threads(workers, n: int) -> int:
    """The number of threads of :func:`fast_peaks` for ``n`` points (``workers``: asked for, or None)."""
    if workers is None:
        try:
            cpus = len(os.sched_getaffinity(0))
        except (AttributeError, OSError):  # not on every platform
            cpus = os.cpu_count() or 1
        return max(1, min(cpus, n // POINTS_PER_THREAD))
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ParameterError("workers", f"must be an integer >= 1 or None, got {workers!r}")
    return workers


def _build_tables(pulse, geometry: Geometry, medium: Medium, exposure: bool, table=None, correlations=None):
    """What :func:`fast_peaks` needs besides the points: peak table, Taylor pulse, correlations, sources."""
    tb = peak_table(pulse, geometry, medium=medium) if table is None else table
    # the refinement evaluates Y, Y' and Y'' of every pulse from its Taylor table
    tp = taylor_pulse(pulse, geometry.radius, medium)
    end = tp.end
    if exposure:
        corr = pulse_correlations(pulse, geometry.radius, medium=medium) if correlations is None else correlations
        cargs = (corr.duration, corr.pole, corr.step, corr.table, corr.y_end, corr.m_g, corr.m_h)
        lag_terms = np.ascontiguousarray(corr.lag_terms, dtype=complex)
    else:
        cargs = (1.0, complex(tp.sr, tp.si), 1.0, np.zeros((2, 4), complex), 0j, 0j, 0j)
        lag_terms = np.zeros(0, complex)
    # p' jumps at an image's pulse start or end only where A does not vanish there: only then can a
    # maximum narrower than a coarse step sit at such a breakpoint (else p is C¹ and p'' bounded)
    a_scale = float(np.max(np.abs(pulse.acceleration(np.linspace(0.0, end, 257)))))
    cusps = bool(np.max(np.abs(pulse.acceleration(np.array([0.0, end])))) > 1e-9 * a_scale)
    return tb, tp, cargs, lag_terms, cusps, _source_arrays(geometry)


def _value_key(obj):
    """A hashable key equal for equal values: the object, or its fields with arrays as bytes."""
    try:
        hash(obj)
        return obj
    except TypeError:
        if isinstance(obj, np.ndarray):
            return (obj.dtype.str, obj.shape, obj.tobytes())
        if dataclasses.is_dataclass(obj):
            return (type(obj), *(_value_key(getattr(obj, f.name)) for f in dataclasses.fields(obj)))
        raise


class _Keyed:
    """An argument of :func:`_observer_tables`, hashed and compared by value (:func:`_value_key`)."""

    __slots__ = ("obj", "key")

    def __init__(self, obj):
        self.obj = obj
        self.key = _value_key(obj)

    def __hash__(self):
        return hash(self.key)

    def __eq__(self, other):
        return isinstance(other, _Keyed) and type(self.key) is type(other.key) and self.key == other.key


@functools.lru_cache(maxsize=16)
def _observer_tables(pulse: _Keyed, geometry: _Keyed, medium: _Keyed, exposure: bool):
    """:func:`_build_tables` kept for the last 16 pulse, geometry and medium values (read, never written)."""
    return _build_tables(pulse.obj, geometry.obj, medium.obj, exposure)
