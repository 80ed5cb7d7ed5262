"""Weighted levels of a design (LAFmax, LCpeak, LAeq over the run) and ranking the design query by any column."""

import math

import numpy as np
import pytest

from acoustiviz.cli import main
from acoustiviz.constants import ANALYSIS_RATE
from acoustiviz.core.medium import Medium
from acoustiviz.core.signal import Signal
from acoustiviz.dynamics import DamperModel, InitialState, simulate
from acoustiviz.errors import ParameterError
from acoustiviz.levels import metric_levels
from acoustiviz.levels.train import train_signal
from acoustiviz.sound import CavityScene, ClickModel, ImpactSequence, render
from acoustiviz.sweep import (
    PAPER_RADIUS,
    RANK_COLUMNS,
    Design,
    FixedSettings,
    SweepSpec,
    SweepTable,
    design,
    evaluate_design,
    listener_point,
    load_sweep,
)
from acoustiviz.sweep.evaluate import sound_setup
from acoustiviz.sweep.levels import SWEEP_LEVEL_COLUMNS, click_windows, design_levels
from acoustiviz.sweep.store import ALL_COLUMNS, NUMERIC_COLUMNS

DURATION = 1.5
#: The sweep's levels come from the clicks' closed-form spectra (acoustiviz.sweep.levels), whose
#: samples differ from the render's by about 2e-7 of the peak (what the render neglects: aliasing
#: from above its 1.5 MHz internal rate and past its 110 dB stop band, the tail after 1e-8), so the
#: levels differ from rendering and filtering every sample by about 1e-7 dB. 1e-5 dB is a hundred
#: times that, and a thousand times below the 0.01 dB that would show on a level meter's 0.1 dB
#: display or the 0.015 dB a 48 kHz rendering moves them (benchmarks/results/bench_levels.txt).
LEVELS_TOL_DB = 1e-5


@pytest.fixture(scope="module")
def plane_design():
    return Design(0, 0.04, 0.0405, 20.0, 5.6e8, "", 2.0, 0.7, math.pi / 4, "plane", PAPER_RADIUS)


@pytest.fixture(scope="module")
def with_levels(plane_design):
    return evaluate_design(plane_design, FixedSettings(duration=DURATION, levels=True))


def test_levels_equal_direct_calls_on_the_same_run(plane_design, with_levels):
    s, d = FixedSettings(duration=DURATION), plane_design
    model = DamperModel(M=s.M, K=s.K, C=s.C, m=d.m, gap=d.gap, k_hertz=d.k_hertz, c1=d.c1)
    run = simulate(model, DURATION, solver=s.solver, initial=InitialState(v=d.v0), rtol=s.rtol)
    assert len(run.impacts) == with_levels.n_impacts > 10
    scene = CavityScene("plane", d.radius, d.gap, walls="one", medium=Medium(c=s.c, rho=s.rho))
    point = listener_point(scene.geometry, d.distance, d.angle)
    clicks = ClickModel(k_hertz=d.k_hertz, mass=d.m, main_mass=s.M, mass_model="impact", pulse=s.pulse)
    p = render(ImpactSequence.from_table(run.impacts), scene, clicks, point, sample_rate=ANALYSIS_RATE,
               duration=DURATION).pressure
    row = with_levels.row()
    for column, metric in (("lafmax_db", "lafmax"), ("lcpeak_db", "lcpeak"), ("laeq_db", "laeq")):
        direct = metric_levels(Signal(p, ANALYSIS_RATE), metric, start=0.0, stop=DURATION)[0]
        assert row[column] == pytest.approx(direct, abs=LEVELS_TOL_DB), column
    # a second method: the unweighted peak of the rendered train is the loudest impact's peak SPL of
    # the field evaluator (band-limiting to 43 kHz changes the half-sine click's peak by < 0.1 dB)
    lzpeak = metric_levels(Signal(p, ANALYSIS_RATE), "lzpeak", start=0.0, stop=DURATION)[0]
    assert lzpeak == pytest.approx(with_levels.max_spl_db, abs=0.1)
    # orders every impact level must obey: an impulse's C-peak is within a few dB of its Z-peak, and
    # the A-weighted 125 ms average of 1 ms clicks lies far below their peak
    assert abs(row["lcpeak_db"] - lzpeak) < 3.0
    assert row["laeq_db"] < row["lafmax_db"] < row["lcpeak_db"] - 10


def test_levels_off_by_default_leave_nan(plane_design):
    r = evaluate_design(plane_design, FixedSettings(duration=0.3))
    assert all(math.isnan(r.row()[c]) for c in ("lafmax_db", "lcpeak_db", "laeq_db"))
    assert np.isfinite(r.max_spl_db)


