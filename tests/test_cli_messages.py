"""Messages a user can act on, and no output that silently holds inf, nan or only zeros.

Each refusal is one line naming the user's option or scene key (never a Python parameter) and the
allowed range or what it would take; the fixtures and helpers are those of ``test_cli_fuzz``.
"""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
import soundfile as sf
from test_cli_fuzz import assert_user_error, call, here, left_over  # noqa: F401 - here: a fixture

RATE = 48000


def _sine_wav(path, *, amplitude=0.5, seconds=0.5, channels=1, sidecar=None):
    """A 1 kHz sine of ``amplitude`` full scale as 24-bit PCM, and optionally its JSON sidecar."""
    t = np.arange(int(seconds * RATE)) / RATE
    data = np.tile(amplitude * np.sin(2 * np.pi * 1000.0 * t)[:, None], (1, channels))
    sf.write(str(path), data, RATE, subtype="PCM_24")
    if sidecar is not None:
        path.with_suffix(".json").write_text(json.dumps(sidecar))
    return path


def _levels_row(path):
    with open(path, newline="") as fh:
        return next(csv.DictReader(fh))


# --- levels: a calibration whose levels overflow is refused, one that does not gives finite levels
@pytest.mark.parametrize("scale", ["1e308", "1e200", "1e-300"])
def test_levels_refuses_a_calibration_whose_levels_overflow(here, capsys, scale):  # noqa: F811
    _sine_wav(here / "s.wav")
    rc = call(["levels", "s.wav", "--pa-per-fs", scale, "--csv", "l.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--pa-per-fs")
    assert "must lie in [" in err and "Pa" in err
    assert "pa_per_fs" not in err
    assert left_over(here) == ["s.wav"]


def test_levels_of_a_huge_calibration_within_range_are_finite_and_linear(here, capsys):  # noqa: F811
    _sine_wav(here / "s.wav")
    assert call(["levels", "s.wav", "--pa-per-fs", "1", "--csv", "one.csv"]) == 0
    assert call(["levels", "s.wav", "--pa-per-fs", "1e100", "--csv", "big.csv"]) == 0
    one, big = _levels_row(here / "one.csv"), _levels_row(here / "big.csv")
    for col in ("lzpeak_db", "lzeq_db", "laeq_db", "sel_db"):
        assert big[col] != "" and one[col] != "", col
        assert float(big[col]) - float(one[col]) == pytest.approx(2000.0, abs=1e-3), col  # 20 log10(1e100)
    with open(here / "big_bands.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(math.isfinite(float(r["leq_db"])) for r in rows if r["band_hz"] == "1000")


def test_levels_refuses_a_sidecar_calibration_whose_levels_overflow(here, capsys):  # noqa: F811
    _sine_wav(here / "s.wav", sidecar={"scale_pa_per_full_scale": 1e308})
    rc = call(["levels", "s.wav", "--csv", "l.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "s.json")
    assert "scale_pa_per_full_scale" in err and "must lie in [" in err


# --- levels: a sidecar that contradicts its file
@pytest.mark.parametrize("field, value", [("sample_rate_hz", 44100), ("channels", 2), ("frames", 1000)])
def test_levels_refuses_a_sidecar_that_contradicts_its_file(here, capsys, field, value):  # noqa: F811
    good = {"scale_pa_per_full_scale": 1.0, "sample_rate_hz": RATE, "channels": 1, "frames": RATE // 2}
    _sine_wav(here / "s.wav", sidecar={**good, field: value})
    rc = call(["levels", "s.wav", "--csv", "l.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "s.json")
    assert field in err and str(value) in err
    assert left_over(here) == ["s.json", "s.wav"]


def test_levels_trusts_a_sidecar_that_agrees_with_its_file(here, capsys):  # noqa: F811
    side = {"scale_pa_per_full_scale": 2.0, "sample_rate_hz": RATE, "channels": 2, "frames": RATE // 2}
    _sine_wav(here / "s.wav", channels=2, sidecar=side)
    assert call(["levels", "s.wav", "--csv", "l.csv"]) == 0
    # a 1 kHz sine of 0.5 x 2 Pa: its peak is 1 Pa, 93.98 dB re 20 uPa
    assert float(_levels_row(here / "l.csv")["lzpeak_db"]) == pytest.approx(20 * math.log10(1.0 / 20e-6), abs=0.05)


# --- auralize: a given scale that leaves the file all zeros (or infinite) is refused before any file
@pytest.mark.parametrize("scale, subtype, words", [("1e308", "PCM_24", "only zeros"), ("1e308", "FLOAT", "only zeros"),
                                                   ("1e-300", "FLOAT", "infinities")])
def test_auralize_refuses_a_scale_the_file_cannot_hold(here, capsys, scale, subtype, words):  # noqa: F811
    rc = call(["auralize", "--duration", "1", "--wav", "a.wav", "--scale", scale, "--subtype", subtype])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--scale")
    assert words in err and "must lie in (" in err
    assert left_over(here) == []


def test_auralize_with_a_scale_in_range_writes_the_sound(here, capsys):  # noqa: F811
    assert call(["auralize", "--duration", "1", "--wav", "a.wav", "--scale", "1000"]) == 0
    data, _ = sf.read(str(here / "a.wav"))
    record = json.loads((here / "a.json").read_text())
    peak = max(record["peak_pa"])
    # 24-bit samples of p / 1000 Pa: the file's peak is the sound's, to half a step
    assert np.max(np.abs(data)) == pytest.approx(peak / 1000.0, abs=2.0**-24)
    assert np.count_nonzero(data) > 0


# --- memory: named after the user's option or scene key and the cap's, in MB, before the work
def _no_field_work(monkeypatch):
    """Make any evaluation of the field fail the test: a refusal must come before the work."""
    import acoustiviz.app.views as views  # imported first: it binds field_metrics when it is imported
    import acoustiviz.field as field

    def forbidden(*args, **kwargs):
        raise AssertionError("the field was evaluated before the refusal")

    for name in ("time_series", "directivity", "field_metrics"):
        monkeypatch.setattr(field, name, forbidden)
    monkeypatch.setattr(views, "field_metrics", forbidden)


def test_directivity_of_a_weighted_level_names_max_memory_before_the_work(here, capsys, monkeypatch):  # noqa: F811
    _no_field_work(monkeypatch)
    rc = call(["directivity", "--metric", "laeq", "--step", "0.01", "--csv", "d.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--step")
    assert "--max-memory" in err and " MB of memory" in err and "2048 MB" in err
    assert "memory_limit" not in err and "iter_time_series" not in err
    assert left_over(here) == []


def test_directivity_of_a_weighted_level_within_a_raised_cap_runs(here, capsys):  # noqa: F811
    argv = ["directivity", "--metric", "laeq", "--step", "15", "--csv", "d.csv"]
    rc = call([*argv, "--max-memory", "0.5"])
    assert_user_error(rc, capsys.readouterr().err, "--step")
    assert call([*argv, "--max-memory", "64"]) == 0
    with open(here / "d.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 13  # 0 to 180 degrees by 15
    assert all(math.isfinite(float(v)) for r in rows for v in r.values())


ROOM_NO_WINDOW = """
[configuration]
kind = "room"
room_m = [6.0, 4.0, 3.0]
absorption = 0.1
source_m = [2.0, 1.5, 0.01905]
{window}
[[listeners]]
name = "middle"
position_m = [3.0, 2.0, 1.5]

[outputs.waveform]
"""


def test_a_room_scene_without_a_window_is_refused_at_load_naming_its_keys(here, capsys, monkeypatch):  # noqa: F811
    _no_field_work(monkeypatch)
    (here / "room.toml").write_text(ROOM_NO_WINDOW.format(window=""))
    rc = call(["run", "room.toml", "--out", "out", "--quiet"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "configuration.window_s")
    assert "grids.memory_limit_mb" in err and " MB of memory" in err and "room.toml" in err
    assert "memory_limit:" not in err and "B is too small" not in err
    assert left_over(here) == ["room.toml"]


def test_the_same_room_with_a_window_runs(here, capsys):  # noqa: F811
    (here / "room.toml").write_text(ROOM_NO_WINDOW.format(window="window_s = 0.02"))
    assert call(["run", "room.toml", "--out", "out", "--quiet"]) == 0
    with open(here / "out" / "waveform_middle.csv", newline="") as fh:
        p = np.array([float(r["pressure_pa"]) for r in csv.DictReader(fh)])
    assert np.all(np.isfinite(p)) and np.max(np.abs(p)) > 0


# --- a room whose image order the memory cap cut before its tolerance was met
LONG_RIGID_ROOM = ["waveform", "--room", "6,4,3", "--duration", "2", "--listener", "3,2,1.5"]


def test_a_room_that_leaves_out_more_than_its_tolerance_is_refused(here, capsys, monkeypatch):  # noqa: F811
    import re

    from acoustiviz.core.geometry import geometry

    _no_field_work(monkeypatch)
    rc = call([*LONG_RIGID_ROOM, "--csv", "w.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--max-memory")
    assert "--duration" in err and "-60 dB" in err and "image order" in err
    assert left_over(here) == []
    # what it would take, taken at its word: that cap meets the tolerance, one MB less does not
    need = int(re.search(r"raise --max-memory to (\d+)", err).group(1))
    room = dict(dimensions=(6.0, 4.0, 3.0), duration=2.0)
    enough = geometry("room", 0.01905, max_memory_mb=need, **room)
    assert not enough.order_capped and enough.neglected_energy_db <= -60.0
    assert geometry("room", 0.01905, max_memory_mb=need - 1, **room).order_capped


def test_the_room_cap_follows_max_memory(here, capsys, monkeypatch):  # noqa: F811
    _no_field_work(monkeypatch)
    short = ["waveform", "--room", "6,4,3", "--duration", "0.05", "--listener", "3,2,1.5", "--absorption", "0.1"]
    rc = call([*short, "--max-memory", "0.001"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--max-memory")
    assert err.startswith("acoustiviz waveform: error: --max-memory: ") and "image order" in err
    assert "cap of 0.001 MB" in err and "inf" not in err


def test_a_directivity_in_a_room_short_of_its_tolerance_is_refused(here, capsys, monkeypatch):  # noqa: F811
    _no_field_work(monkeypatch)
    rc = call(["directivity", "--room", "6,4,3", "--duration", "2", "--distance", "0.5", "--csv", "d.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--max-memory")
    assert err.startswith("acoustiviz directivity: error: --max-memory: ") and "--duration" in err
    assert left_over(here) == []


def test_levels_of_a_silent_file_say_so(here, capsys):  # noqa: F811
    _sine_wav(here / "s.wav", amplitude=0.0)
    assert call(["levels", "s.wav", "--pa-per-fs", "1", "--csv", "l.csv"]) == 0
    assert "channel 1 is silent" in capsys.readouterr().out
    assert _levels_row(here / "l.csv")["lzeq_db"] == "-inf"  # the level of silence (one rule for every CSV)


WEIGHTED_DIRECTIVITY_SCENE = """
[[listeners]]
name = "front"
distance_m = 0.7
angle_deg = 45.0
[outputs.directivity]
step_deg = {step}
metric = "laeq"
"""


def test_a_scene_directivity_of_a_weighted_level_is_refused_at_load(here, capsys, monkeypatch):  # noqa: F811
    _no_field_work(monkeypatch)
    (here / "d.toml").write_text(WEIGHTED_DIRECTIVITY_SCENE.format(step="0.01"))
    rc = call(["run", "d.toml", "--out", "out", "--quiet"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "outputs.directivity.step_deg")
    assert "grids.memory_limit_mb" in err and " MB of memory" in err and "memory_limit:" not in err
    assert left_over(here) == ["d.toml"]


def test_a_scene_directivity_of_a_weighted_level_within_the_cap_runs(here, capsys):  # noqa: F811
    (here / "d.toml").write_text(WEIGHTED_DIRECTIVITY_SCENE.format(step="30.0"))
    assert call(["run", "d.toml", "--out", "out", "--quiet"]) == 0
    with open(here / "out" / "directivity.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 4 and all(math.isfinite(float(r["laeq_db"])) for r in rows)  # 0 to 90 degrees


def test_levels_refuses_a_float_file_holding_nan(here, capsys):  # noqa: F811
    data = np.full(RATE // 10, 0.1)
    data[100] = np.nan
    sf.write(str(here / "n.wav"), data, RATE, subtype="FLOAT")
    rc = call(["levels", "n.wav", "--pa-per-fs", "1", "--csv", "l.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "SIGNAL.wav")
    assert "1 sample(s) that are not finite" in err
    assert left_over(here) == ["n.wav"]


@pytest.mark.slow
def test_a_room_window_too_long_for_memory_names_the_window_first(here, capsys):  # noqa: F811
    """In a room the number of samples grows with the window: the error names --duration before the defaults."""
    rc = call(["waveform", "--room", "6,4,3", "--absorption", "0.3", "--listener", "3,2,1.5", "--duration", "10000",
               "--csv", "o.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--duration")
    assert "--max-memory" in err and left_over(here) == []
