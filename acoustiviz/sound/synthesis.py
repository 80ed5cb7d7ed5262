"""Band-limited synthesis of whole impact sequences at listeners: each click at its exact time, decimated once."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from .._jit import njit as _njit
from .._validate import ParameterError, check_choice, check_positive
from ..constants import SAMPLE_RATES, WAV_RATE
from ..core.contact import PULSE_KINDS, Impact, acceleration_pulse
from ..core.images import ImageSet
from ..core.radiation import pulse_response
from ..core.signal import Signal
from ..field.sources import image_geometry
from .sources import MASS_MODELS, CavityScene, ImpactSequence, check_listeners, spl, wall_sources

__all__ = [
    "SAMPLE_RATES",
    "PASSBAND_FRACTION",
    "STOPBAND_ATTENUATION_DB",
    "ClickModel",
    "Rendering",
    "oversampling_factor",
    "decimation_filter",
    "render",
]


#: Output sample rates in Hz.

#: Upper edge of the flat passband as a fraction of the output rate (0.45 fs).
PASSBAND_FRACTION = 0.45

#: Minimum attenuation in dB of the decimation filter at and above the output Nyquist frequency.
STOPBAND_ATTENUATION_DB = 110.0

_MIN_OVERSAMPLING = 16

_SAMPLES_PER_CONTACT = 200

#: response tails are kept until exp(-c t / a) < 1e-8 (-160 dB of the click)
_TAIL_DECADES = 8.0

#: Above this many sources per wall (a room's images) the sources after the first
#: :data:`EXACT_SOURCES` are rendered as fractional-delay trains convolved with the band-limited
#: click (:func:`_train_kernel`); up to it every source is evaluated in closed form.
TRAIN_ABOVE = 64
#: Sources rendered in closed form when the rest go through trains: the real sphere (a room's
#: images come sorted by order; its reflections, one impact apart, all go through the trains).
EXACT_SOURCES = 1
#: Half-length in output samples of the windowed-sinc fractional delay, and its table's steps per sample.
_SINC_HALF = 48
_SINC_STEPS = 512
#: Images per block when building the trains (bounds the working memory of the delays and weights).
_TRAIN_BLOCK = 200_000


def _sinc_table(half: int = _SINC_HALF, steps: int = _SINC_STEPS) -> np.ndarray:
    """``g(q - f)`` for q = -half+1..half and fractions f = 0..1 in ``steps`` steps, ``(steps + 1, 2 half)``.

    ``g`` is the ideal band-limited interpolator ``sinc`` times a 4-term Blackman-Harris window of
    length ``2 half`` (sidelobes below -92 dB): a fractional delay flat to about ``0.46 fs``.
    """
    f = np.linspace(0.0, 1.0, steps + 1)[:, None]
    x = np.arange(-half + 1, half + 1)[None, :] - f
    u = np.pi * (x / half + 1.0)  # 0 .. 2 pi across the window
    w = 0.35875 - 0.48829 * np.cos(u) + 0.14128 * np.cos(2 * u) - 0.01168 * np.cos(3 * u)
    return np.sinc(x) * w


def _train_kernel_py(out_re, out_im, pos, wre, wim, table, half, steps):  # pragma: no cover - compiled
    """Add ``w_j g(n - pos_j)`` into the trains for every source j (``pos`` in samples, >= half)."""
    for j in range(pos.size):
        p = pos[j]
        n0 = int(math.floor(p))
        fr = (p - n0) * steps
        r = int(fr)
        if r >= steps:
            r = steps - 1
        u = fr - r
        base = n0 - half + 1
        for q in range(2 * half):
            g = table[r, q] * (1.0 - u) + table[r + 1, q] * u
            out_re[base + q] += wre[j] * g
            out_im[base + q] += wim[j] * g


_train_kernel = _njit(_train_kernel_py)


@dataclass(frozen=True)
class ClickModel:
    """How an approach speed becomes an acceleration pulse of the impact mass.

    Parameters
    ----------
    k_hertz : float
        Hertz contact stiffness K_HZ in N/m^1.5.
    mass : float
        Impact mass m in kg.
    main_mass : float
        Main mass M in kg (used by ``mass_model="effective"``).
    mass_model : {"impact", "effective"}
        ``"impact"``: the paper's eq 3, the impact mass against a fixed wall. ``"effective"``:
        approach and duration from the effective mass m M / (m + M) of two free bodies; the
        acceleration is the peak force over m.
    pulse : {"half-sine", "impulse-matched", "hertz"}
        The pulse shape (:func:`acoustiviz.core.pulses.acceleration_pulse`); the paper's half-sine by default.
    hertz_samples : int
        Tabulated samples of the exact Hertz pulse (``pulse="hertz"`` only), kept for plots; the
        pressure uses the closed-form pulse whatever their number.
    """

    k_hertz: float = 5.6e8
    mass: float = 0.0405
    main_mass: float = 0.5
    mass_model: str = "impact"
    pulse: str = "half-sine"
    hertz_samples: int = 513

    def __post_init__(self):
        check_positive("k_hertz", self.k_hertz, "N/m^1.5")
        check_positive("mass", self.mass, "kg")
        check_positive("main_mass", self.main_mass, "kg")
        check_choice("mass_model", self.mass_model, MASS_MODELS)
        check_choice("pulse", self.pulse, PULSE_KINDS)

    def impact(self, velocity: float) -> Impact:
        """The :class:`~acoustiviz.core.contact.Impact` at approach speed ``velocity`` in m/s."""
        partner = self.main_mass if self.mass_model == "effective" else math.inf
        return Impact(velocity=float(velocity), k_hertz=self.k_hertz, mass=self.mass, partner_mass=partner)

    def pulse_for(self, velocity: float):
        """The acceleration pulse (m/s², starting at 0 s) at approach speed ``velocity`` in m/s."""
        return acceleration_pulse(self.impact(velocity), self.pulse, n_samples=self.hertz_samples)

    def describe(self) -> dict:
        """A JSON-ready description."""
        return {"k_hertz_n_m1_5": self.k_hertz, "impact_mass_kg": self.mass, "main_mass_kg": self.main_mass,
                "mass_model": self.mass_model, "pulse": self.pulse,
                "contact_damping": "ignored: undamped Hertz pulses (paper eqs 3-4)"}


# --------------------------------------------------------------------------- band-limiting
def band_limit(sample_rate: float) -> dict:
    """The band limit of a sound rendered at ``sample_rate`` Hz (JSON-ready; frequencies in Hz)."""
    return {"passband_hz": PASSBAND_FRACTION * sample_rate, "stopband_from_hz": 0.5 * sample_rate,
            "stopband_attenuation_db": STOPBAND_ATTENUATION_DB, "filter": "linear-phase Kaiser FIR, zero delay"}


def oversampling_factor(sample_rate: float, shortest_contact: float) -> int:
    """Internal-to-output rate ratio L: at least 16 and at least 200 internal samples per contact.

    Parameters
    ----------
    sample_rate : float
        Output rate in Hz.
    shortest_contact : float
        Shortest contact duration of the sequence in s.
    """
    fs = check_positive("sample_rate", sample_rate, "Hz")
    tau = check_positive("shortest_contact", shortest_contact, "s")
    return max(_MIN_OVERSAMPLING, math.ceil(_SAMPLES_PER_CONTACT / (tau * fs)))


def decimation_filter(oversampling: int) -> np.ndarray:
    """Linear-phase low-pass FIR for decimation by ``oversampling`` (taps at the internal rate).

    Kaiser-window design: gain 1 at 0 Hz, flat (ripple < 1e-5) to ``0.45 fs``, at least
    :data:`STOPBAND_ATTENUATION_DB` dB of attenuation from ``fs/2`` up, where ``fs`` is the output
    rate. The length is ``2 K L + 1`` (odd, centre tap ``K L``) so the decimated output has zero delay.

    Parameters
    ----------
    oversampling : int
        Decimation factor L (>= 2).

    Returns
    -------
    ndarray
        Filter taps (sum 1), read-only: the design (a long Kaiser window) is made once per factor
        and shared by every render.
    """
    L = int(oversampling)
    if L < 2 or L != oversampling:
        raise ParameterError("oversampling", f"must be an integer >= 2, got {oversampling!r}")
    return _decimation_taps(L)


@functools.lru_cache(maxsize=8)
def _decimation_taps(L: int) -> np.ndarray:
    from scipy.signal import firwin, kaiser_beta

    width = (0.5 - PASSBAND_FRACTION) / L * 2.0  # transition width as a fraction of the internal Nyquist
    atten = STOPBAND_ATTENUATION_DB + 3.0  # Kaiser's formulas are approximate: design with a margin
    numtaps = math.ceil((atten - 7.95) / (2.285 * math.pi * width)) + 1
    k = math.ceil((numtaps - 1) / (2 * L))
    cutoff = (PASSBAND_FRACTION + 0.5) / 2.0 / L * 2.0  # mid-transition, fraction of the internal Nyquist
    h = firwin(2 * k * L + 1, cutoff, window=("kaiser", kaiser_beta(atten)))
    h /= h.sum()
    h.flags.writeable = False
    return h


# --------------------------------------------------------------------------- synthesis
@dataclass(frozen=True)
class Rendering:
    """Band-limited pressure signals at the listeners.

    Attributes
    ----------
    signal : Signal
        Sound pressure in Pa, ``(n_listeners, n_samples)``, at the output rate in Hz, from 0 s
        (sample ``n`` at ``n / sample_rate`` s); :attr:`pressure` and :attr:`sample_rate` are its
        samples and its rate.
    internal_rate : float
        Rate in Hz at which the clicks were evaluated before decimation.
    listeners : (n_listeners, 3) ndarray
        Listener positions in m.
    sequence : ImpactSequence
        The impacts rendered.
    scene : CavityScene
        Geometry and medium.
    model : ClickModel
        Contact and pulse model.
    room : dict, optional
        In a room rendered with a :class:`~acoustiviz.sound.room_sound.RoomSound`: the
        exact image order, the transition time, the tail and the bands (JSON-ready).
    balls : dict, optional
        Several balls (:mod:`acoustiviz.sound.balls_sound`): the contacts rendered and what the model
        leaves out (JSON-ready).
    """

    signal: Signal
    internal_rate: float
    listeners: np.ndarray
    sequence: ImpactSequence
    scene: CavityScene
    model: ClickModel
    room: dict | None = None
    balls: dict | None = None

    @property
    def pressure(self) -> np.ndarray:
        """``(n_listeners, n_samples)`` read-only sound pressure in Pa (the samples of :attr:`signal`)."""
        return self.signal.pressure

    @property
    def sample_rate(self) -> int:
        """Output rate in Hz (the rate of :attr:`signal`, a whole number)."""
        return int(self.signal.sample_rate)

    @property
    def n_samples(self) -> int:
        """Number of samples per listener."""
        return self.signal.n_samples

    @property
    def time(self) -> np.ndarray:
        """Sample times in s."""
        return np.arange(self.n_samples) / self.sample_rate

    @property
    def peak(self) -> np.ndarray:
        """Largest |p| in Pa per listener (of the band-limited samples)."""
        return np.max(np.abs(self.pressure), axis=1, initial=0.0)

    @property
    def peak_spl(self) -> np.ndarray:
        """Peak SPL in dB re 20 µPa per listener (of the band-limited samples)."""
        return np.array([spl(row) for row in self.pressure])

    def describe(self) -> dict:
        """A JSON-ready record of everything that made this rendering (without file details)."""
        seq = self.sequence
        out = {
            "sample_rate_hz": self.sample_rate,
            "internal_rate_hz": self.internal_rate,
            "band_limit": band_limit(self.sample_rate),
            "duration_s": self.n_samples / self.sample_rate,
            "impact_count": len(seq),
            "impact_count_by_wall": {"-1": seq.count(-1), "+1": seq.count(1)},
            "approach_speed_range_m_s": ([float(seq.velocities.min()), float(seq.velocities.max())]
                                         if len(seq) else None),
            "scene": self.scene.describe(),
            "click_model": self.model.describe(),
        }
        if self.room is not None:  # the exact images, the transition and the tail replace the room's own order
            out["scene"].update({k: self.room[k] for k in ("image_order", "images", "neglected_energy_db",
                                                             "late_tail", "transition_s")})
            out["room_sound"] = self.room
        if self.balls is not None:  # several balls: the ball-ball contacts and what their sound leaves out
            out["balls"] = self.balls
        return out


def render(sequence: ImpactSequence, scene: CavityScene, model: ClickModel, listeners, *,
           sample_rate: int = WAV_RATE, duration: float | None = None, oversampling: int | None = None,
           room_sound=None) -> Rendering:
    """Render an impact sequence into band-limited pressure signals at the listeners.

    Parameters
    ----------
    sequence : ImpactSequence
        Contact start times (s), walls (-1/+1) and approach speeds (m/s).
    scene : CavityScene
        Where the cavity sits, its geometry (the images) and the medium.
    model : ClickModel
        Impact mass, Hertz stiffness, mass model and pulse kind.
    listeners : (n, 3) or (3,) array_like
        Listener positions in m (see :func:`check_listeners`).
    sample_rate : {44100, 48000, 96000}
        Output rate in Hz.
    duration : float, optional
        Minimum signal length in s; the signal is extended to the end of the last click's tail
        (never cut short).
    oversampling : int, optional
        Internal rate over output rate; default :func:`oversampling_factor`.
    room_sound : RoomSound, optional
        In a room: a statistical late tail after the exact early images, and the absorption per
        octave band (:mod:`acoustiviz.sound.room_sound`); without it every image to the
        room's energy tolerance is summed exactly.

    Returns
    -------
    Rendering
        Pressure in Pa at each listener.

    Notes
    -----
    For impact k on wall w with pulse ``A_k`` the pressure at a listener is
    ``Σ_j P0_j Re[C_j Y_k(t - t_k - (r_j - a)/c)]`` over the wall's sources j
    (:func:`acoustiviz.core.radiation.pulse_response`, paper eqs 12-14). It is evaluated in closed form
    on the internal grid over the click's window (arrival to a tail of ``exp(-c t/a) < 1e-8``),
    filtered by :func:`decimation_filter` and decimated, and added into the output. Cost grows
    with the number of impacts, not with the signal's length.

    Examples
    --------
    >>> seq = ImpactSequence([0.001], [-1], [1.4])
    >>> out = render(seq, CavityScene("plane"), ClickModel(), [0.495, 0.0, 0.514])
    >>> out.pressure.shape[0], round(float(out.peak_spl[0]))
    (1, 102)
    """
    pts, fs, duration = _check_render_args(sequence, scene, model, listeners, sample_rate, duration)
    if room_sound is not None:  # a RoomSound renders the room itself (room_sound.py builds on this module)
        if not callable(getattr(room_sound, "render_scene", None)):
            raise ParameterError("room_sound", f"expected a RoomSound, got {type(room_sound).__name__}")
        return room_sound.render_scene(sequence, scene, model, pts, fs, duration, oversampling)
    a, medium = scene.radius, scene.medium
    pulses = [model.pulse_for(v) for v in sequence.velocities]
    taus = np.array([p.duration for p in pulses]) if pulses else np.array([1.0])
    L = _oversampling(fs, taus, oversampling)
    h = decimation_filter(L)
    half = (h.size - 1) // (2 * L)  # filter half-length in output samples
    f_int = float(L * fs)
    tail = _TAIL_DECADES * math.log(10.0) * a / medium.c
    geom, trains = _wall_geometry(sequence, scene, pts, fs)
    end = 0.0
    for w, (delay, _) in geom.items():
        sel = sequence.walls == w
        if np.any(sel):
            end = max(end, float(np.max(sequence.times[sel] + taus[sel])) + float(delay.max()) + tail)
            if w in trains:
                end = max(end, float(np.max(sequence.times[sel] + taus[sel])) + trains[w][2] + tail)
    n_out = max(math.ceil(end * fs) + half + 1, math.ceil((duration or 0.0) * fs))
    out = np.zeros((pts.shape[0], n_out))
    grid = (fs, L, f_int, h, half, tail)
    _add_exact_clicks(out, sequence, pulses, geom, grid, a, medium)
    _add_trains(out, sequence, pulses, trains, grid, a, medium)
    out.flags.writeable = False  # finished: the Signal takes it without a copy
    return Rendering(Signal(out, fs), f_int, pts, sequence, scene, model)


def _check_render_args(sequence, scene, model, listeners, sample_rate, duration):
    """Refuse bad arguments of :func:`render`; return the listeners (m), the rate (Hz) and the duration (s)."""
    if not isinstance(sequence, ImpactSequence):
        raise ParameterError("sequence", f"expected an ImpactSequence, got {type(sequence).__name__}")
    if not isinstance(scene, CavityScene):
        raise ParameterError("scene", f"expected a CavityScene, got {type(scene).__name__}")
    if not isinstance(model, ClickModel):
        raise ParameterError("model", f"expected a ClickModel, got {type(model).__name__}")
    if sample_rate not in SAMPLE_RATES:
        raise ParameterError("sample_rate", f"must be one of {SAMPLE_RATES} Hz, got {sample_rate!r}")
    fs = int(sample_rate)
    pts = check_listeners(listeners, scene)
    if duration is not None:
        duration = check_positive("duration", duration, "s")
    return pts, fs, duration


def _oversampling(fs: int, taus, oversampling) -> int:
    """The internal rate over the output rate: given, or :func:`oversampling_factor` of the shortest click."""
    if oversampling is None:
        return oversampling_factor(fs, float(taus.min()))
    L = int(oversampling)
    if L < 2 or L != oversampling:
        raise ParameterError("oversampling", f"must be an integer >= 2, got {oversampling!r}")
    return L


def _wall_geometry(sequence, scene, pts, fs):
    """Per wall struck: delays (s) and weights (Pa·s/m) of the exact sources, trains of the rest.

    The sources beyond :data:`TRAIN_ABOVE` of a wall go into fractional-delay trains per listener.
    """
    a, medium = scene.radius, scene.medium
    geom, trains = {}, {}
    for w in (-1, 1):  # delays (r - a)/c in s and complex weights P0 C in Pa·s/m, (listeners, sources)
        srcs = wall_sources(scene, w)
        if len(srcs) > TRAIN_ABOVE and np.any(sequence.walls == w):
            trains[w] = _trains(pts, srcs, a, medium, fs)
            srcs = ImageSet(srcs.positions[:EXACT_SOURCES], srcs.axes[:EXACT_SOURCES],
                            srcs.weights[:EXACT_SOURCES], srcs.orders[:EXACT_SOURCES], srcs.labels[:EXACT_SOURCES])
        delay, p0, c_shape, _ = image_geometry(pts, srcs, a, medium=medium)
        geom[w] = (delay, p0 * c_shape)
    return geom, trains


def _filter_decimate(x: np.ndarray, L: int) -> np.ndarray:
    """``x`` filtered by :func:`decimation_filter` ``(L)`` and decimated by ``L``: ``fftconvolve(x, h)[::L]``.

    The same real FFTs as :func:`scipy.signal.fftconvolve` (length ``next_fast_len(x.size + h.size - 1)``),
    so the samples are the same to the last bit, but the filter's spectrum at each FFT length is
    computed once (:func:`_filter_spectrum`) rather than once per click.
    """
    h = _decimation_taps(L)
    n = x.size + h.size - 1
    if x.ndim != 1 or x.size < 2:
        from scipy.signal import fftconvolve

        return fftconvolve(x, h)[::L]
    import scipy.fft as sfft

    nfft = [sfft.next_fast_len(n, True)]
    y = sfft.irfftn(sfft.rfftn(x, nfft, axes=[0]) * _filter_spectrum(L, nfft[0]), nfft, axes=[0])
    return y[:n][::L]


@functools.lru_cache(maxsize=64)
def _filter_spectrum(L: int, nfft: int) -> np.ndarray:
    """Real FFT of length ``nfft`` of the decimation filter for ``L`` (read-only)."""
    import scipy.fft as sfft

    sp = sfft.rfftn(_decimation_taps(L), [nfft], axes=[0])
    sp.flags.writeable = False
    return sp


def _add_exact_clicks(out, sequence, pulses, geom, grid, a, medium) -> None:
    """Add each impact's click from the exactly rendered sources, in closed form, band-limited."""
    fs, L, f_int, h, half, tail = grid
    n_out = out.shape[1]
    for k, pulse in enumerate(pulses):  # loop over impacts ...
        tk = float(sequence.times[k])
        delay_all, weight_all = geom[int(sequence.walls[k])]
        for i in range(out.shape[0]):  # ... and listeners; vectorised over sources and samples
            delay, weight = delay_all[i], weight_all[i]
            n0 = math.floor((tk + delay.min()) * fs)
            m_stop = math.ceil((tk + delay.max() + pulse.duration + tail) * f_int) + 1
            idx = np.arange(n0 * L, m_stop)
            t_loc = (idx - tk * f_int) / f_int  # time since contact start, s
            y = pulse_response(pulse, t_loc[None, :] - delay[:, None], radius=a, medium=medium)
            x = np.real(weight[:, None] * y).sum(axis=0)
            z = _filter_decimate(x, L)  # = upfirdn(h, x, down=L); FFT is faster for these lengths
            lo = n0 - half
            s0, s1 = max(lo, 0), min(lo + z.size, n_out)
            if s1 > s0:
                out[i, s0:s1] += z[s0 - lo:s1 - lo]


