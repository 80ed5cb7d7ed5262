"""The sweep and design jobs: one settings object, one run and one writer for the command line, scenes and the API.

The same tiny sweep (2 gaps x 2 impact masses, half a second of motion each) and the same design choice are
asked for three ways (``acoustiviz sweep`` and ``acoustiviz design``, a scene's ``[outputs.sweep]`` and
``[outputs.design_table]``, and the jobs built in Python) and the files are compared byte for byte; the
command line and the scene must build equal jobs, also for settings drawn at random from the records'
ranges; bad input is refused before any work, naming the front end's option or key.
"""

from __future__ import annotations

import random
import tomllib

import pytest

from acoustiviz.app import design as design_app
from acoustiviz.app import sweep as sweep_app
from acoustiviz.app.design import DesignJob, design_settings
from acoustiviz.app.settings.damper import DAMPER
from acoustiviz.app.settings.design import DEFINITION, DESIGN
from acoustiviz.app.settings.sweep import SCENE_SWEEP, SWEEP, SWEPT
from acoustiviz.app.settings.sweep_job import SweepJob
from acoustiviz.app.sweep import sweep_settings
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.design import settings_from_args as design_from_args
from acoustiviz.cli.sweep import settings_from_args as sweep_from_args
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict
from acoustiviz.sweep import DEFINITIONS, FixedSettings

#: The tiny sweep: two gaps, two impact masses, 0.5 s of motion per design, one worker, the event solver.
GAPS, MASSES, DURATION = (0.03, 0.04), (0.03, 0.05), 0.5
ARGV = ("sweep", "--gap", "0.03,0.04", "--m", "0.03:0.05:2", "--duration", "0.5", "--solver", "event", "--workers",
        "1", "--quiet")
SCENE = ('[damper]\nsolver = "event"\n[outputs.sweep]\ngap_m = "0.03,0.04"\nmass_kg = "0.03:0.05:2"\n'
         'duration_s = 0.5\nworkers = 1\n')
#: A target wide enough to hold designs of the tiny sweep, whatever their inclinations.
TARGET = (0.008, 0.01)
SWEEP_FILES = ("sweep.json", "sweep.csv", "design_table.csv", "inclination_map.png", "max_spl_map.png")
DESIGN_FILES = ("design_table.png", "design_choice.txt")
#: The scene's memory cap (grids.memory_limit_mb) by default; the command line states it with --max-memory.
CAP = 256.0


def _api_sweep(out, **kw) -> SweepJob:
    return SweepJob(gap=GAPS, m=MASSES, settings=FixedSettings(duration=DURATION), out=str(out), workers=1, **kw)


