"""Directivity balloons in the field layer: the closed lattice of directions and the levels on it."""

import numpy as np
import pytest

from acoustiviz.core.geometry import geometry
from acoustiviz.errors import ParameterError
from acoustiviz.field import field_metrics
from acoustiviz.field.balloon import balloon_data, balloon_metrics

A = 0.01905


@pytest.fixture(scope="module")
def pulse(half_sine_pulse):
    return half_sine_pulse


@pytest.fixture(scope="module")
def plane(plane_geometry):
    return plane_geometry


@pytest.fixture(scope="module")
def corner(wall_floor_geometry):
    return wall_floor_geometry


def test_balloon_data_closes_the_region_and_peaks_on_the_axis(pulse, plane, corner):
    d = balloon_data(pulse, plane, n_theta=8)
    nt, nph, _ = d.directions.shape
    assert (nt, nph) == (8 + 2, 16 + 1)
    np.testing.assert_allclose(np.linalg.norm(d.directions, axis=-1), 1.0, atol=1e-12)
    np.testing.assert_allclose(d.directions[-1] @ [0, 0, 1], 1.0)  # the pole
    np.testing.assert_allclose(d.directions[0] @ [0, 0, 1], 0.0, atol=1e-12)  # the rim on the floor
    assert np.all(np.isfinite(d.level))
    assert d.level[-1].mean() == pytest.approx(d.max_level, abs=0.5)  # loudest along the normal
    assert d.level[-1].mean() - d.level[0].mean() > 15.0  # quiet at grazing
    assert d.mean_level < d.max_level
    q = balloon_data(pulse, corner, n_theta=6)
    assert np.all(q.directions[..., 0] >= -1e-12) and np.all(q.directions[..., 2] >= -1e-12)
    assert q.grid.region == "quarter" and q.label == "peak SPL (dB re 20 µPa)"


def test_balloon_free_field_is_a_symmetric_dipole(pulse):
    d = balloon_data(pulse, geometry("free", A), n_theta=8, distance=1.0)
    lev = d.level.mean(axis=1)  # rows: cos θ from -1 to 1
    np.testing.assert_allclose(lev, lev[::-1], atol=0.3)
    assert lev[0] - lev[len(lev) // 2] > 10.0


def test_balloon_metrics_of_a_level_of_its_own_are_the_field_metrics_on_the_lattice(pulse, plane):
    # a level given by a function carries no metrics; balloon_metrics adds those of field_metrics there
    d = balloon_data(pulse, plane, n_theta=6, distance=0.5, metric="flat",
                     levels=(lambda pts: np.full(len(pts), 80.0), "flat (dB re 20 µPa)"))
    assert d.metrics is None
    m = balloon_metrics(pulse, plane, d).metrics
    lattice = d.anchor + d.distance * d.directions.reshape(-1, 3)
    np.testing.assert_array_equal(m.peak_spl_db, field_metrics(pulse, lattice, plane).peak_spl_db)
    own = balloon_data(pulse, plane, n_theta=6, distance=0.5)
    assert balloon_metrics(pulse, plane, own) is own  # a level of the field itself holds them already
    with pytest.raises(ParameterError, match="data"):
        balloon_metrics(pulse, plane, "balloon")
