"""``acoustiviz auralize``: calibrated WAV files of a damper's whole impact sequence.

The damper options are those of ``acoustiviz damper`` (paper eq 15, Table 1 defaults); the run's
impact table (or a CSV of impacts given with ``--impacts``) is rendered at each ``--listener``.
Positions are in m in the frame where the struck surface is ``z = 0`` and the sphere's centre is
``(0, 0, a)``; see :mod:`acoustiviz.output.audio` for how the two walls map to sources.
"""

from __future__ import annotations

from ..constants import STRIKES
from ..core.geometry import CONFIGURATIONS
from ._damper import add_damper_options

DEFAULT_LISTENER = "0.495,0,0.514"


def _add_run_options(parser) -> None:
    """The options of ``acoustiviz damper`` that define the run, and ``--impacts`` to render a table instead."""
    add_damper_options(parser, duration_help="simulated time in s; the WAV lasts this long, or to the end of the "
                                           "last click (default %(default)s)")
    g = parser.add_argument_group("impacts from a file")
    g.add_argument("--impacts", default=None, metavar="CSV",
                   help="render the impacts of this CSV (columns time_s,wall,approach_velocity_m_s, as written "
                        "by 'acoustiviz damper --impacts-csv') instead of simulating; --m, --M, --gap and "
                        "--k-hertz still describe the damper")


