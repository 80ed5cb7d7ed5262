"""Running scenes: only the outputs asked for, figures that agree with the library, safe folders."""

import math

import numpy as np
import pytest

from acoustiviz.app.pipeline import PRODUCERS, RunContext, run_scene
from acoustiviz.errors import ParameterError
from acoustiviz.scene import OUTPUT_KINDS, load_scene, scene_from_dict, shipped_scenes

SCENES = {name: name for name in shipped_scenes()}


def _fig2(tmp_path):
    from pathlib import Path

    import acoustiviz

    return load_scene(Path(acoustiviz.__file__).parent / "assets" / "scenes" / "fig2_waveform.toml")


def test_every_output_kind_has_a_producer():
    assert set(PRODUCERS) == set(OUTPUT_KINDS)


def test_waveform_scene_matches_the_radiation_core(tmp_path, half_sine_pulse):
    scene = _fig2(tmp_path)
    products = run_scene(scene, tmp_path / "out")
    names = sorted(p.path.name for p in products)
    assert names == ["summary.md", "waveform_fig2.csv", "waveform_fig2.png"]
    data = np.loadtxt(tmp_path / "out" / "waveform_fig2.csv", delimiter=",", skiprows=1)
    t = data[:, 0]
    # column 1 is the paper's half-sine: the sphere and its image summed by hand
    from acoustiviz.core.radiation import pressure

    a = 0.01905
    pulse = half_sine_pulse
    listener = np.array([0.7 * math.sin(math.pi / 4), 0.0, a + 0.7 * math.cos(math.pi / 4)])
    ref = np.zeros_like(t)
    for centre, sign in (((0, 0, a), 1.0), ((0, 0, -a), -1.0)):  # eq 14: p(r1, th1) - p(r2, th2)
        d = listener - np.array(centre)
        r = np.linalg.norm(d)
        ref += sign * pressure(pulse, t, r, d[2] / r, radius=a)
    np.testing.assert_allclose(data[:, 1], ref, atol=1e-7 * np.abs(ref).max())
    summary = (tmp_path / "out" / "summary.md").read_text()
    assert "waveform_fig2.csv" in summary and "peak_spl_db" in summary
    assert not [p for p in (tmp_path / "out").iterdir() if p.name.startswith(".")]  # no temporary files left


def test_a_waveform_scene_never_runs_the_damper(tmp_path, monkeypatch):
    import acoustiviz.dynamics as dyn

    def forbidden(*_a, **_k):
        raise AssertionError("the damper was simulated for a waveform-only scene")

    monkeypatch.setattr(dyn, "simulate", forbidden)
    scene = scene_from_dict({"outputs": {"waveform": True}})
    run_scene(scene, tmp_path / "o")


