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
``sweep.previous-N.csv``, ``sweep.previous-N.json``
    A sweep moved aside by ``overwrite`` (N = 1, 2, ... in order), its journal with the settings
    that made it, and every other file it had (``design_table.previous-N.csv``,
    ``max_spl_map.previous-N.png``, ...): a second ``--overwrite`` never replaces the first one's.

A damaged directory (a binary or non-UTF-8 file, a word where a number belongs, a
``sweep.json`` that is not an object) is refused with a one-line :class:`ParameterError` naming
the file, the line and the column and saying it is damaged. Reading never writes: a file read
back is left byte for byte as it was, damaged or not; only a resumed sweep's :class:`Journal`
cuts a torn last line off before appending to it.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._validate import check_choice
from ..errors import ParameterError
from .balls import BALL_COLUMNS
from .spec import SweepSpec

__all__ = ["put_in_design_order", "CSV_COLUMNS", "EXTRA_COLUMNS", "ALL_COLUMNS", "sweep_columns", "row_columns",
           "NUMERIC_COLUMNS", "SWEEP_CSV", "SWEEP_JSON", "DESIGN_TABLE_CSV", "DEFINITIONS", "SweepMismatch",
           "SweepTable", "Journal", "spec_document", "read_spec", "read_document", "prepare_dir", "check_dir",
           "previous_sweeps", "read_rows", "load_sweep", "table_from_rows", "format_value"]

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
# text and integer columns of both kinds of sweep (those in operation: acoustiviz.sweep.operation)
_TEXT_COLUMNS = ("material", "config", "error", "worst_regime")
_INT_COLUMNS = ("design_id", "balls", "n_impacts", "fit_n_maxima", "spl_impacts_evaluated", "success", "attractors",
                "failed_runs", "cycles_integrated", "warm_from")
#: The numeric columns of ``sweep.csv``.
NUMERIC_COLUMNS = tuple(c for c in ALL_COLUMNS if c not in _TEXT_COLUMNS)


def sweep_columns(spec: SweepSpec) -> tuple:
    """The columns of ``spec``'s ``sweep.csv``: :data:`ALL_COLUMNS`, with ``balls`` and ``fill`` after ``radius_m``.

    The two columns of :data:`acoustiviz.sweep.balls.BALL_COLUMNS` are there when the spec names its balls
    (:attr:`acoustiviz.sweep.SweepSpec.with_balls`); a sweep of one ball writes the columns it always wrote.
    """
    return row_columns(spec.with_balls)


def row_columns(with_balls: bool, columns: tuple = ALL_COLUMNS) -> tuple:
    """``columns`` (default :data:`ALL_COLUMNS`), with ``balls`` and ``fill`` after ``radius_m`` when ``with_balls``.

    The one rule of both kinds of sweep (in operation ``columns`` is
    :data:`~acoustiviz.sweep.operation.OPERATION_COLUMNS`).
    """
    if not with_balls:
        return columns
    at = columns.index("radius_m") + 1
    return columns[:at] + BALL_COLUMNS + columns[at:]

