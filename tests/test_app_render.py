"""The render jobs: one job per view for the command line, scenes and the API, its data computed once.

Each view (snapshot, balloon, animation) is asked for three ways (``acoustiviz render VIEW``, a scene's
``[outputs.VIEW]`` and the job built in Python) and the files are compared byte for byte; the command line
and the scene must build equal jobs, also for random valid settings drawn from the records; a snapshot
written as PNG, VTU and HTML evaluates its field once; bad input is refused before any work.
"""

from __future__ import annotations

import random
import sys
import tomllib

import numpy as np
import pytest

import acoustiviz.field.evaluate as evaluate
from acoustiviz.app.impacts import impact_setup
from acoustiviz.app.outputs import replacing
from acoustiviz.app.render_job import AnimationJob, BalloonJob, SnapshotJob, run, view_job
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.render import settings_from_args
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

pytest.importorskip("pyvista")

#: The paper's Figure 2 sphere above a reflecting plane, as the API takes it.
SETUP = dict(radius=0.01905, velocity=1.4, density=7800.0, config="plane")

#: View -> (argv of its settings, the scene's TOML of the same, API keywords of the job, files: kind -> name).
CASES = {
    "snapshot": (("--time", "0.0003", "0.0006", "--sections", "xz,xy", "--extent", "0.3", "--resolution", "21",
                  "--size", "240x120"),
                 "[grids.plane]\nsections = ['xz', 'xy']\nextent_m = 0.3\nresolution = 21\n"
                 "[outputs.snapshot]\ntimes_s = [0.0003, 0.0006]\nsize_px = [240, 120]\nvtk = true\nhtml = true\n",
                 dict(times=(0.0003, 0.0006), sections=("xz", "xy"), extent=0.3, n_u=21, size=(240, 120)),
                 {"png": "snapshot.png", "vtk": "snapshot.vtu", "html": "snapshot.html"}),
    "balloon": (("--resolution", "6", "--distance", "0.5", "--db-range", "20", "--size", "200x150"),
                "[grids.sphere]\nn_theta = 6\ndistance_m = 0.5\n"
                "[outputs.balloon]\ndb_range = 20.0\nsize_px = [200, 150]\nvtk = true\nhtml = true\n",
                dict(n_theta=6, distance=0.5, db_range=20.0, size=(200, 150)),
                {"png": "balloon.png", "vtk": "balloon.vtu", "html": "balloon.html"}),
    "animation": (("--frames", "3", "--fps", "8", "--resolution", "21", "--size", "160x120"),
                  "[grids.plane]\nresolution = 21\n[outputs.animation]\nframes = 3\nfps = 8.0\n"
                  "size_px = [160, 120]\nvtk = true\n",
                  dict(frames=3, fps=8.0, n_u=21, size=(160, 120)),
                  {"gif": "animation.gif", "vtk": "animation.vtu"}),
}

JOBS = {"snapshot": SnapshotJob, "balloon": BalloonJob, "animation": AnimationJob}


def _written(view):
    files = CASES[view][3]
    stem = files["vtk"][:-4]
    return sorted([*files.values(), f"{stem}_geometry.vtu"])


def _job(view, **kw):
    s = impact_setup(**SETUP)
    return JOBS[view](impact=s.impact, pulse=s.pulse, medium=s.medium, geometry=s.geometry, **kw)


def _scene(view):
    return scene_from_dict(tomllib.loads('[configuration]\nkind = "plane"\n' + CASES[view][1]))


