"""Field snapshots on planar sections: the pressure evaluated once, then drawn or written by every sink.

:func:`section_field` evaluates p(x, t) (:func:`acoustiviz.field.snapshots`) on the planar
sections through the sphere (:func:`section_planes`, cut at the floor and the walls) at a few
times and returns a :class:`SectionField`; a PNG render, a VTK file and an HTML page of the same
snapshot all take that one value, as a dataset is built once and then plotted or exported.
:func:`animation_field` does the same for the frames of a wavefront animation (:func:`frame_fields`
evaluates each frame only where a wave is passing).
Times in s from the start of contact, lengths in m, pressures in Pa.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_choice, check_positive
from ..constants import MAX_SNAPSHOT_TIMES
from ..core.geometry import Geometry
from ..core.medium import AIR, Medium
from . import evaluate
from .grids import SECTIONS, PlanarGrid, section_grid
from .sources import arrival_windows, source_geometry

__all__ = ["SectionField", "check_times", "section_planes", "section_grids", "section_field", "animation_times",
           "frame_fields", "animation_field"]


@dataclass(frozen=True)
class SectionField:
    """The pressure on planar sections at a few times.

    Attributes
    ----------
    grids : tuple of PlanarGrid
        The sections; points in m.
    times : (k,) ndarray
        Times in s from the start of contact.
    pressures : tuple of (k, n_i) ndarray
        Pressure in Pa at each time on the ``n_i`` points of each section (NaN inside the sphere).

    Built by :meth:`of` (from :func:`section_field` or an animation's frames), its arrays are
    read-only: a sink that wrote into them would change what the next sink draws.
    """

    grids: tuple
    times: np.ndarray
    pressures: tuple

    @classmethod
    def of(cls, grids, times, pressures) -> SectionField:
        """A field of ``grids``, a copy of ``times`` and the ``pressures`` themselves, all made read-only.

        Every sink shares the field and none may write it; the pressure arrays are taken over, not
        copied (they are large), so the caller passes arrays of its own.
        """
        tt = np.array(times, dtype=float)
        ps = tuple(np.asarray(p, dtype=float) for p in pressures)
        for a in (tt, *ps):
            a.setflags(write=False)
        return cls(tuple(grids), tt, ps)

    @property
    def points(self) -> np.ndarray:
        """Every section's points one after the other, ``(sum n_i, 3)`` in m."""
        return np.vstack([g.points for g in self.grids])


def check_times(time) -> np.ndarray:
    """The snapshot time(s) as a 1-D array in s, else an error naming ``time``.

    1 to :data:`~acoustiviz.constants.MAX_SNAPSHOT_TIMES` finite times >= 0.
    """
    times = np.atleast_1d(np.asarray(time, dtype=float))
    if times.ndim != 1 or times.size == 0 or times.size > MAX_SNAPSHOT_TIMES or not np.all(np.isfinite(times)) \
            or np.any(times < 0):
        raise ParameterError("time", f"expected 1 to {MAX_SNAPSHOT_TIMES} finite times >= 0 s, got {time!r}")
    return times


def section_planes(geometry, extent: float, *, sections=("xz",), n_u: int = 241) -> list:
    """Planar grids through the sphere for field snapshots, clipped to the fluid's bounding box.

    Parameters
    ----------
    geometry : acoustiviz.core.geometry.Geometry
        The scene.
    extent : float
        Distance in m from the sphere's centre to the far edges of each section.
    sections : sequence of {"xz", "yz", "xy"}
        ``"xz"``: the vertical plane ``y = 0`` (normal to the wall, holding the acceleration
        axis); ``"yz"``: the vertical plane through the centre parallel to the wall; ``"xy"``:
        the horizontal plane through the centre. Each is bounded by the floor and the wall
        (:func:`acoustiviz.field.grids.section_grid`).
    n_u : int
        Points along the longer side (>= 8).

    Returns
    -------
    list of PlanarGrid
    """
    e = check_positive("extent", extent, "m")
    if e <= 2.0 * geometry.radius:
        raise ParameterError("extent", f"must exceed the sphere's diameter {2 * geometry.radius:g} m, got {e:g} m")
    if isinstance(sections, str):
        sections = (sections,)
    if int(n_u) != n_u or n_u < 8:
        raise ParameterError("n_u", f"must be an integer >= 8, got {n_u!r}")
    out = []
    for s in sections:
        check_choice("sections", s, tuple(SECTIONS))
        out.append(section_grid(geometry, s, e, n_u))
    return out


def section_grids(geometry, planes, extent, times, medium: Medium, n_u: int, sections=("xz",)) -> list:
    """The grids of a snapshot: ``planes`` if given, else :func:`section_planes` reaching where sound is by ``times``.

    The default ``extent`` is 1.25 × the distance in m sound travels by the last time (plus the
    sphere's radius), at least eight sphere radii.
    """
    if planes is not None:
        ps = [planes] if isinstance(planes, PlanarGrid) else list(planes)
        if not ps or not all(isinstance(p, PlanarGrid) for p in ps):
            raise ParameterError("planes", "expected a PlanarGrid or a non-empty sequence of them")
        return ps
    if extent is None:
        reach = medium.c * float(np.max(times)) + geometry.radius
        extent = max(8.0 * geometry.radius, 1.25 * reach)
    return section_planes(geometry, extent, sections=sections, n_u=n_u)


def section_field(pulse, geometry, time, *, medium: Medium = AIR, planes=None, extent=None, sections=("xz",),
                  n_u: int = 241) -> SectionField:
    """Evaluate the pressure p(x, t) on planar sections at one or more times.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    geometry : acoustiviz.core.geometry.Geometry
        The scene.
    time : float or sequence of float
        Times in s from the start of contact (1 to :data:`~acoustiviz.constants.MAX_SNAPSHOT_TIMES`, each >= 0).
    medium : Medium
        The fluid.
    planes : PlanarGrid or sequence of PlanarGrid, optional
        Where to evaluate the field (default :func:`section_planes` with ``sections``).
    extent : float, optional
        Half-size in m of the default sections (default 1.25 × the distance sound travels by
        the last time, at least eight sphere radii).
    sections : sequence of {"xz", "yz", "xy"}
        Default sections (ignored with ``planes``).
    n_u : int
        Points along the longer side of each default section.

    Returns
    -------
    SectionField

    Examples
    --------
    >>> from acoustiviz import Impact, acceleration_pulse, geometry
    >>> pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=0.2264), "half-sine")
    >>> f = section_field(pulse, geometry("plane", 0.01905), [0.5e-3, 1e-3], n_u=41)
    >>> f.pressures[0].shape  # (times, points of the xz section)
    (2, 902)
    """
    times = check_times(time)
    grids = section_grids(geometry, planes, extent, times, medium, n_u, sections)
    fields = [evaluate.snapshots(pulse, times, g.points, geometry, medium=medium) for g in grids]
    return SectionField.of(grids, times, fields)


# --------------------------------------------------------------------------- animations
def animation_times(pulse, geometry: Geometry, points, *, medium: Medium = AIR, frames: int = 48) -> np.ndarray:
    """Frame times in s from the start of contact until the last wavefront crosses ``points``.

    The last time is the latest arrival, over the points and the image sources, of the end of
    the pulse ``max (r_j - a)/c + T``.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    geometry : Geometry
        The scene.
    points : (n, 3) array_like
        Points in m (e.g. the planar grids' points).
    medium : Medium
        The fluid.
    frames : int
        Number of frames (>= 2).

    Returns
    -------
    (frames,) ndarray
    """
    if int(frames) != frames or not 2 <= frames <= 2000:
        raise ParameterError("frames", f"must be an integer in [2, 2000], got {frames!r}")
    delay, _, _, _ = source_geometry(points, geometry, medium=medium)
    ok = geometry.in_fluid(points)
    end = float(np.max(delay[ok])) + pulse.duration
    return np.linspace(0.5 * pulse.duration, end, int(frames))


def frame_fields(pulse, geometry: Geometry, times, points, *, medium: Medium = AIR) -> np.ndarray:
    """Pressure (k, n) in Pa at ``times`` (k,), evaluating each frame only where it is non-zero.

    Points outside their arrival window at a frame time (:func:`acoustiviz.field.arrival_windows`)
    are set to zero without evaluation; points outside the fluid are NaN.
    """
    pts = np.asarray(points, dtype=float)
    tt = np.atleast_1d(np.asarray(times, dtype=float))
    start, stop = arrival_windows(pulse, pts, geometry, medium=medium)
    out = np.zeros((tt.size, pts.shape[0]))
    out[:, ~geometry.in_fluid(pts)] = np.nan
    for q, tq in enumerate(tt):
        live = (start <= tq) & (tq <= stop)
        if np.any(live):
            out[q, live] = evaluate.snapshots(pulse, [tq], pts[live], geometry, medium=medium)[0]
    return out


def animation_field(pulse, geometry: Geometry, *, medium: Medium = AIR, times=None, frames: int = 48, planes=None,
                    extent=None, sections=("xz",), n_u: int = 201, min_times: int = 2) -> SectionField:
    """Every frame of a wavefront animation: its grids, frame times and pressures, evaluated once.

    Parameters
    ----------
    pulse : HalfSinePulse or SampledPulse
        Acceleration pulse of the sphere.
    geometry : Geometry
        The scene.
    medium : Medium
        The fluid.
    times : (k,) array_like, optional
        Frame times in s (default :func:`animation_times` over the planes, ``frames`` of them).
    frames : int
        Number of frames when ``times`` is not given.
    planes, extent, sections, n_u
        Where the field is evaluated, as for :func:`section_field`.
    min_times : int
        Fewest frame times accepted in ``times`` (an animation needs two; a data file one).

    Returns
    -------
    acoustiviz.field.sections.SectionField
        Pressures in Pa by :func:`frame_fields` (zero where no wave has arrived or all have
        passed, NaN inside the sphere).
    """
    if times is None:
        grids = section_grids(geometry, planes, extent, [_reach_time(geometry, medium, extent)], medium, n_u, sections)
        times = animation_times(pulse, geometry, np.vstack([g.points for g in grids]), medium=medium, frames=frames)
    else:
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if times.ndim != 1 or times.size < min_times or not np.all(np.isfinite(times)):
            least = "at least two " if min_times == 2 else ""
            raise ParameterError("times", f"expected {least}finite frame times in s")
        grids = section_grids(geometry, planes, extent, times, medium, n_u, sections)
    fields = tuple(frame_fields(pulse, geometry, times, g.points, medium=medium) for g in grids)
    return SectionField.of(grids, times, fields)


def _reach_time(geometry: Geometry, medium: Medium, extent) -> float:
    """A time in s whose default extent frames the scene (used before the frame times exist)."""
    if extent is not None:
        return max(0.0, (float(extent) / 1.25 - geometry.radius) / medium.c)
    return max(12.0 * geometry.radius, 6.0 * geometry.feature_distance) / medium.c
