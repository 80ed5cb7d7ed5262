"""The files and settings of a scene's outputs, all checked before the first output is computed.

:func:`output_files` names every file each output of a scene writes in the run folder, those
derived beside another included (a WAV's JSON sidecar, a VTK file's ``_geometry.vtu``, a level
table's ``_bands.csv``); :func:`preflight` checks each of them as the commands check theirs
(:func:`acoustiviz.app.outputs.check_output_file`: not a folder, a link or a read-only file,
and not an existing file unless replacing is allowed) and builds each output's settings object,
so that a scene whose third output cannot be made writes nothing at all. The run's
:class:`~acoustiviz.app.pipeline.RunContext` writes only the names listed here.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import ParameterError

__all__ = ["SUMMARY", "output_files", "preflight"]

#: The run's summary, written last.
SUMMARY = "summary.md"


def _vtk(stem: str) -> list:
    from ..output.vtk import geometry_path

    return [(f"{stem}.vtu", "vtk"), (geometry_path(f"{stem}.vtu").name, "vtk")]


def _wav(stem: str) -> list:
    from ..output.audio.wav import sidecar_path

    return [(f"{stem}.wav", "wav"), (sidecar_path(f"{stem}.wav").name, "json")]  # the WAV and its JSON sidecar


def _levels(scene, names) -> list:
    from .levels import bands_path

    return [("levels.csv", "csv"), (bands_path("levels.csv").name, "csv")]


def _run_field(scene, names) -> list:
    from .settings.run_field import scene_files

    opts = scene.output("run_field")
    kinds = {"csv": "csv", "png": "figure", "vtu": "vtk"}
    files = [(name, kinds[name.rpartition(".")[2]]) for name in
             scene_files(opts["grid"], opts["waveform"], opts["snapshot_time_s"] is not None, opts["vtk"]).values()]
    return files + (_vtk("run_snapshot")[1:] if any(n.endswith(".vtu") for n, _ in files) else [])


def _view(kind: str, ending: str):
    def files(scene, names):
        opts = scene.output(kind)
        return [(f"{kind}.{ending}", ending)] + (_vtk(kind) if opts["vtk"] else []) \
            + ([(f"{kind}.html", "html")] if opts.get("html") else [])

    return files


def _waveform(scene, name: str) -> list:
    """A listener's table, in a room (an enclosed geometry) its JSON sidecar, and its figure."""
    from ..core.geometry import geometry_class

    enclosed = geometry_class(scene.section("configuration")["kind"]).enclosed
    room = [(f"waveform_{name}.json", "json")] if enclosed else []
    return [(f"waveform_{name}.csv", "csv"), *room, (f"waveform_{name}.png", "figure")]


def _pair(stem: str):
    def files(scene, names):
        return [(f"{stem}.csv", "csv"), (f"{stem}.png", "figure")]

    return files


#: Output kind -> ``files(scene, listener names)``: ``[(file name, format)]`` written in the run folder
#: (format ``"folder"``: a folder of its own).
_FILES = {
    "waveform": lambda scene, names: [f for n in names for f in _waveform(scene, n)],
    "directivity": _pair("directivity"),
    "level_map": lambda scene, names: _pair("level_map")(scene, names)
    + (_vtk("level_map") if scene.output("level_map")["vtk"] else []),
    "damper_history": _pair("damper_history"),
    "impact_table": lambda scene, names: [("impacts.csv", "csv")],
    "snapshot": _view("snapshot", "png"),
    "balloon": _view("balloon", "png"),
    "animation": _view("animation", "gif"),
    "restitution": _pair("restitution"),
    "sweep": lambda scene, names: [("sweep", "folder")],
    "optimize": lambda scene, names: [("optimize", "folder")],
    "design_table": lambda scene, names: [("design_table.png", "png"), ("design_choice.txt", "text")],
    "wav": lambda scene, names: (_wav("wav_stereo") if scene.output("wav")["stereo"]
                                 else [f for n in names for f in _wav(f"wav_{n}")]),
    "levels": _levels,
    "spectrum": _pair("spectrum"),
    "run_field": _run_field,
    "frequency_response": _pair("frequency_response"),
    "bifurcation": lambda scene, names: [("bifurcation.png", "figure")],
    "operating_noise": lambda scene, names: [("operating_noise.csv", "csv"), *_wav(f"operating_noise_{names[0]}")],
}


def output_files(scene) -> dict:
    """``{kind: [(file name, format)]}``: every file each output of ``scene`` writes in the run folder.

    The format is a kind of :data:`acoustiviz.app.outputs.FORMATS` (``"figure"``: any matplotlib
    format), or ``"folder"`` for a folder of the output's own (the sweep's).
    """
    names = [n for n, _ in scene.listeners()]
    return {kind: _FILES[kind](scene, names) for kind in scene.outputs if kind in _FILES}


def preflight(scene, out, settings=None) -> frozenset:
    """Check every output of ``scene`` before any is computed; return the names of the files it may write.

    Parameters
    ----------
    scene : acoustiviz.scene.Scene
        The validated scene.
    out : path-like
        The run folder (existing or not; a missing one has nothing in the way).
    settings : dict, optional
        Output kind -> ``check(scene)`` building that output's settings (errors name scene keys).

    Raises
    ------
    ParameterError
        An output's settings, or a file in its way (named by ``outputs.KIND`` and the file).
    """
    from .outputs import check_distinct, check_output_file

    out = Path(out)
    for kind, check in (settings or {}).items():
        if scene.wants(kind):
            check(scene)
    files = output_files(scene)
    files["summary"] = [(SUMMARY, "text")]
    seen = {}
    for kind, entries in files.items():
        for name, fmt in entries:
            key = f"outputs.{kind}" if kind != "summary" else "--out"
            seen[f"{key} {name}"] = out / name
            if not out.is_dir():
                continue
            target = out / name
            if fmt == "folder":
                if target.exists() and not target.is_dir():
                    raise ParameterError(key, f"{target} is in the way of the output's folder: it is not a folder")
            else:
                check_output_file(key, target, fmt)
    check_distinct(seen)
    return frozenset(Path(p).name for p in seen.values())
