"""Print the package tree: each module's dotted path, line count and the first line of its docstring.

Run from the repository root: ``python docs/module_tree.py`` (or give the package directory).
The modules are read as text, never imported.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent / "acoustiviz"


def first_line(path: Path) -> str:
    """The first non-empty line of a module's docstring ('' when it has none)."""
    doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")))
    for line in (doc or "").splitlines():
        if line.strip():
            return line.strip()
    return ""


def modules(root: Path = ROOT) -> list[tuple[str, int, str]]:
    """``(dotted path, lines, first docstring line)`` of every module under ``root``, sorted by path."""
    rows = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root.parent).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
        with path.open(encoding="utf-8") as fh:
            lines = sum(1 for _ in fh)
        rows.append((".".join(parts), lines, first_line(path)))
    return rows


def main(argv: list[str] | None = None) -> int:
    """Print one line per module, indented by its depth in the package."""
    args = sys.argv[1:] if argv is None else argv
    root = Path(args[0]).resolve() if args else ROOT
    rows = modules(root)
    width = max(len("  " * (name.count(".")) + name.rsplit(".", 1)[-1]) for name, _, _ in rows)
    for name, lines, doc in rows:
        label = "  " * name.count(".") + name.rsplit(".", 1)[-1]
        print(f"{label:<{width}}  {lines:5d}  {doc}")
    print(f"{len(rows)} modules, {sum(r[1] for r in rows)} lines")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
