"""Auralised WAV files and their sidecars: one schema for every front-end.

``acoustiviz auralize`` and a scene's ``[outputs.wav]`` both write their files through
:func:`write_wav_files`, so the WAV data, the calibration and the JSON sidecar beside each file
(:func:`sidecar_record`, version :data:`SIDECAR_VERSION`) are the same whichever asked. The
sidecar records the software version, the scene (if any), the calibration in Pa per full scale,
the listeners, the peaks, whether anything clipped, how the sound was computed and the damper run.

Two peaks are recorded per channel, because they differ: ``physical_peak_pa``, the largest |p| of
the sound itself (each click in closed form, :func:`physical_peaks`), and ``peak_pa``, the largest
|sample| of the band-limited file at its rate times the calibration. Band-limiting a click of a few
hundred microseconds to 21.6 kHz (48 kHz files) moves its peak (the filter rings at the pulse's
kinks, the samples fall between the true maxima), so ``peak_pa`` is the level the file plays,
``physical_peak_pa`` the level the damper makes.

By default the files are normalised 24-bit PCM whose largest sample across the run lies
``headroom_db`` (1 dB) below full scale, so any player plays them without clipping; the sidecar's
``scale_pa_per_full_scale`` turns samples back into pascals (``acoustiviz levels`` reads it). The
float32 file in pascals (``subtype="FLOAT"``) stays available on request.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from .. import __version__
from ..core.geometry import GEOMETRIES
from ..core.signal import Signal
from ..errors import ClippingWarning, ParameterError
from ..output.audio import shared_scale, write_sidecar, write_wav
from ..sound.sources import cavity
from .settings.auralize import ROOM_SOUND_OPTIONS

__all__ = ["SIDECAR_VERSION", "WavFile", "cavity", "sidecar_record", "calibration", "write_wav_files",
           "check_scale_fits", "physical_peaks", "room_sound", "least_absorbing"]

#: Version of the sidecar schema; bumped whenever a key changes meaning (3: physical_peak_pa).
SIDECAR_VERSION = 3


def _enclosed(name) -> bool:
    """Whether the geometry registered as ``name`` closes the fluid (a room); False for an unknown name."""
    cls = GEOMETRIES.get(name)
    return bool(cls is not None and cls.enclosed)


def room_sound(*, late_tail: bool = False, seed=None, decay: str = "eyring", transition=None,
               absorption_bands=None, names=ROOM_SOUND_OPTIONS):
    """The :class:`~acoustiviz.sound.RoomSound` of a front-end's settings, or None when neither is asked for.

    Parameters
    ----------
    late_tail : bool
        The statistical tail after the transition time.
    seed : int, optional
        The tail's seed (default :data:`acoustiviz.constants.TAIL_SEED`).
    decay : {"eyring", "images"}
        The tail's decay law.
    transition : float, optional
        Transition time in s.
    absorption_bands : str, optional
        ``"F:A,F:A,..."`` or ``"F:A1/.../A6,..."`` (:func:`acoustiviz.sound.parse_absorption_bands`).
    names : mapping
        Parameter -> the user's option or key, named in errors.

    Returns
    -------
    RoomSound or None
        None without ``late_tail`` and ``absorption_bands``: the exact render, unchanged.
    """
    from ..constants import TAIL_SEED
    from ..sound import RoomSound, parse_absorption_bands
    from .names import user_terms

    if not late_tail and absorption_bands is None:
        return None
    centres = alpha = None
    if absorption_bands is not None:
        centres, alpha = parse_absorption_bands(absorption_bands, names["band_absorption"])
    with user_terms(names):
        return RoomSound(late_tail=bool(late_tail), seed=TAIL_SEED if seed is None else seed, decay=decay,
                         transition=transition, band_centres=centres, band_absorption=alpha)


def least_absorbing(band_absorption) -> list:
    """Each surface's smallest alpha over the bands of a ``(6, n_bands)`` absorption: the room's broadband one.

    The band that absorbs least decays slowest, so it sets the image order and the room's other
    outputs (the physical peak of the sidecar) use it.
    """
    return [float(x) for x in np.asarray(band_absorption, dtype=float).reshape(6, -1).min(axis=1)]


class WavFile:
    """One file to write: its path, its signal (Pa) and who hears each channel.

    Parameters
    ----------
    path : path-like
        The WAV file.
    signal : Signal
        Sound pressure in Pa, ``(n_channels, n_frames)`` (1-D for one channel), at the file's rate
        (a whole number of Hz).
    listeners : sequence of Listener
        Who hears each channel (name, position in m), one per channel.
    channel_names : sequence of str
        ``["mono"]`` or ``["left", "right"]``.
    """

    def __init__(self, path, signal: Signal, listeners, channel_names):
        if not isinstance(signal, Signal):
            raise ParameterError("signal", f"expected an acoustiviz.Signal, got {type(signal).__name__}")
        self.path = Path(path)
        self.signal = Signal(np.atleast_2d(signal.pressure), signal.sample_rate, start=signal.start)
        self.listeners = list(listeners)
        if len(self.listeners) != self.signal.channels:
            raise ParameterError("listeners", f"expected one Listener per channel ({self.signal.channels}), "
                                              f"got {len(self.listeners)}")
        self.channel_names = list(channel_names)

    @property
    def pressure(self) -> np.ndarray:
        """``(n_channels, n_frames)`` read-only sound pressure in Pa (the samples of :attr:`signal`)."""
        return self.signal.pressure

    @property
    def names(self) -> list:
        """The listeners' names, one per channel."""
        return [lst.name for lst in self.listeners]

    @property
    def positions(self) -> np.ndarray:
        """``(n_channels, 3)`` listener positions in m."""
        return np.array([lst.position for lst in self.listeners], dtype=float).reshape(-1, 3)


