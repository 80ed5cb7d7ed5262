"""Random settings, three front ends, one settings object: the records' vocabularies agree.

For each job built on the settings records (waveform, directivity, map, damper, levels), seeded random
values are drawn inside the records' ranges and among their choices, written out three ways -- as
command-line arguments (each record's option), as a scene (each record's scene key) and as API keyword
arguments (each record's name) -- and the three settings objects built from them must be equal. The
values are drawn on a binary grid where a front end adds lengths (a listener's distance to the sphere's
centre), so that equal inputs give equal floats whichever way they travel.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from acoustiviz.app.impacts import impact_setup, observer_point
from acoustiviz.app.names import IMPACT_OPTIONS, SCENE_IMPACT_KEYS
from acoustiviz.app.settings.damper import DAMPER
from acoustiviz.app.settings.impact import DIRECTIVITY, IMPACT
from acoustiviz.app.settings.map import MAP_SETTINGS
from acoustiviz.app.settings.scene import LISTENER_KEYS
from acoustiviz.app.settings.table import by_name
from acoustiviz.cli import build_parser
from acoustiviz.core.listener import Listener
from acoustiviz.scene import scene_from_dict

#: Seeds per job: each draws one set of settings.
SEEDS = range(6)
#: The memory cap every front end is given (a scene's grids.memory_limit_mb defaults to it).
CAP_MB = 256.0

_IMPACT = by_name(IMPACT)
_DAMPER = by_name(DAMPER)
_LISTENER = by_name(LISTENER_KEYS)


def _within(record, lo: float, hi: float) -> tuple:
    """``(lo, hi)``, a sub-interval of ``record``'s range the test draws from (checked to lie inside it)."""
    assert record.low <= lo <= hi <= record.high, f"{record.name}: [{lo}, {hi}] outside {record.range_text()}"
    if record.low_open:
        assert lo > record.low
    if record.high_open:
        assert hi < record.high
    return lo, hi


def _log(rng, record, lo: float, hi: float) -> float:
    """A log-uniform draw in ``[lo, hi]`` within ``record``'s range."""
    lo, hi = _within(record, lo, hi)
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _grid(rng, record, lo: float, hi: float, step: float) -> float:
    """A draw in ``[lo, hi]`` within ``record``'s range, a multiple of ``step`` (a power of two: sums stay exact)."""
    lo, hi = _within(record, lo, hi)
    return float(rng.integers(math.ceil(lo / step), math.floor(hi / step) + 1)) * step


def _choice(rng, record, exclude=()):
    """One of ``record``'s choices."""
    return str(rng.choice([c for c in record.choices if c not in exclude]))


def _impact(rng) -> dict:
    """Random settings of one impact: ``{API name: value}`` of the impact's records."""
    values = {
        "radius": _grid(rng, _IMPACT["radius"], 0.005, 0.03, 2.0 ** -12),
        "velocity": _log(rng, _IMPACT["velocity"], 0.2, 4.0),
        "k_hertz": _log(rng, _IMPACT["k_hertz"], 1e8, 1e10),
        "density": _log(rng, _IMPACT["density"], 1000.0, 9000.0),
        "pulse": _choice(rng, _IMPACT["pulse"]),
        "c": _log(rng, _IMPACT["c"], 300.0, 1500.0),
        "rho": _log(rng, _IMPACT["rho"], 1.0, 1000.0),
        "config": _choice(rng, _IMPACT["config"]),
    }
    if values["config"] == "wall-floor":
        values["wall_distance"] = _grid(rng, _IMPACT["wall_distance"], 0.125, 1.0, 2.0 ** -12)
    return values


def _argv(values: dict, options: dict) -> list:
    """The command-line arguments of ``{API name: value}`` (``options``: API name -> option)."""
    out = []
    for name, value in values.items():
        if isinstance(value, bool):
            out += [options[name]] if value else []
        else:
            out += [options[name], repr(value) if isinstance(value, float) else str(value)]
    return out


def _scene(values: dict, paths: dict, scene: dict | None = None) -> dict:
    """``scene`` with ``{API name: value}`` at its scene keys (``paths``: API name -> ``"table.key"``)."""
    scene = {} if scene is None else scene
    for name, value in values.items():
        *tables, key = paths[name].split(".")
        table = scene
        for t in tables:
            table = table.setdefault(t, {})
        table[key] = value
    return scene


def _cli(command: str, argv: list, module):
    """The settings ``acoustiviz COMMAND ARGV`` builds (``module``: the command's)."""
    args = build_parser().parse_args([command, *argv])
    args.given_options = frozenset()
    return module.settings_from_args(args)


def _impact_api(values: dict) -> dict:
    """The impact's keyword arguments of a one-impact job, from :func:`acoustiviz.app.impacts.impact_setup`."""
    setup = impact_setup(**values)
    return dict(impact=setup.impact, pulse=setup.pulse, medium=setup.medium, geometry=setup.geometry,
                max_memory_mb=CAP_MB, k_hertz_source=setup.k_hertz_source)


