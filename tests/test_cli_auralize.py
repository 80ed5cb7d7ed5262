"""The ``acoustiviz auralize`` command: files, sidecars, levels against the field evaluator, errors."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
import soundfile as sf

from acoustiviz.cli import main
from acoustiviz.core.contact import Impact, acceleration_pulse

try:
    from acoustiviz.field import time_series
except ImportError:  # pragma: no cover
    time_series = None

A = 0.01905
LISTENER = "0.495,0,0.514"


def _one_impact_csv(path, t=0.01, wall=-1, speed=1.4):
    path.write_text("time_s,wall,approach_velocity_m_s,separation_velocity_m_s,restitution,duration_s,"
                    f"peak_force_n\n{t},{wall},{speed},1.0,0.7,3e-4,1000\n")
    return path


def test_interface_writes_wav_and_sidecar(tmp_path, capsys, table1_model):
    from acoustiviz.dynamics import InitialState, simulate

    wav = tmp_path / "OUT.wav"
    assert main(["auralize", "--M", "0.5", "--K", "500", "--C", "0.05", "--m", "0.0405", "--gap", "0.04",
                 "--k-hertz", "5.6e8", "--c1", "20", "--v0", "2", "--duration", "2", "--solver", "event",
                 "--config", "plane", "--listener", LISTENER, "--rate", "48000", "--wav", str(wav)]) == 0
    out = capsys.readouterr().out
    data, fs = sf.read(wav, dtype="float64")
    info = sf.info(str(wav))
    rec = json.loads((tmp_path / "OUT.json").read_text())
    n_ref = len(simulate(table1_model, 2.0, initial=InitialState(v=2.0)).impacts)
    assert fs == 48000 and info.subtype == "PCM_24" and info.channels == 1 and data.size >= 2 * 48000
    assert rec["impact_count"] == n_ref > 10
    # a file that plays: every sample within [-1, 1], the peak 1 dB below full scale, the calibration recorded
    assert np.max(np.abs(data)) <= 10 ** (-1 / 20) + 2**-23
    assert 20 * math.log10(np.max(np.abs(data))) == pytest.approx(-1.0, abs=1e-3)
    assert rec["subtype"] == "PCM_24" and rec["sample_rate_hz"] == 48000 and rec["peak_dbfs"][0] == pytest.approx(-1.0)
    data = data * rec["scale_pa_per_full_scale"]  # back to pascals
    assert rec["listeners_m"] == [[0.495, 0.0, 0.514]] and rec["scene"]["config"] == "plane"
    assert rec["click_model"]["pulse"] == "half-sine" and rec["damper"]["solver"] == "event"
    peak_spl = 20 * math.log10(np.max(np.abs(data)) / 20e-6)
    assert rec["peak_spl_db_re_20upa"][0] == pytest.approx(peak_spl, abs=1e-4)
    assert f"impacts: {n_ref}" in out and f"peak SPL: {peak_spl:.1f} dB" in out
    assert str(wav) in out and str(tmp_path / "OUT.json") in out


def test_one_click_level_matches_the_field_evaluator(tmp_path, plane_geometry):
    """A single impact read from CSV, at 96 kHz: peak within 0.5 % and RMS within 1e-4 of the evaluator.

    (Half a sample at 96 kHz moves the sampled peak by < 0.5 %; the energy above 43 kHz is < 1e-7.)
    """
    csv = _one_impact_csv(tmp_path / "one.csv")
    wav = tmp_path / "one.wav"
    assert main(["auralize", "--impacts", str(csv), "--m", "0.0405", "--duration", "0.05", "--rate", "96000",
                 "--listener", LISTENER, "--subtype", "FLOAT", "--wav", str(wav)]) == 0
    assert sf.info(str(wav)).subtype == "FLOAT"  # the explicit option: float32 in pascals
    data, fs = sf.read(wav, dtype="float64")
    pulse = acceleration_pulse(Impact(1.4, 5.6e8, 0.0405), "half-sine")
    t = np.arange(0, 0.01, 1 / (64 * fs))
    pt = np.array([[0.495, 0.0, 0.514]])
    if time_series is not None:
        ref = time_series(pulse, t, pt, plane_geometry)[0]
    else:  # pragma: no cover
        from acoustiviz.core.radiation import sphere_pressure

        ref = sum(sphere_pressure(pulse, t, pt, radius=A, centre=s.position, axis=s.axis)[0]
                  for s in plane_geometry.sources)
    assert np.max(np.abs(data)) == pytest.approx(np.max(np.abs(ref)), rel=5e-3)
    assert math.sqrt(np.sum(data**2) / fs) == pytest.approx(math.sqrt(np.sum(ref**2) / (64 * fs)), rel=1e-4)


def test_levels_of_one_click_are_its_exposure_and_read_back_from_the_file(tmp_path, capsys, plane_geometry):
    """SEL of one click against the field evaluator's integral of p²; `acoustiviz levels` on the PCM file agrees."""
    csv = _one_impact_csv(tmp_path / "one.csv")
    wav = tmp_path / "lv.wav"
    assert main(["auralize", "--impacts", str(csv), "--duration", "0.3", "--listener", LISTENER, "--levels",
                 "--levels-csv", str(tmp_path / "lv_levels.csv"), "--wav", str(wav)]) == 0
    out = capsys.readouterr().out
    assert "evaluated at 96 kHz" in out and "LAFmax" in out
    rec = json.loads((tmp_path / "lv.json").read_text())
    row = rec["levels"]["channels"][0]
    assert rec["levels"]["evaluated_at_hz"] == 96000
    pulse = acceleration_pulse(Impact(1.4, 5.6e8, 0.0405), "half-sine")
    fine = 64 * 96000
    t = np.arange(0, 0.01, 1 / fine)
    pt = np.array([[0.495, 0.0, 0.514]])
    from acoustiviz.core.radiation import sphere_pressure

    ref = sum(sphere_pressure(pulse, t, pt, radius=A, centre=s.position, axis=s.axis)[0]
              for s in plane_geometry.sources)
    assert row["sel_db"] == pytest.approx(10 * math.log10(np.sum(ref**2) / fine / 20e-6**2), abs=0.01)
    assert row["lzpeak_db"] == pytest.approx(20 * math.log10(np.max(np.abs(ref)) / 20e-6), abs=0.05)
    assert row["lcpeak_db"] < row["lzpeak_db"] and row["lafmax_db"] < row["lcpeak_db"]
    assert (tmp_path / "lv_levels.csv").exists() and (tmp_path / "lv_levels_bands.csv").exists()
    # the file at 48 kHz, calibrated by its sidecar, gives the same exposure
    assert main(["levels", str(wav), "--csv", str(tmp_path / "back.csv")]) == 0
    back = (tmp_path / "back.csv").read_text().splitlines()
    cols = dict(zip(back[0].split(","), back[1].split(","), strict=True))
    assert float(cols["sel_db"]) == pytest.approx(row["sel_db"], abs=0.01)
    assert float(cols["sel_a_db"]) == pytest.approx(row["sel_a_db"], abs=0.05)


