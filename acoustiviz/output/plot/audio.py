"""Figures of auralised signals: pressure waveforms (Pa against s) and spectrograms (dB re 20 µPa)."""

from __future__ import annotations

import numpy as np

from ...constants import P_REF
from ...core.signal import Signal
from .style import new_axes, style

__all__ = ["plot_pressure_signal", "plot_spectrogram", "auralisation_figure"]


def _samples(signal) -> np.ndarray:
    """The samples in Pa of a one-channel :class:`Signal` of at least two samples."""
    from ..._validate import ParameterError

    if not isinstance(signal, Signal) or signal.channels != 1 or signal.n_samples < 2:
        raise ParameterError("signal", "expected a one-channel acoustiviz.Signal of pressure in Pa (>= 2 samples)")
    return signal.as_channels()[0]


def plot_pressure_signal(signal: Signal, ax=None, *, label=None, title=None, **line_kwargs):
    """Plot a sampled pressure signal against time.

    Parameters
    ----------
    signal : Signal
        One channel of pressure in Pa; drawn against its sample times in s (:attr:`Signal.times`).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure is made when omitted.
    label, title : str, optional
        Legend label and axes title.
    **line_kwargs
        Passed to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> ax = plot_pressure_signal(Signal(np.zeros(480), 48000))
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('time (s)', 'sound pressure (Pa)')
    """
    x = _samples(signal)
    t = signal.times
    with style():
        ax = new_axes(ax)
        kw = {"lw": 0.6, **line_kwargs}
        ax.plot(t, x, label=label, **kw)
        ax.axhline(0.0, color="0.6", lw=0.5, zorder=0)
        ax.set_xlim(t[0], t[-1])
        ax.set_xlabel("time (s)")
        ax.set_ylabel("sound pressure (Pa)")
        if title:
            ax.set_title(title)
        if label:
            ax.legend(loc="upper right")
    return ax


def _segment_samples(n: int, fs: float, segment) -> int:
    """Samples per segment: ``segment`` s, or by default 5 ms or 1/400 of the signal, whichever is longer."""
    seg = max(0.005, n / fs / 400.0) if segment is None else float(segment)
    return max(16, min(n, int(round(seg * fs))))


def plot_spectrogram(signal: Signal, ax=None, *, segment=None, dynamic_range: float = 70.0,
                     vmax=None, title=None, colorbar: bool = True):
    """Draw a spectrogram: band level in dB re 20 µPa against time (s) and frequency (kHz).

    Parameters
    ----------
    signal : Signal
        One channel of pressure in Pa; segment times in s on the signal's axis.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure is made when omitted.
    segment : float, optional
        Length of each Hann-windowed segment in s (half overlapping); the bands are ``1/segment`` Hz wide.
        Default: 5 ms, or 1/400 of the signal if longer (so that every click shows at any length).
    dynamic_range : float
        Colour range in dB below ``vmax``.
    vmax : float, optional
        Top of the colour range in dB (default: the largest level), to share a scale between plots.
    title : str, optional
        Axes title.
    colorbar : bool
        Add a colour bar labelled in dB re 20 µPa.

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    Level of band k: ``10 log10(PSD_k Δf / p_ref²)``, the mean-square pressure of the segment in a band of
    width ``Δf = sample_rate / n_per_segment`` (scipy's Welch density scaling), so a steady tone reads its
    SPL. Short clicks read lower than their peak SPL: their energy is spread over the segment.

    Examples
    --------
    >>> fs = 48000
    >>> ax = plot_spectrogram(Signal(np.sin(2 * np.pi * 1000 * np.arange(fs // 10) / fs), fs))
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('time (s)', 'frequency (kHz)')
    """
    from scipy.signal import spectrogram

    x, fs = _samples(signal), signal.sample_rate
    nper = _segment_samples(x.size, fs, segment)
    f, t, sxx = spectrogram(x, fs=fs, window="hann", nperseg=nper, noverlap=nper // 2, scaling="density",
                            mode="psd")
    df = fs / nper
    level = 10.0 * np.log10(np.maximum(sxx * df, 1e-30) / P_REF**2)
    top = float(level.max()) if vmax is None else float(vmax)
    with style():
        ax = new_axes(ax)
        mesh = ax.pcolormesh(signal.start + t, f / 1e3, level, shading="auto", cmap="magma",
                             vmin=top - dynamic_range, vmax=top, rasterized=True)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("frequency (kHz)")
        ax.set_ylim(0.0, fs / 2e3)
        ax.grid(False)
        if title:
            ax.set_title(title)
        if colorbar:
            cb = ax.figure.colorbar(mesh, ax=ax, pad=0.01)
            cb.set_label(f"level in {df:.0f} Hz bands, {nper / fs * 1e3:.0f} ms (dB re 20 µPa)")
    return ax


