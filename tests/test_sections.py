"""Planar sections in the field layer: the frames of an animation evaluated only where a wave is passing."""

import numpy as np
import pytest

from acoustiviz.field import snapshots
from acoustiviz.field.sections import frame_fields, section_planes


@pytest.fixture(scope="module")
def pulse(half_sine_pulse):
    return half_sine_pulse


@pytest.fixture(scope="module")
def corner(wall_floor_geometry):
    return wall_floor_geometry


def test_frames_evaluate_only_inside_the_arrival_windows(pulse, corner):
    grid = section_planes(corner, 0.25, n_u=31)[0]
    times = np.array([0.0002, 0.0005, 0.0009])
    got = frame_fields(pulse, corner, times, grid.points)
    ref = snapshots(pulse, times, grid.points, corner)
    ok = np.isfinite(ref)
    np.testing.assert_array_equal(np.isfinite(got), ok)
    np.testing.assert_allclose(got[ok], ref[ok], rtol=0, atol=1e-9 * np.abs(ref[ok]).max())
    assert (got[0][ok[0]] == 0).mean() > 0.5  # most points are still silent early on
