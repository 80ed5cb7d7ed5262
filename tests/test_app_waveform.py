"""The waveform job: one settings object, one run and one writer for the command line, scenes and the API.

The same waveform is asked for three ways (``acoustiviz waveform``, a scene's ``[outputs.waveform]``
and :class:`~acoustiviz.app.waveform.WaveformJob` built in Python) and the files are compared byte for
byte; the command line and the scene must build equal settings objects; the settings refuse bad
input before any work, naming the front end's option or key.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from acoustiviz.app.impacts import impact_setup, room_settings
from acoustiviz.app.pipeline import waveform_settings
from acoustiviz.app.waveform import Listener, WaveformJob, run
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.waveform import settings_from_args
from acoustiviz.core.geometry import observer_points
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

#: The paper's Figure 2 sphere, as the API takes it.
SPHERE = dict(radius=0.01905, velocity=1.4, density=7800.0)

#: (argv, scene TOML, API configuration keywords, the listener's point or None for 0.7 m at 45 deg, files)
CASES = {
    "plane": (("--config", "plane"), '[configuration]\nkind = "plane"\n'
              '[[listeners]]\nname = "listener"\ndistance_m = 0.7\nangle_deg = 45.0\n',
              dict(config="plane"), None, ("csv", "png")),
    "room": (("--room", "3,4,2.5", "--absorption", "0.4", "--duration", "0.01", "--listener", "1,1,1.2"),
             '[configuration]\nkind = "room"\nroom_m = [3.0, 4.0, 2.5]\nabsorption = [0.4]\nwindow_s = 0.01\n'
             '[[listeners]]\nname = "listener"\nposition_m = [1.0, 1.0, 1.2]\n',
             dict(room=room_settings("3,4,2.5", absorption="0.4", duration=0.01)), (1.0, 1.0, 1.2),
             ("csv", "json", "png")),
}


def _api_job(config: dict, point, folder: Path) -> WaveformJob:
    setup = impact_setup(**SPHERE, **config)
    if point is None:
        point = observer_points(setup.geometry, 0.7, math.radians(45.0))[0]
    return WaveformJob(impact=setup.impact, pulses=(setup.pulse,), medium=setup.medium,
                       geometry=setup.geometry, listeners=(Listener("listener", point),),
                       csv="waveform_listener.csv", png="waveform_listener.png")


@pytest.mark.parametrize("case", CASES)
def test_every_front_end_writes_the_same_files(case, tmp_path, monkeypatch, capsys):
    argv, scene, config, point, endings = CASES[case]
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main(["waveform", *argv, "--csv", "waveform_listener.csv", "--png", "waveform_listener.png"]) == 0, \
        capsys.readouterr().err
    toml = tmp_path / "scene.toml"
    toml.write_text(scene + "[outputs.waveform]\n")
    assert main(["run", str(toml), "--out", str(tmp_path / "scene")]) == 0, capsys.readouterr().err
    api = tmp_path / "api"
    api.mkdir()
    monkeypatch.chdir(api)
    written = run(_api_job(config, point, api)).write(api)
    assert sorted(p.name for p in written) == sorted(f"waveform_listener.{e}" for e in endings)
    for ending in endings:
        name = f"waveform_listener.{ending}"
        mine = (cli / name).read_bytes()
        assert len(mine) > 100
        assert (tmp_path / "scene" / name).read_bytes() == mine, f"the scene's {name} differs from the CLI's"
        assert (api / name).read_bytes() == mine, f"the API's {name} differs from the CLI's"


@pytest.mark.parametrize("case", CASES)
def test_the_command_line_and_a_scene_build_equal_settings(case, tmp_path):
    argv, scene, _, _, _ = CASES[case]
    csv, png = str(tmp_path / "waveform_{listener}.csv"), str(tmp_path / "waveform_{listener}.png")
    # the scene's memory cap (grids.memory_limit_mb) defaults to 256 MB, the command line's to --max-memory's
    args = build_parser().parse_args(["waveform", *argv, "--max-memory", "256", "--csv", csv, "--png", png])
    args.given_options = frozenset()
    from_cli = settings_from_args(args)
    import tomllib

    from_scene = waveform_settings(scene_from_dict(tomllib.loads(scene + "[outputs.waveform]\n")), tmp_path)
    if case == "room":  # a scene's room is not capped by grids.memory_limit_mb, the command line's by --max-memory
        assert from_cli.geometry.max_memory_mb == 256.0 and from_scene.geometry.max_memory_mb is None
        assert from_cli.geometry.image_order == from_scene.geometry.image_order  # the cap does not bind
        from_cli = dataclasses.replace(from_cli, geometry=dataclasses.replace(from_cli.geometry,
                                                                                   max_memory_mb=None))
    assert from_cli == from_scene
    assert from_cli.csv == csv and from_cli.listeners[0].name == "listener"


def _plane_job(**kw):
    setup = impact_setup(**SPHERE, config="plane")
    points = observer_points(setup.geometry, 0.7, np.radians([30.0, 60.0]))
    values = dict(pulses=(setup.pulse,), listeners=(Listener("a", points[0]), Listener("b", points[1])))
    values.update(kw)
    return WaveformJob(impact=setup.impact, medium=setup.medium, geometry=setup.geometry, **values)


def test_several_listeners_need_the_placeholder_in_each_file_name(tmp_path):
    with pytest.raises(ParameterError, match=r"^--csv: .*\{listener\}"):
        _plane_job(csv=str(tmp_path / "w.csv"), names={"csv": "--csv"})
    job = _plane_job(csv=str(tmp_path / "w_{listener}.csv"))
    assert _plane_job(listeners=[(lst.name, np.array(lst.position)) for lst in job.listeners]) \
        == dataclasses.replace(job, csv=None)  # (name, position) pairs are listeners too
    assert [job.files(lst)["csv"] for lst in job.listeners] == [str(tmp_path / "w_a.csv"), str(tmp_path / "w_b.csv")]


def test_a_listener_inside_the_sphere_or_below_the_floor_is_refused_by_its_key():
    setup = impact_setup(**SPHERE, config="plane")
    for where in (setup.geometry.centre, setup.geometry.centre - [0.0, 0.0, 0.5]):
        with pytest.raises(ParameterError, match=r"^listeners\[0\]: listener 'x'"):
            WaveformJob(impact=setup.impact, pulses=(setup.pulse,), medium=setup.medium,
                        geometry=setup.geometry, listeners=(Listener("x", where),),
                        names={"listeners": "listeners[0]"})


def test_an_existing_file_is_refused_when_the_settings_are_made(tmp_path):
    from acoustiviz.app.outputs import replacing

    (tmp_path / "w_b.csv").write_text("keep")
    with replacing(False), pytest.raises(ParameterError, match=r"^outputs.waveform: .*w_b.csv exists"):
        _plane_job(csv=str(tmp_path / "w_{listener}.csv"), names={"csv": "outputs.waveform"})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w_b.csv"] and (tmp_path / "w_b.csv").read_text() == "keep"


def test_the_result_holds_every_listener_and_pulse_and_reports_the_first_pulse():
    setup = impact_setup(**SPHERE, config="plane")
    other = impact_setup(**SPHERE, config="plane", pulse="impulse-matched").pulse
    job = _plane_job(pulses=(setup.pulse, other))
    result = run(job)
    assert len(result.times) == len(result.pressures) == 2 and result.images == {}
    for t, p, high, low in zip(result.times, result.pressures, result.peak_positive, result.peak_negative,
                               strict=True):
        assert p.shape == (2, t.size)
        assert not np.allclose(p[0], p[1])  # two pulses, two waveforms
        # the reported peaks are the continuous waveform's: at least the samples' extremes, and close to them
        assert high >= p[0].max() and low <= p[0].min()
        assert high == pytest.approx(p[0].max(), rel=1e-3) and low == pytest.approx(p[0].min(), rel=1e-3)
