"""The auralize job: one settings object, one run and one writer for the command line, scenes and the API.

The same damper run is auralised three ways (``acoustiviz auralize``, a scene's ``[outputs.wav]`` with
``[outputs.levels]``, and an :class:`~acoustiviz.app.auralize.AuralizeJob` built in Python) and the
files are compared byte for byte; the command line and the scene must build equal jobs, for the
defaults and for random valid settings drawn from the records; bad input is refused before any work,
naming the front end's option or key.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from acoustiviz.app.auralize import AuralizeJob, run
from acoustiviz.app.damper import DamperJob, damper_model
from acoustiviz.app.pipeline import damper_settings
from acoustiviz.app.scene_wav import wav_settings
from acoustiviz.app.settings.auralize import ALL
from acoustiviz.app.settings.damper import DAMPER
from acoustiviz.app.settings.table import by_name
from acoustiviz.app.wav import cavity
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.auralize import settings_from_args
from acoustiviz.constants import DEFAULT_AIR_DENSITY, DEFAULT_SOUND_SPEED, PAPER_RADIUS
from acoustiviz.core.listener import Listener
from acoustiviz.core.medium import Medium
from acoustiviz.dynamics import InitialState
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict
from acoustiviz.sound import ClickModel, ImpactSequence

#: The listener of the paper: 0.7 m at 45 degrees from its sphere, in m.
LISTENER = (0.495, 0.0, 0.514)
#: Two ears for the stereo file, in m.
EARS = ((0.45, -0.09, 0.5), (0.45, 0.09, 0.5))
#: A short run of the Table 1 damper (a few impacts), the scene's memory cap and its solver spelled out
#: (a scene's solver defaults to auto, its contact stiffness to the materials').
SHORT = {"duration": 0.25, "k_hertz": 5.6e8, "solver": "event"}
_RECORDS = {**by_name(DAMPER), **by_name(ALL)}


def _argv(values: dict, wav: str, points, extra=()) -> list:
    """``acoustiviz auralize`` options of ``values`` (API name -> value), their spelling from the records."""
    argv = ["auralize", "--max-memory", "256", "--wav", wav]
    for name, value in values.items():
        s = _RECORDS[name]
        if s.kind == "bool":
            argv += [s.option] if value else []
        else:
            argv += [s.option, f"{value!r}" if s.kind == "float" else str(value)]
    for p in points:
        argv += ["--listener", ",".join(f"{x!r}" for x in p)]
    return [*argv, *extra]


def _scene(values: dict, names, points, outputs=None) -> dict:
    """The scene of ``values`` (API name -> value), each under its record's scene key."""
    data = {"outputs": outputs or {"wav": {}},
            "listeners": [{"name": n, "position_m": list(p)} for n, p in zip(names, points, strict=True)]}
    for name, value in values.items():
        table, _, key = _RECORDS[name].path.rpartition(".")
        section = data
        for part in table.split("."):
            section = section.setdefault(part, {})
        section[key] = value
    return data


def _api_job(values: dict, names, points, files, **kw) -> AuralizeJob:
    """The job of ``values`` built in Python from the core's objects."""
    d = {s.name: values.get(s.name, s.default) for s in DAMPER}
    model = damper_model(**{k: d[k] for k in ("M", "K", "C", "m", "gap", "k_hertz", "c1", "clip_tensile")})
    damper = DamperJob(model, InitialState(v=d["v0"]), d["duration"], d["solver"], d["rtol"], max_memory_mb=256)
    w = {k: values.get(k, _RECORDS[k].default) for k in ("struck_wall", "walls", "rate", "subtype", "stereo")}
    room = cavity("plane", PAPER_RADIUS, model.gap, struck_wall=w["struck_wall"], walls=w["walls"],
                  medium=Medium(c=DEFAULT_SOUND_SPEED, rho=DEFAULT_AIR_DENSITY))
    click = ClickModel(k_hertz=model.k_hertz, mass=model.m, main_mass=model.M)
    return AuralizeJob(model, room, click, tuple(Listener(n, p) for n, p in zip(names, points, strict=True)),
                       files, d["duration"], damper, stereo=w["stereo"], rate=w["rate"], subtype=w["subtype"],
                       max_memory_mb=256, **kw)


