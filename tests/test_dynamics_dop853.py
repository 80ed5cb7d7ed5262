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


def _stages(seed, n):
    """Stage rows spanning many magnitudes and both signs, as a solver's ``kst`` (13 rows)."""
    rng = np.random.default_rng(seed)
    return rng.standard_normal((13, n)) * 10.0 ** rng.integers(-12, 12, size=(13, n))


def _dense(weights, kst, i):
    acc = 0.0  # the dense sum over every stage, zeros included, in stage order
    for j, w in enumerate(weights):
        acc += float(w) * float(kst[j, i])
    return acc


def test_compiled_sums_equal_the_sums_over_the_arrays_bit_for_bit():
    numba = pytest.importorskip("numba")

    @numba.njit
    def compiled(y, h, kst, n):
        out = np.zeros((13, y.shape[0]))
        for st in range(1, 12):
            dop.stage_state(st, y, h, kst, out[st], n)
        dop.solution(y, h, kst, out[12], n)
        est = np.zeros((2, y.shape[0]))
        for i in range(y.shape[0]):
            est[0, i], est[1, i] = dop.estimates(kst, i)
        return out, est

    for seed, n in ((1, 5), (2, 9), (3, 14)):
        kst = _stages(seed, n)
        y = np.random.default_rng(seed + 10).standard_normal(n)
        h = 0.37
        out, est = compiled(y, h, kst, n - 1)  # the last component left alone
        rows = (*dop.A, dop.B)
        for st in range(1, 13):
            want = [y[i] + h * _dense(rows[st], kst, i) for i in range(n - 1)]
            assert np.array_equal(out[st, : n - 1], want), st
            assert out[st, n - 1] == 0.0
        assert np.array_equal(est[0], [_dense(dop.E5, kst, i) for i in range(n)])
        assert np.array_equal(est[1], [_dense(dop.E3, kst, i) for i in range(n)])


def test_error_norm_is_hairers_dense_formula_and_rejects_an_overflowed_end():
    numba = pytest.importorskip("numba")

    @numba.njit
    def error_norm(y, ynew, h, kst, rtol, atol):  # the compiled helper has no entry point from Python
        return dop.error_norm(y, ynew, h, kst, rtol, atol)

    n = 9
    kst = _stages(4, n) * 1e-6
    rng = np.random.default_rng(5)
    y, ynew, atol = rng.standard_normal(n), rng.standard_normal(n), 10.0 ** rng.uniform(-14, -8, n)
    h, rtol = 0.25, 1e-10
    e5 = e3 = 0.0
    for i in range(n):
        sc = atol[i] + rtol * max(abs(y[i]), abs(ynew[i]))
        q5, q3 = _dense(dop.E5, kst, i) / sc, _dense(dop.E3, kst, i) / sc
        e5 += q5 * q5
        e3 += q3 * q3
    want = h * e5 / math.sqrt((e5 + 0.01 * e3) * n)
    assert error_norm(y, ynew, h, kst, rtol, atol) == want
    ynew[3] = math.inf
    assert error_norm(y, ynew, h, kst, rtol, atol) == math.inf
