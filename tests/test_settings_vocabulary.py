"""A job's vocabulary (``Settings.names_for``): made from records, and every word is one the user can type."""

import argparse

import pytest

from acoustiviz.app.settings.base import vocabulary
from acoustiviz.app.settings.damper_job import DamperJob
from acoustiviz.app.settings.design import DesignJob
from acoustiviz.app.settings.directivity import DirectivityJob
from acoustiviz.app.settings.forced_job import ForcedJob
from acoustiviz.app.settings.map_job import MapJob
from acoustiviz.app.settings.optimize import OptimizeJob
from acoustiviz.app.settings.render_job import JOB_OF_VIEW
from acoustiviz.app.settings.table import Setting
from acoustiviz.app.settings.waveform import WaveformJob
from acoustiviz.cli import build_parser

#: Command -> its job (the view jobs are the subcommands of ``render``).
JOBS = {"damper": DamperJob, "forced": ForcedJob, "directivity": DirectivityJob, "map": MapJob,
        "waveform": WaveformJob, "design": DesignJob, "optimize": OptimizeJob,
        **{f"render {view}": job for view, job in JOB_OF_VIEW.items()}}


#: Names a job keeps for its scene that its command has no option for: the damper records a forced run shares
#: with the scene's ``[damper]`` (the command line gives the model's options only).
SCENE_ONLY = {"forced": {"clip_tensile", "v0", "v", "dt"}}


def _options(command: str) -> set:
    """Every option string (and positional name) the parser of ``command`` accepts."""
    parser = build_parser()
    for word in command.split():
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parser = sub.choices[word]
    return {s for a in parser._actions for s in (a.option_strings or [a.metavar or a.dest])}


def test_vocabulary_reads_records_aliases_and_lookups():
    v0 = Setting("v0", "--v0", "v0_m_s", "float", 1.0, "start speed", "m/s", table="damper")
    window = Setting("window", "--duration", "window_s", "float", None, "window", "s", table="configuration")
    cap = Setting("cap", "--cap", None, "float", None, "a cap", "MB")
    cap_key = Setting("cap", None, "limit_mb", "float", 1.0, "a cap", "MB", table="grids")
    assert vocabulary("cli", [v0], {"v": "v0"}) == {"v0": "--v0", "v": "--v0"}
    assert vocabulary("scene", [v0], {"duration": "window"}, lookup=[window]) == {
        "v0": "damper.v0_m_s", "duration": "configuration.window_s"}
    # the lookup's records name only the aliases that point at them
    assert "window" not in vocabulary("cli", [v0], lookup=[window])
    # of two records of one name, the one with a word for the front end answers an alias
    assert vocabulary("cli", [cap, cap_key], {"limit": "cap"}) == {"cap": "--cap", "limit": "--cap"}
    assert vocabulary("scene", [cap, cap_key], {"limit": "cap"}) == {"cap": "grids.limit_mb",
                                                                     "limit": "grids.limit_mb"}
    # an alias whose record has no word for the front end is left out, not mapped to None
    assert vocabulary("cli", [cap_key], {"limit": "cap"}) == {}


@pytest.mark.parametrize("command", sorted(JOBS))
def test_every_option_a_job_names_is_an_option_of_its_command(command):
    names = JOBS[command].names_for("cli")
    unknown = {api: word for api, word in names.items()
               if word not in _options(command) and api not in SCENE_ONLY.get(command, ())}
    assert not unknown, f"{command}: names options it does not have: {unknown}"


@pytest.mark.parametrize("command", sorted(JOBS))
def test_a_job_names_its_own_options_and_the_memory_cap(command):
    job = JOBS[command]
    names = job.names_for("cli")
    assert {s.name: s.option for s in job.TABLE if s.option}.items() <= names.items()
    if "max_memory_mb" in job.__dataclass_fields__:
        assert names["max_memory_mb"] == "--max-memory"


def test_the_scene_names_the_memory_cap_by_its_grids_key():
    for job in (DamperJob, ForcedJob, DirectivityJob, MapJob, WaveformJob, DesignJob, *JOB_OF_VIEW.values()):
        assert job.names_for("scene")["max_memory_mb"] == "grids.memory_limit_mb", job.__name__


def test_words_that_depend_on_what_the_user_gave():
    assert ForcedJob.names_for("cli", "force")["amplitude"] == "--force"
    assert ForcedJob.names_for("cli", "base")["amplitude"] == "--base"
    assert ForcedJob.names_for("scene", "base")["amplitude"] == "excitation.amplitude"
    assert WaveformJob.names_for("cli", point=True)["listeners"] == "--listener"
    assert WaveformJob.names_for("cli", point=False)["listeners"] == "--distance"
    assert DamperJob.names_for("cli")["v"] == "--v0"  # the physics' v is the start speed the user gave
