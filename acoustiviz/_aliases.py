"""Old import paths kept working: ``acoustiviz.contact`` is ``acoustiviz.core.contact``, and so on.

The package is laid out in layer folders (``core``, ``dynamics``, ``field``, ``output``, ``app``,
``scene``, ``cli``); the flat names it had before stay importable as aliases of the moved modules
(the very same module objects, imported on first use). New code imports the new paths.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys

__all__ = ["ALIASES", "install"]

#: Old module path (below ``acoustiviz.``) -> where it lives now.
ALIASES = {
    "medium": "core.medium",
    "materials": "core.materials",
    "contact": "core.contact",
    "radiation": "core.radiation",
    "images": "core.images",
    "approximations": "core.approximations",
    "plot": "output.plot",
    "render": "output.render",
    "audio": "output.audio",
    "_io": "output.writers",
    "pipeline": "app.pipeline",
    "grids": "field.grids",
}


def _target(fullname: str):
    """The new full name of an aliased module path, or None."""
    prefix = __package__ + "."
    if not fullname.startswith(prefix):
        return None
    rest = fullname[len(prefix):]
    head, _, tail = rest.partition(".")
    if head not in ALIASES:
        return None
    return prefix + ALIASES[head] + ("." + tail if tail else "")


class _AliasLoader(importlib.abc.Loader):
    """Loads an alias as the module it points to (the same object, not a copy)."""

    def __init__(self, target: str):
        self.target = target
        self._spec = None

    def create_module(self, spec):  # noqa: D102
        module = importlib.import_module(self.target)
        self._spec = module.__spec__
        return module

    def exec_module(self, module):  # noqa: D102
        module.__spec__ = self._spec  # the import system set the alias's spec; give the real one back


class _AliasFinder(importlib.abc.MetaPathFinder):
    """Finds the old module paths of :data:`ALIASES`."""

    def find_spec(self, fullname, path=None, target=None):  # noqa: D102
        new = _target(fullname)
        if new is None:
            return None
        return importlib.util.spec_from_loader(fullname, _AliasLoader(new))


def install() -> None:
    """Put the alias finder first on :data:`sys.meta_path` (once)."""
    if not any(isinstance(f, _AliasFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, _AliasFinder())
