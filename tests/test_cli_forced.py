"""``acoustiviz forced``: the promised interface, its CSV and its errors."""

import csv
import math
import subprocess
import sys

import numpy as np
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


NEW = ["attractor", "basin_fraction", "stable", "max_floquet_modulus", "residual", "amplitude_std_err_m"]


@pytest.mark.slow
def test_table1_response_csv_and_png(tmp_path):
    out, png = tmp_path / "r.csv", tmp_path / "r.png"
    rc = main(["forced", *TABLE1, "--force", "5", "--freq", "3:7:3", "--csv", str(out), "--png", str(png)])
    assert rc == 0
    rows = _read(out)
    assert sorted({float(r["frequency_hz"]) for r in rows}) == [3.0, 5.0, 7.0]
    assert list(rows[0])[: len(PROMISED)] == PROMISED and set(NEW) <= set(rows[0])
    for f in (3.0, 5.0, 7.0):  # one row per attractor, the basins of the starts add up to 1
        group = [r for r in rows if float(r["frequency_hz"]) == f]
        assert [int(r["attractor"]) for r in group] == list(range(1, len(group) + 1))
        assert sum(float(r["basin_fraction"]) for r in group) == pytest.approx(1.0)
        assert sum("amplitude" in r["worst_case"] for r in group) == 1
    for r in rows:
        f = float(r["frequency_hz"])
        w = 2 * math.pi * f
        a0 = 5.0 / math.hypot(500 - 0.5 * w * w, 0.05 * w)  # main mass alone, closed form
        assert float(r["amplitude_without_damper_m"]) == pytest.approx(a0, rel=1e-9)  # 10 digits
        amp = float(r["amplitude_m"])
        assert float(r["reduction_db"]) == pytest.approx(20 * math.log10(a0 / amp), abs=1e-7)
        assert r["regime"] in ("quasi-periodic", "chaotic", "unresolved") or r["regime"].startswith("periodic-")
        if r["regime"].startswith("periodic-"):
            assert r["converged"] == "true" and float(r["residual"]) < 1e-9
            assert float(r["amplitude_std_err_m"]) == 0.0 and r["max_floquet_modulus"]
            assert (r["stable"] == "true") == (float(r["max_floquet_modulus"]) <= 1 + 1e-5)
        else:
            assert r["converged"] == "false" and r["residual"] == "" and float(r["amplitude_std_err_m"]) > 0
        if float(r["impacts_per_cycle"]) > 0:  # levels by default, at the paper's listener
            levels = [float(r[c]) for c in ("laeq_db", "lcpeak_db", "lafmax_db", "lzpeak_db", "lzeq_db")]
            assert all(math.isfinite(v) for v in levels)
            assert float(r["lcpeak_db"]) > float(r["lafmax_db"]) >= float(r["laeq_db"]) > 40
            assert float(r["level_interval_s"]) * f == pytest.approx(round(float(r["level_interval_s"]) * f),
                                                                     abs=1e-3)  # whole cycles
        else:
            assert r["laeq_db"] == r["lcpeak_db"] == "-inf"  # silence
        assert (r["tolerance"], r["rtol"], r["starts"], r["max_cycles"]) == ("1e-09", "1e-10", "6", "500")
    # far below resonance the 15.5 mm linear motion fits in the 20 mm half gap: a motion without impacts
    quiet = [r for r in rows if float(r["frequency_hz"]) == 3.0 and float(r["impacts_per_cycle"]) == 0.0]
    assert len(quiet) == 1
    assert float(quiet[0]["amplitude_m"]) == pytest.approx(float(quiet[0]["amplitude_without_damper_m"]), rel=1e-9)
    # at resonance every attractor cuts the amplitude
    assert all(float(r["reduction_db"]) > 10 for r in rows if float(r["frequency_hz"]) == 5.0)
    assert png.stat().st_size > 10_000


