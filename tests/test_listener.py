"""A named listening position: the scene's name rule and a read-only (3,) position in m."""

import numpy as np
import pytest

import acoustiviz
from acoustiviz.core.listener import Listener
from acoustiviz.errors import ParameterError


def test_a_listener_holds_its_name_and_a_read_only_copy_of_its_position():
    raw = [0.5, -0.25, 1.0]
    ear = Listener("left ear", raw)
    assert ear.name == "left ear"
    assert ear.position.shape == (3,) and ear.position.dtype == float
    np.testing.assert_array_equal(ear.position, raw)
    arr = np.array(raw)
    other = Listener("x", arr)
    arr[0] = 7.0
    assert other.position[0] == 0.5
    with pytest.raises(ValueError):
        ear.position[0] = 1.0
    with pytest.raises(AttributeError):
        ear.name = "right"


@pytest.mark.parametrize("name", ["", "../up", "a/b", ".hidden", "ends.", "x" * 65, "CON", "nul.txt", 3])
def test_names_that_cannot_become_part_of_a_file_name_are_refused(name):
    with pytest.raises(ParameterError, match=r"^name: "):
        Listener(name, [0.0, 0.0, 1.0])


def test_the_name_rule_is_the_one_scenes_use(tmp_path):
    # a scene refuses the same names, with the same reason, at its listeners[i].name key
    from acoustiviz.scene.load import SceneError, load_scene

    with pytest.raises(ParameterError) as listener_err:
        Listener("a/b", [0.0, 0.0, 1.0])
    reason = str(listener_err.value).removeprefix("name: ")
    with pytest.raises(SceneError, match="listeners\\[0\\].name") as scene_err:
        path = tmp_path / "scene.toml"
        path.write_text('[[listeners]]\nname = "a/b"\nposition_m = [0.0, 0.0, 1.0]\n')
        load_scene(path)
    assert reason in str(scene_err.value)


@pytest.mark.parametrize("position", [[0.0, 1.0], [0.0, 0.0, np.nan], [[0, 0, 1], [0, 0, 2]], "abc", [0, 0, np.inf]])
def test_positions_other_than_one_finite_point_are_refused(position):
    with pytest.raises(ParameterError, match=r"^position: "):
        Listener("a", position)


def test_listener_is_exported_at_the_top_level():
    assert acoustiviz.Listener is Listener and "Listener" in acoustiviz.__all__


def test_a_listener_unpacks_as_the_name_position_pairs_of_a_scene():
    name, position = Listener("mic", [0.1, 0.2, 0.3])
    assert name == "mic"
    np.testing.assert_array_equal(position, [0.1, 0.2, 0.3])


def test_a_run_sees_the_scene_listeners_as_listener_values(tmp_path):
    from acoustiviz.app.pipeline import RunContext
    from acoustiviz.scene.load import load_scene

    path = tmp_path / "scene.toml"
    path.write_text('[[listeners]]\nname = "near"\nposition_m = [0.0, 0.3, 0.4]\n'
                    '[[listeners]]\nposition_m = [0.5, 0.0, 0.5]\n')
    scene = load_scene(path)
    ctx = RunContext(scene, tmp_path / "out")
    got = ctx.listeners
    assert all(isinstance(lst, Listener) for lst in got)
    assert [lst.name for lst in got] == ["near", "listener2"]
    np.testing.assert_array_equal(got[0].position, [0.0, 0.3, 0.4])
    np.testing.assert_array_equal(got[1].position, [0.5, 0.0, 0.5])
