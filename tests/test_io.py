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


# --------------------------------------------------------------------------- nothing the user made is replaced
def test_a_symbolic_link_is_never_replaced(tmp_path):
    import os

    from acoustiviz.output.writers import write_text_atomic

    target = tmp_path / "elsewhere.txt"
    target.write_text("kept")
    link = tmp_path / "out.txt"
    os.symlink(target, link)
    with pytest.raises(OSError) as info:
        write_text_atomic(link, "new")
    assert info.value.filename == str(link) and "symbolic link" in info.value.strerror
    assert link.is_symlink() and target.read_text() == "kept"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["elsewhere.txt", "out.txt"]


def test_a_read_only_file_is_never_replaced_even_by_root(tmp_path):
    from acoustiviz.output.writers import write_bytes_atomic, write_text_atomic

    target = tmp_path / "out.txt"
    target.write_text("kept")
    target.chmod(0o444)
    for write in (lambda: write_text_atomic(target, "new"), lambda: write_bytes_atomic(target, b"new")):
        with pytest.raises(OSError) as info:
            write()
        assert info.value.filename == str(target) and "read-only" in info.value.strerror
    assert target.read_text() == "kept" and (target.stat().st_mode & 0o777) == 0o444
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_a_link_made_while_the_data_were_computed_is_not_replaced(tmp_path):
    import os

    from acoustiviz.output.writers import atomic_path

    target = tmp_path / "out.txt"
    with pytest.raises(OSError, match="symbolic link"), atomic_path(target) as tmp:
        tmp.write_text("data")
        os.symlink(tmp_path / "nowhere", target)
    assert target.is_symlink() and [p.name for p in tmp_path.iterdir()] == ["out.txt"]


@pytest.mark.parametrize("name", ["a\x00b.txt"])
def test_a_name_the_system_cannot_take_is_an_os_error_naming_it(tmp_path, name):
    from acoustiviz.output.writers import write_text_atomic

    with pytest.raises(OSError) as info:
        write_text_atomic(tmp_path / name, "x")
    assert name in info.value.filename and info.value.strerror.startswith("cannot write")
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_while_writing_bytes_leaves_nothing(tmp_path, monkeypatch):
    import errno

    import acoustiviz.output.writers as writers

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(writers.os, "fsync", full)
    with pytest.raises(OSError) as info:
        writers.write_bytes_atomic(tmp_path / "a.bin", b"x" * 1000)
    assert info.value.errno == errno.ENOSPC and info.value.filename == str(tmp_path / "a.bin")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("label, ok", [
    ("paper", True), ("listener 2", True), ("left-ear_1.5", True), ("é", True),
    ("../../../victim/data", False), ("a/b", False), ("a\\b", False), ("a\x00b", False), ("..", False),
    (".hidden", False), ("tail.", False), ("tail ", False), ("", False), ("x" * 65, False), ("tab\there", False),
    ("CON", False), ("nul.txt", False), ("com1", False), ("lpt9", False), ("console", True),
])
def test_labels_that_become_file_names(label, ok):
    from acoustiviz.output.writers import label_problem

    assert (label_problem(label) is None) == ok
