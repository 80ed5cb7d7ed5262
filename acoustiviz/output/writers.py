"""Atomic file writing: a crash never leaves a half-written output.

Every writer of the package goes through :func:`atomic_path`: the data go to a temporary file
beside the target, which is renamed onto the target only once complete. A failure on the way
(a full disk, a folder that refuses files, a directory in the target's place) removes the
temporary file and is raised as an :class:`OSError` whose ``filename`` is the *target* (not the
temporary name) and whose message starts with "cannot write", so that a front-end can report it
in one line.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

__all__ = ["atomic_path", "temporary_beside", "write_text_atomic", "write_csv_atomic"]

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
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem[:_STEM_CHARS]}-", suffix=path.suffix)
    os.close(fd)
    return Path(tmp)


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
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = temporary_beside(path)
    except OSError as exc:
        raise _cannot_write(exc, path) from exc
    try:
        yield tmp
        # mkstemp creates files readable by the owner only; give outputs the usual permissions
        os.chmod(tmp, 0o666 & ~_umask())
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


def write_csv_atomic(path, header, columns, fmt="%.10g") -> Path:
    """Write equal-length columns as CSV with a header row, atomically; return the path.

    Parameters
    ----------
    path : path-like
        Output file.
    header : sequence of str
        Column names.
    columns : sequence of array_like
        One 1-D array per column.
    fmt : str or sequence of str
        ``numpy.savetxt`` format(s).
    """
    import numpy as np

    data = np.column_stack([np.asarray(c) for c in columns])
    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, delimiter=",", header=",".join(header), comments="", fmt=fmt)
    return Path(path)
