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


def test_the_contact_rule_follows_the_struck_surface(here, capsys):
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


# --- 1. a command that reads a file never writes it
SWEEP_ARGS = ["--gap", "0.03,0.04", "--m", "0.04", "--duration", "0.5", "--quiet"]


@pytest.fixture(scope="module")
def two_designs(tmp_path_factory):
    """A finished two-design sweep folder (copied by each test before damaging it)."""
    folder = tmp_path_factory.mktemp("sweep") / "sw"
    assert call(["sweep", *SWEEP_ARGS, "--out", str(folder)]) == 0
    return folder


def _digest(path):
    import hashlib

    return hashlib.sha256(path.read_bytes()).hexdigest()


def _copy(src, folder):
    import shutil

    shutil.copytree(src, folder / "sw")
    return folder / "sw"


def test_design_reads_a_journal_cut_mid_row_without_writing_it(here, capsys, two_designs):
    sw = _copy(two_designs, here)
    whole = (sw / "sweep.csv").read_bytes()
    (sw / "sweep.csv").write_bytes(whole[:-20])  # a kill in the middle of the last row
    before = _digest(sw / "sweep.csv")
    assert call(["design", "--sweep", "sw", "--inclination", "0.008"]) == 0, capsys.readouterr().err
    assert _digest(sw / "sweep.csv") == before


def test_resuming_a_journal_cut_mid_row_recomputes_that_row_on_a_line_of_its_own(here, capsys, two_designs):
    from acoustiviz.sweep import load_sweep

    sw = _copy(two_designs, here)
    whole = (sw / "sweep.csv").read_bytes()
    (sw / "sweep.csv").write_bytes(whole[:-20])
    assert call(["sweep", *SWEEP_ARGS, "--out", "sw"]) == 0, capsys.readouterr().err
    table = load_sweep(sw)
    assert table.complete and len(table) == 2
    assert (sw / "sweep.csv").read_bytes().count(b"\n") == whole.count(b"\n")


GARBAGE = {"binary": b"\x00\xff\xfe\x80 binary", "text without a newline": b"hello world",
           "text lines": b"hello\nworld\n", "header then garbage": None}


@pytest.mark.parametrize("kind", list(GARBAGE))
@pytest.mark.parametrize("command", ["design", "sweep"])
def test_a_garbage_journal_is_refused_as_damaged_and_left_byte_identical(here, capsys, two_designs, kind, command):
    sw = _copy(two_designs, here)
    content = GARBAGE[kind]
    if content is None:
        content = (sw / "sweep.csv").read_bytes().split(b"\n")[0] + b"\n1,2,three\x00\xff"
    (sw / "sweep.csv").write_bytes(content)
    before = {p.name: _digest(p) for p in sw.iterdir()}
    argv = (["design", "--sweep", "sw", "--inclination", "0.008"] if command == "design"
            else ["sweep", *SWEEP_ARGS, "--out", "sw"])
    rc = call(argv)
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--sweep" if command == "design" else "--out")
    assert "sweep.csv" in err and "damaged" in err
    assert {p.name: _digest(p) for p in sw.iterdir()} == before


@pytest.mark.parametrize("content", [b"[1, 2, 3]\n", b"\xff\xfe\x00{", b"{\"format\": \"acoustiviz-sweep\"",
                                     b"{\"format\": \"acoustiviz-sweep\", \"spec\": [1]}\n", b"{}\n"])
@pytest.mark.parametrize("command", ["design", "sweep"])
def test_a_damaged_settings_file_is_reported_as_damaged(here, capsys, two_designs, content, command):
    sw = _copy(two_designs, here)
    (sw / "sweep.json").write_bytes(content)
    before = {p.name: _digest(p) for p in sw.iterdir()}
    argv = (["design", "--sweep", "sw", "--inclination", "0.008"] if command == "design"
            else ["sweep", *SWEEP_ARGS, "--out", "sw"])
    rc = call(argv)
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--sweep" if command == "design" else "--out")
    assert "sweep.json is damaged" in err and "different settings" not in err
    assert {p.name: _digest(p) for p in sw.iterdir()} == before


# --- 2. one rule: an existing output, named or derived, is replaced only with --force
def _wav(path, seconds=0.5, rate=48000):
    import numpy as np
    import soundfile as sf

    t = np.arange(int(seconds * rate)) / rate
    sf.write(path, 0.1 * np.sin(2 * np.pi * 440 * t), rate)


