"""The gallery's source for sphinx-gallery: the scripts of ``gallery/``, each shown with its figure.

By default the scripts are not run (the build takes seconds): each page shows the script's
text and code and, below its introduction, the committed figure ``docs/images/<script>.png``
that the script makes with its full settings; the same figure is the thumbnail. With
``run=True`` sphinx-gallery runs every script and :func:`scraper` collects the PNG files the
script writes into its output folder (``$ACOUSTIVIZ_GALLERY_DIR``).
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from pathlib import Path

HEADER = """Gallery
=======

Each example is a script of the ``gallery/`` folder that runs alone
(``python gallery/plot_01_impact_waveform.py``) and writes its figures and data into
``gallery/_output/`` (or ``$ACOUSTIVIZ_GALLERY_DIR``). The paper's Figures 2, 3, 5, 6 and 7 and
its Table 2 are reproduced; the others go beyond the paper. The test suite runs every script
in a fast mode (``ACOUSTIVIZ_FAST=1``), so an example that breaks fails the tests; the figures
shown here were made with the full settings.
"""

_DOC = re.compile(r'^(\s*(?:[rRuU])?""")(.*?)(""")', re.S)


def _underlines(text: str) -> str:
    """Lengthen title underlines (``===``) that are shorter than their title, which reST refuses."""
    lines = text.split("\n")
    for i in range(1, len(lines)):
        u = lines[i].strip()
        if u and len(set(u)) == 1 and u[0] in "=-~^" and len(u) >= 3 and lines[i - 1].strip():
            if u[0] == "=":  # the page title: no full stop at its end
                lines[i - 1] = lines[i - 1].rstrip().removesuffix(".")
            lines[i] = u[0] * len(lines[i - 1].strip())
    return "\n".join(lines)


def _with_figure(text: str, stem: str, docs: Path) -> str:
    figure = docs / "images" / f"{stem}.png"
    if not figure.exists():
        return text
    m = _DOC.search(text)
    if not m:
        return text
    title = next((ln.strip() for ln in m.group(2).splitlines() if ln.strip()), stem).rstrip(".")
    block = (f"\n.. figure:: /images/{stem}.png\n   :alt: {title}\n   :class: gallery-figure\n\n"
             f"   Made by this script with its full settings (``python gallery/{stem}.py``).\n")
    body = m.group(2).rstrip() + "\n" + block
    text = text[: m.start(2)] + body + text[m.end(2):]
    return text.rstrip() + f'\n\n# sphinx_gallery_thumbnail_path = "images/{stem}.png"\n'


def prepare_gallery(src: Path, docs: Path, *, run: bool = False) -> str:
    """Copy ``src`` into ``docs/_gallery_src`` for sphinx-gallery; return its path relative to ``docs``."""
    dest = docs / "_gallery_src"
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir()
    (dest / "GALLERY_HEADER.rst").write_text(HEADER, encoding="utf-8")
    for path in sorted(src.glob("*.py")):
        text = path.read_text(encoding="utf-8")
        if path.name.startswith("plot_"):
            m = _DOC.search(text)
            if m:
                text = text[: m.start(2)] + _underlines(m.group(2)) + text[m.end(2):]
            if not run:
                text = _with_figure(text, path.stem, docs)
        (dest / path.name).write_text(text, encoding="utf-8")
    if run:
        os.environ.setdefault("ACOUSTIVIZ_GALLERY_DIR", tempfile.mkdtemp(prefix="acoustiviz-gallery-"))
    return "_gallery_src"


_SEEN: set = set()


def scraper(block, block_vars, gallery_conf):
    """sphinx-gallery image scraper: the PNG files a script wrote into its output folder since the last block."""
    from sphinx_gallery.scrapers import figure_rst

    out = Path(os.environ["ACOUSTIVIZ_GALLERY_DIR"])
    new = sorted(p for p in out.glob("*.png") if p not in _SEEN)
    _SEEN.update(new)
    paths = []
    for p, target in zip(new, block_vars["image_path_iterator"], strict=False):
        shutil.copyfile(p, target)
        paths.append(target)
    return figure_rst(paths, gallery_conf["src_dir"])


def _get_sg_image_scraper():
    """The scraper, found by sphinx-gallery from this module's name in ``image_scrapers``."""
    return scraper