def test_levels_setting_is_checked():
    with pytest.raises(ParameterError) as err:
        FixedSettings(levels="yes")
    assert err.value.name == "levels"


def _table(values):
    """A hand-made sweep table: four designs of one inclination, levels given per design."""
    spec = SweepSpec(gap=(0.02, 0.04), m=(0.02, 0.04), settings=FixedSettings(levels=True))
    n = len(values["max_spl_db"])
    cols = {}
    for c in ALL_COLUMNS:
        if c in values:
            cols[c] = np.asarray(values[c], dtype=float)
        elif c in ("material", "config", "error"):
            cols[c] = np.array(["plane" if c == "config" else ""] * n)
        elif c == "design_id":
            cols[c] = np.arange(n)
        else:
            cols[c] = np.full(n, 1.0)
    cols["inclination_two_maxima_m_s"] = np.full(n, 0.008)
    return SweepTable(spec, cols)


def test_ranking_by_each_level_column_picks_its_own_minimum():
    t = _table({"gap_m": [0.02, 0.02, 0.04, 0.04], "mass_kg": [0.02, 0.04, 0.02, 0.04],
                "max_spl_db": [100.0, 101.0, 102.0, 103.0], "lafmax_db": [80.0, 78.0, 79.0, 81.0],
                "lcpeak_db": [99.0, 98.5, 97.0, 99.5], "laeq_db": [70.0, 71.0, 72.0, 69.0]})
    expected = {"max_spl_db": (0, 3, 3.0), "lafmax_db": (1, 3, 3.0), "lcpeak_db": (2, 3, 2.5),
                "laeq_db": (3, 2, 3.0)}
    for key, (quiet, loud, saving) in expected.items():
        c = design(t, 0.008, 0.0005, rank_by=key)
        assert (c.quietest["design_id"], c.loudest["design_id"]) == (quiet, loud), key
        assert c.saving_db == pytest.approx(saving), key
        assert key in c.summary()


def test_rank_by_rejects_other_names_and_missing_levels():
    t = _table({"gap_m": [0.02, 0.04], "mass_kg": [0.02, 0.02], "max_spl_db": [100.0, 101.0],
                "lafmax_db": [math.nan, math.nan]})
    with pytest.raises(ParameterError) as err:
        design(t, 0.008, 0.001, rank_by="material")
    assert err.value.name == "rank_by" and "lafmax_db" in err.value.detail and "laeq_db" in err.value.detail
    with pytest.raises(ParameterError) as err:
        design(t, 0.008, 0.001, rank_by="lafmax_db")
    assert err.value.name == "rank_by" and "--levels" in err.value.detail
    assert "design_id" not in RANK_COLUMNS and set(RANK_COLUMNS) < set(NUMERIC_COLUMNS)


@pytest.mark.slow
def test_cli_sweep_levels_and_design_rank_by(tmp_path, capsys):
    out = tmp_path / "s"
    assert main(["sweep", "--gap", "0.03,0.05", "--m", "0.0405", "--duration", "0.6", "--workers", "1", "--quiet",
                 "--levels", "--out", str(out)]) == 0
    t = load_sweep(out)
    assert np.all(np.isfinite(t["lafmax_db"])) and np.all(np.isfinite(t["laeq_db"]))
    e = float(np.mean(t["inclination_two_maxima_m_s"]))
    capsys.readouterr()
    assert main(["design", "--sweep", str(out), "--inclination", repr(e), "--tolerance", "1", "--rank-by",
                 "laeq_db"]) == 0
    text = capsys.readouterr().out
    quiet = int(np.argmin(t["laeq_db"]))
    assert f"d = {t['gap_m'][quiet]:.6g} m" in text.splitlines()[1] and "ranked by laeq_db" in text
    assert main(["design", "--sweep", str(out), "--inclination", "0.008", "--rank-by", "loudness"]) == 2
    err = capsys.readouterr().err
    assert "--rank-by" in err and "lafmax_db" in err and "lcpeak_db" in err


def test_design_table_gives_the_range_of_each_level_in_a_band(tmp_path):
    from acoustiviz.sweep import design_table, write_design_table

    t = _table({"gap_m": [0.02, 0.02, 0.04], "mass_kg": [0.02, 0.04, 0.02], "max_spl_db": [100.0, 101.0, 102.0],
                "lafmax_db": [80.0, 78.0, 79.0], "lcpeak_db": [99.0, 98.5, 97.0], "laeq_db": [70.0, 71.0, 72.0]})
    (band,) = design_table(t)
    assert band.level_ranges == {"lafmax_db": (78.0, 80.0), "lcpeak_db": (97.0, 99.0), "laeq_db": (70.0, 72.0)}
    lines = write_design_table([band], tmp_path / "d.csv").read_text().splitlines()
    row = dict(zip(lines[0].split(","), lines[1].split(","), strict=True))
    assert float(row["min_lafmax_db"]) == 78.0 and float(row["max_laeq_db"]) == 72.0


