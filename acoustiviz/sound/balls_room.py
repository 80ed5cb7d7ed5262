"""The room's images of the spheres of several balls: shared by nearby spheres, summed as a single ball's.

A room's image set depends on where its sphere is, so each sphere of a multi-ball run has its own
(:meth:`acoustiviz.core.room_geometry.Room.image_sources`, to the room's order and tolerance, moved
exactly from a known set when the sphere moved along its own axis). The spheres of one radius and
axis whose centres round to the same point of a grid of :data:`POSITION_STEP` share the images of the
first of them; each keeps its own direct sound. The images are summed as :func:`acoustiviz.sound.render`
sums a room's: the few exactly, the many (more than ``TRAIN_ABOVE``) through fractional-delay trains,
one set of trains per group of spheres, made, used and dropped in turn (the cost grows with the number
of groups times the images, the memory with the images of one group).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from ..core.images import ImageSet
from .synthesis import _TRAIN_BLOCK, TRAIN_ABOVE, _add_trains, _trains

__all__ = ["POSITION_STEP", "RoomGroups"]

#: Step in m of the grid a sphere's position is rounded to when the spheres of a room share its images: the
#: images of a group are those of its first sphere, the others lying within this step along each axis of it
#: (an arrival error below 0.5 microseconds, a phase error below 0.07 rad at 20 kHz).
POSITION_STEP = 1e-4


class RoomGroups:
    """The spheres of a multi-ball rendering in a room grouped by place, with their images.

    Attributes
    ----------
    group : (n,) ndarray of int
        The group of each click.
    firsts : list of int
        The click whose sphere's images each group takes.
    exact : dict
        Group -> its images (an :class:`ImageSet` without the real sphere) summed exactly, for the
        groups of ``TRAIN_ABOVE`` sources or fewer (none: the real sphere alone, image order 0).
    last : dict
        Group -> the latest arrival in s of its images (``(r - a)/c``), for the groups summed by trains.
    """

    def __init__(self, clicks, geometry, pts: np.ndarray, radii: np.ndarray, medium):
        self.geometry, self.medium = geometry, medium
        keys, self.group, self.firsts, self.exact, self.last = {}, np.zeros(len(clicks), dtype=np.int64), [], {}, {}
        for k, srcs in enumerate(clicks.sources):
            real = srcs[0]
            key = (tuple(np.rint(real.position / POSITION_STEP).astype(np.int64).tolist()), real.axis.tobytes(),
                   float(radii[k]))
            if key not in keys:
                keys[key] = g = len(self.firsts)
                self.firsts.append(k)
                imgs = self._images(clicks, g)
                if len(imgs) > TRAIN_ABOVE:
                    self.last[g] = _last_arrival(pts, imgs, float(radii[k]), medium.c)
                elif len(imgs) > 1:
                    self.exact[g] = ImageSet(imgs.positions[1:], imgs.axes[1:], imgs.weights[1:], imgs.orders[1:],
                                             tuple(imgs.labels[1:]))
            self.group[k] = keys[key]
        self.clicks = clicks

    def _images(self, clicks, g: int) -> ImageSet:
        return self.geometry.image_sources(clicks.sources[self.firsts[g]][0])

    def sources(self, k: int) -> ImageSet:
        """Click ``k``'s sphere at its own place and the images summed exactly of its group."""
        real = self.clicks.sources[k][0]
        rest = self.exact.get(int(self.group[k]))
        if rest is None:
            return ImageSet(real.position[None, :], real.axis[None, :], np.array([real.weight]), np.array([0]),
                            (real.label,))
        return ImageSet(np.vstack([real.position, rest.positions]), np.vstack([real.axis, rest.axes]),
                        np.concatenate([[real.weight], rest.weights]), np.concatenate([[0], rest.orders]),
                        (real.label, *rest.labels))

    def end(self, times: np.ndarray, taus: np.ndarray, tails: np.ndarray) -> float:
        """The end in s of the latest image of every click summed by trains (0 without any)."""
        return max([float(times[k] + taus[k] + tails[k]) + self.last[int(self.group[k])]
                    for k in range(len(times)) if int(self.group[k]) in self.last], default=0.0)

    def add_trains(self, out: np.ndarray, pts: np.ndarray, radii: np.ndarray, grid_of) -> None:
        """Add the images of every group summed by trains (``grid_of(a)``: the rendering grid of radius a)."""
        for g in self.last:
            k0 = self.firsts[g]
            a = float(radii[k0])
            trains = _trains(pts, self._images(self.clicks, g), a, self.medium, grid_of(a)[0])
            sel = np.flatnonzero(self.group == g)
            pulses = [self.clicks.pulses[k] for k in sel]
            if sel.size * trains[1].shape[-1] < out.shape[1]:  # a few clicks: each over its own span
                _add_click_trains(out, self.clicks.times[sel], pulses, trains, grid_of(a), a, self.medium)
            else:  # many: the group's clicks through the trains at once, over the whole signal
                order = SimpleNamespace(times=self.clicks.times[sel], walls=np.zeros(sel.size, dtype=np.int64))
                _add_trains(out, order, pulses, {0: trains}, grid_of(a), a, self.medium)

    def describe(self) -> dict:
        """JSON-ready: how the room was applied to the spheres."""
        return {"model": "each sphere with the room's images of its own position (the room's order and tolerance), "
                         f"the spheres within {POSITION_STEP:g} m of each other sharing their images (each its own "
                         "direct sound), summed as one ball's (the first images exactly, the rest through "
                         "fractional-delay trains)",
                "sphere_groups": len(self.firsts), "position_step_m": POSITION_STEP}


def _add_click_trains(out, times, pulses, trains, grid, a: float, medium) -> None:
    """Add each click through the trains ``(q0, trains, last)``, convolved over the click's own span.

    The sum of :func:`acoustiviz.sound.synthesis._add_trains` (``Re W Re Y - Im W Im Y`` of every image),
    each click's band-limited ``Y`` convolved with the trains alone rather than the whole signal's.
    """
    from scipy.signal import fftconvolve

    from ..core.radiation import pulse_response
    from .synthesis import _filter_decimate

    q0, tr, _ = trains
    fs, L, f_int, _, half, tail = grid
    n_out = out.shape[1]
    for tk, pulse in zip(times, pulses, strict=True):
        tk = float(tk)
        n0 = math.floor(tk * fs)
        idx = np.arange(n0 * L, math.ceil((tk + pulse.duration + tail) * f_int) + 1)
        y = pulse_response(pulse, (idx - tk * f_int) / f_int, radius=a, medium=medium)
        z_re, z_im = _filter_decimate(y.real, L), _filter_decimate(y.imag, L)
        lo = n0 - half + q0
        for i in range(out.shape[0]):
            wet = fftconvolve(z_re, tr[i, 0]) - fftconvolve(z_im, tr[i, 1])
            s0, s1 = max(lo, 0), min(lo + wet.size, n_out)
            if s1 > s0:
                out[i, s0:s1] += wet[s0 - lo:s1 - lo]


def _last_arrival(pts: np.ndarray, imgs: ImageSet, radius: float, c: float) -> float:
    """Latest ``(r - a)/c`` in s of the sources ``imgs`` at the points ``pts`` (m), in blocks."""
    far = 0.0
    for lo in range(0, len(imgs), _TRAIN_BLOCK):
        r = np.linalg.norm(pts[:, None, :] - imgs.positions[None, lo:lo + _TRAIN_BLOCK, :], axis=-1)
        far = max(far, float(r.max()))
    return (far - radius) / c if math.isfinite(far) else 0.0
