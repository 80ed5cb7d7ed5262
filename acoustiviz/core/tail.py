"""The statistical late tail of a shoebox room's image sum: band splits, decay laws, where it ends.

After the mixing time the image sum's arrivals are dense and their signs and delays effectively
random; :func:`late_tail` samples that part of the room's impulse response as Gaussian noise
whose expected energy follows the image sum's (or Eyring's) decay per band, from a seeded
generator. :func:`tail_end` says how long it must run for an energy tolerance, :func:`band_masks`
splits a spectrum into bands that add back to it.

References
----------
C. F. Eyring, "Reverberation time in 'dead' rooms", J. Acoust. Soc. Am. 1(2A), 217-241 (1930).
H. Kuttruff, *Room Acoustics*, 6th ed., CRC Press (2017), ch. 4 and 5.
J.-M. Jot, L. Cerveau and O. Warusfel, "Analysis and synthesis of room reverberation based on a
statistical time-frequency model", 103rd AES Convention, preprint 4629 (1997) (the late
reverberation as noise shaped by a decay per frequency band).
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import ParameterError, check_choice, check_positive, check_range
from .medium import AIR, Medium
from .reverberation import image_energy_decay, reverberation_time
from .room import Shoebox

__all__ = ["TAIL_DECAYS", "band_masks", "tail_decay_rate", "tail_end", "late_tail"]

#: Decay laws of the statistical tail: the image sum's own expected decay, or Eyring's per band.
TAIL_DECAYS = ("eyring", "images")
#: Nodes of the coarse time grid on which a tail's decay is evaluated before log-linear interpolation.
_DECAY_NODES = 257


def band_masks(freqs, centres, *, transition_octaves: float = 0.5) -> np.ndarray:
    """Zero-phase band-split masks ``(n_bands, n_freqs)`` that sum to one at every frequency.

    Parameters
    ----------
    freqs : (n_freqs,) array_like
        Frequencies in Hz (e.g. :func:`numpy.fft.rfftfreq`), >= 0.
    centres : (n_bands,) array_like
        Band centre frequencies in Hz, increasing, > 0.
    transition_octaves : float
        Width in octaves of each crossover (at most the distance between neighbouring edges);
        0 gives brick-wall masks.

    Returns
    -------
    ndarray
        ``M_b(f) = U_{b-1}(f) - U_b(f)`` with ``U_{-1} = 1``, ``U_{n-1} = 0`` and ``U_k`` a
        raised-sine step from 0 to 1 across the edge ``e_k = sqrt(f_k f_{k+1})`` (the geometric
        mean of neighbouring centres), over ``transition_octaves`` centred on it in ``log2 f``.
        The masks telescope: their sum is 1 (to round-off), so splitting a signal into bands and
        adding them back returns it; each lies in [0, 1] (the steps rise in turn, edge after edge).
        The lowest band reaches down to 0 Hz, the highest up to Nyquist.
    """
    f = np.asarray(freqs, dtype=float)
    c = np.asarray(centres, dtype=float).reshape(-1)
    edges = np.sqrt(c[:-1] * c[1:])
    gaps = np.diff(np.log2(c)) if c.size > 1 else np.zeros(0)
    width = np.minimum(float(transition_octaves), gaps) if gaps.size else gaps
    with np.errstate(divide="ignore"):
        lf = np.log2(np.maximum(f, 1e-300))
    steps = []
    for k, e in enumerate(edges):  # U_k: 0 below the edge, 1 above
        if width[k] <= 0:
            steps.append((f >= e).astype(float))
            continue
        x = np.clip((lf - math.log2(e)) / (0.5 * width[k]), -1.0, 1.0)
        steps.append(0.5 * (1.0 + np.sin(0.5 * np.pi * x)))
    upper = [np.ones_like(f)] + steps
    lower = steps + [np.zeros_like(f)]
    return np.stack([u - lo for u, lo in zip(upper, lower, strict=True)])


def _band_masks(freqs: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Brick-wall masks ``(n_bands, n_freqs)`` that partition the frequency axis at the geometric means."""
    return band_masks(freqs, centres, transition_octaves=0.0) > 0.5


