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
from pathlib import Path

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
    (["waveform", "--k-hertz", "1e-300"], "--k-hertz"),  # the input at fault, not the speed left at its default
    # outside the medium's records' ranges, as a scene's [medium]: refused naming the option before the physics
    (["waveform", "--c", "1e200"], "--c"),
    (["waveform", "--rho", "1e300"], "--rho"),
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
    (["damper", "--M", "1e300", *FAST_DAMPER], "--M"),  # outside the record's range: refused before the physics
    (["damper", "--M", "1e6", *FAST_DAMPER], "--duration"),  # in range, but its period outlasts the run
    (["damper", "--m", "1e-300", *FAST_DAMPER], "--m"),
    (["damper", "--m", "1e-9", *FAST_DAMPER], "--m"),
    (["damper", "--K", "1e308", *FAST_DAMPER], "--K"),
    (["damper", "--K", "1e-3", *FAST_DAMPER], "--duration"),
    (["damper", "--gap", "1e-300", *FAST_DAMPER], "--gap"),
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
@pytest.mark.slow
def test_bad_input_is_one_line_naming_the_option(here, capsys, argv, option):
    rc = call(argv)
    assert_user_error(rc, capsys.readouterr().err, option)
    assert left_over(here) == []


def test_a_failed_write_leaves_nothing_and_names_the_file(here, capsys, monkeypatch):
    import acoustiviz.files as files

    def refuse(src, dst):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(files.os, "replace", refuse)
    rc = call(["waveform", "--csv", "w.csv"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "w.csv")
    assert "cannot write" in err
    assert left_over(here) == []


def test_atomic_writer_names_the_target_not_its_temporary_file(here):
    from acoustiviz.files import write_text_atomic

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
    (["forced", "--force", "5", "--freq", "5", "--png", "rofs/f.png"], "--png"),
    (["forced", "--force", "5", "--freq", "5", "--wav", "rofs/f.wav"], "--wav"),
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


@pytest.mark.slow
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
@pytest.mark.slow
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
@pytest.mark.slow
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


# =========================================================================== second fuzz: files, names, disks
def run_cli(argv, capsys):
    """Exit status and stderr of one in-process command (stdout dropped)."""
    rc = call(argv)
    return rc, capsys.readouterr().err


WAVEFORM_SCENE = """
[[listeners]]
name = {name}
distance_m = 0.7
angle_deg = 45.0
[outputs]
waveform = true
"""


# --- hostile names: a scene never chooses where files go beyond --out
@pytest.mark.parametrize("name", ["../../../victim/data", "../escape", "/abs/path", "a/b", "a\\\\b", "a\\u0000b", "..",
                                  ".hidden", "CON", "nul", "com1.x", "tail.", "x" * 65, "tab\\there"])
def test_a_listener_name_cannot_choose_a_file_outside_the_output_folder(here, capsys, name):
    work = here / "a" / "b" / "c"
    work.mkdir(parents=True)
    (work / "scene.toml").write_text(WAVEFORM_SCENE.format(name=f'"{name}"'))
    before = sorted(str(p) for p in here.rglob("*"))
    rc, err = run_cli(["run", str(work / "scene.toml"), "--out", str(work / "out"), "--quiet"], capsys)
    assert_user_error(rc, err, "listeners[0].name")
    assert "scene.toml" in err
    assert sorted(str(p) for p in here.rglob("*")) == before  # nothing made, not even the output folder


def test_two_listeners_of_one_name_are_refused_before_any_work(here, capsys):
    text = WAVEFORM_SCENE.format(name='"front"') + WAVEFORM_SCENE.format(name='"Front"').replace("[outputs]\n", "") \
        .replace("waveform = true\n", "")
    (here / "dup.toml").write_text(text)
    rc, err = run_cli(["run", "dup.toml", "--out", "out", "--quiet"], capsys)
    assert_user_error(rc, err, "listeners[1].name")
    assert "'Front'" in err and "listeners[0]" in err
    assert left_over(here) == ["dup.toml"]


def test_a_default_listener_name_counts_as_taken(here, capsys):
    text = WAVEFORM_SCENE.format(name='"listener2"') + "[[listeners]]\ndistance_m = 0.5\nangle_deg = 30.0\n"
    (here / "dup.toml").write_text(text)
    rc, err = run_cli(["run", "dup.toml", "--out", "out", "--quiet"], capsys)
    assert_user_error(rc, err, "listeners[1].name")


def test_an_output_path_escaping_the_run_folder_is_refused_by_the_run_itself(tmp_path):
    from acoustiviz.app.pipeline import RunContext
    from acoustiviz.errors import ParameterError
    from acoustiviz.scene import default_scene

    ctx = RunContext(default_scene(), tmp_path / "out")
    for bad in ("../x.csv", "a/b.csv", "..", "", "a\x00.csv", "a\\b.csv"):
        with pytest.raises(ParameterError, match="not a file name inside"):
            ctx.path(bad)
    assert ctx.path("waveform_paper.csv") == tmp_path / "out" / "waveform_paper.csv"


# --- nothing the user made is replaced
def test_a_read_only_output_is_refused_before_work_and_kept(here, capsys):
    target = here / "w.csv"
    target.write_text("mine\n")
    target.chmod(0o444)
    rc, err = run_cli(["waveform", "--csv", "w.csv"], capsys)
    assert_user_error(rc, err, "--csv")
    assert "read-only" in err
    assert target.read_text() == "mine\n" and (target.stat().st_mode & 0o777) == 0o444
    assert left_over(here) == ["w.csv"]


def test_a_symbolic_link_output_is_refused_before_work_and_kept(here, capsys):
    (here / "real.csv").write_text("mine\n")
    os.symlink("real.csv", here / "w.csv")
    rc, err = run_cli(["waveform", "--csv", "w.csv"], capsys)
    assert_user_error(rc, err, "--csv")
    assert "symbolic link" in err
    assert (here / "w.csv").is_symlink() and (here / "real.csv").read_text() == "mine\n"


def test_run_force_keeps_read_only_files_and_links_in_the_folder(here, capsys):
    (here / "s.toml").write_text(WAVEFORM_SCENE.format(name='"front"'))
    out = here / "out"
    out.mkdir()
    (out / "waveform_front.csv").write_text("mine\n")
    (out / "waveform_front.csv").chmod(0o444)
    rc, err = run_cli(["run", "s.toml", "--out", "out", "--quiet", "--force"], capsys)
    assert_user_error(rc, err, "waveform_front.csv")
    assert (out / "waveform_front.csv").read_text() == "mine\n"
    (out / "waveform_front.csv").chmod(0o644)
    (out / "waveform_front.csv").unlink()
    (here / "victim.png").write_text("mine\n")
    os.symlink(here / "victim.png", out / "waveform_front.png")
    rc, err = run_cli(["run", "s.toml", "--out", "out", "--quiet", "--force"], capsys)
    assert_user_error(rc, err, "waveform_front.png")
    assert (here / "victim.png").read_text() == "mine\n" and (out / "waveform_front.png").is_symlink()
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


SMALL_SWEEP = ["sweep", "--m", "0.04", "--duration", "0.5", "--quiet", "--out", "sw"]


@pytest.mark.slow
def test_sweep_overwrite_twice_keeps_both_previous_sweeps_with_their_spec(here, capsys):
    import json

    from acoustiviz.sweep import load_sweep, read_spec

    gaps = ["0.03", "0.04", "0.05"]
    for g in gaps:
        assert call([*SMALL_SWEEP, "--gap", g, "--overwrite"]) == 0, capsys.readouterr().err
    capsys.readouterr()
    names = {p.name for p in (here / "sw").iterdir()}
    current = {p.name for p in (here / "sw").iterdir() if ".previous-" not in p.name}
    assert {"sweep.csv", "sweep.json", "design_table.csv"} <= current
    for n in (1, 2):  # every file of each earlier sweep, moved aside under its number
        assert {f"{Path(c).stem}.previous-{n}{Path(c).suffix}" for c in current} <= names
    assert len(names) == 3 * len(current)
    for n, g in ((1, gaps[0]), (2, gaps[1])):  # each moved-aside journal beside the settings that made it
        doc = json.loads((here / "sw" / f"sweep.previous-{n}.json").read_text())
        assert doc["spec"]["gap"] == [float(g)]
        aside = here / f"aside{n}"
        aside.mkdir()
        (aside / "sweep.json").write_text((here / "sw" / f"sweep.previous-{n}.json").read_text())
        (aside / "sweep.csv").write_text((here / "sw" / f"sweep.previous-{n}.csv").read_text())
        table = load_sweep(aside)
        assert table.complete and list(table["gap_m"]) == [float(g)]
    assert read_spec(here / "sw").gap == (float(gaps[2]),)


@pytest.fixture(scope="module")
def finished_sweep(tmp_path_factory):
    """A finished one-design sweep folder (copied by each test before damaging it)."""
    folder = tmp_path_factory.mktemp("sweep") / "sw"
    assert main(["sweep", "--gap", "0.03", "--m", "0.04", "--duration", "0.5", "--quiet", "--out", str(folder)]) == 0
    return folder


def _damage(kind, folder):
    csv_path, json_path = folder / "sweep.csv", folder / "sweep.json"
    if kind == "binary csv":
        csv_path.write_bytes(b"\x00\xff\xfe\x80 binary\n")
    elif kind == "word in a number":
        lines = csv_path.read_text().splitlines()
        cells = lines[1].split(",")
        cells[2] = "fast"  # inclination_two_maxima_m_s
        csv_path.write_text("\n".join([lines[0], ",".join(cells)]) + "\n")
    elif kind == "word in an integer":
        lines = csv_path.read_text().splitlines()
        cells = lines[1].split(",")
        cells[5] = "many"  # n_impacts
        csv_path.write_text("\n".join([lines[0], ",".join(cells)]) + "\n")
    elif kind == "json list":
        json_path.write_text("[1, 2, 3]\n")
    elif kind == "binary json":
        json_path.write_bytes(b"\xff\xfe\x00{")
    elif kind == "json without spec":
        json_path.write_text('{"format": "acoustiviz-sweep"}\n')
    elif kind == "spec not a table":
        json_path.write_text('{"format": "acoustiviz-sweep", "format_version": 3, "spec": [1]}\n')


DAMAGES = ["binary csv", "word in a number", "word in an integer", "json list", "binary json", "json without spec",
           "spec not a table"]


@pytest.mark.parametrize("kind", DAMAGES)
def test_a_damaged_sweep_folder_is_one_line_for_design(here, capsys, finished_sweep, kind):
    import shutil

    shutil.copytree(finished_sweep, here / "sw")
    _damage(kind, here / "sw")
    rc, err = run_cli(["design", "--sweep", "sw", "--inclination", "0.008"], capsys)
    assert_user_error(rc, err, "--sweep")
    assert "sw" in err


@pytest.mark.parametrize("kind", ["binary csv", "word in a number", "word in an integer"])
def test_a_damaged_journal_is_one_line_when_resuming(here, capsys, finished_sweep, kind):
    import shutil

    shutil.copytree(finished_sweep, here / "sw")
    _damage(kind, here / "sw")
    damaged = (here / "sw" / "sweep.csv").read_bytes()
    rc, err = run_cli(["sweep", "--gap", "0.03", "--m", "0.04", "--duration", "0.5", "--quiet", "--out", "sw"], capsys)
    assert_user_error(rc, err, "--out")
    assert "sweep.csv" in err
    assert (here / "sw" / "sweep.csv").read_bytes() == damaged  # left for the user to inspect


@pytest.mark.parametrize("kind", ["json list", "binary json", "spec not a table"])
@pytest.mark.slow
def test_a_damaged_settings_file_is_refused_or_moved_aside(here, capsys, finished_sweep, kind):
    import shutil

    shutil.copytree(finished_sweep, here / "sw")
    _damage(kind, here / "sw")
    argv = ["sweep", "--gap", "0.03", "--m", "0.04", "--duration", "0.5", "--quiet", "--out", "sw"]
    rc, err = run_cli(argv, capsys)
    assert_user_error(rc, err, "--out")
    assert call([*argv, "--overwrite"]) == 0
    assert (here / "sw" / "sweep.previous-1.csv").exists() and (here / "sw" / "sweep.previous-1.json").exists()


# --- corrupt files of every kind read back
def test_a_binary_scene_file_is_one_line(here, capsys):
    (here / "bin.toml").write_bytes(b"\x00\xff\xfe\x80binary")
    rc, err = run_cli(["run", "bin.toml", "--out", "out"], capsys)
    assert_user_error(rc, err, "bin.toml")
    assert left_over(here) == ["bin.toml"]


@pytest.mark.parametrize("content", [b"\x00\xff\xfe\x80binary", b"time_s,wall,approach_velocity_m_s\n0.5,1\n",
                                     b"time_s,wall,approach_velocity_m_s\n0.5,1,fast\n", b""])
def test_a_damaged_impacts_file_is_one_line(here, capsys, content):
    (here / "imp.csv").write_bytes(content)
    rc, err = run_cli(["auralize", "--wav", "a.wav", "--impacts", "imp.csv"], capsys)
    assert_user_error(rc, err, "--impacts")
    assert left_over(here) == ["imp.csv"]


def test_an_impact_far_in_the_future_is_refused_before_allocating(here, capsys):
    (here / "imp.csv").write_text("time_s,wall,approach_velocity_m_s\n0.1,1,0.5\n1e9,-1,0.5\n")
    rc, err = run_cli(["auralize", "--wav", "a.wav", "--impacts", "imp.csv"], capsys)
    assert_user_error(rc, err, "--impacts")
    assert "MB" in err and left_over(here) == ["imp.csv"]


def test_an_output_folder_name_that_is_not_text_is_one_line(here, capsys):
    bad = os.fsdecode(b"out\xff\xfe")
    rc, err = run_cli(["run", "--out", bad, "--quiet"], capsys)
    assert_user_error(rc, err, "--out")
    assert left_over(here) == []
    rc, err = run_cli(["waveform", "--csv", bad + ".csv"], capsys)
    assert_user_error(rc, err, "--csv")


def test_forced_checks_its_outputs_before_computing(here, capsys, monkeypatch):
    import acoustiviz.app.forced as forced

    def never(*args, **kwargs):
        raise AssertionError("computed before checking the outputs")

    monkeypatch.setattr(forced, "attractor_response", never)
    for argv, option in ((["--png", "out.jpgx"], "--png"), (["--csv", "adir"], "--csv"),
                         (["--png", "missing/f.png"], "--png"), (["--wav", "f.mp3"], "--wav"),
                         (["--csv", "f.csv", "--png", "f.csv"], "--png")):
        rc, err = run_cli(["forced", "--force", "5", "--freq", "5", *argv], capsys)
        assert_user_error(rc, err, option)
    assert left_over(here) == []


# --- full disk: injected deterministically (every run), and on a real small tmpfs where root can mount one
def _full_disk(monkeypatch):
    import errno

    import acoustiviz.files as files

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(files.os, "fsync", full)


@pytest.mark.parametrize("argv, target", [
    (["auralize", "--duration", "0.5", "--wav", "a.wav"], "a.wav"),
    (["map", "--resolution", "12", "--vtk", "m.vtu"], "m.vtu"),
    (["render", "balloon", "--resolution", "8", "--vtk", "b.vtu"], "b.vtu"),
])
def test_a_full_disk_is_one_line_naming_the_file_and_leaves_nothing(here, capsys, monkeypatch, argv, target):
    _full_disk(monkeypatch)
    rc, err = run_cli(argv, capsys)
    lines = [ln for ln in err.strip().splitlines() if "X server" not in ln]  # VTK's own log line, not ours
    assert rc == 2 and len(lines) == 1 and target in lines[0] and "No space left" in lines[0], err
    assert "Traceback" not in err
    assert not [p for p in left_over(here) if p.startswith(".") or p == target]



@pytest.fixture
def tiny_disk(here):
    """A 16 KiB tmpfs (skipped where this process may not mount one)."""
    import shutil
    import subprocess

    disk = here / "tiny"
    disk.mkdir()
    if os.name != "posix" or shutil.which("mount") is None or os.geteuid() != 0:
        pytest.skip("mounting a size-limited tmpfs needs root and the mount command")
    made = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", str(disk)], capture_output=True)
    if made.returncode != 0:
        pytest.skip("cannot mount a tmpfs here: " + made.stderr.decode(errors="replace").strip())
    try:
        yield disk
    finally:
        subprocess.run(["umount", str(disk)], capture_output=True, check=False)


@pytest.mark.parametrize("argv", [
    ["map", "--resolution", "40", "--vtk", "tiny/m.vtu"],
    ["map", "--resolution", "40", "--vtk", "tiny/m.vtkhdf"],
    ["render", "balloon", "--resolution", "16", "--vtk", "tiny/b.vtu", "--png", "b.png"],
    ["auralize", "--duration", "1", "--wav", "tiny/a.wav"],
])
@pytest.mark.slow
def test_a_real_full_disk_is_one_line_and_no_crash(tiny_disk, argv):
    import subprocess
    import sys

    # a separate process: a native abort (exit 134) would otherwise take the test run with it
    done = subprocess.run([sys.executable, "-m", "acoustiviz", *argv], cwd=tiny_disk.parent, capture_output=True,
                          text=True, timeout=300)
    lines = [ln for ln in done.stderr.strip().splitlines() if "X server" not in ln]
    assert done.returncode == 2, done.stderr
    assert len(lines) == 1 and "tiny/" in lines[0] and "space" in lines[0], done.stderr
    assert list(tiny_disk.iterdir()) == []


# --- work bounded up front
def test_a_map_too_large_to_compute_is_refused_whatever_the_memory_cap(here, capsys):
    rc, err = run_cli(["map", "--max-memory", "1e12", "--resolution", "20000", "--csv", "m.csv"], capsys)
    assert_user_error(rc, err, "--resolution")
    assert left_over(here) == []


# --- front-ends agree on bad input
DESCENDING_SCENE = """
[excitation]
frequencies_hz = "7:3:9"
[outputs]
frequency_response = true
"""


def test_a_descending_range_is_refused_by_every_front_end(here, capsys):
    rc, err = run_cli(["forced", "--force", "5", "--freq", "7:3:9"], capsys)
    assert_user_error(rc, err, "--freq")
    rc, err = run_cli(["sweep", "--gap", "0.05:0.03:3", "--m", "0.04", "--quiet", "--out", "s"], capsys)
    assert_user_error(rc, err, "--gap")
    (here / "d.toml").write_text(DESCENDING_SCENE)
    rc, err = run_cli(["run", "d.toml", "--out", "out", "--quiet"], capsys)
    assert_user_error(rc, err, "excitation.frequencies_hz")
    for text in ("[outputs.sweep]\ngap_m = \"0.05:0.03:3\"\n", "[outputs.sweep]\nmass_kg = \"0.08:0.02:3\"\n"):
        (here / "d.toml").write_text(text)
        rc, err = run_cli(["run", "d.toml", "--out", "out", "--quiet"], capsys)
        assert_user_error(rc, err, "outputs.sweep.")
    assert left_over(here) == ["d.toml"]


@pytest.mark.parametrize("argv, option", [
    (["forced", "--force", "5", "--freq", "5", "--listener", "0,0,0.01"], "--listener"),
    (["forced", "--force", "5", "--freq", "5", "--listener", "0.01,0,0.02"], "--listener"),
    (["forced", "--force", "5", "--freq", "5", "--listener", "1,0,-0.1"], "--listener"),
    (["auralize", "--wav", "a.wav", "--listener", "0,0,0.01"], "--listener"),
    (["auralize", "--wav", "a.wav", "--listener", "0.01,0,0.02"], "--listener"),
    (["auralize", "--wav", "a.wav", "--listener", "1,0,-0.1"], "--listener"),
])
def test_a_listener_inside_the_sphere_or_below_the_floor_is_refused_like_scenes_do(here, capsys, argv, option):
    rc, err = run_cli(argv, capsys)
    assert_user_error(rc, err, option)
    (here / "in.toml").write_text("[[listeners]]\nposition_m = [0.01, 0.0, 0.02]\n[outputs]\nwaveform = true\n")
    rc, err = run_cli(["run", "in.toml", "--out", "out", "--quiet"], capsys)
    assert_user_error(rc, err, "listeners[0].position_m")


def _one_frequency_fails(monkeypatch):
    """Make every attractor at the last frequency of each response fail, as a solver failure would."""
    import dataclasses

    import acoustiviz.app.forced as forced

    real = forced.attractor_response

    def failing(*args, **kwargs):
        resp = real(*args, **kwargs)
        last = resp.per_frequency[-1]
        broken = tuple(dataclasses.replace(a, success=False, message="injected solver failure")
                       for a in last.attractors)
        per = resp.per_frequency[:-1] + (dataclasses.replace(last, attractors=broken),)
        return dataclasses.replace(resp, per_frequency=per)

    monkeypatch.setattr(forced, "attractor_response", failing)


FAILING_SCENE = """
[excitation]
amplitude = 5.0
frequencies_hz = "5:6:2"
[outputs]
frequency_response = true
"""


@pytest.mark.slow
def test_a_failed_frequency_exits_1_from_the_command_and_from_a_scene(here, capsys, monkeypatch):
    _one_frequency_fails(monkeypatch)
    rc, _ = run_cli(["forced", "--force", "5", "--freq", "5:6:2", "--no-noise", "--csv", "f.csv"], capsys)
    assert rc == 1 and (here / "f.csv").exists()
    (here / "f.toml").write_text(FAILING_SCENE)
    rc, err = run_cli(["run", "f.toml", "--out", "out", "--quiet"], capsys)
    assert rc == 1 and "failed_frequencies_hz = 6" in err
    assert (here / "out" / "frequency_response.csv").exists() and (here / "out" / "summary.md").exists()


@pytest.mark.parametrize("argv, option", [
    (["--inclination", "-1"], "--inclination"), (["--inclination", "0"], "--inclination"),
    (["--inclination", "11"], "--inclination"), (["--tolerance", "0"], "--tolerance"),
    (["--tolerance", "-0.001"], "--tolerance"), (["--band-width", "0"], "--band-width"),
])
def test_design_targets_are_refused_with_exit_2_like_the_scene(here, capsys, finished_sweep, argv, option):
    argv = ["design", "--sweep", str(finished_sweep), "--inclination", "0.008", *argv]
    rc, err = run_cli(argv, capsys)
    assert_user_error(rc, err, option)
    key = {"--inclination": "inclination_m_s", "--tolerance": "tolerance_m_s"}.get(option)
    if key is not None:
        value = argv[-1]
        (here / "d.toml").write_text(f"[outputs.sweep]\n[outputs.design_table]\n{key} = {value}\n")
        rc, err = run_cli(["run", "d.toml", "--out", "out", "--quiet"], capsys)
        assert_user_error(rc, err, f"outputs.design_table.{key}")


# --- messages that say what is wrong, in the user's terms
def test_frequency_messages_say_the_range(here, capsys):
    rc, err = run_cli(["forced", "--force", "5", "--freq", "0"], capsys)
    assert_user_error(rc, err, "--freq")
    assert "in (0, " in err and "Hz" in err and "at most" not in err
    rc, err = run_cli(["forced", "--force", "5", "--freq", "9000"], capsys)
    assert_user_error(rc, err, "--freq")
    assert "natural frequency" in err and "5.033 Hz" in err
    (here / "f.toml").write_text(FAILING_SCENE.replace('"5:6:2"', '"6000"'))
    rc, err = run_cli(["run", "f.toml", "--out", "out", "--quiet"], capsys)
    assert_user_error(rc, err, "excitation.frequencies_hz")


def test_far_wall_names_the_wall_not_an_internal_setting(here, capsys):
    rc, err = run_cli(["directivity", "--config", "wall-floor", "--wall-distance", "1e9"], capsys)
    assert_user_error(rc, err, "--wall-distance")
    assert "memory_limit" not in err


def test_the_scene_wav_rate_rule_is_its_help_and_is_checked_at_load(here, capsys):
    from acoustiviz.constants import SAMPLE_RATES
    from acoustiviz.scene import schema_help

    line = next(ln for ln in schema_help().splitlines() if ln.strip().startswith("rate_hz"))
    assert "one of " + ", ".join(map(str, SAMPLE_RATES)) in line
    (here / "w.toml").write_text("[outputs.wav]\nrate_hz = 8000\n")
    rc, err = run_cli(["run", "w.toml", "--out", "out", "--quiet"], capsys)
    assert_user_error(rc, err, "outputs.wav.rate_hz")
    assert "w.toml" in err and left_over(here) == ["w.toml"]


@pytest.mark.slow
def test_the_operating_noise_sidecar_states_the_files_rate(here, capsys):
    import json

    import soundfile as sf

    rc, err = run_cli(["forced", "--force", "5", "--freq", "5", "--noise-seconds", "0.2", "--wav", "f.wav"], capsys)
    assert rc == 0, err
    info = sf.info(str(here / "f.wav"))
    doc = json.loads((here / "f.json").read_text())
    assert doc["sample_rate_hz"] == info.samplerate == 48000
    assert doc["frames"] == info.frames
    assert doc["duration_s"] == pytest.approx(info.frames / info.samplerate, rel=1e-12)
    assert doc["band_limit"]["stopband_from_hz"] == info.samplerate / 2
    assert "sample_rate" not in doc


def test_a_warning_from_the_computation_is_one_line_not_a_source_listing(here, capsys, monkeypatch):
    import warnings

    import acoustiviz.app.views as views

    real = views.waveform_times

    def noisy(*args, **kwargs):
        warnings.warn("a library's remark\nover two lines", UserWarning, stacklevel=1)
        np.float64(1e308) * np.float64(10.0)  # numpy's overflow RuntimeWarning
        return real(*args, **kwargs)

    monkeypatch.setattr(views, "waveform_times", noisy)
    assert call(["waveform", "--csv", "w.csv"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["acoustiviz waveform: warning: a library's remark over two lines",
                   "acoustiviz waveform: warning: overflow encountered in scalar multiply"]


@pytest.mark.parametrize("wav, sidecar", [
    (b"RIFF\x00\x00garbage", None),
    (b"", None),
    ("good", b"[1, 2"),
    ("good", b"[1, 2]\n"),
    ("good", b"\xff\xfe\x00"),
    ("good", b'{"scale_pa_per_full_scale": "x"}'),
    ("good", b'{"scale_pa_per_full_scale": -1}'),
    ("good", b'{"scale_pa_per_full_scale": null}'),
])
def test_a_damaged_wav_or_sidecar_is_one_line_for_levels(here, capsys, wav, sidecar):
    import soundfile as sf

    if wav == "good":
        sf.write(str(here / "s.wav"), 0.1 * np.sin(np.arange(4800) / 5.0), 48000, subtype="PCM_24")
    else:
        (here / "s.wav").write_bytes(wav)
    if sidecar is not None:
        (here / "s.json").write_bytes(sidecar)
    rc, err = run_cli(["levels", "s.wav", "--csv", "l.csv"], capsys)
    assert_user_error(rc, err, "s.json" if sidecar is not None else "s.wav")
    assert not (here / "l.csv").exists()


@pytest.mark.slow
def test_overwrite_moves_only_the_sweeps_own_files(here, capsys):
    assert call([*SMALL_SWEEP, "--gap", "0.03"]) == 0
    (here / "sw" / "notes.txt").write_text("mine\n")
    assert call([*SMALL_SWEEP, "--gap", "0.04", "--overwrite"]) == 0
    capsys.readouterr()
    assert (here / "sw" / "notes.txt").read_text() == "mine\n"
    assert (here / "sw" / "max_spl_map.previous-1.png").exists() and (here / "sw" / "max_spl_map.png").exists()


ROOM_SCENE = ("[configuration]\nkind = \"room\"\nroom_m = [6.0, 4.0, 3.0]\nabsorption = 0.1\n"
              "source_m = [2.0, 1.5, 0.01905]\nwindow_s = {window}\n\n"
              "[[listeners]]\nname = \"middle\"\nposition_m = [3.0, 2.0, 1.5]\n\n[outputs.waveform]\n")


def test_a_room_window_too_long_for_memory_is_refused_before_its_images_are_counted(here, capsys, monkeypatch):
    """A waveform over a 10 000 s window: its time grid alone exceeds any cap, named before the image order."""
    import acoustiviz.core.reverberation as reverberation

    def sought(*args, **kwargs):
        raise AssertionError("the image order of the window was sought")

    monkeypatch.setattr(reverberation, "energy_order", sought)
    (here / "room.toml").write_text(ROOM_SCENE.format(window="10000"))
    rc = call(["run", "room.toml", "--out", "out"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "configuration.window_s")
    assert "grids.memory_limit_mb" in err, err
    assert left_over(here) == ["room.toml"]


#: One cheap invocation of every command (inputs made by :func:`_capped_inputs`).
CAPPED = {
    "run": ["run", "--out", "o"],
    "run room scene": ["run", "room.toml", "--out", "o"],
    "waveform": ["waveform", "--csv", "w.csv"],
    "directivity": ["directivity", "--step", "30", "--csv", "d.csv"],
    "map": ["map", "--resolution", "21", "--extent", "0.3", "--csv", "m.csv"],
    "damper": ["damper", "--duration", "1", "--impacts-csv", "i.csv"],
    "forced": ["forced", "--force", "5", "--freq", "5", "--starts", "1", "--max-cycles", "60", "--csv", "f.csv"],
    "sweep": ["sweep", "--gap", "0.02,0.04", "--m", "0.04", "--duration", "1", "--workers", "1", "--out", "sw"],
    "design": ["design", "--sweep", "SWEEP", "--inclination", "0.005", "--tolerance", "0.01"],
    "render balloon": ["render", "balloon", "--resolution", "8", "--size", "160x120", "--png", "b.png"],
    "render snapshot": ["render", "snapshot", "--resolution", "31", "--size", "160x120", "--png", "s.png"],
    "render animation": ["render", "animation", "--frames", "3", "--resolution", "21", "--size", "160x120",
                         "--gif", "a.gif"],
    "auralize": ["auralize", "--duration", "0.3", "--wav", "a.wav"],
    "levels": ["levels", "t.wav", "--csv", "l.csv", "--pa-per-fs", "1"],
}


def _capped_inputs(folder: Path, argv: list, sweep: Path) -> list:
    """Write the inputs ``argv`` reads into ``folder``; return ``argv`` with the sweep's folder filled in."""
    from scipy.io import wavfile

    (folder / "room.toml").write_text(ROOM_SCENE.format(window="0.02"))
    wavfile.write(folder / "t.wav", 48000, (0.1 * np.sin(0.1 * np.arange(4800))).astype(np.float32))
    return [str(sweep) if a == "SWEEP" else a for a in argv]


@pytest.mark.parametrize("command", list(CAPPED))
def test_a_cap_that_refuses_everything_refuses_every_command_naming_max_memory(here, capsys, finished_sweep,
                                                                                command):
    """``--max-memory 1e-6`` (one byte) leaves room for no work: every command, a scene's run included,
    refuses before writing anything, naming ``--max-memory`` (a scene's own cap is larger)."""
    argv = _capped_inputs(here, CAPPED[command], finished_sweep)
    before = left_over(here)
    rc = call([*argv, "--max-memory", "1e-6"])
    err = capsys.readouterr().err
    assert_user_error(rc, err, "--max-memory")
    assert left_over(here) == before


@pytest.mark.parametrize("value", ["-0", "0", "nan", "-5"])
def test_a_cap_that_is_not_a_positive_size_is_refused_by_every_command(here, capsys, finished_sweep, value):
    for command in ("design", "levels", "run"):
        argv = _capped_inputs(here, CAPPED[command], finished_sweep)
        rc = call([*argv, f"--max-memory={value}"])
        assert_user_error(rc, capsys.readouterr().err, "--max-memory")
    assert not (here / "o").exists() and not (here / "l.csv").exists()


@pytest.mark.parametrize("c1, cut", [("1000", True), ("20", False)])
def test_a_contact_cut_by_the_end_of_the_run_is_said_where_the_user_reads(here, capsys, c1, cut):
    """With c1 = 1000 N s/m the Table 1 damper is in contact at t = 1 s: the last row's separation
    velocity and restitution are nan, and the run says so in one note; a run ending between contacts
    has none. ``--help`` of ``--impacts-csv`` explains the nan cells."""
    assert call(["damper", "--duration", "1", "--c1", c1, "--impacts-csv", "i.csv"]) == 0
    out = capsys.readouterr().out
    with open("i.csv", newline="") as fh:
        last = list(csv.DictReader(fh))[-1]
    assert math.isnan(float(last["separation_velocity_m_s"])) == cut
    assert math.isnan(float(last["restitution"])) == cut
    notes = [ln for ln in out.splitlines() if ln.startswith("note: the last contact")]
    assert len(notes) == (1 if cut else 0), out
    if cut:
        assert "i.csv" in notes[0] and "nan" in notes[0] and f"{float(last['time_s']):.6g}" in notes[0], notes
        assert 0.0 < float(last["duration_s"]) <= 1.0 - float(last["time_s"]) + 1e-9
    with pytest.raises(SystemExit):
        main(["damper", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "has nan separation_velocity_m_s and restitution" in text