@pytest.mark.parametrize("view", CASES)
def test_every_front_end_writes_the_same_files(view, tmp_path, monkeypatch, capsys):
    argv, scene, job, files = CASES[view]
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    options = [x for k, v in files.items() for x in (f"--{k}", v)]
    assert main(["render", view, "--config", "plane", *argv, *options]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert all(f"wrote {name}" in printed for name in _written(view))
    toml = tmp_path / "scene.toml"
    toml.write_text('[configuration]\nkind = "plane"\n' + scene)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    written = run(_job(view, **job, **files)).write(api)
    assert sorted(p.name for p in written) == _written(view)
    for name in _written(view):
        mine = (cli / name).read_bytes()
        assert len(mine) > 500
        assert (tmp_path / "scene" / name).read_bytes() == mine, f"the scene's {name} differs from the CLI's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"


@pytest.mark.parametrize("view", CASES)
def test_the_command_line_and_a_scene_build_equal_jobs(view, tmp_path):
    argv, _, job, files = CASES[view]
    paths = {k: str(tmp_path / v) for k, v in files.items()}
    # the scene's memory cap (grids.memory_limit_mb) defaults to 256 MB, the command line's to --max-memory's
    args = build_parser().parse_args(["render", view, "--config", "plane", *argv, "--max-memory", "256",
                                      *[x for k, v in paths.items() for x in (f"--{k}", v)]])
    from_cli = settings_from_args(args)
    from_scene = view_job(_scene(view), view, tmp_path)
    assert from_cli == from_scene
    assert from_cli == _job(view, **job, **paths, max_memory_mb=256.0)
    assert from_cli.files() == paths
    assert from_cli.names["size"] == "--size" and from_scene.names["size"] == f"outputs.{view}.size_px"


def test_a_job_asks_for_no_file_and_writes_none():
    result = run(_job("snapshot", times=(0.0005,), n_u=21))
    field = result.field
    assert field.times.tolist() == [0.0005]
    n = field.grids[0].points.shape[0]
    assert field.pressures[0].shape == (1, n)
    fluid = np.isfinite(field.pressures[0][0])
    assert 0 < fluid.sum() < n  # the points inside the sphere are blank
    assert not field.pressures[0].flags.writeable
    assert result.write() == []


@pytest.mark.parametrize("view", CASES)
def test_every_option_and_scene_key_of_a_view_is_its_jobs_record(view):
    """The command's options of the view and the scene's keys of ``[outputs.<view>]`` are made from the records."""
    import argparse

    from acoustiviz.scene.schema import SCHEMA

    parser = build_parser()
    sub = parser
    for name in ("render", view):
        sub = next(a for a in sub._actions if isinstance(a, argparse._SubParsersAction)).choices[name]
    options = {o for a in sub._actions for o in a.option_strings if o.startswith("--")}
    from acoustiviz.app.outputs import REPLACE
    from acoustiviz.app.settings.impact import IMPACT, WAVEFORM
    from acoustiviz.app.settings.room import ROOM

    # the impact's, the room's and the global options, the same for every command
    others = {s.option for s in (*IMPACT, *ROOM, WAVEFORM[1], REPLACE)} | {*REPLACE.aliases, "--help", "--max-memory"}
    cls = JOBS[view]
    assert options - others == {s.option for s in cls.TABLE if s.option}
    keys = SCHEMA["outputs"].keys[view].keys
    records = {s.key: s for s in cls.TABLE if s.table == f"outputs.{view}"}
    assert set(keys) - {"vtk", "html"} == set(records)
    for key, s in records.items():
        k = keys[key]
        assert (k.low, k.high, k.unit, tuple(k.choices), k.doc) == (s.low, s.high, s.unit, tuple(s.choices), s.doc)
        assert k.default == (list(s.in_scene) if isinstance(s.in_scene, tuple) else s.in_scene)


# --------------------------------------------------------------------------- random settings from the records
def _value(s, rng: random.Random):
    """A random valid value of record ``s`` that keeps the job small (nothing is computed)."""
    if s.kind == "size":
        return (rng.randint(64, 400), rng.randint(64, 400))
    if s.kind == "strs":
        return tuple(rng.sample(s.choices, rng.randint(1, len(s.choices))))
    if s.kind == "floats":
        return tuple(round(rng.uniform(0.0, 0.002), 6) for _ in range(rng.randint(1, 3)))
    if s.choices:
        return rng.choice(s.choices)
    small = {"n_u": (8, 60), "n_theta": (s.low, 12), "frames": (2, 12)}
    if s.kind == "int":
        return rng.randint(*(int(v) for v in small.get(s.name, (s.low, s.low + 20))))
    wide = {"extent": (0.1, 0.5), "distance": (0.15, 2.0), "db_range": (1.0, 200.0), "fps": (1.0, 60.0)}
    return round(rng.uniform(*wide[s.name]), 4)


def _cli_text(s, value) -> list:
    if s.kind == "size":
        return ["{}x{}".format(*value)]
    if s.kind == "strs":
        return [",".join(value)]
    if s.kind == "floats":
        return [repr(v) for v in value]
    return [repr(value) if isinstance(value, float) else str(value)]


def _toml(value) -> str:
    if isinstance(value, tuple):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return f'"{value}"' if isinstance(value, str) else repr(value)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("view", CASES)
def test_random_settings_build_equal_jobs_from_every_front_end(view, seed, tmp_path):
    rng = random.Random(f"{view}-{seed}")
    cls = JOBS[view]
    shared = [s for s in cls.TABLE if s.key and s.option]  # settable both ways
    values = {s.name: _value(s, rng) for s in shared}
    argv = [x for s in shared for x in (s.option, *_cli_text(s, values[s.name]))]
    tables = {}
    for s in shared:
        tables.setdefault(s.table, []).append(f"{s.key} = {_toml(values[s.name])}")
    toml = '[configuration]\nkind = "plane"\n' + "".join(f"[{t}]\n" + "\n".join(keys) + "\n"
                                                         for t, keys in tables.items())
    if f"outputs.{view}" not in tables:
        toml += f"[outputs.{view}]\n"
    first = cls.FILES[0]
    path = str(tmp_path / f"{view}.{first}")
    args = build_parser().parse_args(["render", view, "--config", "plane", *argv, "--max-memory", "256",
                                      f"--{first}", path])
    from_cli = settings_from_args(args)
    from_scene = view_job(scene_from_dict(tomllib.loads(toml)), view, tmp_path)
    from_api = _job(view, **values, max_memory_mb=256.0, **{first: path})
    assert from_cli == from_scene == from_api, (argv, toml)
    for s in shared:  # each value as drawn, in its type
        assert getattr(from_api, s.name) == values[s.name]


# --------------------------------------------------------------------------- computed once
def _count_evaluations(monkeypatch) -> list:
    """Wrap the field evaluator wherever a loaded module holds it; return the list of its calls."""
    original = evaluate.snapshots
    calls = []

    def counted(pulse, times, points, *args, **kwargs):
        calls.append(np.asarray(points).shape[0])
        return original(pulse, times, points, *args, **kwargs)

    for name, module in list(sys.modules.items()):
        if name.startswith("acoustiviz") and getattr(module, "snapshots", None) is original:
            monkeypatch.setattr(module, "snapshots", counted)
    return calls


def test_png_vtu_and_html_of_a_snapshot_evaluate_the_field_once(tmp_path, monkeypatch):
    calls = _count_evaluations(monkeypatch)
    files = {"png": "s.png", "vtk": "s.vtu", "html": "s.html"}
    result = run(_job("snapshot", times=(0.0005,), n_u=21, size=(200, 150), **files))
    assert len(calls) == 1  # one section, evaluated by the run
    written = result.write(tmp_path)
    assert sorted(p.name for p in written) == ["s.html", "s.png", "s.vtu", "s_geometry.vtu"]
    assert all(p.stat().st_size > 0 for p in written)
    assert len(calls) == 1  # the three files drew the one field


def test_a_scene_asking_for_png_vtu_and_html_evaluates_the_field_once(tmp_path, monkeypatch, capsys):
    calls = _count_evaluations(monkeypatch)
    toml = tmp_path / "scene.toml"
    toml.write_text('[configuration]\nkind = "plane"\n[grids.plane]\nresolution = 21\n'
                    "[outputs.snapshot]\ntimes_s = [0.0005]\nsize_px = [200, 150]\nvtk = true\nhtml = true\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 0, capsys.readouterr().err
    assert {p.name for p in (tmp_path / "out").iterdir()} >= {"snapshot.png", "snapshot.vtu", "snapshot.html"}
    assert len(calls) == 1


def test_the_files_of_a_weighted_balloon_compute_nothing(tmp_path, monkeypatch):
    """A weighted level (LCpeak): the run computes the VTK file's metrics too, so writing only draws and exports."""
    import acoustiviz.field.balloon as balloon
    import acoustiviz.field.metrics as metrics

    result = run(_job("balloon", metric="lcpeak", n_theta=4, size=(200, 150), png="w.png", vtk="w.vtu"))
    n = result.data.directions.shape[0] * result.data.directions.shape[1]
    assert result.data.metrics.peak_spl_db.shape == (n,)

    def refuse(*args, **kwargs):
        raise AssertionError("a sink evaluated the field")

    monkeypatch.setattr(metrics, "field_metrics", refuse)  # the evaluator, and the name the balloon calls it by
    monkeypatch.setattr(balloon, "field_metrics", refuse)
    written = result.write(tmp_path)
    assert [p.name for p in written] == ["w.png", "w.vtu", "w_geometry.vtu"]


# --------------------------------------------------------------------------- refused before any work
def _no_work(monkeypatch):
    """Make any evaluation of a field fail the test: bad input must be refused before it."""
    def refuse(*args, **kwargs):
        raise AssertionError("the field was evaluated")

    for name, module in list(sys.modules.items()):
        if name.startswith("acoustiviz") and getattr(module, "snapshots", None) is evaluate.snapshots:
            monkeypatch.setattr(module, "snapshots", refuse)


@pytest.mark.parametrize("argv, option", [
    (["snapshot", "--time", "0.001", "--sections", "xz,xz", "--png", "s.png"], "--sections"),
    (["snapshot", "--time", *["0.001"] * 13, "--png", "s.png"], "--time"),
    (["snapshot", "--resolution", "20000", "--png", "s.png"], "--resolution"),  # over the memory cap
    (["snapshot", "--png", "s.png", "--html", "s.png"], "--html"),  # an ending the page cannot have
    (["snapshot", "--png", "s.png", "--vtk", "s.vtk"], "--vtk"),
    (["balloon", "--room", "3,2.5,2", "--duration", "0.02", "--distance", "2.5",
      "--png", "b.png"], "--distance"),  # the measuring sphere leaves the room
    (["animation", "--size", "64x9000", "--gif", "a.gif"], "--size"),
])
def test_bad_options_are_refused_before_any_work_naming_the_option(argv, option, tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    monkeypatch.chdir(tmp_path)
    assert main(["render", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz render: error: {option}") and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_bad_scene_settings_are_refused_naming_the_scene_key(tmp_path, monkeypatch):
    _no_work(monkeypatch)
    names = view_job(_scene("snapshot"), "snapshot").names  # the scene's vocabulary
    with pytest.raises(ParameterError, match=r"^outputs\.snapshot\.times_s: "):
        _job("snapshot", times=(-1.0,), names=names)
    with pytest.raises(ParameterError, match=r"^grids\.plane\.sections: "):
        _job("snapshot", sections=("xz", "ab"), names=names)
    with pytest.raises(ParameterError, match=r"^grids\.plane\.resolution: .*grids\.memory_limit_mb"):
        _job("snapshot", n_u=20000, max_memory_mb=1.0, names=names)
    (tmp_path / "snapshot.png").write_bytes(b"kept")
    with replacing(False, "--force"), pytest.raises(ParameterError, match=r"^outputs\.snapshot: .*exists"):
        view_job(_scene("snapshot"), "snapshot", tmp_path)
    assert (tmp_path / "snapshot.png").read_bytes() == b"kept"