@pytest.mark.parametrize("seed", SEEDS)
def test_waveform_settings_agree(seed, tmp_path):
    import acoustiviz.cli.waveform as cli
    from acoustiviz.app.pipeline import waveform_settings
    from acoustiviz.app.settings.waveform import WaveformJob

    rng = np.random.default_rng(1000 + seed)
    impact = _impact(rng)
    distance = _log(rng, _LISTENER["distance"], 0.2, 3.0)
    angle = _log(rng, _LISTENER["angle_deg"], 1.0, 90.0)
    files = {k: str(tmp_path / f"waveform_{{listener}}.{k}") for k in ("csv", "png")}
    from_cli = _cli("waveform", [*_argv(impact, IMPACT_OPTIONS), "--distance", repr(distance), "--angle", repr(angle),
                                 "--max-memory", repr(CAP_MB), "--csv", files["csv"], "--png", files["png"]], cli)
    scene = _scene(impact, SCENE_IMPACT_KEYS, {"outputs": {"waveform": {}}})
    scene["listeners"] = [{"name": cli.LISTENER_NAME, "distance_m": distance, "angle_deg": angle}]
    from_scene = waveform_settings(scene_from_dict(scene), tmp_path)
    api = _impact_api(impact)
    point = observer_point(impact_setup(**impact), distance, angle)
    from_api = WaveformJob(**{k: v for k, v in api.items() if k != "pulse"}, pulses=(api["pulse"],),
                           listeners=(Listener(cli.LISTENER_NAME, point),), **files)
    assert from_cli == from_scene == from_api
    assert from_cli.impact.velocity == impact["velocity"] and from_cli.pulses[0].kind == impact["pulse"]


@pytest.mark.parametrize("seed", SEEDS)
def test_directivity_settings_agree(seed, tmp_path):
    import acoustiviz.cli.directivity as cli
    from acoustiviz.app.pipeline import directivity_settings
    from acoustiviz.app.settings.directivity import DirectivityJob

    rng = np.random.default_rng(2000 + seed)
    impact = _impact(rng)
    records = by_name(DIRECTIVITY)
    job = {"step_deg": _grid(rng, records["step_deg"], 5.0, 90.0, 0.25), "metric": _choice(rng, records["metric"])}
    # on the axis, the circle's radius is the listener's distance exactly (both on the binary grid)
    distance = _grid(rng, _LISTENER["distance"], 0.25, 2.0, 2.0 ** -6)
    files = {k: str(tmp_path / f"directivity.{k}") for k in ("csv", "png")}
    from_cli = _cli("directivity", [*_argv(impact, IMPACT_OPTIONS), *_argv(job, DirectivityJob.cli_names()),
                                    "--distance", repr(distance), "--max-memory", repr(CAP_MB),
                                    "--csv", files["csv"], "--png", files["png"]], cli)
    scene = _scene({**impact, **job}, {**SCENE_IMPACT_KEYS, **DirectivityJob.scene_names()})
    scene["listeners"] = [{"name": "l", "distance_m": distance, "angle_deg": 0.0}]
    from_scene = directivity_settings(scene_from_dict(scene), tmp_path)
    from_api = DirectivityJob(**_impact_api(impact), distance=distance, **job, **files)
    assert from_cli == from_scene == from_api
    assert (from_cli.distance, from_cli.step_deg, from_cli.metric) == (distance, job["step_deg"], job["metric"])


@pytest.mark.parametrize("seed", SEEDS)
def test_map_settings_agree(seed, tmp_path):
    import acoustiviz.cli.map as cli
    from acoustiviz.app.map_job import map_settings
    from acoustiviz.app.settings.map_job import MapJob

    rng = np.random.default_rng(3000 + seed)
    impact = _impact(rng)
    records = by_name(MAP_SETTINGS)
    job = {"plane": _choice(rng, records["plane"]), "extent": _log(rng, records["extent"], 0.1, 1.0),
           "resolution": int(rng.integers(*_within(records["resolution"], 8, 80)))}
    if job["plane"] == "horizontal":
        job["height"] = float(rng.uniform(*_within(records["height"], 0.0, 0.5 * job["extent"])))  # meets the box
    vtk = bool(rng.integers(2))
    files = {k: str(tmp_path / f"level_map.{e}") for k, e in (("png", "png"), ("csv", "csv"), ("vtk", "vtu"))
             if k != "vtk" or vtk}
    from_cli = _cli("map", [*_argv(impact, IMPACT_OPTIONS), *_argv(job, MapJob.cli_names()),
                            "--max-memory", repr(CAP_MB), *[x for k, p in files.items() for x in (f"--{k}", p)]], cli)
    scene = _scene({**impact, **job}, {**SCENE_IMPACT_KEYS, **MapJob.scene_names()})
    scene["outputs"]["level_map"]["vtk"] = vtk
    from_scene = map_settings(scene_from_dict(scene), tmp_path)
    from_api = MapJob(**_impact_api(impact), **job, **files)
    assert from_cli == from_scene == from_api
    assert from_cli.files() == files and from_cli.plane == job["plane"]


