"""The directivity figures: two or three polar panels, a half space or the whole circle, nothing clipped."""

import math

import numpy as np
import pytest

from acoustiviz.app.views import directivity_metric_figure
from acoustiviz.core.contact import Impact, acceleration_pulse
from acoustiviz.core.geometry import images_free, images_plane, images_wall_floor
from acoustiviz.field import directivity
from acoustiviz.output.plot.directivity import directivity_figure
from acoustiviz.output.plot.style import save_figure

RADIUS, DISTANCE = 0.01905, 0.7
#: Geometries whose levels span two- and three-digit radial labels (dB) and a decimal one (Pa).
GEOMETRIES = {"plane": images_plane(RADIUS), "wall-floor": images_wall_floor(RADIUS, 0.05), "free": images_free(RADIUS)}


def _directivity(geometry, half_space):
    impact = Impact(velocity=1.4, k_hertz=5.6e8, mass=7800.0 * 4 / 3 * math.pi * RADIUS**3)
    top = 90.0 if half_space else 180.0
    return directivity(acceleration_pulse(impact, "half-sine"), geometry, DISTANCE,
                       np.radians(np.arange(0.0, top + 1.0, 5.0)))


def _border(path):
    """The outermost row and column of pixels on each side of the PNG, as RGB in [0, 1]."""
    from matplotlib.image import imread

    img = imread(path)[..., :3]
    return np.concatenate([img[0], img[-1], img[:, 0], img[:, -1]])


@pytest.mark.parametrize("panels", [2, 3])
@pytest.mark.parametrize("config, half_space", [("plane", True), ("wall-floor", True), ("free", False)])
def test_no_label_reaches_the_edge_of_the_figure(tmp_path, config, half_space, panels):
    """A label cut by the figure's edge touches its border: the outermost pixels stay the white background.

    The radial labels of a polar axes cut to a quarter sit along its 0° edge, at the figure's left edge
    for the first panel (they were cut off there, and overlapped the next panel).
    """
    d = _directivity(GEOMETRIES[config], half_space)
    if panels == 2:
        fig = directivity_figure(d, title=f"{config}: a title", half_space=half_space)
    else:
        fig = directivity_metric_figure(d, d.spl_db - 35.0, "laeq", title=f"{config}: a title",
                                        half_space=half_space)
    assert len(fig.axes) == panels
    path = save_figure(fig, tmp_path / "d.png")
    edge = _border(path)
    assert np.all(edge > 0.99), f"{np.count_nonzero(np.any(edge <= 0.99, axis=1))} border pixels drawn on"
