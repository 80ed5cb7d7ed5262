"""A damper's sound in a shoebox room: exact early images, per-band absorption and a statistical tail.

:func:`acoustiviz.sound.render` sums every image of a room to the order its energy
tolerance needs (order 154, 4.9 million images, for a 6 x 4 x 3 m room with alpha = 0.1 at
-60 dB). Given a :class:`RoomSound` it renders the room differently:

* **Early part, exact.** The direct click of each impact in closed form, and every image that
  arrives before the transition time ``t_x`` through the fractional-delay trains of the exact
  render, each with its own near field, directivity and delay (paper eqs 12-14): the images of
  order ``<= N`` with ``complete_until(N) >= t_x`` hold every image that arrives before
  ``t_x`` (:func:`acoustiviz.core.reverberation.complete_until`), and those of them arriving
  later are left to the tail. Before ``t_x`` the signal is the exact render's.
* **Late part, statistical** (``late_tail=True``): from ``t_x`` on, one room impulse response per
  listener, Gaussian noise from a seeded generator shaped per band to the decay of the
  reverberation (Eyring's by default, from the image sum's expected level at ``t_x``:
  :func:`acoustiviz.core.tail.late_tail`), until the energy left is below the
  tolerance of the total (:func:`acoustiviz.core.tail.tail_end`). It is convolved (FFT)
  with the far-field click train: far from the sphere an image's pressure is
  ``w cos(theta) rho c a (Re Y - Im Y) / r``, and over the many directions of the late images
  ``<cos^2 theta> = 1/3``. The far wall's sphere accelerates the other way, so its impacts
  drive the same response with the opposite sign.
* **Absorption per octave band** (``band_centres``, ``band_absorption``): each image's weight in
  band b is the product of ``sqrt(1 - alpha_b)`` of the surfaces it was reflected in; the
  images' trains are built per band and split by zero-phase masks that sum to one
  (:func:`acoustiviz.core.tail.band_masks`), and the tail decays per band. The direct
  sound is not reflected and stays broadband.

The transition time is ``max(sqrt(V) ms, t_d)`` by default: Polack's mixing time and the time
``t_d`` at which reflections arrive on average once per contact duration (the shortest click's,
:func:`acoustiviz.core.reverberation.echo_density_time`), after which the clicks of successive
reflections overlap; it is cut down to what ``max_images`` exact images reach.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice, check_range
from ..constants import TAIL_SEED
from ..core.signal import Signal
from .synthesis import (
    _SINC_HALF,
    _SINC_STEPS,
    _TAIL_DECADES,
    Rendering,
    _oversampling,
    _sinc_table,
    _train_kernel,
    decimation_filter,
)

__all__ = ["RoomSound", "TAIL_SEED", "parse_absorption_bands", "render_room"]

#: Default budget of exact images (the real sphere included) per wall before the tail takes over.
MAX_EXACT_IMAGES = 100_000
#: Band centres in Hz accepted for a per-band absorption.
BAND_RANGE_HZ = (16.0, 20000.0)
#: Width in octaves of the crossovers between absorption bands (:func:`~acoustiviz.core.tail.band_masks`).
CROSSOVER_OCTAVES = 0.5


@dataclass(frozen=True, eq=False)
class RoomSound:
    """How a room is heard in a WAV: the statistical tail and the absorption per octave band.

    Parameters
    ----------
    late_tail : bool
        Compute the images exactly only until the transition time and continue with a
        statistical tail until the energy tolerance (default False: every image to the
        tolerance, as without a RoomSound).
    seed : int
        Seed of the tail's random generator (>= 0); listener i draws from ``(seed, i)``.
    decay : {"eyring", "images"}
        The tail's decay: Eyring's T60 per band (default) or the image sum's own expected decay
        (:func:`acoustiviz.core.tail.tail_decay_rate`).
    transition : float, optional
        Transition time in s from the start of contact (default: module docstring).
    max_images : int
        Largest number of exact images per wall (>= 1); the transition comes earlier when
        the order it needs has more.
    tolerance_db : float, optional
        Energy left out relative to the total in dB, in ``[-200, 0)`` (default: the room's,
        -60 dB).
    band_centres : (n_bands,) array_like, optional
        Centre frequencies in Hz of the absorption bands, increasing, in [16, 20000].
    band_absorption : (n_bands,) or (6, n_bands) array_like, optional
        Energy absorption coefficient alpha in [0, 1) per band, for every surface or per
        surface (x0, x1, y0, y1, z0 floor, z1 ceiling); replaces the room's broadband
        absorption on the WAV path.
    """

    late_tail: bool = False
    seed: int = TAIL_SEED
    decay: str = "eyring"
    transition: float | None = None
    max_images: int = MAX_EXACT_IMAGES
    tolerance_db: float | None = None
    band_centres: tuple | None = None
    band_absorption: np.ndarray | None = None

    def __post_init__(self):
        if not isinstance(self.late_tail, (bool, np.bool_)):
            raise ParameterError("late_tail", f"expected true or false, got {self.late_tail!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise ParameterError("seed", f"must be an integer >= 0, got {self.seed!r}")
        check_choice("decay", self.decay, ("eyring", "images"))
        if self.transition is not None:
            object.__setattr__(self, "transition", check_range("transition", self.transition, 0.0, 10.0,
                                                               unit="s", low_open=True))
        if isinstance(self.max_images, bool) or not isinstance(self.max_images, (int, np.integer)) \
                or self.max_images < 1:
            raise ParameterError("max_images", f"must be an integer >= 1, got {self.max_images!r}")
        if self.tolerance_db is not None:
            object.__setattr__(self, "tolerance_db", check_range("tolerance_db", self.tolerance_db, -200.0, 0.0,
                                                                 unit="dB", high_open=True))
        if (self.band_centres is None) != (self.band_absorption is None):
            raise ParameterError("band_absorption", "give band_centres and band_absorption together")
        if self.band_centres is not None:
            c, a = _check_bands(self.band_centres, self.band_absorption, "band_centres", "band_absorption")
            object.__setattr__(self, "band_centres", tuple(float(x) for x in c))
            object.__setattr__(self, "band_absorption", a)

    def check_room(self, room) -> None:
        """Refuse what this room cannot give, before any work (a ParameterError naming the parameter).

        ``room``: the :class:`~acoustiviz.core.room_geometry.Room`. A tail needs a room that decays
        (absorption > 0 on some surface in every band; ``late_tail``), and a given image order must
        be complete at some time after the start (``order`` >= 3) to hand over to it.
        """
        from ..core.reverberation import complete_until

        if not self.late_tail:
            return
        # the band that absorbs least, at its most absorbing surface: zero means no decay at all
        worst = float(self.band_absorption.max(axis=0).min()) if self.banded else float(np.max(room.absorption))
        if worst <= 0.0:
            raise ParameterError("late_tail", "needs absorption > 0 on some surface (in every band): a rigid room "
                                              "does not decay")
        if self.transition is None and room.order is not None and \
                complete_until(room.shoebox, room.order, radius=room.radius) <= 0.0:
            raise ParameterError("order", f"with a late tail the exact images must be complete until some time: "
                                          f"an order >= 3, got {room.order}")

    def render_scene(self, sequence, scene, model, pts, fs: int, duration, oversampling):
        """:func:`render_room` with these settings (what :func:`acoustiviz.sound.render` calls)."""
        return render_room(sequence, scene, model, pts, fs, duration, oversampling, self)

    @property
    def banded(self) -> bool:
        """Whether the absorption is given per band."""
        return self.band_centres is not None

    def describe(self) -> dict:
        """The settings, JSON-ready (frequencies in Hz, times in s)."""
        out = {"late_tail": bool(self.late_tail), "tail_seed": int(self.seed), "tail_decay": self.decay,
               "transition_given_s": self.transition, "max_exact_images": int(self.max_images)}
        if self.banded:
            out["absorption_bands_hz"] = list(self.band_centres)
            out["absorption_per_band"] = self.band_absorption.T.tolist()
            out["band_split"] = f"zero-phase complementary masks, {CROSSOVER_OCTAVES:g}-octave raised-sine crossovers"
        return out


def _check_bands(centres, absorption, c_name: str, a_name: str):
    """Band centres (Hz) and their absorption as ``(n_bands,)`` and ``(6, n_bands)`` arrays, or an error."""
    lo, hi = BAND_RANGE_HZ
    try:
        c = np.asarray(centres, dtype=float).reshape(-1)
        a = np.asarray(absorption, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(c_name, f"expected band centres in Hz and one alpha per band, got {centres!r}") from None
    if c.size < 1 or not np.all(np.isfinite(c)) or np.any(c < lo) or np.any(c > hi) or np.any(np.diff(c) <= 0):
        raise ParameterError(c_name, f"band centres must be increasing frequencies in [{lo:g}, {hi:g}] Hz, "
                                     f"got {centres!r}")
    if a.shape == (c.size,):
        a = np.tile(a, (6, 1))
    if a.shape != (6, c.size):
        raise ParameterError(a_name, f"expected one alpha per band ({c.size}) or six per band, got shape {a.shape}")
    if not np.all(np.isfinite(a) & (a >= 0.0) & (a < 1.0)):
        bad = float(a[~(np.isfinite(a) & (a >= 0.0) & (a < 1.0))][0])
        raise ParameterError(a_name, f"each energy absorption coefficient alpha must lie in [0, 1), got {bad:g}")
    a = a.copy()
    a.setflags(write=False)
    return c, a


def parse_absorption_bands(text: str, option: str = "--absorption-bands"):
    """Band centres (Hz) and absorption ``(6, n_bands)`` from ``"125:0.1,250:0.15,..."``.

    Each comma-separated item is ``F:A`` (band centre F in Hz, alpha A in [0, 1) on every
    surface) or ``F:A1/A2/A3/A4/A5/A6`` (one alpha per surface x0, x1, y0, y1, z0 floor,
    z1 ceiling); centres increasing in [16, 20000] Hz. Errors name ``option``.
    """
    items = [s.strip() for s in str(text).split(",") if s.strip()]
    form = "F:A or F:A1/.../A6 items, e.g. 125:0.1,250:0.15,500:0.2"
    if not items:
        raise ParameterError(option, f"expected {form}, got {text!r}")
    centres, rows = [], []
    for item in items:
        f, sep, vals = item.partition(":")
        try:
            centres.append(float(f))
            rows.append([float(v) for v in vals.split("/")])
        except ValueError:
            raise ParameterError(option, f"expected {form}, got {item!r}") from None
        if not sep or len(rows[-1]) not in (1, 6):
            raise ParameterError(option, f"expected {form}, got {item!r}")
    if len({len(r) for r in rows}) != 1:
        raise ParameterError(option, "give one alpha per band or six per band, the same in every band")
    a = np.array(rows, dtype=float).T  # (1 or 6, n_bands)
    try:
        return _check_bands(centres, a[0] if a.shape[0] == 1 else a, option, option)
    except ParameterError as exc:
        raise ParameterError(option, exc.detail) from None


# --------------------------------------------------------------------------- the plan
@dataclass(frozen=True)
class _Plan:
    order: int
    transition: float | None  # s; None: no tail
    tail_end: float | None
    neglected_db: float
    box: object  # the Shoebox (banded or not)
    note: str


def _plan(geometry, rs: RoomSound, shortest_click: float, medium) -> _Plan:
    """The exact image order, the transition time and the tail's end."""
    from ..core.reverberation import complete_until, echo_density_time, energy_order, mixing_time
    from ..core.room import Shoebox, image_count, max_order_for_memory
    from ..core.tail import tail_end

    a = geometry.radius
    box = Shoebox(geometry.dimensions, rs.band_absorption) if rs.banded else geometry.shoebox
    tol = geometry.tolerance_db if rs.tolerance_db is None else rs.tolerance_db
    cap = max_order_for_memory(bands=box.bands)
    if geometry.order is not None and not rs.late_tail:
        return _Plan(geometry.order, None, None, geometry.neglected_energy_db, box, "image order given")
    need = energy_order(box, tol, radius=a, medium=medium, duration=geometry.duration, max_order=cap)
    if not rs.late_tail:
        return _Plan(need.order, None, None, need.neglected_db, box, "images to the tolerance")
    if rs.transition is None and geometry.order is not None:  # the given order, complete until complete_until(N)
        n_x = geometry.order
        t_x = complete_until(box, n_x, radius=a, medium=medium)
    else:
        t_x = rs.transition if rs.transition is not None else max(
            mixing_time(box), echo_density_time(box, shortest_click, medium=medium))
        n_x = 2 + math.ceil((medium.c * t_x + a) / box.lattice_spacing)  # complete_until(n_x) >= t_x
    n_budget = 0
    while image_count(n_budget + 1) <= rs.max_images:
        n_budget += 1
    if need.order <= min(n_x, n_budget) and not need.capped:
        return _Plan(need.order, None, None, need.neglected_db, box, "no tail needed: the exact images reach "
                                                                        "the tolerance before the transition")
    if n_budget < n_x:
        n_x = n_budget
        t_x = complete_until(box, n_x, radius=a, medium=medium)
        note = f"transition moved earlier to what max_images = {rs.max_images} exact images reach"
    else:
        note = "transition: the given time" if rs.transition is not None else (
            "transition: where the given image order is complete" if geometry.order is not None else
            "transition: max(mixing time sqrt(V) ms, one reflection per contact duration)")
    if t_x <= 0:
        given = geometry.order is not None and rs.transition is None and n_x == geometry.order
        name = "order" if given else "max_images"
        raise ParameterError(name, f"the exact images to order {n_x} are complete at no time after the start in "
                                   "this room; allow more (an order of 3 or more)")
    end, neg = tail_end(box, t_x, tol, decay=rs.decay, medium=medium)
    return _Plan(n_x, t_x, end, neg, box, note)