def _sidecar(path) -> dict:
    """A sidecar without what only describes the front end (the scene's name, where the radius came from)."""
    record = json.loads(path.read_text(encoding="utf-8"))
    return {k: v for k, v in record.items() if k not in ("scene_name", "radius_source")}


def test_every_front_end_writes_the_same_files(tmp_path, monkeypatch, capsys):
    values = {**SHORT, "rate": 44100}
    cli, scene_out, api = tmp_path / "cli", tmp_path / "scene", tmp_path / "api"
    for folder in (cli, api):
        folder.mkdir()
    monkeypatch.chdir(cli)
    assert main(_argv(values, "wav_listener1.wav", [LISTENER],
                      ["--levels-csv", "levels.csv", "--png", "waves.png"])) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    assert "wrote levels.csv" in out and "wrote wav_listener1.wav" in out and "wrote waves.png" in out
    scene = scene_from_dict(_scene(values, ["listener1"], [LISTENER], {"wav": {"rate_hz": 44100}, "levels": {}}))
    from acoustiviz.app.pipeline import run_scene

    run_scene(scene, scene_out)
    monkeypatch.chdir(api)
    job = _api_job(values, ["listener1"], [LISTENER], ("wav_listener1.wav",), levels_csv="levels.csv",
                   png="waves.png")
    written = run(job).write(api)
    assert sorted(p.name for p in written) == sorted(["levels.csv", "levels_bands.csv", "wav_listener1.wav",
                                                      "wav_listener1.json", "waves.png"])
    for name in ("wav_listener1.wav", "levels.csv", "levels_bands.csv"):
        mine = (cli / name).read_bytes()
        assert len(mine) > 200
        assert (scene_out / name).read_bytes() == mine, f"the scene's {name} differs from the command line's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the command line's"
    assert (api / "waves.png").read_bytes() == (cli / "waves.png").read_bytes()
    side = _sidecar(cli / "wav_listener1.json")
    assert side["impacts"] > 0 and side["damper"]["duration_s"] == SHORT["duration"]
    assert _sidecar(api / "wav_listener1.json") == side and "levels" in side
    # the scene's levels are an output of their own ([outputs.levels]), not recorded in the WAV's sidecar
    assert _sidecar(scene_out / "wav_listener1.json") == {k: v for k, v in side.items() if k != "levels"}


def test_the_command_line_and_a_scene_build_equal_jobs(tmp_path):
    args = build_parser().parse_args(_argv(SHORT, str(tmp_path / "wav_listener1.wav"), [LISTENER]))
    from_cli = settings_from_args(args)
    scene = scene_from_dict(_scene(SHORT, ["listener1"], [LISTENER]))
    from_scene = wav_settings(scene, tmp_path, damper_settings(scene))
    assert from_cli == from_scene
    assert from_cli == _api_job(SHORT, ["listener1"], [LISTENER], (str(tmp_path / "wav_listener1.wav"),))
    assert from_cli.room_sound is None and from_cli.impacts is None and from_cli.damper.duration == SHORT["duration"]
    assert from_cli.names["rate"] == "--rate" and from_scene.names["rate"] == "outputs.wav.rate_hz"
    other = scene_from_dict(_scene({**SHORT, "rate": 96000}, ["listener1"], [LISTENER]))
    assert wav_settings(other, tmp_path, damper_settings(other)) != from_cli


def test_a_room_with_a_late_tail_builds_equal_jobs(tmp_path):
    point = (1.0, 1.0, 1.2)
    room = ["--room", "3,4,2.5", "--absorption", "0.4", "--late-tail", "--tail-seed", "7"]
    from_cli = settings_from_args(build_parser().parse_args(_argv(SHORT, str(tmp_path / "wav_listener1.wav"),
                                                                  [point], room)))
    data = _scene(SHORT, ["listener1"], [point], {"wav": {"late_tail": True, "tail_seed": 7}})
    data["configuration"] = {"kind": "room", "room_m": [3.0, 4.0, 2.5], "absorption": [0.4]}
    scene = scene_from_dict(data)
    from_scene = wav_settings(scene, tmp_path, damper_settings(scene))
    assert from_cli == from_scene
    assert from_cli.room_sound.late_tail and from_cli.room_sound.seed == 7
    data["outputs"]["wav"]["tail_seed"] = 8
    other = scene_from_dict(data)
    assert wav_settings(other, tmp_path, damper_settings(other)) != from_cli


