"""A scene's [damper] is refused at load, before any simulation, naming the key and what is allowed."""

import math

import pytest

import acoustiviz.dynamics
from acoustiviz.errors import SceneError
from acoustiviz.scene import scene_from_dict

TABLE1_M, TABLE1_K = 0.5, 500.0  # the paper's Table 1 main mass (kg) and spring (N/m)


@pytest.fixture(autouse=True)
def no_simulation(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("the scene ran the damper while loading")

    monkeypatch.setattr(acoustiviz.dynamics, "simulate", refuse)


def _refused(damper: dict) -> SceneError:
    with pytest.raises(SceneError) as info:
        scene_from_dict({"damper": damper}, "s.toml")
    return info.value


def test_duration_shorter_than_a_hundredth_of_the_main_period():
    err = _refused({"duration_s": 1e-4})
    period = 2.0 * math.pi * math.sqrt(TABLE1_M / TABLE1_K)  # 0.1987 s
    assert err.name == "damper.duration_s"
    assert f">= {period / 100.0:.4g} s" in err.detail
    assert str(err).startswith("s.toml: damper.duration_s:")


def test_impact_mass_below_a_millionth_of_the_main_mass():
    err = _refused({"main_mass_kg": 100.0, "impact_mass_kg": 1e-5, "stiffness_n_m": 1e5})
    assert err.name == "damper.impact_mass_kg"
    assert ">= 0.0001 kg" in err.detail  # 1e-6 of 100 kg


def test_speed_that_compresses_beyond_the_gap_names_the_speed_range():
    # 999 m/s into a gap of 1 um: the record's range [-1000, 1000] m/s passes, the physics does not
    err = _refused({"initial_velocity_m_s": 999.0, "gap_m": 1e-6})
    assert err.name == "damper.initial_velocity_m_s"
    assert "must lie in [" in err.detail and "] m/s" in err.detail


def test_overdamped_contact_names_the_largest_contact_damping():
    err = _refused({"contact_damping_n_s_m": 1e8})
    assert err.name == "damper.contact_damping_n_s_m"
    assert "must be <=" in err.detail and "N s/m" in err.detail


def test_range_of_a_record_is_checked_first():
    err = _refused({"gap_m": 20.0})
    assert err.name == "damper.gap_m"
    assert "(0, 10] m" in err.detail


def test_the_paper_damper_loads():
    scene = scene_from_dict({"damper": {"initial_displacement_m": 0.001, "clip_tensile": True}}, "s.toml")
    assert scene.section("damper")["clip_tensile"] is True
