"""Importing the package and asking for help stay light: no numpy, no compiler, no plotting, no 3-D, no filters.

Each check runs in a fresh interpreter (a subprocess) and inspects ``sys.modules`` afterwards, so
what another test imported does not count. No timing is asserted (``benchmarks/bench_startup.py``
measures the times).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: modules a light start must not load: numpy (the package's names and the parsers are imported
#: without it), the kernel compiler, plotting, 3-D rendering and filters
HEAVY = ("numpy", "numba", "matplotlib", "pyvista", "vtk", "vtkmodules", "scipy.signal")


def _loaded_after(code: str) -> list[str]:
    """The :data:`HEAVY` modules present in ``sys.modules`` after running ``code`` in a new interpreter."""
    probe = code + f"\nimport json, sys\nprint(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))\n"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_import_is_light():
    assert _loaded_after("import acoustiviz") == []


def _help_code(argv: list[str]) -> str:
    return ("import contextlib, io, runpy, sys\n"
            f"sys.argv = ['acoustiviz', *{argv!r}]\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    try:\n"
            "        runpy.run_module('acoustiviz', run_name='__main__')\n"
            "    except SystemExit as exc:\n"
            "        assert exc.code in (0, None), exc.code\n")


def _subcommands() -> list[str]:
    from acoustiviz.cli import SUBCOMMANDS

    return list(SUBCOMMANDS)


def test_help_is_light():
    assert _loaded_after(_help_code(["--help"])) == []


@pytest.mark.parametrize("sub", _subcommands())
@pytest.mark.slow
def test_subcommand_help_is_light(sub):
    assert _loaded_after(_help_code([sub, "--help"])) == []


def test_metric_names_follow_the_levels():
    # the light copies the command line offers as choices are the levels' own metric names
    from acoustiviz.app.views import BALLOON_METRICS, DIRECTIVITY_METRICS
    from acoustiviz.levels import METRICS, SoundLevels

    assert set(METRICS.values()) <= set(SoundLevels.__dataclass_fields__)
    assert set(BALLOON_METRICS) == {"peak", "rms", "sel"} | set(METRICS)
    assert {k: v for k, v in DIRECTIVITY_METRICS.items() if k in METRICS} == METRICS


def test_compile_for_compiles_without_running_and_once():
    # a kernel compiled for the types of its arguments is not run, and a second request costs nothing
    import numpy as np
    from numba import njit

    from acoustiviz._jit import compile_for, in_cache


    @njit
    def twice(a, x):
        return 2.0 * a[0] * x

    args = (np.ones(3), 1.5)
    assert not in_cache(twice, args)
    assert compile_for(twice, args) > 0.0
    assert in_cache(twice, args)
    assert compile_for(twice, args) == 0.0
    assert len(twice.signatures) == 1
    assert twice(np.full(3, 2.0), 1.5) == 6.0
    assert len(twice.signatures) == 1  # the call found the compiled signature


def test_compile_for_accepts_a_plain_function():
    # numba's NUMBA_DISABLE_JIT=1 (its debugging switch) turns every @njit into the Python function itself
    from acoustiviz._jit import compile_for

    def twice(x):
        return 2.0 * x

    assert compile_for(twice, (1.5,), "twice", 10.0, announce=True) == 0.0


def test_no_compiling_line_where_stderr_is_not_a_terminal(capsys):
    from numba import njit

    from acoustiviz._jit import compile_for

    @njit
    def thrice(x):
        return 3.0 * x

    compile_for(thrice, (1.5,), "test", 30.0)  # long and not cached, but nobody is watching
    assert capsys.readouterr().err == ""
    assert thrice(1.0) == 3.0


def test_simulate_reports_compile_time_apart():
    from acoustiviz.dynamics import simulate

    simulate(duration=0.5)
    r = simulate(duration=0.5)
    assert r.compile_time == 0.0  # compiled in this process already: nothing to compile or load
    assert r.solver_time > 0.0


@pytest.mark.slow
def test_compiling_line_only_when_the_cache_is_cold(tmp_path):
    # a cached kernel announced as long to compile: the line is printed by the first process (empty
    # cache) and not by the second, which loads the kernel from the cache
    mod = tmp_path / "kern_mod.py"
    mod.write_text("from numba import njit\n\n\n@njit(cache=True)\ndef twice(x):\n    return 2.0 * x\n")
    code = ("import sys\n"
            "from acoustiviz._jit import compile_for\n"
            "import kern_mod\n"
            "compile_for(kern_mod.twice, (1.5,), 'test', 3.0, announce=True)\n"
            "compile_for(kern_mod.twice, (1.5,), 'test', 3.0, announce=True)\n"
            "assert kern_mod.twice(1.5) == 3.0\n")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join([str(ROOT), str(tmp_path), os.environ.get("PYTHONPATH", "")])}
    runs = [subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
            for _ in range(2)]
    assert all(r.returncode == 0 for r in runs), [r.stderr for r in runs]
    assert runs[0].stderr.count("compiling the test kernels (once per installation, about 3 s)") == 1
    assert "compiling" not in runs[1].stderr
