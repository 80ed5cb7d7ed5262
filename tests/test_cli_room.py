"""``acoustiviz waveform --room`` and ``acoustiviz auralize --room``: the issue's commands, their files and errors.

The waveform's samples are checked against the closed-form radiation of
:mod:`acoustiviz.core.radiation` summed over the closed-form room images (an independent sum,
not the field evaluator); the sidecars against the image-order rules of
:mod:`acoustiviz.core.reverberation`.
"""

import csv
import json

import numpy as np
import pytest

from acoustiviz.cli import main
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import pressure
from acoustiviz.core.reverberation import order_for_time
from acoustiviz.core.room import Shoebox, image_count, image_sources

ISSUE_WAVEFORM = ["waveform", "--radius", "0.01905", "--velocity", "1.4", "--k-hertz", "5.6e8", "--density", "7800",
                  "--room", "6,4,3", "--absorption", "0.1", "--source", "2,1.5,0.01905", "--listener", "3,2,1.5",
                  "--duration", "0.2"]
ROOM = ["--room", "6,4,3", "--absorption", "0.1", "--source", "2,1.5,0.01905"]


@pytest.mark.slow
def test_issue_waveform_command_writes_the_columns_and_the_image_fields(tmp_path, capsys, half_sine_pulse):
    out = tmp_path / "OUT.csv"
    assert main([*ISSUE_WAVEFORM, "--csv", str(out)]) == 0
    with open(out, newline="") as f:
        assert next(csv.reader(f)) == ["time_s", "pressure_pa"]
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    t, p = data[:, 0], data[:, 1]
    assert abs(t[-1] - 0.2) < t[1] - t[0]
    side = json.loads((tmp_path / "OUT.json").read_text())
    want = order_for_time(Shoebox((6, 4, 3), 0.1), 0.2, radius=0.01905, medium=AIR)
    assert side["image_order"] == want and side["images"] == image_count(want)
    assert side["neglected_energy_db"] == "-inf"  # every image that can arrive within the window
    text = capsys.readouterr().out
    assert f"image_order {want}" in text and f"images {image_count(want)}" in text
    # the samples: the closed-form pressure summed over the images, in a few short stretches
    pulse = half_sine_pulse
    im = image_sources(Shoebox((6, 4, 3), 0.1), (2, 1.5, 0.01905), want, radius=0.01905)
    d = np.array([3.0, 2.0, 1.5]) - im.positions
    r = np.linalg.norm(d, axis=1)
    cos = np.sum(d * im.directions, axis=1) / r
    for start in (0.0050, 0.0123, 0.0601, 0.1502):
        sel = (t >= start) & (t < start + 0.002)
        ref = np.zeros(sel.sum())
        for j in np.flatnonzero((r - 0.01905) / AIR.c < start + 0.002):
            ref += im.weights[j] * pressure(pulse, t[sel], r[j], cos[j], radius=0.01905)
        scale = np.abs(p).max()
        np.testing.assert_allclose(p[sel], ref, rtol=0, atol=1e-9 * scale)


def test_issue_auralize_command_short_run_writes_a_wav_and_the_image_fields(tmp_path, capsys):
    """The issue's auralize command with a shorter damper run and a looser tolerance (the same path, smaller)."""
    wav = tmp_path / "OUT.wav"
    assert main(["auralize", *ROOM, "--listener", "3,2,1.5", "--duration", "0.3", "--tolerance-db", "-20",
                 "--wav", str(wav)]) == 0
    side = json.loads((tmp_path / "OUT.json").read_text())
    for rec in (side, side["scene"]):
        assert rec["image_order"] >= 1 and rec["images"] == image_count(rec["image_order"])
        assert rec["neglected_energy_db"] <= -20.0
    assert side["configuration"] == "room" and side["scene"]["dimensions_m"] == [6.0, 4.0, 3.0]
    assert wav.stat().st_size > 1000
    assert "image_order" in capsys.readouterr().out


@pytest.mark.parametrize("extra, option", [
    (["--room", "-6,4,3"], "--room"),
    (["--room", "6,4", "--absorption", "0.1"], "--room"),
    (["--room", "6,4,3", "--absorption", "1.0"], "--absorption"),
    (["--room", "6,4,3", "--absorption", "0.1,0.1"], "--absorption"),
    (["--room", "6,4,3", "--absorption", "0.1", "--source", "7,1.5,0.5"], "--source"),
    (["--room", "6,4,3", "--absorption", "0.1", "--source", "2,1.5,0.01905", "--listener", "2,1.5,0.02"],
     "--listener"),
    (["--room", "6,4,3", "--absorption", "0.1", "--source", "2,1.5,0.01905", "--listener", "3,2,3.5"],
     "--listener"),
    (["--absorption", "0.1"], "--absorption"),
])
@pytest.mark.parametrize("command", ["waveform", "auralize"])
def test_bad_room_input_is_refused_in_one_line_naming_the_option(command, extra, option, tmp_path, capsys):
    args = list(extra)
    if command == "waveform":
        if "--room" in args:
            args += ["--duration", "0.01"] + ([] if "--listener" in args else ["--listener", "3,2,1.5"])
        args += ["--csv", str(tmp_path / "o.csv")]
    else:
        args += ([] if "--listener" in args else ["--listener", "3,2,1.5"]) + ["--wav", str(tmp_path / "o.wav")]
    assert main([command, *args]) == 2
    err = capsys.readouterr().err.strip()
    assert option in err and len(err.splitlines()) == 1, err
    assert not list(tmp_path.iterdir())
