"""acoustiviz.output.html: self-contained interactive pages, checked as data and in a headless browser."""

import base64
import importlib.util
import json
import re
from pathlib import Path

import numpy as np
import pytest

from acoustiviz.app.impacts import impact_setup
from acoustiviz.cli import main
from acoustiviz.field import snapshots

pytest.importorskip("pyvista")

ROOT = Path(__file__).resolve().parents[1]


def _browser():
    spec = importlib.util.spec_from_file_location("screenshots", ROOT / "docs" / "screenshots.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _scene(path):
    text = Path(path).read_text(encoding="utf-8")
    m = re.search(r'<script type="application/json" id="scene-data">(.*?)</script>', text, re.S)
    return text, json.loads(m.group(1))


def _f32(b64):
    return np.frombuffer(base64.b64decode(b64), dtype="<f4")


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    d = tmp_path_factory.mktemp("html")
    assert main(["render", "balloon", "--config", "wall-floor", "--wall-distance", "0.05", "--resolution", "10",
                 "--html", str(d / "balloon.html")]) == 0
    assert main(["render", "snapshot", "--config", "plane", "--time", "0.0005", "0.001", "--resolution", "61",
                 "--html", str(d / "snapshot.html")]) == 0
    return d


@pytest.mark.parametrize("name", ["balloon.html", "snapshot.html"])
def test_page_is_self_contained(pages, name):
    text, scene = _scene(pages / name)
    # nothing is fetched: no external script, style, image or frame
    assert not re.search(r'<(script|link|img|iframe)[^>]+(src|href)=', text)
    assert "http://" not in text and "https://" not in text
    assert scene["layers"] and len(base64.b64decode(scene["lut"])) == 256 * 3
    for layer in scene["layers"]:
        n = _f32(layer["positions"]).size // 3
        idx = np.frombuffer(base64.b64decode(layer["indices"]), dtype="<u4")
        assert idx.size and idx.max() < n


def test_snapshot_page_carries_the_evaluators_field(pages):
    _, scene = _scene(pages / "snapshot.html")
    assert scene["frame_labels"] == ["t = 0.500 ms", "t = 1.000 ms"]
    plane = next(layer for layer in scene["layers"] if layer.get("scalars"))
    pts = _f32(plane["positions"]).reshape(-1, 3).astype(float)
    s = impact_setup(radius=0.01905, velocity=1.4, config="plane")
    ref = snapshots(s.pulse, [0.0005, 0.001], pts, s.geometry, medium=s.medium)
    for k in range(2):
        got = _f32(plane["scalars"][k])
        # float32 positions and values: agreement to single precision of the field's scale
        np.testing.assert_allclose(got, ref[k], rtol=0, atol=1e-4 * np.nanmax(np.abs(ref[k])), equal_nan=True)
    lo, hi = scene["clim"]
    assert lo == -hi and hi > 0
    assert scene["colorbar"] == "sound pressure (Pa)"


def test_balloon_page_levels(pages):
    _, scene = _scene(pages / "balloon.html")
    balloon = next(layer for layer in scene["layers"] if layer.get("scalars"))
    level = _f32(balloon["scalars"][0])
    lo, hi = scene["clim"]
    assert hi - lo == pytest.approx(30.0) and np.nanmax(level) == pytest.approx(hi, abs=1e-3)
    assert "dB re 20 µPa" in scene["colorbar"]


@pytest.mark.slow
@pytest.mark.parametrize(("name", "colour"), [("balloon.html", "viridis"), ("snapshot.html", "diverging")])
def test_page_renders_in_headless_chromium(pages, tmp_path, name, colour):
    shots = _browser()
    if shots.find_chromium() is None:
        pytest.skip("Chromium is not installed")
    url = (pages / name).as_uri()
    state = re.search(r'<p id="status">([^<]*)</p>', shots.dom(url))
    assert state and state.group(1).startswith("rendered "), state and state.group(1)
    png = shots.screenshot(url, tmp_path / "page.png", size=(900, 650))
    b = shots.blankness(png)
    assert b["colours"] > 500 and b["ink"] > 0.05, b
    from PIL import Image

    rgb = np.asarray(Image.open(png).convert("RGB")).astype(int)
    r, g, bl = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    if colour == "viridis":  # the balloon's green-yellow-teal surface fills part of the view
        share = np.mean((g > r + 20) & (g > bl - 10) & (g > 80))
    else:  # red and blue lobes of the pressure on the section
        share = min(np.mean((r > bl + 60) & (r > g + 40)), np.mean((bl > r + 60) & (bl > g + 20)))
    assert share > 0.002, share