def add_parser(subparsers) -> None:
    """Register the ``auralize`` subcommand."""
    p = subparsers.add_parser(
        "auralize",
        help="calibrated WAV files (and JSON sidecars) of a damper's impact sequence at listeners",
        description="Render every impact of an impact-damper run into the sound pressure at one or more "
        "listeners: Hertz pulse per impact from its own approach speed, rigid-sphere radiation with image "
        "sources, exact sub-sample times, band-limited to the output rate. Default output: normalised 24-bit "
        "WAV peaking 1 dB below full scale, with OUT.json beside OUT.wav recording the calibration in Pa per full "
        "scale (float32 in pascals with --subtype FLOAT). Lengths in m, times in s.",
    )
    # let "--listener -0.2,0,0.3" read as a value (argparse takes only plain negative numbers for values)
    import re

    p._negative_number_matcher = re.compile(r"^-\d*\.?\d+([eE][-+]?\d+)?(,.*)?$")
    _add_run_options(p)
    a = p.add_argument_group("sound model")
    a.add_argument("--config", default="plane", choices=CONFIGURATIONS,
                   help="reflecting surfaces: none, the struck surface z = 0 (default), or a wall-floor corner")
    a.add_argument("--wall-distance", type=float, default=None, metavar="M",
                   help="wall-floor only: distance in m from the side wall x = -D to the sphere's centre "
                        "(default 0.05)")
    a.add_argument("--strike", default="floor", choices=STRIKES,
                   help="wall-floor only: the struck surface; 'wall' puts the damper against the wall, striking "
                        "along +x (default floor)")
    a.add_argument("--height", type=float, default=None, metavar="M",
                   help="wall strike only: height in m of the sphere's centre above the floor (default: the radius)")
    a.add_argument("--radius", type=float, default=None, metavar="M",
                   help="sphere radius in m (default 0.01905, the paper's sphere, whose levels the paper "
                        "reports whatever the mass)")
    a.add_argument("--density", type=float, default=None, metavar="KG/M^3",
                   help="instead of --radius: a solid sphere of mass --m and this density "
                        "(steel 7800: 10.7 mm for 40.5 g, about 10 dB quieter)")
    a.add_argument("--pulse", default="half-sine", choices=("half-sine", "impulse-matched", "hertz"),
                   help="acceleration pulse per impact: the paper's peak-matched half-sine (default), an "
                        "impulse-matched half-sine, or the exact Hertz pulse")
    a.add_argument("--mass-model", default="impact", choices=("impact", "effective"),
                   help="mass in the Hertz pulse: the impact mass against a fixed wall (paper eq 3, default) "
                        "or the effective mass m M/(m + M) of the two bodies")
    a.add_argument("--walls", default="both", choices=("both", "one"),
                   help="both: impacts on the far wall radiate from it, axis reversed (default); one: every "
                        "impact is heard as a strike on the struck surface (the paper's view)")
    a.add_argument("--struck-wall", type=int, default=-1, choices=(-1, 1),
                   help="the damper wall lying on the struck surface z = 0 (default -1); the other wall is "
                        "gap + 2a further along +z")
    a.add_argument("--c", type=float, default=343.2, metavar="M/S",
                   help="speed of sound in m/s (default %(default)s)")
    a.add_argument("--rho", type=float, default=1.204, metavar="KG/M^3",
                   help="density of air in kg/m^3 (default %(default)s)")
    from ._impact import add_room_options

    add_room_options(p)
    _add_room_sound_options(p)
    o = p.add_argument_group("listeners and files")
    o.add_argument("--listener", action="append", default=None, metavar="X,Y,Z",
                   help=f"listener position in m (repeatable; default {DEFAULT_LISTENER}: 0.7 m at 45 degrees "
                        "from the paper's sphere). Several listeners give OUT-1.wav, OUT-2.wav, ...")
    o.add_argument("--stereo", action="store_true",
                   help="one stereo file: two --listener positions (left, right), or one head position and "
                        "two ears --ear-spacing apart facing the damper (no head shadow)")
    o.add_argument("--ear-spacing", type=float, default=0.18, metavar="M",
                   help="distance between the ears in m with --stereo and one listener (default %(default)s)")
    o.add_argument("--rate", type=int, default=48000, choices=(44100, 48000, 96000),
                   help="output sample rate in Hz (default %(default)s)")
    o.add_argument("--subtype", default="PCM_24", choices=("PCM_24", "FLOAT"),
                   help="PCM_24 (default): normalised 24-bit that plays without clipping, one scale (Pa per full "
                        "scale) shared by all files of the run and recorded in each sidecar; FLOAT: float32 in "
                        "pascals (1.0 = 1 Pa), for analysis")
    o.add_argument("--scale", type=float, default=None, metavar="PA",
                   help="Pa per full scale (default: the run's peak plus --headroom for PCM_24; 1 for FLOAT); a "
                        "PCM_24 scale that clips is reported")
    o.add_argument("--headroom", type=float, default=1.0, metavar="DB",
                   help="PCM_24: the run's peak sits this far below full scale (default %(default)s dB)")
    o.add_argument("--wav", required=True, metavar="PATH", help="output WAV (sidecar: same name, .json)")
    o.add_argument("--png", default=None, metavar="PATH", help="also draw the waveform and spectrogram")
    lv = p.add_argument_group("levels")
    lv.add_argument("--levels", action="store_true",
                    help="print LZpeak, LCpeak, LAFmax, LASmax, LAeq, LZeq, SEL and SEL(A) per listener and record "
                         "them and the 1/3-octave bands in the sidecars; evaluated on the signal computed at 96 kHz, "
                         "not on the file")
    lv.add_argument("--levels-csv", default=None, metavar="OUT.csv",
                    help="also write the levels (one row per listener) and OUT_bands.csv (implies --levels)")
    lv.add_argument("--loudness", action="store_true",
                    help="with the levels, ISO 532-1 loudness N5/Nmax (sone) and DIN 45692 sharpness (acum); needs "
                         "mosqito (pip install 'acoustiviz[hearing]')")
    p.set_defaults(func=run)


