"""Weighted levels of one design: its damper run heard as a click train at the sweep's listener.

A design's maximum SPL (:func:`acoustiviz.sweep.max_spl_db`) is the peak of its loudest impact. How
loud the run sounds to people and to standards is asked of the whole click train, the signal
:func:`acoustiviz.sound.render` makes of every impact at the listener at
:data:`acoustiviz.constants.ANALYSIS_RATE` (96 kHz: each click evaluated in closed form at >= 1.5 MHz
and band-limited flat to 43.2 kHz), evaluated with the IEC 61672-1 weightings of the
conformance-tested library (:func:`acoustiviz.levels.sound_levels`):

* ``lafmax_db``: the largest A-weighted, F (125 ms) time-weighted level over the run;
* ``lcpeak_db``: the largest |p| of the C-weighted signal;
* ``laeq_db``: the A-weighted energy average over the run, ``LAeq,T`` with ``T`` the simulated
  duration (from t = 0, the start of the run, to ``duration``).

Every impact is heard as a strike on the geometry's struck surface (``walls="one"`` of
:class:`acoustiviz.sound.CavityScene`), the view the maximum SPL takes, so the two describe
the same sound. Levels in dB re 20 µPa.

A run of 20 s is 1.9 million samples at 96 kHz and a few hundred clicks of a few milliseconds, so
the levels are computed from the clicks alone (``method="sparse"``, the default):
:func:`click_windows` gives each click's band-limited samples from the closed-form spectrum of its
pressure, and :func:`acoustiviz.levels.train.train_levels` filters only the samples that hold
sound, carrying the filters' states exactly across the silences. The spectrum of click k at the
listener, ``P_k(ω) = A_k(ω) R(ω)``, is the pulse's transform ``A_k`` (half-sine:
``A0 (π/τ)(1 + e^{-iωτ}) / ((π/τ)² - ω²)``) times the listener's radiation factor

``R(ω) = Σ_j P0_j e^{-iω d_j} ½ [C_j / (iω - s) + C̄_j / (iω - s̄)]``,

the transform of ``Σ_j P0_j Re[C_j Y(t - d_j)]`` (paper eqs 12-14, :mod:`acoustiviz.core.radiation`)
over the struck wall's sources j (delay ``d_j = (r_j - a)/c``). The render's decimation filter is a
zero-phase FIR at the internal rate with response ``H(ω)``, so click k's samples are the inverse DFT
of ``fs P_k(ω) H(ω) e^{-iω (t_k - n_k / fs)}`` over a window of ``N`` samples from sample ``n_k``
that holds the filter's support and the click to ``exp(-c t / a) < 1.4e-11``. They differ from the
rendered samples only by what the render neglects (aliasing from above the internal Nyquist
frequency and past 110 dB of stop band, the tail after 1e-8), about 2e-7 of the peak: the levels
agree with rendering and filtering every sample (``method="dense"``) to about 1e-7 dB, checked
within 1e-5 dB at several designs and configurations in ``tests/test_sweep_levels.py``.
``H(ω)``, ``R(ω)`` and the filters' tables are made once per process and reused by every design
of the same rate, sphere, listener and medium. A room (a wall with more than
:data:`acoustiviz.sound.synthesis.TRAIN_ABOVE` sources, whose reflections fill the
silences) is rendered densely. ``benchmarks/bench_sweep.py`` measures the levels' cost beside the
motion's.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..constants import ANALYSIS_RATE

__all__ = ["SWEEP_LEVEL_COLUMNS", "LEVEL_METRICS", "LEVEL_METHODS", "design_levels", "click_windows", "NO_LEVELS"]

#: The level columns of ``sweep.csv``, in order.
SWEEP_LEVEL_COLUMNS = ("lafmax_db", "lcpeak_db", "laeq_db")
#: Column -> metric name of :func:`acoustiviz.levels.metric_levels`.
LEVEL_METRICS = {"lafmax_db": "lafmax", "lcpeak_db": "lcpeak", "laeq_db": "laeq"}
#: The level columns of a design whose levels were not computed.
NO_LEVELS = dict.fromkeys(SWEEP_LEVEL_COLUMNS, math.nan)
#: How :func:`design_levels` computes: from the clicks alone, or rendering and filtering every sample.
LEVEL_METHODS = ("sparse", "dense")

#: Clicks whose spectra are worked on at once (bounds the work arrays to a few MB).
_CHUNK = 1024
#: The clicks' windows hold their tail to ``exp(-c t / a)`` below this (25 sphere time constants).
_TAIL = math.exp(-25.0)


def design_levels(impacts, *, scene, model, point, duration: float, sample_rate: int = ANALYSIS_RATE,
                  method: str = "sparse") -> dict:
    """LAFmax, LCpeak and LAeq,T of a damper run's click train at one listener.

    Parameters
    ----------
    impacts : acoustiviz.dynamics.ImpactTable
        The run's impacts (contact start times in s, walls, approach speeds in m/s).
    scene : acoustiviz.sound.CavityScene
        The cavity and its surroundings (the sweep uses ``walls="one"``).
    model : acoustiviz.sound.ClickModel
        How an approach speed becomes an acceleration pulse.
    point : (3,) or (1, 3) array_like
        Listener position in m.
    duration : float
        The run's simulated duration in s: the interval ``[0, duration]`` of LAeq,T and of the maxima.
    sample_rate : int
        Rate in Hz of the signal the levels are computed from (default
        :data:`~acoustiviz.constants.ANALYSIS_RATE`).
    method : {"sparse", "dense"}
        ``"sparse"``: from the clicks alone (:func:`click_windows`,
        :func:`acoustiviz.levels.train.train_levels`); ``"dense"``: render every sample
        (:func:`acoustiviz.sound.render`) and filter it (:func:`acoustiviz.levels.sound_levels`).

    Returns
    -------
    dict
        ``lafmax_db``, ``lcpeak_db``, ``laeq_db`` in dB re 20 µPa (``-inf`` for a run without impacts).

    Notes
    -----
    ``LAeq,T = 10 log10((1/T) ∫_0^T p_A² dt / p_ref²)``, ``LCpeak = 20 log10(max|p_C| / p_ref)``,
    ``LAFmax = max_t 10 log10(p_AF²(t) / p_ref²)`` (IEC 61672-1:2013, 3.8-3.9 and 3.12).
    """
    from .._validate import check_choice

    check_choice("method", method, LEVEL_METHODS)
    n = int(round(duration * sample_rate))
    if len(impacts) == 0:
        return dict.fromkeys(SWEEP_LEVEL_COLUMNS, -math.inf)
    clicks = click_windows(impacts, scene=scene, model=model, point=point,
                           sample_rate=sample_rate) if method == "sparse" else None
    if clicks is None:
        from ..core.signal import Signal
        from ..levels import sound_levels
        from ..sound import ImpactSequence, render

        out = render(ImpactSequence.from_table(impacts), scene, model, np.reshape(point, (1, 3)),
                     sample_rate=sample_rate, duration=duration)
        lv = sound_levels(Signal(out.pressure[0], sample_rate), start=0.0, stop=n / sample_rate)
        return {c: float(getattr(lv, c)[0]) for c in SWEEP_LEVEL_COLUMNS}
    from ..levels.train import train_levels

    got = train_levels(*clicks, sample_rate, n, list(LEVEL_METRICS.values()))
    return {c: got[m] for c, m in LEVEL_METRICS.items()}


def click_windows(impacts, *, scene, model, point, sample_rate: int = ANALYSIS_RATE):
    """Each impact's band-limited click at a listener, as :func:`~acoustiviz.sound.render` adds it.

    Parameters
    ----------
    impacts : acoustiviz.dynamics.ImpactTable or acoustiviz.sound.ImpactSequence
        Contact start times in s, walls, approach speeds in m/s.
    scene, model
        The :class:`~acoustiviz.sound.CavityScene` and
        :class:`~acoustiviz.sound.ClickModel` of the render.
    point : (3,) or (1, 3) array_like
        Listener position in m.
    sample_rate : {44100, 48000, 96000}
        Output rate in Hz.

    Returns
    -------
    (starts, windows) or None
        ``starts`` (k,) the first sample of each click's window, ``windows`` (k, N) its samples in
        Pa (:func:`acoustiviz.levels.train.train_signal` sums them into the rendered signal); None
        in a room (a wall with more than :data:`~acoustiviz.sound.synthesis.TRAIN_ABOVE`
        sources), which the render builds from delay trains.
    """
    from scipy.fft import irfft, next_fast_len

    from ..core.radiation import sphere_pole
    from ..errors import ParameterError
    from ..field.sources import image_geometry
    from ..sound import (
        SAMPLE_RATES,
        CavityScene,
        ClickModel,
        ImpactSequence,
        check_listeners,
        oversampling_factor,
        wall_sources,
    )
    from ..sound.synthesis import TRAIN_ABOVE

    seq = impacts if isinstance(impacts, ImpactSequence) else ImpactSequence.from_table(impacts)
    for name, value, kind in (("scene", scene, CavityScene), ("model", model, ClickModel)):
        if not isinstance(value, kind):
            raise ParameterError(name, f"expected a {kind.__name__}, got {type(value).__name__}")
    if sample_rate not in SAMPLE_RATES:
        raise ParameterError("sample_rate", f"must be one of {SAMPLE_RATES} Hz, got {sample_rate!r}")
    fs, pts = int(sample_rate), check_listeners(point, scene, name="point")
    a, medium = scene.radius, scene.medium
    walls = sorted({int(w) for w in seq.walls})
    sources = {w: wall_sources(scene, w) for w in walls}
    if any(len(s) > TRAIN_ABOVE for s in sources.values()):
        return None
    amp, tau = _pulses(model, seq.velocities)
    L = oversampling_factor(fs, float(tau.min()))
    geom = {w: image_geometry(pts, sources[w], a, medium=medium)[:3] for w in walls}
    d_lo = min(float(g[0].min()) for g in geom.values())
    d_hi = max(float(g[0].max()) for g in geom.values())
    half = _half_length(L)
    span = (d_hi - d_lo + float(tau.max()) - math.log(_TAIL) * a / medium.c) * fs + 2 * half + 4
    n_win = next_fast_len(math.ceil(span), real=True)
    omega = 2.0 * math.pi * fs / n_win * np.arange(n_win // 2 + 1)
    starts = np.floor((seq.times + d_lo) * fs).astype(np.int64) - half - 1
    s = sphere_pole(a, medium)
    gain = {w: fs * _lowpass(fs, L, n_win) * _radiation(omega, g[0][0], (g[1] * g[2])[0], (g[1] * np.conj(g[2]))[0], s)
            for w, g in geom.items()}
    windows = np.empty((len(seq), n_win))
    for lo in range(0, len(seq), _CHUNK):  # bounded work arrays, whatever the number of impacts
        k = slice(lo, lo + _CHUNK)
        spec = _pulse_spectra(model, seq.velocities[k], amp[k], tau[k], omega)
        spec *= _phases(seq.times[k] - starts[k] / fs, omega)
        for w in walls:
            spec[seq.walls[k] == w] *= gain[w]
        windows[k] = irfft(spec, n=n_win, axis=-1)
    return starts, windows


def _phases(delay, omega) -> np.ndarray:
    """``exp(-i ω_j delay_k)`` on the uniform grid ``ω_j = j Δω``, ``(k, len(omega))``, as powers of the first step.

    The product of ``j`` unit factors carries a phase error of about ``j`` ulps (1e-13 at j = 1000).
    """
    step = np.exp(-1j * omega[1] * np.asarray(delay, dtype=float))
    out = np.empty((step.size, omega.size), dtype=complex)
    out[:, 0] = 1.0
    out[:, 1:] = step[:, None]
    return np.cumprod(out, axis=1)


def _pulses(model, velocities):
    """Peak (m/s²) and duration (s) of each impact's half-sine pulse, as ``model.pulse_for`` makes them."""
    from ..core.contact import contact_duration, effective_mass, peak_force

    v = np.asarray(velocities, dtype=float)
    m_eff = float(effective_mass(model.mass, model.main_mass if model.mass_model == "effective" else math.inf))
    tau = np.asarray(contact_duration(v, model.k_hertz, m_eff), dtype=float).reshape(v.shape)
    if model.pulse == "impulse-matched":
        return math.pi * (2.0 * m_eff * v / model.mass) / (2.0 * tau), tau
    return np.asarray(peak_force(v, model.k_hertz, m_eff), dtype=float).reshape(v.shape) / model.mass, tau


