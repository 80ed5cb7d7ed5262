"""save_figure draws a constrained-layout PNG once and writes what Figure.savefig writes."""

import numpy as np
import pytest
from matplotlib.figure import Figure

from acoustiviz.output.plot.style import save_figure, style

Image = pytest.importorskip("PIL.Image")


def _figure(kind):
    """A constrained-layout figure of the kinds the package draws (lines and legend, image and colour bar)."""
    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    if kind == "lines":
        ax = fig.add_subplot()
        t = np.linspace(0.0, 0.02, 2001)
        ax.plot(t, np.sin(2 * np.pi * 440.0 * t) * np.exp(-200.0 * t), label="p (Pa)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("pressure (Pa)")
        ax.set_title("a decaying tone")
        ax.legend()
    else:
        axes = fig.subplots(1, 2)
        z = np.add.outer(np.linspace(-1.0, 1.0, 40), np.linspace(-1.0, 1.0, 60) ** 2)
        for ax in axes:
            im = ax.pcolormesh(z)
            fig.colorbar(im, ax=ax, label="level (dB)")
        fig.suptitle("two maps")
    return fig


def _pixels(path):
    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))


@pytest.mark.parametrize("kind", ["lines", "maps"])
def test_png_is_the_one_savefig_writes(tmp_path, kind):
    with style():
        ref = _figure(kind)
        ref.savefig(tmp_path / "ref.png")  # matplotlib's own path: a layout-only draw, then the real one
        fig = _figure(kind)
        out = save_figure(fig, tmp_path / "out.png")
    assert out == tmp_path / "out.png"
    a, b = _pixels(tmp_path / "ref.png"), _pixels(out)
    assert a.shape == b.shape
    assert np.array_equal(a, b)


def test_figure_keeps_its_layout_engine_and_dpi(tmp_path):
    with style():
        fig = _figure("lines")
        engine, dpi = fig.get_layout_engine(), fig.dpi
        save_figure(fig, tmp_path / "a.png")
        assert fig.get_layout_engine() is engine
        assert fig.dpi == dpi
        save_figure(fig, tmp_path / "b.png")  # saved again: the same picture
    assert np.array_equal(_pixels(tmp_path / "a.png"), _pixels(tmp_path / "b.png"))


def test_figure_without_axes_and_other_formats(tmp_path):
    with style():
        empty = Figure(figsize=(2.0, 1.0), layout="constrained")
        empty.text(0.5, 0.5, "no axes")
        save_figure(empty, tmp_path / "empty.png")
        svg = save_figure(_figure("lines"), tmp_path / "lines.svg")
    assert _pixels(tmp_path / "empty.png").shape == (150, 300, 4)  # 2 x 1 in at savefig.dpi 150
    assert svg.read_text().lstrip().startswith("<?xml")
