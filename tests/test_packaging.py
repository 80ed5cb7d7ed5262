"""The installed distribution ships its assets, and the lowest-versions constraints are the declared lower bounds."""

import re
import tomllib
from importlib import metadata
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _installed_files():
    try:
        files = metadata.files("acoustiviz") or []
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a bare source tree
        pytest.skip("acoustiviz is not installed")
    names = {str(f).replace("\\", "/") for f in files}
    if "acoustiviz/__init__.py" not in names:
        pytest.skip("editable install: the source tree is the package")
    return names


def test_wheel_contains_materials_and_scenes():
    names = _installed_files()
    assert "acoustiviz/assets/materials.toml" in names
    assert "acoustiviz/assets/scenes/default.toml" in names
    assert any(n.startswith("acoustiviz/cli/") for n in names)


def test_console_script_is_declared():
    eps = metadata.entry_points(group="console_scripts")
    assert any(ep.name == "acoustiviz" and ep.value == "acoustiviz.cli:main" for ep in eps)


def _name(text):
    """PEP 503 normalised project name."""
    return re.sub(r"[-_.]+", "-", text).lower()


def _lower_bounds():
    """``{name: lower bound}`` of every runtime dependency of pyproject.toml (each must have one)."""
    try:
        from packaging.requirements import Requirement
    except ImportError:  # pragma: no cover - packaging is a test extra
        Requirement = None
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    out = {}
    for dep in deps:
        if Requirement is not None:
            req = Requirement(dep)
            name, lows = req.name, [s.version for s in req.specifier if s.operator == ">="]
        else:
            m = re.fullmatch(r"\s*([A-Za-z0-9_.\-]+)(?:\[[^]]*\])?\s*(.*?)\s*(;.*)?", dep)
            name, lows = m.group(1), re.findall(r">=\s*([^,\s]+)", m.group(2))
        assert len(lows) == 1, f"{dep!r}: every runtime dependency declares one lower bound (>=)"
        out[_name(name)] = lows[0]
    return out


def _same_version(a, b):
    """PEP 440 equality (``2.2 == 2.2.0``)."""
    try:
        from packaging.version import Version
    except ImportError:  # pragma: no cover - packaging is a test extra

        def Version(v):  # noqa: N802 - stands in for packaging's class
            parts = [int(p) for p in v.split(".")]
            while len(parts) > 1 and parts[-1] == 0:
                parts.pop()
            return tuple(parts)
    return Version(a) == Version(b)


def _pins():
    """``{name: version}`` of the ``==`` lines of .ci/constraints-lowest.txt."""
    pins = {}
    for line in (ROOT / ".ci" / "constraints-lowest.txt").read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            m = re.fullmatch(r"([A-Za-z0-9_.\-]+)\s*==\s*(\S+)", line)
            assert m, f"constraints-lowest.txt: {line!r} is not a 'name==version' pin"
            assert _name(m.group(1)) not in pins, f"constraints-lowest.txt pins {m.group(1)} twice"
            pins[_name(m.group(1))] = m.group(2)
    return pins


def test_the_lowest_constraints_pin_exactly_the_declared_lower_bounds():
    lows, pins = _lower_bounds(), _pins()
    assert lows, "pyproject.toml declares no runtime dependency"
    for name, low in lows.items():
        assert name in pins, f"constraints-lowest.txt does not pin {name} (pyproject.toml: >= {low})"
        assert _same_version(pins[name], low), \
            f"{name}: pyproject.toml >= {low}, constraints-lowest.txt == {pins[name]}"


def test_the_lower_bounds_reach_the_spec_0_window():
    # Scientific Python SPEC 0 of this release: Python 3.11, numpy 2.2, scipy 1.15, matplotlib 3.10
    from packaging.version import Version

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["requires-python"] == ">=3.11"
    lows = _lower_bounds()
    for name, floor in {"numpy": "2.2", "scipy": "1.15", "matplotlib": "3.10"}.items():
        assert Version(lows[name]) <= Version(floor), f"{name} >= {lows[name]} leaves out {floor}"
