"""Scene outputs ``levels`` and ``spectrum`` of a damper run."""

import csv

import numpy as np
import pytest

from acoustiviz.app.pipeline import run_scene
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("lv") / "o"
    scene = scene_from_dict({"damper": {"duration_s": 0.6}, "outputs": {"levels": {}, "spectrum": {}}})
    return out, run_scene(scene, out)


@pytest.mark.slow
def test_levels_and_spectrum_files_and_summary(run):
    out, products = run
    names = {p.path.name for p in products}
    assert {"levels.csv", "levels_bands.csv", "spectrum.csv", "spectrum.png", "summary.md"} <= names
    row = _rows(out / "levels.csv")[0]
    assert row["evaluated_at_hz"] == "96000" and row["channel_name"] == "paper"
    assert float(row["lzpeak_db"]) >= float(row["lafmax_db"]) >= float(row["laeq_db"]) - 1e-9
    fig = next(p for p in products if p.path.name == "levels.csv").figures
    assert fig["lcpeak_db"] == f"{float(row['lcpeak_db']):.1f}"


def test_band_energies_add_up_to_the_unweighted_level(run):
    out, _ = run
    row = _rows(out / "levels.csv")[0]
    bands = _rows(out / "spectrum.csv")
    total = 10 * np.log10(sum(10 ** (float(b["leq_db"]) / 10) for b in bands))
    assert total == pytest.approx(float(row["lzeq_db"]), abs=0.3)
    assert [float(b["band_hz"]) for b in bands][::29] == [25.0, 20000.0]


def test_exposure_is_the_equivalent_level_times_the_interval(run):
    out, _ = run
    row = _rows(out / "levels.csv")[0]
    t = float(row["stop_s"]) - float(row["start_s"])
    assert float(row["sel_a_db"]) == pytest.approx(float(row["laeq_db"]) + 10 * np.log10(t), abs=1e-3)


def test_loudness_without_mosqito_is_refused_naming_the_key(tmp_path, monkeypatch):
    import acoustiviz.app.scene_levels as sl

    monkeypatch.setattr(sl, "loudness_available", lambda: False)
    scene = scene_from_dict({"damper": {"duration_s": 0.2}, "outputs": {"levels": {"loudness": True}}})
    with pytest.raises(ParameterError, match="outputs.levels.loudness"):
        run_scene(scene, tmp_path / "o")
