"""Designs in operation (acoustiviz.sweep.operation): the summary columns, warm starts, failures, executors."""

import math

import numpy as np
import pytest

from acoustiviz.errors import ParameterError
from acoustiviz.sweep import FixedSettings, SweepSpec
from acoustiviz.sweep.operation import (
    OPERATION_COLUMNS,
    OPERATION_DEFINITIONS,
    Operation,
    WarmStart,
    evaluate_chain,
    evaluate_in_operation,
    evaluate_in_operation_or_fail,
    operation_chains,
    run_operation,
)

#: Relative agreement of a periodic orbit's amplitude with the linear steady state (Newton residual 1e-9 m).
LINEAR_RTOL = 1e-7
#: Standard errors within which a warm-started worst case agrees with a search from scratch.
SIGMAS = 3.0


def _same_rows(a: list, b: list) -> None:
    assert len(a) == len(b)
    for ra, rb in zip(a, b, strict=True):
        assert list(ra) == list(OPERATION_COLUMNS) == list(rb)
        for c in OPERATION_COLUMNS:
            x, y = ra[c], rb[c]
            if isinstance(x, float) and math.isnan(x):
                assert isinstance(y, float) and math.isnan(y), c
            else:
                assert x == y, (c, x, y)


def test_every_column_is_defined_with_its_unit():
    assert OPERATION_COLUMNS == tuple(OPERATION_DEFINITIONS)
    units = {"_n_s_m": "N s/m", "_n_m1_5": "N/m^1.5", "_deg": "degrees", "_hz": "Hz", "_db": "dB", "_kg": "kg",
             "_m": ", m"}  # the longest suffix first
    for c in OPERATION_COLUMNS:
        suffix = next((u for u in units if c.endswith(u)), None)
        if suffix is not None:
            assert units[suffix] in OPERATION_DEFINITIONS[c], c


def test_operation_is_checked_naming_the_field():
    with pytest.raises(ParameterError, match="kind"):
        Operation(5.0, (4.0,), kind="torque")
    with pytest.raises(ParameterError, match="frequencies"):
        Operation(5.0, (4.0, 4.0))
    with pytest.raises(ParameterError, match="amplitude"):
        Operation(-1.0, (4.0,))
    with pytest.raises(ParameterError, match="warm_starts"):
        Operation(5.0, (4.0,), starts=2, warm_starts=3)
    assert Operation(5.0, (6.0, 4.0)).frequencies == (4.0, 6.0)


def test_a_gap_too_large_to_impact_gives_the_linear_response_and_no_reduction():
    # the impact mass starts at rest (linear start and rest), 1 m of travel: the main mass alone responds
    fixed = FixedSettings()
    spec = SweepSpec(gap=(1.0,), settings=fixed)
    op = Operation(5.0, (3.0, 7.0), starts=2)
    row = evaluate_in_operation(spec.designs()[0], fixed, op)
    M, K, C, F0 = fixed.M, fixed.K, fixed.C, 5.0

    def by_hand(f):  # |X| = F0 / sqrt((K - M w^2)^2 + (C w)^2)
        w = 2 * math.pi * f
        return F0 / math.sqrt((K - M * w * w) ** 2 + (C * w) ** 2)

    worst = max(by_hand(3.0), by_hand(7.0))
    assert row["success"] == 1 and row["error"] == ""
    assert row["worst_frequency_hz"] == 3.0
    assert row["worst_amplitude_m"] == pytest.approx(worst, rel=LINEAR_RTOL)
    assert row["max_amplitude_without_damper_m"] == pytest.approx(worst, rel=1e-12)
    assert row["worst_amplitude_std_err_m"] == 0.0
    assert row["worst_regime"] == "periodic-1"
    assert abs(row["min_reduction_db"]) < 1e-5 and abs(row["mean_reduction_db"]) < 1e-5
    assert row["chaotic_fraction"] == 0.0
    for c in ("worst_lcpeak_db", "worst_laeq_db", "worst_lafmax_db"):  # no impact, no sound
        assert row[c] == -math.inf


