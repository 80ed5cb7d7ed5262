"""Sphinx extension: one API page per public module of acoustiviz, generated at build time.

The modules are found by walking the package (:func:`pkgutil.walk_packages`), so a module
added, moved or split needs no edit here. A module is public when no part of its dotted name
starts with an underscore; the command-line modules (``acoustiviz.cli``) are documented by the
command-line reference instead. Each page is an ``automodule`` rendered by numpydoc; each
object appears once, on the page of the module that defines it. The index groups the modules
by layer, in the package's import order, and lists the names exported by ``acoustiviz`` itself
with links to where they are documented.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from pathlib import Path

#: Layers in import order (foundation first): first name below ``acoustiviz`` -> heading.
LAYERS = {
    "constants": "Foundation: constants, errors and atomic files",
    "errors": "Foundation: constants, errors and atomic files",
    "files": "Foundation: constants, errors and atomic files",
    "core": "Core physics: medium, materials, contact, radiation, images",
    "dynamics": "Damper dynamics",
    "field": "Field evaluator and grids",
    "grids": "Field evaluator and grids",
    "levels": "Levels",
    "sound": "Sound synthesis: impact trains to calibrated signals",
    "output": "Outputs: plots, renders, WAV files, VTK and HTML files",
    "sweep": "Design sweeps",
    "app": "Application layer",
    "scene": "Scene files",
}
SKIP_TOP = {"cli", "__main__"}


def public_modules(package: str = "acoustiviz") -> list:
    """Dotted names of the public modules of ``package`` (itself first), sorted within each layer."""
    pkg = importlib.import_module(package)
    names = [package]
    for info in pkgutil.walk_packages(pkg.__path__, prefix=package + ".", onerror=lambda name: None):
        parts = info.name.split(".")[1:]
        if any(p.startswith("_") for p in parts) or parts[0] in SKIP_TOP:
            continue
        names.append(info.name)
    order = list(dict.fromkeys(LAYERS.values()))
    return [package] + sorted(names[1:], key=lambda n: (order.index(_layer(n)), n))


def _layer(name: str) -> str:
    return LAYERS.get(name.split(".")[1], "Other modules")


def _title(text: str, char: str = "=") -> str:
    return f"{text}\n{char * len(text)}\n"


def module_page(name: str) -> str:
    """The reST text of the page of module ``name``."""
    mod = importlib.import_module(name)
    lines = [f".. _api-{name}:\n", _title(name), f".. automodule:: {name}", "   :members:",
             "   :ignore-module-all:", ""]
    subs = [m.name for m in pkgutil.iter_modules(getattr(mod, "__path__", []), prefix=name + ".")
            if not m.name.rsplit(".", 1)[1].startswith("_") and m.name.split(".")[1] not in SKIP_TOP]
    if subs:
        lines += ["Submodules", "----------", ""] + [f"* :doc:`{s}`" for s in subs] + [""]
    return "\n".join(lines)


def _where(name: str, obj, modules) -> str | None:
    mod = getattr(obj, "__module__", None)
    if (inspect.isclass(obj) or inspect.isfunction(obj)) and mod in modules:
        return f"{mod}.{name}"
    for m in modules:  # data: the first public module that defines the name at top level
        module = importlib.import_module(m)
        if m != "acoustiviz" and getattr(module, name, None) is obj and not hasattr(module, "__path__"):
            return f"{m}.{name}"
    return None


def index_page(modules) -> str:
    """The reST text of the API index: the top-level names, then every module grouped by layer."""
    import acoustiviz

    out = [".. _api:\n", _title("API reference"),
           "Everything the command line does is a function of the package; the command line only parses "
           "options and calls the application layer. SI units throughout (m, s, kg, Pa, N); levels in dB "
           "re 20 µPa. These pages are generated from the package's numpydoc docstrings.\n",
           _title("The ``acoustiviz`` namespace", "-"),
           "The most used names are importable from the package itself (``import acoustiviz as av``):\n",
           ".. list-table::", "   :header-rows: 1", "   :widths: 30 70", "", "   * - name", "     - defined in"]
    for name in sorted(acoustiviz.__all__, key=str.lower):
        obj = getattr(acoustiviz, name)
        target = _where(name, obj, modules)
        where = f":obj:`{target.rsplit('.', 1)[0]} <{target}>`" if target else ""
        out += [f"   * - ``acoustiviz.{name}``", f"     - {where}"]
    out.append("")
    group = None
    for m in modules:
        layer = "The package" if m == "acoustiviz" else _layer(m)
        if layer != group:
            out += ["", _title(layer, "-"), ".. toctree::", "   :maxdepth: 1", ""]
            group = layer
        out.append(f"   {m}")
    return "\n".join(out) + "\n"


_PIPES = re.compile(r"(?<![\\|\w])\|([^|\s`]|[^|\s`][^|`]*?[^|\s`])\|(?![|\w])")


def escape_pipes(app, what, name, obj, options, lines) -> None:
    """Let plain-text absolute values in docstrings (``|p|``) read as text, not as substitutions.

    Docstrings write the magnitude of ``p`` as ``|p|``; reST would take it for an undefined
    substitution. Pipes inside literals and roles (between backticks) are left alone.
    """
    for i, line in enumerate(lines):
        if "|" not in line:
            continue
        parts = re.split(r"(`+[^`]*`+)", line)
        lines[i] = "".join(part if part.startswith("`") else _PIPES.sub(r"\\|\1\\|", part) for part in parts)


def _write(path: Path, text: str) -> None:
    if not path.exists() or path.read_text(encoding="utf-8") != text:  # unchanged pages are not rebuilt
        path.write_text(text, encoding="utf-8")


def generate(app) -> None:
    """Write ``api/index.rst`` and one page per public module into the source folder."""
    out = Path(app.srcdir) / "api"
    out.mkdir(exist_ok=True)
    modules = public_modules()
    keep = {"index.rst"} | {f"{m}.rst" for m in modules}
    for stale in out.glob("*.rst"):
        if stale.name not in keep:
            stale.unlink()
    _write(out / "index.rst", index_page(modules))
    for m in modules:
        _write(out / f"{m}.rst", module_page(m))


def setup(app):
    """Register the generator."""
    app.connect("builder-inited", generate)
    app.connect("autodoc-process-docstring", escape_pipes)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