def _pulse_spectra(model, velocities, amp, tau, omega) -> np.ndarray:
    """``A_k(ω)`` of every impact's pulse (m/s), ``(k, len(omega))``.

    Half-sines in closed form, the exact Hertz pulse from its unit transform (:func:`_hertz_chebyshev`).
    """
    if model.pulse == "hertz":  # A0 τ S(ωτ), S the transform of the unit Hertz pulse
        nu = np.outer(tau, omega)
        top = 32.0 * math.ceil(float(nu.max()) / 32.0)
        return (amp * tau)[:, None] * np.polynomial.chebyshev.chebval(2.0 * nu / top - 1.0, _hertz_chebyshev(top))
    w0 = (math.pi / tau)[:, None]
    den = w0 * w0 - omega[None, :] ** 2
    near = np.abs(den) < 1e-9 * w0 * w0
    out = (amp[:, None] * w0) * (1.0 + _phases(tau, omega)) / np.where(near, 1.0, den)
    if np.any(near):
        out[near] = (-0.5j * amp[:, None] * tau[:, None] * np.ones_like(den))[near]
    return out


@functools.lru_cache(maxsize=8)
def _hertz_chebyshev(top: float) -> np.ndarray:
    """Chebyshev coefficients on ``[0, top]`` of ``S(ν) = ∫_0^1 shape(u) e^{-iνu} du`` of the unit Hertz pulse.

    ``S`` is the transform of a pulse lasting 1 s, an entire function oscillating at most once per
    2π; interpolating it at ``0.85 top + 40`` Chebyshev points of the second kind reproduces
    :func:`acoustiviz.levels.energy.pulse_spectrum` to about 1e-14 of its peak (``top`` up to 400).
    """
    from ..core.pulses import HertzPulse
    from ..levels.energy import pulse_spectrum

    deg = int(0.85 * top) + 40
    x = np.polynomial.chebyshev.chebpts2(deg + 1)
    values = pulse_spectrum(HertzPulse(1.0, 1.0, 33), 0.5 * top * (x + 1.0))
    cheb = np.polynomial.chebyshev
    out = cheb.chebfit(x, values.real, deg) + 1j * cheb.chebfit(x, values.imag, deg)
    out.flags.writeable = False
    return out


