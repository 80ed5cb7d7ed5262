"""The command line and a scene asking for the same work write the same files.

Each case is one workflow set up twice: as the argv of its command and as the equivalent scene
TOML run by ``acoustiviz run``. Both run in this process and the files they write are compared
byte for byte (CSV, JSON, VTU and the sweep's PNG maps), a sweep's journal line by line in any
order (its rows are written as designs finish), and a WAV by its decoded samples (its sidecar
records its own file name and the scene's). The key figures a command prints and a
scene writes to ``summary.md`` are compared at the precision of the summary.

A disagreement found here is resolved in the application layer, where both front-ends take it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from acoustiviz.cli import main
from acoustiviz.errors import ParameterError


@dataclass(frozen=True)
class Case:
    """One workflow from both front-ends: its argv, its scene and the files that must agree."""

    argv: tuple
    scene: str
    same: tuple  # (CLI file, scene file relative to the run folder), compared byte for byte
    wav: tuple = ()  # (CLI file, scene file): compared by their decoded samples
    rows: tuple = ()  # (CLI file, scene file): the same lines, in any order (a journal written as work finishes)
    figures: dict = field(default_factory=dict)  # summary figure -> regex on the CLI's stdout giving it


PLANE = '[configuration]\nkind = "plane"\n'
#: A room, its absorbing walls and a 5 ms window (the images of first and second order reach 0.5 m).
ROOM_ARGV = ("--room", "3,2.5,2", "--absorption", "0.3", "--source", "1,1,0.01905", "--duration", "0.005")
ROOM = ('[configuration]\nkind = "room"\nroom_m = [3.0, 2.5, 2.0]\nabsorption = [0.3]\n'
        'source_m = [1.0, 1.0, 0.01905]\nwindow_s = 0.005\n')
WAVEFORM_FIGURES = {"max_pa": r"pressure: max (\S+) Pa", "min_pa": r"min (\S+) Pa"}

CASES = {
    "waveform-plane": Case(("waveform", "--config", "plane", "--csv", "w.csv"),
                           PLANE + "[outputs.waveform]\n", (("w.csv", "waveform_paper.csv"),),
                           figures=WAVEFORM_FIGURES),
    "waveform-wall-floor": Case(
        ("waveform", "--config", "wall-floor", "--wall-distance", "0.3", "--velocity", "0.8", "--distance", "0.5",
         "--angle", "30", "--csv", "w.csv"),
        '[configuration]\nkind = "wall-floor"\nwall_distance_m = 0.3\n[impact]\nvelocity_m_s = 0.8\n'
        '[[listeners]]\nname = "a"\ndistance_m = 0.5\nangle_deg = 30.0\n[outputs.waveform]\n',
        (("w.csv", "waveform_a.csv"),), figures=WAVEFORM_FIGURES),
    "waveform-room": Case(
        ("waveform", "--room", "3,4,2.5", "--absorption", "0.4", "--duration", "0.01", "--listener", "1,1,1.2",
         "--csv", "w.csv"),
        '[configuration]\nkind = "room"\nroom_m = [3.0, 4.0, 2.5]\nabsorption = [0.4]\nwindow_s = 0.01\n'
        '[[listeners]]\nname = "a"\nposition_m = [1.0, 1.0, 1.2]\n[outputs.waveform]\n',
        (("w.csv", "waveform_a.csv"),), figures=WAVEFORM_FIGURES),
    "directivity": Case(("directivity", "--config", "plane", "--step", "10", "--csv", "d.csv"),
                        PLANE + "[outputs.directivity]\nstep_deg = 10.0\n", (("d.csv", "directivity.csv"),)),
    "directivity-metric": Case(("directivity", "--config", "plane", "--step", "30", "--metric", "lcpeak", "--csv",
                                "d.csv"),
                               PLANE + '[outputs.directivity]\nstep_deg = 30.0\nmetric = "lcpeak"\n',
                               (("d.csv", "directivity.csv"),)),
    "directivity-room": Case(("directivity", *ROOM_ARGV, "--distance", "0.5", "--step", "30", "--csv", "d.csv"),
                             ROOM + '[[listeners]]\nname = "up"\nposition_m = [1.0, 1.0, 0.51905]\n'
                             '[outputs.directivity]\nstep_deg = 30.0\n', (("d.csv", "directivity.csv"),)),
    "map-room": Case(("map", *ROOM_ARGV, "--resolution", "16", "--csv", "m.csv"),
                     ROOM + "[outputs.level_map]\nresolution = 16\n", (("m.csv", "level_map.csv"),)),
    "map": Case(("map", "--config", "plane", "--resolution", "16", "--csv", "m.csv"),
                PLANE + "[outputs.level_map]\nresolution = 16\n", (("m.csv", "level_map.csv"),)),
    "damper": Case(("damper", "--duration", "1", "--impacts-csv", "i.csv"),
                   '[damper]\nduration_s = 1.0\nsolver = "event"\n[outputs.impact_table]\n',
                   (("i.csv", "impacts.csv"),)),
    "forced": Case(("forced", "--force", "5", "--freq", "4:6:2", "--starts", "1", "--no-noise", "--workers", "1",
                    "--csv", "f.csv"),
                   '[excitation]\nfrequencies_hz = "4:6:2"\nstarts = 1\n[outputs.frequency_response]\n',
                   (("f.csv", "frequency_response.csv"),)),
    "sweep": Case(("sweep", "--gap", "0.02:0.04:2", "--m", "0.02:0.04:2", "--duration", "1", "--workers", "1",
                   "--quiet", "--out", "sw"),
                  '[damper]\nsolver = "event"\n[outputs.sweep]\ngap_m = "0.02:0.04:2"\nmass_kg = "0.02:0.04:2"\n'
                  'duration_s = 1.0\nworkers = 1\n',
                  tuple((f"sw/{n}", f"sweep/{n}") for n in ("sweep.json", "design_table.csv", "inclination_map.png",
                                                             "max_spl_map.png")),
                  rows=(("sw/sweep.csv", "sweep/sweep.csv"),)),
    "auralize-levels": Case(
        ("auralize", "--duration", "0.5", "--solver", "event", "--listener", "0.495,0,0.514", "--wav", "a.wav",
         "--levels-csv", "l.csv"),
        '[damper]\nduration_s = 0.5\nsolver = "event"\n[[listeners]]\nname = "listener1"\n'
        'position_m = [0.495, 0.0, 0.514]\n[outputs.wav]\n[outputs.levels]\n',
        (("l.csv", "levels.csv"), ("l_bands.csv", "levels_bands.csv")), wav=(("a.wav", "wav_listener1.wav"),)),
}

SLOW_CASES = {
    "render-snapshot": Case(
        ("render", "snapshot", "--config", "plane", "--time", "0.001", "--resolution", "24", "--vtk", "s.vtu"),
        PLANE + "[grids.plane]\nresolution = 24\n[outputs.snapshot]\ntimes_s = [0.001]\nvtk = true\n",
        (("s.vtu", "snapshot.vtu"), ("s_geometry.vtu", "snapshot_geometry.vtu"))),
    "render-balloon": Case(
        ("render", "balloon", "--config", "plane", "--resolution", "8", "--vtk", "b.vtu"),
        PLANE + "[grids.sphere]\nn_theta = 8\n[outputs.balloon]\nvtk = true\n",
        (("b.vtu", "balloon.vtu"), ("b_geometry.vtu", "balloon_geometry.vtu"))),
    "render-animation": Case(
        ("render", "animation", "--config", "plane", "--frames", "3", "--resolution", "24", "--vtk", "a.vtu"),
        PLANE + "[grids.plane]\nresolution = 24\n[outputs.animation]\nframes = 3\nvtk = true\n",
        (("a.vtu", "animation.vtu"), ("a_geometry.vtu", "animation_geometry.vtu"))),
}


def _run_both(case: Case, tmp_path, monkeypatch, capsys):
    """Run the command in ``tmp_path/cli`` and the scene into ``tmp_path/scene``; return both folders and stdout."""
    cli = tmp_path / "cli"
    cli.mkdir()
    monkeypatch.chdir(cli)
    assert main(list(case.argv)) == 0, capsys.readouterr().err
    said = capsys.readouterr().out
    scene = tmp_path / "scene.toml"
    scene.write_text(case.scene)
    out = tmp_path / "scene"
    assert main(["run", str(scene), "--out", str(out)]) == 0, capsys.readouterr().err
    capsys.readouterr()
    return cli, out, said


def _summary_figures(out: Path) -> dict:
    """Every ``key = value`` of the first row of ``summary.md``'s table."""
    rows = [r for r in (out / "summary.md").read_text().splitlines() if r.startswith("| ") and " = " in r]
    return dict(kv.split(" = ", 1) for kv in rows[0].split("|")[3].strip().split(", "))