def _run_and_scene(gap, m, config="plane", pulse="half-sine", pulse_mass="impact", duration=DURATION):
    s = FixedSettings(duration=duration, pulse=pulse, pulse_mass=pulse_mass)
    d = Design(0, gap, m, 20.0, 5.6e8, "", 2.0, 0.7, math.pi / 4, config, PAPER_RADIUS)
    model = DamperModel(M=s.M, K=s.K, C=s.C, m=d.m, gap=d.gap, k_hertz=d.k_hertz, c1=d.c1)
    run = simulate(model, duration, solver=s.solver, initial=InitialState(v=d.v0), rtol=s.rtol)
    scene, clicks = sound_setup(d, s, Medium(c=s.c, rho=s.rho))
    return run, scene, clicks, listener_point(scene.geometry, d.distance, d.angle)


@pytest.mark.parametrize(("config", "pulse", "pulse_mass"), [
    ("plane", "half-sine", "impact"), ("free", "impulse-matched", "impact"),
    ("wall-floor", "half-sine", "effective"), ("plane", "hertz", "impact"),
])
def test_click_windows_add_up_to_the_rendered_train(config, pulse, pulse_mass):
    run, scene, clicks, point = _run_and_scene(0.03, 0.03, config, pulse, pulse_mass, duration=0.4)
    starts, windows = click_windows(run.impacts, scene=scene, model=clicks, point=point)
    n = int(round(0.4 * ANALYSIS_RATE))
    ref = render(ImpactSequence.from_table(run.impacts), scene, clicks, point, sample_rate=ANALYSIS_RATE,
                 duration=0.4).pressure[0, :n]
    assert len(run.impacts) > 5
    np.testing.assert_allclose(train_signal(starts, windows, n), ref, rtol=0, atol=1e-6 * np.max(np.abs(ref)))


@pytest.mark.parametrize(("gap", "m", "config"), [(0.02, 0.02, "plane"), (0.06, 0.08, "plane"),
                                                 (0.04, 0.0405, "free"), (0.03, 0.06, "wall-floor")])
def test_sparse_levels_equal_rendering_and_filtering_every_sample(gap, m, config):
    run, scene, clicks, point = _run_and_scene(gap, m, config, duration=3.0)
    kw = {"scene": scene, "model": clicks, "point": point, "duration": 3.0}
    sparse, dense = design_levels(run.impacts, **kw), design_levels(run.impacts, method="dense", **kw)
    assert set(sparse) == set(SWEEP_LEVEL_COLUMNS)
    for c in SWEEP_LEVEL_COLUMNS:
        assert np.isfinite(dense[c]) and sparse[c] == pytest.approx(dense[c], abs=LEVELS_TOL_DB), c


def test_design_levels_checks_its_method_and_hears_silence():
    run, scene, clicks, point = _run_and_scene(0.04, 0.0405, duration=0.1)
    kw = {"scene": scene, "model": clicks, "point": point, "duration": 0.1}
    with pytest.raises(ParameterError) as err:
        design_levels(run.impacts, method="fast", **kw)
    assert err.value.name == "method"
    assert design_levels(ImpactSequence([], [], []), **kw) == dict.fromkeys(SWEEP_LEVEL_COLUMNS, -math.inf)


@pytest.mark.parametrize(("pulse", "mass_model"), [("half-sine", "impact"), ("impulse-matched", "effective"),
                                                   ("hertz", "impact")])
def test_pulse_spectra_of_a_run_are_each_pulses_transform(pulse, mass_model):
    from acoustiviz.levels.energy import pulse_spectrum
    from acoustiviz.sweep.levels import _pulse_spectra, _pulses

    clicks = ClickModel(mass=0.02, mass_model=mass_model, pulse=pulse)
    v = np.array([0.05, 0.3, 1.0, 2.5])
    amp, tau = _pulses(clicks, v)
    omega = 2 * np.pi * ANALYSIS_RATE / 360 * np.arange(181)
    ref = np.stack([pulse_spectrum(clicks.pulse_for(x), omega) for x in v])
    got = _pulse_spectra(clicks, v, amp, tau, omega)
    assert np.max(np.abs(got - ref)) <= 1e-12 * np.max(np.abs(ref))
