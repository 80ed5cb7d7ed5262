"""The application layer: one set of rules for the command line and for scenes."""

import json
import math

import numpy as np
import pytest

from acoustiviz.app.impacts import impact_setup, k_hertz_from, observer_point, sphere_mass
from acoustiviz.app.names import IMPACT_OPTIONS, user_terms
from acoustiviz.cli import main
from acoustiviz.core.contact import hertz_stiffness
from acoustiviz.core.materials import material
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict


def test_user_terms_renames_only_known_parameters():
    with pytest.raises(ParameterError) as err, user_terms({"radius": "--radius"}):
        raise ParameterError("radius", "must be > 0 m, got -1 m")
    assert (err.value.name, err.value.detail) == ("--radius", "must be > 0 m, got -1 m")
    with pytest.raises(ParameterError) as err, user_terms({"radius": "--radius"}):
        raise ParameterError("gap", "must be > 0 m")
    assert err.value.name == "gap"


def test_stiffness_rules():
    k, source = k_hertz_from(0.01, sphere_material="steel", surface_material="glass")
    # K_HZ by two routes: < 20 roundings and libm pows (<= 1 ulp each), so < 5e-15 apart; 1e-12 catches any wrong term
    assert k == pytest.approx(hertz_stiffness(0.01, material("steel"), material("glass")), rel=1e-12)
    assert source == "Hertz, steel on glass"
    assert k_hertz_from(0.01) == (5.6e8, "default (paper)")
    with pytest.raises(ParameterError, match="k_hertz"):
        k_hertz_from(0.01, k_hertz=1e9, surface_material="glass")


def test_mass_rules():
    vol = 4 / 3 * math.pi * 0.01**3
    assert sphere_mass(0.01) == pytest.approx(7800 * vol, rel=1e-12)  # a few roundings either way
    assert sphere_mass(0.01, sphere_material="glass") == pytest.approx(material("glass").density * vol, rel=1e-12)
    assert sphere_mass(0.01, mass=0.05) == 0.05
    with pytest.raises(ParameterError, match="mass"):
        sphere_mass(0.01, mass=0.05, density=7800)


def test_scene_and_command_line_build_the_same_impact():
    scene = scene_from_dict({"sphere": {"radius_m": 0.012, "material": "steel"}, "contact": {"surface": "glass"},
                             "impact": {"velocity_m_s": 0.9},
                             "configuration": {"kind": "wall-floor", "wall_distance_m": 0.03}})
    api = impact_setup(radius=0.012, velocity=0.9, sphere_material="steel", surface_material="glass",
                       config="wall-floor", wall_distance=0.03)
    s = scene.setup()
    assert s.impact == api.impact
    assert s.pulse.duration == api.pulse.duration
    np.testing.assert_array_equal(s.geometry.sources[1].position, api.geometry.sources[1].position)


def test_errors_name_the_option_the_user_gave():
    with pytest.raises(ParameterError) as err, user_terms(IMPACT_OPTIONS):
        impact_setup(radius=0.01, velocity=1.0, sphere_material="unobtainium")
    assert err.value.name == "--material" and "unobtainium" in err.value.detail
    setup = impact_setup(radius=0.01, velocity=1.0, config="plane")
    with pytest.raises(ParameterError) as err, user_terms(IMPACT_OPTIONS):
        observer_point(setup, 0.5, 120.0)
    assert err.value.name == "--angle"


def _sidecar_keys(path):
    return set(json.loads(path.read_text())) - {"damper"}


@pytest.mark.slow
def test_auralize_and_scene_write_one_sidecar_schema(tmp_path):
    from acoustiviz.app.pipeline import run_scene

    wav = tmp_path / "cli.wav"
    assert main(["auralize", "--duration", "0.3", "--wav", str(wav)]) == 0
    scene = scene_from_dict({"damper": {"duration_s": 0.3}, "outputs": {"wav": {}}})
    run_scene(scene, tmp_path / "scene")
    cli, sc = tmp_path / "cli.json", tmp_path / "scene" / "wav_paper.json"
    assert _sidecar_keys(cli) == _sidecar_keys(sc)
    a, b = json.loads(cli.read_text()), json.loads(sc.read_text())
    assert a["sidecar_version"] == b["sidecar_version"] and a["acoustiviz_version"] == b["acoustiviz_version"]
    assert a["scene_name"] is None and b["scene_name"] == "scene"
    assert "clipping" in a and "clipping" in b
    # the same damper settings give the same impacts from either front-end
    assert a["impact_count"] == b["impact_count"]
    assert a["damper"]["solver_settings"] == b["damper"]["solver_settings"]


def test_auralize_wall_strike(tmp_path, capsys):
    wav = tmp_path / "w.wav"
    assert main(["auralize", "--duration", "0.2", "--config", "wall-floor", "--strike", "wall",
                 "--listener", "0.5,0,0.3", "--wav", str(wav)]) == 0
    side = json.loads((tmp_path / "w.json").read_text())
    assert side["scene"]["strike"] == "wall"
    assert main(["auralize", "--duration", "0.2", "--strike", "wall", "--wav", str(wav)]) == 2
    assert "--strike" in capsys.readouterr().err
