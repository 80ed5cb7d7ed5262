"""Calibrated WAV files and their JSON sidecars, written atomically."""

from __future__ import annotations

import io
import json
import math
import warnings
from pathlib import Path

import numpy as np

from ..._validate import ParameterError, check_choice, check_positive
from ...core.signal import Signal
from ...errors import ClippingWarning
from ...files import atomic_path, write_bytes_atomic

__all__ = [
    "SUBTYPES",
    "shared_scale",
    "write_wav",
    "write_sidecar",
    "sidecar_path",
]


#: WAV sample formats: float32 in Pa, or normalised 24-bit integers.
SUBTYPES = ("FLOAT", "PCM_24")


# --------------------------------------------------------------------------- files
def shared_scale(signals, *, headroom_db: float = 1.0) -> float:
    """One scale in Pa per full scale for all signals of a run (normalised PCM).

    Parameters
    ----------
    signals : iterable of array_like
        Pressure signals in Pa (any shapes).
    headroom_db : float
        The largest |p| of all signals lands this many dB below full scale (>= 0).

    Returns
    -------
    float
        Pa per full scale: a sample value v stands for ``v * scale`` Pa. 1.0 if all are silent.
    """
    hr = float(headroom_db)
    if not (math.isfinite(hr) and hr >= 0):
        raise ParameterError("headroom_db", f"must be finite and >= 0 dB, got {headroom_db!r}")
    peak = max((float(np.max(np.abs(np.asarray(s, dtype=float)), initial=0.0)) for s in signals), default=0.0)
    return peak * 10.0 ** (hr / 20.0) if peak > 0 else 1.0


def sidecar_path(wav_path) -> Path:
    """The JSON sidecar of a WAV file: ``OUT.json`` for ``OUT.wav``."""
    return Path(wav_path).with_suffix(".json")


def write_wav(path, signal: Signal, *, subtype: str = "FLOAT", scale: float = 1.0) -> dict:
    """Write a pressure signal to a WAV file atomically; return what was written.

    Parameters
    ----------
    path : path-like
        Output ``.wav`` file.
    signal : Signal
        Pressure in Pa, one or more channels, at a whole number of Hz (a WAV file stores the rate
        as an integer and no start time).
    subtype : {"FLOAT", "PCM_24"}
        ``"FLOAT"``: 32-bit float, sample value = pressure / scale (default scale 1: values in Pa;
        nothing is clipped, values beyond ±1 are stored as they are; a ``PEAK`` chunk holds each channel's
        peak, without the time of writing, so the bytes depend on the signal alone). ``"PCM_24"``: 24-bit
        integers of pressure / scale; samples beyond full scale are clipped with a :class:`ClippingWarning`.
    scale : float
        Pa per full scale (see :func:`shared_scale`).

    Returns
    -------
    dict
        ``path``, ``subtype``, ``channels``, ``frames``, ``sample_rate_hz``, ``pa_per_full_scale``,
        ``peak_full_scale`` (largest |sample| before any clipping), ``over_full_scale_db`` (dB by which it
        exceeds full scale, or 0), ``clipped_samples``.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     info = write_wav(Path(folder) / "click.wav", Signal([0.0, 0.5, -0.25], 48000))
    >>> info["frames"], info["sample_rate_hz"], info["peak_full_scale"]
    (3, 48000, 0.5)
    """
    import soundfile as sf

    check_choice("subtype", subtype, SUBTYPES)
    sc = check_positive("scale", scale, "Pa")
    if not isinstance(signal, Signal):
        raise ParameterError("signal", f"expected an acoustiviz.Signal (pressure in Pa with its sample rate in Hz), "
                                       f"got {type(signal).__name__}")
    fs = signal.sample_rate
    if fs != int(fs):
        raise ParameterError("sample_rate", f"a WAV file holds a whole number of Hz, got {fs!r}")
    p = signal.as_channels()
    data = (p / sc).T
    peak = float(np.max(np.abs(data), initial=0.0))
    over_db = 20.0 * math.log10(peak) if peak > 1.0 else 0.0
    clipped = 0
    if subtype == "PCM_24":
        top = 1.0 - 2.0**-23
        clipped = int(np.count_nonzero((data > top) | (data < -1.0)))
        if clipped:
            warnings.warn(f"{path}: {clipped} samples clipped at full scale ({scale:g} Pa); the peak was "
                          f"{over_db:.2f} dB over full scale", ClippingWarning, stacklevel=2)
            data = np.clip(data, -1.0, top)
        out = data
    else:
        out = data.astype(np.float32)
    # encoded in memory, written by Python: a full disk is an OSError naming the file, not a libsndfile error
    buf = io.BytesIO()
    sf.write(buf, out, int(fs), subtype=subtype, format="WAV")
    write_bytes_atomic(path, _without_clock(buf.getvalue()))
    return {"path": str(path), "subtype": subtype, "channels": int(p.shape[0]), "frames": int(p.shape[1]),
            "sample_rate_hz": int(fs), "pa_per_full_scale": sc, "peak_full_scale": peak,
            "over_full_scale_db": over_db, "clipped_samples": clipped}


def _without_clock(data: bytes) -> bytes:
    """The WAV file ``data`` with the time of writing in its ``PEAK`` chunk set to 0 (not given).

    libsndfile gives every float WAV a ``PEAK`` chunk: a version (4 bytes), the seconds since 1970 at which
    the file was written (4 bytes), then each channel's peak and its frame. That stamp made two writes of the
    same sound differ whenever they fell in different seconds; zeroed, the file depends on the sound alone
    (the peaks stay). A file without the chunk (24-bit PCM) is returned as it is.
    """
    out = bytearray(data)
    at = 12  # the chunks follow "RIFF", the file's size and "WAVE"
    while at + 8 <= len(out):
        size = int.from_bytes(out[at + 4:at + 8], "little")
        if out[at:at + 4] == b"PEAK" and size >= 8:
            out[at + 12:at + 16] = bytes(4)
            break
        at += 8 + size + (size & 1)  # chunks are padded to an even length
    return bytes(out)


def write_sidecar(wav_path, record: dict) -> Path:
    """Write ``record`` as JSON beside ``wav_path`` (``OUT.json`` for ``OUT.wav``), atomically."""
    path = sidecar_path(wav_path)
    text = json.dumps(_finite(record), indent=2, default=_json_default, allow_nan=False)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text + "\n", encoding="utf-8")
    return path


def _finite(obj):
    """``obj`` with arrays as lists and non-finite floats (a silent signal's -inf dB) as None."""
    if isinstance(obj, dict):
        return {str(k): _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [_finite(v) for v in (obj.tolist() if isinstance(obj, np.ndarray) else obj)]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _json_default(obj):
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