def _add_room_sound_options(parser) -> None:
    """The statistical tail and the absorption per octave band of a room's WAV (with ``--room``)."""
    from ..constants import TAIL_SEED

    g = parser.add_argument_group("room sound (with --room)")
    g.add_argument("--late-tail", action="store_true",
                   help="images exactly only until the transition time (the mixing time, or when reflections "
                        "arrive once per click), then a seeded statistical tail (noise decaying per band at "
                        "Eyring's T60, from the images' level) until --tolerance-db of the energy: seconds instead "
                        "of minutes for a reverberant room; the direct click and the early images stay exact")
    g.add_argument("--tail-seed", type=int, default=None, metavar="N",
                   help=f"seed of the tail's noise, an integer >= 0 (default {TAIL_SEED}: the same WAV every run)")
    g.add_argument("--tail-decay", default=None, choices=("eyring", "images"),
                   help="the tail's decay: Eyring's T60 per band (default) or the image sum's own expected decay")
    g.add_argument("--transition", type=float, default=None, metavar="S",
                   help="with --late-tail: transition time in s from the start of contact, in (0, 10] "
                        "(default: max(sqrt(V) ms, one reflection per contact duration))")
    g.add_argument("--absorption-bands", default=None, metavar="F:A,...",
                   help="absorption per octave band for the WAV instead of --absorption: comma-separated F:A "
                        "(band centre F in Hz in [16, 20000], increasing; alpha A in [0, 1) on every surface) "
                        "or F:A1/A2/A3/A4/A5/A6 (per surface x0,x1,y0,y1,z0 floor,z1 ceiling), e.g. "
                        "125:0.1,250:0.15,500:0.2,1000:0.25,2000:0.3,4000:0.35; the images and the tail "
                        "are filtered per band, the direct click stays broadband")


def _room_sound_of(args):
    """The RoomSound of the options (None without --late-tail and --absorption-bands), refused without --room."""
    from .._validate import ParameterError
    from ..app.wav import room_sound

    given = {"--late-tail": args.late_tail or None, "--tail-seed": args.tail_seed, "--tail-decay": args.tail_decay,
             "--transition": args.transition, "--absorption-bands": args.absorption_bands}
    if args.room is None:
        for opt, val in given.items():
            if val is not None:
                raise ParameterError(opt, "only applies with --room LX,LY,LZ")
        return None
    if not args.late_tail:
        for opt in ("--tail-seed", "--tail-decay", "--transition"):
            if given[opt] is not None:
                raise ParameterError(opt, "only applies with --late-tail")
    if args.absorption_bands is not None and args.absorption is not None:
        raise ParameterError("--absorption-bands", "give either --absorption or --absorption-bands, not both")
    return room_sound(late_tail=args.late_tail, seed=args.tail_seed, decay=args.tail_decay or "eyring",
                      transition=args.transition, absorption_bands=args.absorption_bands)


def parse_point(text: str, option: str = "--listener"):
    """``"x,y,z"`` in m as a float array (:func:`acoustiviz.app.settings.parse.parse_point`)."""
    from ..app.settings.parse import parse_point as _parse_point

    return _parse_point(text, option)


def read_impacts_csv(path):
    """Impact times (s), walls (-1/+1) and approach speeds (m/s) from a damper impact CSV."""
    import warnings

    import numpy as np

    from .._validate import ParameterError
    from ..output.audio import ImpactSequence

    try:
        with warnings.catch_warnings():  # an empty file: refused below, not warned about
            warnings.simplefilter("ignore", UserWarning)
            data = np.genfromtxt(path, delimiter=",", names=True, ndmin=1)
    except OSError as exc:
        raise ParameterError("--impacts", f"cannot read {path}: {exc}") from None
    except UnicodeDecodeError as exc:
        raise ParameterError("--impacts", f"{path} is not a CSV file (not UTF-8 text: {exc.reason} at byte "
                                          f"{exc.start})") from None
    except (ValueError, IndexError) as exc:
        reason = (str(exc).splitlines() or ["empty"])[0] if not isinstance(exc, IndexError) else "no header row"
        raise ParameterError("--impacts", f"{path} is not a table of impacts: {reason}") from None
    names = data.dtype.names or ()
    need = ("time_s", "wall", "approach_velocity_m_s")
    if any(n not in names for n in need):
        raise ParameterError("--impacts", f"{path} needs the columns {','.join(need)}; it has {','.join(names)}")
    try:
        return ImpactSequence(data["time_s"], data["wall"], np.abs(data["approach_velocity_m_s"]))
    except ParameterError as exc:
        raise ParameterError("--impacts", f"{path}: {exc}") from None