def _check(case: Case, cli: Path, out: Path, said: str) -> None:
    for mine, theirs in case.same:
        assert (cli / mine).read_bytes() == (out / theirs).read_bytes(), f"{mine} differs from the scene's {theirs}"
    for mine, theirs in case.rows:
        lines = [sorted((folder / f).read_text().splitlines()) for folder, f in ((cli, mine), (out, theirs))]
        assert lines[0] == lines[1], f"{mine} differs from the scene's {theirs}"
    for mine, theirs in case.wav:
        import soundfile

        a, rate_a = soundfile.read(cli / mine, dtype="int32")
        b, rate_b = soundfile.read(out / theirs, dtype="int32")
        assert rate_a == rate_b and np.array_equal(a, b), f"{mine} differs from the scene's {theirs}"
    if case.figures:
        figures = _summary_figures(out)
        for key, pattern in case.figures.items():
            printed = float(re.search(pattern, said).group(1))
            assert figures[key] == f"{printed:.4g}", (key, figures[key], printed)


@pytest.mark.parametrize("name", sorted(CASES))
def test_command_and_scene_write_the_same_files(name, tmp_path, monkeypatch, capsys):
    case = CASES[name]
    _check(case, *_run_both(case, tmp_path, monkeypatch, capsys))


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(SLOW_CASES))
def test_command_and_scene_render_the_same_data(name, tmp_path, monkeypatch, capsys):
    pytest.importorskip("pyvista")
    case = SLOW_CASES[name]
    _check(case, *_run_both(case, tmp_path, monkeypatch, capsys))


