"""Levels of a calibrated WAV file or a computed signal, and the two CSV files that report them.

``acoustiviz levels SIGNAL.wav`` reads the file, its calibration (Pa per full scale, from the JSON
sidecar ``SIGNAL.json`` that :mod:`acoustiviz.app.wav` writes, else given), and reports per channel
the weighted levels of :func:`acoustiviz.levels.sound_levels`, the 1/3-octave bands of
:func:`acoustiviz.levels.third_octave_levels` and, on request, loudness and sharpness
(:func:`acoustiviz.levels.loudness`). The same :func:`analyse` serves the damper's auralisation,
which evaluates the levels on the signal computed at :data:`ANALYSIS_RATE` rather than on the file.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._validate import ParameterError, check_positive
from ..constants import ANALYSIS_RATE
from ..core.signal import Signal
from ..levels import LEVEL_COLUMNS, BandLevels, Loudness, SoundLevels, loudness, third_octave_levels
from .settings.levels import LevelsJob

__all__ = ["ANALYSIS_RATE", "file_summary", "silent_notes", "LevelsJob", "LevelsResult", "run", "job_from_wav",
           "CalibratedSignal", "LevelReport", "read_calibrated_wav", "analyse",
           "bands_path", "write_levels_csv", "write_spectrum_csv", "summary_lines", "rendered_levels"]



@dataclass(frozen=True)
class CalibratedSignal:
    """Pressure read from a WAV file and where its calibration came from.

    Attributes
    ----------
    signal : Signal
        Sound pressure in Pa, ``(n_channels, n_samples)``, at the file's rate in Hz, from 0 s.
    pa_per_full_scale : float
        The calibration applied: a sample value v is ``v × pa_per_full_scale`` Pa.
    source : str
        ``"sidecar <path>"`` or ``"given"``.
    channels : list of str
        Channel names (from the sidecar, else ``"1"``, ``"2"``, ...).
    """

    signal: Signal
    pa_per_full_scale: float
    source: str
    channels: list


def _sidecar_scale(wav: Path):
    """``(scale, sidecar record)`` from ``wav``'s JSON sidecar, or ``(None, None)`` if there is none."""
    from ..output.audio import sidecar_path

    side = sidecar_path(wav)
    if not side.is_file():
        return None, None
    try:
        record = json.loads(side.read_text(encoding="utf-8"))
        scale = float(record["scale_pa_per_full_scale"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ParameterError("signal", f"cannot read the calibration from the sidecar {side}: {exc}") from None
    if not (math.isfinite(scale) and scale > 0):
        raise ParameterError("signal", f"the sidecar {side} records scale_pa_per_full_scale = {scale!r}, not > 0 Pa")
    return scale, record


#: Margin on the squared pressure's sums (samples x the filters' gains) kept from float64's range.
_ENERGY_MARGIN = 1e4
#: The facts a sidecar records about its file, checked against the file: key -> (soundfile attribute, unit).
_FILE_FACTS = {"sample_rate_hz": ("samplerate", " Hz"), "channels": ("channels", ""), "frames": ("frames", "")}


def calibration_range(data) -> tuple:
    """The calibrations in Pa per full scale whose levels of ``data`` stay finite: ``(low, high)``.

    The levels square the pressure and sum it over the samples (through filters of modest gain):
    ``(peak × scale)² × samples`` must stay within float64's range, with :data:`_ENERGY_MARGIN`
    to spare, and the peak's square must not underflow. ``data``: ``(n_samples, n_channels)``
    sample values; a silent file takes any calibration.
    """
    peak = float(np.max(np.abs(data), initial=0.0))
    if not (peak > 0 and math.isfinite(peak)):
        return 0.0, math.inf
    fi = np.finfo(float)
    high = math.sqrt(fi.max / (max(1, data.shape[0]) * _ENERGY_MARGIN)) / peak
    low = math.sqrt(fi.tiny * _ENERGY_MARGIN) / peak
    return low, high


def _check_sidecar(side: Path, record: dict, wav: Path, info) -> None:
    """Refuse a sidecar whose rate, channels or frames contradict the file it describes."""
    for key, (attr, unit) in _FILE_FACTS.items():
        if key not in record:
            continue
        said, found = record[key], getattr(info, attr)
        if isinstance(said, bool) or not isinstance(said, (int, float)) or said != found:
            raise ParameterError("signal", f"the sidecar {side} records {key} = {said!r}, but {wav.name} has "
                                           f"{found}{unit}: it describes another file; remove or correct it")


def _check_scale(scale: float, data, wav: Path, source: str) -> None:
    """Refuse a calibration for which the levels of ``data`` would overflow or underflow."""
    low, high = calibration_range(data)
    if low <= scale <= high:
        return
    what = "overflow" if scale > high else "underflow to silence"
    peak = float(np.max(np.abs(data)))
    if source == "given":
        raise ParameterError("pa_per_fs", f"{scale:g} Pa per full scale makes the levels of {wav.name} {what} "
                                          f"(peak {peak:.3g} of full scale, {data.shape[0]} frames): it must "
                                          f"lie in [{low:.3g}, {high:.3g}] Pa for this file")
    raise ParameterError("signal", f"the {source} records scale_pa_per_full_scale = {scale:g}, which makes the "
                                   f"levels of {wav.name} {what}: it must lie in [{low:.3g}, {high:.3g}] Pa")


def read_calibrated_wav(path, *, pa_per_fs=None) -> CalibratedSignal:
    """Read a WAV file as pressure in Pa.

    Parameters
    ----------
    path : path-like
        The WAV file.
    pa_per_fs : float, optional
        Pa per full scale, used when the file has no sidecar (``SIGNAL.json`` beside
        ``SIGNAL.wav``); with a sidecar its ``scale_pa_per_full_scale`` is used.

    Raises
    ------
    ParameterError
        ``signal`` if the file cannot be read or its sidecar's ``sample_rate_hz``, ``channels``
        or ``frames`` contradict it; ``pa_per_fs`` if there is neither a sidecar nor a
        calibration, or if the calibration lies outside :func:`calibration_range` (the levels
        would overflow or underflow).
    """
    import soundfile as sf

    wav = Path(path)
    if pa_per_fs is not None:
        check_positive("pa_per_fs", pa_per_fs, "Pa")
    scale, record = _sidecar_scale(wav)
    if scale is not None:
        source = f"sidecar {wav.with_suffix('.json').name}"
    elif pa_per_fs is not None:
        scale, source = float(pa_per_fs), "given"
    else:
        raise ParameterError("pa_per_fs", f"{wav.name} has no sidecar {wav.with_suffix('.json').name}: give the "
                                          "calibration in Pa per full scale (> 0)")
    try:
        if record is not None:
            _check_sidecar(wav.with_suffix(".json"), record, wav, sf.info(str(wav)))
        data, fs = sf.read(str(wav), dtype="float64", always_2d=True)
    except (OSError, RuntimeError, sf.LibsndfileError) as exc:
        raise ParameterError("signal", f"cannot read {wav}: {exc}") from None
    bad = int(np.size(data) - np.count_nonzero(np.isfinite(data)))
    if bad:
        raise ParameterError("signal", f"{wav.name} holds {bad} sample(s) that are not finite numbers (inf or nan)")
    _check_scale(scale, data, wav, source)
    names = None
    if record is not None and isinstance(record.get("channel_names"), list) \
            and len(record["channel_names"]) == data.shape[1]:
        names = [str(n) for n in record["channel_names"]]
    return CalibratedSignal(Signal(data.T * scale, int(fs)), scale, source,
                            names or [str(i + 1) for i in range(data.shape[1])])


@dataclass(frozen=True)
class LevelReport:
    """Everything :func:`analyse` found for one signal."""

    levels: SoundLevels
    bands: BandLevels
    loudness: Loudness | None
    channels: list

    def subset(self, indices) -> LevelReport:
        """The report of the channels ``indices`` only."""
        from dataclasses import fields, replace

        idx = list(indices)

        def pick(obj):
            if obj is None:
                return None
            return replace(obj, **{f.name: getattr(obj, f.name)[idx] for f in fields(obj)
                                   if isinstance(getattr(obj, f.name), np.ndarray)
                                   and getattr(obj, f.name).shape[0] == len(self.channels)})

        return LevelReport(pick(self.levels), pick(self.bands), pick(self.loudness), [self.channels[i] for i in idx])

    def describe(self) -> dict:
        """A JSON-ready summary (levels per channel, how they were computed)."""
        out = {"evaluated_at_hz": self.levels.sample_rate, **self.levels.describe(),
               "channels": self.levels.rows(self.channels),
               "bands": {"nominal_hz": self.bands.nominal_hz.tolist(), "leq_db": self.bands.leq_db.tolist(),
                         "lmax_db": self.bands.lmax_db.tolist(),
                         "filters": "IEC 61260-1 1/3-octave, order 6; Lmax with F time weighting"}}
        if self.loudness is not None:
            out["loudness"] = {"rows": self.loudness.rows(self.channels), "library": self.loudness.library,
                               "method": "ISO 532-1 time-varying (N5 = 95th percentile), DIN 45692 sharpness",
                               "field": self.loudness.field}
        return out


def analyse(signal: Signal, *, start=None, stop=None, channels=None, with_loudness: bool = False) -> LevelReport:
    """Weighted levels, 1/3-octave bands and (optionally) loudness of a pressure signal in Pa.

    ``start`` and ``stop`` are times in s on the signal's axis (default: the whole signal);
    ``channels`` names the signal's channels (default ``"1"``, ``"2"``, ...).

    The weighted levels are those of :func:`acoustiviz.levels.sound_levels`, computed from the
    signal's sound alone where it is mostly exact silence (a damper run's click train:
    :func:`acoustiviz.levels.train.signal_levels`, equal up to round-off); the bands' decimation
    likewise works on the sound alone (:func:`acoustiviz.levels.bands.decimate`).
    """
    from ..levels.train import signal_levels

    lv = signal_levels(signal, start=start, stop=stop)  # sound_levels, from the sound alone
    bl = third_octave_levels(signal, start=start, stop=stop)
    ld = loudness(signal, start=start, stop=stop) if with_loudness else None
    n = lv.lzpeak_db.size
    names = list(channels) if channels is not None else [str(i + 1) for i in range(n)]
    return LevelReport(lv, bl, ld, names)


def _check_inputs(s, names: dict) -> None:
    """The file to read, the CSV to write, the memory the analysis needs and the loudness library.

    ``names``: API name -> the option (or the file's argument) its errors name.
    """
    from ..levels import loudness_available
    from .budget import Estimate, check_budget
    from .outputs import check_output_file

    if not Path(s.signal).is_file():
        raise ParameterError(names["signal"], f"no such file: {s.signal}")
    check_output_file(names["csv"], s.csv, "csv")
    check_output_file(names["csv"], bands_path(s.csv), "csv")  # OUT_bands.csv, written beside it
    import soundfile as sf

    try:
        info = sf.info(s.signal)
    except RuntimeError as exc:
        raise ParameterError(names["signal"], f"cannot read {s.signal} as a sound file: {exc}") from None
    # the signal in float64 and about ten filtered copies of one channel (weightings, bands, envelopes)
    samples = float(info.frames) * max(1, info.channels)
    check_budget(Estimate(8.0 * (samples + 10.0 * info.frames), 2e4, f"{samples:.3g} samples of {s.signal}",
                          (names["signal"], names["start"], names["stop"])), s.max_memory)
    if s.loudness and not loudness_available():
        raise ParameterError(names["loudness"], "needs mosqito: pip install 'acoustiviz[hearing]'")


def job_from_wav(s, echo=print):
    """The :class:`~acoustiviz.app.settings.levels.LevelsJob` of ``acoustiviz levels``' settings.

    Checks the file, the CSV, the memory and the loudness library, then reads the file and its
    calibration (:func:`read_calibrated_wav`); a ``--pa-per-fs`` a sidecar overrides is ``echo``-ed
    as ignored. Errors name the command-line options.
    """
    from .names import user_terms
    from .settings.levels import LevelsJob, LevelsSettings

    terms = LevelsSettings.names_for("cli")
    _check_inputs(s, terms)
    with user_terms(terms):
        sig = read_calibrated_wav(s.signal, pa_per_fs=s.pa_per_fs)
    if sig.source != "given" and s.pa_per_fs is not None and s.pa_per_fs != sig.pa_per_full_scale:
        echo(f"note: --pa-per-fs {s.pa_per_fs:g} ignored: the {sig.source} records "
             f"{sig.pa_per_full_scale:g} Pa per full scale")
    return LevelsJob(sig.signal, tuple(sig.channels), sig.pa_per_full_scale, sig.source, start=s.start,
                     stop=s.stop, loudness=s.loudness, csv=s.csv,
                     names={**terms, "input": terms["pa_per_fs" if sig.source == "given" else "signal"],
                            "input_name": str(s.signal)})


@dataclass(frozen=True, eq=False)
class LevelsResult:
    """The levels of a :class:`~acoustiviz.app.settings.levels.LevelsJob`: its settings and its report."""

    settings: object
    report: LevelReport

    def write(self, folder=None) -> list:
        """Write the files the settings ask for into ``folder``; return their paths.

        The levels CSV and its ``_bands.csv`` (:func:`write_levels_csv`), the spectrum's CSV
        (:func:`write_spectrum_csv`) and its figure, each atomically. ``folder``: where relative
        file names are put (default: as given, the current folder).
        """
        s, written = self.settings, []

        def where(name):
            return Path(name) if folder is None else Path(folder) / name

        if s.csv is not None:
            written += write_levels_csv(where(s.csv), self.report)
        if s.spectrum_csv is not None:
            written.append(write_spectrum_csv(where(s.spectrum_csv), self.report))
        if s.spectrum_png is not None:
            written.append(self._spectrum_figure(where(s.spectrum_png)))
        return [Path(p) for p in written]

    def _spectrum_figure(self, path):
        """The 1/3-octave band Leq and LFmax of each channel."""
        from ..output.plot.levels import plot_band_levels
        from ..output.plot.style import style
        from .products import new_figure, save

        bl = self.report.bands
        with style():
            fig = new_figure()
            ax = fig.add_subplot()
            for i, name in enumerate(self.report.channels):
                plot_band_levels(bl.nominal_hz, bl.leq_db[i], lmax_db=bl.lmax_db[i], label=name, ax=ax)
            ax.set_title(f"1/3-octave bands of {self.settings.what} over {bl.stop - bl.start:g} s")
            return save(fig, path)


def write_spectrum_csv(path, report: LevelReport):
    """Write ``channel,band_hz,leq_db,lmax_db`` (channels by name, nominal mid-band in Hz, dB) atomically."""
    from ..files import write_text_atomic

    rows = ["channel,band_hz,leq_db,lmax_db"] + [
        f"{r['channel']},{r['band_hz']:g},{r['leq_db']:.4f},{r['lmax_db']:.4f}"
        for r in report.bands.rows(report.channels)]
    return write_text_atomic(path, "\n".join(rows) + "\n")


def run(settings) -> LevelsResult:
    """The levels, bands and optional loudness of a job's signal over its interval (:func:`analyse`).

    Physics only: no file is written and nothing printed. Levels that are not numbers or infinitely
    loud (a calibration too large) are refused, naming the setting that gave the calibration.
    """
    from .names import user_terms

    s = settings
    with user_terms({k: v for k, v in s.names.items() if k in ("start", "stop", "signal")}):
        report = analyse(s.signal, start=s.start, stop=s.stop, channels=s.channels, with_loudness=s.loudness)
    _check_finite(report, s)
    return LevelsResult(s, report)


def file_summary(result: LevelsResult) -> list:
    """The summary of a WAV file's levels: the file, its rate and calibration, then :func:`summary_lines`."""
    job, sig = result.settings, result.settings.signal
    return [f"{job.names.get('input_name', 'the signal')}: {sig.channels} channel(s), {sig.duration:g} s at "
            f"{int(sig.sample_rate)} Hz, {job.pa_per_full_scale:g} Pa per full scale ({job.source})",
            *summary_lines(result.report, rate_note=" (the file's rate)")]


def _level_values(report: LevelReport):
    """The report's levels, ``(n_channels, len(LEVEL_COLUMNS))`` in dB."""
    rows = report.levels.rows(report.channels)
    return np.array([[row[c] for c in LEVEL_COLUMNS] for row in rows], dtype=float)


def _check_finite(report: LevelReport, job) -> None:
    """No level that is not a number or infinitely loud is written.

    The calibration's range (:func:`calibration_range`) keeps the levels finite; should one still
    be NaN or +inf, nothing is written, and the error names the setting the calibration came from.
    """
    values = _level_values(report)
    if np.any(np.isnan(values)) or np.any(values == np.inf):
        what = job.names.get("input_name", job.what)
        if job.pa_per_full_scale is None:  # a computed signal: no calibration to blame
            raise ParameterError(job.names.get("input", "signal"), f"the levels of {what} are not finite numbers")
        raise ParameterError(job.names.get("input", "signal"),
                             f"the levels of {what} are not finite numbers with the calibration of "
                             f"{job.pa_per_full_scale:g} Pa per full scale ({job.source}); give a smaller one")


def silent_notes(report: LevelReport, echo) -> None:
    """``echo`` a note for each channel with no sound at all: its levels are -inf dB, written as ``-inf``."""
    values, lv = _level_values(report), report.levels
    for i, name in enumerate(report.channels):
        if np.all(values[i] == -np.inf):
            echo(f"note: channel {name} is silent over {lv.start:g}-{lv.stop:g} s: its levels are -inf dB")


def bands_path(csv_path) -> Path:
    """``OUT_bands.csv`` beside ``OUT.csv``."""
    p = Path(csv_path)
    return p.with_name(f"{p.stem}_bands{p.suffix or '.csv'}")


def _fmt(v) -> str:
    if isinstance(v, str):
        return v
    from ..output.tables import csv_number

    return csv_number(v, ".4f")


def write_levels_csv(csv_path, report: LevelReport) -> tuple:
    """Write ``OUT.csv`` (one row per channel) and ``OUT_bands.csv`` (one row per channel and band).

    ``OUT.csv``: ``channel,channel_name`` (1-based index and name), the columns of
    :data:`acoustiviz.levels.LEVEL_COLUMNS` in dB, ``evaluated_at_hz,start_s,stop_s`` and, with
    loudness, ``n5_sone,nmax_sone,sharpness_acum``. ``OUT_bands.csv``:
    ``channel,band_hz,leq_db,lmax_db`` (nominal mid-band frequency in Hz, 25 Hz to 20 kHz).
    A silent channel's levels are empty cells.

    Returns
    -------
    tuple of Path
        The two files written.
    """
    from ..files import write_text_atomic

    lv, bl = report.levels, report.bands
    header = ["channel", "channel_name", *LEVEL_COLUMNS, "evaluated_at_hz", "start_s", "stop_s"]
    loud = report.loudness.rows(report.channels) if report.loudness is not None else None
    if loud is not None:
        header += ["n5_sone", "nmax_sone", "sharpness_acum"]
    lines = [",".join(header)]
    for i, row in enumerate(lv.rows(report.channels)):
        cells = [str(i + 1), row["channel"], *(_fmt(row[c]) for c in LEVEL_COLUMNS),
                 f"{lv.sample_rate:g}", f"{lv.start:.6g}", f"{lv.stop:.6g}"]
        if loud is not None:
            cells += [_fmt(loud[i][c]) for c in ("n5_sone", "nmax_sone", "sharpness_acum")]
        lines.append(",".join(cells))
    main = write_text_atomic(csv_path, "\n".join(lines) + "\n")
    band_lines = ["channel,band_hz,leq_db,lmax_db"]
    for i in range(bl.leq_db.shape[0]):
        for k, f in enumerate(bl.nominal_hz):
            band_lines.append(f"{i + 1},{f:g},{_fmt(bl.leq_db[i, k])},{_fmt(bl.lmax_db[i, k])}")
    side = write_text_atomic(bands_path(csv_path), "\n".join(band_lines) + "\n")
    return main, side


def summary_lines(report: LevelReport, *, rate_note: str = "") -> list:
    """Lines for a terminal: the levels of each channel and where they were evaluated."""
    lv = report.levels
    out = [f"levels over {lv.start:g}-{lv.stop:g} s, evaluated at {lv.sample_rate / 1e3:g} kHz{rate_note} "
           f"({lv.library})"]
    for i, row in enumerate(lv.rows(report.channels)):
        out.append(f"  {row['channel']}: LZpeak {row['lzpeak_db']:.1f}, LCpeak {row['lcpeak_db']:.1f}, "
                   f"LAFmax {row['lafmax_db']:.1f}, LASmax {row['lasmax_db']:.1f}, LAeq {row['laeq_db']:.1f}, "
                   f"LZeq {row['lzeq_db']:.1f} dB; SEL {row['sel_db']:.1f}, SEL(A) {row['sel_a_db']:.1f} dB")
        if report.loudness is not None:
            ld = report.loudness.rows(report.channels)[i]
            out.append(f"     loudness N5 {ld['n5_sone']:.2f} sone (Nmax {ld['nmax_sone']:.2f}), sharpness "
                       f"{ld['sharpness_acum']:.2f} acum")
    return out


def rendered_levels(sequence, scene, model, listeners, *, duration=None, start=None, stop=None, channels=None,
                    with_loudness: bool = False, rendering=None, room_sound=None) -> LevelReport:
    """Levels of an impact sequence at listeners, evaluated on the signal rendered at :data:`ANALYSIS_RATE`.

    Parameters
    ----------
    sequence, scene, model, listeners
        As for :func:`acoustiviz.sound.render`.
    duration : float, optional
        Minimum signal length in s.
    start, stop : float, optional
        Interval in s.
    channels : sequence of str, optional
        Names of the listeners.
    with_loudness : bool
        Also loudness and sharpness (needs mosqito).
    rendering : acoustiviz.sound.Rendering, optional
        A rendering already at :data:`ANALYSIS_RATE` to reuse.
    room_sound : acoustiviz.sound.RoomSound, optional
        In a room: the late tail and the absorption bands of the rendering (:func:`~acoustiviz.sound.render`).

    Notes
    -----
    The clicks are evaluated in closed form at the renderer's internal rate (>= 16 × 96 kHz) and
    band-limited flat to 43.2 kHz, so neither the weightings, the 20 kHz band nor the peaks are
    limited by a 44.1 or 48 kHz file.
    """
    from ..sound import render

    if rendering is None or rendering.sample_rate != ANALYSIS_RATE:
        rendering = render(sequence, scene, model, listeners, sample_rate=ANALYSIS_RATE, duration=duration,
                           room_sound=room_sound)
    return analyse(rendering.signal, start=start, stop=stop, channels=channels,
                   with_loudness=with_loudness)
