"""Peaks and exposure of one impact in a room (many image sources), checked against independent references.

Past :data:`acoustiviz.field.peaks.PULSE_TABLE_ABOVE` sources :func:`acoustiviz.field.fast_peaks`
tabulates the pulse only and searches the sorted arrivals (the images' decays as one running sum),
and past :data:`acoustiviz.field.exposure.PAIRS_ABOVE` the exposure sums the pairs further apart
than the pulse as one running sum. References: the sampled and Brent-refined search of
:func:`acoustiviz.field.field_metrics`, the closed form (:func:`acoustiviz.core.radiation.pulse_response`
summed over the images) at the reported times, the windowed search over the whole delay spread,
and the exposure summed over every pair of images.
"""

import dataclasses
import sys

import numpy as np
import pytest

import acoustiviz.field  # noqa: F401 - the package, for its modules below
from acoustiviz.core.radiation import pulse_response
from acoustiviz.core.room_geometry import Room
from acoustiviz.field import exposure, fast_peaks, field_metrics, peak_table, source_geometry

A = 0.01905  # the paper's sphere, m
DIMS = (6.0, 4.0, 3.0)
PEAKS = sys.modules["acoustiviz.field.peaks"]
EXPOSURE = sys.modules["acoustiviz.field.exposure"]


def _points(n, seed):
    return np.random.default_rng(seed).uniform(0.05, 1.0, (n, 3)) * (np.array(DIMS) - 0.05)


def _closed_form(pulse, room, pts, when):
    """Pressure in Pa at each point at its time ``when``, summed over the images (vectorised closed form)."""
    delay, p0, cc, _ = source_geometry(pts, room)
    y = pulse_response(pulse, when[:, None] - delay, radius=A)
    return np.sum(p0 * (cc.real * y.real - cc.imag * y.imag), axis=1)


@pytest.mark.parametrize("kind", ["half-sine", "hertz", "impulse-matched"])
def test_room_peaks_equal_the_refined_field_metrics_and_the_closed_form(kind, monkeypatch, paper_pulse):
    """Order 4 (129 images): each peak is the pressure at its time (closed form, 1e-10 of the peak), never
    below field_metrics' refined peak by more than 1e-8 and nearly always equal to it."""
    room = Room(A, DIMS, 0.1, (2.0, 1.5, A), order=4)
    assert room.image_count > PEAKS.PULSE_TABLE_ABOVE
    pulse = paper_pulse(kind)
    pts = np.vstack([_points(10, 3), [[5.97, 3.96, 0.03], [0.04, 3.97, 2.96], [2.0, 1.5, 0.3]]])
    fp = fast_peaks(pulse, pts, room)
    fm = field_metrics(pulse, pts, room)
    scale = fm.peak
    for got, ref, when, sign in ((fp.peak_positive, fm.peak_positive, fp.time_positive, 1.0),
                                 (fp.peak_negative, fm.peak_negative, fp.time_negative, -1.0)):
        assert np.all(sign * (got - ref) >= -1e-8 * scale)
        assert np.all(np.abs(got - _closed_form(pulse, room, pts, when)) <= 1e-10 * scale)
        assert np.mean(np.abs(got - ref) <= 1e-8 * scale) > 0.9
    # the exposure against the sum over every pair of images
    monkeypatch.setattr(EXPOSURE, "PAIRS_ABOVE", 10**9)
    np.testing.assert_allclose(fp.exposure, exposure(pulse, pts, room), rtol=1e-11)


@pytest.mark.slow
def test_room_peaks_equal_the_windowed_search(monkeypatch, paper_pulse):
    """The sorted-arrival search and the windowed search over the whole delay spread (tables over it)
    find the same peaks to 1e-10 (both refine the closed form to ~1e-11), here at order 5."""
    room = Room(A, DIMS, 0.1, (2.0, 1.5, A), order=5)
    pulse = paper_pulse()
    pts = _points(16, 11)
    dense = fast_peaks(pulse, pts, room, exposure=False, table=peak_table(pulse, room))
    assert peak_table(pulse, room).pulse_only
    monkeypatch.setattr(PEAKS, "PULSE_TABLE_ABOVE", 10**9)
    table = peak_table(pulse, room)
    assert not table.pulse_only and table.spread > 0.0
    windowed = fast_peaks(pulse, pts, room, exposure=False, table=table)
    np.testing.assert_allclose(dense.peak_positive, windowed.peak_positive, rtol=1e-10)
    np.testing.assert_allclose(dense.peak_negative, windowed.peak_negative, rtol=1e-10)