@pytest.mark.parametrize("tolerance", [None, 0.001])
def test_design_choice_is_the_same(tolerance, tmp_path, monkeypatch, capsys):
    """``acoustiviz design`` on a sweep prints the choice a scene's design table writes (default tolerance too)."""
    case = CASES["sweep"]
    toml = case.scene + "[outputs.design_table]\ninclination_m_s = 0.007\n"
    argv = ["design", "--sweep", str(tmp_path / "cli" / "sw"), "--inclination", "0.007"]
    if tolerance is not None:
        toml += f"tolerance_m_s = {tolerance}\n"
        argv += ["--tolerance", str(tolerance)]
    cli, out, _ = _run_both(Case(case.argv, toml, case.same), tmp_path, monkeypatch, capsys)
    assert main(argv) == 0
    said = capsys.readouterr().out
    assert (out / "design_choice.txt").read_text() in said


def test_a_click_longer_than_the_sound_is_refused_by_both():
    """The one check (app.damper.check_click_fits) names the option on the command line and the key in a scene."""
    from acoustiviz.app.damper import check_click_fits
    from acoustiviz.core.contact import contact_duration
    from acoustiviz.sound import ImpactSequence

    seq = ImpactSequence(times=np.array([0.001, 0.002]), walls=np.array([-1, 1]), velocities=np.array([1e-3, 2.0]))
    tau = float(contact_duration(1e-3, 5.6e8, 0.0405))  # the slowest impact's contact time, eqs 1-4
    check_click_fits(seq, 5.6e8, 0.0405, 1.01 * tau)
    for names, key in ((None, "m"), ({"m": "damper.impact_mass_kg"}, "damper.impact_mass_kg")):
        with pytest.raises(ParameterError) as err:
            check_click_fits(seq, 5.6e8, 0.0405, 0.99 * tau, names=names)
        assert err.value.name == key and "longer than" in err.value.detail