def tail_decay_rate(room: Shoebox, start: float, times, *, decay: str = "images", medium: Medium = AIR,
                    nodes: int = _DECAY_NODES) -> np.ndarray:
    """Expected energy arrival rate in 1/(m² s) of a statistical tail from ``start`` on, per band.

    Parameters
    ----------
    room : Shoebox
        The room and its absorption.
    start : float
        Onset time in s (>= 0): the rate there is the image sum's (:func:`image_energy_decay`).
    times : array_like
        Times in s, >= ``start``.
    decay : {"images", "eyring"}
        ``"images"``: the image sum's own expected decay (:func:`image_energy_decay`);
        ``"eyring"``: ``rate(start) exp(-6 ln(10) (t - start) / T60)`` with Eyring's T60 of each
        band (:func:`reverberation_time`), the diffuse-field decay, continuing the image sum's
        level at the onset.
    medium : Medium
        The fluid.
    nodes : int
        ``"images"``: nodes of the coarse grid from ``start`` to the last time on which the
        direction average is evaluated; ``log`` of the rate (smooth and convex in t) is
        interpolated linearly between them.

    Returns
    -------
    ndarray
        Shaped like ``times`` with a trailing band axis when the absorption is banded.
    """
    check_choice("decay", decay, TAIL_DECAYS)
    t = np.asarray(times, dtype=float)
    t0 = check_range("start", start, 0.0, unit="s")
    flat = t.reshape(-1)
    if flat.size and (np.any(~np.isfinite(flat)) or flat.min() < t0):
        raise ParameterError("times", f"must be finite and >= start = {t0:g} s")
    onset = np.atleast_1d(image_energy_decay(room, [t0], medium=medium)).reshape(1, -1)
    if decay == "eyring":
        t60 = np.atleast_1d(reverberation_time(room, "eyring", medium=medium)).reshape(1, -1)
        k = 6.0 * math.log(10.0) / t60
        out = onset * np.exp(-(flat[:, None] - t0) * k)
    else:
        t1 = float(flat.max()) if flat.size else t0
        grid = np.linspace(t0, max(t1, t0 + 1e-9), int(nodes))
        lg = np.log(np.atleast_2d(image_energy_decay(room, grid, medium=medium).reshape(grid.size, -1)))
        out = np.exp(np.stack([np.interp(flat, grid, lg[:, b]) for b in range(lg.shape[1])], axis=1))
    return out.reshape(t.shape) if room.bands is None else out.reshape(*t.shape, -1)


def tail_end(room: Shoebox, start: float, tolerance_db: float = -60.0, *, decay: str = "images",
             medium: Medium = AIR) -> tuple:
    """Where a statistical tail from ``start`` may stop, and the energy it then leaves out.

    Parameters
    ----------
    room : Shoebox
        The room and its absorption.
    start : float
        Onset of the tail in s (the transition time), >= 0.
    tolerance_db : float
        Largest energy left out relative to the whole response's, in dB, in ``[-200, 0)``.
    decay : {"images", "eyring"}
        The tail's decay law (:func:`tail_decay_rate`).
    medium : Medium
        The fluid.

    Returns
    -------
    (float, float)
        The end time in s and the energy after it relative to the total, in dB, of the worst
        band. The total is the expected energy of the reverberation,
        ``int_0^start image_energy_decay + int_start^inf tail``, a lower bound of the energy at a
        receiver (the direct sound left out), so the figure is an estimate from above.

    Notes
    -----
    Both decay laws are exponential in t or decay faster than the slowest direction's
    exponential; the rate is integrated on a grid to ``start + 4 T_max`` (``T_max`` the largest
    direction-wise T60) and the rest extrapolated from the last log-slope.
    """
    tol = check_range("tolerance_db", tolerance_db, -200.0, 0.0, unit="dB", high_open=True)
    t0 = check_range("start", start, 0.0, unit="s")
    if float(np.min(room.absorption)) <= 0.0 and float(np.max(room.absorption.reshape(6, -1).min(axis=0))) <= 0.0:
        raise ParameterError("absorption", "a statistical tail needs absorption > 0 on some surface in every band")
    t60 = np.atleast_1d(reverberation_time(room, "eyring", medium=medium))
    slow = 3.0 * float(np.max(t60[np.isfinite(t60)]))  # the direction-averaged decay is slower than Eyring's
    grid = t0 + np.linspace(0.0, 4.0 * slow, 4097)
    rate = np.atleast_2d(tail_decay_rate(room, t0, grid, decay=decay, medium=medium).reshape(grid.size, -1))
    dt = grid[1] - grid[0]
    seg = 0.5 * (rate[1:] + rate[:-1]) * dt
    slope = np.log(rate[-1] / rate[-2]) / dt  # < 0
    after = np.concatenate([np.cumsum(seg[::-1], axis=0)[::-1], np.zeros((1, rate.shape[1]))], axis=0)
    after += rate[-1] / np.maximum(-slope, 1e-300)
    x, wq = np.polynomial.legendre.leggauss(16)  # the early decay is smooth: Gauss-Legendre over [0, start]
    early = 0.5 * t0 * (x + 1.0)
    e_early = 0.5 * t0 * np.tensordot(wq, np.atleast_2d(
        image_energy_decay(room, early, medium=medium).reshape(early.size, -1)), axes=(0, 0))
    total = e_early + after[0]
    ratio = (after / total).max(axis=1)
    ok = np.flatnonzero(ratio <= 10.0 ** (tol / 10.0))
    i = int(ok[0]) if ok.size else grid.size - 1
    return float(grid[i]), float(10.0 * math.log10(max(ratio[i], 1e-300)))


