import os

# the same in every environment: a MPLBACKEND inherited from the shell (an interactive backend on a
# machine without a display) must not change what the tests do
os.environ["MPLBACKEND"] = "Agg"

from hypothesis import settings  # noqa: E402

# property tests draw the same examples on every run and keep no example database between runs: a
# failure is reproducible from a clean clone, never a draw of the day; no deadline (machine load)
settings.register_profile("acoustiviz", derandomize=True, database=None, deadline=None)
settings.load_profile("acoustiviz")


def pytest_report_header(config):
    """The versions and CPU the run is on (.ci/versions.py), at the top of every report."""
    import runpy
    from pathlib import Path

    script = Path(__file__).resolve().parents[1] / ".ci" / "versions.py"
    return runpy.run_path(str(script))["version_line"]() if script.is_file() else None
