"""``acoustiviz auralize``: calibrated WAV files of a damper's whole impact sequence.

argv -> :class:`~acoustiviz.app.settings.auralize.AuralizeJob` (:func:`settings_from_args`, the options
generated from the records of :mod:`acoustiviz.app.settings.auralize` and the damper's) ->
:func:`acoustiviz.app.auralize.run` -> the summary -> :meth:`~acoustiviz.app.auralize.AuralizeResult.write`.

The damper options are those of ``acoustiviz damper`` (paper eq 15, Table 1 defaults); the run's
impact table (or a CSV of impacts given with ``--impacts``) is rendered at each ``--listener``.
Positions are in m in the frame where the struck surface is ``z = 0`` and the sphere's centre is
``(0, 0, a)``; see :mod:`acoustiviz.sound` for how the two walls map to sources.
"""

from __future__ import annotations

from ..app.settings.auralize import AURALIZE_GROUPS
from ..app.settings.damper import BALLS
from ..app.settings.run_field import RUN_FIELD
from ..app.settings.table import add_option
from ._damper import add_damper_options
from ._impact import add_room_options

#: argparse arguments of an option beyond its record.
_EXTRA = {"--listener": {"action": "append"}, "--wav": {"required": True}}


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
    add_damper_options(p, duration_help="simulated time; the WAV lasts this long, or to the end of the last click")
    balls = p.add_argument_group("several balls (every collision heard: ball-wall and ball-ball)")
    for s in BALLS:
        add_option(balls, s)
    for title, records in AURALIZE_GROUPS:
        group = p.add_argument_group(title)
        for s in records:
            add_option(group, s, **_EXTRA.get(s.option, {}))
        if title == "sound model":  # the room follows; its setup lets "--listener -0.2,0,0.3" read as a value
            add_room_options(p)
    field = p.add_argument_group("the run's field: its levels on a grid of listeners, its waveform at the listeners")
    for s in RUN_FIELD:
        if s.option is not None:
            add_option(field, s)
    p.set_defaults(func=run)


def settings_from_args(args):
    """The :class:`~acoustiviz.app.settings.auralize.AuralizeJob` of the options; errors name the options.

    The options' ranges are checked first (:class:`~acoustiviz.app.settings.auralize.AuralizeSettings`),
    then the job is built and checked (:func:`acoustiviz.app.auralize.job_from_settings`).
    """
    from ..app.auralize import job_from_settings
    from ..app.settings.auralize import AuralizeSettings

    return job_from_settings(AuralizeSettings.from_namespace(vars(args)))


def field_settings_from_args(args, sound):
    """The :class:`~acoustiviz.app.settings.run_field.RunFieldJob` of the options around the run's ``sound``.

    None when no grid or waveform file is asked for.
    """
    from ..app.settings.run_field import RunFieldJob

    job = RunFieldJob.from_namespace(vars(args), sound)
    return job if job.wanted else None


def run(args) -> int:
    """Run the ``auralize`` subcommand: argv -> job -> run -> summary -> files; return the exit status."""
    from ..app.auralize import run as run_job

    job = settings_from_args(args)
    field = field_settings_from_args(args, job)  # checked, with its files and memory, before the run
    result = run_job(job)
    if result.damper is not None:
        for msg in result.damper.warnings:
            print(f"warning: {msg}")
        if not result.damper.result.success:
            print(f"warning: the damper solver stopped early: {result.damper.result.message}")
    for line in sound_lines(result):
        print(line)
    if result.levels is not None:
        from ..app.levels import summary_lines

        for line in summary_lines(result.levels.report, rate_note=" (computed signal, flat to 43.2 kHz)"):
            print(line)
    paths = result.write()
    for path in paths:
        if path.suffix.lower() == ".csv":  # the levels, written first
            print(f"wrote {path}")
    for line in written_lines(result):
        print(line)
    if result.settings.png is not None:
        print(f"wrote {paths[-1]}")
    if field is not None:
        _run_field(field, result)
    return 0


def _run_field(job, sound) -> None:
    """The run's field around its ``sound`` already rendered: evaluated, summarised and written."""
    from ..app.run_field import run as run_field

    if job.grid != "none":  # the longest part: every grid point heard as a listener
        from .._jit import announce_long_work

        announce_long_work(f"{job.grid}: the run's {len(sound.sequence)} impacts rendered at each grid point at 96 kHz "
                           "(Ctrl-C stops it; the files written so far are kept)")
    out = run_field(job, sound=sound)
    for line in field_lines(out):
        print(line)
    for path in out.write():
        print(f"wrote {path}")


