"""The map job: one settings object, one run and one writer for the command line, scenes and the API.

The same map is asked for three ways (``acoustiviz map``, a scene's ``[outputs.level_map]`` and
:class:`~acoustiviz.app.settings.map_job.MapJob` built in Python) and the files are compared byte for
byte; the command line and the scene must build equal settings objects; the settings refuse bad input
before any work, naming the front end's option or key.
"""

from __future__ import annotations

import dataclasses
import tomllib

import numpy as np
import pytest

import acoustiviz.app.maps as job_module
from acoustiviz.app.impacts import impact_setup, room_settings
from acoustiviz.app.map_job import MapJob, map_settings, run
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.map import settings_from_args
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

#: The paper's Figure 2 sphere, as the API takes it.
SPHERE = dict(radius=0.01905, velocity=1.4, density=7800.0)

#: (argv, scene TOML before its [outputs.level_map] table, the table's keys, API keywords of the job,
#: API configuration keywords).
CASES = {
    "vertical": (("--config", "plane", "--extent", "0.2", "--resolution", "24"),
                 '[configuration]\nkind = "plane"\n', "extent_m = 0.2\nresolution = 24\nvtk = true\n",
                 dict(extent=0.2, resolution=24), dict(config="plane")),
    "horizontal": (("--config", "wall-floor", "--plane", "horizontal", "--plane-height", "0.05", "--extent", "0.25",
                    "--resolution", "20"),
                   '[configuration]\nkind = "wall-floor"\n',
                   'plane = "horizontal"\nheight_m = 0.05\nextent_m = 0.25\nresolution = 20\nvtk = true\n',
                   dict(plane="horizontal", height=0.05, extent=0.25, resolution=20), dict(config="wall-floor")),
    "room": (("--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905", "--duration", "0.005",
              "--extent", "0.3", "--resolution", "16"),
             '[configuration]\nkind = "room"\nroom_m = [3.0, 2.5, 2.0]\nabsorption = [0.3]\n'
             'source_m = [1.0, 1.0, 0.01905]\nwindow_s = 0.005\n', "extent_m = 0.3\nresolution = 16\nvtk = true\n",
             dict(extent=0.3, resolution=16),
             dict(room=room_settings("3,2.5,2", absorption="0.3", source="1,1,0.01905", duration=0.005))),
}

FILES = {"png": "level_map.png", "csv": "level_map.csv", "vtk": "level_map.vtu"}
WRITTEN = ("level_map.csv", "level_map.png", "level_map.vtu", "level_map_geometry.vtu")


def _setup(case: str):
    return impact_setup(**SPHERE, **CASES[case][4])