@pytest.mark.slow
def test_a_late_arrival_sets_the_peak_in_a_rigid_room(paper_pulse):
    """A rigid room, the listener level with the sphere's centre (the direct sound's and the floor image's
    dipole null) in a far corner: the peak comes long after the first arrival and is found there
    (closed form at its time; a dense 1 us scan of the closed form finds nothing higher)."""
    room = Room(A, DIMS, 0.0, (2.0, 1.5, A), order=4)
    pulse = paper_pulse()
    pts = np.array([[5.9, 3.9, A], [0.1, 3.9, A]])
    fp = fast_peaks(pulse, pts, room)
    delay, _, _, _ = source_geometry(pts, room)
    first = delay.min(axis=1)
    assert np.all(fp.time_positive > first + 5 * pulse.duration)  # a late arrival: not the direct sound
    for i, p in enumerate(pts):
        t = np.arange(first[i], delay[i].max() + 3 * pulse.duration, 1e-6)
        scan = np.concatenate([_closed_form(pulse, room, np.repeat(p[None], c.size, 0), c)
                               for c in np.array_split(t, max(1, t.size // 4000))])
        peak = fp.peak_positive[i]
        assert scan.max() <= peak * (1 + 1e-9)
        assert scan.max() >= peak * (1 - 1e-3)  # the scan's own sampling error near the maximum
        assert -scan.min() <= -fp.peak_negative[i] * (1 + 1e-9)


def test_half_sine_correlations_in_closed_form_equal_the_quadrature(paper_pulse):
    """The half-sine's G and H on [0, T] as sums of exponentials in the lag equal the Gauss-Legendre
    quadrature's Chebyshev series of pulse_correlations (an independent computation) to 1e-13."""
    corr = EXPOSURE.pulse_correlations(paper_pulse(), A)
    t = corr.lag_terms
    assert t.size == 12
    tau, s = corr.duration, corr.pole
    w = np.pi / tau
    lag = np.linspace(0.0, tau, 301)
    g = (t[0] * np.exp(s * lag) + t[2] * np.exp(s * (tau - lag)) + (t[4] + t[5] * lag) * np.exp(1j * w * lag)
         + (t[6] + t[7] * lag) * np.exp(-1j * w * lag))
    h = (t[1] * np.exp(np.conj(s) * lag) + t[3] * np.exp(s * (tau - lag)) + (t[8] + t[9] * lag) * np.exp(1j * w * lag)
         + (t[10] + t[11] * lag) * np.exp(-1j * w * lag))
    g_ref, h_ref = corr.series(lag)
    assert np.max(np.abs(g - g_ref)) <= 1e-13 * np.max(np.abs(g_ref))
    assert np.max(np.abs(h - h_ref)) <= 1e-13 * np.max(np.abs(h_ref))
    assert EXPOSURE.pulse_correlations(paper_pulse("hertz"), A).lag_terms.size == 0  # the table for other pulses


def _exact_exposure(pulse, room, pt, corr):
    """``∫ p² dt`` at one point summed over every pair of images, ``G`` and ``H`` from the Chebyshev series
    of the Gauss-Legendre quadrature on ``[0, T]`` and their closed-form exponentials past ``T``."""
    delay, p0, cc, _ = source_geometry(pt[None, :], room)
    d, a = delay[0], p0[0] * cc[0]
    lag = d[None, :] - d[:, None]  # d_k - d_j
    j, k = np.nonzero(lag >= 0.0)
    keep = j != k
    j, k = j[keep], k[keep]
    x = lag[j, k]
    g = np.empty(x.size, complex)
    h = np.empty(x.size, complex)
    close = x < corr.duration
    g[close], h[close] = corr.series(x[close])
    e = corr.y_end * np.exp(corr.pole * (x[~close] - corr.duration))
    g[~close], h[~close] = e * corr.m_g, np.conj(e) * corr.m_h
    g0, h0 = corr.series(np.zeros(1))
    pairs = (a[k] * a[j] * g + a[k] * np.conj(a[j]) * h).real
    ties = lag[j, k] == 0.0  # equal delays: each pair counted from both sides
    own = 0.5 * np.sum((a * a * g0[0] + np.abs(a) ** 2 * h0[0]).real)
    return np.sum(pairs[~ties]) + 0.5 * np.sum(pairs[ties]) + own


def test_room_exposure_of_the_half_sine_in_closed_form_equals_every_pair(monkeypatch, paper_pulse):
    """Order 6 (377 images): the close pairs summed in closed form equal the exact sum over every pair
    of images (1e-12; the correlations from the quadrature's series), and the table's paths (1e-11)."""
    room = Room(A, DIMS, 0.1, (2.0, 1.5, A), order=6)
    pulse = paper_pulse()
    pts = np.vstack([_points(6, 5), [[5.97, 3.96, 0.03], [2.0, 1.5, 0.3]]])
    corr = EXPOSURE.pulse_correlations(pulse, A)
    closed = exposure(pulse, pts, room, correlations=corr)
    fp = fast_peaks(pulse, pts, room, correlations=corr)
    exact = np.array([_exact_exposure(pulse, room, p, corr) for p in pts])
    np.testing.assert_allclose(closed, exact, rtol=1e-12)
    np.testing.assert_allclose(fp.exposure, exact, rtol=1e-12)
    tabled = dataclasses.replace(corr, lag_terms=np.zeros(0, complex))
    np.testing.assert_allclose(exposure(pulse, pts, room, correlations=tabled), exact, rtol=1e-11)
    monkeypatch.setattr(EXPOSURE, "PAIRS_ABOVE", 10**9)
    np.testing.assert_allclose(exposure(pulse, pts, room, correlations=corr), exact, rtol=1e-11)
