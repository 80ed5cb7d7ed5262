"""Scenes with an [excitation]: the damper in operation as scene outputs."""

import csv

import pytest

from acoustiviz.cli import main
from acoustiviz.scene import scene_from_text

SCENE = """
[scene]
name = "forced"
[excitation]
amplitude = 5.0
frequencies_hz = "6:7:3"
[[listeners]]
name = "paper"
distance_m = 0.7
angle_deg = 45.0
[outputs.frequency_response]
[outputs.bifurcation]
[outputs.operating_noise]
seconds = 0.3
"""


@pytest.mark.slow
def test_scene_writes_the_three_forced_outputs(tmp_path):
    path = tmp_path / "forced.toml"
    path.write_text(SCENE)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    with open(out / "frequency_response.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert sorted({float(r["frequency_hz"]) for r in rows}) == [6.0, 6.5, 7.0]  # a row per attractor
    with open(out / "operating_noise.csv", newline="") as fh:
        noise = list(csv.DictReader(fh))
    assert [r["regime"] for r in noise] == [r["regime"] for r in rows]
    for r, n in zip(rows, noise, strict=True):  # the response table carries the same levels
        for c in ("laeq_db", "lcpeak_db", "lafmax_db"):
            assert float(r[c]) == float(n[c]), c
            assert float(n[c]) > 40 or float(r["impacts_per_cycle"]) == 0, c
    for name in ("frequency_response.png", "bifurcation.png", "operating_noise_paper.wav"):
        assert (out / name).stat().st_size > 1000, name
    assert "| operating_noise |" in (out / "summary.md").read_text()


@pytest.mark.parametrize("line,key", [
    ('amplitude = -1.0', "amplitude"),
    ('kind = "wind"', "kind"),
    ('frequencies_hz = "0:7:3"', "frequencies_hz"),
    ('sweep = "sideways"', "sweep"),
    ('max_cycles = 3', "max_cycles"),
    ('starts = 0', "starts"),
    ('rtol = 0.1', "rtol"),
    ('tolerance = 0.0', "tolerance"),
])
def test_bad_excitation_keys_are_named(line, key):
    block = '[excitation]\namplitude = 5.0\nfrequencies_hz = "6:7:3"\n'
    assert block in SCENE
    text = SCENE.replace(block, f"[excitation]\n{line}\n")
    with pytest.raises(ValueError) as err:
        scene_from_text(text, "bad")
    assert f"excitation.{key}" in str(err.value)