def _simulate(args):
    """Run the damper as ``acoustiviz damper`` would; return the impact sequence and a description."""
    from ..app.damper import damper_description
    from ..output.audio import ImpactSequence
    from ._damper import damper_from_args

    model, run = damper_from_args(args)
    for msg in run.warnings:
        print(f"warning: {msg}")
    if not run.result.success:
        print(f"warning: the damper solver stopped early: {run.result.message}")
    return ImpactSequence.from_table(run.result.impacts), damper_description(model, run, args.duration)


def _output_paths(wav, n: int):
    """``OUT.wav`` for one file, ``OUT-1.wav ... OUT-n.wav`` for several."""
    from pathlib import Path

    wav = Path(wav)
    if n == 1:
        return [wav]
    return [wav.with_name(f"{wav.stem}-{i + 1}{wav.suffix}") for i in range(n)]


def _check_sphere_and_medium(args):
    """Validate the damper, sphere and fluid options; return ``(radius, radius_source, medium)``."""
    from pathlib import Path

    from .._validate import ParameterError, check_positive, check_range
    from ..constants import PAPER_RADIUS
    from ..core.medium import Medium
    from ..output.audio import sphere_radius

    for opt, val, unit in (("--M", args.M, "kg"), ("--K", args.K, "N/m"), ("--m", args.m, "kg"),
                           ("--gap", args.gap, "m"), ("--k-hertz", args.k_hertz, "N/m^1.5"),
                           ("--duration", args.duration, "s")):
        check_positive(opt, val, unit)
    check_range("--C", args.C, 0.0, unit="N s/m")
    check_range("--c1", args.c1, 0.0, unit="N s/m")
    check_range("--v0", args.v0, unit="m/s")
    if Path(args.wav).suffix.lower() != ".wav":
        raise ParameterError("--wav", f"must end in .wav, got {args.wav!r}")
    # ranges in which the rendering stays finite: a damper's sphere, a real fluid, a bounded cavity
    check_range("--gap", args.gap, 0.0, 1e3, unit="m", low_open=True)
    check_range("--c", args.c, 1.0, 1e5, unit="m/s")
    check_range("--rho", args.rho, 1e-6, 1e5, unit="kg/m^3")
    if args.radius is not None and args.density is not None:
        raise ParameterError("--radius", "give either --radius or --density, not both")
    if args.density is not None:
        radius = sphere_radius(args.m, check_range("--density", args.density, 1.0, 1e5, unit="kg/m^3"))
        check_range("--m", radius, 1e-6, 1.0, unit="m (the radius of a sphere of this mass and --density)")
        radius_source = f"solid sphere of {args.m:g} kg at {args.density:g} kg/m^3"
    else:
        radius = check_range("--radius", PAPER_RADIUS if args.radius is None else args.radius, 1e-6, 1.0, unit="m")
        radius_source = "given" if args.radius is not None else "default: the paper's sphere"
    medium = Medium(c=check_positive("--c", args.c, "m/s"), rho=check_positive("--rho", args.rho, "kg/m^3"))
    return radius, radius_source, medium


def _room_of(args):
    """The ``--room`` settings (or None); a rigid room's images are those arriving within the sound."""
    from .._validate import ParameterError
    from ._impact import room_settings

    if args.room is not None and args.config != "plane":
        raise ParameterError("--config", "give either --config or --room, not both")
    args.config = "free" if args.room is not None else args.config
    room = room_settings(args)
    if room is not None and "order" not in room:
        try:  # a rigid surface has no finite image energy: the images that arrive within the sound
            rigid = min(float(x) for x in str(room.get("absorption", 0.0)).split(",")) == 0.0
        except ValueError:
            rigid = False  # Room names --absorption
        if rigid:
            room["duration"] = args.duration
    return room