def _add_trains(out, sequence, pulses, trains, grid, a, medium) -> None:
    """Add the rest of the images: the band-limited click through each listener's delay trains."""
    from scipy.signal import fftconvolve

    fs, L, f_int, h, half, tail = grid
    n_out = out.shape[1]
    for w, (q0, tr, _) in trains.items():
        sel = np.flatnonzero(sequence.walls == w)
        dry = np.zeros((2, n_out))
        for k in sel:
            pulse, tk = pulses[k], float(sequence.times[k])
            n0 = math.floor(tk * fs)
            idx = np.arange(n0 * L, math.ceil((tk + pulse.duration + tail) * f_int) + 1)
            y = pulse_response(pulse, (idx - tk * f_int) / f_int, radius=a, medium=medium)
            lo = n0 - half
            for part, x in ((0, y.real), (1, y.imag)):
                z = _filter_decimate(x, L)
                s0, s1 = max(lo, 0), min(lo + z.size, n_out)
                if s1 > s0:
                    dry[part, s0:s1] += z[s0 - lo:s1 - lo]
        for i in range(out.shape[0]):  # Re[W Y] = Re W Re Y - Im W Im Y
            wet = fftconvolve(dry[0], tr[i, 0]) - fftconvolve(dry[1], tr[i, 1])
            s0, s1 = max(q0, 0), min(q0 + wet.size, n_out)
            if s1 > s0:
                out[i, s0:s1] += wet[s0 - q0:s1 - q0]