def _draw(rng) -> dict:
    """Random valid settings: damper records within a factor of two of their defaults, every wav record."""
    values = dict(SHORT, duration=float(rng.uniform(0.05, 0.5)))
    for name in ("M", "K", "C", "m", "gap", "c1", "v0"):
        s = _RECORDS[name]
        values[name] = float(np.clip(s.default * rng.uniform(0.5, 2.0), s.low, s.high))
    for s in ALL:
        if s.table == "outputs.wav" and s.name in ("rate", "subtype", "walls", "struck_wall", "stereo"):
            values[s.name] = bool(rng.integers(2)) if s.kind == "bool" else s.choices[rng.integers(len(s.choices))]
            if s.kind == "int":
                values[s.name] = int(values[s.name])
    return values


@pytest.mark.parametrize("seed", range(8))
def test_random_settings_build_equal_jobs_everywhere(seed, tmp_path):
    values = _draw(np.random.default_rng(seed))
    stereo = values["stereo"]
    names, points = (["left", "right"], EARS) if stereo else (["listener1"], [LISTENER])
    wav = str(tmp_path / ("wav_stereo.wav" if stereo else "wav_listener1.wav"))
    from_cli = settings_from_args(build_parser().parse_args(_argv(values, wav, points)))
    scene = scene_from_dict(_scene(values, names, points))
    from_scene = wav_settings(scene, tmp_path, damper_settings(scene))
    from_api = _api_job(values, names, points, (wav,))
    assert from_cli == from_scene == from_api, values
    assert from_cli.rate == values["rate"] and from_cli.stereo == stereo
    assert from_cli.cavity.struck_wall == values["struck_wall"] and from_cli.damper.duration == values["duration"]


def test_impacts_given_are_rendered_without_a_damper_run(tmp_path, monkeypatch):
    csv = tmp_path / "impacts.csv"
    csv.write_text("time_s,wall,approach_velocity_m_s\n0.01,-1,1.4\n0.05,1,-0.9\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    args = build_parser().parse_args(["auralize", "--impacts", str(csv), "--duration", "0.1", "--wav", "one.wav"])
    job = settings_from_args(args)
    assert job.damper is None and job.impacts == ImpactSequence([0.01, 0.05], [-1, 1], [1.4, 0.9])
    result = run(job)
    assert result.damper is None and result.sequence == job.impacts and not list(tmp_path.glob("*.wav"))
    assert [p.name for p in result.write()] == ["one.wav", "one.json"]
    assert json.loads((tmp_path / "one.json").read_text())["damper"]["impacts_csv"] == str(csv)


def test_bad_input_is_refused_before_any_work_naming_the_front_ends_words(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken.csv").write_text("x\n")
    assert main(["auralize", "--duration", "0.1", "--wav", "a.wav", "--levels-csv", "taken.csv"]) == 2
    err = capsys.readouterr().err
    assert "--levels-csv" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "a.wav").exists()
    scene = scene_from_dict(_scene(SHORT, ["listener1", "listener2"], [LISTENER, (0.3, 0.2, 0.4)]))
    with pytest.raises(ParameterError) as exc:
        _api_job(SHORT, ["listener1", "listener2"], [LISTENER, (0.3, 0.2, 0.4)], ("only_one.wav",))
    assert exc.value.name == "wav_files"
    job = wav_settings(scene, None, damper_settings(scene))
    assert job.wav_files == () and len(job.listeners) == 2
    inside = scene_from_dict(_scene(SHORT, ["listener1"], [(0.0, 0.0, 0.06)]))
    with pytest.raises(ParameterError) as exc:
        wav_settings(inside, tmp_path, damper_settings(inside))
    assert exc.value.name == "listeners"
