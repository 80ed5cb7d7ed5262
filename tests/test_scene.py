"""Scene loading: defaults, every kind of invalid input, and fuzzing of random and malformed scenes."""

import math
import string

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acoustiviz.scene import (
    OUTPUT_KINDS,
    SceneError,
    default_scene,
    load_scene,
    parse_range,
    scene_from_dict,
    scene_from_text,
    schema_help,
    shipped_scenes,
)

PAPER_SCENES = {"fig2_waveform", "fig3_directivity", "fig5_free_vibration", "fig6_design_maps",
                "fig7_restitution", "table2_design"}
BEYOND = {"bead_in_corner", "soft_polymer_ball", "steel_on_steel_damper"}


def test_shipped_scenes_all_load():
    texts = shipped_scenes()
    assert PAPER_SCENES | BEYOND | {"default"} <= set(texts)
    for name, text in texts.items():
        sc = scene_from_text(text, name)
        assert sc.outputs, name


def test_default_scene_is_the_paper_damper_with_every_output():
    sc = default_scene()
    assert set(sc.outputs) == set(OUTPUT_KINDS)
    d = sc.section("damper")
    assert (d["main_mass_kg"], d["stiffness_n_m"], d["damping_n_s_m"]) == (0.5, 500.0, 0.05)
    assert (d["impact_mass_kg"], d["gap_m"], d["contact_damping_n_s_m"]) == (0.0405, 0.04, 20.0)
    assert sc.k_hertz() == 5.6e8
    (name, pos), = sc.listeners()
    centre = sc.geometry().sources[0].position
    assert math.dist(pos, centre) == pytest.approx(0.7)
    assert math.degrees(math.acos((pos[2] - centre[2]) / 0.7)) == pytest.approx(45.0)


def test_defaults_fill_an_empty_scene():
    sc = scene_from_dict({})
    assert sc.outputs == ()
    assert sc.medium().c == pytest.approx(343.2)
    assert sc.section("sphere")["radius_m"] == 0.01905
    assert sc.sphere_mass() == pytest.approx(7800 * 4 / 3 * math.pi * 0.01905**3)


def test_mass_material_and_stiffness_rules():
    sc = scene_from_dict({"sphere": {"material": "glass", "radius_m": 0.01}, "contact": {"surface": "steel"}})
    from acoustiviz.core.contact import hertz_stiffness
    from acoustiviz.core.materials import material

    assert sc.k_hertz() == pytest.approx(hertz_stiffness(0.01, material("glass"), material("steel")))
    assert sc.sphere_density() == material("glass").density
    from_mass = scene_from_dict({"sphere": {"damper_radius": "from-mass", "density_kg_m3": 7800.0},
                                 "damper": {"impact_mass_kg": 0.0405}})
    assert from_mass.damper_sphere_radius() == pytest.approx((3 * 0.0405 / (4 * math.pi * 7800)) ** (1 / 3))