def test_worst_amplitude_and_reduction_match_a_direct_forced_run():
    from acoustiviz.app.forced import run
    from acoustiviz.app.settings.forced_job import ForcedJob
    from acoustiviz.dynamics import DamperModel

    freqs = (3.0, 6.5)
    spec = SweepSpec()
    row = evaluate_in_operation(spec.designs()[0], spec.settings, Operation(5.0, freqs, levels=False))
    s = spec.settings
    model = DamperModel(M=s.M, K=s.K, C=s.C, m=0.0405, gap=0.04, k_hertz=5.6e8, c1=20.0)
    fr = run(ForcedJob(model=model, frequencies=freqs, amplitude=5.0, noise=False))
    amps = [r["amplitude_m"] for r in fr.rows]
    k = int(np.argmax(amps))
    assert row["worst_amplitude_m"] == amps[k]
    assert row["worst_amplitude_std_err_m"] == fr.rows[k]["amplitude_std_err_m"]
    assert row["worst_frequency_hz"] == fr.rows[k]["frequency_hz"]
    assert row["min_reduction_db"] == min(r["reduction_db"] for r in fr.rows)
    assert row["attractors"] == len(fr.rows)
    chaotic = {r["frequency_hz"] for r in fr.rows if r["regime"] == "chaotic"}
    assert row["chaotic_fraction"] == len(chaotic) / len(freqs)
    assert math.isnan(row["worst_lcpeak_db"])
    assert row["warm_from"] == -1


def test_warm_started_worst_case_within_standard_error_of_scratch():
    # neighbours whose 5 Hz attractor is chaotic for every start (benchmarks/results/operation.md)
    op = Operation(5.0, (4.0, 5.0), levels=False, warm_radius=0.5)
    spec = SweepSpec(m=(0.0385, 0.0395))
    first, second = spec.designs()
    warm = WarmStart()
    evaluate_in_operation(first, spec.settings, op, warm=warm)
    w = evaluate_in_operation(second, spec.settings, op, warm=warm)
    s = evaluate_in_operation(second, spec.settings, op)
    assert w["warm_from"] == first.design_id and s["warm_from"] == -1
    assert s["worst_amplitude_std_err_m"] > 0  # a chaotic batch mean
    se = math.hypot(w["worst_amplitude_std_err_m"], s["worst_amplitude_std_err_m"])
    assert abs(w["worst_amplitude_m"] - s["worst_amplitude_m"]) <= SIGMAS * se
    assert w["cycles_integrated"] < s["cycles_integrated"]  # the work saved, counted in cycles


def test_warm_starting_is_off_by_default():
    op = Operation(5.0, (3.0,), starts=1)
    spec = SweepSpec(m=(0.0405, 0.0415))
    warm = WarmStart()
    rows = [evaluate_in_operation(d, spec.settings, op, warm=warm) for d in spec.designs()]
    assert [r["warm_from"] for r in rows] == [-1, -1]
    assert len(warm) == 2


def test_same_dynamics_reuses_the_attractors_exactly():
    op = Operation(5.0, (3.0,), starts=2)
    spec = SweepSpec(distance=(0.7, 1.4))
    near, far = spec.designs()
    warm = WarmStart()
    a = evaluate_in_operation(near, spec.settings, op, warm=warm)
    b = evaluate_in_operation(far, spec.settings, op, warm=warm)
    scratch = evaluate_in_operation(far, spec.settings, op)
    assert b["warm_from"] == near.design_id
    _same_rows([{**b, "warm_from": -1}], [scratch])
    assert b["worst_amplitude_m"] == a["worst_amplitude_m"]
    assert b["worst_lcpeak_db"] < a["worst_lcpeak_db"]  # twice as far: quieter