def calibration(files, subtype: str, *, scale=None, headroom_db: float = 1.0) -> tuple:
    """Pa per full scale for a set of files written together, and where it came from.

    ``FLOAT``: 1 Pa (the file holds pascals) unless ``scale`` is given. ``PCM_24``: ``scale`` if
    given, else the run's largest peak plus ``headroom_db`` dB, shared by every file of the run so
    that their levels compare.
    """
    if scale is not None:
        return float(scale), "given"
    if subtype == "PCM_24":
        return shared_scale([f.pressure for f in files], headroom_db=headroom_db), (
            f"shared by the {len(files)} file(s) of this run: their peak + {headroom_db:g} dB headroom")
    return 1.0, "pascals (1.0 = 1 Pa)"


def check_scale_fits(files, subtype: str, scale) -> None:
    """Refuse a given ``scale`` (Pa per full scale) that leaves the files silent or, in float32, infinite.

    The run's largest |p| over ``scale`` must reach one step of the format (2^-23 of full scale
    in 24-bit PCM, the smallest normal float32 in FLOAT), or the file holds only zeros; in FLOAT it
    must stay below float32's largest value, or the file holds infinities. (A PCM scale that clips
    is written and reported: its file still holds the sound, flattened.) A silent run, or no
    ``scale`` (the run's own peak sets it), passes.

    Raises
    ------
    ParameterError
        Named ``scale``, with the range of scales that fits this run.
    """
    if scale is None:
        return
    peak = max((float(np.max(np.abs(f.pressure), initial=0.0)) for f in files), default=0.0)
    if not peak > 0:
        return
    f32 = np.finfo(np.float32)
    step = 2.0**-23 if subtype == "PCM_24" else float(f32.tiny)
    high = peak / step
    low = 0.0 if subtype == "PCM_24" else peak / float(f32.max)
    ratio = peak / float(scale)
    if low < float(scale) <= high:
        return
    fmt = "24-bit PCM" if subtype == "PCM_24" else "float32"
    smallest = "smallest step" if subtype == "PCM_24" else "smallest normal number"
    what = (f"below the {fmt} file's {smallest}: the file would hold only zeros" if ratio < step
            else f"beyond the {fmt} file's largest value: the file would hold infinities")
    lo = "(0" if low == 0.0 else f"({low:.3g}"
    raise ParameterError("scale", f"{float(scale):g} Pa per full scale puts the run's peak of {peak:.4g} Pa "
                                  f"{ratio:.3g} of full scale, {what}; for this run it must lie in "
                                  f"{lo}, {high:.3g}] Pa, or be left out to normalise the file to its peak")


