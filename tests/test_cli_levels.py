"""The ``acoustiviz levels`` command: calibration from the sidecar or the option, CSV files, errors."""

import csv
import json
import math

import numpy as np
import pytest
import soundfile as sf

from acoustiviz.cli import main

FS = 48000
L_1PA = 20 * math.log10(1 / 20e-6)
COLUMNS = ["channel", "lzpeak_db", "lcpeak_db", "lafmax_db", "lasmax_db", "laeq_db", "lzeq_db", "sel_db", "sel_a_db"]


def _tone(freq=1000.0, seconds=2.0, rms=1.0):
    t = np.arange(int(seconds * FS)) / FS
    return math.sqrt(2) * rms * np.sin(2 * np.pi * freq * t)


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_pcm_file_with_sidecar_reads_its_calibration(tmp_path, capsys):
    wav = tmp_path / "SIGNAL.wav"
    scale = 4.0  # Pa per full scale: a 1 Pa rms tone peaks at 0.35 FS
    sf.write(wav, _tone() / scale, FS, subtype="PCM_24")
    (tmp_path / "SIGNAL.json").write_text(json.dumps({"scale_pa_per_full_scale": scale, "channel_names": ["mono"]}))
    out = tmp_path / "OUT.csv"
    assert main(["levels", str(wav), "--csv", str(out), "--start", "0.5", "--stop", "2"]) == 0
    assert "sidecar" in capsys.readouterr().out
    rows = _rows(out)
    assert len(rows) == 1 and set(COLUMNS) <= set(rows[0])
    r = rows[0]
    assert float(r["laeq_db"]) == pytest.approx(L_1PA, abs=0.05)
    assert float(r["lzpeak_db"]) - float(r["lzeq_db"]) == pytest.approx(3.01, abs=0.02)
    assert float(r["sel_db"]) == pytest.approx(L_1PA + 10 * math.log10(1.5), abs=0.02)
    bands = _rows(tmp_path / "OUT_bands.csv")
    assert list(bands[0]) == ["channel", "band_hz", "leq_db", "lmax_db"]
    freqs = [float(b["band_hz"]) for b in bands]
    assert freqs[0] == 25.0 and freqs[-1] == 20000.0 and len(freqs) == 30
    assert float(bands[freqs.index(1000.0)]["leq_db"]) == pytest.approx(L_1PA, abs=0.1)


def test_without_sidecar_the_option_calibrates_and_each_channel_gets_a_row(tmp_path):
    wav = tmp_path / "two.wav"
    sf.write(wav, np.stack([_tone(), 0.1 * _tone(100.0)], axis=1) / 2.0, FS, subtype="FLOAT")
    out = tmp_path / "two.csv"
    assert main(["levels", str(wav), "--csv", str(out), "--pa-per-fs", "2", "--start", "0.5"]) == 0
    rows = _rows(out)
    assert [r["channel"] for r in rows] == ["1", "2"]
    assert float(rows[0]["lzeq_db"]) == pytest.approx(L_1PA, abs=0.01)
    assert float(rows[1]["laeq_db"]) - float(rows[1]["lzeq_db"]) == pytest.approx(-19.1, abs=0.1)
    assert len(_rows(tmp_path / "two_bands.csv")) == 2 * 30


def test_no_calibration_exits_2_naming_the_option(tmp_path, capsys):
    wav = tmp_path / "bare.wav"
    sf.write(wav, _tone(seconds=0.5) / 2, FS, subtype="FLOAT")
    assert main(["levels", str(wav), "--csv", str(tmp_path / "x.csv")]) == 2
    assert "--pa-per-fs" in capsys.readouterr().err
    assert not (tmp_path / "x.csv").exists()


@pytest.mark.parametrize("extra, option", [(["--pa-per-fs", "-1"], "--pa-per-fs"), (["--start", "9"], "--start"),
                                           (["--start", "0.3", "--stop", "0.2"], "--stop"),
                                           (["--stop", "7"], "--stop")])
def test_bad_options_exit_2_naming_the_option(tmp_path, capsys, extra, option):
    wav = tmp_path / "s.wav"
    sf.write(wav, _tone(seconds=0.5) / 2, FS, subtype="FLOAT")
    assert main(["levels", str(wav), "--csv", str(tmp_path / "x.csv"), "--pa-per-fs", "2", *extra]) == 2
    assert option in capsys.readouterr().err


def test_missing_file_exits_2(tmp_path, capsys):
    assert main(["levels", str(tmp_path / "none.wav"), "--csv", str(tmp_path / "x.csv"), "--pa-per-fs", "1"]) == 2
    assert "no such file" in capsys.readouterr().err


@pytest.mark.slow
def test_loudness_columns_when_asked(tmp_path):
    from acoustiviz.levels import loudness_available

    if not loudness_available():
        pytest.skip("mosqito (extra 'hearing') not installed")
    wav = tmp_path / "quiet.wav"
    sf.write(wav, _tone(seconds=0.6, rms=20e-6 * 10 ** (40 / 20)) / 0.01, FS, subtype="PCM_24")
    out = tmp_path / "q.csv"
    assert main(["levels", str(wav), "--csv", str(out), "--pa-per-fs", "0.01", "--start", "0.2", "--loudness"]) == 0
    row = _rows(out)[0]
    assert float(row["n5_sone"]) == pytest.approx(1.0, abs=0.05)  # 1 kHz at 40 dB: 1 sone
    assert float(row["sharpness_acum"]) > 0


@pytest.mark.parametrize("extra, csv_name, option", [
    (["--max-memory", "0.1"], "x.csv", "--max-memory"),  # 0.5 s at 48 kHz needs about 2 MB
    ([], "x.txt", "--csv"),
    ([], "adir", "--csv"),
])
def test_work_and_outputs_checked_before_reading_the_signal(tmp_path, capsys, extra, csv_name, option):
    wav = tmp_path / "s.wav"
    sf.write(wav, _tone(seconds=0.5) / 2, FS, subtype="FLOAT")
    (tmp_path / "adir").mkdir()
    assert main(["levels", str(wav), "--csv", str(tmp_path / csv_name), "--pa-per-fs", "2", *extra]) == 2
    err = capsys.readouterr().err
    assert option in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.csv").exists()


def test_a_file_that_is_not_sound_exits_2(tmp_path, capsys):
    bad = tmp_path / "bad.wav"
    bad.write_text("not a sound file\n")
    assert main(["levels", str(bad), "--csv", str(tmp_path / "x.csv"), "--pa-per-fs", "1"]) == 2
    assert "SIGNAL.wav" in capsys.readouterr().err


def test_a_silent_channel_writes_minus_inf_levels(tmp_path):
    """Silence has a level of -inf dB, written as ``-inf`` (as the operating-noise CSV writes it), not left empty."""
    wav = tmp_path / "SIGNAL.wav"
    stereo = np.stack([_tone(), np.zeros(2 * FS)], axis=1)
    sf.write(wav, stereo / 4.0, FS, subtype="FLOAT")
    out = tmp_path / "OUT.csv"
    assert main(["levels", str(wav), "--csv", str(out), "--pa-per-fs", "4"]) == 0
    loud, silent = _rows(out)
    assert float(loud["laeq_db"]) == pytest.approx(L_1PA, abs=0.1)
    assert [silent[c] for c in ("lzpeak_db", "lzeq_db", "sel_db")] == ["-inf"] * 3  # unweighted: exactly zero
    assert float(silent["lzeq_db"]) == -math.inf
