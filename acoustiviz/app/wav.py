"""Auralised WAV files and their sidecars: one schema for every front-end.

``acoustiviz auralize`` and a scene's ``[outputs.wav]`` both write their files through
:func:`write_wav_files`, so the WAV data, the calibration and the JSON sidecar beside each file
(:func:`sidecar_record`, version :data:`SIDECAR_VERSION`) are the same whichever asked. The
sidecar records the software version, the scene (if any), the calibration in Pa per full scale,
the listeners, the peaks, whether anything clipped, how the sound was computed and the damper run.

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
from ..constants import P_REF
from ..errors import ClippingWarning
from ..output.audio import CavityScene, shared_scale, write_sidecar, write_wav
from .impacts import surroundings

__all__ = ["SIDECAR_VERSION", "WavFile", "cavity", "sidecar_record", "calibration", "write_wav_files"]

#: Version of the sidecar schema; bumped whenever a key changes meaning.
SIDECAR_VERSION = 2


def cavity(config: str, radius: float, gap: float, *, struck_wall: int = -1, walls: str = "both",
           wall_distance=None, strike: str = "floor", height=None, medium=None) -> CavityScene:
    """The damper's cavity in its surroundings (:func:`acoustiviz.app.impacts.surroundings` resolves them)."""
    wall_distance, strike, height = surroundings(radius, config, wall_distance, strike, height)
    extra = {} if medium is None else {"medium": medium}
    return CavityScene(config, radius, gap, struck_wall=struck_wall, walls=walls, wall_distance=wall_distance,
                       strike=strike, height=height, **extra)


class WavFile:
    """One file to write: its path, its channels (Pa) and who hears them.

    Parameters
    ----------
    path : path-like
        The WAV file.
    pressure : (n_channels, n_frames) array_like
        Sound pressure in Pa at the output rate.
    listeners : sequence of str
        Listener names, one per channel.
    positions : (n_channels, 3) array_like
        Listener positions in m.
    channel_names : sequence of str
        ``["mono"]`` or ``["left", "right"]``.
    """

    def __init__(self, path, pressure, listeners, positions, channel_names):
        self.path = Path(path)
        self.pressure = np.atleast_2d(np.asarray(pressure, dtype=float))
        self.listeners = list(listeners)
        self.positions = np.asarray(positions, dtype=float).reshape(-1, 3)
        self.channel_names = list(channel_names)


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


def sidecar_record(wav: WavFile, info: dict, *, sample_rate: int, scale: float, scale_source: str,
                   rendering: dict, scene_name=None, damper=None, radius_source: str = "", levels=None) -> dict:
    """The JSON sidecar of one WAV file (schema version :data:`SIDECAR_VERSION`).

    Parameters
    ----------
    wav : WavFile
        The file written.
    info : dict
        What :func:`acoustiviz.output.audio.write_wav` returned.
    sample_rate : int
        Output rate in Hz.
    scale : float
        Pa per full scale.
    scale_source : str
        Where the scale came from.
    rendering : dict
        :meth:`acoustiviz.output.audio.Rendering.describe` (sources, pulse, internal rate, ...).
    scene_name : str, optional
        The scene that asked for the file (None from the command line).
    damper : dict, optional
        The damper run (:func:`acoustiviz.app.damper.damper_description`) or the impacts file.
    radius_source : str
        Where the sphere radius came from.
    levels : dict, optional
        Weighted levels and bands (:meth:`acoustiviz.app.levels.LevelReport.describe`), recorded
        under ``levels``.
    """
    peaks = np.max(np.abs(wav.pressure), axis=1)
    dbfs = [20 * math.log10(pk / scale) if pk > 0 else None for pk in peaks]
    spls = [20 * math.log10(pk / P_REF) if pk > 0 else None for pk in peaks]
    return {
        "sidecar_version": SIDECAR_VERSION,
        "acoustiviz_version": __version__,
        "scene_name": scene_name,
        "file": wav.path.name,
        "subtype": info["subtype"],
        "sample_rate_hz": int(sample_rate),
        "channels": info["channels"],
        "frames": info["frames"],
        "scale_pa_per_full_scale": scale,
        "scale_source": scale_source,
        "pressure_pa": "sample value x scale_pa_per_full_scale",
        "listeners": wav.listeners,
        "listeners_m": wav.positions.tolist(),
        "channel_names": wav.channel_names,
        "peak_pa": peaks.tolist(),
        "peak_spl_db_re_20upa": spls,
        "peak_dbfs": dbfs,
        "peak_note": "peaks of the band-limited samples at the output rate",
        "clipping": {"clipped_samples": info["clipped_samples"],
                     "peak_over_full_scale_db": info["over_full_scale_db"]},
        "impacts": rendering.get("impact_count"),
        "configuration": rendering.get("scene", {}).get("config"),
        **rendering,
        "damper": damper,
        "radius_source": radius_source,
        **({"levels": levels} if levels is not None else {}),
    }


def write_wav_files(files, *, sample_rate: int, subtype: str = "PCM_24", scale=None, headroom_db: float = 1.0,
                    rendering: dict, scene_name=None, damper=None, radius_source: str = "", levels=None) -> list:
    """Write WAV files and their sidecars with one shared calibration.

    Parameters
    ----------
    files : sequence of WavFile
        The files of one run.
    sample_rate : int
        Output rate in Hz.
    subtype : {"PCM_24", "FLOAT"}
        Sample format (see :func:`acoustiviz.output.audio.write_wav`): normalised 24-bit PCM (default,
        peak ``headroom_db`` below full scale) or float32 (in pascals unless ``scale`` is given).
    scale : float, optional
        Pa per full scale (default: :func:`calibration`).
    headroom_db : float
        ``PCM_24`` without ``scale``: the run's peak sits this far below full scale, in dB.
    rendering, scene_name, damper, radius_source
        Recorded in every sidecar (:func:`sidecar_record`).
    levels : sequence of dict, optional
        Per file, its levels to record in its sidecar.

    Returns
    -------
    list of dict
        Per file: its ``record`` (the sidecar), the ``sidecar`` path and any ``warnings`` (str).
    """
    scale, source = calibration(files, subtype, scale=scale, headroom_db=headroom_db)
    written = []
    for k, wav in enumerate(files):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ClippingWarning)
            info = write_wav(wav.path, wav.pressure, sample_rate, subtype=subtype, scale=scale)
        record = sidecar_record(wav, info, sample_rate=sample_rate, scale=scale, scale_source=source,
                                rendering=rendering, scene_name=scene_name, damper=damper,
                                radius_source=radius_source, levels=None if levels is None else levels[k])
        side = write_sidecar(wav.path, record)
        written.append({"record": record, "sidecar": side, "warnings": [str(w.message) for w in caught]})
    return written
