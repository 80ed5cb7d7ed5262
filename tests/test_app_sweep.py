"""The application layer of sweeps: settings to a spec, errors in the user's words, scenes, reports."""

import math

import numpy as np
import pytest

from acoustiviz import constants
from acoustiviz.app import design as design_job
from acoustiviz.app import sweep as sweep_job
from acoustiviz.app.names import user_terms
from acoustiviz.app.settings.design import DesignJob
from acoustiviz.app.settings.sweep_job import sweep_job as build_sweep
from acoustiviz.app.sweep import SWEEP_OPTIONS, scene_sweep_spec, sweep_spec
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict
from acoustiviz.sweep import FixedSettings, SweepSpec


def test_values_ranges_and_lists():
    spec = sweep_spec(gap="0.02:0.04:3", m=(0.03, 0.05), c1="10,20", angle_deg="30", config="plane,wall-floor",
                      material="steel", radius="mass", density=7800.0, duration=1.0)
    assert spec.gap == (0.02, 0.03, 0.04) and spec.m == (0.03, 0.05) and spec.c1 == (10.0, 20.0)
    assert spec.angle == (math.radians(30),) and spec.config == ("plane", "wall-floor")
    assert spec.material == ("steel",) and spec.k_hertz is None
    assert spec.settings.radius_mode == "from-mass" and spec.settings.density == 7800.0


def test_defaults_are_the_constants():
    spec = sweep_spec()
    assert spec == SweepSpec(angle=(math.radians(constants.PAPER_ANGLE_DEG),), settings=FixedSettings())
    assert spec.settings.rtol == constants.DEFAULT_RTOL
    assert spec.distance == (constants.PAPER_DISTANCE,) and spec.settings.radius == constants.PAPER_RADIUS


@pytest.mark.parametrize("kw, name, option", [
    ({"gap": "1:2"}, "gap", "--gap"),
    ({"m": "0.1", "mass_ratio": "0.2"}, "m", "--m"),
    ({"angle_deg": "95"}, "angle_deg", "--angle"),
    ({"radius": "big"}, "radius", "--radius"),
    ({"density": 7800.0}, "density", "--density"),
    ({"n_fastest": -1}, "n_fastest", "--spl-fastest"),
    ({"rtol": 1.0}, "rtol", "--rtol"),
])
def test_errors_name_the_parameter_and_the_option(kw, name, option):
    with pytest.raises(ParameterError) as exc:
        sweep_spec(**kw)
    assert exc.value.name == name
    with pytest.raises(ParameterError) as exc, user_terms(SWEEP_OPTIONS):
        sweep_spec(**kw)
    assert exc.value.name == option


def test_a_listener_by_position_gives_the_same_sweep_as_by_distance_and_angle():
    sweep = {"gap_m": "0.03:0.04:2", "mass_kg": "0.03", "duration_s": 1.0}
    polar = scene_from_dict({"listeners": [{"distance_m": 0.5, "angle_deg": 30.0}], "outputs": {"sweep": sweep}})
    a = 0.01905
    pos = [0.5 * math.sin(math.radians(30)), 0.0, a + 0.5 * math.cos(math.radians(30))]
    cartesian = scene_from_dict({"listeners": [{"position_m": pos}], "outputs": {"sweep": sweep}})
    p, c = scene_sweep_spec(polar, solver="event"), scene_sweep_spec(cartesian, solver="event")
    assert p.angle == (math.radians(30.0),) and p.distance == (0.5,)
    assert c.angle[0] == pytest.approx(p.angle[0], rel=1e-12) and c.distance[0] == pytest.approx(0.5, rel=1e-12)


def test_scene_errors_name_the_scene_key():
    # a 5 kg steel ball has a radius of 5.3 cm: the listener at 5 cm would be inside it
    scene = scene_from_dict({"sphere": {"damper_radius": "from-mass"},
                             "outputs": {"sweep": {"gap_m": "0.02:0.03:2", "mass_kg": "0.04:5:2", "duration_s": 1.0}},
                             "listeners": [{"distance_m": 0.05, "angle_deg": 45.0}]})
    with pytest.raises(ParameterError) as exc:
        scene_sweep_spec(scene, solver="event")
    assert exc.value.name == "listeners" and "sphere radius" in exc.value.detail


@pytest.mark.slow
def test_outputs_and_report(tmp_path):
    run = sweep_job.run(build_sweep(dict(gap="0.03,0.05", m="0.04", duration=1.0), out=str(tmp_path), workers=1))
    paths = run.write()
    assert len(run.table) == 2 and [p.name for p in paths] == ["design_table.csv", "inclination_map.png",
                                                               "max_spl_map.png"]
    e = float(run.table["inclination_two_maxima_m_s"][0])
    # a tolerance must be > 0; 1e-9 m/s holds this design only
    lines = design_job.run(DesignJob(sweep=str(tmp_path), inclination=e, tolerance=1e-9, table=True)).lines()
    spl = run.table["max_spl_db"][0]
    assert f"max SPL {spl:.2f} dB" in "\n".join(lines) and any(ln.startswith("design table") for ln in lines)
    assert np.isfinite(run.table["max_spl_db"]).all()
    with pytest.raises(ParameterError, match="^sweep"):
        DesignJob(sweep=str(tmp_path / "none"), inclination=0.008)


def test_a_room_typed_or_listed_is_the_same_setting(tmp_path):
    # the command line types the room as text, a scene lists numbers: both are the room's numbers in the spec
    from acoustiviz.cli import build_parser
    from acoustiviz.cli.sweep import settings_from_args

    args = build_parser().parse_args(["sweep", "--gap", "0.02", "--room", "3,2.5,2", "--absorption", "0.3",
                                      "--source", "1,1,0.01905", "--room-window", "0.005",
                                      "--out", str(tmp_path / "sw")])
    typed = dict(settings_from_args(args).spec.settings.room)
    scene = scene_from_dict({"configuration": {"kind": "room", "room_m": [3.0, 2.5, 2.0], "absorption": [0.3],
                                               "source_m": [1.0, 1.0, 0.01905], "window_s": 0.005},
                             "outputs": {"sweep": {"gap_m": "0.02"}}})
    listed = dict(scene_sweep_spec(scene).settings.room)
    assert typed == listed
    assert typed["dimensions"] == (3.0, 2.5, 2.0) and typed["source"] == (1.0, 1.0, 0.01905)