def _cavity_of(args, radius, medium, room):
    """The sound scene: the cavity's walls in the geometry the options give."""
    from ..app.names import ROOM_OPTIONS, user_terms
    from ..app.wav import cavity

    terms = {"wall_distance": "--wall-distance", "strike": "--strike", "height": "--height",
             **(ROOM_OPTIONS if room is not None else {})}
    with user_terms(terms):
        return cavity(args.config, radius, args.gap, struck_wall=args.struck_wall, walls=args.walls,
                      wall_distance=args.wall_distance, strike=args.strike, height=args.height, medium=medium,
                      room=room)


def _listeners_of(args, scene, room):
    """The listener positions (m): the given ones, or two ears around one head with ``--stereo``."""
    import numpy as np

    from .._validate import ParameterError, check_positive
    from ..output.audio import check_listeners, ear_positions

    points = [parse_point(s) for s in (args.listener or [DEFAULT_LISTENER])]
    if args.stereo:
        if len(points) == 1:
            points = list(ear_positions(points[0], scene, spacing=check_positive("--ear-spacing",
                                                                                  args.ear_spacing, "m")))
        elif len(points) != 2:
            raise ParameterError("--stereo", f"needs one head position or two --listener positions, got {len(points)}")
    if room is not None:
        scene.configuration.in_room("--listener", np.array(points))
    return check_listeners(np.array(points), scene, name="--listener")


def _check_outputs(args, n_files: int) -> None:
    """Refuse unwritable or clashing WAV, sidecar and figure paths."""
    from ..app.outputs import check_distinct, check_output_file

    outputs = {}
    for path in _output_paths(args.wav, n_files):
        outputs[f"--wav {path}"] = check_output_file("--wav", path, "wav")
        outputs[f"--wav {path.with_suffix('.json')}"] = check_output_file("--wav", path.with_suffix(".json"), "json")
    if args.png is not None:
        outputs["--png"] = check_output_file("--png", args.png, "figure")
    check_distinct(outputs)


def _impacts_given(args, n_listeners: int):
    """The impacts read from ``--impacts`` (or None), with the sound's length checked against the budget."""
    from ..app.budget import check_budget, wav_estimate
    from ..app.outputs import check_input_file

    seq = None
    sound_length, length_options = args.duration, ("--duration",)
    if args.impacts:
        check_input_file("--impacts", args.impacts, "CSV file")
        seq = read_impacts_csv(args.impacts)
        last = float(seq.times.max()) if len(seq) else 0.0
        if last > args.duration:  # the sound lasts until the last click has died away
            sound_length, length_options = last, ("--impacts", "--duration")
    check_budget(wav_estimate(sound_length, args.rate, n_listeners, options=length_options),
                 getattr(args, "max_memory", None))
    return seq


def _check_run_and_levels(args) -> None:
    """The damper to simulate (when no ``--impacts``), the file's scale and the levels asked for."""
    from pathlib import Path

    from .._validate import ParameterError, check_positive, check_range

    if not args.impacts:
        from ..app.limits import check_damper
        from ..app.names import DAMPER_OPTIONS, user_terms

        with user_terms(DAMPER_OPTIONS):
            check_damper(M=args.M, K=args.K, m=args.m, gap=args.gap, k_hertz=args.k_hertz, v=args.v0,
                         duration=args.duration, c1=args.c1)
    if args.scale is not None:
        check_positive("--scale", args.scale, "Pa")
    check_range("--headroom", args.headroom, 0.0, 60.0, unit="dB")
    if args.levels_csv is not None and Path(args.levels_csv).suffix.lower() != ".csv":
        raise ParameterError("--levels-csv", f"must end in .csv, got {args.levels_csv!r}")
    if args.loudness:
        from ..levels import loudness_available

        if not loudness_available():
            raise ParameterError("--loudness", "needs mosqito: pip install 'acoustiviz[hearing]'")