@pytest.mark.parametrize(
    ("raw", "key", "words"),
    [
        ({"sphere": {"radius_m": -1.0}}, "sphere.radius_m", "(0, 1] m"),
        ({"sphere": {"radius_m": "big"}}, "sphere.radius_m", "expected a number"),
        ({"sphere": {"raduis_m": 0.01}}, "sphere.raduis_m", "did you mean 'radius_m'"),
        ({"sphear": {}}, "sphear", "did you mean 'sphere'"),
        ({"damper": {"gap_m": 0.0}}, "damper.gap_m", "(0, 10] m"),
        ({"damper": {"solver": "newmrak"}}, "damper.solver", "did you mean 'newmark'"),
        ({"contact": {"pulse": "square"}}, "contact.pulse", "one of"),
        ({"sphere": {"material": "unobtainium"}}, "sphere.material", "unknown material"),
        ({"sphere": {"mass_kg": 1.0, "density_kg_m3": 7800.0}}, "sphere.mass_kg", "not both"),
        ({"listeners": [{"distance_m": 0.01, "angle_deg": 0.0}]}, "listeners[0].distance_m", "inside the sphere"),
        ({"listeners": [{"distance_m": 0.7, "angle_deg": 120.0}]}, "listeners[0].angle_deg", "below the floor"),
        ({"listeners": [{"position_m": [0.1, 0.0, -0.2]}]}, "listeners[0].position_m", "below the floor"),
        ({"configuration": {"kind": "wall-floor", "wall_distance_m": 0.05},
          "listeners": [{"position_m": [-0.2, 0.0, 0.2]}]}, "listeners[0].position_m", "behind the wall"),
        ({"listeners": [{"angle_deg": 30.0}]}, "listeners[0]", "needs distance_m"),
        ({"configuration": {"kind": "wall-floor", "wall_distance_m": 0.001}}, "configuration.wall_distance_m",
         "cut the wall"),
        ({"outputs": {"design_table": {}}}, "outputs.design_table", "needs [outputs.sweep]"),
        ({"outputs": {"sweep": {"gap_m": "0.02:0.06"}}}, "outputs.sweep.gap_m", "start:stop:count"),
        ({"outputs": {"sweep": {"gap_m": "-0.02:0.06:3"}}}, "outputs.sweep.gap_m", "(0, 10] m"),
        ({"outputs": {"wavv": True}}, "outputs.wavv", "did you mean 'wav'"),
        ({"outputs": {"wav": {"rate_hz": 44100.5}}}, "outputs.wav.rate_hz", "an integer"),
        ({"damper": {"clip_tensile": "yes"}}, "damper.clip_tensile", "true or false"),
        ({"outputs": {"snapshot": {"times_s": [0.001] * 13}}}, "outputs.snapshot.times_s", "at most 12"),
        ({"outputs": {"balloon": {"size_px": [800]}}}, "outputs.balloon.size_px", "list of 2 integers"),
        ({"grids": {"plane": {"sections": ["xz", "zz"]}}}, "grids.plane.sections[1]", "one of"),
        ({"outputs": {"wav": {"stereo": True}}}, "outputs.wav.stereo", "two [[listeners]]"),
    ],
)
def test_invalid_scenes_name_file_key_and_range(raw, key, words):
    with pytest.raises(SceneError) as info:
        scene_from_dict(raw, "my.toml")
    msg = str(info.value)
    assert msg.startswith(f"my.toml: {key}: "), msg
    assert words in msg, msg
    assert "\n" not in msg


#: A room scene's surroundings: the sphere on the floor of a 1 m cube with a 10 ms window.
_CUBE = ('[configuration]\nkind = "room"\nroom_m = [1.0, 1.0, 1.0]\nsource_m = [0.5, 0.5, 0.01905]\n'
         "window_s = 0.01\n")


@pytest.mark.parametrize(
    ("toml", "key", "words"),
    [
        ("[grids.plane]\nresolution = 20000\n[outputs.snapshot]\ntimes_s = [0.001, 0.002]\n",
         "grids.plane.resolution", "grids.memory_limit_mb"),
        ("[grids]\nmemory_limit_mb = 1.0\n[grids.sphere]\nn_theta = 512\n[outputs.balloon]\n",
         "grids.sphere.n_theta", "grids.memory_limit_mb"),
        ("[grids]\nmemory_limit_mb = 1.0\n[outputs.directivity]\nstep_deg = 0.01\n",
         "outputs.directivity.step_deg", "grids.memory_limit_mb"),
        ('[configuration]\nkind = "wall-floor"\nwall_distance_m = 0.05\n[grids.sphere]\ndistance_m = 0.02\n'
         "[outputs.balloon]\n", "grids.sphere.distance_m", "to stay in the fluid"),
        (_CUBE + "[grids.sphere]\ndistance_m = 0.9\n[outputs.balloon]\n", "grids.sphere.distance_m",
         "(0.040005, 0.5] m"),
        ("[grids]\nmemory_limit_mb = 1.0\n[outputs.animation]\n", "outputs.animation.frames",
         "40 frames of 800x600 px"),  # its GIF's frames counted, though the run has not named it yet
    ],
    ids=["snapshot-memory", "balloon-memory", "directivity-memory", "balloon-behind-the-wall", "balloon-in-a-room",
         "animation-memory"],
)
def test_a_scene_the_jobs_refuse_is_refused_before_any_work_naming_the_key(tmp_path, monkeypatch, capsys, toml, key,
                                                                             words):
    """The loader leaves these checks to the outputs' jobs, which the run builds before its first output."""
    from acoustiviz.app import pipeline
    from acoustiviz.cli import main

    for kind in OUTPUT_KINDS:  # any output made fails the test
        monkeypatch.setitem(pipeline.PRODUCERS, kind, lambda ctx: pytest.fail("an output was made"))
    scene = tmp_path / "s.toml"
    scene.write_text(toml, encoding="utf-8")
    scene_from_text(toml, "s.toml")  # the loader accepts it: the check is the job's alone
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert f"{key}: " in err and words in err, err
    assert not (tmp_path / "out").exists()  # nothing written, not even the run folder


