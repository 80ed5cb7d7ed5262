"""The top-level API: every public function and class shows itself at work in a doctest.

The names are those ``acoustiviz/__init__.py`` imports and those it exports lazily (``_LAZY``);
their ``Examples`` sections run with the test suite (``--doctest-modules`` over the package).
"""

import doctest
import inspect
import re
import tomllib
from pathlib import Path

import pytest

import acoustiviz

ROOT = Path(__file__).resolve().parents[1]
#: numpydoc section headings, in the order numpydoc prescribes (Examples last).
SECTIONS = ("Parameters", "Attributes", "Returns", "Yields", "Receives", "Other Parameters", "Raises",
            "Warns", "Warnings", "See Also", "Notes", "References", "Examples")


def _public_callables():
    names = sorted(set(acoustiviz.__all__) | set(acoustiviz._LAZY))
    out = []
    for name in names:
        obj = getattr(acoustiviz, name)
        if inspect.isfunction(obj) or inspect.isclass(obj):
            out.append(name)
    return out


PUBLIC = _public_callables()


def _headings(doc: str) -> list:
    """Section headings of a numpydoc docstring (a title line underlined by dashes)."""
    return re.findall(r"^[ \t]*([A-Z][A-Za-z ]+)\n[ \t]*-{3,}[ \t]*$", doc, flags=re.M)


def test_the_top_level_api_is_what_the_package_exports():
    # the list below is not empty and holds both eagerly imported and lazily exported names
    assert "contact_duration" in PUBLIC and "run_scene" in PUBLIC
    assert len(PUBLIC) >= 30


@pytest.mark.parametrize("name", PUBLIC)
def test_every_public_name_has_a_doctest_in_its_examples_section(name):
    obj = getattr(acoustiviz, name)
    doc = inspect.cleandoc(obj.__doc__ or "")  # its own docstring, not one inherited from a base class
    heads = _headings(doc)
    assert "Examples" in heads, f"{name}: no numpydoc 'Examples' section"
    assert heads[-1] == "Examples", f"{name}: 'Examples' must be the last section, got {heads}"
    known = [h for h in heads if h in SECTIONS]
    assert known == sorted(known, key=SECTIONS.index), f"{name}: sections out of numpydoc order: {heads}"
    examples = doc.split("Examples\n--------", 1)[1]
    assert doctest.DocTestParser().get_examples(examples), f"{name}: its Examples section has no doctest"


def test_doctests_run_with_the_test_suite():
    """pytest collects the package's doctests, so the examples above are run, not only present."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))["tool"]["pytest"]["ini_options"]
    assert "--doctest-modules" in config["addopts"].split()
    assert "acoustiviz" in config["testpaths"]