def field_lines(result) -> list:
    """The grid's evaluation and its loudest point, one line each (nothing without a grid)."""
    import numpy as np

    job = result.settings
    if job.grid == "none":
        return []
    lv, n = result.levels, int(result.heard.sum())
    k = int(np.nanargmax(lv["laeq_db"]))
    where = ", ".join(f"{v:.3g}" for v in result.points[k])
    return [f"{job.grid}: {n} of {len(result.points)} grid point(s) heard (the others inside the cavity or a wall), "
            f"evaluated at {result.sample_rate / 1e3:g} kHz",
            f"loudest point ({where}) m: LAeq {lv['laeq_db'][k]:.1f} dB, LCpeak {lv['lcpeak_db'][k]:.1f} dB, "
            f"LAFmax {lv['lafmax_db'][k]:.1f} dB, SEL(A) {lv['sel_a_db'][k]:.1f} dB"]


def _radius_text(job, out) -> str:
    """The radius the sound uses: the one sphere's, or with several balls each ball's own."""
    radii = (out.balls or {}).get("sphere_radii_m")
    if radii:
        return (f"sphere radius {', '.join(f'{r * 1e3:.2f}' for r in radii)} mm (each ball its own, from its mass "
                f"and the density of steel)")
    return f"sphere radius {job.cavity.radius * 1e3:.2f} mm ({job.radius_source})"


def sound_lines(result) -> list:
    """The impacts, the sound model and (in a room) its images, one line each."""
    job, seq, out = result.settings, result.sequence, result.rendering
    scene, model = out.scene, job.click
    counts = result.collisions
    walls = f"{seq.count(-1)} on wall -1, {seq.count(1)} on wall +1"
    if "ball_ball" in counts:  # several balls: every collision, of a ball on a wall and of two balls
        walls = f"{counts['ball_wall']} ball-wall: {walls}; {counts['ball_ball']} ball-ball"
    lines = [f"impacts: {counts['impacts']} ({walls}), "
             f"{'ball-wall ' if 'ball_ball' in counts else ''}approach speeds "
             f"{seq.velocities.min():.3g}-{seq.velocities.max():.3g} m/s" if len(seq)
             else "impacts: 0 (silence)",
             f"sound: {_radius_text(job, out)}, pulse {model.pulse}, "
             f"mass model {model.mass_model}, configuration {scene.geometry.name}, walls {scene.walls}; "
             f"{job.rate} Hz (computed at {out.internal_rate / 1e3:g} kHz, band-limited)"]
    if out.balls is not None:  # several balls: the ball-ball contacts are heard too
        b = out.balls
        lines.insert(1, f"balls: {job.damper.balls}, {b['ball_ball_contacts']} ball-ball contacts heard as pairs of "
                        f"spheres pushed apart; left out: {', '.join(b['left_out'])}")
    geometry = scene.geometry
    if not getattr(geometry, "enclosed", False):
        return lines
    if out.room is not None:
        r = out.room
        neg = r["neglected_energy_db"]
        tail = (f"late tail from {r['transition_s']:.4f} s to {r['tail_end_s']:.3f} s ({r['tail_decay']}, seed "
                f"{r['tail_seed']})" if r["late_tail"] else "no late tail")
        bands = f", absorption in {len(r['absorption_bands_hz'])} bands" if "absorption_bands_hz" in r else ""
        lines.append(f"room: {geometry.caption()}; image_order {r['image_order']}, images {r['images']}, "
                     f"{tail}{bands}, neglected_energy_db " + (f"{neg:.1f}" if isinstance(neg, float) else str(neg)))
    else:
        lines.append(f"room: {geometry.caption()}; image_order {geometry.image_order}, images {geometry.image_count}, "
                     f"neglected_energy_db {geometry.neglected_energy_db:.1f}"
                     + (" (capped by the memory budget)" if geometry.order_capped else ""))
    return lines


def written_lines(result) -> list:
    """Each WAV file's warnings, peak, calibration and name, after :meth:`write`."""
    lines = []
    for wav, w in zip(result.settings.wav_files, result.written, strict=True):
        lines += [f"warning: {msg}" for msg in w["warnings"]]
        rec = w["record"]
        spls, peaks = rec["peak_spl_db_re_20upa"], rec["peak_pa"]
        lvl = ", ".join(f"{v:.1f}" if v is not None else "silent" for v in spls)
        lines.append(f"peak SPL: {lvl} dB re 20 uPa (peak {max(peaks):.4g} Pa)")
        if rec["subtype"] == "PCM_24":
            top = max((v for v in rec["peak_dbfs"] if v is not None), default=None)
            lines.append(f"calibration: {rec['scale_pa_per_full_scale']:.6g} Pa per full scale "
                         f"({rec['scale_source']})" + (f"; peak {top:.1f} dBFS" if top is not None else ""))
        over = rec["clipping"]["peak_over_full_scale_db"]
        if result.settings.subtype == "FLOAT" and over > 0:
            lines.append(f"note: the peak is {over:.1f} dB above 1.0 = {rec['scale_pa_per_full_scale']:g} Pa; the "
                         "float file stores it exactly, but players that treat 1.0 as full scale will clip it (use "
                         "--subtype PCM_24 for listening)")
        lines += [f"wrote {wav}", f"wrote {w['sidecar']}"]
    return lines
