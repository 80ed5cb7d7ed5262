"""The documentation site: its generators, and (where Sphinx is installed) a build with warnings as errors.

The generators (API pages, CLI reference, gallery source) are checked with the package alone.
The full build and the screenshots of the built pages run where the ``docs`` extra (and, for
the screenshots, Chromium) is installed; ``.ci/run`` builds the site the same way after the
tests.
"""

import argparse
import importlib
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

apipages = importlib.import_module("apipages")
cliref = importlib.import_module("cliref")
gallery_source = importlib.import_module("gallery_source")


def _all_parsers(parser, prog=()):
    yield prog, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _all_parsers(sub, (*prog, name))


def test_cli_reference_lists_every_subcommand_and_option():
    from acoustiviz.cli import build_parser

    text = "\n".join(cliref.reference_lines())
    parsers = list(_all_parsers(build_parser()))
    assert len(parsers) > 8
    for prog, parser in parsers[1:]:
        assert f".. _cli-{'-'.join(prog)}:" in text
        for action in parser._actions:
            if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)):
                continue
            for opt in action.option_strings:
                assert f"``{opt}" in text or f", {opt}" in text, (prog, opt)
    assert "``--vtk PATH``" in text and "acoustiviz render snapshot" in text


def test_cli_reference_escapes_markup():
    assert cliref.escape("a *b* |p| `c` d_") == r"a \*b\* \|p\| \`c\` d\_"


def test_api_pages_cover_the_public_modules():
    mods = apipages.public_modules()
    assert mods[0] == "acoustiviz"
    assert {"acoustiviz.core.contact", "acoustiviz.output.vtk", "acoustiviz.output.html"} <= set(mods)
    assert not [m for m in mods if ".cli" in m or "._" in m or m.endswith("__main__")]
    assert len(mods) == len(set(mods))
    # layers appear in import order: core before dynamics before output before app
    first = {layer: min(i for i, m in enumerate(mods) if m.split(".")[1:2] == [layer]) for layer in
             ("core", "dynamics", "output", "app")}
    assert first["core"] < first["dynamics"] < first["output"] < first["app"]
    page = apipages.module_page("acoustiviz.output")
    assert ".. automodule:: acoustiviz.output" in page and ":doc:`acoustiviz.output.vtk`" in page


def test_index_page_links_top_level_names_to_their_modules():
    import acoustiviz

    text = apipages.index_page(apipages.public_modules())
    assert "``acoustiviz.Impact``" in text
    assert "<acoustiviz.core.contact.Impact>" in text
    assert text.count("   * - ``acoustiviz.") == len(acoustiviz.__all__)


def test_absolute_value_bars_read_as_text():
    lines = ["peak |p| in Pa", "literal ``|p|`` kept", "| a | b |", "norm ||x|| kept", ":math:`|x|` kept"]
    apipages.escape_pipes(None, "function", "f", None, {}, lines)
    assert lines == [r"peak \|p\| in Pa", "literal ``|p|`` kept", "| a | b |", "norm ||x|| kept",
                     ":math:`|x|` kept"]


def test_gallery_source_shows_each_committed_figure(tmp_path):
    src = tmp_path / "gallery"
    src.mkdir()
    (src / "plot_01_x.py").write_text('"""\nA title that is long.\n===\n\nText.\n"""\n\nx = 1\n', encoding="utf-8")
    (src / "plot_02_nofig.py").write_text('"""\nOther\n=====\n"""\n', encoding="utf-8")
    (src / "_gallery.py").write_text("", encoding="utf-8")
    docs = tmp_path / "docs"
    (docs / "images").mkdir(parents=True)
    (docs / "images" / "plot_01_x.png").write_bytes(b"png")
    assert gallery_source.prepare_gallery(src, docs) == "_gallery_src"
    out = (docs / "_gallery_src" / "plot_01_x.py").read_text(encoding="utf-8")
    assert "A title that is long\n====================\n" in out  # underline fitted, full stop dropped
    assert ".. figure:: /images/plot_01_x.png" in out and out.index("figure::") < out.index('"""\n\nx = 1')
    assert out.rstrip().endswith('# sphinx_gallery_thumbnail_path = "images/plot_01_x.png"')
    assert "figure::" not in (docs / "_gallery_src" / "plot_02_nofig.py").read_text(encoding="utf-8")
    assert (docs / "_gallery_src" / "GALLERY_HEADER.rst").exists()


def test_every_gallery_script_has_a_committed_figure():
    for script in sorted((ROOT / "gallery").glob("plot_*.py")):
        assert (DOCS / "images" / f"{script.stem}.png").exists(), script.name


@pytest.mark.slow
def test_site_builds_without_warnings_and_renders(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("pydata_sphinx_theme")
    pytest.importorskip("sphinx_gallery")
    pytest.importorskip("numpydoc")
    pytest.importorskip("myst_parser")
    out = tmp_path / "html"
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("ACOUSTIVIZ_DOCS_RUN_GALLERY", None)
    res = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", "-d", str(tmp_path / "doctrees"),
                          str(DOCS), str(out)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=1200)
    assert res.returncode == 0, res.stderr[-4000:]
    for page in ("index.html", "cli.html", "api/index.html", "api/acoustiviz.output.vtk.html",
                 "auto_examples/index.html", "auto_examples/plot_02_directivity.html", "guide/outputs.html",
                 "interactive/balloon.html", "interactive/snapshot.html"):
        assert (out / page).exists(), page
    gallery_page = (out / "auto_examples" / "plot_09_balloon.html").read_text(encoding="utf-8")
    assert "plot_09_balloon.png" in gallery_page and "render_balloon" in gallery_page  # its figure and its code
    spec = importlib.util.spec_from_file_location("screenshots", DOCS / "screenshots.py")
    shots = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(shots)
    if shots.find_chromium() is None:
        pytest.skip("Chromium is not installed: the site built, the screenshots were not taken")
    assert shots.main([str(out), "--out", str(tmp_path / "shots")]) == 0
    assert len(list((tmp_path / "shots").glob("*.png"))) == len(shots.PAGES)


def test_scene_reference_lists_every_key_with_the_tables_range():
    from acoustiviz.app.settings.render import BALLOON

    text = "\n".join(cliref.scene_reference_lines())
    assert ".. _cli-scene-keys:" in text and "[outputs.balloon]" in text
    n_theta = next(s for s in BALLOON if s.name == "n_theta")
    assert f"n_theta = an integer in {n_theta.range_text()}" in text
