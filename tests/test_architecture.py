"""Imports point down the layers: the physics core knows nothing of grids, plots, files or the CLI."""

import ast
import subprocess
import sys
from pathlib import Path

import acoustiviz

PKG = Path(acoustiviz.__file__).parent
CORE = ["medium", "materials", "contact", "radiation", "images", "dynamics"]
UPPER = ["field", "grids", "plot", "render", "audio", "scene", "cli", "sweep", "_gallery"]
MIDDLE_FORBIDDEN = ["plot", "render", "audio", "scene", "cli", "sweep", "_gallery"]


def _imports(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    mods = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:  # relative import inside acoustiviz
                base = path.relative_to(PKG).parent.parts
                up = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                mods.append(".".join((*up, node.module or "")).strip("."))
            elif node.module and node.module.startswith("acoustiviz"):
                mods.append(node.module.removeprefix("acoustiviz").lstrip("."))
        elif isinstance(node, ast.Import):
            mods += [a.name.removeprefix("acoustiviz").lstrip(".") for a in node.names
                     if a.name.startswith("acoustiviz")]
    return [m.split(".")[0] for m in mods if m]


def _files(names):
    for name in names:
        p = PKG / f"{name}.py"
        if p.exists():
            yield name, p
        d = PKG / name
        if d.is_dir():
            for f in d.rglob("*.py"):
                yield name, f


def test_core_imports_no_upper_layer():
    bad = [(str(f.relative_to(PKG)), m) for _, f in _files(CORE) for m in _imports(f) if m in UPPER]
    assert not bad, bad


def test_field_layer_imports_no_output_layer():
    bad = [(str(f.relative_to(PKG)), m) for _, f in _files(["field", "grids"])
           for m in _imports(f) if m in MIDDLE_FORBIDDEN]
    assert not bad, bad


def test_import_is_light_and_side_effect_free():
    code = ("import sys, acoustiviz; heavy = [m for m in ('matplotlib', 'pyvista', 'soundfile', 'numba', "
            "'dask') if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