@pytest.mark.parametrize("case", CASES)
def test_every_front_end_writes_the_same_files(case, tmp_path, monkeypatch, capsys):
    argv, scene, table, job, _ = CASES[case]
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    options = [x for k, v in FILES.items() for x in (f"--{k}", v)]
    assert main(["map", *argv, *options]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert printed.startswith("impact: U0 = 1.4 m/s")
    assert all(f"wrote {name}" in printed for name in WRITTEN)
    toml = tmp_path / "scene.toml"
    toml.write_text(scene + "[outputs.level_map]\n" + table)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    s = _setup(case)
    result = run(MapJob(impact=s.impact, pulse=s.pulse, medium=s.medium, geometry=s.geometry, **job, **FILES))
    written = result.write(api)
    assert sorted(p.name for p in written) == list(WRITTEN)
    for name in WRITTEN:
        mine = (cli / name).read_bytes()
        assert len(mine) > 100
        assert (tmp_path / "scene" / name).read_bytes() == mine, f"the scene's {name} differs from the CLI's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"


def test_the_result_holds_the_grid_and_the_levels_in_si_units():
    s = _setup("vertical")
    result = run(MapJob(impact=s.impact, pulse=s.pulse, medium=s.medium, geometry=s.geometry, extent=0.2,
                        resolution=24))
    level = result.level
    n = level.grid.points.shape[0]
    assert level.peak_pa.shape == level.sel_db.shape == (n,)
    fluid = np.isfinite(level.peak_pa)
    assert 0 < fluid.sum() < n  # the points inside the sphere are blank
    # the peak SPL in dB re 20 uPa of the peak pressure in Pa, point by point
    np.testing.assert_allclose(level.peak_spl_db[fluid], 20 * np.log10(level.peak_pa[fluid] / 20e-6), rtol=1e-9)
    assert np.all(np.abs(level.grid.points[fluid] - s.geometry.centre) <= 0.2 + 1e-12)
    assert result.write() == []  # no files asked for, none written


@pytest.mark.parametrize("case", CASES)
def test_the_command_line_and_a_scene_build_equal_settings(case, tmp_path):
    argv, scene, table, _, _ = CASES[case]
    paths = {k: str(tmp_path / v) for k, v in FILES.items()}
    # the scene's memory cap (grids.memory_limit_mb) defaults to 256 MB, the command line's to --max-memory's
    args = build_parser().parse_args(["map", *argv, "--max-memory", "256",
                                      *[x for k, v in paths.items() for x in (f"--{k}", v)]])
    from_cli = settings_from_args(args)
    from_scene = map_settings(scene_from_dict(tomllib.loads(scene + "[outputs.level_map]\n" + table)), tmp_path)
    if case == "room":  # a scene's room is not capped by grids.memory_limit_mb, the command line's by --max-memory
        assert from_cli.geometry.max_memory_mb == 256.0 and from_scene.geometry.max_memory_mb is None
        assert from_cli.geometry.image_order == from_scene.geometry.image_order  # the cap does not bind
        from_cli = dataclasses.replace(from_cli, geometry=dataclasses.replace(from_cli.geometry,
                                                                                   max_memory_mb=None))
    assert from_cli == from_scene
    assert from_cli.files() == paths
    assert from_cli.names["resolution"] == "--resolution"
    assert from_scene.names["resolution"] == "outputs.level_map.resolution"


def _no_work(monkeypatch):
    """Make any computation of a map fail the test: bad input must be refused before it."""
    def refuse(*args, **kwargs):
        raise AssertionError("the map was computed")

    monkeypatch.setattr(job_module, "map_on_grid", refuse)


@pytest.mark.parametrize("extra, option", [
    (["--extent", "0.03"], "--extent"),  # inside the sphere's diameter
    (["--resolution", "7"], "--resolution"),
    (["--plane-height", "0.1"], "--plane-height"),  # a height for the vertical plane
    (["--plane", "horizontal", "--plane-height", "-0.1"], "--plane-height"),  # below the floor
    (["--resolution", "20000"], "--resolution"),  # over the memory cap: the option to lower
    (["--png", "m.csv"], "--png"),  # the same file twice
    (["--vtk", "m.png"], "--vtk"),
])
def test_bad_options_are_refused_before_any_work_naming_the_option(extra, option, tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    monkeypatch.chdir(tmp_path)
    assert main(["map", "--config", "plane", "--csv", "m.csv", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz map: error: {option}") and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_bad_scene_settings_are_refused_naming_the_scene_key(monkeypatch):
    _no_work(monkeypatch)
    setup = _setup("vertical")
    scene = scene_from_dict({"configuration": {"kind": "plane"}, "outputs": {"level_map": {}}})
    names = map_settings(scene).names  # the scene's vocabulary
    job = dict(impact=setup.impact, pulse=setup.pulse, medium=setup.medium, geometry=setup.geometry,
               names=names)
    with pytest.raises(ParameterError, match=r"^outputs\.level_map\.resolution: .*\[8, 20000\]"):
        MapJob(**job, resolution=4)
    with pytest.raises(ParameterError, match=r"^outputs\.level_map\.extent_m: .*diameter"):
        MapJob(**job, extent=0.02)
    with pytest.raises(ParameterError, match=r"^outputs\.level_map\.height_m: "):
        MapJob(**job, plane="horizontal", height=-1.0)
    with pytest.raises(ParameterError, match=r"^outputs\.level_map\.resolution: .*grids\.memory_limit_mb"):
        MapJob(**job, resolution=20000, max_memory_mb=1.0)


def test_a_bad_scene_is_refused_before_the_run_folder_is_made(tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    toml = tmp_path / "scene.toml"
    toml.write_text('[configuration]\nkind = "plane"\n[outputs.level_map]\nextent_m = 0.02\n')
    assert main(["run", str(toml), "--out", str(tmp_path / "out")]) == 2
    assert "outputs.level_map.extent_m" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
