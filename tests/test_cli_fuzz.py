"""Bad and extreme input to every command: exit 2 with one line naming the option, or exit 0 with finite output.

The command line is called in-process (:func:`acoustiviz.cli.main`) from a fresh folder holding a
folder ``adir`` and a file ``afile``. Every refused case must print exactly one line on stderr,
``acoustiviz CMD: error: ...`` naming the option (or scene argument) the user gave, with no
traceback, and leave no file behind (neither the output nor a temporary file).
"""

from __future__ import annotations

import csv
import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from acoustiviz.cli import main

FAST_DAMPER = ["--duration", "1"]


def call(argv):
    """Run the command line in-process; return its exit status."""
    try:
        return int(main(argv) or 0)
    except SystemExit as exc:  # argparse refusals
        return int(exc.code)


@pytest.fixture
def here(tmp_path, monkeypatch):
    """A fresh working folder with a sub-folder ``adir`` and a file ``afile``."""
    (tmp_path / "adir").mkdir()
    (tmp_path / "afile").write_text("not a folder\n")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def assert_user_error(rc, err, option):
    assert "Traceback" not in err, err
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert ": error:" in lines[0], err
    assert option in lines[0], err


def left_over(folder):
    """Everything in ``folder`` besides the fixture's ``adir`` and ``afile`` (recursively)."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.name not in ("adir", "afile"))


CASES = [
    # --- waveform: the reproductions first
    (["waveform", "--png", "w.xyz"], "--png"),
    (["waveform", "--csv", "adir"], "--csv"),
    (["waveform", "--velocity", "1e200", "--csv", "w.csv"], "--velocity"),
    (["waveform", "--csv", "afile/x.csv"], "--csv"),
    (["waveform", "--csv", "missing/x.csv"], "--csv"),
    (["waveform", "--csv", ""], "--csv"),
    (["waveform", "--csv", "w"], "--csv"),
    (["waveform", "--velocity", "nan"], "--velocity"),
    (["waveform", "--velocity", "inf"], "--velocity"),
    (["waveform", "--velocity", "-0"], "--velocity"),
    (["waveform", "--velocity", "1e-300"], "--velocity"),
    (["waveform", "--velocity", "1e100"], "--velocity"),  # the option typed, not one left at its default
    (["waveform", "--radius", "1e-9"], "--radius"),
    (["waveform", "--radius", "1e-300"], "--radius"),
    (["waveform", "--radius", "1e200"], "--radius"),
    (["waveform", "--density", "1e300"], "--density"),
    (["waveform", "--k-hertz", "1e-300"], "--velocity"),
    (["waveform", "--c", "1e200"], "--velocity"),
    (["waveform", "--rho", "1e300"], "--velocity"),
    (["waveform", "--distance", "1e300"], "--distance"),
    (["waveform", "--distance", "1e10"], "--distance"),
    (["waveform", "--angle", "1e300"], "--angle"),
    (["waveform", "--samples-per-duration", "1000000000"], "--samples-per-duration"),
    (["waveform", "--samples-per-duration", "10"], "--samples-per-duration"),
    (["waveform", "--material", "ünobtainium"], "--material"),
    (["waveform", "--max-memory", "0"], "--max-memory"),
    (["waveform", "--max-memory", "nan"], "--max-memory"),
    (["waveform", "--velocity", "-1e200"], "--velocity"),
    # --- directivity
    (["directivity", "--step", "1e-9", "--csv", "d.csv"], "--step"),
    (["directivity", "--step", "0"], "--step"),
    (["directivity", "--step", "nan"], "--step"),
    (["directivity", "--step", "0.001", "--max-memory", "1"], "--step"),
    (["directivity", "--distance", "1e300"], "--distance"),
    (["directivity", "--distance", "1e-300"], "--distance"),
    (["directivity", "--png", "adir"], "--png"),
    (["directivity", "--png", "d.wav"], "--png"),
    # --- damper
    (["damper", "--v0", "1e200", "--impacts-csv", "i.csv", *FAST_DAMPER], "--v0"),
    (["damper", "--v0", "1e-300", *FAST_DAMPER], "--v0"),
    (["damper", "--v0", "nan", *FAST_DAMPER], "--v0"),
    (["damper", "--c1", "1e300", *FAST_DAMPER], "--c1"),
    (["damper", "--duration", "1e-300"], "--duration"),
    (["damper", "--duration", "1e9"], "--duration"),
    (["damper", "--duration", "inf"], "--duration"),
    (["damper", "--M", "1e300", *FAST_DAMPER], "--duration"),
    (["damper", "--m", "1e-300", *FAST_DAMPER], "--m"),
    (["damper", "--m", "1e-9", *FAST_DAMPER], "--m"),
    (["damper", "--K", "1e308", *FAST_DAMPER], "--duration"),
    (["damper", "--gap", "1e-300", *FAST_DAMPER], "--v0"),
    (["damper", "--solver", "newmark", "--dt", "1e-300", *FAST_DAMPER], "--dt"),
    (["damper", "--solver", "impact-map", "--v0", "1e200", *FAST_DAMPER], "--v0"),
    (["damper", "--impacts-csv", "afile/i.csv", *FAST_DAMPER], "--impacts-csv"),
    (["damper", "--impacts-csv", "adir", *FAST_DAMPER], "--impacts-csv"),
    (["damper", "--png", "p.nope", *FAST_DAMPER], "--png"),
    # --- sweep and design
    (["sweep", "--out", "afile/x", "--quiet"], "--out"),
    (["sweep", "--out", "afile", "--quiet"], "--out"),
    (["sweep", "--out", "s", "--gap", "0.01:0.05:1000000000", "--quiet"], "--gap"),
    (["sweep", "--out", "s", "--duration", "1e9", "--quiet"], "--duration"),
    (["sweep", "--out", "s", "--M", "nan", "--quiet"], "--M"),
    (["design", "--sweep", "missing", "--inclination", "0.008"], "--sweep"),
    (["design", "--sweep", "afile", "--inclination", "0.008"], "--sweep"),
    (["design", "--sweep", "adir", "--inclination", "nan"], "--inclination"),
    # --- render
    (["render", "balloon", "--png", "b.xyz"], "--png"),
    (["render", "balloon", "--png", "adir"], "--png"),
    (["render", "balloon", "--png", "b.png", "--distance", "1e300"], "--distance"),
    (["render", "snapshot", "--png", "s.png", "--extent", "1e300"], "--extent"),
    (["render", "snapshot", "--png", "afile/s.png"], "--png"),
    (["render", "animation", "--gif", "a.gif", "--frames", "2000", "--size", "8192x8192"], "--frames"),
    (["render", "animation", "--gif", "afile/a.gif"], "--gif"),
    (["render", "animation", "--gif", "a.gif", "--extent", "1e300"], "--extent"),
    # --- auralize
    (["auralize", "--wav", "x.mp3"], "--wav"),
    (["auralize", "--wav", "adir"], "--wav"),
    (["auralize", "--wav", "afile/x.wav"], "--wav"),
    (["auralize", "--wav", "x.wav", "--duration", "1e9"], "--duration"),
    (["auralize", "--wav", "x.wav", "--impacts", "missing.csv"], "--impacts"),
    (["auralize", "--wav", "x.wav", "--impacts", "adir"], "--impacts"),
    (["auralize", "--wav", "x.wav", "--v0", "1e200", *FAST_DAMPER], "--v0"),
    (["auralize", "--wav", "x.wav", "--png", "x.wav"], "--png"),
    (["auralize", "--wav", "x.wav", "--radius", "1e200", *FAST_DAMPER], "--radius"),
    (["auralize", "--wav", "x.wav", "--c", "1e-30", *FAST_DAMPER], "--c"),
    (["auralize", "--wav", "x.wav", "--gap", "1e308", *FAST_DAMPER], "--gap"),
    (["auralize", "--wav", "x.wav", "--m", "1e200", *FAST_DAMPER], "--m"),
    # --- run
    (["run", "--out", "afile/x"], "--out"),
    (["run", "--out", "afile"], "--out"),
    (["run", "adir", "--out", "r"], "SCENE"),
    (["run", "missing.toml", "--out", "r"], "SCENE"),
    (["run", "--out", "r", "--max-memory", "-1"], "--max-memory"),
]


@pytest.mark.parametrize("argv, option", CASES, ids=[" ".join(c[0]) for c in CASES])
def test_bad_input_is_one_line_naming_the_option(here, capsys, argv, option):
    rc = call(argv)
    assert_user_error(rc, capsys.readouterr().err, option)
    assert left_over(here) == []


def test_a_failed_write_leaves_nothing_and_names_the_file(here, capsys, monkeypatch):
    import acoustiviz.output.writers as writers

    def refuse(src, dst):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(writers.os, "replace", refuse)
    rc = call(["waveform", "--csv", "w.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "w.csv")
    assert "cannot write" in err
    assert left_over(here) == []


def test_atomic_writer_names_the_target_not_its_temporary_file(here):
    from acoustiviz.output.writers import write_text_atomic

    with pytest.raises(OSError) as info:
        write_text_atomic(here / "adir", "x")
    assert info.value.filename == str(here / "adir")
    assert "folder" in info.value.strerror
    assert list((here / "adir").iterdir()) == []


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0,
                    reason="root writes into folders without write permission; nothing to refuse")
def test_unwritable_folder_is_refused_before_work(here, capsys):
    ro = here / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        rc = call(["waveform", "--csv", "ro/w.csv"])
    finally:
        ro.chmod(0o755)
    assert_user_error(rc, capsys.readouterr().err, "--csv")


@pytest.fixture
def read_only_folder(here):
    """A folder on a tmpfs mounted read-only (skipped where this process may not mount one)."""
    import shutil
    import subprocess

    ro = here / "rofs"
    ro.mkdir()
    if os.name != "posix" or shutil.which("mount") is None:
        pytest.skip("no mount command")
    made = subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=1m", "tmpfs", str(ro)], capture_output=True)
    if made.returncode != 0:
        pytest.skip("cannot mount a read-only tmpfs here: " + made.stderr.decode(errors="replace").strip())
    try:
        yield ro
    finally:
        subprocess.run(["umount", str(ro)], capture_output=True, check=False)


@pytest.mark.parametrize("argv, option", [
    (["waveform", "--csv", "rofs/w.csv"], "--csv"),
    (["waveform", "--png", "rofs/w.png"], "--png"),
    (["directivity", "--csv", "rofs/d.csv"], "--csv"),
    (["damper", *FAST_DAMPER, "--impacts-csv", "rofs/i.csv"], "--impacts-csv"),
    (["auralize", "--duration", "1", "--wav", "rofs/a.wav"], "--wav"),
    (["render", "snapshot", "--png", "rofs/s.png"], "--png"),
    (["sweep", "--gap", "0.03", "--m", "0.04", "--duration", "1", "--out", "rofs/sweep", "--quiet"], "--out"),
    (["run", "--out", "rofs/out"], "--out"),
])
def test_read_only_file_system_is_refused_before_work(read_only_folder, argv, option, capsys):
    rc = call(argv)
    assert_user_error(rc, capsys.readouterr().err, option)
    assert list(read_only_folder.iterdir()) == []


def test_the_cap_is_documented_and_can_be_raised(capsys):
    with pytest.raises(SystemExit):
        main(["waveform", "--help"])
    out = capsys.readouterr().out
    assert "--max-memory" in out and "2048" in out


def test_max_memory_lets_through_what_the_default_refuses(here, capsys):
    argv = ["directivity", "--step", "0.01", "--max-memory", "0.05"]
    assert_user_error(call(argv), capsys.readouterr().err, "--step")
    assert call(argv[:-2] + ["--max-memory", "64"]) == 0


# --- property-based: a pool of bad and extreme values in every numeric option of a single impact
POOL = ["nan", "inf", "0", "-0", "1e-300", "1e-30", "1e308", "1e200", "1e30", "-1", "", "ü", "1e-9", "3"]
IMPACT_OPTIONS = ["--radius", "--velocity", "--k-hertz", "--density", "--c", "--rho", "--distance", "--angle"]


def _finite_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))[1:]
    data = np.array(rows, dtype=float)
    return bool(np.all(np.isfinite(data)))


@settings(max_examples=150, derandomize=True, deadline=None, phases=(Phase.explicit, Phase.generate),
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(option=st.sampled_from(IMPACT_OPTIONS), value=st.sampled_from(POOL))
def test_waveform_fuzz_either_finite_or_one_line(here, capsys, option, value):
    for f in here.glob("w.csv"):
        f.unlink()
    rc = call(["waveform", option, value, "--csv", "w.csv"])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    if rc == 0:
        assert _finite_csv(here / "w.csv"), (option, value)
        assert "nan" not in out.lower()
    else:
        assert_user_error(rc, err, "--")
        assert not (here / "w.csv").exists()
        assert left_over(here) == []


DAMPER_OPTIONS = ["--M", "--K", "--C", "--m", "--gap", "--k-hertz", "--c1", "--v0", "--duration"]


@settings(max_examples=150, derandomize=True, deadline=None, phases=(Phase.explicit, Phase.generate),
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(option=st.sampled_from(DAMPER_OPTIONS), value=st.sampled_from(POOL))
def test_damper_fuzz_either_finite_or_one_line(here, capsys, option, value):
    argv = ["damper", *FAST_DAMPER, option, value]
    rc = call(argv)
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    if rc == 2:
        assert_user_error(rc, err, "--")
    else:
        assert rc in (0, 1), err  # 1: the solver stopped early, reported on stdout
        assert "damping inclination" in out
        closure = out.split("energy closure: ")[1].split()[0]
        assert closure == "no" or math.isfinite(float(closure)), out
