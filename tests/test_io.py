"""Atomic file writing."""

import pytest


def test_atomic_writes_leave_no_temporary_and_normal_permissions(tmp_path):
    import os

    from acoustiviz.output.writers import atomic_path, write_text_atomic

    target = write_text_atomic(tmp_path / "a.txt", "hello")
    assert target.read_text() == "hello"
    mask = os.umask(0)
    os.umask(mask)
    assert (target.stat().st_mode & 0o777) == (0o666 & ~mask)
    # a failure inside the block keeps the old file intact and removes the temporary one
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("crash")
    assert target.read_text() == "hello"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]