def _check_click_fits(seq, args) -> None:
    """The slowest impact gives the longest click: it must fit in the sound (app.damper.check_click_fits)."""
    from ..app.damper import check_click_fits

    check_click_fits(seq, args.k_hertz, args.m, args.duration,
                     names={"m": "--m", "k_hertz": "--k-hertz", "duration": "--duration"})


def _print_sound(seq, scene, model, out, radius, radius_source, room, rate) -> None:
    """The impacts, the sound model and (in a room) its images, one line each."""
    print(f"impacts: {len(seq)} ({seq.count(-1)} on wall -1, {seq.count(1)} on wall +1), "
          f"approach speeds {seq.velocities.min():.3g}-{seq.velocities.max():.3g} m/s" if len(seq)
          else "impacts: 0 (silence)")
    print(f"sound: sphere radius {radius * 1e3:.2f} mm ({radius_source}), pulse {model.pulse}, "
          f"mass model {model.mass_model}, configuration {scene.configuration.name}, walls {scene.walls}; "
          f"{rate} Hz (computed at {out.internal_rate / 1e3:g} kHz, band-limited)")
    if room is not None and out.room is not None:
        r = out.room
        neg = r["neglected_energy_db"]
        tail = (f"late tail from {r['transition_s']:.4f} s to {r['tail_end_s']:.3f} s ({r['tail_decay']}, seed "
                f"{r['tail_seed']})" if r["late_tail"] else "no late tail")
        bands = f", absorption in {len(r['absorption_bands_hz'])} bands" if "absorption_bands_hz" in r else ""
        print(f"room: {scene.configuration.caption()}; image_order {r['image_order']}, images {r['images']}, "
              f"{tail}{bands}, neglected_energy_db " + (f"{neg:.1f}" if isinstance(neg, float) else str(neg)))
    elif room is not None:
        conf = scene.configuration
        print(f"room: {conf.caption()}; image_order {conf.image_order}, images {conf.image_count}, "
              f"neglected_energy_db {conf.neglected_energy_db:.1f}" + (" (capped by the memory budget)"
                                                                        if conf.order_capped else ""))


def _levels_per_file(args, seq, scene, model, listeners, files, out, rs=None):
    """The levels of each file when asked for (printed, and written with ``--levels-csv``), else None."""
    if not (args.levels or args.levels_csv is not None or args.loudness):
        return None
    from ..app.levels import rendered_levels, summary_lines

    names_all = [n for f in files for n in (f.channel_names if args.stereo else f.listeners)]
    report = rendered_levels(seq, scene, model, listeners, duration=args.duration, channels=names_all,
                             with_loudness=args.loudness, rendering=out, room_sound=rs)
    for line in summary_lines(report, rate_note=" (computed signal, flat to 43.2 kHz)"):
        print(line)
    groups = [[0, 1]] if args.stereo else [[i] for i in range(len(files))]
    per_file = [report.subset(g).describe() for g in groups]
    if args.levels_csv is not None:
        from ..app.levels import write_levels_csv

        for path in write_levels_csv(args.levels_csv, report):
            print(f"wrote {path}")
    return per_file


def _print_written(args, files, written) -> None:
    """Each file's warnings, peak, calibration and name."""
    for wav, w in zip(files, written, strict=True):
        for msg in w["warnings"]:
            print(f"warning: {msg}")
        rec = w["record"]
        spls, peaks = rec["peak_spl_db_re_20upa"], rec["peak_pa"]
        lvl = ", ".join(f"{s:.1f}" if s is not None else "silent" for s in spls)
        print(f"peak SPL: {lvl} dB re 20 uPa (peak {max(peaks):.4g} Pa)")
        if rec["subtype"] == "PCM_24":
            top = max((v for v in rec["peak_dbfs"] if v is not None), default=None)
            print(f"calibration: {rec['scale_pa_per_full_scale']:.6g} Pa per full scale ({rec['scale_source']})"
                  + (f"; peak {top:.1f} dBFS" if top is not None else ""))
        over = rec["clipping"]["peak_over_full_scale_db"]
        if args.subtype == "FLOAT" and over > 0:
            print(f"note: the peak is {over:.1f} dB above 1.0 = {rec['scale_pa_per_full_scale']:g} Pa; the float "
                  "file stores it exactly, but players that treat 1.0 as full scale will clip it (use --subtype "
                  "PCM_24 for listening)")
        print(f"wrote {wav.path}")
        print(f"wrote {w['sidecar']}")


