"""The tables a waveform and a directivity write, and the peaks they report: one rule for the command line and scenes.

``acoustiviz waveform --csv`` and a scene's ``[outputs.waveform]`` write the same columns in the
same number format, and report the same peaks; so do ``acoustiviz directivity --csv`` and
``[outputs.directivity]``.

Number formats
--------------
Time is written with 13 significant digits (``%.12e``): a waveform's times are multiples of a step
of about T/400 (1.3 µs for the paper's sphere), and a reader who takes the step from the difference
of two late times (a room's window of 1 s holds 10^6 samples) keeps it to 1e-6 relative; with 11
digits it would keep only 1e-4. Pressures carry 11 significant digits (``%.10e``), far more than
the model's accuracy and enough to compare runs bit for bit. Directivity angles are written as
given (``%.6g`` of a step in degrees), levels in dB to 1e-6 dB.
"""

from __future__ import annotations

import numpy as np

from ..files import write_csv_atomic

__all__ = ["WAVEFORM_FORMATS", "DIRECTIVITY_FORMATS", "write_waveform_csv", "waveform_extremes",
           "write_directivity_csv"]

#: ``time_s`` and each pressure column of a waveform table.
WAVEFORM_FORMATS = ("%.12e", "%.10e")
#: ``angle_deg, peak_pa, rms_pa, spl_db`` and a further level in dB of a directivity table.
DIRECTIVITY_FORMATS = ("%.6g", "%.10e", "%.10e", "%.6f", "%.6f")


def write_waveform_csv(path, times, pressures, names):
    """Write ``time_s`` and one pressure column per entry of ``names`` atomically; return the path.

    Parameters
    ----------
    path : path-like
        The CSV file.
    times : (n,) array_like
        Times in s from the start of contact.
    pressures : sequence of (n,) array_like
        Pressure in Pa, one series per column.
    names : sequence of str
        Column names of the pressures (``pressure_pa``, or one per pulse).
    """
    fmt = [WAVEFORM_FORMATS[0]] + [WAVEFORM_FORMATS[1]] * len(names)
    return write_csv_atomic(path, ["time_s", *names], [times, *pressures], fmt=fmt)


def waveform_extremes(pulse, samples, point, geometry, medium, *, memory_limit=None) -> tuple[float, float]:
    """Largest and smallest pressure in Pa a waveform reports.

    In a room (a configuration with an image order) the waveform is a window of a longer
    reverberant response, so its extremes are the largest and smallest samples within the window;
    otherwise they are the peaks of the continuous waveform, refined between samples on the closed
    form (:func:`acoustiviz.app.views.waveform_peaks`).

    Parameters
    ----------
    pulse : pulse
        Acceleration pulse of the sphere.
    samples : (n,) array_like
        The tabulated pressure in Pa at ``point``.
    point : (3,) array_like
        Observer in m.
    geometry : acoustiviz.core.geometry.Geometry
        The sphere and its images.
    medium : Medium
        The fluid.
    memory_limit : float, optional
        Working-memory cap in bytes of the refinement.

    Returns
    -------
    peak_positive, peak_negative : float
    """
    if getattr(geometry, "image_order", None) is not None:
        return float(np.max(samples)), float(np.min(samples))
    from .views import waveform_peaks

    return waveform_peaks(pulse, point, geometry, medium, memory_limit=memory_limit)


def write_directivity_csv(path, directivity, column=None, values=None):
    """Write ``angle_deg, peak_pa, rms_pa, spl_db`` (and ``column`` of ``values`` in dB) atomically; return the path.

    Parameters
    ----------
    path : path-like
        The CSV file.
    directivity : acoustiviz.field.Directivity
        Peak, RMS and SPL against angle.
    column : str, optional
        Name of a further level column (:data:`acoustiviz.app.views.DIRECTIVITY_METRICS`).
    values : (n,) array_like, optional
        That level in dB at each angle.
    """
    d = directivity
    names, cols = ["angle_deg", "peak_pa", "rms_pa", "spl_db"], [d.angle_deg, d.peak, d.rms, d.spl_db]
    if column is not None:
        names.append(column)
        cols.append(values)
    return write_csv_atomic(path, names, cols, fmt=list(DIRECTIVITY_FORMATS[:len(names)]))
