"""Output and input paths checked before any work, errors naming the option or scene key.

Every command checks the files it will write *before* it computes anything, so that a long run
never ends in a file it cannot write: the file name ends in a format its writer knows, the
target is not a folder, and its folder exists and takes new files (probed by creating and
removing the very kind of temporary file :func:`acoustiviz.files.atomic_path` will
use, so a read-only file system, a folder without write permission or a name too long for the
file system are all caught). Output folders (``--out``) may be created, provided the nearest
existing ancestor is a folder that takes new entries.

An existing file is replaced only when the user asked for it: every command takes ``--force``
(:data:`REPLACE`; ``forced``, whose ``--force`` is the force amplitude, takes ``--replace``), and
while a command runs without it (:func:`replacing`), :func:`check_output_file` refuses any output
that exists, the files derived beside a named one (a WAV's JSON sidecar, a VTK file's geometry,
a level table's band table) included, naming the file and the option to pass. Called from
Python outside a command, the checks replace files as before.

Examples
--------
>>> from acoustiviz.errors import ParameterError
>>> try:
...     check_output_file("--png", "w.xyz", "figure")
... except ParameterError as exc:
...     print(exc.name)
--png
"""

from __future__ import annotations

import contextlib
import contextvars
import os
from pathlib import Path

from ..errors import ParameterError
from .settings.table import Setting

__all__ = ["FORMATS", "REPLACE", "suffixes", "replacing", "check_output_file", "check_output_dir",
           "check_input_file", "check_distinct"]

#: The flag every command takes to replace existing output files: ``--force``, also spelled ``--replace``
#: (the one spelling on ``forced``, whose ``--force`` is the force amplitude).
REPLACE = Setting("replace", "--force", None, "bool", False,
                  "replace existing output files, those derived beside a named one included (without it an "
                  "existing file is refused before any work)", aliases=("--replace",))

#: ``(allowed, option)`` while a command runs: may an existing output be replaced, and the option allowing it.
_REPLACING = contextvars.ContextVar("acoustiviz_replacing", default=(True, REPLACE.option))


@contextlib.contextmanager
def replacing(allowed: bool, option: str = REPLACE.option):
    """Within the block, :func:`check_output_file` refuses an existing file unless ``allowed``, naming ``option``."""
    token = _REPLACING.set((bool(allowed), option))
    try:
        yield
    finally:
        _REPLACING.reset(token)


def _refuse_existing(option: str, target: Path) -> None:
    """An existing file (or link) in the target's place is refused unless replacing is allowed."""
    allowed, flag = _REPLACING.get()
    if not allowed and (target.exists() or target.is_symlink()):
        raise ParameterError(option, f"{target} exists; pass {flag} to replace it")

#: Output kind -> the file-name endings its writer knows ("figure": matplotlib's formats, read
#: from matplotlib at check time; "png": the off-screen renders).
FORMATS = {
    "csv": (".csv",),
    "wav": (".wav",),
    "json": (".json",),
    "png": (".png",),
    "gif": (".gif",),
    "mp4": (".mp4",),
    "animation": (".gif", ".mp4"),
    "text": (".txt", ".md"),
    "vtk": (".vtu", ".vtkhdf"),
    "html": (".html", ".htm"),
}


def suffixes(kind: str) -> tuple:
    """The file-name endings (lower case, with the dot) accepted for output ``kind``."""
    if kind == "figure":
        from matplotlib.backend_bases import FigureCanvasBase

        return tuple(sorted("." + ext.lower() for ext in FigureCanvasBase.get_supported_filetypes()))
    return FORMATS[kind]


def _as_path(option: str, path, what: str) -> Path:
    text = os.fspath(path) if isinstance(path, os.PathLike) else path
    if not isinstance(text, str) or not text.strip():
        raise ParameterError(option, f"expected a {what}, got {path!r}")
    if "\x00" in text:
        raise ParameterError(option, f"a {what} cannot contain a NUL character, got {text!r}")
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        raise ParameterError(option, f"a {what} must be valid UTF-8 text, got {text!r}") from None
    return Path(text)