def test_several_listeners_share_one_pcm_scale(tmp_path, capsys):
    csv = tmp_path / "two.csv"
    csv.write_text("time_s,wall,approach_velocity_m_s\n0.01,-1,1.4\n0.03,1,0.8\n")
    wav = tmp_path / "run.wav"
    assert main(["auralize", "--impacts", str(csv), "--duration", "0.05", "--listener", LISTENER,
                 "--listener", "0.2,0.3,0.6", "--subtype", "PCM_24", "--wav", str(wav)]) == 0
    out = capsys.readouterr().out
    recs = [json.loads((tmp_path / f"run-{i}.json").read_text()) for i in (1, 2)]
    assert not wav.exists() and "run-1.wav" in out and "run-2.wav" in out
    scales = {r["scale_pa_per_full_scale"] for r in recs}
    assert len(scales) == 1
    scale = scales.pop()
    peaks = []
    for i, rec in zip((1, 2), recs, strict=True):
        data, _ = sf.read(tmp_path / f"run-{i}.wav", dtype="float64")
        assert sf.info(str(tmp_path / f"run-{i}.wav")).subtype == "PCM_24" and rec["subtype"] == "PCM_24"
        assert np.max(np.abs(data)) * scale == pytest.approx(rec["peak_pa"][0], rel=1e-5)
        assert rec["impact_count"] == 2 and rec["impact_count_by_wall"] == {"-1": 1, "+1": 1}
        assert rec["listeners"] == [f"listener{i}"]  # each file names the --listener it was rendered at
        peaks.append(rec["peak_pa"][0])
    assert scale == pytest.approx(max(peaks) * 10 ** (1 / 20))  # 1 dB headroom on the run's peak


