"""Running scenes: only the outputs asked for, figures that agree with the library, safe folders."""

import math

import numpy as np
import pytest

from acoustiviz._validate import ParameterError
from acoustiviz.pipeline import PRODUCERS, RunContext, run_scene
from acoustiviz.scene import OUTPUT_KINDS, load_scene, scene_from_dict, shipped_scenes

SCENES = {name: name for name in shipped_scenes()}


def _fig2(tmp_path):
    from pathlib import Path

    import acoustiviz

    return load_scene(Path(acoustiviz.__file__).parent / "assets" / "scenes" / "fig2_waveform.toml")


def test_every_output_kind_has_a_producer():
    assert set(PRODUCERS) == set(OUTPUT_KINDS)


def test_waveform_scene_matches_the_radiation_core(tmp_path):
    scene = _fig2(tmp_path)
    products = run_scene(scene, tmp_path / "out")
    names = sorted(p.path.name for p in products)
    assert names == ["summary.md", "waveform_fig2.csv", "waveform_fig2.png"]
    data = np.loadtxt(tmp_path / "out" / "waveform_fig2.csv", delimiter=",", skiprows=1)
    t = data[:, 0]
    # column 1 is the paper's half-sine: the sphere and its image summed by hand
    from acoustiviz.contact import Impact, acceleration_pulse
    from acoustiviz.radiation import pressure

    a = 0.01905
    pulse = acceleration_pulse(Impact(1.4, 5.6e8, 7800 * 4 / 3 * math.pi * a**3), "half-sine")
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
    _ = ctx.configuration
    assert "damper_run" not in ctx.__dict__