#: File names inside a sweep directory.
SWEEP_CSV = "sweep.csv"
SWEEP_JSON = "sweep.json"
DESIGN_TABLE_CSV = "design_table.csv"
#: Prefix of a sweep moved aside by ``overwrite``: ``sweep.previous-N.csv`` with ``sweep.previous-N.json``.
_PREVIOUS = "sweep.previous-{n}"
#: The files a sweep writes beside its ``*_map.png`` figures (moved aside together by ``overwrite``).
_SWEEP_FILES = (SWEEP_CSV, SWEEP_JSON, DESIGN_TABLE_CSV, "design_table.png")
_MOVED = re.compile(r"\.previous-\d+(\.[^.]*)?$")
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
    operation : acoustiviz.sweep.Operation, optional
        The excitation of a sweep in operation (its columns :data:`acoustiviz.sweep.OPERATION_COLUMNS`);
        None: free vibration.
    """

    spec: SweepSpec
    columns: dict
    operation: object = None

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
        return SweepTable(self.spec, cols, self.operation)

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
        if spec.fill is not None:  # each design's gap follows from its fill and mass: no grid of gaps
            raise ParameterError("table", "a gap x mass map needs the gaps swept, not the fill")
        ng, nm = len(spec.gap), len(spec.masses)
        out = np.full(ng * nm, np.nan)
        out[self.columns["design_id"]] = self.columns[name]
        return out.reshape(ng, nm)


def _number(kind, text: str, column: str, where, name: str):
    """``kind(text)``, or a :class:`ParameterError` ``name`` saying where (a design id or a file line)."""
    try:
        return kind(text)
    except (TypeError, ValueError):
        what = "an integer" if kind is int else "a number"
        place = f"design {where}" if isinstance(where, int) else where
        raise ParameterError(name, f"{place}: column {column} holds {text!r}, expected {what} "
                                   "(the sweep's files are damaged)") from None


def table_from_rows(spec: SweepSpec, rows: dict[int, dict], name: str = "sweep", *, columns=None,
                    operation=None) -> SweepTable:
    """A :class:`SweepTable` from rows of text values keyed by design id (``columns``: those of the rows).

    ``columns`` defaults to :func:`sweep_columns`.
    A cell that is not a number where one belongs raises :class:`ParameterError` named ``name``.
    """
    ids = sorted(rows)
    cols = {}
    for c in sweep_columns(spec) if columns is None else columns:
        vals = [rows[i][c] for i in ids]
        if c in _TEXT_COLUMNS:
            cols[c] = np.array(vals, dtype=str)
        elif c in _INT_COLUMNS:
            cols[c] = np.array([_number(int, v, c, i, name) for i, v in zip(ids, vals, strict=True)], dtype=int)
        else:
            cols[c] = np.array([_number(float, v, c, i, name) for i, v in zip(ids, vals, strict=True)],
                               dtype=float)
    for a in cols.values():
        a.setflags(write=False)
    return SweepTable(spec, cols, operation)


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
def spec_document(spec: SweepSpec, operation: dict | None = None) -> dict:
    """The content of ``sweep.json``: the format, the writing version and every setting.

    ``operation``: the excitation of a sweep in operation as plain values, kept under the spec's
    ``operation`` key (absent for free vibration), so a folder resumes only in its own mode.
    """
    from .. import __version__

    d = spec.to_dict() if operation is None else {**spec.to_dict(), "operation": operation}
    return {"format": _FORMAT, "format_version": _FORMAT_VERSION, "written_by": f"acoustiviz {__version__}",
            "spec": d}


def spec_text(spec: SweepSpec, operation: dict | None = None) -> str:
    """``sweep.json`` as written (two-space indented JSON and a final newline)."""
    return json.dumps(spec_document(spec, operation), indent=2) + "\n"


class _Damaged(ParameterError):
    """A sweep's file read back is damaged (not what a sweep writes); the message says so."""