def _trains(pts, srcs, radius, medium, fs):
    """Fractional-delay trains of the sources after the first :data:`EXACT_SOURCES`, per listener.

    Returns ``(q0, trains, last)``: ``trains[i, 0]`` (``[i, 1]``) holds ``Re`` (``Im``) of the
    weights ``P0_j C_j`` (Pa·s/m) of listener i's sources placed at their delays ``(r_j - a)/c``
    through the windowed-sinc interpolator (:func:`_sinc_table`), sample 0 at ``q0 / fs`` s; ``last``
    is the latest delay in s. Convolving the band-limited click ``Y`` with them delays and weights
    every image's click at once: the sum is that of the closed form to the interpolator's accuracy
    (about 1e-4 of each image's click up to ``0.45 fs``).
    """
    n = len(srcs)
    d_min, d_max = np.full(pts.shape[0], np.inf), np.zeros(pts.shape[0])
    for lo in range(EXACT_SOURCES, n, _TRAIN_BLOCK):  # first pass: the span of the delays
        hi = min(lo + _TRAIN_BLOCK, n)
        r = np.linalg.norm(pts[:, None, :] - srcs.positions[None, lo:hi, :], axis=-1)
        d_min, d_max = np.minimum(d_min, r.min(axis=1)), np.maximum(d_max, r.max(axis=1))
        del r
    d_min, d_max = (d_min.min() - radius) / medium.c, (d_max.max() - radius) / medium.c
    q0 = math.floor(d_min * fs) - _SINC_HALF - 1
    size = math.ceil(d_max * fs) - q0 + _SINC_HALF + 2
    out = np.zeros((pts.shape[0], 2, size))
    table = _sinc_table()
    for lo in range(EXACT_SOURCES, n, _TRAIN_BLOCK):
        hi = min(lo + _TRAIN_BLOCK, n)
        block = ImageSet(srcs.positions[lo:hi], srcs.axes[lo:hi], srcs.weights[lo:hi], srcs.orders[lo:hi],
                         srcs.labels[lo:hi])
        delay, p0, c_shape, _ = image_geometry(pts, block, radius, medium=medium)
        weight = p0 * c_shape
        for i in range(pts.shape[0]):
            _train_kernel(out[i, 0], out[i, 1], np.ascontiguousarray(delay[i] * fs - q0),
                          np.ascontiguousarray(weight[i].real), np.ascontiguousarray(weight[i].imag), table,
                          _SINC_HALF, _SINC_STEPS)
        del delay, p0, c_shape, weight
    return q0, out, d_max
