"""Band-limited synthesis of whole impact sequences at listeners: each click at its exact time, decimated once."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._validate import ParameterError, check_choice, check_positive
from ...constants import SAMPLE_RATES
from ...core.contact import PULSE_KINDS, Impact, acceleration_pulse
from ...core.radiation import pulse_response
from ...field.sources import image_geometry
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
        The pulse shape (:func:`acoustiviz.core.contact.acceleration_pulse`); the paper's half-sine by default.
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
        Filter taps (sum 1).
    """
    from scipy.signal import firwin, kaiser_beta

    L = int(oversampling)
    if L < 2 or L != oversampling:
        raise ParameterError("oversampling", f"must be an integer >= 2, got {oversampling!r}")
    width = (0.5 - PASSBAND_FRACTION) / L * 2.0  # transition width as a fraction of the internal Nyquist
    atten = STOPBAND_ATTENUATION_DB + 3.0  # Kaiser's formulas are approximate: design with a margin
    numtaps = math.ceil((atten - 7.95) / (2.285 * math.pi * width)) + 1
    k = math.ceil((numtaps - 1) / (2 * L))
    cutoff = (PASSBAND_FRACTION + 0.5) / 2.0 / L * 2.0  # mid-transition, fraction of the internal Nyquist
    h = firwin(2 * k * L + 1, cutoff, window=("kaiser", kaiser_beta(atten)))
    return h / h.sum()


# --------------------------------------------------------------------------- synthesis
@dataclass(frozen=True)
class Rendering:
    """Band-limited pressure signals at the listeners.

    Attributes
    ----------
    pressure : (n_listeners, n_samples) ndarray
        Sound pressure in Pa; sample ``n`` is at time ``n / sample_rate`` s.
    sample_rate : int
        Output rate in Hz.
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
    """

    pressure: np.ndarray
    sample_rate: int
    internal_rate: float
    listeners: np.ndarray
    sequence: ImpactSequence
    scene: CavityScene
    model: ClickModel

    @property
    def n_samples(self) -> int:
        """Number of samples per listener."""
        return int(self.pressure.shape[1])

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
        return {
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


def render(sequence: ImpactSequence, scene: CavityScene, model: ClickModel, listeners, *,
           sample_rate: int = 48000, duration: float | None = None, oversampling: int | None = None) -> Rendering:
    """Render an impact sequence into band-limited pressure signals at the listeners.

    Parameters
    ----------
    sequence : ImpactSequence
        Contact start times (s), walls (-1/+1) and approach speeds (m/s).
    scene : CavityScene
        Where the cavity sits, the image configuration and the medium.
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
    from scipy.signal import fftconvolve

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
    a, medium = scene.radius, scene.medium
    pulses = [model.pulse_for(v) for v in sequence.velocities]
    taus = np.array([p.duration for p in pulses]) if pulses else np.array([1.0])
    if oversampling is None:
        L = oversampling_factor(fs, float(taus.min()))
    else:
        L = int(oversampling)
        if L < 2 or L != oversampling:
            raise ParameterError("oversampling", f"must be an integer >= 2, got {oversampling!r}")
    h = decimation_filter(L)
    half = (h.size - 1) // (2 * L)  # filter half-length in output samples
    f_int = float(L * fs)
    tail = _TAIL_DECADES * math.log(10.0) * a / medium.c
    geom = {}
    for w in (-1, 1):  # delays (r - a)/c in s and complex weights P0 C in Pa·s/m, (listeners, sources)
        delay, p0, c_shape, _ = image_geometry(pts, wall_sources(scene, w), a, medium=medium)
        geom[w] = (delay, p0 * c_shape)

    end = 0.0
    for w, (delay, _) in geom.items():
        sel = sequence.walls == w
        if np.any(sel):
            end = max(end, float(np.max(sequence.times[sel] + taus[sel])) + float(delay.max()) + tail)
    n_out = max(math.ceil(end * fs) + half + 1, math.ceil((duration or 0.0) * fs))
    out = np.zeros((pts.shape[0], n_out))
    for k, pulse in enumerate(pulses):  # loop over impacts ...
        tk = float(sequence.times[k])
        delay_all, weight_all = geom[int(sequence.walls[k])]
        for i in range(pts.shape[0]):  # ... and listeners; vectorised over sources and samples
            delay, weight = delay_all[i], weight_all[i]
            n0 = math.floor((tk + delay.min()) * fs)
            m_stop = math.ceil((tk + delay.max() + pulse.duration + tail) * f_int) + 1
            idx = np.arange(n0 * L, m_stop)
            t_loc = (idx - tk * f_int) / f_int  # time since contact start, s
            y = pulse_response(pulse, t_loc[None, :] - delay[:, None], radius=a, medium=medium)
            x = np.real(weight[:, None] * y).sum(axis=0)
            z = fftconvolve(x, h)[::L]  # = upfirdn(h, x, down=L); FFT is faster for these lengths
            lo = n0 - half
            s0, s1 = max(lo, 0), min(lo + z.size, n_out)
            if s1 > s0:
                out[i, s0:s1] += z[s0 - lo:s1 - lo]
    return Rendering(out, fs, f_int, pts, sequence, scene, model)
