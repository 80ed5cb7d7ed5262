"""The bucket sort of arrival times (:mod:`acoustiviz.field._arrivals`) against NumPy's stable argsort."""

import numpy as np
import pytest

from acoustiviz.field._arrivals import arrival_order


@pytest.mark.parametrize("n", [1, 2, 7, 1561])
def test_arrival_order_is_a_stable_argsort(n):
    rng = np.random.default_rng(n)
    d = rng.uniform(0.0, 0.2, n) ** 3  # crowded early and sparse late, as any t**k law
    d[: n // 3] = np.round(d[: n // 3], 3)  # ties, kept in their given order
    np.testing.assert_array_equal(arrival_order(d), np.argsort(d, kind="stable"))


def test_arrival_order_of_equal_and_of_no_delays():
    np.testing.assert_array_equal(arrival_order(np.full(5, 0.01)), np.arange(5))
    assert arrival_order(np.empty(0)).size == 0
