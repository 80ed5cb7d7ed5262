"""One table of ranges and defaults: the options, the scene keys and the settings objects read the same records."""

from __future__ import annotations

import argparse
import dataclasses
import math

import pytest

from acoustiviz.app.maps import MAP_SETTINGS
from acoustiviz.app.settings.auralize import ALL as AURALIZE_ALL
from acoustiviz.app.settings.auralize import AURALIZE, AuralizeSettings, DamperSettings
from acoustiviz.app.settings.damper import BALLS, DAMPER, MODEL
from acoustiviz.app.settings.design import DESIGN, DESIGN_RUN, DesignJob, DesignSettings
from acoustiviz.app.settings.forced import EXCITATION_KIND, FORCED, FORCED_EXECUTION, NOISE
from acoustiviz.app.settings.forced_job import ForcedJob
from acoustiviz.app.settings.impact import DIRECTIVITY, IMPACT, WAVEFORM, DirectivitySettings, WaveformSettings
from acoustiviz.app.settings.levels import ALL as LEVELS_ALL
from acoustiviz.app.settings.levels import LEVELS, LevelsSettings
from acoustiviz.app.settings.render import (
    ANIMATION,
    BALLOON,
    SNAPSHOT,
    AnimationSettings,
    BalloonSettings,
    SnapshotSettings,
)
from acoustiviz.app.settings.sweep import SCENE_SWEEP, SWEEP, SWEEP_RUN, SWEEP_SOUND, SWEPT, SweepSettings
from acoustiviz.cli import build_parser
from acoustiviz.errors import ParameterError
from acoustiviz.scene.schema import SCHEMA

#: (command path, table, settings class or None)
TABLES = [
    (("render", "balloon"), BALLOON, BalloonSettings),
    (("render", "snapshot"), SNAPSHOT, SnapshotSettings),
    (("render", "animation"), ANIMATION, AnimationSettings),
    (("waveform",), WAVEFORM, WaveformSettings),
    (("directivity",), DIRECTIVITY, DirectivitySettings),
    (("forced",), FORCED, ForcedJob),
    (("forced",), (EXCITATION_KIND, *FORCED_EXECUTION[:2], NOISE), ForcedJob),
    (("design",), DESIGN, DesignSettings),
    (("sweep",), SWEEP, SweepSettings),
    (("design",), DESIGN_RUN, DesignJob),
    # the sweep's swept values, its scene-only keys and where it runs: checked by the sweep job as a whole
    (("sweep",), tuple(s for s in SWEPT + SWEEP_SOUND + SWEEP_RUN + SCENE_SWEEP
                       if s.key or s.choices or s.kind == "bool" or math.isfinite(s.low) or math.isfinite(s.high)),
     None),
    (("map",), MAP_SETTINGS, None),
    (("damper",), DAMPER, DamperSettings),
    (("damper",), BALLS, None),
    (("waveform",), tuple(s for s in IMPACT if s.choices or math.isfinite(s.low) or math.isfinite(s.high)), None),
    (("auralize",), DAMPER, DamperSettings),
    (("forced",), MODEL, None),
    (("levels",), LEVELS, LevelsSettings),  # a scene's levels are of its own run, not of a file: no scene keys
    (("auralize",), AURALIZE, AuralizeSettings),
    # the other auralize records with a range, choices or a scene key; their checks need the run's other settings
    (("auralize",), tuple(s for s in AURALIZE_ALL if s not in AURALIZE and (
        s.key or s.choices or math.isfinite(s.low) or math.isfinite(s.high))), None),
]
RECORDS = [(cmd, s, cls) for cmd, table, cls in TABLES for s in table]


def _ids(case):
    cmd, s, _ = case
    return f"{'-'.join(cmd)}:{s.name}"


def _subparser(parser, names):
    for name in names:
        action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parser = action.choices[name]
    return parser


@pytest.fixture(scope="module")
def parser():
    return build_parser()


def _range(s) -> str:
    """``(0, 90]``: the interval as the help and the scene reference print it."""
    return f"{'(' if s.low_open else '['}{s.low:g}, {s.high:g}{')' if s.high_open else ']'}"


_WITH_OPTION = [c for c in RECORDS if c[1].option is not None]
_WITH_KEY = [c for c in RECORDS if c[1].key is not None]


@pytest.mark.parametrize("case", _WITH_OPTION, ids=[_ids(c) for c in _WITH_OPTION])
def test_option_takes_its_default_and_range_from_the_table(case, parser):
    cmd, s, _ = case
    action = next(a for a in _subparser(parser, cmd)._actions if s.option in a.option_strings)
    assert action.default == s.default
    if s.choices and action.choices is None:  # checked after parsing: every choice named in the help
        assert all(c in action.help for c in s.choices)
    elif s.choices:
        assert tuple(action.choices) == tuple(s.choices)
    elif s.kind not in ("bool", "str"):  # a flag and a free name (a path) have no range
        assert _range(s) in action.help % {"default": action.default}


@pytest.mark.parametrize("case", _WITH_KEY, ids=[_ids(c) for c in _WITH_KEY])
def test_scene_key_takes_its_default_and_range_from_the_table(case):
    _, s, _ = case
    table = SCHEMA
    for part in s.table.split("."):
        table = table[part].keys if isinstance(table, dict) else table.keys[part].keys
    k = table[s.key]
    assert (k.kind, k.low, k.high, k.low_open, tuple(k.choices), k.unit) == \
        (s.kind, s.low, s.high, s.low_open, tuple(s.choices), s.unit)
    assert k.default == s.in_scene


@pytest.mark.parametrize("case", [c for c in RECORDS if c[2] is not None],
                         ids=[_ids(c) for c in RECORDS if c[2] is not None])
