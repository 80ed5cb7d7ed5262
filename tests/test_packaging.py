"""The installed distribution ships its assets, so the catalogue and scenes work from a wheel."""

from importlib import metadata

import pytest


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
