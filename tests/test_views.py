"""Weighted levels per observer point: the fast path against the full 1 s computation, and the samples behind it."""

import numpy as np
import pytest

from acoustiviz.app.impacts import impact_setup, observer_point
from acoustiviz.app.views import balloon_levels, directivity_angles, directivity_metric, point_levels
from acoustiviz.errors import ParameterError
from acoustiviz.field import directivity
from acoustiviz.levels import METRICS
from acoustiviz.sound.impact_levels import impact_signals, impact_sound, points_metric_levels, reference_metric_levels

ALL = list(METRICS)
TOL_DB = 0.01


def _setup(config, pulse):
    return impact_setup(radius=0.01905, velocity=1.4, k_hertz=5.6e8, density=7800.0, config=config, pulse=pulse)


def _assert_levels_close(new, ref, tol=TOL_DB):
    for m in ref:
        np.testing.assert_allclose(new[m], ref[m], rtol=0, atol=tol, err_msg=m)


@pytest.mark.parametrize("pulse", ["half-sine", "hertz"])
@pytest.mark.parametrize("config", ["free", "plane", "wall-floor"])
@pytest.mark.slow
def test_every_metric_matches_the_full_interval(config, pulse):
    s = _setup(config, pulse)
    # on axis, oblique, grazing, very near the sphere (2 mm off its surface) and far (late arrival)
    pts = np.array([observer_point(s, d, a) for d, a in ((0.7, 0.0), (0.7, 45.0), (0.7, 88.0), (0.0211, 30.0),
                                                         (4.0, 60.0))])
    new = points_metric_levels(ALL, s.pulse, pts, s.geometry, s.medium)
    ref = reference_metric_levels(ALL, s.pulse, pts, s.geometry, s.medium)
    _assert_levels_close(new, ref)
    assert np.all(np.isfinite(ref["laeq"][:4])) and ref["laeq"][3] > ref["laeq"][1] + 20  # the near point is loud


def test_the_sound_is_the_start_of_the_full_signal():
    s = _setup("wall-floor", "hertz")
    pts = np.array([observer_point(s, d, a) for d, a in ((0.3, 20.0), (1.5, 70.0))])
    full = impact_signals(s.pulse, pts, s.geometry, s.medium)
    sound, n = impact_sound(s.pulse, pts, s.geometry, s.medium)
    assert n == full.shape[1] and sound.shape[1] < n // 10
    assert np.max(np.abs(sound - full[:, :sound.shape[1]])) <= 1e-12 * np.max(np.abs(full))
    assert not np.any(full[:, sound.shape[1]:])


@pytest.mark.slow
def test_a_late_point_keeps_the_time_grid_of_its_chunk():
    s = _setup("plane", "half-sine")
    pts = np.array([observer_point(s, d, 40.0) for d in (0.2, 0.25, 6.0, 0.7)])
    for chunk in (None, 2, 3):
        new = points_metric_levels(["lcpeak", "lafmax", "sel-a"], s.pulse, pts, s.geometry, s.medium, chunk=chunk)
        ref = reference_metric_levels(["lcpeak", "lafmax", "sel-a"], s.pulse, pts, s.geometry, s.medium,
                                      chunk=chunk)
        _assert_levels_close(new, ref)
    # 30 times farther: the far-field level falls by about 20 log10(30) = 29.5 dB
    assert 27.0 < new["sel-a"][1] - new["sel-a"][2] < 32.0


@pytest.mark.parametrize("metric", ["lcpeak", "lasmax", "laeq"])
@pytest.mark.slow
def test_directivity_metric_matches_the_full_interval(metric):
    s = _setup("free", "half-sine")
    d = directivity(s.pulse, s.geometry, 0.7, directivity_angles(s.geometry, 30.0), medium=s.medium)
    got = directivity_metric(d, metric, s.pulse, s.geometry, s.medium)
    ref = reference_metric_levels([metric], s.pulse, d.points, s.geometry, s.medium)[metric]
    np.testing.assert_allclose(got[:3], ref[:3], rtol=0, atol=TOL_DB)
    assert got[0] > got[2] + 5.0  # a dipole: loudest on its axis
    # the null at 90 degrees holds no sound in either computation
    assert got[3] < got[0] - 100.0 and ref[3] < ref[0] - 100.0


def test_balloon_and_point_levels_use_the_same_levels():
    s = _setup("wall-floor", "half-sine")
    assert balloon_levels("peak", s.pulse, s.geometry, s.medium) is None
    function, label = balloon_levels("sel-a", s.pulse, s.geometry, s.medium)
    assert label.startswith("SEL(A)")
    pts = np.array([observer_point(s, 0.7, a) for a in (0.0, 30.0, 60.0)])
    ref = reference_metric_levels(["sel-a"], s.pulse, pts, s.geometry, s.medium, chunk=2)["sel-a"]
    np.testing.assert_allclose(function(pts), ref, rtol=0, atol=TOL_DB)
    f2, _ = point_levels("sel-a", s.pulse, s.geometry, s.medium, chunk=2)
    np.testing.assert_allclose(f2(pts), ref, rtol=0, atol=TOL_DB)


def test_bad_metrics_are_refused_before_any_work():
    s = _setup("free", "half-sine")
    with pytest.raises(ParameterError, match="metric"):
        points_metric_levels(["lafmax", "loud"], s.pulse, np.ones((1, 3)), s.geometry, s.medium)
    with pytest.raises(ParameterError, match="metric"):
        reference_metric_levels("loud", s.pulse, np.ones((1, 3)), s.geometry, s.medium)
