"""docs/check_numbers.py: every figure the README and the guide quote from the program is rerun and checked."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = ROOT / "docs" / "check_numbers.py"


def _module():
    spec = importlib.util.spec_from_file_location("docs_numbers", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


def test_a_drifted_figure_is_reported_and_updated(tmp_path, monkeypatch):
    mod = _module()
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    (tmp_path / "page.md").write_text("the damper makes LAeq 80.0 dB and LCpeak 101.0 dB here\n")
    fig = mod.Figure("toy", "page.md", r"LAeq (?P<laeq>[\d.]+) dB and LCpeak (?P<peak>[\d.]+) dB",
                     lambda: {"laeq": "80.0", "peak": "100.5", "unused": "x"})
    assert mod.check([fig]) == [("toy", "peak", "101.0", "100.5")]
    assert mod.update([fig]) == ["page.md"]
    assert (tmp_path / "page.md").read_text() == "the damper makes LAeq 80.0 dB and LCpeak 100.5 dB here\n"
    assert mod.check([fig]) == []
    twice = mod.Figure("twice", "page.md", r"dB", lambda: {})
    with pytest.raises(LookupError):  # a pattern must point at one place
        mod.check([twice])


def test_every_registered_pattern_finds_its_text():
    mod = _module()
    for fig in mod.REGISTRY:
        mod._spans(fig, (ROOT / fig.file).read_text(encoding="utf-8"))


@pytest.mark.slow
def test_the_quoted_figures_are_what_the_program_gives():
    proc = subprocess.run([sys.executable, str(SCRIPT), "--check"], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_quoted_bounds_round_up_and_ranges_collapse():
    mod = _module()
    assert [mod._bound(x) for x in (2.2e-14, 6e-12, 9.95e-8, 1.7e-2)] == ["3e-14", "6e-12", "1e-7", "2e-2"]
    assert mod._range([1.17, 1.1, 1.13], ".2f") == "1.10-1.17"
    assert mod._range([2.04, 1.96], ".0f") == "2"
    rows = mod._rows("title\n  a  b  c\n-------\n x 1 2\n y 3 4 (default)\n note: a line longer than any row\n", "a  b")
    assert rows == [["x", "1", "2"], ["y", "3", "4", "(default)"]]
