"""The pressure of a run's clicks at one instant: the sum of each click's field, the one-impact evaluator's."""

from __future__ import annotations

import numpy as np

from acoustiviz.core.geometry import images_plane
from acoustiviz.field.evaluate import snapshots
from acoustiviz.sound import ClickModel, ImpactSequence
from acoustiviz.sound.snapshot import snapshot_pressure
from acoustiviz.sound.sources import CavityScene

#: Points above the plane in m, around the paper's 19.05 mm sphere.
POINTS = np.array([[0.0, 0.0, 0.3], [0.2, 0.0, 0.1], [-0.25, 0.1, 0.05], [0.05, -0.3, 0.4]])


def test_the_snapshot_is_the_sum_of_each_clicks_field():
    """Three overlapping clicks on the struck wall: each one's field at t - t_k by field.evaluate.snapshots, summed."""
    scene, click = CavityScene("plane"), ClickModel()
    seq = ImpactSequence([0.0, 3e-4, 8e-4], [-1, -1, -1], [1.4, 0.7, 2.0])
    geometry = images_plane(scene.radius)
    for t in (6e-4, 1.2e-3, 1.6e-3, 2.4e-3):
        mine = snapshot_pressure(t, seq, scene, click, POINTS)
        expected = sum(snapshots(click.pulse_for(v), [t - tk], POINTS, geometry)[0]
                       for tk, v in zip(seq.times, seq.velocities, strict=True) if tk <= t)
        np.testing.assert_allclose(mine, expected, rtol=1e-9, atol=1e-12 * np.max(np.abs(expected)))
        assert np.max(np.abs(mine)) > 0 or t < 6e-4


def test_silence_before_the_first_arrival_and_after_the_last_click_dies_away():
    scene, click = CavityScene("plane"), ClickModel()
    seq = ImpactSequence([0.01], [1], [1.4])
    assert not np.any(snapshot_pressure(0.0105, seq, scene, click, POINTS))
    assert np.any(snapshot_pressure(0.0115, seq, scene, click, POINTS))
    assert not np.any(snapshot_pressure(0.5, seq, scene, click, POINTS))
