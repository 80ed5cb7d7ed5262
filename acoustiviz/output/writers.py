"""Atomic file writing: a crash never leaves a half-written output."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

__all__ = ["atomic_path", "write_text_atomic", "write_csv_atomic"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; on success rename it onto ``path``.

    The temporary file keeps ``path``'s suffix so that writers which pick a format from the
    suffix (soundfile, matplotlib, pyvista) behave as for the final name.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}-", suffix=path.suffix)
    os.close(fd)
    try:
        yield Path(tmp)
        # mkstemp creates files readable by the owner only; give outputs the usual permissions
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
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
