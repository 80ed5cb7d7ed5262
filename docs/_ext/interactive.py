"""Interactive 3-D pages made at build time and shown in the user guide.

Writes ``interactive/balloon.html`` and ``interactive/snapshot.html`` (the self-contained pages
of :mod:`acoustiviz.output.html`) into ``docs/_interactive``, which is copied to the root of the
built site, so the guide can show them in frames. Each takes a second or two to compute.
"""

from __future__ import annotations

from pathlib import Path

PAGES = ("balloon.html", "snapshot.html")


def make_pages(folder: Path) -> list:
    """Write the interactive pages into ``folder``; return their paths."""
    from acoustiviz.app.impacts import impact_setup
    from acoustiviz.field.balloon import balloon_data
    from acoustiviz.field.sections import section_field
    from acoustiviz.output.html import write_balloon_html, write_snapshot_html

    corner = impact_setup(radius=0.01905, velocity=1.4, config="wall-floor", wall_distance=0.05)
    plane = impact_setup(radius=0.01905, velocity=1.4, config="plane")
    balloon = balloon_data(corner.pulse, corner.geometry, medium=corner.medium, n_theta=32)
    field = section_field(plane.pulse, plane.geometry, [0.25e-3, 0.5e-3, 0.75e-3, 1e-3, 1.25e-3],
                          medium=plane.medium, n_u=161)
    return [
        write_balloon_html(balloon, corner.pulse, corner.geometry, folder / "balloon.html"),
        write_snapshot_html(field, plane.pulse, plane.geometry, folder / "snapshot.html"),
    ]


def prepare_interactive(docs: Path) -> str:
    """Make the pages under ``docs/_interactive/interactive``; return ``"_interactive"`` for ``html_extra_path``."""
    folder = docs / "_interactive" / "interactive"
    folder.mkdir(parents=True, exist_ok=True)
    make_pages(folder)
    return "_interactive"