# --------------------------------------------------------------------------- rendering
def render_room(sequence, scene, model, pts, fs: int, duration, oversampling, rs: RoomSound):
    """:func:`acoustiviz.sound.render` of a scene in a room with a :class:`RoomSound` (arguments checked)."""
    from ..field.sources import image_geometry
    from .sources import wall_sources

    geometry = scene.geometry
    if not getattr(geometry, "enclosed", False):
        raise ParameterError("room_sound", f"only for a scene in a room (a geometry that closes the fluid), "
                                           f"got {geometry.name!r}")
    if not isinstance(rs, RoomSound):
        raise ParameterError("room_sound", f"expected a RoomSound, got {type(rs).__name__}")
    a, medium = scene.radius, scene.medium
    pulses = [model.pulse_for(v) for v in sequence.velocities]
    taus = np.array([p.duration for p in pulses]) if pulses else np.array([1.0])
    plan = _plan(geometry, rs, float(taus.min()), medium)
    ordered = dataclasses.replace(geometry, order=plan.order)  # the exact images to the planned order
    scene2 = dataclasses.replace(scene, geometry=ordered)
    L = _oversampling(fs, taus, oversampling)
    h = decimation_filter(L)
    half = (h.size - 1) // (2 * L)
    f_int = float(L * fs)
    tail = _TAIL_DECADES * math.log(10.0) * a / medium.c
    grid = (fs, L, f_int, h, half, tail)

    walls = [w for w in (-1, 1) if np.any(sequence.walls == w)]
    srcs = {w: wall_sources(scene2, w) for w in (-1, 1)}
    ratio = _band_ratios(ordered, plan.box) if rs.banded else None
    geom, trains = {}, {}
    for w in (-1, 1):
        s = srcs[w]
        delay, p0, c_shape, _ = image_geometry(pts, type(s)(s.positions[:1], s.axes[:1], s.weights[:1],
                                                           s.orders[:1], s.labels[:1]), a, medium=medium)
        geom[w] = (delay, p0 * c_shape)
        if w in walls and len(s) > 1:
            trains[w] = _early_trains(pts, s, delay[:, 0], ratio, plan, rs, a, medium, fs)
    last = float(np.max(sequence.times + taus)) if len(sequence) else 0.0
    end = last + tail + max([float(geom[w][0].max()) for w in walls]
                            + [tr[2] + float(geom[w][0].max()) for w, tr in trains.items()]
                            + [plan.tail_end or 0.0]) if walls else 0.0
    n_out = max(math.ceil(end * fs) + half + 1, math.ceil((duration or 0.0) * fs))
    out = np.zeros((pts.shape[0], n_out))
    dry = _clicks(out, sequence, pulses, geom, grid, a, medium)
    for w, (q0, tr, _) in trains.items():
        _add_early(out, [d for d in dry if d[0] == w], q0, tr)
    tail_info = None
    if plan.transition is not None and walls:
        sign = {w: float(np.sign(srcs[w].axes[0] @ srcs[scene.struck_wall].axes[0])) for w in (-1, 1)}
        shift = {w: np.rint(geom[w][0][:, 0] * fs).astype(int) for w in (-1, 1)}
        tail_info = _add_tail(out, dry, sign, shift, plan, rs, a, medium, fs)
    info = _describe(plan, rs, tail_info, len(srcs[scene.struck_wall]))
    out.flags.writeable = False  # finished: the Signal takes it without a copy
    return Rendering(Signal(out, fs), f_int, pts, sequence, scene2, model, info)


