"""Every module says in the first line of its docstring what it holds (docs/module_tree.py prints them)."""

import importlib.util
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"
spec = importlib.util.spec_from_file_location("module_tree", DOCS / "module_tree.py")
module_tree = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module_tree)

ROWS = module_tree.modules()


def test_the_tree_holds_every_module():
    files = sorted(module_tree.ROOT.rglob("*.py"))
    assert len(ROWS) == len(files) > 100
    assert ROWS[0][0] == "acoustiviz"
    assert "acoustiviz.field._peak_kernels" in {name for name, _, _ in ROWS}


@pytest.mark.parametrize("name,lines,doc", ROWS, ids=[r[0] for r in ROWS])
def test_module_has_a_first_docstring_line(name, lines, doc):
    # a sentence of its own: not empty, not a bare title, short enough for one line of the tree
    assert lines > 0
    assert len(doc.split()) >= 3, f"{name}: the docstring's first line {doc!r} does not say what the module holds"
    assert len(doc) <= 160


def test_main_prints_one_line_per_module(capsys):
    assert module_tree.main([]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == len(ROWS) + 1
    assert out[-1].startswith(f"{len(ROWS)} modules")