def test_bad_toml_and_missing_file(tmp_path):
    with pytest.raises(SceneError, match=r"s.toml: <toml>: not valid TOML"):
        scene_from_text("[sphere\nradius_m = 1", "s.toml")
    with pytest.raises(SceneError, match="cannot read the scene"):
        load_scene(tmp_path / "missing.toml")
    p = tmp_path / "ok.toml"
    p.write_text('[impact]\nvelocity_m_s = 2.0\n[outputs.waveform]\n', encoding="utf-8")
    assert load_scene(p).outputs == ("waveform",)


def test_parse_range_is_inclusive():
    assert parse_range("0.02:0.06:5") == pytest.approx([0.02, 0.03, 0.04, 0.05, 0.06])
    assert parse_range("0.5") == [0.5]
    with pytest.raises(SceneError):
        parse_range("1:2:0")


def test_schema_help_lists_every_section():
    text = schema_help()
    for section in ("[medium]", "[sphere]", "[damper]", "[outputs]", "radius_m", "duration_s"):
        assert section in text


# ----------------------------------------------------------------------------- fuzzing
_scalars = st.one_of(
    st.none(), st.booleans(), st.integers(-10**6, 10**6),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=12),
    st.lists(st.floats(allow_nan=True), max_size=4),
)
_sections = st.sampled_from(["scene", "medium", "sphere", "contact", "impact", "configuration", "damper", "grids",
                             "outputs", "listeners", "bogus"])
_keys = st.one_of(
    st.sampled_from(["radius_m", "mass_kg", "density_kg_m3", "material", "velocity_m_s", "kind", "gap_m",
                     "solver", "duration_s", "c_m_s", "rho_kg_m3", "pulse", "waveform", "wav", "sweep",
                     "distance_m", "angle_deg", "position_m", "plane", "sphere", "wall_distance_m"]),
    st.text(alphabet=string.ascii_lowercase + "_", min_size=1, max_size=10),
)
_values = st.recursive(_scalars, lambda inner: st.dictionaries(_keys, inner, max_size=3)
                       | st.lists(inner, max_size=2), max_leaves=6)


def _is_clean_error(exc):
    msg = str(exc)
    return isinstance(exc, SceneError) and msg.startswith("fuzz.toml: ") and "\n" not in msg and len(msg) < 600


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(_sections, st.one_of(st.dictionaries(_keys, _values, max_size=4), _values), max_size=4))
@pytest.mark.slow
def test_random_scenes_load_or_fail_cleanly(raw):
    try:
        scene_from_dict(raw, "fuzz.toml")
    except SceneError as exc:
        assert _is_clean_error(exc), exc


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet=string.printable, max_size=200))
def test_random_text_loads_or_fails_cleanly(text):
    try:
        scene_from_text(text, "fuzz.toml")
    except SceneError as exc:
        assert _is_clean_error(exc), exc


@settings(max_examples=150, deadline=None)
@given(st.data())
def test_mutated_shipped_scenes_load_or_fail_cleanly(data):
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib

    texts = shipped_scenes()
    raw = tomllib.loads(texts[data.draw(st.sampled_from(sorted(texts)))])
    section = data.draw(st.sampled_from(sorted(raw)))
    if isinstance(raw[section], dict) and raw[section]:
        key = data.draw(st.sampled_from(sorted(raw[section])))
        raw[section][key] = data.draw(_values)
    else:
        raw[section] = data.draw(_values)
    try:
        scene_from_dict(raw, "fuzz.toml")
    except SceneError as exc:
        assert _is_clean_error(exc), exc
