"""A scene's ``[configuration] kind = "room"`` (or ``[geometry]``): the same room and verdicts as ``--room``."""

import pytest

from acoustiviz.cli import main
from acoustiviz.errors import SceneError
from acoustiviz.scene.load import scene_from_text, shipped_scenes

BASE = """
[{table}]
kind = "room"
room_m = {dims}
absorption = {alpha}
source_m = {source}
window_s = 0.05

[[listeners]]
name = "l"
position_m = {listener}

[outputs.waveform]
"""


def _text(table="geometry", dims="[6.0, 4.0, 3.0]", alpha="0.1", source="[2.0, 1.5, 0.01905]",
          listener="[3.0, 2.0, 1.5]"):
    return BASE.format(table=table, dims=dims, alpha=alpha, source=source, listener=listener)


def test_shipped_room_scene_is_a_room_with_its_image_model():
    sc = scene_from_text(shipped_scenes()["room"], "room.toml")
    geometry = sc.geometry()
    assert geometry.name == "room" and geometry.dimensions == (6.0, 4.0, 3.0) and geometry.absorption == (0.1,)
    assert geometry.image_order == 18 and geometry.image_count == 8473  # as the scene's comment says


@pytest.mark.parametrize("table", ["geometry", "configuration"])
def test_geometry_table_is_the_configuration_table(table):
    geometry = scene_from_text(_text(table), "s.toml").geometry()
    assert geometry.name == "room" and geometry.source == (2.0, 1.5, 0.01905) and geometry.duration == 0.05


@pytest.mark.parametrize("scene_kw, key, option, cli", [
    ({"alpha": "1.0"}, "configuration.absorption", "--absorption", ["--absorption", "1.0"]),
    ({"alpha": "[0.1, 0.2]"}, "configuration.absorption", "--absorption", ["--absorption", "0.1,0.2"]),
    ({"dims": "[-6.0, 4.0, 3.0]"}, "configuration.room_m", "--room", ["--room", "-6,4,3"]),
    ({"source": "[7.0, 1.5, 0.5]"}, "configuration.source_m", "--source", ["--source", "7,1.5,0.5"]),
])
def test_scene_and_command_line_give_the_same_verdict(scene_kw, key, option, cli, tmp_path, capsys):
    with pytest.raises(SceneError) as err:
        scene_from_text(_text(**scene_kw), "s.toml")
    assert key in str(err.value)
    args = {"--room": "6,4,3", "--absorption": "0.1", "--source": "2,1.5,0.01905"}
    args.update(dict(zip(cli[::2], cli[1::2], strict=True)))
    flat = [x for kv in args.items() for x in kv]
    assert main(["waveform", *flat, "--listener", "3,2,1.5", "--duration", "0.05",
                 "--csv", str(tmp_path / "o.csv")]) == 2
    cli_err = capsys.readouterr().err.strip()
    assert option in cli_err
    # the one validation (Room): the same reason after the name
    assert cli_err.split(f"{option}: ", 1)[1] in str(err.value)


def test_listener_outside_the_room_is_refused():
    with pytest.raises(SceneError, match="listeners"):
        scene_from_text(_text(listener="[3.0, 2.0, 3.5]"), "s.toml")


@pytest.mark.parametrize("key, value, option, text", [
    ("tolerance_db", "0.0", "--tolerance-db", "[-200, 0) dB"),
    ("image_order", "10001", "--image-order", "[0, 10000]"),
])
def test_room_ranges_are_one_record_for_scene_and_command_line(key, value, option, text, tmp_path, capsys):
    """The image model's ranges come from one record: a scene and the command line refuse the same value."""
    scene = _text(table="configuration").replace("window_s = 0.05", f"window_s = 0.05\n{key} = {value}")
    with pytest.raises(SceneError) as err:
        scene_from_text(scene, "s.toml")
    assert f"configuration.{key}" in str(err.value) and text in str(err.value)
    assert main(["waveform", "--room", "6,4,3", "--absorption", "0.1", "--source", "2,1.5,0.01905",
                 "--listener", "3,2,1.5", "--duration", "0.05", option, value,
                 "--csv", str(tmp_path / "o.csv")]) == 2
    cli_err = capsys.readouterr().err.strip()
    assert f"{option}: " in cli_err and text in cli_err
    assert not (tmp_path / "o.csv").exists()