def test_a_failing_design_is_a_row_with_its_reason():
    fixed = FixedSettings(C=100.0)  # overdamped main system: the event solver refuses it
    spec = SweepSpec(settings=fixed)
    row = evaluate_in_operation_or_fail(spec.designs()[0], fixed, Operation(5.0, (4.0,)))
    assert list(row) == list(OPERATION_COLUMNS)
    assert row["success"] == 0 and "C" in row["error"] and "\n" not in row["error"]
    assert math.isnan(row["worst_amplitude_m"]) and row["design_id"] == 0
    with pytest.raises(ParameterError, match="C"):  # the sweep refuses it before any work
        run_operation(spec, Operation(5.0, (4.0,)), workers=1)


def test_process_pool_equals_serial_whatever_the_order_of_the_chains():
    op = Operation(5.0, (4.5,), starts=1, max_cycles=100, warm_radius=0.5)
    spec = SweepSpec(m=(0.0405, 0.0415), distance=(0.7, 1.0))
    chains = operation_chains(spec.designs(), 2)
    assert [len(c) for c in chains] == [2, 2]
    serial = {r["design_id"]: r for c in chains[::-1] for r in evaluate_chain(c, spec.settings, op)}
    kept, said = [], []
    pooled = run_operation(spec, op, workers=2, chain=2, on_rows=kept.append, progress=said.append)
    _same_rows(pooled, [serial[d.design_id] for d in spec.designs()])
    assert sorted(r["design_id"] for rows in kept for r in rows) == [0, 1, 2, 3]  # each chain as it finished
    assert len(kept) == 2 and said[-1] == "operation: 4 of 4 designs"
    assert [r["warm_from"] for r in pooled] == [-1, 0, -1, 2]


def test_a_given_executor_is_used_and_left_open():
    from concurrent.futures import ThreadPoolExecutor

    op = Operation(5.0, (3.0, 3.5), starts=1)
    spec = SweepSpec(gap=(0.04, 0.05, 0.06))
    serial = [r for c in operation_chains(spec.designs(), 1) for r in evaluate_chain(c, spec.settings, op)]
    with ThreadPoolExecutor(2) as ex:
        rows = run_operation(spec, op, executor=ex, chain=1)
        assert ex.submit(int).result() == 0  # not shut down by the run
    _same_rows(rows, serial)


@pytest.mark.parametrize("m,gap,freqs", [
    (0.0385, 0.040, (4.5, 5.0)),  # the worst case chaotic at 5 Hz; periodic orbits reached by several starts at 4.5
    (0.0405, 0.042, (5.0,)),  # the worst case a periodic orbit
])
def test_the_search_in_operation_keeps_the_worst_case_of_the_search_cycle_by_cycle(monkeypatch, m, gap, freqs):
    """Known orbits reused and direct runs compiled in stretches: the row of the plain search, in fewer cycles."""
    from dataclasses import replace

    from acoustiviz.dynamics import _attractors

    op = Operation(5.0, freqs, levels=False)
    spec = SweepSpec(m=(m,), gap=(gap,))
    design = spec.designs()[0]
    quick = evaluate_in_operation(design, spec.settings, op)
    options = Operation.options
    monkeypatch.setattr(Operation, "options", lambda self: replace(options(self), reuse_known=False))
    monkeypatch.setattr(_attractors._Settler, "advance", lambda self, k0, next_try: (k0, self.step(k0)))
    plain = evaluate_in_operation(design, spec.settings, op)
    assert quick["worst_regime"] == plain["worst_regime"] == ("chaotic" if gap == 0.040 else "periodic-1")
    for col in ("worst_amplitude_m", "worst_amplitude_std_err_m", "worst_frequency_hz", "min_reduction_db",
                "mean_reduction_db", "chaotic_fraction", "attractors", "failed_runs"):
        assert quick[col] == plain[col], col
    assert quick["cycles_integrated"] < plain["cycles_integrated"]
