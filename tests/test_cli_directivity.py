"""The ``acoustiviz directivity`` command."""

import csv

import numpy as np
import pytest

from acoustiviz.cli import main
from acoustiviz.core.contact import Impact, acceleration_pulse
from acoustiviz.core.images import images_plane
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import sphere_pressure

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


def test_plane_directivity_csv_and_png(tmp_path):
    out, png = tmp_path / "d.csv", tmp_path / "d.png"
    assert main([*ARGS, "--config", "plane", "--step", "5", "--csv", str(out), "--png", str(png)]) == 0
    header, data = _read(out)
    assert header == ["angle_deg", "peak_pa", "rms_pa", "spl_db"]
    np.testing.assert_allclose(data[:, 0], np.arange(0, 91, 5))
    np.testing.assert_allclose(data[:, 3], 20 * np.log10(data[:, 1] / 20e-6), atol=1e-5)
    assert png.stat().st_size > 10_000
    # independent reference at 45 deg: a fine direct sum of the two spheres of eq 14
    cfg = images_plane(A)
    pulse = acceleration_pulse(Impact(velocity=1.4, k_hertz=5.6e8, mass=7800 * 4 / 3 * np.pi * A**3))
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
