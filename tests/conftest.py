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


# --------------------------------------------------------------------------- shared fixtures
# The paper's values, built once per session: each is an immutable value (frozen dataclasses;
# a test never writes into their arrays), so sharing them cannot couple two tests.
import math  # noqa: E402

import pytest  # noqa: E402

from acoustiviz.constants import PAPER_DENSITY, PAPER_K_HERTZ, PAPER_RADIUS, PAPER_VELOCITY  # noqa: E402

#: Radius in m of the paper's Figure 2 sphere.
PAPER_A = PAPER_RADIUS


@pytest.fixture(scope="session")
def paper_impact():
    """The paper's Figure 2 impact: a steel sphere of radius 19.05 mm (mass ρ 4/3 π a³, ρ = 7800 kg/m³,
    about 226 g) at 1.4 m/s on a surface of Hertz stiffness 5.6e8 N/m^1.5."""
    from acoustiviz.core.contact import Impact

    mass = PAPER_DENSITY * 4 / 3 * math.pi * PAPER_A**3
    return Impact(velocity=PAPER_VELOCITY, k_hertz=PAPER_K_HERTZ, mass=mass)


@pytest.fixture(scope="session")
def paper_pulse(paper_impact):
    """``paper_pulse(kind)``: the acceleration pulse of :func:`paper_impact` of that kind ("half-sine",
    "impulse-matched" or "hertz"), each built once per session."""
    from acoustiviz.core.contact import acceleration_pulse

    built = {}

    def pulse(kind="half-sine"):
        if kind not in built:
            built[kind] = acceleration_pulse(paper_impact, kind)
        return built[kind]

    return pulse


@pytest.fixture(scope="session")
def half_sine_pulse(paper_pulse):
    """The paper's peak-matched half-sine pulse of the Figure 2 impact (m/s² over its contact time)."""
    return paper_pulse("half-sine")


@pytest.fixture(scope="session")
def hertz_pulse(paper_pulse):
    """The exact Hertz pulse of the Figure 2 impact."""
    return paper_pulse("hertz")


@pytest.fixture(scope="session")
def plane_geometry():
    """The Figure 2 sphere resting on a rigid floor z = 0 (one image)."""
    from acoustiviz.core.geometry import images_plane

    return images_plane(PAPER_A)


@pytest.fixture(scope="session")
def wall_floor_geometry():
    """The Figure 2 sphere on the floor in a wall-floor corner, its centre 5 cm from the wall (four sources)."""
    from acoustiviz.core.geometry import images_wall_floor

    return images_wall_floor(PAPER_A, 0.05)


@pytest.fixture(scope="session")
def table1_model():
    """The paper's Table 1 damper (M = 0.5 kg, K = 500 N/m, C = 0.05 N s/m, m = 40.5 g, gap 4 cm)."""
    from acoustiviz.dynamics import TABLE1

    return TABLE1


# --------------------------------------------------------------------------- children interrupted with Ctrl-C
import os as _os  # noqa: E402
import signal  # noqa: E402
from pathlib import Path  # noqa: E402

#: The tree under test, first on a child's path.
ROOT = Path(__file__).resolve().parents[1]
#: Inherited settings a child drops: numba's switches, matplotlib's backend, Python's own (PYTHONPATH is set anew).
_INHERITED = ("NUMBA_", "PYTHON", "MPL")


def interruptible_child(*, sigint=signal.SIG_DFL, pythonpath=()) -> dict:
    """Keyword arguments of :class:`subprocess.Popen` (or :func:`subprocess.run`) for a child to be sent Ctrl-C.

    The child starts as a terminal starts a command: in a session (and process group) of its own, so
    ``os.killpg(proc.pid, SIGINT)`` reaches it and its workers alike; with SIGINT at ``sigint`` before it
    execs (default: the default action, which a shell's background job would otherwise inherit ignored);
    in a clean environment, without inherited ``NUMBA_*``, ``MPL*`` or ``PYTHON*`` settings: this tree
    first on its path, then the folders of ``pythonpath``, matplotlib drawing off screen, and Python's
    fault handler on (a crash shows where).
    """
    env = {k: v for k, v in _os.environ.items() if not k.startswith(_INHERITED)}
    env.update(PYTHONPATH=_os.pathsep.join([str(ROOT), *map(str, pythonpath)]), MPLBACKEND="Agg",
               PYTHONFAULTHANDLER="1")

    def disposition():  # in the child, before it execs Python
        signal.signal(signal.SIGINT, sigint)

    return {"env": env, "start_new_session": True, "preexec_fn": disposition}


@pytest.fixture(scope="session")
def interruptible():
    """:func:`interruptible_child`: ``subprocess.Popen(argv, **interruptible(), ...)`` starts a child to interrupt."""
    return interruptible_child