def physical_peaks(rendering, points=None, *, n_fastest: int = 4) -> np.ndarray:
    """Largest |p| in Pa of the sound of a rendered impact sequence at each point, not band-limited.

    Each click is evaluated in closed form by the field evaluator
    (:func:`acoustiviz.field.field_metrics`, paper eqs 12-14) for the sources of the wall it strikes
    (:func:`acoustiviz.sound.wall_sources`) and the pulse the renderer used
    (:meth:`acoustiviz.sound.ClickModel.pulse_for`). At a fixed point the peak of a click grows
    with its approach speed (:mod:`acoustiviz.sweep`), so per wall the ``n_fastest`` fastest distinct
    speeds are evaluated; if their peaks are not ordered like their speeds, every impact of the wall
    is. Clicks are taken one at a time: a click's sound lasts a few milliseconds (its arrivals, its
    contact and 40 decay times a/c), and a neighbour's tail overlapping it adds nothing measurable.

    Parameters
    ----------
    rendering : acoustiviz.sound.Rendering
        The rendered sequence (its impacts, cavity, click model and listeners).
    points : (n, 3) array_like, optional
        Where, in m (default the rendering's listeners).
    n_fastest : int
        Fastest distinct speeds evaluated per wall (0: every impact).

    Returns
    -------
    (n,) ndarray
        Peak pressure in Pa (0 without impacts).
    """
    from ..field import field_metrics
    from ..sound import wall_sources

    scene, model, seq = rendering.scene, rendering.model, rendering.sequence
    pts = np.asarray(rendering.listeners if points is None else points, dtype=float).reshape(-1, 3)
    base = scene.geometry
    if getattr(base, "enclosed", False):  # a room: the images that arrive with the clicks, not the reverberation
        scene = _early_room(scene, pts, model, seq)
        base = scene.geometry
    peak = np.zeros(pts.shape[0])
    for wall in (-1, 1):
        u = np.abs(np.asarray(seq.velocities, dtype=float)[np.asarray(seq.walls) == wall])
        u = np.unique(u[np.isfinite(u) & (u > 0)])[::-1]
        if u.size == 0:
            continue
        geometry = _room_wall(scene, wall) if getattr(base, "enclosed", False) else None
        if geometry is None:
            srcs = wall_sources(scene, wall)
            geometry = base.with_sources(srcs.sources() if hasattr(srcs, "sources") else srcs)

        def peaks_of(speeds, geometry=geometry):
            return np.array([field_metrics(model.pulse_for(v), pts, geometry, medium=scene.medium).peak
                             for v in speeds])

        k = u.size if n_fastest == 0 else min(int(n_fastest), u.size)
        rows = peaks_of(u[:k])
        if k < u.size and np.any(rows[1:] > rows[:-1] * (1 + 1e-9)):
            rows = np.vstack([rows, peaks_of(u[k:])])
        peak = np.maximum(peak, np.max(rows, axis=0))
    return peak


_OPPOSITE = {"x0": "x1", "x1": "x0", "y0": "y1", "y1": "y0", "z0": "z1", "z1": "z0", "floor": "ceiling",
             "ceiling": "floor"}


