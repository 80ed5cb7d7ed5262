"""``acoustiviz forced``: the promised interface, its CSV and its errors."""

import csv
import math
import subprocess
import sys

import pytest

from acoustiviz.app.forced import parse_frequencies
from acoustiviz.cli import main
from acoustiviz.errors import ParameterError

TABLE1 = ["--M", "0.5", "--K", "500", "--C", "0.05", "--m", "0.0405", "--gap", "0.04",
          "--k-hertz", "5.6e8", "--c1", "20"]
PROMISED = ["frequency_hz", "amplitude_m", "amplitude_without_damper_m", "reduction_db",
            "impacts_per_cycle", "regime", "laeq_db", "lcpeak_db"]


def _read(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_table1_response_csv_and_png(tmp_path):
    out, png = tmp_path / "r.csv", tmp_path / "r.png"
    rc = main(["forced", *TABLE1, "--force", "5", "--freq", "3:7:3", "--csv", str(out), "--png", str(png)])
    assert rc == 0
    rows = _read(out)
    assert [float(r["frequency_hz"]) for r in rows] == [3.0, 5.0, 7.0]
    assert list(rows[0])[: len(PROMISED)] == PROMISED
    for r in rows:
        f = float(r["frequency_hz"])
        w = 2 * math.pi * f
        a0 = 5.0 / math.hypot(500 - 0.5 * w * w, 0.05 * w)  # main mass alone, closed form
        assert float(r["amplitude_without_damper_m"]) == pytest.approx(a0, rel=1e-9)  # 10 digits
        amp = float(r["amplitude_m"])
        assert float(r["reduction_db"]) == pytest.approx(20 * math.log10(a0 / amp), abs=1e-7)
        assert r["regime"] in ("non-periodic",) or r["regime"].startswith("periodic-")
        assert r["laeq_db"] == "" and r["lcpeak_db"] == ""
    # far below resonance the 15.5 mm linear motion fits in the 20 mm half gap: no impacts
    assert float(rows[0]["impacts_per_cycle"]) == 0.0
    assert float(rows[0]["amplitude_m"]) == pytest.approx(float(rows[0]["amplitude_without_damper_m"]), rel=1e-9)
    # at resonance the damper cuts the amplitude
    assert float(rows[1]["reduction_db"]) > 10
    assert png.stat().st_size > 10_000


def test_base_excitation_and_comma_list(tmp_path):
    out = tmp_path / "b.csv"
    rc = main(["forced", "--base", "0.002", "--freq", "2,8", "--sweep", "both", "--csv", str(out)])
    assert rc == 0
    rows = _read(out)
    assert len(rows) == 2 and "hysteresis" in rows[0]
    w = 2 * math.pi * 2.0
    a0 = 0.002 * math.hypot(500, 0.05 * w) / math.hypot(500 - 0.5 * w * w, 0.05 * w)
    assert float(rows[0]["amplitude_without_damper_m"]) == pytest.approx(a0, rel=1e-9)


@pytest.mark.parametrize("argv,option", [
    (["--force", "5", "--freq", "7:3:5"], "--freq"),
    (["--force", "5", "--freq", "abc"], "--freq"),
    (["--force", "5", "--freq", "0,3"], "--freq"),
    (["--force", "5", "--freq", "3:7:0"], "--freq"),
    (["--force", "-1", "--freq", "3:7:3"], "--force"),
    (["--base", "-1", "--freq", "3:7:3"], "--base"),
    (["--force", "5", "--freq", "3", "--M", "0"], "--M"),
    (["--force", "5", "--freq", "3", "--gap", "-0.1"], "--gap"),
    (["--force", "5", "--freq", "3", "--sweep", "sideways"], "--sweep"),
    (["--force", "5", "--freq", "3", "--solver", "rk4"], "--solver"),
    (["--force", "5", "--freq", "3", "--tolerance", "2"], "--tolerance"),
    (["--force", "5", "--freq", "3", "--max-cycles", "1"], "--max-cycles"),
    (["--force", "5", "--freq", "3", "--solver", "impact-map", "--restitution", "1.5"], "--restitution"),
    (["--force", "5", "--freq", "3", "--workers", "2"], "--workers"),
])
def test_bad_values_exit_2_naming_the_option(argv, option, capsys, tmp_path):
    out = tmp_path / "x.csv"
    rc = main(["forced", *argv, "--csv", str(out)])
    assert rc == 2
    err = capsys.readouterr().err
    assert option in err
    assert not out.exists()


def test_force_and_base_together_are_refused():
    proc = subprocess.run([sys.executable, "-m", "acoustiviz", "forced", "--force", "5", "--base", "0.01",
                           "--freq", "3"], capture_output=True, text=True)
    assert proc.returncode == 2 and "--base" in proc.stderr


def test_parse_frequencies():
    assert parse_frequencies("3:7:9").tolist() == pytest.approx([3, 3.5, 4, 4.5, 5, 5.5, 6, 6.5, 7])
    assert parse_frequencies("5").tolist() == [5.0]
    with pytest.raises(ParameterError) as err:
        parse_frequencies("3,3")
    assert err.value.name == "--freq"


def test_operating_noise_is_the_sum_of_its_clicks(tmp_path):
    """A period-1 motion with two equal impacts per cycle: SEL per cycle = two lone clicks' exposure."""
    import numpy as np

    from acoustiviz.app.forced import default_listener, operating_noise
    from acoustiviz.app.wav import cavity
    from acoustiviz.constants import P_REF, PAPER_RADIUS
    from acoustiviz.dynamics import DamperModel
    from acoustiviz.dynamics.forced import Excitation, steady_state
    from acoustiviz.output.audio import ClickModel, ImpactSequence, render

    model = DamperModel()
    r = steady_state(model, Excitation(6.5, 5.0), initial=(0.0, 0.0, 0.0, 0.5))
    assert r.regime == "periodic-1" and r.impacts_per_cycle == 2
    nz = operating_noise(r, seconds=0.5)
    clicks = ClickModel(k_hertz=model.k_hertz, mass=model.m, main_mass=model.M)
    scene = cavity("plane", PAPER_RADIUS, model.gap)
    energy = 0.0
    for wall, speed in zip(r.impact_walls, r.impact_speeds, strict=True):
        one = render(ImpactSequence([0.01], [int(wall)], [speed]), scene, clicks, default_listener())
        energy += float(np.sum(one.pressure[0] ** 2)) / one.sample_rate
    assert nz.sel_per_cycle_db == pytest.approx(10 * math.log10(energy / P_REF**2), abs=0.01)
    assert nz.lzeq_db == pytest.approx(nz.sel_per_cycle_db + 10 * math.log10(6.5), abs=1e-9)
    assert nz.duration == pytest.approx(4 / 6.5)


def test_noise_columns_and_wav(tmp_path):
    out, wav = tmp_path / "n.csv", tmp_path / "n.wav"
    rc = main(["forced", "--force", "5", "--freq", "3,7", "--wav", str(wav), "--csv", str(out)])
    assert rc == 0
    rows = _read(out)
    assert rows[0]["lzpeak_db"] == "-inf"  # no impacts at 3 Hz: silence
    assert float(rows[1]["lzpeak_db"]) > 80
    assert wav.stat().st_size > 1000 and (tmp_path / "n.json").exists()


def test_design_map_is_silent_and_neutral_where_the_mass_never_strikes():
    import numpy as np

    from acoustiviz.app.forced import design_map
    from acoustiviz.dynamics import DamperModel

    # at 3 Hz and 5 N the main mass moves 15.5 mm: clear of a 20 mm half gap, not of a 10 mm one
    d = design_map(DamperModel(), [0.0405], [0.02, 0.04], 3.0, 5.0)
    assert d.reduction_db.shape == d.lzeq_db.shape == (1, 2)
    assert d.reduction_db[0, 1] == pytest.approx(0.0, abs=1e-9)
    assert d.lzeq_db[0, 1] == -np.inf
    assert np.isfinite(d.lzeq_db[0, 0]) and d.lzeq_db[0, 0] > 40
