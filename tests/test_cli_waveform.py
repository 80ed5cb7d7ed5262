"""The ``acoustiviz waveform`` command: interface, CSV contents and error handling."""

import math
import subprocess
import sys

import numpy as np
import pytest

from acoustiviz.cli import main
from acoustiviz.core.radiation import pressure

FIG2 = ["--radius", "0.01905", "--velocity", "1.4", "--k-hertz", "5.6e8", "--density", "7800",
        "--distance", "0.7", "--angle", "45"]


def _read(path):
    with open(path) as fh:
        header = fh.readline().strip()
    return header, np.loadtxt(path, delimiter=",", skiprows=1)


def test_free_field_csv_matches_radiation_and_sampling(tmp_path, paper_impact, half_sine_pulse):
    out = tmp_path / "w.csv"
    png = tmp_path / "w.png"
    assert main(["waveform", *FIG2, "--config", "free", "--pulse", "half-sine", "--csv", str(out),
                 "--png", str(png)]) == 0
    header, data = _read(out)
    assert header == "time_s,pressure_pa"
    t, p = data[:, 0], data[:, 1]
    assert t[0] == 0.0 and np.all(np.diff(t) > 0)
    a = 0.01905
    imp = paper_impact
    # at least 200 samples per contact duration
    assert imp.duration / np.diff(t).max() >= 200
    # the listener is 0.7 m from the centre at 45 deg: compare with the radiation core directly
    ref = pressure(half_sine_pulse, t, 0.7, math.cos(math.pi / 4), radius=a)
    np.testing.assert_allclose(p, ref, rtol=1e-7, atol=1e-8 * np.abs(ref).max())
    # zero before arrival, and the whole click is inside the window
    assert np.all(p[t < (0.7 - a) / 343.2] == 0)
    assert abs(p[-1]) < 1e-9 * np.abs(p).max()
    assert png.stat().st_size > 10_000


def test_plane_is_m_shaped(tmp_path):
    out = tmp_path / "plane.csv"
    assert main(["waveform", *FIG2, "--config", "plane", "--csv", str(out)]) == 0
    _, data = _read(out)
    p = data[:, 1]
    big = np.abs(p) > 0.2 * np.abs(p).max()
    signs = np.sign(p[big])
    lobes = signs[np.r_[True, signs[1:] != signs[:-1]]]
    assert lobes.tolist() == [1, -1, 1]


def test_pulse_choice_changes_the_waveform(tmp_path):
    peaks = {}
    for kind in ("half-sine", "impulse-matched", "hertz"):
        out = tmp_path / f"{kind}.csv"
        assert main(["waveform", *FIG2, "--pulse", kind, "--csv", str(out)]) == 0
        peaks[kind] = np.abs(_read(out)[1][:, 1]).max()
    # the impulse-matched half-sine has 1/1.171 of the paper's amplitude
    assert peaks["impulse-matched"] / peaks["half-sine"] == pytest.approx(1 / 1.1711, rel=1e-3)
    assert peaks["hertz"] != pytest.approx(peaks["half-sine"], rel=1e-3)


@pytest.mark.slow
def test_material_options_replace_k_hertz(tmp_path):
    out = tmp_path / "m.csv"
    assert main(["waveform", "--material", "steel", "--surface", "glass", "--csv", str(out)]) == 0
    assert _read(out)[1].shape[1] == 2


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["--radius", "-0.01"], "--radius"),
        (["--velocity", "0"], "--velocity"),
        (["--distance", "0.01"], "--distance"),
        (["--material", "unobtainium"], "--material"),
        (["--config", "plane", "--angle", "120"], "--angle"),
        (["--config", "wall-floor", "--wall-distance", "0.001"], "--wall-distance"),
        (["--mass", "0.1", "--density", "7800"], "--mass"),
    ],
)
def test_bad_values_exit_2_naming_the_option(args, option, capsys, tmp_path):
    out = tmp_path / "never.csv"
    assert main(["waveform", *args, "--csv", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert option in err and "Traceback" not in err and len(err.splitlines()) == 1
    assert not out.exists()


@pytest.mark.slow
def test_console_script_has_no_traceback(tmp_path):
    res = subprocess.run([sys.executable, "-m", "acoustiviz", "waveform", "--radius", "-1"],
                         capture_output=True, text=True, cwd=tmp_path)
    assert res.returncode == 2
    assert "--radius" in res.stderr and "Traceback" not in res.stderr


def test_wall_strike_in_the_corner(tmp_path):
    # a sphere striking the wall of a corner, high above the floor: until the floor's echo arrives,
    # the field is that of a sphere on a single plane, seen from the same angle
    wall, plane = tmp_path / "wall.csv", tmp_path / "plane.csv"
    assert main(["waveform", "--config", "wall-floor", "--strike", "wall", "--height", "0.5", "--csv", str(wall)]) == 0
    assert main(["waveform", "--config", "plane", "--csv", str(plane)]) == 0
    w, p = _read(wall)[1], _read(plane)[1]
    n = min(len(w), len(p))
    np.testing.assert_allclose(w[:n, 0], p[:n, 0])
    t = w[:n, 0]
    # the floor image is 2 x 0.5 m below the wall pair: its sound arrives later than ~0.7 m / c
    early = t < 0.9 / 343.2
    np.testing.assert_allclose(w[:n][early, 1], p[:n][early, 1], atol=1e-9)
    assert np.any(np.abs(w[:n][~early, 1] - p[:n][~early, 1]) > 1e-3)


def test_strike_and_height_need_their_configuration(capsys):
    assert main(["waveform", "--config", "plane", "--strike", "wall"]) == 2
    assert "--strike" in capsys.readouterr().err
    assert main(["waveform", "--config", "wall-floor", "--strike", "wall", "--height", "0.001"]) == 2
    assert "--height" in capsys.readouterr().err


@pytest.mark.parametrize("config", ["free", "plane", "wall-floor"])
def test_printed_peaks_are_those_of_the_continuous_waveform(tmp_path, capsys, config):
    # the printed max/min are the peaks between the samples: against a dense evaluation (1e5
    # samples across the two samples around each extreme sample of the CSV), to 1e-8 relative
    from acoustiviz.app.impacts import impact_setup, observer_point
    from acoustiviz.field import time_series

    out = tmp_path / "w.csv"
    assert main(["waveform", *FIG2, "--config", config, "--pulse", "hertz", "--csv", str(out)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("pressure:"))
    words = line.replace(",", "").split()
    pmax, pmin = float(words[words.index("max") + 1]), float(words[words.index("min") + 1])
    t, p = _read(out)[1].T
    s = impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config=config, pulse="hertz")
    point = observer_point(s, 0.7, 45.0)
    dt = t[1] - t[0]
    for k, sign, printed in ((int(np.argmax(p)), 1.0, pmax), (int(np.argmin(p)), -1.0, pmin)):
        dense_t = np.linspace(t[k] - dt, t[k] + dt, 100_001)
        dense = time_series(s.pulse, dense_t, point[None, :], s.geometry, medium=s.medium)[0]
        ref = sign * np.max(sign * dense)
        assert sign * printed >= sign * p[k]  # never below the largest sample
        assert printed == pytest.approx(ref, rel=1e-8)
