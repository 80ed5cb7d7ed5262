"""The levels job: one settings object, one run and one writer for the command line, scenes and the API.

The levels of one pressure signal are asked for three ways (``acoustiviz levels`` on a WAV file holding
it, a scene's ``[outputs.levels]`` and ``[outputs.spectrum]`` on the damper run that computes it, and a
:class:`~acoustiviz.app.levels.LevelsJob` built in Python) and the files are compared byte for byte;
the command line and the scene must build equal settings objects; bad input is refused before any
work, naming the front end's option or key.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import acoustiviz.app.scene_levels as scene_levels
from acoustiviz.app.levels import LevelsJob, run
from acoustiviz.app.pipeline import run_scene
from acoustiviz.cli import build_parser, main
from acoustiviz.cli.levels import settings_from_args
from acoustiviz.core.signal import Signal
from acoustiviz.errors import ParameterError
from acoustiviz.scene import scene_from_dict

LEVEL_FILES = ("levels.csv", "levels_bands.csv")
SPECTRUM_FILES = ("spectrum.csv", "spectrum.png")


@pytest.fixture(scope="module")
def scene_run(tmp_path_factory):
    """A damper scene's levels and spectrum, with the signal and channel names its job was built from."""
    seen = {}
    real = scene_levels.levels_settings

    def spy(scene, out=None, signal=None, channels=()):
        if signal is not None:
            seen.update(scene=scene, signal=signal, channels=tuple(channels))
        return real(scene, out, signal, channels)

    out = tmp_path_factory.mktemp("scene") / "o"
    scene = scene_from_dict({"damper": {"duration_s": 0.2}, "outputs": {"levels": {}, "spectrum": {}}})
    mp = pytest.MonkeyPatch()
    mp.setattr(scene_levels, "levels_settings", spy)
    try:
        run_scene(scene, out)
    finally:
        mp.undo()
    return out, seen


def _write_wav(folder, signal: Signal, channels) -> str:
    """The signal as a 64-bit float WAV file with a sidecar; a power-of-two scale keeps every sample exact."""
    import soundfile as sf

    scale = 2.0 ** np.ceil(np.log2(np.max(np.abs(signal.pressure))))
    wav = folder / "run.wav"
    sf.write(str(wav), (signal.pressure / scale).T, int(signal.sample_rate), subtype="DOUBLE")
    (folder / "run.json").write_text(json.dumps({"scale_pa_per_full_scale": scale,
                                                 "channel_names": list(channels)}), encoding="utf-8")
    return str(wav)


def test_command_line_scene_and_api_write_identical_files(scene_run, tmp_path):
    out, seen = scene_run
    signal, channels = seen["signal"], seen["channels"]
    assert signal.sample_rate == 96000 and len(channels) >= 1
    api = tmp_path / "api"
    api.mkdir()
    job = LevelsJob(signal, channels, csv="levels.csv", spectrum_csv="spectrum.csv", spectrum_png="spectrum.png",
                    what="the damper run")
    written = run(job).write(api)
    assert sorted(p.name for p in written) == sorted(LEVEL_FILES + SPECTRUM_FILES)
    for name in LEVEL_FILES + SPECTRUM_FILES:
        assert (api / name).read_bytes() == (out / name).read_bytes(), name
    cli = tmp_path / "cli"
    cli.mkdir()
    wav = _write_wav(cli, signal, channels)
    assert main(["levels", wav, "--csv", str(cli / "levels.csv")]) == 0
    for name in LEVEL_FILES:
        assert (cli / name).read_bytes() == (out / name).read_bytes(), name


def test_command_line_and_scene_build_equal_settings(scene_run, tmp_path):
    _, seen = scene_run
    wav = _write_wav(tmp_path, seen["signal"], seen["channels"])
    args = build_parser().parse_args(["levels", wav, "--csv", str(tmp_path / "levels.csv")])
    from_cli = settings_from_args(args, echo=lambda line: None)
    scene = scene_from_dict({"damper": {"duration_s": 0.2}, "outputs": {"levels": {}}})
    from_scene = scene_levels.levels_settings(scene, tmp_path, seen["signal"], seen["channels"])
    assert from_cli == from_scene
    assert from_cli.source == "sidecar run.json" and from_scene.source == "computed"
    with_loudness = scene_from_dict({"damper": {"duration_s": 0.2}, "outputs": {"levels": {"loudness": True}}})
    if scene_levels.loudness_available():
        assert scene_levels.levels_settings(with_loudness, tmp_path, seen["signal"], seen["channels"]) != from_cli


def test_command_line_refuses_an_empty_interval_before_writing(tmp_path, capsys):
    signal = Signal(np.sin(np.linspace(0.0, 100.0, 4800)), 48000.0)
    wav = _write_wav(tmp_path, signal, ["a"])
    out = tmp_path / "out.csv"
    assert main(["levels", wav, "--csv", str(out), "--start", "0.05", "--stop", "0.02"]) == 2
    err = capsys.readouterr().err
    assert "--stop" in err and "--start" in err and len(err.strip().splitlines()) == 1
    assert not out.exists() and not (tmp_path / "out_bands.csv").exists()


def test_api_refuses_an_empty_interval_and_mismatched_channel_names():
    signal = Signal(np.ones((2, 100)), 1000.0)
    with pytest.raises(ParameterError, match="stop"):
        LevelsJob(signal, ("a", "b"), start=0.05, stop=0.05)
    with pytest.raises(ParameterError, match="channel name"):
        LevelsJob(signal, ("a",))


def test_scene_refuses_loudness_without_mosqito_before_the_run(tmp_path, monkeypatch):
    monkeypatch.setattr(scene_levels, "loudness_available", lambda: False)
    ran = []
    monkeypatch.setattr(scene_levels, "_result", lambda ctx: ran.append(ctx))
    scene = scene_from_dict({"damper": {"duration_s": 0.2}, "outputs": {"levels": {"loudness": True}}})
    with pytest.raises(ParameterError, match=r"outputs\.levels\.loudness"):
        run_scene(scene, tmp_path / "o")
    assert not ran and not any((tmp_path / "o").glob("*.csv"))


def test_levels_that_overflow_are_refused_before_any_file(tmp_path):
    rng = np.random.default_rng(1)
    loud = Signal(1e200 * rng.standard_normal(4800), 48000.0)
    job = LevelsJob(loud, ("a",), csv="levels.csv", names={"input": "damper"})
    with np.errstate(all="ignore"), pytest.raises(ParameterError, match="damper.*not finite"):
        run(job).write(tmp_path)
    assert not any(tmp_path.iterdir())
