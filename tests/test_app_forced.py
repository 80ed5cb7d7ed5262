"""The forced job: one settings object, one run and one writer for the command line, scenes and the API.

The same damper in operation is asked for three ways (``acoustiviz forced``, a scene's
``[outputs.frequency_response]``, ``[outputs.bifurcation]`` and ``[outputs.operating_noise]``, and
:class:`~acoustiviz.app.settings.forced_job.ForcedJob` built in Python) and the files are compared byte
for byte; the command line and the scene must build equal settings objects, for a fixed case and for
random valid settings drawn from the records; the settings refuse bad input before any work, naming the
front end's option or key.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import random
import tomllib

import pytest

import acoustiviz.app.forced as job_module
from acoustiviz.app.damper import damper_model
from acoustiviz.app.forced import ForcedJob, forced_settings, run
from acoustiviz.app.settings.damper import MODEL
from acoustiviz.app.settings.forced import AMPLITUDE, EXCITATION_KIND, FORCED, FREQUENCIES
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.forced import settings_from_args
from acoustiviz.dynamics import DamperModel
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

#: A case that runs in seconds: one frequency, one start, instantaneous impacts, few cycles, a short interval.
ARGV = ("--force", "5", "--freq", "6.5", "--starts", "1", "--solver", "impact-map", "--max-cycles", "40",
        "--sweep", "independent", "--noise-seconds", "0.1", "--listener", "0.495,0,0.514")
SCENE = """
[excitation]
amplitude = 5.0
frequencies_hz = "6.5"
starts = 1
solver = "impact-map"
max_cycles = 40
sweep = "independent"
[[listeners]]
name = "ear"
position_m = [0.495, 0.0, 0.514]
[outputs.frequency_response]
[outputs.bifurcation]
[outputs.operating_noise]
seconds = 0.1
"""
#: The same job in Python (the damper: the paper's Table 1 with d = 4 cm, the default of both front ends).
API = dict(frequencies=(6.5,), kind="force", amplitude=5.0, starts=1, solver="impact-map", max_cycles=40,
           sweep="independent", noise_seconds=0.1, listener=(0.495, 0.0, 0.514))

#: Command-line file -> the scene's file holding the same bytes.
SAME = {"f.csv": "frequency_response.csv", "f.wav": "operating_noise_ear.wav"}
#: The scene's own figures and level table, which the API asks for by their fields.
SCENE_ONLY = {"response_png": "frequency_response.png", "bifurcation_png": "bifurcation.png",
              "noise_csv": "operating_noise.csv"}


def _no_work(monkeypatch):
    """Make any search for attractors fail the test: bad input must be refused before it."""
    def refuse(*args, **kwargs):
        raise AssertionError("the attractors were computed")

    monkeypatch.setattr(job_module, "attractor_response", refuse)


def test_every_front_end_writes_the_same_files(tmp_path, monkeypatch, capsys):
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main(["forced", *ARGV, "--wav", "f.wav", "--csv", "f.csv", "--png", "f.png"]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert printed.startswith("force amplitude 5 N; sweep independent; solver impact-map; 1 starts;")
    assert "wrote f.wav (sidecar f.json)" in printed and "wrote f.csv" in printed and "wrote f.png" in printed
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene"), "--quiet"]) == 0, capsys.readouterr().err
    scene = tmp_path / "scene"
    api = tmp_path / "api"
    api.mkdir()
    result = run(ForcedJob(damper_model(), **API, wav="f.wav", csv="f.csv", png="f.png", **SCENE_ONLY))
    written = result.write(api)
    assert sorted(p.name for p in written) == sorted(["f.wav", "f.json", "f.csv", "f.png", *SCENE_ONLY.values()])
    for name in ("f.wav", "f.json", "f.csv", "f.png"):
        mine = (cli / name).read_bytes()
        assert len(mine) > 100
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"
    for name, theirs in SAME.items():
        assert (scene / theirs).read_bytes() == (cli / name).read_bytes(), f"the scene's {theirs} differs"
    for name in SCENE_ONLY.values():
        assert (scene / name).read_bytes() == (api / name).read_bytes(), f"the API's {name} differs from the scene's"
    # the sidecars differ only by the file they describe
    sidecars = [json.loads((folder / name).read_text()) for folder, name in
                ((cli, "f.json"), (scene, "operating_noise_ear.json"))]
    assert sidecars[0].pop("file") == "f.wav" and sidecars[1].pop("file") == "operating_noise_ear.wav"
    assert sidecars[0] == sidecars[1]
    # the table carries the levels of the noise in operation: the level table's, row by row
    with open(api / "f.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    with open(api / "operating_noise.csv", newline="") as fh:
        levels = list(csv.DictReader(fh))
    assert len(rows) == len(levels) == len(result.rows) >= 1
    for row, level in zip(rows, levels, strict=True):
        assert row["regime"] == level["regime"]
        for c in ("laeq_db", "lcpeak_db", "lafmax_db"):
            assert float(row[c]) == float(level[c]), c


def test_the_result_holds_the_attractors_and_their_levels():
    result = run(ForcedJob(damper_model(), **API))
    assert result.write() == []  # no files asked for, none written
    assert result.success and len(result.rows) == len(result.noises) >= 1
    for row, noise in zip(result.rows, result.noises, strict=True):
        assert row["frequency_hz"] == 6.5 and row["starts"] == 1 and row["solver"] == "impact-map"
        assert row["laeq_db"] == noise.laeq_db
        # whole periods of the forcing (6.5 Hz) to a sample of the 96 kHz grid its ends are placed on;
        # a periodic motion's span at least the 0.1 s asked for
        assert noise.duration >= 0.1 or not row["regime"].startswith("periodic-")
        assert noise.duration * 6.5 == pytest.approx(round(noise.duration * 6.5), abs=2 * 6.5 / noise.sample_rate)
    assert run(dataclasses.replace(result.settings, noise=False)).noises is None


def test_the_command_line_and_a_scene_build_equal_settings(tmp_path):
    cli_files = {"wav": str(tmp_path / "operating_noise_ear.wav"), "csv": str(tmp_path / "frequency_response.csv")}
    # the scene's memory cap (grids.memory_limit_mb) defaults to 256 MB, the command line's to --max-memory's
    args = build_parser().parse_args(["forced", *ARGV, "--max-memory", "256",
                                      *[x for k, v in cli_files.items() for x in (f"--{k}", v)]])
    from_cli = settings_from_args(args)
    from_scene = forced_settings(scene_from_dict(tomllib.loads(SCENE)), tmp_path)
    assert from_scene.files() == {**cli_files, **{k: str(tmp_path / v) for k, v in SCENE_ONLY.items()}}
    assert from_cli == dataclasses.replace(from_scene, **dict.fromkeys(SCENE_ONLY))
    assert from_cli.frequencies == (6.5,) and from_cli.listener == (0.495, 0.0, 0.514)
    assert from_cli.names["starts"] == "--starts" and from_scene.names["starts"] == "excitation.starts"
    assert from_cli.names["amplitude"] == "--force" and from_scene.names["amplitude"] == "excitation.amplitude"
    # a scene without [outputs.operating_noise] is the command line without the noise
    quiet = SCENE.split("[outputs.bifurcation]")[0]
    args = build_parser().parse_args(["forced", *ARGV[:-4], "--no-noise", "--max-memory", "256"])  # no interval
    assert settings_from_args(args) == forced_settings(scene_from_dict(tomllib.loads(quiet)))


# --------------------------------------------------------------------------- random valid settings
def _log_uniform(rng, low, high):
    return math.exp(rng.uniform(math.log(low), math.log(high)))


def _draw(rng) -> dict:
    """Random valid settings ``{record: value}``, each drawn from its record's range or choices.

    The damper's main mass and spring are drawn first; the frequencies lie within a factor 3 of its
    natural frequency (the physics' limit is a factor 10), the dashpot below the critical one (the
    event solver's need), and starts times cycles within the memory cap.
    """
    by_name = {s.name: s for s in MODEL}
    model = {"M": _log_uniform(rng, 0.05, 50.0), "K": _log_uniform(rng, 10.0, 1e5)}
    critical = 2.0 * math.sqrt(model["K"] * model["M"])
    model.update(C=rng.uniform(0.0, 0.5 * critical), m=_log_uniform(rng, 1e-3, 1.0),
                 gap=_log_uniform(rng, 1e-3, 0.5), k_hertz=_log_uniform(rng, 1e6, 1e12), c1=rng.uniform(0.0, 100.0))
    for name, value in model.items():
        assert by_name[name].check(value) == value  # within the record's range
    f0 = math.sqrt(model["K"] / model["M"]) / (2.0 * math.pi)
    freqs = sorted({round(f0 * _log_uniform(rng, 1 / 3, 3), 4) for _ in range(rng.randint(1, 4))})
    rng.shuffle(freqs)  # any order: each front end sorts them
    values = {"model": model, "frequencies": freqs, "kind": rng.choice(EXCITATION_KIND.choices)}
    values["amplitude"] = _log_uniform(rng, 1e-3, AMPLITUDE.high) if values["kind"] == "force" \
        else _log_uniform(rng, 1e-6, 1e-2)
    for s in FORCED:
        if s.choices:
            values[s.name] = rng.choice(s.choices)
        elif s.kind == "int":
            values[s.name] = int(round(_log_uniform(rng, s.low, min(s.high, 1e5))))
        else:
            values[s.name] = _log_uniform(rng, s.low if s.low > 0 else 1e-3 * s.high, s.high)
    while len(freqs) * values["starts"] * values["max_cycles"] * 128 > 5e8:  # within the 2048 MB cap
        values["max_cycles"] = max(int(FORCED[5].low), values["max_cycles"] // 2)
        values["starts"] = max(1, values["starts"] // 2)
    values["noise"] = rng.random() < 0.5
    if not values["noise"]:  # the level interval is the noise's: without it, its default
        del values["noise_seconds"]
    values["listener"] = (rng.uniform(0.3, 1.0), rng.uniform(-0.5, 0.5), rng.uniform(0.3, 1.0))
    return values


def _argv(v: dict) -> list:
    argv = ["forced", "--max-memory", "2048", f"--{v['kind']}", repr(v["amplitude"]),
            FREQUENCIES.option, ",".join(repr(f) for f in v["frequencies"])]
    argv += [x for s in MODEL for x in (s.option, repr(v["model"][s.name]))]
    argv += [x for s in FORCED if s.name in v for x in (s.option, v[s.name] if isinstance(v[s.name], str)
                                                         else repr(v[s.name]))]
    if v["noise"]:
        return argv + ["--listener", ",".join(repr(x) for x in v["listener"])]
    return argv + ["--no-noise"]


def _scene(v: dict) -> dict:
    tables: dict = {"grids": {"memory_limit_mb": 2048.0}, "outputs": {"frequency_response": {}}}
    for s in MODEL:
        tables.setdefault(s.table, {})[s.key] = v["model"][s.name]
    tables["excitation"] = {EXCITATION_KIND.key: v["kind"], AMPLITUDE.key: v["amplitude"],
                            FREQUENCIES.key: ",".join(repr(f) for f in v["frequencies"])}
    for s in FORCED:
        if s.table == "excitation":
            tables["excitation"][s.key] = v[s.name]
    if v["noise"]:
        tables["outputs"]["operating_noise"] = {"seconds": v["noise_seconds"]}
        tables["listeners"] = [{"name": "ear", "position_m": list(v["listener"])}]
    return tables


def _api(v: dict) -> ForcedJob:
    return ForcedJob(DamperModel(**v["model"]), tuple(v["frequencies"]), kind=v["kind"], amplitude=v["amplitude"],
                     **{s.name: v[s.name] for s in FORCED if s.name in v}, noise=v["noise"],
                     listener=v["listener"] if v["noise"] else None, max_memory_mb=2048.0)


@pytest.mark.parametrize("seed", range(20))
def test_random_valid_settings_build_equal_jobs_from_every_front_end(seed):
    v = _draw(random.Random(seed))
    from_cli = settings_from_args(build_parser().parse_args(_argv(v)))
    from_scene = forced_settings(scene_from_dict(_scene(v)))
    from_api = _api(v)
    assert from_cli == from_scene == from_api
    assert from_api.frequencies == tuple(sorted(v["frequencies"]))
    assert from_cli.noise == v["noise"] and from_cli.starts == v["starts"] and from_cli.kind == v["kind"]


# --------------------------------------------------------------------------- errors in the user's words
@pytest.mark.parametrize("extra, option", [
    (["--starts", "0"], "--starts"),
    (["--max-cycles", "1000000000"], "--max-cycles"),
    (["--noise-seconds", "0"], "--noise-seconds"),
    (["--freq", "0.001"], "--freq"),  # far below the damper's natural frequency
    (["--freq", "6,6"], "--freq"),
    (["--force", "-1"], "--force"),
    (["--gap", "-0.01"], "--gap"),
    (["--workers", "0"], "--workers"),
    (["--executor", "nowhere"], "--executor"),
    (["--restitution", "0.5", "--solver", "event"], "--restitution"),
    (["--listener", "0,0,0.01"], "--listener"),  # inside the sphere
    (["--max-memory", "1"], "--noise-seconds"),  # the click trains exceed the cap
    (["--png", "f.csv"], "--png"),  # the same file twice
    (["--no-noise", "--wav", "f.wav"], "--wav"),
    (["--room", "3,2.5,2", "--duration", "0.05"], "--listener"),  # a room needs its listener
])
def test_bad_options_are_refused_before_any_work_naming_the_option(extra, option, tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    monkeypatch.chdir(tmp_path)
    argv = ["forced", "--force", "5", "--freq", "6.5", "--csv", "f.csv"]  # a later option given again wins
    assert main([*argv, *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz forced: error: {option}") and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_bad_scene_settings_are_refused_naming_the_scene_key(tmp_path, monkeypatch):
    _no_work(monkeypatch)
    names = forced_settings(scene_from_dict(tomllib.loads(SCENE))).names  # the scene's vocabulary
    job = dict(model=damper_model(), **API, names=names)
    cases = [(dict(starts=0), r"excitation\.starts: "),
             (dict(noise_seconds=0.0), r"outputs\.operating_noise\.seconds: "),
             (dict(frequencies=(0.001,)), r"excitation\.frequencies_hz: "),
             (dict(amplitude=-1.0), r"excitation\.amplitude: .*\[0, 1e\+09\] N"),
             (dict(kind="wind"), r"excitation\.kind: "),
             (dict(model=dataclasses.replace(damper_model(), C=100.0)), r"damper\.damping_n_s_m: "),  # overdamped
             (dict(listener=(0.0, 0.0, 0.01)), r"listeners: .*inside the sphere"),
             (dict(max_cycles=100_000, max_memory_mb=1.0), r"^excitation\.max_cycles: .*grids\.memory_limit_mb")]
    for change, message in cases:
        with pytest.raises(ParameterError, match=message):
            ForcedJob(**{**job, **change})


def test_a_bad_scene_is_refused_before_the_run_folder_is_made(tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    toml = tmp_path / "scene.toml"
    toml.write_text(SCENE + "[grids]\nmemory_limit_mb = 1.0\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    assert "outputs.operating_noise.seconds" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_the_scene_keys_of_the_excitation_are_the_records():
    from acoustiviz.scene.schema import SCHEMA

    keys = SCHEMA["excitation"].keys
    for s in (EXCITATION_KIND, AMPLITUDE, FREQUENCIES, *(s for s in FORCED if s.table == "excitation")):
        k = keys[s.key]
        assert (k.doc, k.default, k.unit, k.low, k.high, k.low_open, tuple(k.choices)) == \
            (s.doc, s.in_scene, s.unit, s.low, s.high, s.low_open, tuple(s.choices)), s.key
    assert keys[FREQUENCIES.key].kind == "frequencies"  # written as text: a range or a list