def auralisation_figure(signals, *, labels=None, segment=None, dynamic_range: float = 70.0,
                        time_range=None, zoom: float | None = 0.004):
    """One row per signal: its waveform (Pa against s), its loudest click, and its spectrogram.

    Rows share one pressure scale and one colour scale, so the signals compare at a glance.

    Parameters
    ----------
    signals : sequence of Signal
        One-channel pressure signals in Pa, each at its own rate.
    labels : sequence of str, optional
        A heading per row.
    segment, dynamic_range : float, optional
        See :func:`plot_spectrogram`.
    time_range : (float, float), optional
        Time limits in s of the waveform and spectrogram panels (default: the whole signals).
    zoom : float or None
        Width in s of a middle panel centred on each signal's largest sample (time in ms); None omits it.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from scipy.signal import spectrogram

    signals = list(signals)
    samples = [_samples(s) for s in signals]
    labels = list(labels) if labels is not None else [f"signal {i + 1}" for i in range(len(signals))]
    n = len(signals)
    ncol = 3 if zoom else 2
    widths = [1.0, 0.45, 1.25] if zoom else [1.0, 1.25]
    lim = max(float(np.max(np.abs(s), initial=0.0)) for s in samples) * 1.08 or 1.0
    vmax = -np.inf
    for sig, s in zip(signals, samples, strict=True):  # a shared top level so the colours compare across rows
        fs = sig.sample_rate
        nper = _segment_samples(s.size, fs, segment)
        _, _, sxx = spectrogram(s, fs=fs, window="hann", nperseg=nper, noverlap=nper // 2)
        vmax = max(vmax, 10.0 * np.log10(max(float(sxx.max()) * fs / nper, 1e-30) / P_REF**2))
    with style():
        fig = Figure(figsize=(12.5 if zoom else 11.0, 3.1 * n + 0.5), layout="constrained")
        rows = fig.subfigures(n, 1, squeeze=False)[:, 0]
        for row, sig, s, lab, color in zip(rows, signals, samples, labels, ("C0", "C3", "C2", "C1") * n,
                                           strict=False):
            fs = sig.sample_rate
            axes = row.subplots(1, ncol, gridspec_kw={"width_ratios": widths})
            pk = float(np.max(np.abs(s), initial=0.0))
            spl = 20 * np.log10(pk / P_REF) if pk > 0 else float("nan")
            row.suptitle(f"{lab} -- peak {pk:.2f} Pa, {spl:.1f} dB re 20 µPa", fontsize=11)
            wa, sa = axes[0], axes[-1]
            plot_pressure_signal(sig, ax=wa, color=color)
            wa.set_ylim(-lim, lim)
            wa.set_title("whole run")
            if zoom:
                za = axes[1]
                k = int(np.argmax(np.abs(s)))
                half = int(round(zoom * fs / 2))
                lo, hi = max(k - half, 0), min(k + half, s.size)
                t_ms = (sig.start + np.arange(lo, hi) / fs) * 1e3
                za.plot(t_ms, s[lo:hi], color=color, lw=1.0, marker=".", ms=2.5)
                za.axhline(0.0, color="0.6", lw=0.5, zorder=0)
                za.set_xlim(t_ms[0], t_ms[-1])
                za.set_ylim(-lim, lim)
                za.set_xlabel("time (ms)")
                za.set_ylabel("sound pressure (Pa)")
                za.set_title("loudest click")
            plot_spectrogram(sig, ax=sa, segment=segment, dynamic_range=dynamic_range, vmax=vmax,
                             title="spectrogram")
            if time_range is not None:
                wa.set_xlim(*time_range)
                sa.set_xlim(*time_range)
    return fig
