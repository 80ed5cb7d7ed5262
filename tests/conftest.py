import os

# the same in every environment: a MPLBACKEND inherited from the shell (an interactive backend on a
# machine without a display) must not change what the tests do
os.environ["MPLBACKEND"] = "Agg"

from hypothesis import settings  # noqa: E402

# property tests draw the same examples on every run and keep no example database between runs: a
# failure is reproducible from a clean clone, never a draw of the day; no deadline (machine load)
settings.register_profile("acoustiviz", derandomize=True, database=None, deadline=None)
settings.load_profile("acoustiviz")
