"""Open pages in headless Chromium and save screenshots, as a reader would see them.

Usage::

    python docs/screenshots.py docs/_build/html --out docs/_build/screenshots

takes screenshots of the built site's index page and four gallery pages, and fails (exit
status 1) when a page is blank. Without Chromium it says so and exits 0. The functions are
also used by the tests of the HTML export.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

#: Pages of the built site that are looked at: the front page and four gallery examples.
PAGES = ("index.html", "auto_examples/plot_02_directivity.html", "auto_examples/plot_09_balloon.html",
         "auto_examples/plot_13_frequency_response.html", "auto_examples/plot_14_levels.html")

_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def find_chromium():
    """Path of a Chromium (or Chrome) executable, or None."""
    for name in _NAMES:
        path = shutil.which(name)
        if path:
            return path
    return None


def _run(args, timeout):
    browser = find_chromium()
    if browser is None:
        raise RuntimeError("no Chromium found")
    with tempfile.TemporaryDirectory() as profile:
        cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu-sandbox", "--disable-dev-shm-usage",
               "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--hide-scrollbars", "--mute-audio",
               "--no-first-run", "--disable-extensions", "--disable-background-networking",
               f"--user-data-dir={profile}", *args]
        env = dict(os.environ)
        env.pop("DISPLAY", None)
        return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, check=False)


def screenshot(url: str, out, *, size=(1280, 900), wait_ms: int = 4000, timeout: float = 120.0) -> Path:
    """Save a PNG screenshot of ``url`` (``file://`` or ``http://``) at ``size`` pixels to ``out``."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    if out.exists():
        out.unlink()
    proc = _run([f"--window-size={size[0]},{size[1]}", f"--virtual-time-budget={wait_ms}",
                 f"--screenshot={out}", url], timeout)
    if not out.exists():
        raise RuntimeError(f"Chromium wrote no screenshot of {url}: {proc.stderr[-2000:]}")
    return out


def dom(url: str, *, wait_ms: int = 4000, timeout: float = 120.0) -> str:
    """The page's DOM after its scripts ran for ``wait_ms`` of virtual time."""
    proc = _run([f"--virtual-time-budget={wait_ms}", "--dump-dom", url], timeout)
    return proc.stdout


def blankness(png) -> dict:
    """How much a screenshot shows: number of distinct colours and the share of non-white pixels."""
    import numpy as np
    from PIL import Image

    with Image.open(png) as im:
        rgb = np.asarray(im.convert("RGB")).reshape(-1, 3)
    return {"colours": int(len(np.unique(rgb, axis=0))), "ink": float(np.mean(np.any(rgb < 235, axis=1)))}


def main(argv=None) -> int:
    """Screenshot the built site's pages; exit status 1 if one is blank."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("site", help="folder of the built HTML site (docs/_build/html)")
    p.add_argument("--out", default="docs/_build/screenshots", help="folder for the PNG files")
    args = p.parse_args(argv)
    if find_chromium() is None:
        print("screenshots: no Chromium installed; skipped")
        return 0
    site = Path(args.site).resolve()
    bad = 0
    for page in PAGES:
        path = site / page
        if not path.exists():
            print(f"screenshots: missing page {path}")
            bad += 1
            continue
        out = Path(args.out) / (page.replace("/", "_").removesuffix(".html") + ".png")
        screenshot(path.as_uri(), out)
        b = blankness(out)
        ok = b["colours"] > 200 and b["ink"] > 0.02
        bad += not ok
        print(f"{'ok' if ok else 'BLANK'}: {out} ({b['colours']} colours, {100 * b['ink']:.0f}% ink)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