# (the command, the file it is asked to write, a file derived from it) on a fresh folder
DERIVED = {
    "auralize": (["auralize", "--duration", "0.2", "--wav", "o.wav"], "o.wav", "o.json"),
    "map": (["map", "--resolution", "8", "--vtk", "o.vtu"], "o.vtu", "o_geometry.vtu"),
    "levels": (["levels", "s.wav", "--pa-per-fs", "1", "--csv", "o.csv"], "o.csv", "o_bands.csv"),
    "room waveform": (["waveform", "--room", "6,4,3", "--source", "2,1.5,0.01905", "--listener", "3,2,1.5",
                       "--duration", "0.01", "--csv", "o.csv"], "o.csv", "o.json"),
    "render": (["render", "balloon", "--resolution", "8", "--vtk", "o.vtu"], "o.vtu", "o_geometry.vtu"),
}


@pytest.mark.parametrize("which", ["named", "derived"])
@pytest.mark.parametrize("case", list(DERIVED))
def test_an_existing_output_is_replaced_only_with_force(here, capsys, case, which):
    argv, named, derived = DERIVED[case]
    _wav(here / "s.wav")
    target = here / (named if which == "named" else derived)
    target.write_bytes(b"the user's own file\n")
    rc = call(argv)
    err = capsys.readouterr().err
    assert_user_error(rc, err, str(target.name))
    assert "pass --force" in err and "exists" in err
    assert target.read_bytes() == b"the user's own file\n"
    assert sorted(p.name for p in here.iterdir()) == sorted({"adir", "afile", "s.wav", target.name})
    assert call([*argv, "--force"]) == 0, capsys.readouterr().err
    assert (here / named).exists() and (here / derived).exists()
    assert target.read_bytes() != b"the user's own file\n"


@pytest.mark.parametrize("argv, name", [
    (["waveform", "--csv", "o.csv"], "o.csv"),
    (["directivity", "--png", "o.png"], "o.png"),
    (["damper", *["--duration", "1"], "--impacts-csv", "o.csv"], "o.csv"),
    (["forced", "--force", "5", "--freq", "5", "--starts", "1", "--no-noise", "--csv", "o.csv"], "o.csv"),
])
def test_every_command_refuses_to_replace_without_its_flag(here, capsys, argv, name):
    (here / name).write_text("mine\n")
    rc = call(argv)
    err = capsys.readouterr().err
    flag = "--replace" if argv[0] == "forced" else "--force"
    assert_user_error(rc, err, name)
    assert f"pass {flag}" in err
    assert (here / name).read_text() == "mine\n"


def test_forced_takes_replace_since_its_force_is_the_amplitude(capsys):
    from acoustiviz.cli import build_parser

    parser = build_parser()
    args = parser.parse_args(["forced", "--force", "5", "--freq", "5", "--replace"])
    assert args.force == 5.0 and args.replace and args.replace_option == "--replace"
    args = parser.parse_args(["waveform", "--force"])
    assert args.replace and args.replace_option == "--force"


def test_every_command_has_the_flag(capsys):
    from acoustiviz.cli import _leaf_parsers, build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.choices and "run" in a.choices)
    leaves = list(_leaf_parsers(sub))
    assert len(leaves) >= 11
    for leaf in leaves:
        flags = [a for a in leaf._actions if a.dest == "replace"]
        assert len(flags) == 1 and flags[0].option_strings in (["--force", "--replace"], ["--replace"]), leaf.prog
        amplitude = leaf.prog in ("acoustiviz forced", "acoustiviz sweep", "acoustiviz optimize")  # --force: F0
        assert (flags[0].option_strings == ["--replace"]) == amplitude, leaf.prog


def test_replace_is_one_spelling_of_force_on_every_command(here, capsys):
    """``--replace`` replaces as ``--force`` does, so one flag works on every command, ``forced`` included."""
    (here / "w.csv").write_text("mine\n")
    assert call(["waveform", "--csv", "w.csv"]) == 2
    assert "w.csv" in capsys.readouterr().err and (here / "w.csv").read_text() == "mine\n"
    assert call(["waveform", "--csv", "w.csv", "--replace"]) == 0
    assert (here / "w.csv").read_text().startswith("time_s")