def test_stereo_from_one_head_position_and_from_two_microphones(tmp_path):
    csv = _one_impact_csv(tmp_path / "one.csv")
    wav = tmp_path / "st.wav"
    assert main(["auralize", "--impacts", str(csv), "--duration", "0.05", "--listener", "0.3,0.2,0.4",
                 "--stereo", "--wav", str(wav)]) == 0
    data, _ = sf.read(wav)
    rec = json.loads((tmp_path / "st.json").read_text())
    assert data.shape[1] == 2 and rec["channel_names"] == ["left", "right"]
    ears = np.array(rec["listeners_m"])
    assert np.linalg.norm(ears[0] - ears[1]) == pytest.approx(0.18)
    # facing the damper, both ears are equally far from the contact point: a centred image
    assert np.linalg.norm(ears[0]) == pytest.approx(np.linalg.norm(ears[1]), rel=1e-12)
    # two microphones: the one nearer the damper hears the click first and louder
    wav2 = tmp_path / "mics.wav"
    assert main(["auralize", "--impacts", str(csv), "--duration", "0.05", "--listener", "0.3,0.2,0.4",
                 "--listener", "0.6,0.4,0.8", "--stereo", "--wav", str(wav2)]) == 0
    data, fs = sf.read(wav2)
    onset = [int(np.argmax(np.abs(data[:, c]) > 0.01 * np.abs(data).max())) for c in (0, 1)]
    delay = (np.linalg.norm([0.6, 0.4, 0.8 - A]) - np.linalg.norm([0.3, 0.2, 0.4 - A])) / 343.2
    assert onset[1] - onset[0] == pytest.approx(delay * fs, abs=2)
    assert np.abs(data[:, 0]).max() > 1.8 * np.abs(data[:, 1]).max()


@pytest.mark.parametrize(
    "extra, option",
    [(["--listener", "0.4,0,-0.1"], "--listener"),  # below the floor
     (["--listener", "0,0,0.01"], "--listener"),  # inside the sphere
     (["--listener", "0,0,0.04"], "--listener"),  # inside the cavity
     (["--listener", "0.4,0"], "--listener"),
     (["--config", "wall-floor", "--listener", "-0.2,0,0.3"], "--listener"),  # behind the wall
     (["--stereo", "--listener", "1,0,1", "--listener", "1,1,1", "--listener", "1,2,1"], "--stereo"),
     (["--m", "-1"], "--m"),
     (["--gap", "0"], "--gap"),
     (["--density", "7800", "--radius", "0.01"], "--radius"),
     (["--wall-distance", "0.1"], "--wall-distance")],
)
def test_bad_options_exit_2_naming_the_option(tmp_path, capsys, extra, option):
    code = main(["auralize", "--duration", "0.5", *extra, "--wav", str(tmp_path / "x.wav")])
    err = capsys.readouterr().err
    assert code == 2 and f"error: {option}:" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.wav").exists()


@pytest.mark.slow
def test_console_script_runs(tmp_path):
    csv = _one_impact_csv(tmp_path / "one.csv")
    res = subprocess.run([sys.executable, "-m", "acoustiviz", "auralize", "--impacts", str(csv), "--duration",
                          "0.05", "--wav", str(tmp_path / "c.wav")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert "impacts: 1" in res.stdout and (tmp_path / "c.json").exists()


def test_two_processes_write_the_same_float_wav_of_two_balls(tmp_path):
    """The float WAV of a two-ball run is the same file from two processes of different hash seeds.

    The processes run one after the other (the second starts when the first has written its file), so
    nothing that changes from one moment, or one process, to the next may reach the file's bytes.
    """
    import os
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    argv = ["auralize", "--balls", "2", "--duration", "0.3", "--listener", LISTENER, "--subtype", "FLOAT"]
    files = []
    for seed in ("1", "2"):
        env = {**os.environ, "PYTHONPATH": str(root), "PYTHONHASHSEED": seed, "MPLBACKEND": "Agg"}
        wav = tmp_path / f"seed{seed}.wav"
        res = subprocess.run([sys.executable, "-m", "acoustiviz", *argv, "--wav", str(wav)], env=env, cwd=tmp_path,
                             capture_output=True, text=True, timeout=600)
        assert res.returncode == 0, res.stderr
        files.append(wav.read_bytes())
    assert sf.info(str(tmp_path / "seed1.wav")).subtype == "FLOAT"
    assert files[0] == files[1]