def _read_document(path: Path, name: str):
    """``sweep.json`` parsed, or :class:`ParameterError` ``name`` naming the file (unreadable, damaged)."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ParameterError(name, f"cannot read {path}: {exc.strerror or exc}") from None
    try:
        doc = json.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as exc:
        raise _Damaged(name, f"{path} is damaged: not JSON text ({exc})") from None
    if not isinstance(doc, dict):
        raise _Damaged(name, f"{path} is damaged: expected a JSON object, got a {type(doc).__name__}")
    if doc.get("format") != _FORMAT:
        raise _Damaged(name, f"{path} is damaged: not an acoustiviz sweep's settings (no format {_FORMAT!r})")
    if not isinstance(doc.get("spec"), dict):
        raise _Damaged(name, f"{path} is damaged: its 'spec' is {'missing' if 'spec' not in doc else 'not a table'}")
    return doc


def read_document(out_dir, name: str = "sweep") -> dict:
    """``out_dir/sweep.json`` parsed (errors named ``name``: missing, unreadable, damaged)."""
    path = Path(out_dir) / SWEEP_JSON
    if not path.is_file():
        raise ParameterError(name, f"{out_dir} holds no {SWEEP_JSON}: not a sweep directory")
    return _read_document(path, name)


def read_spec(out_dir, name: str = "sweep") -> SweepSpec:
    """The :class:`SweepSpec` stored in ``out_dir/sweep.json`` (errors named ``name``)."""
    path = Path(out_dir) / SWEEP_JSON
    doc = read_document(out_dir, name)
    try:
        return SweepSpec.from_dict({k: v for k, v in doc["spec"].items() if k != "operation"})
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise _Damaged(name, f"{path} is damaged: {exc}") from None


def _differences(a: dict, b: dict, prefix="") -> list[str]:
    out = []
    for k in sorted(set(a) | set(b)):
        va, vb = a.get(k), b.get(k)
        if isinstance(va, dict) and isinstance(vb, dict):
            out += _differences(va, vb, prefix + k + ".")
        elif va != vb:
            out.append(f"{prefix}{k}: {va!r} there, {vb!r} now")
    return out


def _dir_plan(spec: SweepSpec, out: Path, overwrite: bool, operation: dict | None = None) -> str:
    """What :func:`prepare_dir` will do with ``out``, without writing: ``"resume"``, ``"aside"`` or ``"new"``.

    Raises what :func:`prepare_dir` refuses (:class:`SweepMismatch`, a damaged ``sweep.json``).
    """
    path = out / SWEEP_JSON
    if path.is_file():
        try:
            have = _read_document(path, "out")
        except _Damaged as exc:
            if not overwrite:
                raise _Damaged("out", f"{exc.detail}; use another directory, or --overwrite to move it aside "
                                      "and start afresh") from None
            have = {"spec": {}}
        diffs = _differences(have["spec"], spec_document(spec, operation)["spec"])
        if have.get("format_version") != _FORMAT_VERSION:
            diffs = diffs or [f"format_version: {have.get('format_version')!r} there, {_FORMAT_VERSION} now"]
        if diffs and not overwrite:
            shown = "; ".join(diffs[:4]) + (f"; and {len(diffs) - 4} more" if len(diffs) > 4 else "")
            raise SweepMismatch(
                "out",
                f"{out} holds a sweep made with different settings ({shown}); use another directory, "
                "or overwrite it (--overwrite) to start afresh",
            )
        return "aside" if diffs else "resume"
    if (out / SWEEP_CSV).exists() and not overwrite:
        raise SweepMismatch("out", f"{out} has a {SWEEP_CSV} but no {SWEEP_JSON}; use another directory or "
                                   "--overwrite")
    return "aside" if (out / SWEEP_CSV).exists() else "new"


def check_dir(spec: SweepSpec, out, overwrite: bool = False, operation: dict | None = None,
              columns=None) -> None:
    """Refuse, writing nothing, a folder :func:`prepare_dir` would refuse or a journal :func:`read_rows` would."""
    out = Path(out)
    if out.is_dir() and _dir_plan(spec, out, overwrite, operation) == "resume":
        read_rows(out / SWEEP_CSV, spec, "out", columns=columns)


def prepare_dir(spec: SweepSpec, out: Path, overwrite: bool = False, operation: dict | None = None) -> None:
    """Create ``out`` with ``sweep.json``, or check that it holds the same settings.

    With ``overwrite``, a directory made with other settings has its ``sweep.csv`` and
    ``sweep.json`` moved aside to the next free ``sweep.previous-N.csv`` and ``.json`` and starts
    afresh; without, it is refused (:class:`SweepMismatch`). A damaged ``sweep.json`` is refused
    as damaged, and left as it is, unless ``overwrite`` moves it aside.
    """
    from ..files import write_text_atomic

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    plan = _dir_plan(spec, out, overwrite, operation)
    if plan == "resume":
        return
    if plan == "aside":
        _move_aside(out)
    write_text_atomic(out / SWEEP_JSON, spec_text(spec, operation))


def previous_sweeps(out) -> list[Path]:
    """The journals moved aside by ``overwrite`` in ``out``, oldest first (``sweep.previous-N.csv``)."""
    found = []
    for p in Path(out).glob("sweep.previous-*.csv"):
        n = p.stem.removeprefix("sweep.previous-")
        if n.isdigit():
            found.append((int(n), p))
    return [p for _, p in sorted(found)]


def _move_aside(out: Path) -> None:
    """Rename the sweep's files to the next free ``previous-N``: ``sweep.csv`` to ``sweep.previous-N.csv``.

    The files a sweep writes go (the journal, its settings, the design table and the figures
    made from them, ``*_map.png`` and ``design_table.png``: ``max_spl_map.png`` to
    ``max_spl_map.previous-N.png``), so the sweep moved aside keeps everything that described it;
    other files, files already moved aside and sub-folders stay.
    """
    from ..files import refuse_replacing

    n = 1
    while any((out / (_PREVIOUS.format(n=n) + ext)).exists() for ext in (".csv", ".json")):
        n += 1
    for src in sorted(out.iterdir()):
        ours = src.name in _SWEEP_FILES or src.name.endswith("_map.png")
        if not ours or src.is_symlink() or not src.is_file() or _MOVED.search(src.name):
            continue
        refuse_replacing(src)
        os.replace(src, out / f"{src.stem}.previous-{n}{src.suffix}")
    _fsync_dir(out)


# --------------------------------------------------------------------------- sweep.csv
def _journal_lines(path: Path, name: str, columns=ALL_COLUMNS) -> list:
    """The complete text lines of the journal ``path`` (a torn last line left out); the file is only read."""
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ParameterError(name, f"{path} is damaged: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    lines = text.split("\n")
    torn = lines.pop()  # "" after a final newline; a kill in the middle of a row leaves a part of it
    if torn and not lines and not (",".join(columns)).startswith(torn):
        raise ParameterError(name, f"{path} is damaged: no complete line and not the start of a sweep journal")
    return lines


def _matches_design(row: dict, designs) -> bool:
    """True when the row's design id, gap and mass are those of a design of the spec."""
    try:
        did = int(row["design_id"])
        d = designs[did]
        return did >= 0 and (math.isclose(float(row["gap_m"]), d.gap, rel_tol=1e-12)
                             and math.isclose(float(row["mass_kg"]), d.m, rel_tol=1e-12))
    except (ValueError, IndexError):
        return False


