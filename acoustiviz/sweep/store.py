"""The files of a sweep directory: the settings, the row journal, resuming, and the table of rows.

``sweep.json``
    Every setting of the sweep (:func:`spec_document`). A sweep resumes only into a directory
    made with the same settings (:class:`SweepMismatch` otherwise, unless ``overwrite``).
``sweep.csv``
    The journal: one row per finished design, in order of completion, each written, flushed and
    synced before the next (:class:`Journal`). Columns :data:`CSV_COLUMNS` then
    :data:`EXTRA_COLUMNS` (``lafmax_db``, ``lcpeak_db``, ``laeq_db`` are NaN unless the sweep's
    ``levels`` setting is on, :mod:`acoustiviz.sweep.levels`). A torn last line left by a kill is
    dropped on resume; finished designs (failed ones included, with their reason) are never
    recomputed.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._validate import check_choice
from ..errors import ParameterError
from .spec import SweepSpec

__all__ = [
    "CSV_COLUMNS",
    "EXTRA_COLUMNS",
    "ALL_COLUMNS",
    "NUMERIC_COLUMNS",
    "SWEEP_CSV",
    "SWEEP_JSON",
    "DESIGN_TABLE_CSV",
    "DEFINITIONS",
    "SweepMismatch",
    "SweepTable",
    "Journal",
    "spec_document",
    "read_spec",
    "prepare_dir",
    "read_rows",
    "load_sweep",
    "table_from_rows",
    "format_value",
]

#: The columns every ``sweep.csv`` starts with (the command-line interface promises these).
CSV_COLUMNS = (
    "gap_m",
    "mass_kg",
    "inclination_two_maxima_m_s",
    "inclination_fit_m_s",
    "settling_time_s",
    "n_impacts",
    "max_spl_db",
)
#: Further columns, after :data:`CSV_COLUMNS`; ``error`` is empty unless the design failed.
EXTRA_COLUMNS = (
    "design_id",
    "mass_ratio",
    "c1_n_s_m",
    "k_hertz_n_m1_5",
    "material",
    "v0_m_s",
    "distance_m",
    "angle_deg",
    "config",
    "radius_m",
    "energy_dissipated_contact_j",
    "energy_dissipated_main_j",
    "max_approach_velocity_m_s",
    "fit_window_start_s",
    "fit_window_stop_s",
    "fit_n_maxima",
    "spl_impacts_evaluated",
    "lafmax_db",
    "lcpeak_db",
    "laeq_db",
    "success",
    "error",
)
ALL_COLUMNS = CSV_COLUMNS + EXTRA_COLUMNS
_TEXT_COLUMNS = ("material", "config", "error")
_INT_COLUMNS = ("design_id", "n_impacts", "fit_n_maxima", "spl_impacts_evaluated", "success")
#: The numeric columns of ``sweep.csv``.
NUMERIC_COLUMNS = tuple(c for c in ALL_COLUMNS if c not in _TEXT_COLUMNS)

#: File names inside a sweep directory.
SWEEP_CSV = "sweep.csv"
SWEEP_JSON = "sweep.json"
DESIGN_TABLE_CSV = "design_table.csv"
_PREVIOUS_CSV = "sweep.previous.csv"
#: Damping-inclination definitions: paper eq 16, or the envelope fit.
DEFINITIONS = ("two-maxima", "fit")
_FORMAT = "acoustiviz-sweep"
_FORMAT_VERSION = 3  # 2: the error column of failed designs; 3: lafmax_db, lcpeak_db, laeq_db


class SweepMismatch(ParameterError):
    """A sweep directory holds results made with other settings."""


# --------------------------------------------------------------------------- the table
@dataclass(frozen=True)
class SweepTable:
    """The rows of a sweep, ordered by design id.

    Attributes
    ----------
    spec : SweepSpec
        The sweep's settings.
    columns : dict
        Column name (those of ``sweep.csv``) to a 1-D array; text columns are arrays of str.
    """

    spec: SweepSpec
    columns: dict

    def __len__(self) -> int:
        return int(self.columns["design_id"].size)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    @property
    def complete(self) -> bool:
        """True when every design of the spec has a row."""
        return len(self) == len(self.spec.designs())

    @property
    def failed(self) -> np.ndarray:
        """Boolean mask of the designs that could not be evaluated (their reason in ``error``)."""
        err = self.columns.get("error")
        return np.zeros(len(self), dtype=bool) if err is None else np.char.str_len(err) > 0

    def subset(self, mask) -> SweepTable:
        """The rows where the boolean ``mask`` (one entry per row) is True."""
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != (len(self),):
            raise ParameterError("mask", f"expected {len(self)} booleans, got shape {mask.shape}")
        cols = {}
        for k, v in self.columns.items():
            a = v[mask]
            a.setflags(write=False)
            cols[k] = a
        return SweepTable(self.spec, cols)

    def inclination(self, definition: str = "two-maxima") -> np.ndarray:
        """Damping inclination in m/s by ``definition`` (``"two-maxima"``, paper eq 16, or ``"fit"``)."""
        check_choice("definition", definition, DEFINITIONS)
        return self.columns["inclination_two_maxima_m_s" if definition == "two-maxima" else "inclination_fit_m_s"]

    def grid(self, name: str) -> np.ndarray:
        """Column ``name`` on the gap × mass grid, shape ``(n_gap, n_mass)`` (NaN where missing).

        Only for sweeps whose other axes hold a single value.
        """
        spec = self.spec
        others = [a for a in spec.swept() if a not in ("gap", "m")]
        if others:
            raise ParameterError("table", f"a gap x mass map needs the other axes fixed; swept also: {others}")
        ng, nm = len(spec.gap), len(spec.masses)
        out = np.full(ng * nm, np.nan)
        out[self.columns["design_id"]] = self.columns[name]
        return out.reshape(ng, nm)


def table_from_rows(spec: SweepSpec, rows: dict[int, dict]) -> SweepTable:
    """A :class:`SweepTable` from rows of text values keyed by design id."""
    ids = sorted(rows)
    cols = {}
    for c in ALL_COLUMNS:
        vals = [rows[i][c] for i in ids]
        if c in _TEXT_COLUMNS:
            cols[c] = np.array(vals, dtype=str)
        elif c in _INT_COLUMNS:
            cols[c] = np.array([int(v) for v in vals], dtype=int)
        else:
            cols[c] = np.array([float(v) for v in vals], dtype=float)
    for a in cols.values():
        a.setflags(write=False)
    return SweepTable(spec, cols)


def format_value(v) -> str:
    """A value as written in the CSV files: text as is, integers and booleans as integers, floats by repr."""
    if isinstance(v, str):
        return v
    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    return repr(float(v))


# --------------------------------------------------------------------------- sweep.json
def spec_document(spec: SweepSpec) -> dict:
    """The content of ``sweep.json``: the format, the writing version and every setting."""
    from .. import __version__

    return {"format": _FORMAT, "format_version": _FORMAT_VERSION, "written_by": f"acoustiviz {__version__}",
            "spec": spec.to_dict()}


def spec_text(spec: SweepSpec) -> str:
    """``sweep.json`` as written (two-space indented JSON and a final newline)."""
    return json.dumps(spec_document(spec), indent=2) + "\n"


def read_spec(out_dir) -> SweepSpec:
    """The :class:`SweepSpec` stored in ``out_dir/sweep.json``."""
    path = Path(out_dir) / SWEEP_JSON
    if not path.is_file():
        raise ParameterError("sweep", f"{out_dir} holds no {SWEEP_JSON}: not a sweep directory")
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        if doc.get("format") != _FORMAT:
            raise ValueError("not an acoustiviz sweep")
        return SweepSpec.from_dict(doc["spec"])
    except (ValueError, KeyError, TypeError) as exc:
        raise ParameterError("sweep", f"cannot read {path}: {exc}") from None


def _differences(a: dict, b: dict, prefix="") -> list[str]:
    out = []
    for k in sorted(set(a) | set(b)):
        va, vb = a.get(k), b.get(k)
        if isinstance(va, dict) and isinstance(vb, dict):
            out += _differences(va, vb, prefix + k + ".")
        elif va != vb:
            out.append(f"{prefix}{k}: {va!r} there, {vb!r} now")
    return out


def prepare_dir(spec: SweepSpec, out: Path, overwrite: bool = False) -> None:
    """Create ``out`` with ``sweep.json``, or check that it holds the same settings.

    With ``overwrite``, a directory made with other settings has its ``sweep.csv`` moved aside
    to ``sweep.previous.csv`` and starts afresh; without, it is refused (:class:`SweepMismatch`).
    """
    from ..output.writers import write_text_atomic

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / SWEEP_JSON
    want = spec_document(spec)
    if path.is_file():
        try:
            have = json.loads(path.read_text(encoding="utf-8"))
        except ValueError:
            have = {}
        diffs = _differences(have.get("spec", {}), want["spec"])
        if have.get("format") != _FORMAT:
            diffs = diffs or ["not an acoustiviz sweep.json"]
        elif have.get("format_version") != _FORMAT_VERSION:
            diffs = diffs or [f"format_version: {have.get('format_version')!r} there, {_FORMAT_VERSION} now"]
        if diffs and not overwrite:
            shown = "; ".join(diffs[:4]) + (f"; and {len(diffs) - 4} more" if len(diffs) > 4 else "")
            raise SweepMismatch(
                "out",
                f"{out} holds a sweep made with different settings ({shown}); use another directory, "
                "or overwrite it (--overwrite) to start afresh",
            )
        if not diffs:
            return
        if (out / SWEEP_CSV).exists():
            os.replace(out / SWEEP_CSV, out / _PREVIOUS_CSV)
        if (out / DESIGN_TABLE_CSV).exists():
            (out / DESIGN_TABLE_CSV).unlink()
    elif (out / SWEEP_CSV).exists() and not overwrite:
        raise SweepMismatch("out", f"{out} has a {SWEEP_CSV} but no {SWEEP_JSON}; use another directory or "
                                   "--overwrite")
    elif (out / SWEEP_CSV).exists():
        os.replace(out / SWEEP_CSV, out / _PREVIOUS_CSV)
    write_text_atomic(path, spec_text(spec))


# --------------------------------------------------------------------------- sweep.csv
def read_rows(path: Path, spec: SweepSpec) -> dict[int, dict]:
    """Finished rows of ``sweep.csv`` keyed by design id; a torn last line is cut off the file."""
    path = Path(path)
    if not path.exists():
        return {}
    raw = path.read_bytes()
    if raw and not raw.endswith(b"\n"):  # killed in the middle of a row: drop the partial line
        cut = raw.rfind(b"\n") + 1
        with open(path, "r+b") as f:
            f.truncate(cut)
            f.flush()
            os.fsync(f.fileno())
        raw = raw[:cut]
    lines = raw.decode("utf-8").splitlines()
    if not lines:
        return {}
    header = next(csv.reader([lines[0]]))
    if tuple(header) != ALL_COLUMNS:
        raise SweepMismatch("out", f"{path} has other columns than this version writes; use another directory")
    designs = spec.designs()
    rows: dict[int, dict] = {}
    for k, line in enumerate(lines[1:], start=2):
        vals = next(csv.reader([line]))
        if len(vals) != len(header):
            raise ParameterError("out", f"{path} line {k} is damaged ({len(vals)} fields, {len(header)} expected)")
        row = dict(zip(header, vals, strict=True))
        try:
            did = int(row["design_id"])
            d = designs[did]
            same = did >= 0 and (math.isclose(float(row["gap_m"]), d.gap, rel_tol=1e-12)
                                 and math.isclose(float(row["mass_kg"]), d.m, rel_tol=1e-12))
        except (ValueError, IndexError):
            same = False
        if not same:
            raise ParameterError("out", f"{path} line {k} does not match a design of {SWEEP_JSON}")
        rows.setdefault(did, row)
    return rows


def load_sweep(out_dir) -> SweepTable:
    """Read a sweep directory (finished or not) into a :class:`SweepTable`.

    Parameters
    ----------
    out_dir : path-like
        Directory written by :func:`acoustiviz.sweep.run_sweep`.
    """
    out = Path(out_dir)
    spec = read_spec(out)
    path = out / SWEEP_CSV
    if not path.is_file():
        raise ParameterError("sweep", f"{out} holds no {SWEEP_CSV}")
    return table_from_rows(spec, read_rows(path, spec))


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - platforms without directory fds
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(fd)


class Journal:
    """``sweep.csv`` opened for appending: each row written, flushed and synced on its own.

    Use as a context manager; the header is written when the file is new or empty.
    """

    def __init__(self, path):
        self.path = Path(path)
        new = not self.path.exists() or self.path.stat().st_size == 0
        self._f = open(self.path, "a", encoding="utf-8", newline="")  # noqa: SIM115 - closed by close()
        if new:
            self._f.write(",".join(ALL_COLUMNS) + "\n")
            self._sync()
            _fsync_dir(self.path.parent)

    def _sync(self):
        self._f.flush()
        os.fsync(self._f.fileno())

    def append(self, row: dict) -> dict:
        """Write one row (column name to value); return it as the text values written."""
        text = {c: format_value(row[c]) for c in ALL_COLUMNS}
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerow([text[c] for c in ALL_COLUMNS])
        self._f.write(buf.getvalue())
        self._sync()
        return text

    def close(self) -> None:
        """Close the file."""
        self._f.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
