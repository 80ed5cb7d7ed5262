"""The design query: paper Table 2 and the quietest design for a target damping inclination.

Among impact dampers that damp equally well -- the same damping inclination -- the paper
chooses the quietest. :func:`design_table` groups a sweep's designs into bands of inclination
and reports the range of their maximum SPL (Table 2); :func:`design` answers one target.
Failed designs (NaN values) are left out. Inclinations in m/s, levels in dB re 20 µPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._validate import check_positive, check_range
from ..constants import MAX_INCLINATION
from ..errors import ParameterError
from .levels import SWEEP_LEVEL_COLUMNS
from .store import NUMERIC_COLUMNS, SweepTable, format_value, sweep_columns

__all__ = ["PAPER_TABLE2", "DESIGN_TABLE_COLUMNS", "RANK_COLUMNS", "Band", "DesignChoice", "design_table",
           "write_design_table", "design"]

#: The paper's Table 2: (damping inclination in m/s, minimum and maximum of the maximum SPL in dB,
#: their difference in dB), for bands 0.1 cm/s wide.
PAPER_TABLE2 = (
    (0.007, 103.0, 105.0, 2.0),
    (0.008, 100.0, 108.0, 8.0),
    (0.009, 100.0, 107.0, 7.0),
    (0.010, 100.0, 107.0, 7.0),
    (0.011, 101.0, 106.0, 5.0),
    (0.012, 104.0, 106.0, 2.0),
)


@dataclass(frozen=True)
class Band:
    """One row of the design table (paper Table 2).

    Attributes
    ----------
    centre, low, high : float
        Band of damping inclination in m/s: ``low <= e < high``, ``centre`` its middle.
    n_designs : int
        Designs in the band.
    min_spl_db, max_spl_db : float
        Smallest and largest maximum SPL in dB of those designs.
    decrease_db : float
        ``max_spl_db - min_spl_db``: what the acoustic-based choice saves.
    quietest_gap, quietest_mass : float
        Design (m, kg) attaining the minimum.
    loudest_gap, loudest_mass : float
        Design (m, kg) attaining the maximum.
    level_ranges : dict
        For each of ``lafmax_db``, ``lcpeak_db``, ``laeq_db``: ``(min, max)`` in dB over the band's
        designs (NaN when the sweep computed no levels).
    """

    centre: float
    low: float
    high: float
    n_designs: int
    min_spl_db: float
    max_spl_db: float
    decrease_db: float
    quietest_gap: float
    quietest_mass: float
    loudest_gap: float
    loudest_mass: float
    level_ranges: dict | None = None


#: Columns of ``design_table.csv``: paper Table 2, then the range of each weighted level in the band.
DESIGN_TABLE_COLUMNS = (
    "inclination_m_s", "band_low_m_s", "band_high_m_s", "n_designs", "min_max_spl_db", "max_max_spl_db",
    "decrease_db", "quietest_gap_m", "quietest_mass_kg", "loudest_gap_m", "loudest_mass_kg",
    *(f"{end}_{c}" for c in SWEEP_LEVEL_COLUMNS for end in ("min", "max")),
)
#: Columns a design query can rank by: every numeric column of ``sweep.csv`` but the design id and
#: the success flag.
RANK_COLUMNS = tuple(c for c in NUMERIC_COLUMNS if c not in ("design_id", "success"))


def _nan_range(x) -> tuple:
    x = x[np.isfinite(x)]
    return (float(np.min(x)), float(np.max(x))) if x.size else (math.nan, math.nan)


def design_table(table: SweepTable, *, definition: str = "two-maxima", width: float = 0.001,
                 centres=None) -> tuple[Band, ...]:
    """Paper Table 2: per band of damping inclination, the range of the maximum SPL.

    Parameters
    ----------
    table : SweepTable
        Sweep rows.
    definition : {"two-maxima", "fit"}
        Inclination definition (default paper eq 16).
    width : float
        Band width in m/s (default 0.001 m/s = 0.1 cm/s, as in Table 2).
    centres : array_like, optional
        Band centres in m/s; default every multiple of ``width`` whose band holds a design.

    Returns
    -------
    tuple of Band
        Bands holding at least one design, in increasing inclination. A band is
        ``[centre - width/2, centre + width/2)``.
    """
    w = check_positive("width", width, "m/s")
    e = np.asarray(table.inclination(definition), dtype=float)
    spl = np.asarray(table["max_spl_db"], dtype=float)
    ok = np.isfinite(e) & np.isfinite(spl)
    if centres is None:
        if not np.any(ok):
            return ()
        k = np.floor(e[ok] / w + 0.5)
        centres = np.unique(k) * w
    bands = []
    for c in np.asarray(centres, dtype=float):
        lo, hi = c - w / 2, c + w / 2
        sel = np.flatnonzero(ok & (e >= lo) & (e < hi))
        if sel.size == 0:
            continue
        bands.append(_band(table, sel, spl, float(np.round(c, 12)), float(np.round(lo, 12)),
                           float(np.round(hi, 12))))
    return tuple(bands)


def _band(table, sel, spl, centre, lo, hi) -> Band:
    i_min = sel[np.argmin(spl[sel])]
    i_max = sel[np.argmax(spl[sel])]
    g, m = table["gap_m"], table["mass_kg"]
    ranges = {c: _nan_range(np.asarray(table[c], dtype=float)[sel]) for c in SWEEP_LEVEL_COLUMNS if c in table.columns}
    return Band(centre, float(lo), float(hi), int(sel.size), float(spl[i_min]), float(spl[i_max]),
                float(spl[i_max] - spl[i_min]), float(g[i_min]), float(m[i_min]), float(g[i_max]), float(m[i_max]),
                ranges)


def write_design_table(bands, path) -> Path:
    """Write bands as ``design_table.csv`` (columns :data:`DESIGN_TABLE_COLUMNS`) atomically."""
    from ..files import write_text_atomic

    lines = [",".join(DESIGN_TABLE_COLUMNS)]
    for b in bands:
        ranges = b.level_ranges or {}
        levels = [v for c in SWEEP_LEVEL_COLUMNS for v in ranges.get(c, (math.nan, math.nan))]
        lines.append(",".join(format_value(v) for v in (
            b.centre, b.low, b.high, b.n_designs, b.min_spl_db, b.max_spl_db, b.decrease_db,
            b.quietest_gap, b.quietest_mass, b.loudest_gap, b.loudest_mass, *levels)))
    return write_text_atomic(path, "\n".join(lines) + "\n")


@dataclass(frozen=True)
class DesignChoice:
    """Answer of :func:`design`: the quietest design among those that damp as asked.

    Attributes
    ----------
    inclination, tolerance : float
        Target damping inclination and tolerance in m/s.
    definition : str
        Inclination definition used.
    n_candidates : int
        Designs with ``|e - inclination| <= tolerance``.
    quietest, loudest : dict or None
        Row (column name to value) of the candidate with the smallest and the largest
        ``rank_by``; None when no design lies within the tolerance.
    saving_db : float
        ``rank_by`` of the loudest minus that of the quietest candidate (dB for a level; NaN
        without candidates).
    nearest : tuple of dict
        The designs whose inclination is closest to the target (up to three), for a target
        that no design meets.
    span : tuple of float
        Smallest and largest inclination of the sweep in m/s.
    rank_by : str
        The column the candidates were ranked by (default ``max_spl_db``).
    """

    inclination: float
    tolerance: float
    definition: str
    n_candidates: int
    quietest: dict | None
    loudest: dict | None
    saving_db: float
    nearest: tuple = ()
    span: tuple = (math.nan, math.nan)
    rank_by: str = "max_spl_db"

    def summary(self) -> str:
        """A few lines of plain text for the command line."""
        q, lo = self.quietest, self.loudest
        if q is None:
            lines = [f"no design has a {self.definition} damping inclination within {self.tolerance:g} m/s of "
                     f"{self.inclination:g} m/s; the sweep spans [{self.span[0]:.4g}, {self.span[1]:.4g}] m/s",
                     "nearest designs (widen --tolerance or the sweep to include them):"]
            lines += [f"  {_which(r)}, inclination {r['inclination']:.6g} m/s, "
                      f"max SPL {r['max_spl_db']:.2f} dB{self._extra(r)}" for r in self.nearest]
            return "\n".join(lines)
        k = self.rank_by
        head = "quietest" if k.endswith("_db") else f"smallest {k}"
        tail = "loudest" if k.endswith("_db") else f"largest {k}"
        pad = " " * max(1, len(head) - len(tail) + 1)
        return "\n".join([
            f"designs with {self.definition} damping inclination {self.inclination:g} +/- {self.tolerance:g} m/s: "
            f"{self.n_candidates}; ranked by {k}",
            f"{head}: {_which(q)}, max SPL {q['max_spl_db']:.2f} dB"
            f"{self._extra(q)}, inclination {q['inclination']:.6g} m/s",
            f"{tail}:{pad}{_which(lo)}, max SPL {lo['max_spl_db']:.2f} dB"
            f"{self._extra(lo)}, inclination {lo['inclination']:.6g} m/s",
            (f"the quietest is {self.saving_db:.2f} dB quieter than the loudest by {k}" if k.endswith("_db")
             else f"{k} spans {self.saving_db:.6g} among them"),
        ])

    def _extra(self, row) -> str:
        """The weighted levels of a row (when the sweep computed them) and the ranked column."""
        parts = [f"{name} {row[c]:.2f} dB" for c, name in (("lafmax_db", "LAFmax"), ("lcpeak_db", "LCpeak"),
                                                            ("laeq_db", "LAeq")) if math.isfinite(row.get(c, math.nan))]
        if self.rank_by not in ("max_spl_db", *SWEEP_LEVEL_COLUMNS):
            parts.append(f"{self.rank_by} {row[self.rank_by]:.6g}")
        return "".join(f", {p}" for p in parts)




def _which(row) -> str:
    """``m = ... kg, d = ... m`` of a row; with its balls named, ``N balls of m = ... kg, d = ... m, fill ...``."""
    text = f"m = {row['mass_kg']:.6g} kg, d = {row['gap_m']:.6g} m"
    if "balls" not in row:
        return text
    return f"{row['balls']} ball{'s' if row['balls'] != 1 else ''} of {text}, fill {row['fill']:.4g}"


def check_target(inclination: float, tolerance: float) -> tuple[float, float]:
    """The target damping inclination and its tolerance in m/s, each checked to lie in (0, 10] m/s.

    A damper's damping inclination (paper eq 16) is a positive rate of decay; a zero tolerance
    would match only designs equal to the target to the last bit.
    """
    target = check_range("inclination", inclination, 0.0, MAX_INCLINATION, unit="m/s", low_open=True)
    tol = check_range("tolerance", tolerance, 0.0, MAX_INCLINATION, unit="m/s", low_open=True)
    return target, tol


def design(table: SweepTable, inclination: float, tolerance: float, *,
           definition: str = "two-maxima", rank_by: str = "max_spl_db") -> DesignChoice:
    """For a target damping inclination within a tolerance, the quietest (m, d) and its saving.

    Parameters
    ----------
    table : SweepTable
        Sweep rows.
    inclination : float
        Target damping inclination in m/s (e.g. 0.008 m/s = 0.8 cm/s).
    tolerance : float
        Accepted deviation in m/s (> 0; both in (0, 10] m/s, :func:`check_target`).
    definition : {"two-maxima", "fit"}
        Inclination definition (default paper eq 16).
    rank_by : str
        The column whose smallest value is "quietest": any of :data:`RANK_COLUMNS`, e.g.
        ``max_spl_db`` (default, paper Table 2), ``lafmax_db``, ``lcpeak_db``, ``laeq_db``
        (sweeps run with levels) or ``settling_time_s``.

    Returns
    -------
    DesignChoice
        When no design lies within the tolerance: no candidates, and the (up to three) designs
        nearest the target in ``nearest``.

    Raises
    ------
    ParameterError
        If the sweep holds no finished design; ``rank_by`` if it names no numeric column or the
        sweep holds no value of it.
    """
    target, tol = check_target(inclination, tolerance)
    if rank_by not in RANK_COLUMNS:
        raise ParameterError("rank_by", f"must be one of {', '.join(RANK_COLUMNS)}; got {rank_by!r}")
    e = np.asarray(table.inclination(definition), dtype=float)
    spl = np.asarray(table["max_spl_db"], dtype=float)
    ok = np.isfinite(e) & np.isfinite(spl)
    if not np.any(ok):
        raise ParameterError("sweep", "the sweep holds no finished design")
    key = np.asarray(table[rank_by], dtype=float)
    if not np.any(ok & np.isfinite(key)):
        hint = " (run the sweep with levels: acoustiviz sweep --levels)" if rank_by in SWEEP_LEVEL_COLUMNS else ""
        raise ParameterError("rank_by", f"the sweep holds no value of {rank_by}{hint}")
    ok &= np.isfinite(key)
    span = (float(np.min(e[ok])), float(np.max(e[ok])))

    def row(i):
        d = {c: table[c][i].item() for c in sweep_columns(table.spec) if c in table.columns}
        d["inclination"] = float(e[i])
        return d

    sel = np.flatnonzero(ok & (np.abs(e - target) <= tol * (1 + 1e-12)))
    if sel.size == 0:
        valid = np.flatnonzero(ok)
        near = valid[np.argsort(np.abs(e[valid] - target), kind="stable")[:3]]
        return DesignChoice(target, tol, definition, 0, None, None, math.nan, tuple(row(i) for i in near), span,
                            rank_by)
    i_min = sel[np.argmin(key[sel])]
    i_max = sel[np.argmax(key[sel])]
    return DesignChoice(target, tol, definition, int(sel.size), row(i_min), row(i_max),
                        float(key[i_max] - key[i_min]), (), span, rank_by)