def read_rows(path: Path, spec: SweepSpec, name: str = "out", *, columns=None) -> dict[int, dict]:
    """Finished rows of ``sweep.csv`` (``columns``: its header) keyed by design id; a torn last line left out.

    ``columns`` defaults to :func:`sweep_columns`.
    A damaged file (not UTF-8 text, other columns, a row with another number of fields or that
    matches no design) raises :class:`ParameterError` named ``name``.
    """
    path = Path(path)
    if not path.exists():
        return {}
    columns = sweep_columns(spec) if columns is None else columns
    lines = _journal_lines(path, name, columns)
    if not lines:
        return {}
    try:
        header = next(csv.reader([lines[0]]))
    except csv.Error as exc:
        raise ParameterError(name, f"{path} line 1 is damaged: {exc}") from None
    if tuple(header) != tuple(columns):
        raise SweepMismatch(name, f"{path} is damaged or from another version: its columns are not those this "
                                  "version writes; use another directory")
    designs = spec.designs()
    rows: dict[int, dict] = {}
    for k, line in enumerate(lines[1:], start=2):
        try:
            vals = next(csv.reader([line]))
        except (csv.Error, StopIteration) as exc:
            raise ParameterError(name, f"{path} line {k} is damaged: {exc or 'empty'}") from None
        if len(vals) != len(header):
            raise ParameterError(name, f"{path} line {k} is damaged ({len(vals)} fields, {len(header)} expected)")
        row = dict(zip(header, vals, strict=True))
        same = _matches_design(row, designs)
        for c in (c for c in columns if c not in _TEXT_COLUMNS):  # damage found on reading, naming the line
            _number(int if c in _INT_COLUMNS else float, row[c], c, f"{path} line {k}", name)
        if not same:
            raise ParameterError(name, f"{path} line {k} is damaged: it matches no design of {SWEEP_JSON}")
        rows.setdefault(int(row["design_id"]), row)
    return rows


