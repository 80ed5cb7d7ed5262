"""benchmarks/bench_optimisers.py: the measures of the comparison in operation, and its results file."""

import math

import bench_optimisers
import bench_optimisers_operation as op
import numpy as np
import pytest


def test_hypervolume_of_a_staircase_is_the_sum_of_its_rectangles():
    ref = (-12.0, 112.0)
    # (reduction, peak): maximise the first, minimise the second; the last is dominated, the fourth outside
    points = [(-2.0, 111.0), (-6.0, 108.0), (-10.0, 105.0), (-13.0, 100.0), (-7.0, 111.5)]
    # minimised coordinates (-reduction, peak) against (12, 112): (2, 111), (6, 108), (10, 105)
    expected = (12 - 2) * (112 - 111) + (12 - 6) * (111 - 108) + (12 - 10) * (108 - 105)
    assert op.hypervolume(points, ref) == pytest.approx(expected, rel=1e-12)
    assert op.hypervolume([], ref) == 0.0
    assert op.hypervolume([(-12.0, 100.0), (0.0, 112.0)], ref) == 0.0  # on the reference: no area


def test_hypervolume_agrees_with_pymoo():
    hv = pytest.importorskip("pymoo.indicators.hv")
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(-14, 0, 40), rng.uniform(100, 115, 40)])
    ref = (-12.0, 112.0)
    inside = points[(points[:, 0] > ref[0]) & (points[:, 1] < ref[1])]
    expected = hv.HV(ref_point=np.array([-ref[0], ref[1]]))(np.column_stack([-inside[:, 0], inside[:, 1]]))
    assert op.hypervolume(map(tuple, points), ref) == pytest.approx(expected, rel=1e-12)


def _row(red, peak, error=""):
    return {"min_reduction_db": red, "worst_lcpeak_db": peak, "error": error}


def test_a_run_is_judged_on_its_feasible_designs_only():
    class Known:
        cache = {(0.02, 0.02): _row(-1.0, op.LCPEAK_LIMIT + 0.5), (0.03, 0.03): _row(-4.0, op.LCPEAK_LIMIT - 1.0),
                 (0.04, 0.04): _row(-3.0, op.LCPEAK_LIMIT), (0.05, 0.05): _row(math.nan, math.nan, "failed"),
                 (0.06, 0.06): _row(-9.0, op.LCPEAK_LIMIT - 6.0)}

        def rows(self, points):
            return [self.cache[(float(g), float(m))] for g, m in points]

    trace = op.Trace(Known())
    trace([(0.02, 0.02), (0.03, 0.03)])
    trace([(0.03, 0.03), (0.04, 0.04), (0.05, 0.05), (0.06, 0.06)])  # a design asked twice counts once
    assert len(trace.rows()) == 5
    assert trace.best() == (-3.0, op.LCPEAK_LIMIT)  # the louder -1 dB design breaks the bound
    hv, size = trace.front_hypervolume()
    assert size == 3  # none of the feasible three dominates another
    front = [(-3.0, op.LCPEAK_LIMIT), (-4.0, op.LCPEAK_LIMIT - 1.0), (-9.0, op.LCPEAK_LIMIT - 6.0)]
    assert hv == pytest.approx(op.hypervolume(front))


def test_writing_one_mode_keeps_the_other(tmp_path, monkeypatch):
    monkeypatch.setattr(bench_optimisers, "RESULTS", tmp_path)
    path = tmp_path / "optimisers.md"
    bench_optimisers.write_section("free table 1", operation=False)
    bench_optimisers.write_section("## In operation\n\nfirst", operation=True)
    bench_optimisers.write_section("## In operation\n\nsecond", operation=True)
    assert path.read_text() == "free table 1\n\n## In operation\n\nsecond\n"
    bench_optimisers.write_section("free table 2", operation=False)
    assert path.read_text() == "free table 2\n\n## In operation\n\nsecond\n"