def _room_wall(scene, wall):
    """The sources of an impact on ``wall`` in a room as a room value (images in closed form), or None.

    The struck wall's are the room's own; the far wall's sphere, at the cavity's far centre with
    the axis reversed, is the same room's sphere striking the opposite surface (its images are
    those :func:`acoustiviz.sound.wall_sources` moves along their axes, to round-off). No
    conversion of the images into single sources. None where that sphere would leave the room.
    """
    import dataclasses

    from ..errors import ParameterError

    room = scene.geometry
    if wall == scene.struck_wall or scene.walls == "one":
        return room
    try:
        far = dataclasses.replace(room, source=tuple(float(x) for x in scene.far_centre),
                                  strike=_OPPOSITE[room.strike])
    except ParameterError:
        return None
    return far if np.allclose(far.direction, -np.asarray(scene.axis), atol=1e-12) else None


#: Keys of a rendering's description that are facts of the file written, taken from the file instead
#: (a train analysed at 96 kHz may be written at 48 kHz).
_FILE_FACTS = ("sample_rate_hz", "duration_s", "sample_rate")


def sidecar_record(wav: WavFile, info: dict, *, scale: float, scale_source: str,
                   rendering: dict, scene_name=None, damper=None, radius_source: str = "", levels=None,
                   physical_peak=None) -> dict:
    """The JSON sidecar of one WAV file (schema version :data:`SIDECAR_VERSION`).

    Parameters
    ----------
    wav : WavFile
        The file written.
    info : dict
        What :func:`acoustiviz.output.audio.write_wav` returned (the file's rate and length among it).
    scale : float
        Pa per full scale.
    scale_source : str
        Where the scale came from.
    rendering : dict
        :meth:`acoustiviz.sound.Rendering.describe` (sources, pulse, internal rate, ...).
    scene_name : str, optional
        The scene that asked for the file (None from the command line).
    damper : dict, optional
        The damper run (:func:`acoustiviz.app.damper.damper_description`) or the impacts file.
    radius_source : str
        Where the sphere radius came from.
    levels : dict, optional
        Weighted levels and bands (:meth:`acoustiviz.app.levels.LevelReport.describe`), recorded
        under ``levels``.
    physical_peak : (n_channels,) array_like, optional
        Peak in Pa of the sound itself at each channel's listener (:func:`physical_peaks`), recorded
        as ``physical_peak_pa`` (None when not given).
    """
    from ..field.metrics import spl_db

    peaks = np.max(np.abs(wav.pressure), axis=1)
    dbfs = [20 * math.log10(pk / scale) if pk > 0 else None for pk in peaks]
    spls = [spl_db(pk) if pk > 0 else None for pk in peaks]
    phys = None if physical_peak is None else [float(v) for v in np.ravel(physical_peak)]
    phys_spl = None if phys is None else [spl_db(v) if v > 0 else None for v in phys]
    return {
        "sidecar_version": SIDECAR_VERSION,
        "acoustiviz_version": __version__,
        "scene_name": scene_name,
        "file": wav.path.name,
        "subtype": info["subtype"],
        "sample_rate_hz": int(info["sample_rate_hz"]),
        "channels": info["channels"],
        "frames": info["frames"],
        "scale_pa_per_full_scale": scale,
        "scale_source": scale_source,
        "pressure_pa": "sample value x scale_pa_per_full_scale",
        "listeners": wav.names,
        "listeners_m": wav.positions.tolist(),
        "channel_names": wav.channel_names,
        "peak_pa": peaks.tolist(),
        "peak_spl_db_re_20upa": spls,
        "peak_dbfs": dbfs,
        "peak_note": "peak_pa: the largest |sample| of the band-limited file at its rate (before any "
                     "clipping) x scale; physical_peak_pa: the largest |p| of the sound itself, each click "
                     "in closed form, not band-limited",
        **({"physical_peak_note": f"room: over the direct clicks and the images arriving within "
                                  f"{ROOM_PEAK_WINDOW:g} s of them"}
           if _enclosed(rendering.get("scene", {}).get("config")) else {}),
        "physical_peak_pa": phys,
        "physical_peak_spl_db_re_20upa": phys_spl,
        "clipping": {"clipped_samples": info["clipped_samples"],
                     "peak_over_full_scale_db": info["over_full_scale_db"]},
        "impacts": rendering.get("impact_count"),
        "configuration": rendering.get("scene", {}).get("config"),
        # a room's image model, also at the top level: the order, the number of images, the neglected energy
        **{k: rendering["scene"][k] for k in ("image_order", "images", "neglected_energy_db", "late_tail",
                                              "transition_s")
           if k in rendering.get("scene", {})},
        # how the sound was made; what the file itself holds (rate, length) is stated above from the file
        **{k: v for k, v in rendering.items() if k not in _FILE_FACTS},
        "duration_s": info["frames"] / info["sample_rate_hz"],
        "damper": damper,
        "radius_source": radius_source,
        **({"levels": levels} if levels is not None else {}),
    }


