"""Every gallery script runs alone (in fast mode) and writes its figure into one output folder."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

GALLERY = Path(__file__).resolve().parents[1] / "gallery"
SCRIPTS = sorted(GALLERY.glob("plot_*.py"))


def test_gallery_is_not_empty():
    assert SCRIPTS


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
@pytest.mark.slow
def test_gallery_script_runs(script, tmp_path):
    env = dict(os.environ, ACOUSTIVIZ_FAST="1", ACOUSTIVIZ_GALLERY_DIR=str(tmp_path), MPLBACKEND="Agg")
    res = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=900)
    assert res.returncode == 0, res.stderr[-3000:]
    made = [p for p in tmp_path.iterdir() if p.suffix in {".png", ".gif", ".mp4", ".wav", ".csv"}]
    pngs = [p for p in made if p.suffix == ".png"]
    assert pngs, f"{script.name} wrote no PNG into the gallery folder"
    for p in pngs:
        assert p.stat().st_size > 5_000, p
