"""``acoustiviz run``: the built-in default scene end to end, shipped scenes, and refusals."""

import subprocess
import sys
from pathlib import Path

import pytest

from acoustiviz.cli import main
from acoustiviz.scene import OUTPUT_KINDS

SCENES = Path(__file__).resolve().parents[1] / "assets" / "scenes"


@pytest.mark.slow
def test_default_scene_produces_every_kind_of_output(tmp_path):
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, "-m", "acoustiviz", "run", "--out", str(out)], capture_output=True,
                         text=True, cwd=tmp_path, timeout=600)
    assert res.returncode == 0, res.stderr[-3000:]
    summary = (out / "summary.md").read_text()
    for kind in OUTPUT_KINDS:
        assert f"| {kind} |" in summary, kind
    for name in ("waveform_paper.csv", "directivity.csv", "snapshot.png", "balloon.png", "animation.gif",
                 "damper_history.png", "impacts.csv", "restitution.png", "sweep/sweep.csv", "design_table.png",
                 "wav_paper.wav", "wav_paper.json"):
        assert (out / name).stat().st_size > 0, name
    assert not list(out.rglob(".*")), "temporary files left behind"
    # a second run into the same folder is refused without --force, with exit status 2
    again = subprocess.run([sys.executable, "-m", "acoustiviz", "run", "--out", str(out)], capture_output=True,
                           text=True, cwd=tmp_path)
    assert again.returncode == 2 and "--force" in again.stderr and "Traceback" not in again.stderr


SHIPPED = sorted(p.stem for p in SCENES.glob("*.toml") if p.stem != "default")


@pytest.mark.parametrize("name", SHIPPED)
@pytest.mark.slow
def test_every_shipped_scene_runs(name, tmp_path):
    assert main(["run", str(SCENES / f"{name}.toml"), "--out", str(tmp_path / name), "--quiet"]) == 0
    assert (tmp_path / name / "summary.md").exists()


def test_invalid_scene_is_one_line_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[sphere]\nradius_m = -1\n")
    assert main(["run", str(bad), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "bad.toml: sphere.radius_m" in err and "(0, 1] m" in err
    assert not (tmp_path / "o").exists()  # nothing written before validation


def test_help_scene_lists_keys(capsys):
    assert main(["run", "--help-scene"]) == 0
    assert "[outputs]" in capsys.readouterr().out


@pytest.mark.slow
def test_output_piped_into_head_ends_without_a_traceback(tmp_path):
    # a reader that stops early closes the pipe; the command must not print a traceback.
    # 1801 angles print about 70 kB, more than a pipe holds, so the writer does meet the closed pipe
    cmd = f"{sys.executable} -m acoustiviz directivity --config free --step 0.1 | head -n 1"
    res = subprocess.run(["bash", "-c", cmd], capture_output=True, text=True, cwd=tmp_path)
    assert res.stdout.startswith("impact:") and "Traceback" not in res.stderr, res.stderr[-500:]