#: A room's physical peak is taken over the images that arrive within this time in s of the first
#: arrival at each listener (the early reflections that can add to the direct click's peak).
ROOM_PEAK_WINDOW = 0.02


def _early_room(scene, pts, model, seq):
    """The cavity in the same room with only the images that arrive within :data:`ROOM_PEAK_WINDOW` s."""
    import dataclasses

    room = scene.geometry
    longest = max((model.pulse_for(v).duration for v in np.unique(seq.velocities) if v > 0), default=0.0)
    reach = float(np.max(np.linalg.norm(pts - room.centre, axis=1))) + scene.gap
    window = (reach - room.radius) / scene.medium.c + longest + ROOM_PEAK_WINDOW
    early = dataclasses.replace(room, order=None, tolerance_db=-200.0, duration=window)
    return dataclasses.replace(scene, geometry=early)


def write_wav_files(files, *, subtype: str = "PCM_24", scale=None, headroom_db: float = 1.0,
                    rendering, scene_name=None, damper=None, radius_source: str = "", levels=None) -> list:
    """Write WAV files and their sidecars with one shared calibration.

    Parameters
    ----------
    files : sequence of WavFile
        The files of one run, each with its signal at the file's rate.
    subtype : {"PCM_24", "FLOAT"}
        Sample format (see :func:`acoustiviz.output.audio.write_wav`): normalised 24-bit PCM (default,
        peak ``headroom_db`` below full scale) or float32 (in pascals unless ``scale`` is given).
    scale : float, optional
        Pa per full scale (default: :func:`calibration`).
    headroom_db : float
        ``PCM_24`` without ``scale``: the run's peak sits this far below full scale, in dB.
    rendering : acoustiviz.sound.Rendering or dict
        The rendering the files come from: its description is recorded in every sidecar, and
        (given the Rendering itself) the physical peak at each channel's listener
        (:func:`physical_peaks`); a description alone records ``physical_peak_pa`` as null.
    scene_name, damper, radius_source
        Recorded in every sidecar (:func:`sidecar_record`).
    levels : sequence of dict, optional
        Per file, its levels to record in its sidecar.

    Returns
    -------
    list of dict
        Per file: its ``record`` (the sidecar), the ``sidecar`` path and any ``warnings`` (str).
    """
    check_scale_fits(files, subtype, scale)
    scale, source = calibration(files, subtype, scale=scale, headroom_db=headroom_db)
    physical = [None] * len(files)
    if not isinstance(rendering, dict):
        physical = [physical_peaks(rendering, f.positions) for f in files]
        rendering = rendering.describe()
    written = []
    for k, wav in enumerate(files):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ClippingWarning)
            info = write_wav(wav.path, wav.signal, subtype=subtype, scale=scale)
        record = sidecar_record(wav, info, scale=scale, scale_source=source,
                                rendering=rendering, scene_name=scene_name, damper=damper,
                                radius_source=radius_source, levels=None if levels is None else levels[k],
                                physical_peak=physical[k])
        side = write_sidecar(wav.path, record)
        written.append({"record": record, "sidecar": side, "warnings": [str(w.message) for w in caught]})
    return written