@pytest.mark.parametrize("seed", SEEDS)
def test_damper_settings_agree(seed, tmp_path):
    import acoustiviz.cli.damper as cli
    from acoustiviz.app.damper import DamperJob, damper_model
    from acoustiviz.app.names import DAMPER_OPTIONS, SCENE_DAMPER_KEYS
    from acoustiviz.app.pipeline import damper_settings
    from acoustiviz.dynamics import InitialState

    rng = np.random.default_rng(4000 + seed)

    def around(name, low=0.5, high=2.0):  # within a factor of the record's default (Table 1), inside its range
        r = _DAMPER[name]
        return _log(rng, r, max(r.default * low, r.low * 1.001 if r.low_open else r.low), r.default * high)

    model = {name: around(name) for name in ("M", "K", "C", "m", "gap", "k_hertz", "c1")}
    model["clip_tensile"] = bool(rng.integers(2))
    solver = _choice(rng, _DAMPER["solver"])
    run = {"v0": float(rng.choice([-1.0, 1.0])) * _log(rng, _DAMPER["v0"], 0.5, 3.0),
           "duration": _log(rng, _DAMPER["duration"], 1.0, 3.0), "solver": solver,
           "rtol": _log(rng, _DAMPER["rtol"], 1e-10, 1e-4)}
    files = {"impacts_csv": str(tmp_path / "impacts.csv"), "history_csv": str(tmp_path / "damper_history.csv"),
             "png": str(tmp_path / "damper_history.png")}
    options = {**DAMPER_OPTIONS, **{s.name: s.option for s in DAMPER if s.option}}
    paths = {s.name: s.path for s in DAMPER if s.key}
    from_cli = _cli("damper", [*_argv({**model, **run}, options), "--max-memory", repr(CAP_MB),
                               *[x for k, p in files.items() for x in (f"--{k.replace('_', '-')}", p)]], cli)
    scene = _scene({**model, **run}, paths, {"outputs": {"impact_table": {}, "damper_history": {}}})
    from_scene = damper_settings(scene_from_dict(scene), tmp_path)
    from_api = DamperJob(model=damper_model(**model), initial=InitialState(v=run["v0"]), duration=run["duration"],
                         solver=solver, rtol=run["rtol"], max_memory_mb=CAP_MB, **files)
    assert from_cli == from_scene == from_api
    assert from_cli.model.clip_tensile == model["clip_tensile"] and from_cli.solver == solver
    assert set(SCENE_DAMPER_KEYS.values()) >= {paths[name] for name in ("M", "K", "C", "m", "gap")}


def _write_wav(folder, pressure: np.ndarray, rate: int, channels) -> str:
    """The pressure as a 64-bit float WAV file with its sidecar; a power-of-two scale keeps every sample exact."""
    import soundfile as sf

    scale = 2.0 ** np.ceil(np.log2(np.max(np.abs(pressure))))
    wav = folder / "signal.wav"
    sf.write(str(wav), (pressure / scale).T, rate, subtype="DOUBLE")
    (folder / "signal.json").write_text(json.dumps({"scale_pa_per_full_scale": scale,
                                                    "channel_names": list(channels)}), encoding="utf-8")
    return str(wav)


@pytest.mark.parametrize("seed", SEEDS)
def test_levels_settings_agree(seed, tmp_path):
    import acoustiviz.app.scene_levels as scene_levels
    import acoustiviz.cli.levels as cli
    from acoustiviz.app.settings.levels import ALL, LevelsJob
    from acoustiviz.core.signal import Signal

    rng = np.random.default_rng(5000 + seed)
    records = by_name(ALL)
    channels = tuple(f"listener{i}" for i in range(int(rng.integers(1, 4))))
    rate = int(rng.choice([48000, 96000]))
    pressure = rng.normal(0.0, _log(rng, records["pa_per_fs"], 0.01, 10.0), (len(channels), int(rate * 0.05)))
    loudness = bool(rng.integers(2)) and scene_levels.loudness_available()
    csv = str(tmp_path / "levels.csv")
    wav = _write_wav(tmp_path, pressure, rate, channels)
    args = build_parser().parse_args(["levels", wav, "--csv", csv, *(["--loudness"] if loudness else [])])
    from_cli = cli.settings_from_args(args, echo=lambda line: None)
    scene = scene_from_dict({"damper": {"duration_s": 1.0}, "outputs": {"levels": {records["loudness"].key: loudness}}})
    signal = Signal(pressure, float(rate))
    from_scene = scene_levels.levels_settings(scene, tmp_path, signal, channels)
    from_api = LevelsJob(signal, channels, loudness=loudness, csv=csv)
    assert from_cli == from_scene == from_api
    assert from_cli.channels == channels and from_cli.loudness == loudness
