"""Acceleration pulses of one impact: the paper's half-sine (eq 4), sampled pulses and the exact Hertz pulse.

:func:`acceleration_pulse` builds the pulse of an :class:`~acoustiviz.core.contact.Impact`; the
classes are importable from :mod:`acoustiviz.core.contact` too. Times in s, accelerations in m/s².
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice, check_positive
from ..constants import HERTZ_DURATION_CONSTANT, PULSES

__all__ = ["PULSE_KINDS", "HalfSinePulse", "SampledPulse", "HertzPulse", "hertz_pulse_shape", "acceleration_pulse"]

#: The acceleration pulses on offer (see :func:`acceleration_pulse`).
PULSE_KINDS = PULSES


@dataclass(frozen=True)
class HalfSinePulse:
    """A half-sine acceleration pulse ``A(t) = amplitude sin(π t / duration)`` for 0 <= t <= duration.

    Parameters
    ----------
    amplitude : float
        Peak acceleration in m/s².
    duration : float
        Pulse length in s.
    kind : str
        Which pulse this is: ``"half-sine"`` (peak- and duration-matched, paper eq 4) or
        ``"impulse-matched"``.

    Examples
    --------
    The paper's eq 4 pulse of its Figure 2 impact (peak 9800 m/s², 525.6 µs): zero at both ends,
    the peak at mid-contact, and a velocity change ``2 A τ / π``:

    >>> pulse = HalfSinePulse(9800.0, 525.6e-6)
    >>> np.round(pulse.acceleration([0.0, 262.8e-6, 525.6e-6, 1e-3]), 6)
    array([   0., 9800.,    0.,    0.])
    >>> round(pulse.velocity_change, 4)  # m/s
    3.2792
    """

    amplitude: float
    duration: float
    kind: str = "half-sine"

    def __post_init__(self):
        check_positive("duration", self.duration, "s")
        if not math.isfinite(self.amplitude):
            raise ParameterError("amplitude", f"must be finite, got {self.amplitude}")

    def acceleration(self, t):
        """Acceleration in m/s² at times ``t`` in s (zero outside the pulse)."""
        t = np.asarray(t, dtype=float)
        inside = (t >= 0) & (t <= self.duration)
        return np.where(inside, self.amplitude * np.sin(np.pi * np.clip(t, 0, self.duration) / self.duration), 0.0)

    @property
    def velocity_change(self) -> float:
        """Velocity change ∫A dt = 2 A τ / π in m/s."""
        return 2.0 * self.amplitude * self.duration / math.pi

    @property
    def peak(self) -> float:
        """Peak acceleration in m/s²."""
        return abs(self.amplitude)


@dataclass(frozen=True, eq=False)
class SampledPulse:
    """An acceleration pulse given by samples, linear between them and zero outside.

    Parameters
    ----------
    times : (n,) array_like
        Strictly increasing sample times in s, starting at 0.
    acceleration : (n,) array_like
        Acceleration in m/s² at those times.
    kind : str
        A label saying what the pulse is (``"hertz"`` for the exact Hertz pulse).

    Examples
    --------
    A triangular pulse of 1000 m/s² peak and 0.2 ms length, e.g. from a measured acceleration;
    its velocity change is the triangle's area, 0.1 m/s:

    >>> pulse = SampledPulse([0.0, 1e-4, 2e-4], [0.0, 1000.0, 0.0])
    >>> np.round(pulse.acceleration([5e-5, 1e-4, 3e-4]), 6)  # linear inside, zero outside
    array([ 500., 1000.,    0.])
    >>> round(pulse.velocity_change, 12), pulse.peak, pulse.duration
    (0.1, 1000.0, 0.0002)
    """

    times: np.ndarray
    acceleration_samples: np.ndarray
    kind: str = "sampled"

    def __eq__(self, other):
        """Equal pulses are of one class and kind with equal samples (by value; unhashable, as arrays are)."""
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self.kind == other.kind and np.array_equal(self.times, other.times) \
            and np.array_equal(self.acceleration_samples, other.acceleration_samples)

    def __post_init__(self):
        t = np.array(self.times, dtype=float)
        a = np.array(self.acceleration_samples, dtype=float)
        if t.ndim != 1 or t.size < 2:
            raise ParameterError("times", "need a 1-D array of at least 2 sample times in s")
        if a.shape != t.shape:
            raise ParameterError("acceleration", f"shape {a.shape} does not match times {t.shape}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a))):
            raise ParameterError("acceleration", "times and samples must be finite")
        if np.any(np.diff(t) <= 0):
            raise ParameterError("times", "must be strictly increasing")
        if t[0] != 0.0:
            raise ParameterError("times", f"must start at 0 s, got {t[0]:g} s")
        t.setflags(write=False)
        a.setflags(write=False)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "acceleration_samples", a)

    @property
    def duration(self) -> float:
        """Length of the pulse in s."""
        return float(self.times[-1])

    def acceleration(self, t):
        """Acceleration in m/s² at times ``t`` in s (linear interpolation, zero outside)."""
        return np.interp(np.asarray(t, dtype=float), self.times, self.acceleration_samples, left=0.0, right=0.0)

    @property
    def velocity_change(self) -> float:
        """Velocity change ∫A dt in m/s (exact for the piecewise-linear pulse)."""
        return float(np.trapezoid(self.acceleration_samples, self.times))

    @property
    def peak(self) -> float:
        """Largest |acceleration| in m/s²."""
        return float(np.max(np.abs(self.acceleration_samples)))


@dataclass(frozen=True, init=False, repr=False, eq=False)
class HertzPulse(SampledPulse):
    """The exact undamped Hertz pulse ``A(t) = amplitude · s(θ_c t / duration)^{3/2}``, in closed form.

    ``s^{3/2}`` is :func:`hertz_pulse_shape` (inverse incomplete beta function), so the
    acceleration is exact at every time. The pulse also carries ``n_samples`` exact samples
    clustered at both ends (``times``, ``acceleration_samples``) for plots and bounds; the
    radiation (:func:`acoustiviz.core.radiation.pulse_response`) does not interpolate them.

    Parameters
    ----------
    amplitude : float
        Peak acceleration in m/s².
    duration : float
        Contact duration τ in s.
    n_samples : int
        Number of tabulated samples (>= 17).

    Examples
    --------
    >>> p = HertzPulse(1000.0, 1e-4)
    >>> round(p.velocity_change / (1000.0 * 1e-4), 6)  # 1.6/θ_c of amplitude x duration
    0.543612
    """

    amplitude: float = 0.0

    def __init__(self, amplitude: float, duration: float, n_samples: int = 1025):
        tau = check_positive("duration", duration, "s")
        if not math.isfinite(amplitude):
            raise ParameterError("amplitude", f"must be finite, got {amplitude}")
        n = int(n_samples)
        if n < 17 or n != n_samples:
            raise ParameterError("n_samples", f"must be an integer >= 17, got {n_samples}")
        u = np.linspace(0.0, 1.0, n)
        t = tau * 0.5 * (1.0 - np.cos(np.pi * u))  # Chebyshev-like clustering at both ends
        t[0], t[-1] = 0.0, tau
        a = float(amplitude) * hertz_pulse_shape(t * (HERTZ_DURATION_CONSTANT / tau))
        a[0] = a[-1] = 0.0
        super().__init__(t, a, "hertz")
        object.__setattr__(self, "amplitude", float(amplitude))

    def __repr__(self) -> str:
        return f"HertzPulse(amplitude={self.amplitude!r}, duration={self.duration!r}, n_samples={self.times.size})"

    def __reduce__(self):
        return (type(self), (self.amplitude, self.duration, self.times.size))

    def acceleration(self, t):
        """Exact acceleration in m/s² at times ``t`` in s (zero outside the contact)."""
        t = np.asarray(t, dtype=float)
        return self.amplitude * hertz_pulse_shape(t * (HERTZ_DURATION_CONSTANT / self.duration))

    @property
    def velocity_change(self) -> float:
        """Velocity change ∫A dt = 1.6 amplitude τ / θ_c in m/s (``∫ s^{3/2} dθ = 2/(5/4)``)."""
        return 1.6 * self.amplitude * self.duration / HERTZ_DURATION_CONSTANT

    @property
    def peak(self) -> float:
        """Peak acceleration in m/s²."""
        return abs(self.amplitude)


def hertz_pulse_shape(theta):
    """Universal undamped Hertz force shape ``s(θ)^{3/2}`` (peak 1).

    Parameters
    ----------
    theta : array_like
        Dimensionless time θ = t U0 / α_max; the contact lasts 0 <= θ <= 2.943275.

    Returns
    -------
    ndarray
        Force (or sphere acceleration) divided by its peak, zero outside the contact.

    Notes
    -----
    ``s'' = -(5/4) s^{3/2}`` with ``s(0)=0, s'(0)=1`` conserves ``s'² + s^{5/2} = 1``, so
    ``θ(s) = ∫_0^s dx / sqrt(1 - x^{5/2}) = (2/5) B(s^{5/2}; 2/5, 1/2)``. Inverting the
    regularised incomplete beta function gives ``s^{5/2} = I^{-1}_{2/5,1/2}(2θ/θ_c)`` on the
    loading half; the unloading half is its mirror image.
    """
    from scipy.special import betaincinv

    th = np.asarray(theta, dtype=float)
    tc = HERTZ_DURATION_CONSTANT
    inside = (th >= 0) & (th <= tc)
    half = np.minimum(np.clip(th, 0, tc), tc - np.clip(th, 0, tc))
    x = betaincinv(0.4, 0.5, np.clip(2.0 * half / tc, 0.0, 1.0))
    return np.where(inside, x**0.6, 0.0)


def acceleration_pulse(impact, kind: str = "half-sine", *, n_samples: int = 1025):
    """The acceleration pulse of the sphere during one impact.

    Parameters
    ----------
    impact : acoustiviz.core.contact.Impact
        The collision (its damping is ignored: these are the undamped Hertz pulses).
    kind : {"half-sine", "impulse-matched", "hertz"}
        ``"half-sine"``: the paper's eq 4, peak A_max and duration τ of the Hertz impact; it
        carries about 1.171 times the true impulse. ``"impulse-matched"``: a half-sine of
        duration τ whose area is the Hertz velocity change 2 m_eff U0 / m. ``"hertz"``: the
        exact Hertz pulse in closed form (:class:`HertzPulse`).
    n_samples : int, optional
        Number of tabulated samples of the exact pulse (>= 17), for plots and bounds only.

    Returns
    -------
    HalfSinePulse or HertzPulse
        The pulse; its ``kind`` says which one it is.

    Examples
    --------
    For the paper's Figure 2 impact the exact Hertz pulse changes the sphere's speed by
    ``2 U0 = 2.8`` m/s; the peak-matched half-sine carries 17 % more, the impulse-matched one
    exactly as much with a lower peak:

    >>> from acoustiviz.core.contact import Impact
    >>> imp = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800.0 * 4.0 / 3.0 * math.pi * 0.01905**3)
    >>> for kind in PULSE_KINDS:
    ...     p = acceleration_pulse(imp, kind)
    ...     print(f"{kind:16s} {type(p).__name__:13s} peak {p.peak:6.0f} m/s²  dv {p.velocity_change:.4f} m/s")
    half-sine        HalfSinePulse peak   9800 m/s²  dv 3.2791 m/s
    impulse-matched  HalfSinePulse peak   8368 m/s²  dv 2.8000 m/s
    hertz            HertzPulse    peak   9800 m/s²  dv 2.8000 m/s
    """
    check_choice("pulse", kind, PULSE_KINDS)
    tau = impact.duration
    if kind == "half-sine":
        return HalfSinePulse(impact.peak_acceleration, tau, kind)
    if kind == "impulse-matched":
        dv = impact.impulse / impact.mass
        return HalfSinePulse(math.pi * dv / (2.0 * tau), tau, kind)
    return HertzPulse(impact.peak_acceleration, tau, n_samples)
