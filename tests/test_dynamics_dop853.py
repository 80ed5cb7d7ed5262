"""The vendored Dormand-Prince 8(5,3) tableau: order conditions, estimators, observed order 8."""

import math

import numpy as np
import pytest

from acoustiviz.dynamics import _dop853 as dop


def test_shapes_and_explicitness():
    assert dop.A.shape == (12, 12) and dop.B.shape == (12,) and dop.C.shape == (13,)
    assert dop.E3.shape == dop.E5.shape == (13,)
    assert np.all(np.triu(dop.A) == 0.0)  # explicit: a_ij = 0 for j >= i
    assert not dop.A.flags.writeable


def test_row_sums_are_the_nodes():
    # c_i = sum_j a_ij for every stage, and c = 1 for the final (FSAL) stage whose row is b
    np.testing.assert_allclose(dop.A.sum(axis=1), dop.C[:12], rtol=0, atol=4e-15)
    assert dop.C[12] == 1.0 and dop.C[11] == 1.0


@pytest.mark.parametrize("k", range(8))
def test_quadrature_conditions_up_to_order_8(k):
    # the bushy trees: sum_j b_j c_j^k = 1 / (k + 1) for k = 0..7
    assert math.isclose(float(dop.B @ dop.C[:12] ** k), 1.0 / (k + 1), rel_tol=0, abs_tol=2e-15)


def test_tree_conditions_of_orders_3_to_5():
    b, a, c = dop.B, dop.A, dop.C[:12]
    checks = {
        "b A c = 1/6": (b @ a @ c, 1 / 6),
        "b A c^2 = 1/12": (b @ a @ c**2, 1 / 12),
        "b (c * A c) = 1/8": (b @ (c * (a @ c)), 1 / 8),
        "b A A c = 1/24": (b @ a @ a @ c, 1 / 24),
        "b A c^3 = 1/20": (b @ a @ c**3, 1 / 20),
        "b (c * A A c) = 1/30": (b @ (c * (a @ a @ c)), 1 / 30),
        "b A A A c = 1/120": (b @ a @ a @ a @ c, 1 / 120),
        "b (A c)^2 = 1/20": (b @ (a @ c) ** 2, 1 / 20),
    }
    bad = {k: v for k, (v, want) in checks.items() if abs(v - want) > 2e-15}
    assert not bad, bad


def test_error_estimators_are_differences_of_consistent_weights():
    # each estimator is (b - bhat) for a bhat of its own (lower) order: its weights sum to zero and it
    # annihilates low-order quadrature (E5: c^k for k <= 4; E3: c^k for k <= 2)
    c = dop.C
    for k in range(5):
        assert abs(dop.E5 @ c**k) < 2e-15, k
    for k in range(3):
        assert abs(dop.E3 @ c**k) < 2e-15, k
    assert abs(dop.E3 @ c**3) > 1e-4  # but not beyond its order


def _rk_solve(f, y0, t_end, n):
    """Fixed-step integration with the vendored tableau (independent of the compiled kernels)."""
    h = t_end / n
    y = np.array(y0, dtype=float)
    t = 0.0
    k = np.empty((12, y.size))
    for _ in range(n):
        for i in range(12):
            k[i] = f(t + dop.C[i] * h, y + h * (dop.A[i, :i] @ k[:i]))
        y = y + h * (dop.B @ k)
        t += h
    return y


def test_observed_order_is_8():
    # y' = cos(t) y, y(0) = 1: y = exp(sin t); non-autonomous, so the nodes c matter too
    def f(t, y):
        return np.cos(t) * y

    exact = math.exp(math.sin(5.0))
    errs = [abs(_rk_solve(f, [1.0], 5.0, n)[0] - exact) for n in (10, 20, 40)]
    orders = [math.log2(errs[i] / errs[i + 1]) for i in range(2)]
    assert all(7.6 < p < 8.6 for p in orders), (errs, orders)


def test_matches_the_published_digits():
    # a few coefficients as printed in dop853.f (Hairer's code), read independently of the table
    assert dop.A[1, 0] == 5.26001519587677318785587544488e-2
    assert dop.A[4, 2] == -8.84549479328286085344864962717e-1
    assert dop.A[11, 10] == 6.43392746015763530355970484046e-1
    assert dop.B[0] == 5.42937341165687622380535766363e-2
    assert dop.E5[0] == 0.1312004499419488073250102996e-1