def test_base_excitation_and_comma_list(tmp_path):
    out = tmp_path / "b.csv"
    rc = main(["forced", "--base", "0.002", "--freq", "2,8", "--sweep", "both", "--starts", "3", "--csv", str(out)])
    assert rc == 0
    rows = _read(out)
    assert {float(r["frequency_hz"]) for r in rows} == {2.0, 8.0} and "hysteresis" in rows[0]
    w = 2 * math.pi * 2.0
    a0 = 0.002 * math.hypot(500, 0.05 * w) / math.hypot(500 - 0.5 * w * w, 0.05 * w)
    assert float(rows[0]["amplitude_without_damper_m"]) == pytest.approx(a0, rel=1e-9)
    assert all(r["starts"] == "3" for r in rows)


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
    (["--force", "5", "--freq", "3", "--workers", "0"], "--workers"),
    (["--force", "5", "--freq", "3", "--starts", "0"], "--starts"),
    (["--force", "5", "--freq", "3", "--rtol", "1e-2"], "--rtol"),
    (["--force", "5", "--freq", "3", "--tolerance", "0"], "--tolerance"),
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


@pytest.mark.slow
def test_noise_columns_and_wav(tmp_path):
    out, wav = tmp_path / "n.csv", tmp_path / "n.wav"
    rc = main(["forced", "--force", "5", "--freq", "3,7", "--wav", str(wav), "--csv", str(out)])
    assert rc == 0
    rows = _read(out)
    assert rows[0]["lzpeak_db"] == "-inf"  # no impacts at 3 Hz: silence
    assert float(rows[1]["lzpeak_db"]) > 80
    assert wav.stat().st_size > 1000 and (tmp_path / "n.json").exists()
    import soundfile as sf

    data, fs = sf.read(wav)
    assert fs == 48000 and np.max(np.abs(data)) <= 1.0  # plays without clipping
    # each frequency's level interval in turn (whole periods), re-rendered at 48 kHz
    total = sum(float(r["level_interval_s"]) for r in rows)
    assert data.shape[0] == pytest.approx(total * fs, abs=len(rows))


@pytest.mark.slow
def test_no_noise_leaves_the_level_columns_empty(tmp_path):
    out = tmp_path / "q.csv"
    assert main(["forced", "--force", "5", "--freq", "5", "--no-noise", "--csv", str(out)]) == 0
    row = _read(out)[0]
    assert float(row["impacts_per_cycle"]) > 0
    assert row["laeq_db"] == row["lcpeak_db"] == row["lafmax_db"] == ""


@pytest.mark.parametrize("argv,option", [
    (["--noise-seconds", "0"], "--noise-seconds"),
    (["--noise-seconds", "nan"], "--noise-seconds"),
    (["--no-noise", "--wav", "x.wav"], "--wav"),
    (["--listener", "0,0,0.01"], "--listener"),  # inside the sphere
    (["--no-noise", "--listener", "0.5,0,-1"], "--listener"),  # below the floor
])
def test_bad_noise_options_exit_2(argv, option, capsys, tmp_path):
    out = tmp_path / "x.csv"
    assert main(["forced", "--force", "5", "--freq", "7", *argv, "--csv", str(out)]) == 2
    assert option in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.slow
def test_independent_frequencies_on_a_dask_cluster_equal_the_serial_run(tmp_path):
    """The sweeps' executors serve the frequency response too: a Dask cluster gives the serial table."""
    distributed = pytest.importorskip("distributed")
    argv = ["forced", *TABLE1, "--force", "5", "--freq", "6.5,7", "--sweep", "independent", "--no-noise"]
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp://",
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        address = cluster.scheduler_address.removeprefix("tcp://")
        assert main([*argv, "--executor", f"dask://{address}", "--csv", str(tmp_path / "dask.csv")]) == 0
    assert main([*argv, "--csv", str(tmp_path / "serial.csv")]) == 0
    assert _read(tmp_path / "dask.csv") == _read(tmp_path / "serial.csv")


@pytest.mark.slow
def test_an_unreachable_dask_scheduler_is_named(capsys):
    assert main(["forced", *TABLE1, "--force", "5", "--freq", "6.5,7", "--executor", "dask://127.0.0.1:1"]) == 2
    err = capsys.readouterr().err
    assert "--executor" in err and "Dask" in err


@pytest.mark.parametrize("extra, option", [(["--max-memory", "5"], "--noise-seconds"),
                                           (["--max-cycles", "100000000"], "--max-cycles"),
                                           (["--max-cycles", "0"], "--max-cycles")])
def test_work_is_bounded_before_it_starts(extra, option, capsys, tmp_path):
    rc = main(["forced", *TABLE1, "--force", "5", "--freq", "3:7:9", "--csv", str(tmp_path / "f.csv"), *extra])
    assert rc == 2
    err = capsys.readouterr().err
    assert option in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "f.csv").exists()
