"""Several balls in a sweep: the balls and fill axes, the multi-ball evaluation, and every front end agreeing.

A sweep of one ball writes what it wrote before balls were swept; the one-ball rows of a sweep over balls are
those rows; a two-ball design counts every collision of its multi-ball run and hears each through the
multi-ball sound; the fill and the gap convert into each other as the cavity's geometry says; the command
line, a scene and the API build equal sweeps and write the same files; several balls are heard in a room,
louder than on the plane; in operation a design of several balls finds the attractors of ``forced --balls``,
its level columns the worst of their noise in operation, and the one-ball rows are those of a sweep without
balls. Runs are a few tenths of a second, those in operation a few seconds.
"""

from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest

from acoustiviz.app import sweep as sweep_app
from acoustiviz.app.settings.sweep_job import SweepJob
from acoustiviz.app.sweep import sweep_settings
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.sweep import settings_from_args
from acoustiviz.constants import ANALYSIS_RATE, P_REF
from acoustiviz.core.medium import Medium
from acoustiviz.dynamics import BallState, DamperModel, MultiBallModel, equal_balls, simulate_balls
from acoustiviz.dynamics.metrics import sample_times
from acoustiviz.errors import ParameterError, SceneError
from acoustiviz.scene import scene_from_dict
from acoustiviz.sound import CavityScene, ClickModel
from acoustiviz.sound.balls_sound import ball_clicks, column_scene, render_clicks
from acoustiviz.sweep import FixedSettings, SweepSpec, load_sweep
from acoustiviz.sweep.balls import BALL_COLUMNS, fill_of, gap_of_fill
from acoustiviz.sweep.evaluate import evaluate_design, listener_point
from acoustiviz.sweep.query import design as choose
from acoustiviz.sweep.store import ALL_COLUMNS

#: Seconds of motion per design: a handful of collisions, enough to tell the bodies apart.
DURATION = 0.5
#: Tolerance in dB between two computations of the same peak on the same sample grid.
SPL_TOL_DB = 1e-6


def _rows(path) -> list[dict]:
    return list(csv.DictReader(io.StringIO(path.read_text())))


def _line(row: dict, columns) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([row[c] for c in columns])
    return buf.getvalue()


def test_one_ball_rows_are_those_of_a_sweep_without_balls(tmp_path, capsys):
    common = ["--m", "0.03,0.05", "--duration", str(DURATION), "--workers", "1", "--quiet"]
    assert main(["sweep", *common, "--out", str(tmp_path / "plain")]) == 0, capsys.readouterr().err
    assert main(["sweep", *common, "--balls", "1,2", "--out", str(tmp_path / "balls")]) == 0, capsys.readouterr().err
    plain = (tmp_path / "plain" / "sweep.csv").read_text().splitlines(keepends=True)
    assert plain[0].rstrip("\n").split(",") == list(ALL_COLUMNS)  # no balls, fill columns without --balls
    assert "balls" not in (tmp_path / "plain" / "sweep.json").read_text()
    rows = _rows(tmp_path / "balls" / "sweep.csv")
    assert [r["balls"] for r in rows] == ["1", "1", "2", "2"]
    one = [_line(r, ALL_COLUMNS) for r in rows if r["balls"] == "1"]
    assert one == plain[1:]  # the one-ball rows, byte for byte, without the two new columns
    two = [r for r in rows if r["balls"] == "2"]
    assert all(r["success"] == "1" and int(r["n_impacts"]) > 0 for r in two)