def _radiation(omega, delay, pc, pc_bar, s) -> np.ndarray:
    """``R(ω) = Σ_j e^{-iω d_j} ½ [P0_j C_j / (iω - s) + P0_j C̄_j / (iω - s̄)]`` (Pa·s/m per m/s·s)."""
    key = (omega.size, float(omega[1]), tuple(delay.tolist()), tuple(pc.tolist()), tuple(pc_bar.tolist()), s)
    return _radiation_cached(key)


@functools.lru_cache(maxsize=64)
def _radiation_cached(key) -> np.ndarray:
    size, step, delay, pc, pc_bar, s = key
    omega = step * np.arange(size)
    iw = 1j * omega[:, None]
    d, c1, c2 = np.array(delay)[None, :], np.array(pc)[None, :], np.array(pc_bar)[None, :]
    out = np.sum(np.exp(-iw * d) * 0.5 * (c1 / (iw - s) + c2 / (iw - np.conj(s))), axis=1)
    out.flags.writeable = False
    return out


def _half_length(L: int) -> int:
    """Half-length in output samples of the render's decimation filter for factor ``L``."""
    from ..sound import decimation_filter

    return (decimation_filter(L).size - 1) // (2 * L)


@functools.lru_cache(maxsize=16)
def _lowpass(fs: int, L: int, n_win: int) -> np.ndarray:
    """The render's zero-phase decimation filter at the window's DFT frequencies (real, gain 1 at 0 Hz)."""
    from ..sound import decimation_filter

    h = decimation_filter(L)
    half = (h.size - 1) // (2 * L)
    k = np.arange(n_win // 2 + 1)
    out = np.real(np.fft.rfft(h, n=n_win * L)[:k.size] * np.exp(2j * math.pi * k * half / n_win))
    out.flags.writeable = False
    return out