def put_in_design_order(path: Path, rows: dict[int, dict], designs, columns=ALL_COLUMNS) -> bool:
    """Rewrite a finished ``sweep.csv`` with its rows in the order of ``designs``; True if it was rewritten.

    The journal appends each row as its design finishes, in an order that depends on the workers;
    once every design is in, the file is rewritten (atomically, each row's text as written) in the
    designs' order, so the same sweep writes the same bytes whatever ran it. A file already in
    that order is left untouched.
    """
    from ..files import write_text_atomic

    order = [d.design_id for d in designs]
    if list(rows) == order:
        return False
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(columns)
    for i in order:
        writer.writerow([rows[i][c] for c in columns])
    write_text_atomic(path, buf.getvalue())
    return True


def load_sweep(out_dir, name: str = "sweep") -> SweepTable:
    """Read a sweep directory (finished or not) into a :class:`SweepTable`.

    Parameters
    ----------
    out_dir : path-like
        Directory written by :func:`acoustiviz.sweep.run_sweep`.
    name : str
        The option or key that named the directory (named by errors about damaged files).
    """
    out = Path(out_dir)
    spec = read_spec(out, name)
    path = out / SWEEP_CSV
    if not path.is_file():
        raise ParameterError(name, f"{out} holds no {SWEEP_CSV}")
    return table_from_rows(spec, read_rows(path, spec, name), name)


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


def _cut_torn_line(path: Path) -> None:
    """Cut a partial last line (no final newline) off the journal ``path``, synced."""
    with open(path, "r+b") as f:
        size = f.seek(0, os.SEEK_END)
        if size == 0:
            return
        f.seek(size - 1)
        if f.read(1) == b"\n":
            return
        f.seek(0)
        cut = f.read().rfind(b"\n") + 1
        f.truncate(cut)
        f.flush()
        os.fsync(f.fileno())


class Journal:
    """``sweep.csv`` opened for appending: each row written, flushed and synced on its own.

    Use as a context manager; the header is written when the file is new or empty. A torn last
    line (a kill in the middle of a row) is cut off first, so the next row starts a line of its
    own: open it only after :func:`read_rows` has accepted the rest of the file.
    """

    def __init__(self, path, columns=ALL_COLUMNS):
        self.path = Path(path)
        self.columns = tuple(columns)
        if self.path.exists():
            _cut_torn_line(self.path)
        new = not self.path.exists() or self.path.stat().st_size == 0
        self._f = open(self.path, "a", encoding="utf-8", newline="")  # noqa: SIM115 - closed by close()
        if new:
            self._f.write(",".join(self.columns) + "\n")
            self._sync()
            _fsync_dir(self.path.parent)

    def _sync(self):
        self._f.flush()
        os.fsync(self._f.fileno())

    def append(self, row: dict) -> dict:
        """Write one row (column name to value); return it as the text values written."""
        text = {c: format_value(row[c]) for c in self.columns}
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerow([text[c] for c in self.columns])
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
