"""The ``acoustiviz map`` command: files, the scene equivalent byte for byte, and refusals before work."""

import numpy as np
import pytest

from acoustiviz.cli import build_parser, main
from acoustiviz.scene import load_scene

SMALL = ["--resolution", "24", "--extent", "0.2"]


@pytest.mark.slow
def test_writes_png_csv_and_vtk(tmp_path, capsys):
    pv = pytest.importorskip("pyvista")
    Image = pytest.importorskip("PIL.Image")
    png, csv, vtk = tmp_path / "m.png", tmp_path / "m.csv", tmp_path / "m.vtu"
    assert main(["map", "--config", "wall-floor", "--wall-distance", "0.05", *SMALL, "--png", str(png),
                 "--csv", str(csv), "--vtk", str(vtk)]) == 0
    out = capsys.readouterr().out
    for p in (png, csv, vtk, tmp_path / "m_geometry.vtu"):
        assert f"wrote {p}" in out
    assert "peak SPL:" in out and "SEL:" in out
    with Image.open(png) as im:
        assert np.asarray(im.convert("RGB")).std() > 20
    rows = np.genfromtxt(csv, delimiter=",", names=True)
    assert rows.dtype.names == ("x_m", "y_m", "z_m", "peak_pa", "peak_spl_db", "sel_db", "time_of_peak_s")
    mesh = pv.read(vtk)
    np.testing.assert_allclose(np.asarray(mesh.point_data["sel_db"]), rows["sel_db"], atol=1e-6)  # CSV: %.6f
    assert not list(tmp_path.glob(".*")), "temporary files left behind"


def test_horizontal_plane_at_a_height(tmp_path):
    csv = tmp_path / "h.csv"
    assert main(["map", "--config", "plane", "--plane", "horizontal", "--plane-height", "0.1", *SMALL,
                 "--csv", str(csv)]) == 0
    rows = np.genfromtxt(csv, delimiter=",", names=True)
    assert np.all(rows["z_m"] == 0.1) and np.all(np.isfinite(rows["sel_db"]))


@pytest.mark.slow
def test_csv_equals_the_scene_output_byte_for_byte(tmp_path):
    csv = tmp_path / "cli.csv"
    assert main(["map", "--config", "wall-floor", "--wall-distance", "0.07", "--pulse", "hertz", "--velocity", "0.9",
                 "--plane", "horizontal", "--plane-height", "0.04", "--extent", "0.25", "--resolution", "30",
                 "--csv", str(csv)]) == 0
    scene = tmp_path / "s.toml"
    scene.write_text('[impact]\nvelocity_m_s = 0.9\n[contact]\npulse = "hertz"\n'
                     '[configuration]\nkind = "wall-floor"\nwall_distance_m = 0.07\n'
                     '[outputs.level_map]\nplane = "horizontal"\nheight_m = 0.04\nextent_m = 0.25\nresolution = 30\n')
    assert main(["run", str(scene), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    assert (tmp_path / "run" / "level_map.csv").read_bytes() == csv.read_bytes()
    assert (tmp_path / "run" / "level_map.png").stat().st_size > 0


def test_defaults_are_the_scene_defaults():
    args = build_parser().parse_args(["map"])
    sc = load_scene_text('[outputs.level_map]\n')
    opts = sc.output("level_map")
    assert (args.plane, args.plane_height, args.extent, args.resolution) == \
        (opts["plane"], opts["height_m"], opts["extent_m"], opts["resolution"])


def load_scene_text(text, tmp=None):
    from acoustiviz.scene import scene_from_text

    return scene_from_text(text, "t.toml")


BAD = [
    (["--resolution", "7"], "--resolution"),
    (["--extent", "0"], "--extent"),
    (["--extent", "5000"], "--extent"),
    (["--plane-height", "0.1"], "--plane-height"),
    (["--plane", "horizontal", "--plane-height", "-0.5"], "--plane-height"),
    (["--resolution", "20000"], "--resolution"),
    (["--resolution", "400", "--max-memory", "1"], "--resolution"),
    (["--radius", "-1"], "--radius"),
    (["--png", "x.unknown"], "--png"),
    (["--vtk", "x.csv"], "--vtk"),
]


@pytest.mark.parametrize(("argv", "option"), BAD)
def test_bad_input_is_one_line_naming_the_option_and_writes_nothing(argv, option, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    outs = ["--csv", str(tmp_path / "m.csv")] + (["--png", str(tmp_path / "m.png")] if "--png" not in argv else [])
    assert main(["map", "--config", "plane", *argv, *outs]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and f"error: {option}" in err, err
    assert list(tmp_path.iterdir()) == []


def test_scene_with_a_bad_map_is_refused_before_any_output(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text('[outputs.waveform]\n[outputs.level_map]\nplane = "horizontal"\nheight_m = -1.0\n')
    assert main(["run", str(scene), "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert "outputs.level_map.height_m" in err
    assert not (tmp_path / "run").exists()


def test_scene_map_over_the_memory_cap_is_refused_at_load(tmp_path):
    from acoustiviz.scene.validate import SceneError

    scene = tmp_path / "s.toml"
    scene.write_text('[grids]\nmemory_limit_mb = 10.0\n[outputs.level_map]\nresolution = 1000\n')
    with pytest.raises(SceneError) as err:
        load_scene(scene)
    assert err.value.key == "outputs.level_map.resolution" and "grids.memory_limit_mb" in str(err.value)


def test_map_progress_bar_only_on_a_terminal():
    # a map (command line and scene) reports its points done to a tqdm bar on a terminal (cleared when it
    # ends), to nothing elsewhere
    import io

    from acoustiviz.app.maps import points_bar

    with points_bar(io.StringIO()) as bar:
        assert bar is None
    term = io.StringIO()
    term.isatty = lambda: True
    with points_bar(term) as bar:
        for done in (100, 200, 300):
            bar(done, 300)
    text = term.getvalue()
    assert "map:" in text and "point" in text and text.endswith("\r")
