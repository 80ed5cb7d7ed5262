"""``acoustiviz levels``: weighted levels, 1/3-octave bands and loudness of a calibrated WAV file."""

from __future__ import annotations


def add_parser(subparsers) -> None:
    """Register the ``levels`` subcommand."""
    p = subparsers.add_parser(
        "levels",
        help="LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL, SEL(A) and 1/3-octave bands of a WAV file (CSV)",
        description="Sound levels of a WAV file per channel (IEC 61672-1 weightings, IEC 61260-1 1/3-octave bands "
        "from 25 Hz to 20 kHz), in dB re 20 uPa. The calibration (Pa per full scale) is read from the sidecar "
        "SIGNAL.json beside SIGNAL.wav when there is one, else from --pa-per-fs. Times in s.",
    )
    p.add_argument("signal", metavar="SIGNAL.wav", help="the WAV file")
    p.add_argument("--csv", required=True, metavar="OUT.csv",
                   help="one row per channel; the bands go to OUT_bands.csv beside it")
    p.add_argument("--pa-per-fs", type=float, default=None, metavar="PA",
                   help="calibration in Pa per full scale when the file has no sidecar")
    p.add_argument("--start", type=float, default=None, metavar="S",
                   help="start of the interval in s (default: the start of the file)")
    p.add_argument("--stop", type=float, default=None, metavar="S",
                   help="end of the interval in s (default: the end of the file)")
    p.add_argument("--loudness", action="store_true",
                   help="also ISO 532-1 loudness N5/Nmax (sone) and DIN 45692 sharpness (acum); needs mosqito "
                        "(pip install 'acoustiviz[hearing]')")
    p.set_defaults(func=run)


def run(args) -> int:
    """Read the file and its calibration, compute the levels, print them and write the CSV files."""
    from pathlib import Path

    from .._validate import ParameterError
    from ..app.budget import Estimate, check_budget
    from ..app.levels import analyse, read_calibrated_wav, summary_lines, write_levels_csv
    from ..app.names import user_terms
    from ..app.outputs import check_output_file
    from ..levels import loudness_available

    if not Path(args.signal).is_file():
        raise ParameterError("SIGNAL.wav", f"no such file: {args.signal}")
    check_output_file("--csv", args.csv, "csv")
    import soundfile as sf

    try:
        info = sf.info(args.signal)
    except RuntimeError as exc:
        raise ParameterError("SIGNAL.wav", f"cannot read {args.signal} as a sound file: {exc}") from None
    # the signal in float64 and about ten filtered copies of one channel (weightings, bands, envelopes)
    samples = float(info.frames) * max(1, info.channels)
    check_budget(Estimate(8.0 * (samples + 10.0 * info.frames), 2e4, f"{samples:.3g} samples of {args.signal}",
                          ("SIGNAL.wav", "--start", "--stop")), getattr(args, "max_memory", None))
    if args.loudness and not loudness_available():
        raise ParameterError("--loudness", "needs mosqito: pip install 'acoustiviz[hearing]'")
    terms = {"pa_per_fs": "--pa-per-fs", "start": "--start", "stop": "--stop", "signal": "SIGNAL.wav"}
    with user_terms(terms):
        sig = read_calibrated_wav(args.signal, pa_per_fs=args.pa_per_fs)
        if sig.source != "given" and args.pa_per_fs is not None and args.pa_per_fs != sig.pa_per_full_scale:
            print(f"note: --pa-per-fs {args.pa_per_fs:g} ignored: the {sig.source} records "
                  f"{sig.pa_per_full_scale:g} Pa per full scale")
        if args.start is not None and args.stop is not None and args.stop <= args.start:
            raise ParameterError("--stop", f"must be later than --start ({args.start:g} s), got {args.stop:g} s")
        report = analyse(sig.pressure, sig.sample_rate, start=args.start, stop=args.stop, channels=sig.channels,
                         with_loudness=args.loudness)
    print(f"{args.signal}: {sig.pressure.shape[0]} channel(s), {sig.pressure.shape[1] / sig.sample_rate:g} s at "
          f"{sig.sample_rate} Hz, {sig.pa_per_full_scale:g} Pa per full scale ({sig.source})")
    for line in summary_lines(report, rate_note=" (the file's rate)"):
        print(line)
    for path in write_levels_csv(args.csv, report):
        print(f"wrote {path}")
    return 0