def _write_png(args, paths, channels) -> None:
    """The waveforms of the files as one figure."""
    from pathlib import Path

    from ..output.plot.audio import auralisation_figure
    from ..output.plot.style import save_figure

    if args.stereo:
        labels = [f"{Path(paths[0]).name} {side}" for side in ("left", "right")]
        signals = list(channels[0])
    else:
        labels = [Path(p).name for p in paths]
        signals = [c[0] for c in channels]
    fig = auralisation_figure(signals, args.rate, labels=labels)
    save_figure(fig, args.png)
    print(f"wrote {args.png}")


def run(args) -> int:
    """Simulate (or read) the impacts, render them, write the WAVs and sidecars, print a summary."""
    from ..app.wav import WavFile, write_wav_files
    from ..output.audio import ClickModel, render

    # ---- validate every option before any work
    radius, radius_source, medium = _check_sphere_and_medium(args)
    rs = _room_sound_of(args)
    if rs is not None and rs.banded:  # the least absorbing band sets the room's image order and its peaks
        from ..app.wav import least_absorbing

        args.absorption = ",".join(f"{x:.17g}" for x in least_absorbing(rs.band_absorption))
    room = _room_of(args)
    scene = _cavity_of(args, radius, medium, room)
    if rs is not None:
        from ..app.names import user_terms
        from ..app.wav import ROOM_SOUND_OPTIONS

        with user_terms({**ROOM_SOUND_OPTIONS, "order": "--image-order"}):
            rs.check_room(scene.configuration)
    model = ClickModel(k_hertz=args.k_hertz, mass=args.m, main_mass=args.M, mass_model=args.mass_model,
                       pulse=args.pulse)
    listeners = _listeners_of(args, scene, room)
    _check_outputs(args, 1 if args.stereo else len(listeners))
    seq = _impacts_given(args, len(listeners))
    _check_run_and_levels(args)

    # ---- impacts
    if seq is not None:
        run_desc = {"impacts_csv": str(args.impacts), "m_kg": args.m, "M_kg": args.M, "gap_m": args.gap,
                    "k_hertz_n_m1_5": args.k_hertz}
    else:
        seq, run_desc = _simulate(args)
    _check_click_fits(seq, args)
    out = render(seq, scene, model, listeners, sample_rate=args.rate, duration=args.duration, room_sound=rs)

    # ---- files
    channels = [out.pressure] if args.stereo else [out.pressure[i:i + 1] for i in range(out.pressure.shape[0])]
    chan_listeners = [listeners] if args.stereo else [listeners[i:i + 1] for i in range(listeners.shape[0])]
    paths = _output_paths(args.wav, len(channels))
    names = ["left", "right"] if args.stereo else ["mono"]
    files = [WavFile(path, data, [f"listener{i + 1}" for i in range(len(pts))] if not args.stereo else names, pts,
                     names) for path, data, pts in zip(paths, channels, chan_listeners, strict=True)]
    _print_sound(seq, out.scene, model, out, radius, radius_source, room, args.rate)
    per_file = _levels_per_file(args, seq, scene, model, listeners, files, out, rs)
    written = write_wav_files(files, sample_rate=args.rate, subtype=args.subtype, scale=args.scale,
                              headroom_db=args.headroom, rendering=out, damper=run_desc,
                              radius_source=radius_source, levels=per_file)
    _print_written(args, files, written)
    if args.png:
        _write_png(args, paths, channels)
    return 0
