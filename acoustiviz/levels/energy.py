"""Sound energy radiated by one impact, radiation efficiency, and the sound power of a run.

Three independent routes to the acoustic energy ``E`` (J) that one acceleration pulse of a rigid
sphere sends to infinity:

1. **Closed form, free sphere** (:func:`radiated_energy_free`): the power the surface delivers is
   ``∫ p u_n dS``; with the sphere's surface pressure per unit velocity (paper eq 7 at ``r = a``)
   its real part, the dipole's radiation resistance, is
   ``R(ω) = (4π a²/3) ρ c (ka)⁴ / (4 + (ka)⁴)`` (Kinsler et al., *Fundamentals of Acoustics*,
   §7.5; Morse & Ingard §7.2), and Parseval gives ``E = (1/π) ∫_0^∞ R(ω) |V(ω)|² dω`` with
   ``V(ω) = A(ω)/(iω)`` the velocity spectrum of the pulse ``A``. The reactive part (the
   entrained mass ``2π ρ a³/3``) stores energy but radiates none, so it drops out.
2. **Surface work in time** (:func:`surface_work_free`): ``∫ F v dt`` with the surface force
   ``F = (4π a²/3) p(a, 0, t)`` from the same transient solution, less the kinetic energy
   ``½ m_a ΔV²`` left in the steady flow round the sphere after the pulse. A check of (1).
3. **Intensity over a spherical grid** (:func:`radiated_energy_grid`): the far-field intensity
   ``p²/(ρ c)`` of the sphere and all its images, integrated over the directions of a weighted
   spherical grid (:func:`acoustiviz.field.grids.spherical_grid_for`: the whole sphere, the half space
   above a plane, the quarter space of a corner) and over time. It is exact at infinity (no
   near-field bias), so it is the only route for the plane and the corner, and its error is the
   quadrature's: it converges as the grid is refined.

The radiation efficiency of an impact is ``E`` over the kinetic energy lost in that impact; the
sound power of a damper run is the radiated energy of all its impacts over the run's duration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_positive
from ..constants import W_REF
from ..core.contact import HalfSinePulse, HertzPulse, SampledPulse
from ..core.images import ImageSet
from ..core.medium import AIR, Medium
from ..core.radiation import _phi12, hertz_shape_pieces, pulse_response, pulse_response_function

__all__ = [
    "radiation_resistance",
    "pulse_spectrum",
    "radiated_energy_free",
    "surface_work_free",
    "radiated_energy_grid",
    "radiation_efficiency",
    "sound_power",
    "RunEnergy",
    "run_energy",
]

#: response tails are integrated until exp(-c t / a) < exp(-40)
_TAIL = 40.0


def radiation_resistance(omega, *, radius: float, medium: Medium = AIR) -> np.ndarray:
    """Mechanical radiation resistance of a rigid sphere oscillating along an axis, in N·s/m.

    ``R(ω) = (4π a²/3) ρ c (ka)⁴ / (4 + (ka)⁴)`` with ``k = ω/c``: the real part of the force on the
    sphere per unit velocity (paper eq 7 at ``r = a``, integrated over the surface with ``cos²θ``).

    Parameters
    ----------
    omega : array_like
        Angular frequency in rad/s.
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.
    """
    a = check_positive("radius", radius, "m")
    x4 = (np.asarray(omega, dtype=float) * a / medium.c) ** 4
    return (4.0 * math.pi * a * a / 3.0) * medium.rho * medium.c * x4 / (4.0 + x4)


def pulse_spectrum(pulse, omega) -> np.ndarray:
    """Fourier transform ``A(ω) = ∫ A(t) e^{-iωt} dt`` of an acceleration pulse, in m/s.

    Parameters
    ----------
    pulse : HalfSinePulse, HertzPulse or SampledPulse
        The pulse (m/s², starting at 0 s).
    omega : array_like
        Angular frequency in rad/s.

    Notes
    -----
    Half-sine ``A0 sin(πt/τ)``: ``A0 (π/τ)(1 + e^{-iωτ}) / ((π/τ)² - ω²)`` (its limit
    ``-i A0 τ/2`` at ``ω = π/τ``). Exact Hertz pulse: the transform of its polynomial pieces
    (:func:`acoustiviz.core.radiation.hertz_shape_pieces`, shape error < 1e-13 of the peak),
    each monomial moment ``∫_0^1 u^j e^{zu} du`` by 24-point Gauss-Legendre for ``|z| <= 8`` and
    by the recurrence ``M_j = (e^z - j M_{j-1})/z`` (stable there) above. Sampled: exact for the
    piecewise-linear pulse.
    """
    w = np.asarray(omega, dtype=float)
    if isinstance(pulse, HertzPulse):
        return _hertz_spectrum(pulse, w)
    if isinstance(pulse, HalfSinePulse):
        a0, tau = pulse.amplitude, pulse.duration
        w0 = math.pi / tau
        den = w0 * w0 - w * w
        near = np.abs(den) < 1e-9 * w0 * w0
        safe = np.where(near, 1.0, den)
        out = a0 * w0 * (1 + np.exp(-1j * w * tau)) / safe
        return np.where(near, -0.5j * a0 * tau, out)
    if isinstance(pulse, SampledPulse):
        t, acc = np.asarray(pulse.times, dtype=float), np.asarray(pulse.acceleration_samples, dtype=float)
        h = np.diff(t)
        slope = np.diff(acc) / h
        flat = w.reshape(-1)
        out = np.empty(flat.size, dtype=complex)
        step = max(1, 2**22 // h.size)  # bound the (frequencies x segments) work array
        for i in range(0, flat.size, step):
            wi = flat[i:i + step, None]
            p1, p2 = _phi12(-1j * wi * h)  # ∫_0^1 e^{zv} dv and ∫_0^1 (1 - v) e^{zv} dv
            seg = np.exp(-1j * wi * t[:-1]) * h * (acc[:-1] * p1 + slope * h * (p1 - p2))
            out[i:i + step] = seg.sum(axis=-1)
        return out.reshape(w.shape)
    raise ParameterError("pulse", f"expected a HalfSinePulse or SampledPulse, got {type(pulse).__name__}")


def _hertz_spectrum(pulse: HertzPulse, w: np.ndarray) -> np.ndarray:
    """Fourier transform of the exact Hertz pulse from its polynomial pieces (see :func:`pulse_spectrum`)."""
    breaks, coef = hertz_shape_pieces()
    tau, deg = float(pulse.duration), coef.shape[1] - 1
    lo, h = breaks[:-1] * tau, np.diff(breaks) * tau
    x, wq = np.polynomial.legendre.leggauss(24)
    u = 0.5 * (x + 1.0)
    wq = 0.5 * wq
    pu = coef @ (u[None, :] ** np.arange(deg + 1)[:, None])  # (pieces, nodes): the shape at the nodes
    flat = w.reshape(-1)
    out = np.empty(flat.size, dtype=complex)
    step = max(1, 2**20 // (h.size * u.size))
    for i in range(0, flat.size, step):
        wi = flat[i:i + step, None]
        z = -1j * wi * h[None, :]  # (freqs, pieces)
        small = np.abs(z) <= 8.0
        # small |z|: Gauss-Legendre on each piece
        quad = np.einsum("fpq,pq,q->fp", np.exp(z[..., None] * u), pu, wq)
        # large |z|: moments by forward recurrence, then the polynomial
        zs = np.where(small, 1.0, z)
        ez = np.exp(zs)
        m = (ez - 1.0) / zs
        rec = coef[None, :, 0] * m
        for j in range(1, deg + 1):
            m = (ez - j * m) / zs
            rec = rec + coef[None, :, j] * m
        piece = np.where(small, quad, rec) * h[None, :] * np.exp(-1j * wi * lo[None, :])
        out[i:i + step] = piece.sum(axis=-1)
    return pulse.amplitude * out.reshape(w.shape)


#: Frequency steps per period ``2π/τ`` of ``|A(ω)|²`` and per radiation corner ``c/a`` of ``R(ω)``.
_PER_PERIOD = 64
_PER_CORNER = 16
#: Above this many corners ``c/a`` the resistance is flat to ``4 (c/(ωa))⁴ < 1e-6``: only ``|A|²`` needs steps.
_CORNERS = 64


def _frequency_grid(pulse, radius: float, medium: Medium, n_per_period: int = _PER_PERIOD):
    """Angular frequencies (rad/s) fine enough to resolve ``|A(ω)|²`` and far enough to hold its energy.

    ``n_per_period`` steps per period ``2π/τ`` of ``|A|²`` up to ``ω_max = 400π / min(τ, a/c)``,
    beyond which the integrand falls off at least as ``ω⁻⁶``. One uniform grid; it also resolves the
    corner of ``R(ω)`` at ``c/a`` when :func:`_frequency_segments` keeps it whole.
    """
    tau = float(pulse.duration)
    wmax = 400.0 * math.pi / min(tau, radius / medium.c)
    n = int(n_per_period * wmax * tau / (2 * math.pi)) + 2001
    return np.linspace(0.0, wmax, n | 1)


def _frequency_segments(pulse, radius: float, medium: Medium) -> list:
    """Uniform grids (rad/s, odd sizes, end to end) on which Simpson's rule resolves ``R |A|² / ω²``.

    :func:`_frequency_grid` when its step is at most ``(c/a) / 16``, i.e. when the contact lasts
    longer than about ``1.4 a/c``. A shorter contact spreads ``|A|²`` so far that a step per period
    of it is too coarse for the resistance's corner ``ω = c/a`` (``R ∝ ω⁴`` below it, flat above):
    the band up to ``64 c/a`` is then stepped by ``(c/a)/16``, and only the rest by the period of
    ``|A|²``.
    """
    grid = _frequency_grid(pulse, radius, medium)
    corner = medium.c / radius
    if grid[1] <= corner / _PER_CORNER:
        return [grid]
    tau = float(pulse.duration)
    split = _CORNERS * corner  # below ω_max = 400π / min(τ, a/c), which is at least 400π c/a
    low = np.linspace(0.0, split, int(split / min(corner / _PER_CORNER, 2 * math.pi / (_PER_PERIOD * tau))) + 3 | 1)
    n = int(_PER_PERIOD * (grid[-1] - split) * tau / (2 * math.pi)) + 3
    return [low, np.linspace(split, float(grid[-1]), n | 1)]


def _half_sine_energy(pulse: HalfSinePulse, radius: float, medium: Medium) -> float:
    """:func:`radiated_energy_free` of a half-sine pulse in closed form (J), by residues.

    With ``b = c/a``, ``ω0 = π/τ``, ``K = (4π a²/3) ρ c`` and ``N(ω) = 2 K A0² ω0² ω²``, the
    integrand is ``g(ω) (1 + cos ωτ)`` with ``g = N / ((ω⁴ + 4 b⁴)(ω0² - ω²)²)`` (even in ω), so
    ``E = (1/2π) Re PV∫ g(ω)(1 + e^{iωτ}) dω`` over the real line. Closing in the upper half plane,
    the poles ``ω_k = b(±1 + i)`` give ``2πi N(ω_k)(1 + e^{iω_kτ}) / (4 ω_k³ (ω0² - ω_k²)²)``, and the
    simple poles left at ``±ω0`` (``1 + e^{iωτ}`` has a simple zero there) ``πi`` times their residues,
    ``2πτ N(ω0) / (4 ω0² (ω0⁴ + 4 b⁴))`` together.
    """
    a0, tau = float(pulse.amplitude), float(pulse.duration)
    w0 = math.pi / tau
    b = medium.c / radius
    c2 = 2.0 * (4.0 * math.pi * radius * radius / 3.0) * medium.rho * medium.c * a0 * a0 * w0 * w0  # N(ω) = c2 ω²
    upper = 0j
    for wk in (complex(b, b), complex(-b, b)):
        upper += c2 * (1.0 + np.exp(1j * wk * tau)) / (4.0 * wk * (w0 * w0 - wk * wk) ** 2)
    axis = tau * c2 / (4.0 * (w0**4 + 4.0 * b**4))  # (1/2π) πi Σ Res at ±ω0
    return float(-upper.imag + axis)  # (1/2π) Re(2πi Σ Res) = -Im Σ Res


def radiated_energy_free(pulse, *, radius: float, medium: Medium = AIR) -> float:
    """Acoustic energy in J radiated by a free rigid sphere under one acceleration pulse (closed form).

    Parameters
    ----------
    pulse : HalfSinePulse, HertzPulse or SampledPulse
        The sphere's acceleration in m/s² along its axis (:func:`acoustiviz.core.pulses.acceleration_pulse`).
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.

    Returns
    -------
    float
        ``E = (1/π) ∫_0^∞ R(ω) |A(ω)|² / ω² dω`` in J (:func:`radiation_resistance`,
        :func:`pulse_spectrum`). A half-sine pulse's in closed form, by residues
        (:func:`_half_sine_energy`); another pulse's by Simpson's rule on grids resolving both
        ``|A(ω)|²`` and the resistance's corner at ``c/a`` (:func:`_frequency_segments`), the
        neglected tail beyond ``ω = 400π / min(τ, a/c)`` falling off at least as ``ω⁻⁶``.

    Examples
    --------
    >>> from acoustiviz.core.contact import HalfSinePulse
    >>> e = radiated_energy_free(HalfSinePulse(1e5, 1e-4), radius=0.01905)
    >>> 0 < e < 1e-3
    True
    """
    from scipy.integrate import simpson

    a = check_positive("radius", radius, "m")
    if isinstance(pulse, HalfSinePulse):
        return _half_sine_energy(pulse, a, medium)
    total = 0.0
    for grid in _frequency_segments(pulse, a, medium):
        w = grid[1:] if grid[0] == 0.0 else grid
        integrand = radiation_resistance(w, radius=a, medium=medium) * np.abs(pulse_spectrum(pulse, w)) ** 2 / (w * w)
        if grid[0] == 0.0:  # the integrand vanishes like ω² at 0: prepend that point exactly
            integrand = np.concatenate([[0.0], integrand])
        total += float(simpson(integrand, dx=float(grid[-1] - grid[0]) / (grid.size - 1)))
    return total / math.pi


def _time_grid(pulse, radius: float, medium: Medium, t_min: float = 0.0, t_max: float = 0.0, per: int = 400):
    """Times in s covering ``[t_min, t_max + τ + tail]`` with ``per`` samples per ``min(τ, a/c)``."""
    tau = float(pulse.duration)
    step = min(tau, radius / medium.c) / per
    end = t_max + tau + _TAIL * radius / medium.c
    return np.arange(math.floor(t_min / step), math.ceil(end / step) + 1) * step


def surface_work_free(pulse, *, radius: float, medium: Medium = AIR) -> float:
    """The same energy in J as :func:`radiated_energy_free`, from the surface work in time.

    ``E = (4π a²/3) ∫ p(a, 0, t) v(t) dt - ½ m_a ΔV²`` with ``m_a = 2π ρ a³ / 3`` the entrained
    mass and ``ΔV`` the pulse's velocity change: the work done on the fluid less the kinetic
    energy of the steady flow that remains once the sphere moves at constant speed. The surface
    pressure is the paper's eq 11-13 response at ``r = a`` (``P0 = ρ c``, ``C = 1``).
    Trapezoidal in time; the subtraction costs digits when ``lτ`` is large.
    """
    from scipy.integrate import cumulative_trapezoid, trapezoid

    a = check_positive("radius", radius, "m")
    t = _time_grid(pulse, a, medium, per=2000)
    ps = medium.rho * medium.c * np.real(pulse_response(pulse, t, radius=a, medium=medium))
    v = cumulative_trapezoid(pulse.acceleration(t), t, initial=0.0)
    m_a = 2.0 * math.pi * medium.rho * a**3 / 3.0
    work = (4.0 * math.pi * a * a / 3.0) * trapezoid(ps * v, t)
    return float(work - 0.5 * m_a * v[-1] ** 2)


def radiated_energy_grid(pulse, sources, grid, *, radius: float, medium: Medium = AIR, chunk: int = 256) -> float:
    """Acoustic energy in J through a region of directions: far-field intensity over a spherical grid.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration of the real sphere (m/s²); every image moves with it along its own axis.
    sources : ImageSet or sequence of ImageSource
        The sphere and its images (:meth:`acoustiviz.core.geometry.Geometry.images`), each with its
        mirrored axis and reflection weight.
    grid : acoustiviz.field.grids.SphericalGrid
        Directions (``directions``), solid-angle weights in sr (``weights``) and ``centre`` in m;
        its radius does not enter (the intensity is taken at infinity).
    radius : float
        Sphere radius a in m.
    medium : Medium
        The fluid.
    chunk : int
        Directions evaluated at once (memory only).

    Returns
    -------
    float
        ``E = (1/ρc) Σ_i w_i ∫ q_i(t)² dt`` with the far-field ``q = r p`` in Pa·m:
        ``q_i(t) = ρ c a Σ_j g_j cos θ_ij Re[(1 + i) Y(t - τ_ij)]``, ``τ_ij = -(x_j - centre)·n_i / c``,
        ``g_j`` the image's reflection weight
        (paper eq 11 as ``r → ∞``, each image delayed by its path difference; eq 14).
    """
    from scipy.integrate import trapezoid

    a = check_positive("radius", radius, "m")
    imgs = ImageSet.of(sources)
    pos = imgs.positions - np.asarray(grid.centre, dtype=float)
    axes = imgs.weighted_axes  # an image's far field scales with its reflection weight
    dirs, weights = np.asarray(grid.directions, dtype=float), np.asarray(grid.weights, dtype=float)
    reach = float(np.max(np.linalg.norm(pos, axis=1))) / medium.c
    t = _time_grid(pulse, a, medium, -reach, reach, per=100)
    total = 0.0
    y_of = pulse_response_function(pulse, radius=a, medium=medium)  # the pulse's tables once
    for i0 in range(0, dirs.shape[0], int(chunk)):
        n = dirs[i0:i0 + chunk]
        delay = -(n @ pos.T) / medium.c  # (n_dir, n_src)
        cos = n @ axes.T
        q = np.zeros((n.shape[0], t.size))
        for j in range(pos.shape[0]):  # loop over the few sources, vectorised over directions and times
            # directions at the same delay (a ring about an axis through the source) share its response
            lag, ring = np.unique(delay[:, j], return_inverse=True)
            y = np.real((1 + 1j) * y_of(t[None, :] - lag[:, None]))
            q += cos[:, j:j + 1] * y[ring.reshape(-1)]
        q *= medium.rho * medium.c * a
        total += float(weights[i0:i0 + chunk] @ trapezoid(q * q, t, axis=1))
    return total / (medium.rho * medium.c)


def radiation_efficiency(radiated_energy, energy_lost) -> np.ndarray:
    """Radiated sound energy over the kinetic energy lost in the impact (dimensionless).

    Parameters
    ----------
    radiated_energy : array_like
        Acoustic energy in J.
    energy_lost : array_like
        Kinetic energy lost in the impact in J (> 0), e.g. ``ImpactTable.energy_lost``.
    """
    e = np.asarray(radiated_energy, dtype=float)
    lost = np.asarray(energy_lost, dtype=float)
    if np.any(~(lost > 0)):
        raise ParameterError("energy_lost", "must be > 0 J for every impact (an elastic impact loses none)")
    return e / lost


def sound_power(energies, duration: float) -> float:
    """Mean sound power in W of a run: the energy in J radiated by all its impacts over its duration in s."""
    d = check_positive("duration", duration, "s")
    e = np.asarray(energies, dtype=float)
    if np.any(~np.isfinite(e)) or np.any(e < 0):
        raise ParameterError("energies", "must be finite and >= 0 J")
    return float(e.sum() / d)


@dataclass(frozen=True)
class RunEnergy:
    """Acoustic energy of every impact of a damper run, its sound power and radiation efficiency.

    Attributes
    ----------
    energy_j : (n_impacts,) ndarray
        Energy radiated by each impact in J (into the geometry's half or quarter space).
    energy_lost_j : (n_impacts,) ndarray
        Kinetic energy lost in each impact in J (the dynamics' impact table).
    efficiency : (n_impacts,) ndarray
        ``energy_j / energy_lost_j``.
    sound_power_w : float
        Mean sound power over the run in W.
    loudest : int
        Index of the impact that radiates most.
    ratio_speeds_m_s, ratios : dict
        Per wall (-1, +1): the approach speeds in m/s at which the geometry's energy was
        integrated over the spherical grid, and its ratio to the free sphere's closed form there.
    """

    energy_j: np.ndarray
    energy_lost_j: np.ndarray
    efficiency: np.ndarray
    sound_power_w: float
    loudest: int
    ratio_speeds_m_s: dict
    ratios: dict

    @property
    def sound_power_level_db(self) -> float:
        """Sound power level in dB re 1 pW (:data:`~acoustiviz.constants.W_REF`)."""
        return 10.0 * math.log10(self.sound_power_w / W_REF) if self.sound_power_w > 0 else -math.inf


def run_energy(table, cavity_scene, model, duration: float, *, n_theta: int = 8) -> RunEnergy:
    """Radiated energy, sound power and radiation efficiency of a damper run.

    Parameters
    ----------
    table : acoustiviz.dynamics.ImpactTable
        The run's impacts (approach speeds, walls, energy lost).
    cavity_scene : acoustiviz.sound.CavityScene
        Where the cavity sits (geometry, walls, radius, medium); its ``sources(wall)`` gives
        the image sources of an impact on each wall.
    model : acoustiviz.sound.ClickModel
        How an approach speed becomes an acceleration pulse.
    duration : float
        The run's duration in s (for the mean power).
    n_theta : int
        Polar nodes of the spherical grid (see :func:`acoustiviz.field.grids.spherical_grid_for`).

    Notes
    -----
    Each impact's energy is the free sphere's closed form for its own pulse
    (:func:`radiated_energy_free`) times the ratio of the geometry's energy
    (:func:`radiated_energy_grid`, far-field intensity over the half or quarter
    sphere, with the struck or the far wall's images) to the free sphere's, integrated at the
    quartiles (and extremes) of that wall's approach speeds and interpolated in log speed: the
    ratio depends on the pulse only through its spectrum, which changes slowly with speed.

    Not defined in a room (a geometry that is ``enclosed``): its walls close the fluid and return
    the sound, so no surface around the sphere encloses an energy radiated away; refused with that
    reason (a ParameterError naming ``config``).
    """
    from ..field.grids import spherical_grid_for

    cavity_scene.geometry.enclosure()  # a room refuses here, saying why, before any work
    a, medium = cavity_scene.radius, cavity_scene.medium
    v = np.abs(np.asarray(table.approach_velocity, dtype=float))
    walls = np.asarray(table.wall, dtype=float).astype(int)
    free = np.array([radiated_energy_free(model.pulse_for(vk), radius=a, medium=medium) for vk in v])
    grid = spherical_grid_for(cavity_scene.geometry, 1.0, n_theta=n_theta)
    energy = free.copy()
    speeds, ratios = {}, {}
    for w in (-1, 1):
        sel = walls == w
        if not np.any(sel):
            continue
        ref = np.unique(np.percentile(v[sel], [0, 25, 50, 75, 100]))
        srcs = cavity_scene.sources(w)  # the wall's image sources (acoustiviz.sound.wall_sources)
        r = np.array([radiated_energy_grid(model.pulse_for(s), srcs, grid, radius=a, medium=medium)
                      / radiated_energy_free(model.pulse_for(s), radius=a, medium=medium) for s in ref])
        energy[sel] = free[sel] * (np.interp(np.log(v[sel]), np.log(ref), r) if ref.size > 1 else r[0])
        speeds[w], ratios[w] = ref.tolist(), r.tolist()
    lost = np.asarray(table.energy_lost, dtype=float)
    ok = lost > 0
    eff = np.full(energy.shape, np.nan)
    eff[ok] = radiation_efficiency(energy[ok], lost[ok])
    k = int(np.argmax(energy)) if energy.size else -1
    return RunEnergy(energy, lost, eff, sound_power(energy, duration), k, speeds, ratios)