def test_damper_outputs_share_one_simulation(tmp_path, monkeypatch):
    import acoustiviz.dynamics as dyn

    calls = []
    real = dyn.simulate

    def counting(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(dyn, "simulate", counting)
    scene = scene_from_dict({"damper": {"duration_s": 2.0}, "outputs": {"damper_history": True, "impact_table": True}})
    products = run_scene(scene, tmp_path / "o")
    assert len(calls) == 1
    rows = np.loadtxt(tmp_path / "o" / "impacts.csv", delimiter=",", skiprows=1, ndmin=2)
    with open(tmp_path / "o" / "impacts.csv") as fh:
        assert fh.readline().startswith("time_s,wall,approach_velocity_m_s,separation_velocity_m_s,restitution,")
    assert rows.shape[0] == int(next(p for p in products if p.kind == "impact_table").figures["impacts"])


def test_existing_folder_needs_force(tmp_path):
    out = tmp_path / "o"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    scene = scene_from_dict({"outputs": {"restitution": {"masses_kg": [0.04], "velocities_m_s": [1.0]}}})
    with pytest.raises(ParameterError, match="--force"):
        run_scene(scene, out)
    run_scene(scene, out, force=True)
    assert (out / "keep.txt").read_text() == "mine"
    assert (out / "restitution.csv").exists()


def test_context_is_lazy(tmp_path):
    ctx = RunContext(scene_from_dict({}), tmp_path)
    assert "damper_run" not in ctx.__dict__
    _ = ctx.geometry
    assert "damper_run" not in ctx.__dict__


def test_wav_output_is_calibrated_against_the_field_evaluator(tmp_path):
    import json

    import soundfile as sf

    from acoustiviz.field import field_metrics

    # walls = "one": every impact is heard as a strike on the floor z = 0, the field evaluator's frame
    scene = scene_from_dict({"damper": {"duration_s": 1.0}, "outputs": {"wav": {"rate_hz": 96000, "walls": "one",
                                                                                    "subtype": "FLOAT"}}})
    products = run_scene(scene, tmp_path / "o")
    data, rate = sf.read(tmp_path / "o" / "wav_paper.wav", dtype="float64")
    info = sf.info(tmp_path / "o" / "wav_paper.wav")
    assert rate == 96000 and info.subtype == "FLOAT"
    side = json.loads((tmp_path / "o" / "wav_paper.json").read_text())
    assert side["scale_pa_per_full_scale"] == 1.0
    assert side["impacts"] == int(next(p for p in products if p.path.suffix == ".wav").figures["impacts"])
    # the loudest click in the file against the field evaluator at the same point, for the fastest impact
    from acoustiviz.dynamics import simulate

    ctx = RunContext(scene, tmp_path)
    res = simulate(ctx.damper_model, 1.0, initial=ctx.damper_initial)
    fastest = float(np.max(res.impacts.approach_velocity))
    (_, pos), = scene.listeners()
    from acoustiviz.core.contact import Impact, acceleration_pulse

    # the damper's sphere is its impact mass m = 40.5 g with the paper's radius 19.05 mm
    pulse = acceleration_pulse(Impact(fastest, 5.6e8, 0.0405), "half-sine")
    ref = field_metrics(pulse, pos[None, :], scene.geometry(), medium=scene.medium())
    # band-limited samples at 96 kHz land within half a sample of the true peak: allow 2 %
    assert np.abs(data).max() == pytest.approx(float(ref.peak[0]), rel=0.02)


def test_scene_sweep_maps_onto_the_sweep_spec(tmp_path):
    from acoustiviz.app.sweep import scene_sweep_spec

    scene = scene_from_dict({"damper": {"contact_damping_n_s_m": 15.0, "initial_velocity_m_s": 1.5},
                             "outputs": {"sweep": {"gap_m": "0.02:0.04:3", "mass_kg": "0.03:0.05:2",
                                                   "duration_s": 1.5}}})
    spec = scene_sweep_spec(scene)
    assert spec.gap == pytest.approx((0.02, 0.03, 0.04)) and spec.m == pytest.approx((0.03, 0.05))
    assert spec.c1 == (15.0,) and spec.v0 == (1.5,) and spec.config == ("plane",)
    assert spec.distance[0] == pytest.approx(0.7) and spec.angle[0] == pytest.approx(math.pi / 4)
    assert spec.settings.duration == 1.5 and spec.settings.radius == pytest.approx(0.01905)
    assert spec.settings.levels is False
    with_levels = scene_from_dict({"outputs": {"sweep": {"gap_m": "0.02:0.04:3", "levels": True}}})
    assert scene_sweep_spec(with_levels).settings.levels is True


@pytest.mark.slow
def test_sweep_and_design_table_outputs_resume_without_recomputing(tmp_path):
    scene = scene_from_dict({"outputs": {"sweep": {"gap_m": "0.03:0.04:2", "mass_kg": "0.03:0.05:2",
                                                   "duration_s": 1.0},
                                         "design_table": {"inclination_m_s": 0.008, "tolerance_m_s": 0.01}}})
    out = tmp_path / "o"
    run_scene(scene, out)
    csv = out / "sweep" / "sweep.csv"
    rows = csv.read_text().splitlines()
    assert rows[0].startswith("gap_m,mass_kg,inclination_two_maxima_m_s,inclination_fit_m_s,settling_time_s,"
                              "n_impacts,max_spl_db")
    assert len(rows) == 5
    for name in ("design_table.csv", "inclination_map.png", "max_spl_map.png"):
        assert (out / "sweep" / name).stat().st_size > 0
    assert "quietest" in (out / "design_choice.txt").read_text()
    before = csv.stat().st_mtime_ns, csv.read_text()
    run_scene(scene, out, force=True)  # a finished sweep is not recomputed
    assert (csv.stat().st_mtime_ns, csv.read_text()) == before


def _cli_spec(argv):
    from acoustiviz.cli import build_parser
    from acoustiviz.cli.sweep import spec_from_args

    return spec_from_args(build_parser().parse_args(["sweep", *argv]))


def test_fig6_scene_and_the_sweep_command_write_the_same_sweep_json(tmp_path):
    """The shipped scene and the command with its settings make one sweep: the same sweep.json,
    so that either resumes the other's folder."""
    from pathlib import Path

    import acoustiviz
    from acoustiviz.app.sweep import scene_sweep_spec
    from acoustiviz.sweep.store import SWEEP_JSON, prepare_dir

    scene = load_scene(Path(acoustiviz.__file__).parent / "assets" / "scenes" / "fig6_design_maps.toml")
    from_scene = scene_sweep_spec(scene)
    from_cli = _cli_spec(["--gap", "0.02:0.06:20", "--m", "0.02:0.08:20", "--duration", "20", "--out", "x"])
    assert from_scene == from_cli
    assert from_scene.gap[9] == 0.0389473684210526  # 0.02 + 9 * 0.04/19 to 15 digits
    prepare_dir(from_scene, tmp_path / "scene")  # what run_sweep writes before any design runs
    prepare_dir(from_cli, tmp_path / "cli")
    text = (tmp_path / "scene" / SWEEP_JSON).read_bytes()
    assert text == (tmp_path / "cli" / SWEEP_JSON).read_bytes()
    prepare_dir(from_cli, tmp_path / "scene")  # the command accepts the scene's folder as its own
    prepare_dir(from_scene, tmp_path / "cli")
    assert (tmp_path / "scene" / SWEEP_JSON).read_bytes() == text


@pytest.mark.slow
def test_the_sweep_command_resumes_a_scene_sweep(tmp_path, capsys):
    from acoustiviz.cli import main

    scene = scene_from_dict({"outputs": {"sweep": {"gap_m": "0.03:0.05:2", "mass_kg": "0.03:0.05:2",
                                                   "duration_s": 0.5, "workers": 1}}})
    run_scene(scene, tmp_path / "o")
    folder = tmp_path / "o" / "sweep"
    before = (folder / "sweep.csv").read_bytes()
    assert main(["sweep", "--gap", "0.03:0.05:2", "--m", "0.03:0.05:2", "--duration", "0.5", "--workers", "1",
                 "--out", str(folder)]) == 0
    assert "all 4 designs already in" in capsys.readouterr().err
    assert (folder / "sweep.csv").read_bytes() == before


def test_wav_sidecar_records_the_physical_and_the_file_peak_separately(tmp_path):
    import json

    import soundfile as sf

    from acoustiviz.core.contact import Impact, acceleration_pulse
    from acoustiviz.core.radiation import sphere_pressure
    from acoustiviz.dynamics import simulate

    # default file: normalised PCM_24 at 48 kHz; walls = "one": every click from the floor's sphere and its image
    scene = scene_from_dict({"damper": {"duration_s": 1.0}, "outputs": {"wav": {"walls": "one"}}})
    products = run_scene(scene, tmp_path / "o")
    side = json.loads((tmp_path / "o" / "wav_paper.json").read_text())
    assert side["sidecar_version"] == 3
    data, rate = sf.read(tmp_path / "o" / "wav_paper.wav", dtype="float64")
    assert rate == 48000
    # the file's peak: its samples times the calibration
    file_peak = np.max(np.abs(data)) * side["scale_pa_per_full_scale"]
    assert side["peak_pa"][0] == pytest.approx(file_peak, rel=1e-5)
    # the physical peak: the fastest impact's two spheres (eq 14) summed directly at 10 ns steps
    ctx = RunContext(scene, tmp_path)
    res = simulate(ctx.damper_model, 1.0, initial=ctx.damper_initial)
    pulse = acceleration_pulse(Impact(float(np.max(res.impacts.approach_velocity)), 5.6e8, 0.0405), "half-sine")
    (_, pos), = scene.listeners()
    geometry = scene.geometry()
    t0 = (np.linalg.norm(pos - geometry.centre) - geometry.radius) / scene.medium().c - 1e-4
    t = t0 + np.arange(0, 3e-3, 1e-8)
    p = sum(sphere_pressure(pulse, t, pos, radius=geometry.radius, centre=s.position, axis=s.axis,
                            medium=scene.medium()) for s in geometry.sources)[0]
    assert side["physical_peak_pa"][0] == pytest.approx(np.max(np.abs(p)), rel=1e-4)
    assert side["physical_peak_spl_db_re_20upa"][0] == pytest.approx(20 * np.log10(np.max(np.abs(p)) / 20e-6),
                                                                      abs=1e-3)
    # band-limiting a ~0.3 ms click to 21.6 kHz moves its peak (the filter's ringing at the pulse's
    # kinks, the samples' grid): close, but not the same number, beyond the file's 24-bit resolution
    ratio = side["peak_pa"][0] / side["physical_peak_pa"][0]
    assert abs(20 * np.log10(ratio)) < 1.0 and abs(ratio - 1) > 1e-5
    wav = next(p for p in products if p.path.suffix == ".wav")
    assert float(wav.figures["physical_peak_spl_db"]) == pytest.approx(side["physical_peak_spl_db_re_20upa"][0],
                                                                       abs=0.06)


@pytest.mark.slow
def test_wav_and_levels_hear_one_setup(tmp_path):
    """``wav`` and ``levels`` share the scene's sound setup: the 96 kHz analysis of the run finds the
    unweighted peak the WAV sidecar's closed form records, and both count the same clicks."""
    import csv
    import json

    scene = scene_from_dict({"damper": {"duration_s": 0.8},
                             "outputs": {"wav": {"walls": "both", "struck_wall": 1}, "levels": True}})
    products = run_scene(scene, tmp_path / "o")
    side = json.loads((tmp_path / "o" / "wav_paper.json").read_text())
    with open(tmp_path / "o" / "levels.csv", newline="") as f:
        (row,) = list(csv.DictReader(f))
    assert float(row["lzpeak_db"]) == pytest.approx(side["physical_peak_spl_db_re_20upa"][0], abs=0.1)
    assert side["scene"]["struck_wall"] == 1 and side["scene"]["walls"] == "both"
    wav = next(p for p in products if p.path.suffix == ".wav")
    assert int(wav.figures["impacts"]) == side["impacts"] > 0


@pytest.mark.slow
def test_scene_directivity_metric_equals_the_command(tmp_path):
    """One rule for a weighted directivity: the scene key and `acoustiviz directivity --metric` agree."""
    from acoustiviz.cli import main

    scene = scene_from_dict({"sphere": {"radius_m": 0.01905}, "impact": {"velocity_m_s": 1.4},
                             "contact": {"k_hertz_n_m1_5": 5.6e8}, "configuration": {"kind": "plane"},
                             "outputs": {"directivity": {"step_deg": 30.0, "metric": "lcpeak"}}}, "t.toml")
    run_scene(scene, tmp_path / "scene")
    assert main(["directivity", "--radius", "0.01905", "--velocity", "1.4", "--k-hertz", "5.6e8", "--density", "7800",
                 "--distance", "0.7", "--config", "plane", "--step", "30", "--metric", "lcpeak",
                 "--csv", str(tmp_path / "cli.csv")]) == 0
    a = np.genfromtxt(tmp_path / "scene" / "directivity.csv", delimiter=",", names=True)
    b = np.genfromtxt(tmp_path / "cli.csv", delimiter=",", names=True)
    np.testing.assert_allclose(a["angle_deg"], b["angle_deg"])
    np.testing.assert_allclose(a["lcpeak_db"], b["lcpeak_db"], atol=1e-5)
    assert np.all(a["lcpeak_db"] <= a["spl_db"] + 0.1)  # C weighting removes energy, never adds much


def test_scene_directivity_refuses_an_unknown_metric():
    with pytest.raises(ParameterError, match="outputs.directivity.metric"):
        scene_from_dict({"outputs": {"directivity": {"metric": "loudness"}}}, "t.toml")


def test_a_damper_scene_beyond_the_computable_range_names_its_key(tmp_path):
    """The damper's limits (core.limits.check_damper) are checked when the scene is loaded, in scene keys."""
    with pytest.raises(ParameterError) as err:
        scene_from_dict({"damper": {"duration_s": 0.001}, "outputs": {"damper_history": {}}}, "t.toml")
    assert err.value.name == "damper.duration_s" and "period" in err.value.detail
    assert not (tmp_path / "out").exists()


def test_a_sidecar_states_the_rate_and_length_of_its_file_not_of_the_rendering_it_describes(tmp_path):
    """A train analysed at 96 kHz and written at 48 kHz: the sidecar gives the file's 48 kHz (it said 96000)."""
    import json

    import soundfile as sf

    from acoustiviz.app.wav import WavFile, write_wav_files
    from acoustiviz.core.listener import Listener
    from acoustiviz.core.signal import Signal

    fs, n = 48000, 4800
    wav = WavFile(tmp_path / "a.wav", Signal(np.sin(np.arange(n) / 7.0)[None, :], fs),
                  [Listener("listener1", [0.5, 0, 0.5])], ["mono"])
    described = {"sample_rate_hz": 96000, "duration_s": 0.2, "sample_rate": 96000, "impact_count": 3}
    [w] = write_wav_files([wav], rendering=described)
    info = sf.info(str(tmp_path / "a.wav"))
    doc = json.loads(w["sidecar"].read_text())
    assert doc["sample_rate_hz"] == info.samplerate == fs and doc["frames"] == info.frames == n
    assert doc["duration_s"] == n / fs and "sample_rate" not in doc
    assert doc["impacts"] == 3  # the rest of the description is kept


def test_a_wav_file_names_one_listener_per_channel(tmp_path):
    from acoustiviz.app.wav import WavFile
    from acoustiviz.core.listener import Listener
    from acoustiviz.core.signal import Signal
    from acoustiviz.errors import ParameterError

    two = Signal(np.zeros((2, 100)), 48000)
    left, right = Listener("left", [0.1, 0.0, 0.5]), Listener("right", [-0.1, 0.0, 0.5])
    wav = WavFile(tmp_path / "s.wav", two, [left, right], ["left", "right"])
    assert wav.names == ["left", "right"]
    np.testing.assert_array_equal(wav.positions, [[0.1, 0.0, 0.5], [-0.1, 0.0, 0.5]])
    assert wav.signal.channels == 2 and wav.pressure.shape == (2, 100)
    mono = WavFile(tmp_path / "m.wav", Signal(np.zeros(100), 48000), [left], ["mono"])
    assert mono.pressure.shape == (1, 100)  # one channel is one row
    with pytest.raises(ParameterError, match="listeners"):
        WavFile(tmp_path / "x.wav", two, [left], ["mono"])
    with pytest.raises(ParameterError, match="signal"):
        WavFile(tmp_path / "y.wav", np.zeros((2, 100)), [left, right], ["left", "right"])
