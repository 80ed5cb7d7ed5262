"""Small field requests summed in numpy (field._closed) against the compiled kernels, and no compiling for them.

Both paths are forced on the same requests by setting ``SMALL_WORK`` to 0 (the kernels) or to a huge
value (numpy): two independent implementations of the same sums -- the kernels advance the closed form
sample by sample (recurrences, Taylor tables), numpy evaluates
:func:`acoustiviz.core.radiation.pulse_response` at every sample and refines the extremes with SciPy's
bounded Brent search -- which must agree to round-off, tail cut included.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from acoustiviz import field
from acoustiviz.core.geometry import images_free, images_plane, images_wall_floor
from acoustiviz.core.pulses import SampledPulse
from acoustiviz.core.radiation import sphere_pressure
from acoustiviz.field import _closed

ROOT = Path(__file__).resolve().parents[1]
A = 0.01905
CONFIGS = {"free": images_free(A), "plane": images_plane(A), "corner": images_wall_floor(A, 0.05)}
#: both paths sum the same closed form: they must agree far below any modelling error
RTOL = 1e-12


def _pulse(paper_pulse, kind):
    if kind == "sampled":  # a piecewise-linear pulse: 129 of the Hertz pulse's exact samples
        hertz = paper_pulse("hertz")
        return SampledPulse(hertz.times[::8].copy(), hertz.acceleration_samples[::8].copy())
    return paper_pulse(kind)


def _points(cfg):
    """Listeners near and far, above and beside the sphere, plus two outside the fluid (NaN)."""
    centre = cfg.sources[0].position
    pts = np.array([[0.0, 0.0, 0.3], [0.5, 0.1, 0.5], [0.3, -0.2, 0.1], [0.495, 0.0, A + 0.495],
                    [0.06, 0.02, 0.04], [0.1, 0.2, -0.05], centre])  # fmt: skip
    assert not np.all(cfg.in_fluid(pts)) and np.sum(cfg.in_fluid(pts)) >= 4
    return pts


def _both(monkeypatch, call):
    """``call()`` by the compiled kernels, then in numpy."""
    monkeypatch.setattr(_closed, "SMALL_WORK", 0)
    compiled = call()
    monkeypatch.setattr(_closed, "SMALL_WORK", 10**15)
    return compiled, call()


def _assert_same(got, ref):
    got, ref = np.asarray(got), np.asarray(ref)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(ref))
    scale = np.nanmax(np.abs(ref))
    assert scale > 0
    np.testing.assert_allclose(got, ref, rtol=RTOL, atol=RTOL * scale)


KINDS = ["half-sine", "hertz", "sampled"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", list(CONFIGS))
def test_small_time_series_equal_the_kernel(monkeypatch, kind, name, paper_pulse):
    cfg, pulse = CONFIGS[name], _pulse(paper_pulse, kind)
    pts = _points(cfg)
    # 8 ms: each image's kept tail ends inside the grid, where the cut drops ~1e-10 of Y(T)
    t = np.linspace(-1e-4, 8e-3, 4001)
    compiled, numpy_sum = _both(monkeypatch, lambda: field.time_series(pulse, t, pts, cfg))
    _assert_same(numpy_sum, compiled)
    blocks = _both(monkeypatch, lambda: np.vstack([b for _, _, b in field.iter_time_series(pulse, t, pts, cfg)]))
    _assert_same(blocks[1], blocks[0])


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", list(CONFIGS))
@pytest.mark.parametrize(
    "options",
    [{}, {"refine": False}, {"window": 1.2e-3}, {"t": np.linspace(1e-3, 7e-3, 3001)}],
    ids=["default-window", "samples-only", "short-window", "long-grid"],
)
def test_small_field_metrics_equal_the_kernel(monkeypatch, kind, name, options, paper_pulse):
    cfg, pulse = CONFIGS[name], _pulse(paper_pulse, kind)
    pts = _points(cfg)
    compiled, numpy_sum = _both(monkeypatch, lambda: field.field_metrics(pulse, pts, cfg, **options))
    for q in ("peak_positive", "peak_negative", "rms", "exposure", "window_start"):
        _assert_same(getattr(numpy_sum, q), getattr(compiled, q))
    assert numpy_sum.window == compiled.window and numpy_sum.sample_interval == compiled.sample_interval


def test_the_numpy_sum_cuts_each_tail_where_the_kernel_does(monkeypatch, paper_pulse):
    """The cut is seen: both differ from the uncut direct sum by ~1e-11 of the peak (the half-sine's Y(T) is large)."""
    cfg, pulse = CONFIGS["plane"], _pulse(paper_pulse, "half-sine")
    pts = _points(cfg)[:4]
    t = np.linspace(-1e-4, 8e-3, 4001)
    compiled, numpy_sum = _both(monkeypatch, lambda: field.time_series(pulse, t, pts, cfg))
    uncut = sum(sphere_pressure(pulse, t, pts, radius=A, centre=s.position, axis=s.axis) for s in cfg.sources)
    scale = np.max(np.abs(uncut))
    for got in (compiled, numpy_sum):
        assert 1e-12 * scale < np.max(np.abs(got - uncut)) < 1e-9 * scale
    # a non-uniform grid (one time dropped) is summed in numpy with the same cut, at the same times
    keep = np.arange(t.size) != 1234
    monkeypatch.setattr(_closed, "SMALL_WORK", 0)
    np.testing.assert_allclose(field.time_series(pulse, t[keep], pts, cfg), compiled[:, keep], rtol=0,
                               atol=RTOL * scale)


def test_a_small_request_compiles_no_kernel(tmp_path):
    """One point's series and metrics on an empty numba cache leave both field kernels uncompiled."""
    probe = (
        "import numpy as np\n"
        "from acoustiviz import field\n"
        "from acoustiviz.core.contact import Impact, acceleration_pulse\n"
        "from acoustiviz.core.geometry import images_plane\n"
        "from acoustiviz.field._kernels import _metrics_kernel, _series_kernel\n"
        f"a = {A!r}\n"
        "pulse = acceleration_pulse(Impact(1.4, 5.6e8, 7800 * 4 / 3 * np.pi * a**3), 'hertz')\n"
        "cfg, pt = images_plane(a), [[0.495, 0.0, a + 0.495]]\n"
        "p = field.time_series(pulse, np.arange(3662) * 1e-6, pt, cfg)\n"
        "m = field.field_metrics(pulse, pt, cfg)\n"
        "assert np.all(np.isfinite(p)) and m.peak[0] > 0\n"
        "print(len(_series_kernel.signatures), len(_metrics_kernel.signatures))\n"
    )
    env = {"PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "HOME": str(tmp_path),
           "PATH": os.defpath}  # fmt: skip
    out = subprocess.run([sys.executable, "-c", probe], env=env, cwd=tmp_path, capture_output=True, text=True,
                         timeout=300)  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["0", "0"]