def test_run_refuses_a_non_empty_folder_without_force(here, capsys):
    (here / "out").mkdir()
    (here / "out" / "mine.txt").write_text("mine\n")
    rc = call(["run", "--out", "out", "--quiet"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--out")
    assert "pass --force" in err
    assert sorted(p.name for p in (here / "out").iterdir()) == ["mine.txt"]


# --- 3. every output path, derived ones included, checked before any work
@pytest.mark.parametrize("case", list(DERIVED))
def test_a_folder_in_a_derived_outputs_place_is_refused_before_any_work(here, capsys, case):
    argv, named, derived = DERIVED[case]
    _wav(here / "s.wav")
    (here / derived).mkdir()
    rc = call([*argv, "--force"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, derived)
    assert not (here / named).exists()


def test_a_new_sweep_does_not_replace_a_design_table_it_did_not_write(here, capsys):
    (here / "sw").mkdir()
    (here / "sw" / "design_table.csv").write_text("mine\n")
    rc = call(["sweep", *SWEEP_ARGS, "--out", "sw"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "design_table.csv")
    assert "pass --replace" in err  # sweep's --force is the force amplitude of a sweep in operation
    assert sorted(p.name for p in (here / "sw").iterdir()) == ["design_table.csv"]
    assert call(["sweep", *SWEEP_ARGS, "--out", "sw", "--replace"]) == 0, capsys.readouterr().err
    assert (here / "sw" / "design_table.csv").read_text() != "mine\n"


# --- 4. a scene checks every output before the first is computed
THREE_OUTPUTS = """
[damper]
duration_s = 1.0

[outputs.waveform]
[outputs.directivity]
[outputs.damper_history]
"""


@pytest.mark.parametrize("blocker", ["folder", "read-only file"])
def test_a_scene_whose_third_output_cannot_be_written_writes_nothing(here, capsys, blocker):
    import os

    from acoustiviz.app.scene_outputs import output_files
    from acoustiviz.scene.load import load_scene

    (here / "s.toml").write_text(THREE_OUTPUTS)
    third = [name for name, _ in output_files(load_scene(here / "s.toml"))["damper_history"]][-1]
    out = here / "out"
    out.mkdir()
    if blocker == "folder":
        (out / third).mkdir()
    else:
        (out / third).write_text("mine\n")
        os.chmod(out / third, 0o444)
    rc = call(["run", "s.toml", "--out", "out", "--force", "--quiet"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, third)
    assert "outputs.damper_history" in err
    assert [p.name for p in out.iterdir()] == [third]  # the waveform and the directivity were not made


def test_every_file_a_scene_writes_was_checked_before_the_run(here, capsys):
    from acoustiviz.app.scene_outputs import SUMMARY, output_files
    from acoustiviz.scene.load import load_scene

    (here / "s.toml").write_text(THREE_OUTPUTS)
    assert call(["run", "s.toml", "--out", "out", "--quiet"]) == 0, capsys.readouterr().err
    planned = {name for files in output_files(load_scene(here / "s.toml")).values() for name, _ in files}
    written = {p.name for p in (here / "out").iterdir()}
    assert written == planned | {SUMMARY}


def test_a_scene_whose_later_output_has_settings_it_cannot_honour_writes_nothing(here, capsys, monkeypatch):
    import acoustiviz.app.scene_levels as scene_levels

    monkeypatch.setattr(scene_levels, "loudness_available", lambda: False)  # as without mosqito
    (here / "s.toml").write_text(THREE_OUTPUTS + "[outputs.levels]\nloudness = true\n")
    rc = call(["run", "s.toml", "--out", "out", "--quiet"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "outputs.levels.loudness")
    assert not (here / "out").exists() or not any((here / "out").iterdir())


LISTENER_IN_THE_CAVITY = """
[damper]
duration_s = 1.0

[excitation]
frequencies_hz = "5:5:1"
starts = 1

[[listeners]]
name = "top"
position_m = [0.0, 0.0, 0.05]

[outputs.waveform]
[outputs.{later}]
"""


@pytest.mark.parametrize("later", ["wav", "levels", "operating_noise"])
def test_a_listener_in_the_dampers_cavity_is_refused_before_the_waveform_is_made(here, capsys, later):
    # in the fluid of the struck plane (the waveform could be made), but within the damper's cavity
    (here / "s.toml").write_text(LISTENER_IN_THE_CAVITY.format(later=later))
    rc = call(["run", "s.toml", "--out", "out", "--quiet"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "listeners")
    assert "inside the cavity" in err
    assert not (here / "out").exists() or not any((here / "out").iterdir())


SWEEP_SCENE = """
[outputs.waveform]
[outputs.sweep]
gap_m = "0.03:0.03:1"
mass_kg = "0.04:0.04:1"
duration_s = 0.5
workers = 1
"""


@pytest.mark.parametrize("damage", ["settings", "journal"])
def test_a_scene_onto_a_damaged_sweep_folder_is_refused_before_any_output(here, capsys, damage):
    (here / "s.toml").write_text(SWEEP_SCENE)
    assert call(["run", "s.toml", "--out", "out", "--quiet"]) == 0, capsys.readouterr().err
    victim = here / "out" / "sweep" / ("sweep.json" if damage == "settings" else "sweep.csv")
    victim.write_bytes(b"\x00\xff damaged")
    before = {p.relative_to(here): _digest(p) for p in (here / "out").rglob("*") if p.is_file()}
    rc = call(["run", "s.toml", "--out", "out", "--quiet", "--force"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "outputs.sweep")
    assert "damaged" in err and victim.name in err
    assert {p.relative_to(here): _digest(p) for p in (here / "out").rglob("*") if p.is_file()} == before
