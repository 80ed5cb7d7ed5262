"""The command line, a scene and the ``--help`` texts state and enforce the same range for one setting.

Each case reads the range a front-end announces (``--help``, ``run --help-scene``), then gives a
value just outside it to every front-end: each must refuse it before any work, in one line naming
its own option or key and the same range, and leave no file behind.
"""

from __future__ import annotations

import re

import pytest

from acoustiviz.cli import main


def call(argv):
    """Run the command line in-process; return its exit status."""
    try:
        return int(main(argv) or 0)
    except SystemExit as exc:  # argparse refusals and --help
        return int(exc.code or 0)


@pytest.fixture
def here(tmp_path, monkeypatch):
    """A fresh, empty working folder."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def refused(argv, capsys, name):
    """Run ``argv``; assert one line on stderr naming ``name`` and exit status 2; return that line."""
    rc = call(argv)
    err = capsys.readouterr().err
    assert "Traceback" not in err, err
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert ": error:" in lines[0] and name in lines[0], err
    return lines[0]


def help_text(argv, capsys) -> str:
    """The ``--help`` (or ``--help-scene``) text of ``argv``, on one line."""
    call(argv)
    return " ".join(capsys.readouterr().out.split())


#: An interval as the help texts write it: ``[4, 512]``, ``(0, 0.5]``.
_INTERVAL = r"([\[(][-+0-9.eE]+, [-+0-9.eEinf]+\])"


def option_range(text: str, option: str) -> str:
    """The interval ``[a, b]`` or ``(a, b]`` that ``--help`` gives after ``option``."""
    m = re.search(re.escape(option) + r" [^\s\]]+ (?![\[-]).*?" + _INTERVAL, text)
    assert m, f"{option} states no range in its help"
    return m.group(1)


def scene_range(text: str, key: str) -> str:
    """The interval ``run --help-scene`` gives for ``key`` (its last component)."""
    m = re.search(r"\b" + re.escape(key) + r" = [^;]*? in " + _INTERVAL, text)
    assert m, f"{key} states no range in --help-scene"
    return m.group(1)


def run_scene(here, text, capsys, key):
    """Write ``text`` as a scene, run it and assert it is refused naming ``key`` with no output folder made."""
    (here / "s.toml").write_text(text)
    line = refused(["run", "s.toml", "--out", "o"], capsys, key)
    assert not (here / "o").exists(), sorted(p.name for p in (here / "o").rglob("*"))
    return line


def above(interval: str) -> str:
    """A number just above the upper end of ``interval`` (as text)."""
    hi = float(interval.split(",")[1].strip(" ]"))
    return repr(int(hi) + 1) if hi == int(hi) and hi >= 1 else repr(2 * hi)


# --------------------------------------------------------------------------- the balloon's resolution
def test_balloon_resolution_one_range_in_help_scene_and_errors(here, capsys):
    interval = option_range(help_text(["render", "balloon", "--help"], capsys), "--resolution")
    assert scene_range(help_text(["run", "--help-scene"], capsys), "n_theta") == interval
    bad = above(interval)
    line = refused(["render", "balloon", "--resolution", bad, "--png", "b.png"], capsys, "--resolution")
    assert interval in line
    line = run_scene(here, f"[grids.sphere]\nn_theta = {bad}\n[outputs.waveform]\n[outputs.balloon]\n", capsys,
                     "grids.sphere.n_theta")
    assert interval in line
    assert not (here / "b.png").exists()


# --------------------------------------------------------------------------- a room's settings without a room
ROOM_KEYS = [("room_m", "[3.0, 2.0, 2.0]", None), ("source_m", "[1.0, 1.0, 0.02]", ("--source", "1,1,0.02")),
             ("absorption", "0.3", ("--absorption", "0.3")), ("image_order", "2", ("--image-order", "2")),
             ("tolerance_db", "-40.0", ("--tolerance-db", "-40")), ("window_s", "0.01", ("--duration", "0.01"))]


@pytest.mark.parametrize("kind", ["plane", "free", "wall-floor"])
@pytest.mark.parametrize("key, value, argv", ROOM_KEYS, ids=[k[0] for k in ROOM_KEYS])
def test_a_room_setting_without_a_room_is_refused_by_scene_and_command(here, capsys, kind, key, value, argv):
    line = run_scene(here, f'[configuration]\nkind = "{kind}"\n{key} = {value}\n[outputs.waveform]\n', capsys,
                     f"configuration.{key}")
    assert "room" in line.split(key, 1)[1]
    if argv is not None:
        line = refused(["waveform", "--config", kind, *argv, "--csv", "w.csv"], capsys, argv[0])
        assert "--room" in line
        assert not (here / "w.csv").exists()


def test_a_room_scene_still_takes_its_settings(here):
    (here / "s.toml").write_text('[configuration]\nkind = "room"\nroom_m = [3.0, 2.5, 2.0]\nabsorption = 0.4\n'
                                 'source_m = [1.0, 1.0, 0.01905]\nwindow_s = 0.005\n')
    from acoustiviz.scene import load_scene

    geometry = load_scene(here / "s.toml").geometry()
    assert geometry.name == "room" and tuple(geometry.dimensions) == (3.0, 2.5, 2.0)


# --------------------------------------------------------------------------- the forcing frequencies
FORCED_SCENE = '[excitation]\namplitude = 5.0\nfrequencies_hz = "{}"\nstarts = 1\n[outputs.frequency_response]\n'


@pytest.mark.parametrize("text, expected", [("5,6", [5.0, 6.0]), ("4.5, 5.5", [4.5, 5.5]), ("6,5", [5.0, 6.0]),
                                            ("3:7:5", [3.0, 4.0, 5.0, 6.0, 7.0]), ("6", [6.0])])
def test_a_frequency_list_reads_the_same_in_scene_and_command(text, expected):
    from acoustiviz.app.settings.parse import parse_frequencies
    from acoustiviz.scene import scene_from_text
    from acoustiviz.scene.validate import scene_frequencies

    scene = scene_from_text(FORCED_SCENE.format(text))
    assert parse_frequencies(text).tolist() == pytest.approx(expected)
    assert scene_frequencies(scene.data["excitation"]["frequencies_hz"]).tolist() == pytest.approx(expected)


@pytest.mark.parametrize("text", ["5,5", "0,5", "-1", "a,b", "5,,6", "7:3:9", "nan"])
def test_a_bad_frequency_list_is_refused_alike(here, capsys, text):
    cli = refused(["forced", "--force", "5", "--freq", text, "--csv", "f.csv"], capsys, "--freq")
    scene = run_scene(here, FORCED_SCENE.format(text), capsys, "excitation.frequencies_hz")
    assert cli.split("--freq", 1)[1] == scene.split("excitation.frequencies_hz", 1)[1]
    assert not (here / "f.csv").exists()


def test_the_frequency_range_is_one_in_help_scene_and_errors(here, capsys):
    interval = option_range(help_text(["forced", "--help"], capsys), "--freq")
    assert scene_range(help_text(["run", "--help-scene"], capsys), "frequencies_hz") == interval
    bad = above(interval)
    assert interval in refused(["forced", "--force", "5", "--freq", f"5,{bad}"], capsys, "--freq")
    assert interval in run_scene(here, FORCED_SCENE.format(f"5,{bad}"), capsys, "excitation.frequencies_hz")


# --------------------------------------------------------------------------- the damper's tolerance, per solver
def solver_ranges(capsys) -> tuple:
    """The ranges ``damper --help`` states for --rtol: the event and impact-map solvers', and the whole option's."""
    text = help_text(["damper", "--help"], capsys)
    m = re.search(r"--rtol RTOL .*?event and impact-map: .*?in " + _INTERVAL, text)
    assert m, "--rtol states no range of the event solver"
    whole = re.search(r"--rtol RTOL .*?" + _INTERVAL + r" \(default", text)
    assert whole, "--rtol states no range"
    return m.group(1), whole.group(1)


def test_the_rtol_ranges_agree_between_help_scene_and_command(capsys):
    event, whole = solver_ranges(capsys)
    assert scene_range(help_text(["run", "--help-scene"], capsys), "tolerance") == whole
    assert event in help_text(["run", "--help-scene"], capsys)
    assert event != whole


@pytest.mark.parametrize("solver", ["event", "impact-map"])
def test_a_tolerance_beyond_the_solver_is_refused_before_any_output(here, capsys, solver):
    event, _ = solver_ranges(capsys)
    bad = above(event)
    line = refused(["damper", "--solver", solver, "--rtol", bad, "--duration", "1", "--impacts-csv", "i.csv"],
                   capsys, "--rtol")
    assert event in line and solver in line
    line = run_scene(here, f'[damper]\nsolver = "{solver}"\ntolerance = {bad}\nduration_s = 1.0\n'
                           '[outputs.waveform]\n[outputs.impact_table]\n', capsys, "damper.tolerance")
    assert event in line and solver in line
    assert not (here / "i.csv").exists()


def test_the_sweep_states_and_enforces_the_solver_range(here, capsys):
    event, _ = solver_ranges(capsys)
    assert option_range(help_text(["sweep", "--help"], capsys), "--rtol") == event
    line = refused(["sweep", "--rtol", above(event), "--duration", "1", "--out", "sw"], capsys, "--rtol")
    assert event in line
    assert not (here / "sw").exists()


def test_auto_reads_a_coarse_tolerance_and_runs_within_the_solver_range(here, capsys):
    from acoustiviz.scene import scene_from_text

    event, whole = solver_ranges(capsys)
    coarse = above(event)
    assert float(coarse) <= float(whole.split(",")[1].strip(" ]"))
    scene_from_text(f'[damper]\nsolver = "auto"\ntolerance = {coarse}\n')  # loads
    assert call(["damper", "--solver", "auto", "--rtol", coarse, "--duration", "1"]) == 0
    ran = float(re.search(r"\(rtol (\S+)\)", capsys.readouterr().out).group(1))
    lo, hi = (float(v) for v in event.strip("[]").split(","))
    assert lo <= ran <= hi
    assert refused(["damper", "--solver", "auto", "--rtol", above(whole)], capsys, "--rtol")


# --------------------------------------------------------------------------- a sweep's values, the damper's ranges
SWEPT = ["--m", "--gap", "--c1", "--k-hertz", "--v0", "--M", "--K", "--C"]


@pytest.mark.parametrize("option", SWEPT)
def test_a_sweep_states_and_enforces_the_damper_range(here, capsys, option):
    interval = option_range(help_text(["damper", "--help"], capsys), option)
    assert option_range(help_text(["sweep", "--help"], capsys), option) == interval
    bad = above(interval)
    assert interval in refused(["damper", option, bad, "--duration", "1"], capsys, option)
    line = refused(["sweep", option, bad, "--duration", "1", "--out", "sw"], capsys, option)
    assert interval in line
    assert not (here / "sw").exists()


def test_a_mass_ratio_giving_a_mass_out_of_range_is_refused(here, capsys):
    interval = option_range(help_text(["damper", "--help"], capsys), "--m")
    hi = float(interval.split(",")[1].strip(" ]"))
    main_mass = 0.5
    line = refused(["sweep", "--M", str(main_mass), "--mass-ratio", repr(4 * hi / main_mass), "--duration", "1",
                    "--out", "sw"], capsys, "--mass-ratio")
    assert interval in line
    assert not (here / "sw").exists()


def test_a_scene_sweep_states_and_enforces_the_damper_mass_range(here, capsys):
    interval = option_range(help_text(["damper", "--help"], capsys), "--m")
    text = help_text(["run", "--help-scene"], capsys)
    assert re.search(r"mass_kg = a 'start:stop:count' string[^;]*? in " + re.escape(interval), text)
    bad = above(interval)
    line = run_scene(here, f'[outputs.sweep]\nmass_kg = "0.02,{bad}"\n', capsys, "outputs.sweep.mass_kg")
    assert interval in line


# --------------------------------------------------------------------------- the input at fault is the one named
BOUND = re.compile(r"must be (>=|<=) (\S+) ")

BLAMED = [
    (["waveform", "--mass", "1e-308"], "--mass"),
    (["waveform", "--k-hertz", "1e-308"], "--k-hertz"),
    (["damper", "--gap", "1e-308", "--duration", "1"], "--gap"),
    (["damper", "--k-hertz", "1e-308", "--duration", "1"], "--k-hertz"),
]


@pytest.mark.parametrize("argv, option", BLAMED, ids=[" ".join(b[0][:3]) for b in BLAMED])
def test_the_input_out_of_range_is_named_not_the_speed(here, capsys, argv, option):
    line = refused(argv, capsys, option)
    assert "--velocity" not in line and "--v0" not in line
    assert BOUND.search(line), line


@pytest.mark.parametrize("argv, option", [(["waveform", "--velocity", "1e-300"], "--velocity"),
                                          (["damper", "--v0", "1e-300", "--duration", "1"], "--v0")])
def test_a_speed_out_of_range_is_still_the_speed(here, capsys, argv, option):
    refused(argv, capsys, option)


@pytest.mark.parametrize("name, bad", [("gap", 1e-308), ("k_hertz", 1e-308), ("m", 1e-12)])
def test_the_stated_bound_of_a_damper_input_works(name, bad):
    from acoustiviz.constants import PAPER_GAP, PAPER_V0, TABLE1_PARAMETERS
    from acoustiviz.core.limits import check_damper
    from acoustiviz.errors import ParameterError

    given = dict(M=TABLE1_PARAMETERS["M"], K=TABLE1_PARAMETERS["K"], m=TABLE1_PARAMETERS["m"], gap=PAPER_GAP,
                 k_hertz=TABLE1_PARAMETERS["k_hertz"], v=PAPER_V0, duration=1.0)
    given[name] = bad
    with pytest.raises(ParameterError) as err:
        check_damper(**given)
    if name == "m":  # below the solvers' mass ratio: its own rule, named too
        assert err.value.name == "m"
        return
    assert err.value.name == name
    sign, bound = BOUND.search(err.value.detail).groups()
    assert sign == ">="
    check_damper(**{**given, name: 1.01 * float(bound)})  # the bound stated is one that works


@pytest.mark.parametrize("name, bad", [("mass", 1e-308), ("k_hertz", 1e-308), ("k_hertz", 1e-250)])
def test_the_stated_bound_of_an_impact_input_works(name, bad):
    from acoustiviz.core.limits import check_impact

    given = dict(velocity=1.4, k_hertz=5.6e8, mass=0.2259, radius=0.01905, c=343.2, rho=1.204)
    given[name] = bad
    from acoustiviz.errors import ParameterError

    with pytest.raises(ParameterError) as err:
        check_impact(**given)
    assert err.value.name == name
    sign, bound = BOUND.search(err.value.detail).groups()
    check_impact(**{**given, name: float(bound) * (1.01 if sign == ">=" else 0.99)})


@pytest.mark.parametrize("key, value, table", [("mass_kg", "1e-308", "sphere"),
                                               ("k_hertz_n_m1_5", "1e-308", "contact"),
                                               ("gap_m", "1e-308", "damper")])
def test_a_scene_names_the_key_at_fault(here, capsys, key, value, table):
    extra = "[outputs.waveform]\n" if table != "damper" else "[outputs.impact_table]\n"
    line = run_scene(here, f"[{table}]\n{key} = {value}\n{extra}", capsys, f"{table}.{key}")
    assert BOUND.search(line.split(f"{table}.{key}", 1)[1]), line


@pytest.mark.parametrize("speed", ["1e300", "1e-300"])
def test_an_impact_file_speed_out_of_range_names_the_file(here, capsys, speed):
    (here / "imp.csv").write_text(f"time_s,wall,approach_velocity_m_s\n0.5,1,{speed}\n")
    line = refused(["auralize", "--impacts", "imp.csv", "--wav", "a.wav"], capsys, "--impacts")
    assert "--m:" not in line
    assert not (here / "a.wav").exists()


def test_auto_with_a_coarse_tolerance_runs_alike_from_scene_and_command(here, capsys):
    """The tolerance auto runs at is one rule: the command and a scene asking the same make the same impacts."""
    assert call(["damper", "--solver", "auto", "--rtol", "0.01", "--duration", "1", "--impacts-csv", "i.csv"]) == 0
    (here / "s.toml").write_text('[damper]\nsolver = "auto"\ntolerance = 0.01\nduration_s = 1.0\n'
                                 '[outputs.impact_table]\n')
    assert call(["run", "s.toml", "--out", "o", "--quiet"]) == 0
    assert (here / "i.csv").read_bytes() == (here / "o" / "impacts.csv").read_bytes()


@pytest.mark.parametrize("value", ["4.9e-324", "1e-12"])
def test_a_main_mass_too_light_for_the_contacts_is_named(here, capsys, value):
    """The main mass, not the speed left at its default, is blamed (a denormal one made the reduced mass 0)."""
    refused(["damper", "--duration", "1", "--M", value], capsys, "--M")
