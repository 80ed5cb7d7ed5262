"""The ``acoustiviz directivity`` command."""

import csv

import numpy as np
import pytest

from acoustiviz.cli import main
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import sphere_pressure
from acoustiviz.core.signal import Signal

A = 0.01905
ARGS = [
    "directivity",
    "--radius",
    "0.01905",
    "--velocity",
    "1.4",
    "--k-hertz",
    "5.6e8",
    "--density",
    "7800",
    "--distance",
    "0.7",
]


def _read(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], dtype=float)


@pytest.mark.slow
def test_plane_directivity_csv_and_png(tmp_path, plane_geometry, paper_pulse):
    out, png = tmp_path / "d.csv", tmp_path / "d.png"
    assert main([*ARGS, "--config", "plane", "--step", "5", "--csv", str(out), "--png", str(png)]) == 0
    header, data = _read(out)
    assert header == ["angle_deg", "peak_pa", "rms_pa", "spl_db"]
    np.testing.assert_allclose(data[:, 0], np.arange(0, 91, 5))
    np.testing.assert_allclose(data[:, 3], 20 * np.log10(data[:, 1] / 20e-6), atol=1e-5)
    assert png.stat().st_size > 10_000
    # independent reference at 45 deg: a fine direct sum of the two spheres of eq 14
    cfg = plane_geometry
    pulse = paper_pulse()
    th = np.pi / 4
    obs = cfg.centre + 0.7 * np.array([np.sin(th), 0, np.cos(th)])
    t1 = (0.7 - A) / AIR.c
    dt = 1e-7
    t = np.arange(t1, t1 + 4e-3, dt)
    p = sum(sphere_pressure(pulse, t, obs, radius=A, centre=s.position, axis=s.axis) for s in cfg.sources)[0]
    row = data[9]
    assert row[1] == pytest.approx(np.max(np.abs(p)), rel=1e-3)
    # RMS window: tau + largest arrival spread on the circle (2a/c, on the axis) + 10 a/c
    window = pulse.duration + 2 * A / AIR.c + 10 * A / AIR.c
    assert row[2] == pytest.approx(np.sqrt(np.sum(p**2) * dt / window), rel=2e-3)
    # a dipole above a rigid plane: loudest along the normal, quietest along the plane
    assert data[0, 1] == data[:, 1].max() and data[-1, 1] < 0.1 * data[0, 1]


def test_wall_floor_and_free(tmp_path, capsys):
    out = tmp_path / "w.csv"
    assert main([*ARGS, "--config", "wall-floor", "--wall-distance", "0.05", "--step", "15", "--csv", str(out)]) == 0
    _, data = _read(out)
    np.testing.assert_allclose(data[:, 0], np.arange(0, 91, 15))
    assert np.all(np.isfinite(data)) and np.all(data[:, 1] > 0)
    assert main([*ARGS, "--config", "free", "--step", "45"]) == 0
    text = capsys.readouterr().out
    assert "180.00" in text


@pytest.mark.parametrize(
    "extra, option",
    [
        (["--step", "0"], "--step"),
        (["--step", "120"], "--step"),
        (["--distance", "0.01"], "--distance"),
        (["--radius", "-1"], "--radius"),
    ],
)
def test_bad_options_exit_2_naming_the_option(extra, option, capsys):
    args = [a for a in ARGS]
    if "--distance" in extra:
        i = args.index("--distance")
        del args[i : i + 2]
    if "--radius" in extra:
        i = args.index("--radius")
        del args[i : i + 2]
    assert main([*args, "--config", "plane", *extra]) == 2
    err = capsys.readouterr().err
    assert option in err and len(err.strip().splitlines()) == 1


def test_weighted_metric_columns_lcpeak_near_peak_and_one_angle_checked_directly(tmp_path, plane_geometry, paper_pulse):
    """``--metric lcpeak`` and ``laeq``: C-peak within the C-weighting effect of the peak SPL; one
    angle recomputed from an independent fine direct sum, band-limited by another filter."""
    from scipy.signal import resample_poly

    from acoustiviz.levels import metric_levels

    out = tmp_path / "d.csv"
    assert main([*ARGS, "--config", "plane", "--step", "15", "--metric", "lcpeak", "--csv", str(out)]) == 0
    header, data = _read(out)
    assert header == ["angle_deg", "peak_pa", "rms_pa", "spl_db", "lcpeak_db"]
    # the click's energy lies around 1-3 kHz, where C-weighting is within 0.3 dB of flat; its
    # low- and high-frequency parts are cut by at most a few dB, never raised by more than 0.1 dB
    diff = data[:, 4] - data[:, 3]
    assert np.all(diff < 0.1) and np.all(diff > -2.0)
    # independent reference at 45 deg: both spheres of eq 14 summed directly at 1/(16 x 96 kHz),
    # decimated by scipy's polyphase filter, then the levels called directly
    cfg = plane_geometry
    pulse = paper_pulse()
    th = np.pi / 4
    obs = cfg.centre + 0.7 * np.array([np.sin(th), 0, np.cos(th)])
    fs, up = 96000, 16
    t = np.arange(0, 0.02 * fs * up) / (fs * up)
    p = sum(sphere_pressure(pulse, t, obs, radius=A, centre=s.position, axis=s.axis) for s in cfg.sources)[0]
    low = resample_poly(p, 1, up, window=("kaiser", 12.0))
    low = np.concatenate([low, np.zeros(fs - low.size)])  # 1 s, as the command's LAeq interval
    assert data[3, 0] == 45.0
    assert data[3, 4] == pytest.approx(metric_levels(Signal(low, fs), "lcpeak")[0], abs=0.05)
    out2 = tmp_path / "e.csv"
    assert main([*ARGS, "--config", "plane", "--step", "15", "--metric", "laeq", "--csv", str(out2)]) == 0
    header2, data2 = _read(out2)
    assert header2[-1] == "laeq_db"
    assert data2[3, 4] == pytest.approx(metric_levels(Signal(low, fs), "laeq")[0], abs=0.05)


def test_rms_and_sel_a_metrics_and_bad_metric(tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main([*ARGS, "--config", "free", "--step", "30", "--metric", "rms", "--csv", str(out)]) == 0
    header, data = _read(out)
    assert header[-1] == "rms_db"
    np.testing.assert_allclose(data[:, 4], 20 * np.log10(data[:, 2] / 20e-6), atol=1e-5)
    out2, png = tmp_path / "s.csv", tmp_path / "s.png"
    assert main([*ARGS, "--config", "free", "--step", "30", "--metric", "sel-a", "--csv", str(out2),
                 "--png", str(png)]) == 0
    _, data2 = _read(out2)
    assert png.stat().st_size > 10_000
    # one impact: SEL(A) (re 1 s) equals LAeq over the command's stated 1 s interval
    out3 = tmp_path / "q.csv"
    assert main([*ARGS, "--config", "free", "--step", "30", "--metric", "laeq", "--csv", str(out3)]) == 0
    _, data3 = _read(out3)
    np.testing.assert_allclose(data2[:, 4], data3[:, 4], atol=1e-6)
    assert np.all(data2[:, 4] < data2[:, 3] - 20)  # a ms-long click's 1 s average lies far below its peak
    capsys.readouterr()
    assert main([*ARGS, "--metric", "loudness"]) == 2
    err = capsys.readouterr().err
    assert "--metric" in err and "lcpeak" in err and "sel-a" in err