def _refuse_replacing(option: str, target: Path) -> None:
    """A symbolic link or a read-only file in the target's place is refused (never replaced)."""
    from ..files import refuse_replacing

    try:
        refuse_replacing(target)
    except OSError as exc:
        raise ParameterError(option, f"will not replace {target}: {exc.strerror}") from None


def _probe(option: str, target: Path) -> None:
    """Create and remove the temporary file the atomic writer will create beside ``target``."""
    from ..files import temporary_beside

    try:
        tmp = temporary_beside(target)
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise ParameterError(option, f"cannot write {target}: {reason} (in folder {target.parent})") from None
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def check_output_file(option: str, path, kind: str) -> Path:
    """Check, before any work, that output ``path`` can be written; return it as a Path.

    Parameters
    ----------
    option : str
        The option or scene key that gave the path (named in errors).
    path : str or path-like
        The file to write.
    kind : str
        A key of :data:`FORMATS`, or ``"figure"`` for any format matplotlib writes.

    Raises
    ------
    ParameterError
        Empty name, an ending the writer does not know, a target that is a folder, a parent
        that is missing or not a folder, a folder that takes no new files, or an existing file
        while replacing is not allowed (:func:`replacing`).
    """
    p = _as_path(option, path, "file name")
    known = suffixes(kind)
    if p.is_dir():
        example = p / ("out" + (".png" if ".png" in known else known[0]))
        raise ParameterError(option, f"{p} is a folder; give a file name inside it, e.g. {example}")
    if p.suffix.lower() not in known:
        got = f"'{p.suffix}'" if p.suffix else "no extension"
        raise ParameterError(option, f"{str(p)!r} has {got}; expected a file ending in {', '.join(known)}")
    parent = p.parent
    if not parent.exists():
        raise ParameterError(option, f"folder {parent} does not exist")
    if not parent.is_dir():
        raise ParameterError(option, f"{parent} is a file, not a folder")
    _refuse_replacing(option, p)  # a link or a read-only file: never replaced, even with --force
    _refuse_existing(option, p)
    _probe(option, p)
    return p


def check_output_dir(option: str, path) -> Path:
    """Check, before any work, that output folder ``path`` exists or can be made, and takes files.

    A missing folder is fine when its nearest existing ancestor is a folder that takes new
    entries (the folder is then created by the run). Returns ``path`` as a Path.
    """
    p = _as_path(option, path, "folder name")
    if p.exists():
        if not p.is_dir():
            raise ParameterError(option, f"{p} exists and is not a folder")
        _probe(option, p / "probe.tmp")
        return p
    anc = p.parent
    while not anc.exists() and anc != anc.parent:
        anc = anc.parent
    if not anc.is_dir():
        raise ParameterError(option, f"cannot make folder {p}: {anc} is a file, not a folder")
    _probe(option, anc / "probe.tmp")
    return p


def check_input_file(option: str, path, what: str = "file") -> Path:
    """Check that input ``path`` is a readable file (not a folder); return it as a Path."""
    p = _as_path(option, path, f"{what} name")
    if not p.exists():
        raise ParameterError(option, f"no such {what}: {p}")
    if p.is_dir():
        raise ParameterError(option, f"{p} is a folder, not a {what}")
    if not os.access(p, os.R_OK):
        raise ParameterError(option, f"cannot read {p}: permission denied")
    return p


def check_distinct(paths) -> None:
    """Refuse two options that name the same output file: ``paths`` maps option -> path (or None)."""
    seen = {}
    for option, path in paths.items():
        if path is None:
            continue
        key = os.path.abspath(os.fspath(path))
        if key in seen:
            raise ParameterError(option.split()[0], f"names the same file as {seen[key].split()[0]}: {path}")
        seen[key] = option
