"""The directivity job: one settings object, one run and one writer for the command line, scenes and the API.

The same directivity is asked for three ways (``acoustiviz directivity``, a scene's
``[outputs.directivity]`` and :class:`~acoustiviz.app.directivity.DirectivityJob` built in Python) and
the files are compared byte for byte; the command line and the scene must build equal settings
objects; the settings refuse bad input before any work, naming the front end's option or key.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import acoustiviz.app.directivity as job_module
from acoustiviz.app.directivity import DirectivityJob, run
from acoustiviz.app.impacts import impact_setup, room_settings
from acoustiviz.app.pipeline import directivity_settings
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.directivity import settings_from_args
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

#: The paper's Figure 2 sphere, as the API takes it.
SPHERE = dict(radius=0.01905, velocity=1.4, density=7800.0)

#: Reference pressure of the levels in Pa.
P_REF = 20e-6

#: (argv, scene TOML before its [outputs.directivity] table, the table's keys, API configuration keywords,
#: the circle's radius in m). The listener of each scene lies level with the sphere's centre, so its distance
#: from the centre is the circle's radius exactly.
CASES = {
    "plane-lcpeak": (("--config", "plane", "--step", "30", "--metric", "lcpeak", "--distance", "0.7"),
                     '[configuration]\nkind = "plane"\n'
                     '[[listeners]]\nname = "side"\nposition_m = [0.7, 0.0, 0.01905]\n',
                     'step_deg = 30.0\nmetric = "lcpeak"\n', dict(config="plane"), 0.7, "lcpeak"),
    "room": (("--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905", "--duration", "0.005",
              "--distance", "0.5", "--step", "30"),
             '[configuration]\nkind = "room"\nroom_m = [3.0, 2.5, 2.0]\nabsorption = [0.3]\n'
             'source_m = [1.0, 1.0, 0.01905]\nwindow_s = 0.005\n'
             '[[listeners]]\nname = "side"\nposition_m = [1.0, 1.5, 0.01905]\n',
             "step_deg = 30.0\n", dict(room=room_settings("3,2.5,2", absorption="0.3", source="1,1,0.01905",
                                                          duration=0.005)), 0.5, "peak-spl"),
}

FILES = ("directivity.csv", "directivity.png")


def _api_job(config: dict, distance: float, metric: str, **kw) -> DirectivityJob:
    setup = impact_setup(**SPHERE, **config)
    return DirectivityJob(impact=setup.impact, pulse=setup.pulse, medium=setup.medium,
                          geometry=setup.geometry, distance=distance, step_deg=30.0, metric=metric, **kw)


@pytest.mark.parametrize("case", CASES)
def test_every_front_end_writes_the_same_files(case, tmp_path, monkeypatch, capsys):
    argv, scene, table, config, distance, metric = CASES[case]
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main(["directivity", *argv, "--csv", FILES[0], "--png", FILES[1]]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert f"wrote {FILES[0]}" in printed and f"wrote {FILES[1]}" in printed
    toml = tmp_path / "scene.toml"
    toml.write_text(scene + "[outputs.directivity]\n" + table)
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    written = run(_api_job(config, distance, metric, csv=FILES[0], png=FILES[1])).write(api)
    assert [p.name for p in written] == list(FILES)
    for name in FILES:
        mine = (cli / name).read_bytes()
        assert len(mine) > 100
        assert (tmp_path / "scene" / name).read_bytes() == mine, f"the scene's {name} differs from the CLI's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"


@pytest.mark.parametrize("case", CASES)
def test_the_command_line_and_a_scene_build_equal_settings(case, tmp_path):
    argv, scene, table, _, distance, metric = CASES[case]
    csv, png = str(tmp_path / "directivity.csv"), str(tmp_path / "directivity.png")
    # the scene's memory cap (grids.memory_limit_mb) defaults to 256 MB, the command line's to --max-memory's
    args = build_parser().parse_args(["directivity", *argv, "--max-memory", "256", "--csv", csv, "--png", png])
    from_cli = settings_from_args(args)
    import tomllib

    from_scene = directivity_settings(scene_from_dict(tomllib.loads(scene + "[outputs.directivity]\n" + table)),
                                      tmp_path)
    if case == "room":  # a scene's room is not capped by grids.memory_limit_mb, the command line's by --max-memory
        assert from_cli.geometry.max_memory_mb == 256.0 and from_scene.geometry.max_memory_mb is None
        assert from_cli.geometry.image_order == from_scene.geometry.image_order  # the cap does not bind
        from_cli = dataclasses.replace(from_cli, geometry=dataclasses.replace(from_cli.geometry,
                                                                                   max_memory_mb=None))
    assert from_cli == from_scene
    assert (from_cli.distance, from_cli.metric, from_cli.csv) == (distance, metric, csv)
    assert from_cli.names["step_deg"] == "--step" and from_scene.names["step_deg"] == "outputs.directivity.step_deg"


def _no_work(monkeypatch):
    """Make any computation of a directivity fail the test: bad input must be refused before it."""
    def refuse(*args, **kwargs):
        raise AssertionError("the directivity was computed")

    monkeypatch.setattr(job_module, "_run", refuse)


@pytest.mark.parametrize("extra, option", [
    (["--step", "0"], "--step"),
    (["--step", "91"], "--step"),
    (["--metric", "loudness"], "--metric"),
    (["--distance", "0.01"], "--distance"),
    (["--metric", "laeq", "--step", "0.01"], "--step"),  # the sound at 9001 angles: over the memory cap
    (["--room", "3,4,2.5", "--duration", "0.0005", "--distance", "1"], "--distance"),  # reached after the window
    (["--png", "d.csv"], "--png"),
])
def test_bad_options_are_refused_before_any_work_naming_the_option(extra, option, tmp_path, monkeypatch, capsys):
    _no_work(monkeypatch)
    monkeypatch.chdir(tmp_path)
    assert main(["directivity", "--csv", "d.csv", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"acoustiviz directivity: error: {option}: ") and len(err.splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_bad_scene_settings_are_refused_naming_the_scene_key(tmp_path, monkeypatch):
    _no_work(monkeypatch)
    setup = impact_setup(**SPHERE, config="plane")
    scene = scene_from_dict({"configuration": {"kind": "plane"}, "outputs": {"directivity": {}}})
    names = directivity_settings(scene).names  # the scene's vocabulary
    job = dict(impact=setup.impact, pulse=setup.pulse, medium=setup.medium, geometry=setup.geometry,
               names=names)
    with pytest.raises(ParameterError, match=r"^outputs\.directivity\.step_deg: .*\(0, 90\] deg"):
        DirectivityJob(**job, distance=0.7, step_deg=120.0)
    with pytest.raises(ParameterError, match=r"^outputs\.directivity\.metric: .*lcpeak"):
        DirectivityJob(**job, distance=0.7, metric="loudness")
    with pytest.raises(ParameterError, match=r"^listeners\[0\]\.distance_m: .*sphere radius"):
        DirectivityJob(**job, distance=0.01)


def test_a_file_in_the_way_of_a_scene_is_refused_before_the_run(tmp_path, monkeypatch):
    from acoustiviz.app.outputs import replacing

    _no_work(monkeypatch)
    (tmp_path / "directivity.png").write_text("keep")
    scene = scene_from_dict({"configuration": {"kind": "plane"}, "outputs": {"directivity": {"step_deg": 30.0}}})
    assert directivity_settings(scene).csv is None  # without a folder: the scene's settings alone
    with replacing(False), pytest.raises(ParameterError, match=r"^outputs\.directivity: .*directivity.png exists"):
        directivity_settings(scene, tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["directivity.png"]
    assert (tmp_path / "directivity.png").read_text() == "keep"


@pytest.mark.parametrize("metric", ["peak-spl", "rms"])
def test_the_result_holds_the_angles_and_the_levels_of_its_metric(metric):
    result = run(_api_job(dict(config="free"), 0.7, metric))
    np.testing.assert_allclose(result.angles_deg, np.arange(0.0, 181.0, 30.0), rtol=0, atol=1e-12)  # 0-180 deg: free
    np.testing.assert_allclose(result.angles, np.radians(result.angles_deg), rtol=0, atol=1e-15)
    np.testing.assert_allclose(result.spl_db, 20 * np.log10(result.peak / P_REF), rtol=0, atol=1e-9)
    assert np.all(result.rms < result.peak) and np.all(result.rms > 0)
    # a free sphere radiates a dipole: loudest along the axis either way, silent (within the near field) at 90 deg
    assert result.loudest() in (0, 6) and result.peak[3] < 0.1 * result.peak[0]
    if metric == "peak-spl":
        assert result.levels is None and result.column is None
    else:
        assert result.column == "rms_db"
        np.testing.assert_allclose(result.levels, 20 * np.log10(result.rms / P_REF), rtol=0, atol=1e-9)
    assert result.write(Path("unused")) == []  # no files asked for, none written