def _independent_spl(res, design, settings) -> tuple[int, float]:
    """The collisions heard and their loudest peak, each collision rendered alone at its own time."""
    medium = Medium(c=settings.c, rho=settings.rho)
    scene = CavityScene(design.geometry(settings), gap=design.gap, walls="one", medium=medium)
    click = ClickModel(k_hertz=design.k_hertz, mass=design.m, main_mass=settings.M, mass_model=settings.pulse_mass,
                       pulse=settings.pulse)
    scene = column_scene(scene, res.model.cavities[0])
    point = listener_point(scene.geometry, design.distance, design.angle)
    clicks = ball_clicks(res, scene, click)
    peaks = []
    for k in np.unique(clicks.collision):
        p = render_clicks(clicks.take(clicks.collision == k), scene, click, point, sample_rate=ANALYSIS_RATE)
        peaks.append(20 * math.log10(np.max(np.abs(p.pressure[0])) / P_REF))
    return len(peaks), max(peaks)


def test_a_two_ball_design_counts_every_collision_and_hears_the_loudest():
    settings = FixedSettings(duration=DURATION)
    (design,) = SweepSpec(balls=(2,), settings=settings).designs()
    row = evaluate_design(design, settings)
    damper = DamperModel(M=settings.M, K=settings.K, C=settings.C, m=design.m, gap=design.gap,
                         k_hertz=design.k_hertz, c1=design.c1)
    res = simulate_balls(MultiBallModel.from_damper(damper, 2), DURATION, initial=BallState(v=design.v0),
                         rtol=settings.rtol, t_eval=sample_times(DURATION, damper))
    walls = np.isin(res.impacts.first, ["wall-"]) | np.isin(res.impacts.second, ["wall+"])
    assert walls.any() and not walls.all()  # both kinds of collision happen in the run
    assert row.success and row.n_impacts == len(res.impacts)
    heard, loudest = _independent_spl(res, design, settings)
    assert row.spl_impacts_evaluated == heard
    assert abs(row.max_spl_db - loudest) < SPL_TOL_DB
    assert row.mass_ratio == pytest.approx(2 * design.m / settings.M, rel=1e-15)


@pytest.mark.parametrize("n", [1, 2, 3, 5])
@pytest.mark.parametrize("fill", [0.1, 0.45, 0.9])
def test_the_fill_and_the_gap_convert_as_the_cavity_says(n, fill):
    m = 0.02
    (design,) = SweepSpec(balls=(n,), fill=(fill,), m=(m,)).designs()
    cavity = equal_balls(n, m, design.gap, 5.6e8, 20.0)  # the cavity the dynamics builds, steel balls of m
    diameter = 2 * cavity.radii[0]
    assert design.fill == fill
    assert n * diameter / cavity.length == pytest.approx(fill, rel=1e-12)
    assert fill_of(n, diameter, gap_of_fill(n, diameter, fill)) == pytest.approx(fill, rel=1e-12)
    (by_gap,) = SweepSpec(balls=(n,), gap=(design.gap,), m=(m,)).designs()
    assert by_gap.fill == pytest.approx(fill, rel=1e-12) and by_gap.gap == design.gap


