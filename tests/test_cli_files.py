"""Files read back, files replaced and outputs checked before work, through the command line.

A command that reads a file never writes it; an existing file (named or derived) is replaced only
with ``--force``; every output path, derived ones included, is checked before any work; a scene
checks all its outputs before computing the first; and physically meaningless input is refused up
front with one line naming the option or scene key. The command line is called in-process from a
fresh folder (the fixtures of :mod:`tests.test_cli_fuzz`).
"""

# ruff: noqa: F811 - the fixture ``here`` imported from test_cli_fuzz is the tests' argument

from __future__ import annotations

import pytest
from test_cli_fuzz import assert_user_error, call, here  # noqa: F401 - the fixture

ROOM_OFF_FLOOR = ["waveform", "--room", "6,4,3", "--source", "2,1.5,1.5", "--listener", "3,2,1.5",
                  "--duration", "0.05", "--csv", "o.csv"]


def test_a_room_source_off_the_floor_it_strikes_is_refused(here, capsys):
    rc = call(ROOM_OFF_FLOOR)
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--source")
    assert "must touch the floor" in err and "z = 0.01905 m" in err
    assert not (here / "o.csv").exists()


def test_a_room_source_against_the_wall_it_strikes_is_accepted_up_to_the_physics(here, capsys):
    # the rule follows the struck surface: x1 of a 6 m room wants x = 6 - a
    rc = call(["waveform", "--room", "6,4,3", "--room-strike", "x1", "--source", "5.98095,1.5,1.5",
               "--listener", "3,2,1.5", "--duration", "0.01", "--csv", "o.csv"])
    assert rc == 0, capsys.readouterr().err
    rc = call(["waveform", "--room", "6,4,3", "--room-strike", "x1", "--source", "2,1.5,0.01905",
               "--listener", "3,2,1.5", "--duration", "0.01", "--csv", "p.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--source")
    assert "x = 5.98095 m" in err


SCENE_OFF_FLOOR = """
[configuration]
kind = "room"
room_m = [6.0, 4.0, 3.0]
absorption = 0.1
source_m = [2.0, 1.5, 1.5]
window_s = 0.05

[[listeners]]
name = "l"
position_m = [3.0, 2.0, 1.5]

[outputs.waveform]
"""


def test_a_scene_room_source_off_the_floor_is_refused_before_any_output(here, capsys):
    (here / "s.toml").write_text(SCENE_OFF_FLOOR)
    rc = call(["run", "s.toml", "--out", "out", "--quiet"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "configuration.source_m")
    assert "must touch the floor" in err
    assert not (here / "out").exists() or not any((here / "out").iterdir())


@pytest.mark.parametrize("option, value, unit", [("--force", "1e308", "N"), ("--base", "1e308", "m"),
                                                  ("--force", "1e10", "N"), ("--base", "-1", "m")])
def test_forced_amplitude_has_the_scene_range(here, capsys, option, value, unit):
    from acoustiviz.scene.schema import SCHEMA

    key = SCHEMA["excitation"].keys["amplitude"]  # the scene's range: the command line must agree
    rc = call(["forced", option, value, "--freq", "3:7:2", "--no-noise", "--csv", "f.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, option)
    assert f"[{key.low:g}, {key.high:g}] {unit}" in err and key.high < 1e308
    assert not (here / "f.csv").exists()