def _band_ratios(geometry, box) -> np.ndarray:
    """``(n_images, n_bands)`` band weight over broadband weight of each image: ``prod_s (beta_bs / beta_s)^n_s``."""
    refl = geometry.room_images().reflections.astype(float)  # (n, 6), the same lattice order for both walls
    lg = np.log(box.reflection) - np.log(geometry.shoebox.reflection)[:, None]  # (6, n_bands)
    return np.exp(refl @ lg)


def _early_trains(pts, srcs, direct, ratio, plan, rs, radius, medium, fs):
    """The images after the direct sound arriving before the transition, as fractional-delay trains.

    As :func:`acoustiviz.sound.synthesis._trains`, the images cut at the transition time,
    each placed at its delay after the direct sound's (``direct``, s, per listener): the trains
    drive the click evaluated at the direct sound's exact arrival. Per band (weights times
    ``ratio``) and split by :func:`~acoustiviz.core.tail.band_masks` when the absorption
    is banded. Returns ``(q0, trains (n_listeners, 2, size), last delay after the direct sound s)``.
    """
    from ..core.images import ImageSet
    from ..core.tail import band_masks
    from ..field.sources import image_geometry

    rest = ImageSet(srcs.positions[1:], srcs.axes[1:], srcs.weights[1:], srcs.orders[1:], srcs.labels[1:])
    delay, p0, c_shape, _ = image_geometry(pts, rest, radius, medium=medium)
    weight = p0 * c_shape
    keep = np.ones(delay.shape, dtype=bool) if plan.transition is None else delay < plan.transition
    if not np.any(keep):
        keep[:, 0] = True  # an empty train: one image with no weight
        weight = np.where(keep, 0.0, weight)
    rel = delay - direct[:, None]  # >= 0: an image is farther than the sphere it mirrors
    d_min, d_max = float(rel[keep].min()), float(rel[keep].max())
    # room for the band filters' zero-phase ringing, both sides: four periods of the lowest crossover
    pad = 0 if ratio is None else math.ceil(4.0 * fs / min(rs.band_centres[0] * 1.414, rs.band_centres[-1]))
    q0 = math.floor(d_min * fs) - _SINC_HALF - 1 - pad
    size = math.ceil(d_max * fs) - q0 + _SINC_HALF + 2 + pad
    nb = 1 if ratio is None else ratio.shape[1]
    out = np.zeros((pts.shape[0], 2, size))
    table = _sinc_table()
    for i in range(pts.shape[0]):
        k = keep[i]
        pos = np.ascontiguousarray(rel[i, k] * fs - q0)
        per = np.zeros((nb, 2, size))
        for b in range(nb):
            wb = weight[i, k] if ratio is None else weight[i, k] * ratio[1:][k, b]
            _train_kernel(per[b, 0], per[b, 1], pos, np.ascontiguousarray(wb.real), np.ascontiguousarray(wb.imag),
                          table, _SINC_HALF, _SINC_STEPS)
        if ratio is None:
            out[i] = per[0]
        else:
            masks = band_masks(np.fft.rfftfreq(size, 1.0 / fs), rs.band_centres, transition_octaves=CROSSOVER_OCTAVES)
            spec = np.einsum("bf,bpf->pf", masks, np.fft.rfft(per, axis=-1))
            out[i] = np.fft.irfft(spec, size, axis=-1)
    return q0, out, d_max


