"""Running an optimisation: the executors, interrupts, the problem's parsing, and the paper's question checked
against a dense grid sweep."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

pytest.importorskip("optuna")

from acoustiviz.errors import ParameterError  # noqa: E402
from acoustiviz.sweep.modes import FreeVibration  # noqa: E402
from acoustiviz.sweep.optimise import JOURNAL, read_journal, run_optimisation  # noqa: E402
from acoustiviz.sweep.problem import (  # noqa: E402
    Objective,
    Problem,
    feasible_mask,
    pareto_mask,
    parse_constraint,
    parse_variable,
)
from acoustiviz.sweep.spec import FixedSettings  # noqa: E402

#: The paper's question in free vibration: the quietest design with the damping inclination in a band.
GAP, MASS, BAND = (0.01, 0.06), (0.01, 0.08), (0.004, 0.006)


def _problem(evaluations=16, seed=0, batch=8) -> Problem:
    return Problem((parse_variable("gap", f"{GAP[0]}:{GAP[1]}"), parse_variable("m", f"{MASS[0]}:{MASS[1]}")),
                   (Objective("max_spl_db", "min"),),
                   (parse_constraint("c", f"inclination_two_maxima_m_s>={BAND[0]}"),
                    parse_constraint("c", f"inclination_two_maxima_m_s<={BAND[1]}")),
                   evaluations=evaluations, seed=seed, batch=batch, columns=FreeVibration.objective_columns)


def _records(tmp_path, name, **kw):
    return run_optimisation(_problem(), FreeVibration(FixedSettings(duration=0.5)), tmp_path / name, **kw)


def test_two_workers_give_the_result_of_one(tmp_path):
    one = _records(tmp_path, "one", workers=1)
    two = _records(tmp_path, "two", workers=2)
    assert [r["evaluation"] for r in two] == list(range(16))
    assert json.dumps(one) == json.dumps(two)  # the same designs and rows, in evaluation order (NaN included)


@pytest.mark.slow
def test_dask_with_worker_processes_gives_the_result_of_the_process_pool(tmp_path):
    distributed = pytest.importorskip("distributed")
    local = _records(tmp_path, "local", workers=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, protocol="tcp://",
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        address = cluster.scheduler_address.removeprefix("tcp://")
        remote = _records(tmp_path, "dask", executor=f"dask://{address}")
    assert json.dumps(remote) == json.dumps(local)


def test_ctrl_c_keeps_every_finished_evaluation(tmp_path, interruptible):
    out = tmp_path / "o"
    argv = [sys.executable, "-m", "acoustiviz", "optimize", "--gap", "0.01:0.06", "--m", "0.01:0.08",
            "--minimize", "max_spl_db", "--evaluations", "5000", "--duration", "1", "--workers", "1",
            "--out", str(out)]
    # as a terminal starts the command, in a clean environment, in a process group of its own
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **interruptible())
    journal = out / JOURNAL
    deadline = time.monotonic() + 300  # a hang detector only: the trigger is the journal's third line
    while time.monotonic() < deadline and proc.poll() is None:
        if journal.exists() and journal.read_text().count("\n") >= 3:
            break
        time.sleep(0.05)
    assert proc.poll() is None, proc.stderr.read()
    os.killpg(proc.pid, signal.SIGINT)  # parent and workers alike, as a terminal's Ctrl-C
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err[-2000:]
    assert "interrupted; finished outputs were kept" in err
    text = journal.read_text()
    kept = read_journal(journal)
    assert f"optimize: stopped; {len(kept)} of 5000 evaluations kept" in err
    assert len(kept) >= 3 and sorted(kept) == list(range(len(kept)))
    assert all(json.loads(line)["row"]["error"] == "" for line in text.splitlines())


@pytest.mark.slow
def test_the_best_design_is_within_0_3_db_of_a_30_by_30_grid_with_a_tenth_of_its_evaluations(tmp_path):
    from acoustiviz.sweep import run_sweep
    from acoustiviz.sweep.spec import SweepSpec, value_range

    settings = FixedSettings(duration=1.0)
    grid = run_sweep(SweepSpec(gap=value_range(*GAP, 30), m=value_range(*MASS, 30), settings=settings),
                     tmp_path / "grid", workers=2)
    inc, spl = grid["inclination_two_maxima_m_s"], grid["max_spl_db"]
    ok = (inc >= BAND[0]) & (inc <= BAND[1])
    reference = float(spl[ok].min())
    found = []
    for seed in range(5):
        records = run_optimisation(_problem(evaluations=90, seed=seed), FreeVibration(settings),
                                   tmp_path / f"seed{seed}", workers=2)
        rows = [r["row"] for r in records]
        assert len(rows) == 90
        feasible = feasible_mask(_problem(), rows)
        found.append(min(r["max_spl_db"] for r, f in zip(rows, feasible, strict=True) if f))
    assert all(b <= reference + 0.3 for b in found), (reference, found)


def test_a_design_that_cannot_be_built_is_a_row_with_its_reason_and_its_variables():
    row = FreeVibration(FixedSettings(duration=0.1))(3, {"gap": 0.04, "angle_deg": 100.0, "config": "plane"})
    assert row["design_id"] == 3 and row["success"] == 0 and "angle" in row["error"]
    assert (row["gap_m"], row["angle_deg"], row["config"]) == (0.04, 100.0, "plane")
    assert math.isnan(row["max_spl_db"]) and len(row["error"].splitlines()) == 1


# --------------------------------------------------------------------------- the problem
@pytest.mark.parametrize(("text", "kind", "expected"), [
    ("0.01:0.06", float, ("float", 0.01, 0.06, ())),
    ("log:0.001:0.1", float, ("log", 0.001, 0.1, ())),
    ("steel,brass,nylon", str, ("categorical", math.nan, math.nan, ("steel", "brass", "nylon"))),
    ("0.04", float, ("fixed", math.nan, math.nan, (0.04,))),
    (0.04, float, ("fixed", math.nan, math.nan, (0.04,))),
])
def test_variables_are_parsed_in_every_form(text, kind, expected):
    v = parse_variable("x", text, kind)
    got = (v.kind, v.low, v.high, v.choices)
    assert got[0] == expected[0] and got[3] == expected[3]
    np.testing.assert_array_equal(got[1:3], expected[1:3])


@pytest.mark.parametrize("text", ["0.06:0.01", "0.01:0.01", "log:0:1", "a:b", "1:2:3", "", "1,1", "nan:1"])
def test_bad_variables_are_refused(text):
    with pytest.raises(ParameterError, match=r"^x: "):
        parse_variable("x", text)


def test_constraints_and_feasibility():
    c = parse_constraint("c", " max_spl_db <= 100 ")
    assert (c.column, c.op, c.value) == ("max_spl_db", "<=", 100.0)
    assert c.violation(99.0) == 0.0 and c.violation(110.0) == pytest.approx(0.1) and c.violation(math.nan) == math.inf
    for bad in ("max_spl_db<100", "max_spl_db<=x", "<=3"):
        with pytest.raises(ParameterError, match=r"^c: "):
            parse_constraint("c", bad)
    rows = [{"max_spl_db": 99.0, "error": ""}, {"max_spl_db": 101.0, "error": ""},
            {"max_spl_db": math.nan, "error": "x"}]
    p = Problem((parse_variable("gap", "0.01:0.02"),), (Objective("max_spl_db", "min"),), (c,), 1, 0, 1)
    assert feasible_mask(p, rows).tolist() == [True, False, False]


def test_the_pareto_filter_keeps_ties_and_only_candidates():
    v = [[1, 3], [2, 2], [3, 1], [2, 2], [3, 3], [0, 0]]
    assert pareto_mask(v, [True] * 5 + [False]).tolist() == [True, True, True, True, False, False]