def late_tail(room: Shoebox, start: float, duration: float, sample_rate: float, rng: np.random.Generator, *,
              band_centres=None, medium: Medium = AIR, decay: str = "images",
              transition_octaves: float = 0.0) -> np.ndarray:
    """A statistical late tail of the image sum: Gaussian noise shaped to its expected decay.

    The image sum is an impulse response ``h(t) = sum_k (w_k / r_k) delta(t - r_k / c)``: a
    click ``p1(t)`` radiated by the source (its pressure at 1 m) is heard as ``p1 * h``. After
    the mixing time the arrivals are dense and their signs and delays effectively random; this
    returns ``h`` sampled as a noise whose expected energy per sample is the image sum's,
    ``E[h_m^2] = (dE/dt)(t_m) / sample_rate`` (:func:`image_energy_decay`), per band when the
    absorption is.

    Parameters
    ----------
    room : Shoebox
        The room and its absorption.
    start : float
        Time in s of the first sample after the emission, >= 0 (e.g. :func:`complete_until` the
        order of the images computed exactly, or :func:`mixing_time` if that is later).
    duration : float
        Length of the tail in s, > 0.
    sample_rate : float
        Samples per second, > 0.
    rng : numpy.random.Generator
        The source of randomness (seeded by the caller, so the tail is reproducible).
    band_centres : (n_bands,) array_like, optional
        Centre frequencies in Hz of the absorption's bands, increasing; required when the
        absorption is banded, unused otherwise. The white noise is split by brick-wall masks at
        the geometric means of neighbouring centres (the lowest band down to 0 Hz, the highest
        up to Nyquist), which partition its spectrum exactly, and each band follows its own decay.
    medium : Medium
        The fluid.
    decay : {"images", "eyring"}
        The decay law (:func:`tail_decay_rate`): the image sum's own expected decay (default),
        or Eyring's per band from the image sum's level at ``start``. Long tails are evaluated
        on a coarse grid and interpolated (log-linear).
    transition_octaves : float
        Width of the crossovers between bands in octaves (:func:`band_masks`); 0 (default):
        brick-wall masks at the geometric means.

    Returns
    -------
    (n,) ndarray
        ``h`` at ``start + m / sample_rate`` for ``m = 0..n-1`` with ``n = round(duration * sample_rate)``,
        in 1/m (a pressure at 1 m convolved with it gives Pa).

    Notes
    -----
    The tail's energy follows the expected energy density of the image sum itself, so where the
    exact images stop and the tail starts the two agree on average: the match at the transition
    is by construction, not by fitting. The sphere radiates like a dipole; averaged over the
    images' directions its ``cos^2 theta`` is 1/3, which the caller folds into ``p1``.
    """
    t0 = check_range("start", start, 0.0, unit="s")
    dur = check_positive("duration", duration, "s")
    fs = check_positive("sample_rate", sample_rate, "Hz")
    if not isinstance(rng, np.random.Generator):
        raise ParameterError("rng", f"expected a numpy.random.Generator (seeded), got {type(rng).__name__}")
    n = int(round(dur * fs))
    if n < 1:
        raise ParameterError("duration", f"shorter than one sample at {fs:g} Hz, got {dur:g} s")
    t = t0 + np.arange(n) / fs
    if decay == "images" and n <= 4 * _DECAY_NODES:
        rate = image_energy_decay(room, t, medium=medium)
    else:
        rate = tail_decay_rate(room, t0, t, decay=decay, medium=medium)
    noise = rng.standard_normal(n)
    if room.bands is None:
        if band_centres is not None:
            raise ParameterError("band_centres", "only for a banded absorption; this room has one value per surface")
        return np.sqrt(rate / fs) * noise
    if band_centres is None:
        raise ParameterError("band_centres", f"required: the absorption has {room.bands} bands")
    centres = np.asarray(band_centres, dtype=float).reshape(-1)
    if centres.size != room.bands or not np.all(np.isfinite(centres)) or np.any(centres <= 0) \
            or np.any(np.diff(centres) <= 0):
        raise ParameterError("band_centres",
                             f"expected {room.bands} increasing frequencies > 0 Hz, got {band_centres!r}")
    spectrum = np.fft.rfft(noise)
    masks = band_masks(np.fft.rfftfreq(n, 1.0 / fs), centres, transition_octaves=transition_octaves)
    out = np.zeros(n)
    for b in range(room.bands):
        out += np.sqrt(rate[:, b] / fs) * np.fft.irfft(spectrum * masks[b], n)
    return out