def test_settings_object_checks_the_tables_range(case):
    _, s, cls = case
    fields = {f.name for f in dataclasses.fields(cls)}
    assert s.name in fields
    assert getattr(cls(), s.name) == s.default  # the dataclass's default is the table's
    if s.choices:
        bad = "no-such-" + str(s.choices[0])
    elif s.kind == "int":
        bad = int(s.low) - 1
    else:
        bad = s.low if s.low_open else (s.high * 2 if math.isfinite(s.high) else -1.0)
    with pytest.raises(ParameterError) as err:
        cls(**{s.name: bad})
    assert err.value.name == s.name


def test_levels_command_options_are_its_records(parser):
    """Every option of ``acoustiviz levels`` (but the positional file and the global flags) is a record."""
    from acoustiviz.app.outputs import REPLACE

    sub = _subparser(parser, ("levels",))
    options = {o for a in sub._actions for o in a.option_strings if o.startswith("--")} - {"--help", "--max-memory",
                                                                                           REPLACE.option,
                                                                                           *REPLACE.aliases}
    assert options == {s.option for s in LEVELS_ALL}
    fields = {f.name for f in dataclasses.fields(LevelsSettings)}
    assert {s.name for s in LEVELS_ALL} <= fields


def test_settings_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        BalloonSettings().n_theta = 8


def test_both_plane_resolutions_share_one_scene_key():
    """The command's snapshot and animation have their own default resolution; a scene's planes share one."""
    a, b = (next(s for s in t if s.name == "n_u") for t in (SNAPSHOT, ANIMATION))
    assert (a.path, a.low, a.high, a.in_scene) == (b.path, b.low, b.high, b.in_scene) == \
        ("grids.plane.resolution", 8, 20000, 200)


def test_user_names_are_the_records_options_and_keys():
    from acoustiviz.app import names
    from acoustiviz.app.settings.impact import OBSERVER
    from acoustiviz.app.settings.room import ROOM

    options = {s.option for s in (*DAMPER, *IMPACT, *OBSERVER, *ROOM, *WAVEFORM)}
    for table in (names.DAMPER_OPTIONS, names.IMPACT_OPTIONS, names.ROOM_OPTIONS):
        assert set(table.values()) <= options
    keys = {s.path for s in (*DAMPER, *IMPACT)}
    assert set(names.SCENE_DAMPER_KEYS.values()) <= keys
    # the API's spellings that differ from the records' (simulate's v, the room's dimensions and window)
    assert names.DAMPER_OPTIONS["v"] == "--v0"
    assert names.SCENE_DAMPER_KEYS["v"] == "damper.initial_velocity_m_s"
    assert names.SCENE_DAMPER_KEYS["x0"] == "damper.initial_displacement_m"
    assert names.ROOM_OPTIONS["dimensions"] == "--room"
    assert names.ROOM_OPTIONS["duration"] == "--duration"
    assert names.ROOM_OPTIONS["strike"] == "--room-strike"
    assert names.IMPACT_OPTIONS["strike"] == "--strike"
    assert names.IMPACT_OPTIONS["angle_deg"] == "--angle"
    assert names.SCENE_IMPACT_KEYS["k_hertz"] == "contact.k_hertz_n_m1_5"


def test_damper_command_solver_options_are_records(parser):
    sub = _subparser(parser, ("damper",))
    dests = {a.dest for a in sub._actions}
    assert {"solver", "dt", "clip_tensile"} <= dests
    for bad in ("0", "-1e-3"):
        with pytest.raises(ParameterError) as err:
            DamperSettings(dt=float(bad))
        assert err.value.name == "dt" and "(0, 10000] s" in err.value.detail
    with pytest.raises(ParameterError):
        DamperSettings(clip_tensile="yes")


def test_add_option_makes_positional_and_required_arguments():
    """A positional record is named by its API name (optional unless required); a required option must be given."""
    from acoustiviz.app.settings.table import Setting, add_option

    class Refuse(argparse.ArgumentParser):
        def error(self, message):
            raise ValueError(message)

    parser = Refuse()
    add_option(parser, Setting("wav", "WAV", None, "str", None, "the file", metavar="WAV", positional=True,
                               required=True))
    add_option(parser, Setting("scene", "SCENE", None, "str", None, "the scene", metavar="SCENE", positional=True))
    add_option(parser, Setting("csv", "--csv", None, "str", None, "the table", metavar="PATH", required=True))
    args = parser.parse_args(["a.wav", "--csv", "t.csv"])
    assert (args.wav, args.scene, args.csv) == ("a.wav", None, "t.csv")
    assert parser.parse_args(["a.wav", "s.toml", "--csv", "t.csv"]).scene == "s.toml"
    with pytest.raises(ValueError, match="--csv"):
        parser.parse_args(["a.wav"])
    with pytest.raises(ValueError, match="WAV"):
        parser.parse_args(["--csv", "t.csv"])
    text = parser.format_help()
    assert "WAV" in text and "the file" in text and "[SCENE]" in text


def test_a_scene_key_shares_the_record_of_its_option():
    """--room and configuration.room_m are one record: the scene's key is a list of 3 lengths, the option text."""
    from acoustiviz.app.settings.room import ROOM
    from acoustiviz.scene.schema import SCHEMA

    room = next(s for s in ROOM if s.name == "room")
    key = SCHEMA["configuration"].keys[room.key]
    assert (room.option, room.kind, key.kind, key.length, key.unit) == ("--room", "str", "floats", 3, "m")
    assert key.doc == room.scene_doc != room.doc
    tolerance = SCHEMA["configuration"].keys["tolerance_db"]
    assert (tolerance.low, tolerance.high, tolerance.high_open) == (-200.0, 0.0, True)