def _decimate_rows(rows, h, L: int) -> list:
    """``convolve(x, h)[::L]`` of each row, computed for the outputs kept only (polyphase, FFT).

    Every row starts on an output sample (its first internal sample is ``n0 L``), so
    ``z[q] = sum_m x[m] h[q L - m] = sum_p (x_p * g_p)[q]`` with the phases
    ``x_p[j] = x[j L + p]`` and ``g_p[i] = h[i L - p]``: L short convolutions at the output rate,
    summed in the frequency domain (one batched real FFT per batch of rows; no BLAS threads).
    """
    import scipy.fft as sfft

    lh = h.size
    n_i = -(-(lh + L - 1) // L)
    k = np.arange(n_i)[None, :] * L - np.arange(L)[:, None]  # (L, n_i): i L - p
    g = np.where((k >= 0) & (k < lh), h[np.clip(k, 0, lh - 1)], 0.0)
    out = []
    for b0 in range(0, len(rows), _BATCH):
        chunk = rows[b0:b0 + _BATCH]
        n_j = -(-max(x.size for x in chunk) // L)
        m = sfft.next_fast_len(n_j + n_i - 1, real=True)
        x = np.zeros((len(chunk), n_j * L))
        for j, r in enumerate(chunk):
            x[j, :r.size] = r
        phases = x.reshape(len(chunk), n_j, L).transpose(0, 2, 1)  # (rows, L, n_j)
        spec = np.einsum("rpf,pf->rf", sfft.rfft(phases, m, axis=-1), sfft.rfft(g, m, axis=-1))
        z = sfft.irfft(spec, m, axis=-1)
        out += [z[j, :-(-(r.size + lh - 1) // L)] for j, r in enumerate(chunk)]
    return out


def _clicks(out, sequence, pulses, geom, grid, radius, medium) -> list:
    """Add each impact's direct click in closed form; return the clicks that drive the images.

    Per impact and listener ``Y`` is evaluated once in closed form at the exact retarded times
    of the direct sound, ``t - t_k - (r_0 - a)/c``, on the internal grid, and ``Re Y`` and
    ``Im Y`` are band-limited and decimated (batched). The direct click is
    ``Re W_0 Re Y - Im W_0 Im Y`` (``W_0 = P0 C`` of the sphere, paper eqs 12-14); the images'
    trains, placed at their delays after the direct sound's, take ``Re Y`` and ``Im Y``.
    Returns ``[(wall, listener, lo, z (2, m))]``, sample ``lo + j`` holding ``z[:, j]``, cut to
    the signal.
    """
    from ..core.radiation import pulse_response

    fs, L, f_int, h, half, tail = grid
    n_out = out.shape[1]
    rows, places = [], []
    for k, pulse in enumerate(pulses):
        tk, w = float(sequence.times[k]), int(sequence.walls[k])
        delay_all = geom[w][0]
        for i in range(out.shape[0]):
            d0 = float(delay_all[i, 0])
            n0 = math.floor((tk + d0) * fs)
            idx = np.arange(n0 * L, math.ceil((tk + d0 + pulse.duration + tail) * f_int) + 1)
            y = pulse_response(pulse, (idx - tk * f_int) / f_int - d0, radius=radius, medium=medium)
            rows += [y.real, y.imag]
            places.append((w, i, n0 - half))
    zs = _decimate_rows(rows, h, L)
    dry = []
    for j, (w, i, lo) in enumerate(places):
        z = np.stack([zs[2 * j], zs[2 * j + 1]])
        s0, s1 = max(lo, 0), min(lo + z.shape[1], n_out)
        if s1 <= s0:
            continue
        z = z[:, s0 - lo:s1 - lo]
        w0 = complex(geom[w][1][i, 0])
        out[i, s0:s1] += w0.real * z[0] - w0.imag * z[1]
        dry.append((w, i, s0, z))
    return dry


_BATCH = 256


def _add_early(out, dry, q0, tr) -> None:
    """Add ``Re Y * train_re - Im Y * train_im`` of each click (batched FFTs; the exact render's sum)."""
    import scipy.fft as sfft

    if not dry:
        return
    n_out = out.shape[1]
    size = tr.shape[-1]
    lz = max(z.shape[1] for _, _, _, z in dry)
    m = sfft.next_fast_len(lz + size - 1, real=True)
    for i in range(out.shape[0]):
        ft = sfft.rfft(tr[i], m, axis=-1)
        mine = [d for d in dry if d[1] == i]
        for b0 in range(0, len(mine), _BATCH):
            chunk = mine[b0:b0 + _BATCH]
            z = np.zeros((2, len(chunk), lz))
            for j, (_, _, _, zz) in enumerate(chunk):
                z[:, j, :zz.shape[1]] = zz
            fz = sfft.rfft(z, m, axis=-1)
            wet = sfft.irfft(fz[0] * ft[0] - fz[1] * ft[1], m, axis=-1)
            for j, (_, _, lo, zz) in enumerate(chunk):
                n = zz.shape[1] + size - 1
                s0, s1 = max(lo + q0, 0), min(lo + q0 + n, n_out)
                if s1 > s0:
                    out[i, s0:s1] += wet[j, s0 - lo - q0:s1 - lo - q0]


def _add_tail(out, dry, sign, shift, plan, rs, radius, medium, fs) -> dict:
    """Convolve each listener's far-field click train with its statistical tail (one FFT convolution each).

    The click train is ``rho c a (Re Y - Im Y)`` of every impact (the far-field click at 1 m on
    the axis), signed by the wall's direction and moved back by the direct sound's delay
    (``shift``, whole samples) so that it starts at the impact; the tail's sample m lies at
    ``t_k + m_x / fs + m / fs``.
    """
    from ..core.tail import late_tail

    n_out = out.shape[1]
    m_x = math.ceil(plan.transition * fs)
    start = m_x / fs
    length = max(plan.tail_end - start, 1.0 / fs)
    n_tail = int(round(length * fs))
    rca = medium.rho * medium.c * radius
    scale = math.sqrt(1.0 / 3.0)  # <cos^2 theta> of the dipole over the late images' directions
    for i in range(out.shape[0]):
        drive = np.zeros(n_out, dtype=np.float32)
        for w, li, lo, z in dry:
            if li != i:
                continue
            at = lo - int(shift[w][i])
            s0 = max(at, 0)
            drive[s0:at + z.shape[1]] += ((sign[w] * rca) * (z[0] - z[1]))[s0 - at:]
        rng = np.random.default_rng([int(rs.seed), i])
        h = scale * late_tail(plan.box, start, length, fs, rng, band_centres=rs.band_centres, medium=medium,
                              decay=rs.decay, transition_octaves=CROSSOVER_OCTAVES if rs.banded else 0.0)
        # single precision: the tail is a random signal; its FFT round-off (1e-7) is below a 24-bit file's step
        wet = _overlap_add(drive, h.astype(np.float32))
        s1 = min(m_x + wet.size, n_out)
        if s1 > m_x:
            out[i, m_x:s1] += wet[:s1 - m_x]
    return {"samples": n_tail, "start_s": start}


def _overlap_add(x: np.ndarray, h: np.ndarray) -> np.ndarray:
    """``convolve(x, h)`` by overlap-add in blocks of about eight times ``h`` (FFT), in the dtype of x."""
    import scipy.fft as sfft

    m = sfft.next_fast_len(max(8 * h.size, 1024), real=True)
    step = m - h.size + 1
    nb = -(-x.size // step)
    xp = np.zeros(nb * step, dtype=x.dtype)
    xp[:x.size] = x
    y = sfft.irfft(sfft.rfft(xp.reshape(nb, step), m, axis=-1) * sfft.rfft(h, m), m, axis=-1)
    out = np.zeros(nb * step + h.size - 1, dtype=x.dtype)
    blocks = out[:nb * step].reshape(nb, step)  # a view
    blocks[:] = y[:, :step]
    blocks[1:, :h.size - 1] += y[:-1, step:step + h.size - 1]  # each block's overlap into the next (h < step)
    out[nb * step:] += y[-1, step:step + h.size - 1]
    return out[:x.size + h.size - 1]


def _describe(plan, rs, tail_info, images) -> dict:
    """What the sidecar records of the room's sound: the exact order, the transition and the tail."""
    from ..core.reverberation import reverberation_time

    neg = plan.neglected_db
    t60 = reverberation_time(plan.box, "eyring")
    out = {"image_order": int(plan.order), "images": int(images),
           "late_tail": plan.transition is not None,
           "transition_s": plan.transition,
           "tail_end_s": plan.tail_end,
           "neglected_energy_db": None if math.isnan(neg) else (neg if math.isfinite(neg) else "-inf"),
           "eyring_t60_s": np.atleast_1d(t60).tolist() if rs.banded else float(t60),
           "note": plan.note, **rs.describe()}
    if tail_info is not None:
        out["tail"] = {"samples": tail_info["samples"], "start_s": tail_info["start_s"],
                       "model": "Gaussian noise shaped per band to the decay, times sqrt(1/3) (the dipole's "
                                "mean cos^2 over the late images' directions), convolved with the far-field click "
                                "rho c a (Re Y - Im Y); the far wall's impacts with the opposite sign"}
    return out
