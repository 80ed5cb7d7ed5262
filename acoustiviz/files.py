"""Atomic file writing: a crash never leaves a half-written output.

Every writer of the package goes through :func:`atomic_path`: the data go to a temporary file
beside the target, which is renamed onto the target only once complete. A failure on the way
(a full disk, a folder that refuses files, a directory in the target's place) removes the
temporary file and is raised as an :class:`OSError` whose ``filename`` is the *target* (not the
temporary name) and whose message starts with "cannot write", so that a front-end can report it
in one line.

Nothing the user made is replaced behind their back: a target that is a symbolic link, or an
existing file without write permission for its owner (``chmod 444``), is refused with such an
error (:func:`refuse_replacing`) instead of being replaced by a new regular file. Writers whose
library would fail natively or with an untyped error on a full disk (VTK, libsndfile) produce
their bytes in memory and hand them to :func:`write_bytes_atomic`, so that a full disk is an
ordinary :class:`OSError` (``ENOSPC``) and no temporary file is left behind.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from pathlib import Path

from ._validate import LABEL_MAX, label_problem

__all__ = ["atomic_path", "temporary_beside", "refuse_replacing", "label_problem", "LABEL_MAX",
           "write_text_atomic", "write_bytes_atomic", "write_csv_atomic", "CSV_BLOCK_ROWS"]

#: Longest part of the target's stem kept in the temporary file's name (the name must stay
#: within the file system's limit of 255 bytes even for a target near that limit).
_STEM_CHARS = 40


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def temporary_beside(path) -> Path:
    """Create an empty temporary file beside ``path`` (same folder and suffix) and return its path.

    The caller renames it onto ``path`` or removes it. Raises :class:`OSError` when the folder
    does not take new files.
    """
    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem[:_STEM_CHARS]}-", suffix=path.suffix)
    except (ValueError, UnicodeError) as exc:  # a NUL byte or a name the file system cannot encode
        raise OSError(errno.EINVAL, f"not a valid file name ({exc})", str(path)) from None
    os.close(fd)
    return Path(tmp)


def refuse_replacing(path) -> None:
    """Raise :class:`OSError` (``EEXIST``) if ``path`` is a symbolic link or a read-only file.

    A link is never replaced by a regular file (the data would silently stop reaching the
    link's target, or a link planted in an output folder would redirect it); a file whose owner
    has no write permission was protected on purpose. Both are left as they are.
    """
    path = Path(path)
    try:
        st = os.lstat(path)
    except (OSError, ValueError):
        return
    if stat.S_ISLNK(st.st_mode):
        raise OSError(errno.EEXIST, f"it is a symbolic link (to {os.readlink(path)}); "
                                    "remove it or choose another name", str(path))
    if stat.S_ISREG(st.st_mode) and not st.st_mode & stat.S_IWUSR:
        raise OSError(errno.EEXIST, "the file exists and is read-only; make it writable "
                                    "(chmod u+w) or choose another name", str(path))


def _cannot_write(exc: OSError, path: Path) -> OSError:
    """``exc`` as an OSError about ``path`` (the target) with a one-line message."""
    reason = exc.strerror or str(exc)
    if isinstance(exc, IsADirectoryError) or path.is_dir():
        reason = "it is a folder"
    return OSError(exc.errno, f"cannot write: {reason}", str(path))


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; on success rename it onto ``path``.

    The temporary file keeps ``path``'s suffix so that writers which pick a format from the
    suffix (soundfile, matplotlib, pyvista) behave as for the final name. Missing parent folders
    are created. On any failure the temporary file is removed and ``path`` is left as it was;
    an :class:`OSError` is raised again naming ``path``.
    """
    path = Path(path)
    try:
        refuse_replacing(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = temporary_beside(path)
    except OSError as exc:
        raise _cannot_write(exc, path) from exc
    try:
        yield tmp
        # mkstemp creates files readable by the owner only; give outputs the usual permissions
        os.chmod(tmp, 0o666 & ~_umask())
        refuse_replacing(path)  # made a link or read-only while the data were computed
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError):
            raise _cannot_write(exc, path) from exc
        raise


def write_text_atomic(path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (UTF-8); return the path."""
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return Path(path)


def write_bytes_atomic(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; return the path.

    The bytes are written and synced by Python, so that a full disk or a quota is an
    :class:`OSError` naming ``path`` and no temporary file is left behind.
    """
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())
    return Path(path)


#: Rows formatted at a time by :func:`write_csv_atomic` (bounds the text held in memory).
CSV_BLOCK_ROWS = 8192


def write_csv_atomic(path, header, columns, fmt="%.10g") -> Path:
    """Write equal-length columns as CSV with a header row, atomically; return the path.

    The text is that of ``numpy.savetxt(path, column_stack(columns), delimiter=",",
    header=",".join(header), comments="", fmt=fmt)``, formatted a block of
    :data:`CSV_BLOCK_ROWS` rows at a time by one ``%`` operation instead of one per row (the
    per-row Python overhead paid once per block), and encoded in UTF-8.

    Parameters
    ----------
    path : path-like
        Output file.
    header : sequence of str
        Column names.
    columns : sequence of array_like
        One 1-D array per column.
    fmt : str or sequence of str
        One ``%`` format for every column, or one per column.
    """
    import numpy as np

    data = np.column_stack([np.asarray(c) for c in columns])
    fmts = [fmt] * data.shape[1] if isinstance(fmt, str) else list(fmt)
    if len(fmts) != data.shape[1]:
        raise ValueError(f"{len(fmts)} formats for {data.shape[1]} columns")
    row = ",".join(fmts) + "\n"
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        fh.write(",".join(header) + "\n")
        for lo in range(0, data.shape[0], CSV_BLOCK_ROWS):
            block = data[lo:lo + CSV_BLOCK_ROWS]
            fh.write((row * block.shape[0]) % tuple(block.ravel().tolist()))
    return Path(path)