def test_every_front_end_writes_the_same_files(tmp_path, capsys):
    cli = tmp_path / "cli"
    assert main([*ARGV, "--out", str(cli / "sweep")]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert printed.startswith("sweep: 4 designs in")
    assert all(f"wrote {cli / 'sweep' / name}" in printed for name in SWEEP_FILES[2:])
    assert main(["design", "--sweep", str(cli / "sweep"), "--inclination", str(TARGET[0]), "--tolerance",
                 str(TARGET[1]), "--png", str(cli / DESIGN_FILES[0]), "--choice", str(cli / DESIGN_FILES[1])]) == 0
    printed = capsys.readouterr().out
    assert "quietest" in printed and f"wrote {cli / DESIGN_FILES[1]}" in printed
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE + f"[outputs.design_table]\ninclination_m_s = {TARGET[0]}\ntolerance_m_s = {TARGET[1]}\n")
    scene = tmp_path / "scene"
    assert main(["run", str(toml), "--out", str(scene)]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    result = sweep_app.run(_api_sweep(api / "sweep"))
    assert [p.name for p in result.write()] == list(SWEEP_FILES[2:])
    choice = design_app.run(DesignJob(*TARGET, sweep=str(api / "sweep"), png=DESIGN_FILES[0],
                                      choice=DESIGN_FILES[1])).write(api)
    assert [p.name for p in choice] == list(DESIGN_FILES)
    for name in [f"sweep/{n}" for n in SWEEP_FILES] + list(DESIGN_FILES):
        mine = (cli / name).read_bytes()
        assert len(mine) > 100, name
        assert (scene / name).read_bytes() == mine, f"the scene's {name} differs from the command line's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the command line's"


def test_the_sweep_result_holds_every_design_and_its_design_table(tmp_path):
    result = sweep_app.run(_api_sweep(tmp_path))
    table = result.table
    assert len(table) == 4 and table.complete and not table.failed.any()
    assert sorted(zip(table["gap_m"].tolist(), table["mass_kg"].tolist(), strict=True)) == \
        [(g, m) for g in GAPS for m in MASSES]
    assert sum(b.n_designs for b in result.bands) == 4  # every design lies in one band of the table
    assert result.others == []
    again = sweep_app.run(_api_sweep(tmp_path))  # a finished sweep resumes with nothing to compute
    assert (tmp_path / "sweep.csv").read_text().count("\n") == 5 and len(again.table) == 4


def _scene(text: str):
    return scene_from_dict(tomllib.loads(text))


def test_the_command_line_and_a_scene_build_equal_jobs(tmp_path):
    args = build_parser().parse_args([*ARGV, "--out", str(tmp_path / "sweep"), "--max-memory", str(CAP)])
    from_cli = sweep_from_args(args)
    from_scene = sweep_settings(_scene(SCENE), tmp_path)
    assert from_cli == from_scene
    assert from_cli == _api_sweep(tmp_path / "sweep", max_memory_mb=CAP)
    assert from_cli.spec == from_scene.spec and len(from_cli.spec.designs()) == 4
    assert from_cli.names["m"] == "--m" and from_scene.names["m"] == "outputs.sweep.mass_kg"
    assert from_cli.names["workers"] == "--workers" and from_scene.names["workers"] == "outputs.sweep.workers"
    (tmp_path / "sweep").mkdir()
    target = ["--inclination", str(TARGET[0]), "--tolerance", str(TARGET[1])]
    files = ["--png", str(tmp_path / DESIGN_FILES[0]), "--choice", str(tmp_path / DESIGN_FILES[1])]
    design_cli = design_from_args(build_parser().parse_args(
        ["design", "--sweep", str(tmp_path / "sweep"), *target, *files, "--max-memory", str(CAP)]))
    scene = _scene(SCENE + f"[outputs.design_table]\ninclination_m_s = {TARGET[0]}\ntolerance_m_s = {TARGET[1]}\n")
    assert design_cli == design_settings(scene, tmp_path)
    assert design_settings(scene).files() == {}  # before the run folder: the scene's settings alone


def _record(records, name):
    return next(s for s in records if s.name == name)


def _draw(rng, name, low, high, n=1) -> list:
    """``n`` distinct values of damper record ``name`` in [low, high] within its range, to 4 significant digits."""
    r = _record(DAMPER, name)
    assert r.low <= low and high <= r.high  # the window lies inside the record's range
    return sorted({float(f"{rng.uniform(low, high):.4g}") for _ in range(n)})


def _random_case(rng):
    """Settings drawn from the records' ranges: the command's argv, the scene's TOML and the API's job fields."""
    gaps, masses = _draw(rng, "gap", 0.005, 0.2, rng.randint(1, 3)), _draw(rng, "m", 0.005, 0.5, rng.randint(1, 3))
    (c1,), (v0,) = _draw(rng, "c1", 0.0, 100.0), _draw(rng, "v0", 0.1, 5.0)
    duration = float(f"{rng.uniform(0.05, 30.0):.3g}")
    workers, levels = rng.randint(1, 8), rng.random() < 0.5
    assert _record(SWEEP, "duration").check(duration) == duration and _record(SCENE_SWEEP, "workers").check(workers)
    text = lambda values: ",".join(repr(v) for v in values)  # noqa: E731 - one line
    argv = ["sweep", "--gap", text(gaps), "--m", text(masses), "--c1", repr(c1), "--v0", repr(v0), "--duration",
            repr(duration), "--workers", str(workers), "--solver", "event", *(["--levels"] if levels else [])]
    scene = (f'[damper]\nsolver = "event"\ncontact_damping_n_s_m = {c1!r}\ninitial_velocity_m_s = {v0!r}\n'
             f'[outputs.sweep]\ngap_m = "{text(gaps)}"\nmass_kg = "{text(masses)}"\nduration_s = {duration!r}\n'
             f"workers = {workers}\nlevels = {str(levels).lower()}\n")
    api = dict(gap=tuple(gaps), m=tuple(masses), c1=(c1,), v0=(v0,), workers=workers,
               settings=FixedSettings(duration=duration, levels=levels))
    return argv, scene, api


@pytest.mark.parametrize("seed", range(20))
def test_random_settings_give_equal_jobs_from_every_front_end(seed, tmp_path):
    argv, scene, api = _random_case(random.Random(seed))
    out = str(tmp_path / "sweep")
    from_cli = sweep_from_args(build_parser().parse_args([*argv, "--out", out, "--max-memory", str(CAP)]))
    from_scene = sweep_settings(_scene(scene), tmp_path)
    from_api = SweepJob(**api, out=out, max_memory_mb=CAP)
    assert from_cli == from_scene == from_api
    assert from_cli.spec == from_scene.spec == from_api.spec


@pytest.mark.parametrize("seed", range(20))
def test_random_targets_give_equal_design_jobs_from_every_front_end(seed, tmp_path):
    rng = random.Random(1000 + seed)
    inclination, tolerance = (_record(DESIGN, name).check(float(f"{rng.uniform(1e-4, 0.1):.4g}"))
                              for name in ("inclination", "tolerance"))
    (tmp_path / "sweep").mkdir()
    png, choice = str(tmp_path / "design_table.png"), str(tmp_path / "design_choice.txt")
    from_cli = design_from_args(build_parser().parse_args(
        ["design", "--sweep", str(tmp_path / "sweep"), "--inclination", repr(inclination), "--tolerance",
         repr(tolerance), "--png", png, "--choice", choice, "--max-memory", str(CAP)]))
    scene = _scene(SCENE + f"[outputs.design_table]\ninclination_m_s = {inclination!r}\n"
                           f"tolerance_m_s = {tolerance!r}\n")
    from_api = DesignJob(inclination, tolerance, sweep=str(tmp_path / "sweep"), png=png, choice=choice,
                         max_memory_mb=CAP)
    assert from_cli == design_settings(scene, tmp_path) == from_api


def test_the_swept_records_are_the_scene_keys():
    """``[outputs.sweep]``'s gap_m and mass_kg are the records of --gap and --m, with the damper's ranges."""
    gap, m = _record(SWEPT, "gap"), _record(SWEPT, "m")
    assert (gap.path, m.path) == ("outputs.sweep.gap_m", "outputs.sweep.mass_kg")
    for s in (gap, m):
        r = _record(DAMPER, s.name)
        assert (s.kind, s.low, s.high, s.low_open, s.unit) == ("range", r.low, r.high, r.low_open, r.unit)
    assert gap.check("0.02:0.06:5") == (0.02, 0.03, 0.04, 0.05, 0.06)
    with pytest.raises(ParameterError) as exc:
        gap.check("0.02,11")
    assert exc.value.name == "gap" and "(0, 10] m" in exc.value.detail
    assert DEFINITION.choices == DEFINITIONS


def _no_work(monkeypatch):
    """Make any design's run fail the test: bad input must be refused before it."""
    import acoustiviz.sweep.execute

    def refuse(*args, **kwargs):
        raise AssertionError("a design ran")

    monkeypatch.setattr(acoustiviz.sweep.execute, "evaluate_or_fail", refuse)


@pytest.mark.parametrize("extra, option", [
    (["--executor", "dask://nohost"], "--executor"),
    (["--band-width", "0"], "--band-width"),
    (["--workers", "0"], "--workers"),
    (["--gap", "0:1:20000"], "--gap"),
    (["--m", "0.001:1:10000", "--gap", "0.01:1:9000"], "--m"),  # 9e7 designs: over the cap, named by the longest
])
def test_the_command_refuses_bad_input_before_any_work(tmp_path, capsys, monkeypatch, extra, option):
    _no_work(monkeypatch)
    assert main(["sweep", "--out", str(tmp_path / "x"), "--duration", "1", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz sweep: error: {option}") and "\n" not in err, err
    assert not (tmp_path / "x").exists()


def test_a_folder_in_the_way_is_refused_naming_the_scene_key(tmp_path):
    (tmp_path / "sweep").write_text("not a folder")
    with pytest.raises(ParameterError) as exc:
        sweep_settings(_scene(SCENE), tmp_path)
    assert exc.value.name == "outputs.sweep"


def test_the_design_command_refuses_a_file_it_cannot_write_naming_the_option(tmp_path, capsys):
    (tmp_path / "sweep").mkdir()
    argv = ["design", "--sweep", str(tmp_path / "sweep"), "--inclination", "0.008"]
    assert main([*argv, "--choice", str(tmp_path / "choice.csv")]) == 2
    assert capsys.readouterr().err.startswith("acoustiviz design: error: --choice")
    assert main([*argv, "--rank-by", "loudness"]) == 2
    assert capsys.readouterr().err.startswith("acoustiviz design: error: --rank-by")
    assert not (tmp_path / "choice.csv").exists()
