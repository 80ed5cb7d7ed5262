"""Atomic file writing."""

import pytest


def test_atomic_writes_leave_no_temporary_and_normal_permissions(tmp_path):
    import os

    from acoustiviz.files import atomic_path, write_text_atomic

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

    from acoustiviz.files import write_text_atomic

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
    from acoustiviz.files import write_bytes_atomic, write_text_atomic

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

    from acoustiviz.files import atomic_path

    target = tmp_path / "out.txt"
    with pytest.raises(OSError, match="symbolic link"), atomic_path(target) as tmp:
        tmp.write_text("data")
        os.symlink(tmp_path / "nowhere", target)
    assert target.is_symlink() and [p.name for p in tmp_path.iterdir()] == ["out.txt"]


@pytest.mark.parametrize("name", ["a\x00b.txt"])
def test_a_name_the_system_cannot_take_is_an_os_error_naming_it(tmp_path, name):
    from acoustiviz.files import write_text_atomic

    with pytest.raises(OSError) as info:
        write_text_atomic(tmp_path / name, "x")
    assert name in info.value.filename and info.value.strerror.startswith("cannot write")
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_while_writing_bytes_leaves_nothing(tmp_path, monkeypatch):
    import errno

    import acoustiviz.files as files

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(files.os, "fsync", full)
    with pytest.raises(OSError) as info:
        files.write_bytes_atomic(tmp_path / "a.bin", b"x" * 1000)
    assert info.value.errno == errno.ENOSPC and info.value.filename == str(tmp_path / "a.bin")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("label, ok", [
    ("paper", True), ("listener 2", True), ("left-ear_1.5", True), ("é", True),
    ("../../../victim/data", False), ("a/b", False), ("a\\b", False), ("a\x00b", False), ("..", False),
    (".hidden", False), ("tail.", False), ("tail ", False), ("", False), ("x" * 65, False), ("tab\there", False),
    ("CON", False), ("nul.txt", False), ("com1", False), ("lpt9", False), ("console", True),
])
def test_labels_that_become_file_names(label, ok):
    from acoustiviz.files import label_problem

    assert (label_problem(label) is None) == ok


# --------------------------------------------------------------------------- CSV columns
@pytest.mark.parametrize("rows", [0, 1, 3, 8192, 8193, 20000])
def test_csv_columns_are_numpys_savetxt_text(tmp_path, rows):
    # the block formatting writes the text numpy.savetxt writes for the same columns and formats
    import io

    import numpy as np

    from acoustiviz.files import write_csv_atomic

    rng = np.random.default_rng(rows)
    cols = [rng.normal(size=rows) * 10.0 ** rng.integers(-30, 30, size=rows) for _ in range(4)]
    cols.append(np.arange(rows))  # an integer column
    if rows >= 3:
        cols[0][:3] = [np.nan, np.inf, -0.0]
        cols[1][:3] = [-np.inf, 0.0, 1e-300]
    fmts = ["%.9e", "%.6f", "%.10g", "%.10e", "%d"]
    header = ["x_m", "level_db", "p_pa", "t_s", "index"]
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack(cols), delimiter=",", header=",".join(header), comments="", fmt=fmts)
    path = write_csv_atomic(tmp_path / "a.csv", header, cols, fmt=fmts)
    assert path.read_bytes() == buf.getvalue().encode()
    one = write_csv_atomic(tmp_path / "b.csv", header[:2], cols[:2], fmt="%.8g")  # one format for all columns
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack(cols[:2]), delimiter=",", header=",".join(header[:2]), comments="", fmt="%.8g")
    assert one.read_bytes() == buf.getvalue().encode()


def test_csv_columns_refuse_a_format_count_that_does_not_match(tmp_path):
    import numpy as np

    from acoustiviz.files import write_csv_atomic

    with pytest.raises(ValueError, match="2 formats for 3 columns"):
        write_csv_atomic(tmp_path / "a.csv", ["a", "b", "c"], [np.ones(2)] * 3, fmt=["%g", "%g"])
    assert not (tmp_path / "a.csv").exists()