def test_a_gap_with_a_fill_is_refused_naming_both(tmp_path, capsys):
    out = tmp_path / "sweep"
    assert main(["sweep", "--gap", "0.03", "--fill", "0.4", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--gap" in err and "--fill" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
    with pytest.raises(SceneError, match="gap_m") as exc:
        scene_from_dict({"outputs": {"sweep": {"gap_m": "0.03", "fill": "0.4"}}})
    assert "outputs.sweep.fill" in str(exc.value)
    with pytest.raises(ParameterError, match="fill"):
        SweepSpec(gap=(0.03,), fill=(0.4,))


@pytest.mark.parametrize("argv, option", [(["--balls", "1.5"], "--balls"), (["--balls", "0"], "--balls"),
                                          (["--fill", "1"], "--fill"), (["--fill", "0:0.5:3"], "--fill")])
def test_bad_balls_and_fills_are_refused_naming_the_option(tmp_path, capsys, argv, option):
    assert main(["sweep", *argv, "--out", str(tmp_path / "sweep")]) == 2
    assert capsys.readouterr().err.startswith(f"acoustiviz sweep: error: {option}:")
    assert not (tmp_path / "sweep").exists()


#: A sweep in operation under F0 = 5 N at two frequencies, with a short search.
OPERATION = ["--force", "5", "--freq", "6.5,7", "--starts", "2", "--max-cycles", "18", "--noise-seconds", "0.02",
             "--workers", "1", "--quiet"]


def test_several_balls_in_operation_find_the_attractors_of_forced_balls(tmp_path, capsys):
    from acoustiviz.app.forced import run as run_forced
    from acoustiviz.app.settings.forced_job import ForcedJob
    from acoustiviz.core.geometry import geometry
    from acoustiviz.sound.balls_operating import balls_operating_noise
    from acoustiviz.sweep.operation import OPERATION_COLUMNS

    assert main(["sweep", *OPERATION, "--out", str(tmp_path / "plain")]) == 0, capsys.readouterr().err
    capsys.readouterr()
    assert main(["sweep", "--balls", "1,2", *OPERATION, "--out", str(tmp_path / "balls")]) == 0, \
        capsys.readouterr().err
    assert "quietest by worst_laeq_db: design" in capsys.readouterr().out
    plain = (tmp_path / "plain" / "sweep.csv").read_text().splitlines(keepends=True)
    assert plain[0].rstrip("\n").split(",") == list(OPERATION_COLUMNS)
    rows = _rows(tmp_path / "balls" / "sweep.csv")
    assert [r["balls"] for r in rows] == ["1", "2"] and all(r["success"] == "1" for r in rows)
    assert _line(rows[0], OPERATION_COLUMNS) == plain[1]  # one ball: the row of a sweep without --balls
    two = rows[1]
    for c in ("worst_amplitude_m", "min_reduction_db", "mean_reduction_db", "chaotic_fraction",
              "worst_lcpeak_db", "worst_laeq_db", "worst_lafmax_db"):  # several balls heard in operation too
        assert math.isfinite(float(two[c])), c
    # the forced job of the same two balls finds the same worst case
    forced = run_forced(ForcedJob(model=DamperModel(m=float(two["mass_kg"]), gap=float(two["gap_m"])),
                                  frequencies=(6.5, 7.0), amplitude=5.0, starts=2, max_cycles=18, balls=2,
                                  noise=False, workers=1))
    worst = max((r for r in forced.rows if math.isfinite(r["amplitude_m"])), key=lambda r: r["amplitude_m"])
    assert float(two["worst_amplitude_m"]) == pytest.approx(worst["amplitude_m"], rel=1e-12)
    assert float(two["worst_frequency_hz"]) == worst["frequency_hz"]
    # its worst LCpeak: the loudest of those attractors heard directly at the design's listener
    radius = float(two["radius_m"])
    assert two["config"] == "plane"
    listener = geometry("plane", radius).observer_points(float(two["distance_m"]),
                                                         math.radians(float(two["angle_deg"])))[0]
    heard = [balls_operating_noise(a, listener=listener, kind="plane", radius=radius, seconds=0.02).lcpeak_db
             for _, _, a, _ in forced.response.entries() if a.success]
    assert len(heard) == int(two["attractors"])
    assert float(two["worst_lcpeak_db"]) == pytest.approx(max(heard), rel=0, abs=1e-9)
    assert int(two["attractors"]) == len(forced.rows)


def test_the_equal_total_mass_divides_the_mass_among_the_balls():
    total = 0.06
    shared = SweepSpec(balls=(1, 2, 4), m=(total,), settings=FixedSettings(equal_total_mass=True)).designs()
    assert [d.balls for d in shared] == [1, 2, 4]
    assert [d.m for d in shared] == [total / n for n in (1, 2, 4)]
    each = SweepSpec(balls=(1, 2, 4), m=(total,)).designs()
    assert [d.m for d in each] == [total] * 3


#: The same small sweep over balls and fills at equal total mass, three ways.
ARGV = ("sweep", "--balls", "1,2", "--fill", "0.4", "--m", "0.04", "--equal-total-mass", "--duration",
        str(DURATION), "--solver", "event", "--workers", "1", "--quiet")
SCENE = ('[damper]\nsolver = "event"\n[outputs.sweep]\nballs = "1,2"\nfill = "0.4"\nmass_kg = "0.04"\n'
         f'equal_total_mass = true\nduration_s = {DURATION}\nworkers = 1\n')
CAP = 256.0  # the scene's memory cap by default, stated on the command line


def _api(out) -> SweepJob:
    return SweepJob(balls=(1, 2), fill=(0.4,), m=(0.04,), out=str(out), workers=1, max_memory_mb=CAP,
                    settings=FixedSettings(duration=DURATION, equal_total_mass=True))


def test_the_command_line_a_scene_and_the_api_agree(tmp_path, capsys):
    import tomllib

    args = build_parser().parse_args([*ARGV, "--out", str(tmp_path / "cli" / "sweep"), "--max-memory", str(CAP)])
    from_cli = settings_from_args(args)
    scene = scene_from_dict(tomllib.loads(SCENE))
    from_scene = sweep_settings(scene, tmp_path / "cli")
    assert from_cli == from_scene == _api(tmp_path / "cli" / "sweep")
    assert from_cli.spec == from_scene.spec
    assert from_cli.names["fill"] == "--fill" and from_scene.names["fill"] == "outputs.sweep.fill"
    assert from_cli.names["balls"] == "--balls" and from_scene.names["balls"] == "outputs.sweep.balls"
    assert main([*ARGV, "--out", str(tmp_path / "cli" / "sweep")]) == 0, capsys.readouterr().err
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    sweep_app.run(_api(tmp_path / "api" / "sweep")).write()
    for name in ("sweep.json", "sweep.csv", "design_table.csv"):
        mine = (tmp_path / "cli" / "sweep" / name).read_bytes()
        assert (tmp_path / "scene" / "sweep" / name).read_bytes() == mine, name
        assert (tmp_path / "api" / "sweep" / name).read_bytes() == mine, name
    rows = _rows(tmp_path / "cli" / "sweep" / "sweep.csv")
    assert list(rows[0])[list(rows[0]).index("radius_m") + 1:][:2] == list(BALL_COLUMNS)
    assert [(r["balls"], float(r["fill"]), float(r["mass_kg"])) for r in rows] == [("1", 0.4, 0.04), ("2", 0.4, 0.02)]
    table = load_sweep(tmp_path / "cli" / "sweep")
    chosen = choose(table, float(np.nanmean(table.inclination())), 1.0)  # the design command's ranking
    assert chosen.quietest["balls"] in (1, 2) and chosen.quietest["fill"] == 0.4
    n = chosen.quietest["balls"]
    assert f"{n} ball{'s' if n > 1 else ''} of m = {chosen.quietest['mass_kg']:.6g} kg" in chosen.summary()


def test_a_sweep_of_fills_skips_the_gap_by_mass_maps(tmp_path, capsys):
    out = tmp_path / "sweep"
    argv = ["sweep", "--fill", "0.3", "--m", "0.03,0.05", "--duration", str(DURATION), "--workers", "1", "--quiet"]
    assert main([*argv, "--out", str(out)]) == 0, capsys.readouterr().err
    assert "maps skipped: they need only --gap and --m swept (also swept: fill)" in capsys.readouterr().out
    assert not (out / "inclination_map.png").exists() and (out / "design_table.csv").is_file()
    gaps = [float(r["gap_m"]) for r in _rows(out / "sweep.csv")]
    assert gaps[0] != gaps[1]  # the same fill of balls of other masses: other gaps
    with pytest.raises(ParameterError, match="fill"):
        load_sweep(out).grid("max_spl_db")


def test_several_balls_in_a_room_are_heard_with_its_images_louder_than_on_the_plane(tmp_path, capsys):
    # a rigid room (absorption 0) holds the plane's floor and five more reflecting surfaces
    room = ["--room", "3,2.5,2", "--absorption", "0", "--source", "1,1,0.01905", "--room-window", "0.005"]
    out = tmp_path / "sweep"
    argv = ["sweep", "--balls", "1,2", *room, "--duration", "0.3", "--levels", "--workers", "1", "--quiet"]
    assert main([*argv, "--out", str(out)]) == 0, capsys.readouterr().err
    rows = _rows(out / "sweep.csv")
    assert [(r["config"], r["balls"], r["success"]) for r in rows] == [("room", "1", "1"), ("room", "2", "1")]
    two = rows[1]
    cols = ("max_spl_db", "lafmax_db", "lcpeak_db", "laeq_db")
    assert all(math.isfinite(float(two[c])) for c in cols) and int(two["n_impacts"]) > 0
    settings = FixedSettings(duration=0.3, levels=True)
    (plane,) = SweepSpec(balls=(2,), settings=settings).designs()
    on_plane = evaluate_design(plane, settings)
    assert on_plane.n_impacts == int(two["n_impacts"])  # the same motion, heard in other surroundings
    assert float(two["max_spl_db"]) > on_plane.max_spl_db
    assert float(two["laeq_db"]) > on_plane.levels["laeq_db"] + 1.0  # the room's reverberation adds energy


def test_a_two_ball_design_damps_as_the_damper_job_of_two_balls_measures():
    from acoustiviz.app.damper import run as run_damper
    from acoustiviz.app.settings.damper_job import DamperJob
    from acoustiviz.dynamics import InitialState

    settings = FixedSettings(duration=DURATION)
    (design,) = SweepSpec(balls=(2,), settings=settings).designs()
    row = evaluate_design(design, settings)
    model = DamperModel(M=settings.M, K=settings.K, C=settings.C, m=design.m, gap=design.gap,
                        k_hertz=design.k_hertz, c1=design.c1)
    damper = run_damper(DamperJob(model, InitialState(v=design.v0), duration=DURATION, balls=2))
    assert len(damper.result.impacts) == row.n_impacts
    m = damper.metrics
    ours = [row.inclination_two_maxima, row.inclination_fit, row.fit_n_maxima, row.settling_time]
    assert np.array_equal(ours, [m.two_maxima.value, m.fit.value, m.fit.n_maxima, m.settling_time], equal_nan=True)


def test_the_contact_between_two_balls_is_that_of_the_damper_options(tmp_path, capsys):
    import tomllib

    from acoustiviz.sweep.balls import design_balls_model

    argv = ["sweep", "--balls", "2", "--k-hertz-ball", "1e9", "--c1-ball", "5", "--solver", "event", "--duration",
            "5", "--max-memory", str(CAP), "--out", str(tmp_path / "sweep")]
    from_cli = settings_from_args(build_parser().parse_args(argv))
    scene = scene_from_dict(tomllib.loads('[damper]\nsolver = "event"\nk_hertz_ball_n_m1_5 = 1e9\n'
                                          'contact_damping_ball_n_s_m = 5.0\n[outputs.sweep]\nballs = "2"\n'))
    from_scene = sweep_settings(scene, tmp_path)
    assert from_cli.settings == from_scene.settings
    assert from_scene.names["k_hertz_ball"] == "damper.k_hertz_ball_n_m1_5"
    settings = from_cli.settings
    (design,) = from_cli.spec.designs()
    cavity = design_balls_model(design, settings)[1].cavities[0]
    assert cavity.k_ball == (1e9,) and cavity.c_ball == 5.0 and cavity.c_wall == design.c1
    assert main(["sweep", "--balls", "2", "--k-hertz-ball", "-1", "--out", str(tmp_path / "bad")]) == 2
    assert capsys.readouterr().err.startswith("acoustiviz sweep: error: --k-hertz-ball:")
    assert from_cli.spec.to_dict()["settings"]["k_hertz_ball"] == 1e9
    assert "k_hertz_ball" not in SweepSpec().to_dict()["settings"]  # one ball: sweep.json as before


def test_fills_and_the_equal_total_mass_apply_in_operation_and_a_sweep_resumes(tmp_path, capsys):
    from acoustiviz.core.materials import material
    from acoustiviz.sweep.in_operation import load_any_sweep, rank_in_operation

    argv = ["sweep", "--balls", "1,2", "--fill", "0.3,0.5", "--m", "0.04", "--equal-total-mass", *OPERATION]
    out = tmp_path / "sweep"
    assert main([*argv, "--out", str(out)]) == 0, capsys.readouterr().err
    first = (out / "sweep.csv").read_bytes()
    rows = _rows(out / "sweep.csv")
    assert [(r["balls"], float(r["fill"]), float(r["mass_kg"])) for r in rows] == \
        [("1", 0.3, 0.04), ("1", 0.5, 0.04), ("2", 0.3, 0.02), ("2", 0.5, 0.02)]
    rho = material("steel").density
    for r in rows:  # each design's gap from its fill, its balls and their diameter (steel)
        n, fill = int(r["balls"]), float(r["fill"])
        diameter = 2 * (3 * float(r["mass_kg"]) / (4 * math.pi * rho)) ** (1 / 3)
        assert float(r["gap_m"]) == pytest.approx(gap_of_fill(n, diameter, fill), rel=1e-12)
        assert r["success"] == "1" and math.isfinite(float(r["worst_amplitude_m"]))
    assert main([*argv, "--out", str(out)]) == 0  # a finished sweep resumes with nothing to compute
    assert (out / "sweep.csv").read_bytes() == first
    table = load_any_sweep(out)
    best = rank_in_operation(table, "worst_amplitude_m")
    assert sorted(table["design_id"][best].tolist()) == [0, 1, 2, 3]
    # a ranking by a level ranks the designs of several balls too, heard in operation (a design whose
    # attractors strike nothing in their measured cycles has levels of -inf, none to rank by)
    laeq = np.asarray(table["worst_laeq_db"], dtype=float)
    assert not np.isnan(laeq).any() and np.isfinite(laeq[np.asarray(table["balls"]) == 2]).any()
    ranked = rank_in_operation(table, "worst_laeq_db")
    assert sorted(ranked.tolist()) == np.flatnonzero(np.isfinite(laeq)).tolist()
    assert np.all(np.diff(laeq[ranked]) >= 0)


def test_only_designs_of_the_same_balls_seed_each_other_in_operation():
    from dataclasses import replace

    from acoustiviz.sweep import Operation
    from acoustiviz.sweep.operation import evaluate_chain, evaluate_in_operation

    operation = Operation(5.0, (6.5, 7.0), starts=2, max_cycles=18, levels=False, warm_radius=1.0)
    settings = FixedSettings()
    one, two = SweepSpec(balls=(1, 2), settings=settings).designs()
    again = replace(two, design_id=2, distance=1.0)  # the same dynamics, another listener
    rows = evaluate_chain((one, two, again), settings, operation)
    assert [r["warm_from"] for r in rows] == [-1, -1, 1]  # one ball never seeds two; two seeds its twin
    alone = evaluate_in_operation(two, settings, operation)
    assert rows[1] == alone  # from scratch, as if evaluated alone
    cols = ("worst_amplitude_m", "worst_frequency_hz", "min_reduction_db", "chaotic_fraction", "attractors")
    assert [rows[2][c] for c in cols] == [alone[c] for c in cols]  # the twin's attractors taken as they are
    # a neighbour of other balls (their final states need not fit its cavity) is searched from scratch
    near = SweepSpec(balls=(2,), m=(0.04, 0.041), settings=settings).designs()
    rows = evaluate_chain(near, settings, operation)
    assert [r["warm_from"] for r in rows] == [-1, -1] and all(r["success"] == 1 for r in rows)
