"""Matplotlib figures. Each function takes ``ax=None`` and returns the Axes it drew on.

Submodules are imported on demand (``from acoustiviz.output.plot.waveform import plot_waveform``) so
that importing :mod:`acoustiviz` never imports matplotlib. Plot functions style themselves
inside :func:`acoustiviz.output.plot.style.style` and leave global matplotlib state alone.
"""
