"""A fuzz campaign over the command line: a hostile, careless user, run many times, every outcome classified.

Not a test (pytest does not collect it: no ``test_`` prefix); run it by hand::

    python tests/fuzz_campaign.py --seed 1 --count 300 --jobs 1 --out fuzz.json

Each invocation runs one command (``run``, ``waveform``, ``directivity``, ``map``, ``damper``,
``forced``, ``sweep``, ``design``, ``render balloon|snapshot|animation``, ``auralize``,
``levels``, or ``run`` on a damaged scene file) as ``python -m acoustiviz`` in its own scratch
folder, starting from a cheap valid invocation (short runs, coarse grids) and changing one to
three of its options to bad, extreme or malformed values (0, negative, 1e-308, 1e308, nan, inf,
text, empty, ...), giving hostile output names, outputs that exist already, missing or damaged
input files, and, for a subset, a SIGINT (Ctrl-C, to the whole process group) at a random
moment after the start. Each outcome is one of:

``refused``        exit 2, one line on stderr
``worked``         exit 0 and every output it was asked for exists
``interrupted``    exit 130 after the SIGINT the campaign sent
``failed``         exit 1 with a message on stderr
``traceback``      stderr holds "Traceback"
``crash``          killed by a signal the campaign did not send
``hang``           still running at the time-out (then killed)
``changed-input``  an input file (or an output that existed before a run that did not succeed)
                   changed
``inf-nan``        an output CSV holds inf, nan or empty cells in a numeric column, or a WAV is
                   all zeros or not finite
``other``          anything else (exit 2 with several lines, exit 0 with an output missing, ...)

The argv of every invocation follows from ``--seed`` and its index alone, so a run is
reproducible (what a SIGINT interrupts depends on timing, as a user's Ctrl-C does). The log
(``--out``, JSON or CSV by its suffix) holds every invocation: its argv, exit status, class,
reason, stderr tail and duration. The scratch folders of the bad classes (traceback, crash,
hang, changed-input, inf-nan, other) are kept under ``--work`` to reproduce them; the others are
removed.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import json
import math
import os
import random
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BAD = ("traceback", "crash", "hang", "changed-input", "inf-nan", "other")
CLASSES = ("refused", "worked", "interrupted", "failed", *BAD)

#: Cheap valid invocations (a fraction of a second to a few seconds of work each); ``{wav}`` and
#: ``{sweep}`` are the input fixtures, ``{scene}`` a scene file.
BASE = {
    "run": ["run", "{scene}", "--out", "out"],
    "waveform": ["waveform", "--csv", "w.csv"],
    "directivity": ["directivity", "--step", "30", "--csv", "d.csv"],
    "map": ["map", "--resolution", "21", "--extent", "0.3", "--csv", "m.csv"],
    "damper": ["damper", "--duration", "1", "--impacts-csv", "i.csv"],
    "forced": ["forced", "--force", "5", "--freq", "5", "--starts", "1", "--max-cycles", "60",
               "--noise-seconds", "0.2", "--csv", "f.csv"],
    "sweep": ["sweep", "--gap", "0.02,0.04", "--m", "0.04", "--duration", "1", "--workers", "1",
              "--out", "sw"],
    "design": ["design", "--sweep", "{sweep}", "--inclination", "0.005", "--tolerance", "0.01"],
    "render balloon": ["render", "balloon", "--resolution", "8", "--size", "160x120", "--png", "b.png"],
    "render snapshot": ["render", "snapshot", "--resolution", "31", "--size", "160x120", "--png", "s.png"],
    "render animation": ["render", "animation", "--frames", "3", "--resolution", "21", "--size", "160x120",
                         "--gif", "a.gif"],
    "auralize": ["auralize", "--duration", "0.3", "--wav", "a.wav"],
    "levels": ["levels", "{wav}", "--csv", "l.csv"],
    "scene": ["run", "{scene}", "--out", "out"],
}

#: Options whose value names a file or folder the command writes.
OUTPUT_OPTIONS = {"--csv", "--png", "--vtk", "--html", "--gif", "--mp4", "--wav", "--impacts-csv",
                  "--levels-csv", "--out"}
#: Options left alone: they only print, or change where the work runs rather than what it computes.
SKIP_OPTIONS = {"--help", "--help-scene", "--version", "--executor", "--quiet"}

NUMBERS = ["0", "-1", "-0", "1e-308", "-1e-308", "1e308", "1e999", "nan", "-nan", "inf", "-inf", "text",
           "", " ", "0x10", "1,2,3", "1:2:3", "3:1:0", "0:1:100000", "1e-9", "1e9", "2,nan", "1,,2",
           "½", "1_000", "--", "-5e3", "4.9e-324"]
NAMES = ["", ".", "..", "missing/dir/x{ext}", "existing_dir", "x", "x.wrong", " {ext}", "-{ext}",
         "a" * 300 + "{ext}", "ü ñ{ext}", "x{ext}/", "sub/../x{ext}", "{same}"]
WORKERS = ["0", "-1", "nan", "inf", "text", "", "1.5", "2", "1e308"]
PLAUSIBLE = ["1e-6", "1e-3", "0.01", "0.5", "1", "2", "10", "1000", "1e6", "0.1,0.2,0.3", "3:7:3", "1,0,0.5"]
SCENE_VALUES = ["0", "-1", "1e-308", "1e308", "nan", "inf", "-inf", '"text"', '""', "[]", "true", "{}",
                "[nan, inf]", '"0.7"', "-0.0", "99999999999999999999"]
COORDINATES = ("x_m", "y_m", "z_m")
SENTINEL = b"precious user data: must survive any run that does not succeed\n"


@dataclass
class Invocation:
    """One planned run and, once run, its outcome."""

    index: int
    command: str
    argv: list
    files: dict = field(default_factory=dict)      # relative path -> bytes written before the run
    dirs: list = field(default_factory=list)       # folders made before the run
    outputs: list = field(default_factory=list)    # output paths named on the command line
    sigint_after: float | None = None              # s after the start, or None
    note: str = ""
    status: int | None = None
    klass: str = ""
    reason: str = ""
    stderr_tail: str = ""
    traceback: bool = False  # stderr held "Traceback" anywhere (the tail may have cut it off)
    duration: float = 0.0
    sigint_sent: bool = False


# ---------------------------------------------------------------- the options of each command


def command_options(command: str) -> dict:
    """``{option: (nargs, choices)}`` of a command, read from the program's own parser."""
    from acoustiviz.cli import build_parser

    parser = build_parser()
    for word in ("run" if command == "scene" else command).split():
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parser = sub.choices[word]
    opts = {}
    for action in parser._actions:
        names = [s for s in action.option_strings if s.startswith("--")]
        if names and names[0] not in SKIP_OPTIONS:
            opts[names[0]] = (action.nargs, list(action.choices) if action.choices else None)
    return opts


# ---------------------------------------------------------------- planning an invocation


def _ext(argv: list, option: str) -> str:
    value = argv[argv.index(option) + 1] if option in argv else ""
    return Path(value).suffix or {"--out": "", "--png": ".png", "--gif": ".gif", "--wav": ".wav",
                                  "--vtk": ".vtu", "--html": ".html", "--mp4": ".mp4"}.get(option, ".csv")


def _set(argv: list, option: str, values: list) -> list:
    """``argv`` with ``option`` given ``values`` (replacing its old value, or added)."""
    if option in argv:
        i = argv.index(option)
        j = i + 1
        while j < len(argv) and not argv[j].startswith("--"):
            j += 1
        return argv[:i] + [option, *values] + argv[j:]
    return [*argv, option, *values]


def _value(rng: random.Random, choices) -> str:
    if choices and rng.random() < 0.6:
        return str(rng.choice(choices))
    if rng.random() < 0.4:  # plausible but extreme: past the bad-value check, into the work
        return rng.choice(PLAUSIBLE)
    return rng.choice(NUMBERS + ["Plane", "none", "both,one"])


def _hostile_name(rng: random.Random, inv: Invocation, option: str) -> str:
    ext = _ext(inv.argv, option)
    others = _outputs(inv.argv)
    inputs = sorted(inv.files)
    name = rng.choice(NAMES).replace("{ext}", ext)
    if name == "{same}":  # the same file as another output, or as an input
        name = rng.choice(others + inputs) if others + inputs else "x" + ext
    if name == "existing_dir":
        inv.dirs.append(name)
    return name


def _mutate_options(rng: random.Random, inv: Invocation, opts: dict) -> None:
    k = rng.choices([1, 2, 3], weights=[6, 3, 1])[0]  # mostly one change: past the first refusal, into the work
    for option in rng.sample(sorted(opts), k=min(len(opts), k)):
        nargs, choices = opts[option]
        if nargs == 0:
            inv.argv = [*inv.argv, option]
        elif option in OUTPUT_OPTIONS:
            inv.argv = _set(inv.argv, option, [_hostile_name(rng, inv, option)])
        elif option == "--workers":  # never more processes than a shared machine can take
            inv.argv = _set(inv.argv, option, [rng.choice(WORKERS)])
        elif nargs == "+":
            inv.argv = _set(inv.argv, option, [_value(rng, choices) for _ in range(rng.randint(1, 3))])
        else:
            inv.argv = _set(inv.argv, option, [_value(rng, choices)])


def _outputs(argv: list) -> list:
    return [argv[i + 1] for i, a in enumerate(argv[:-1]) if a in OUTPUT_OPTIONS]


def _existing_outputs(rng: random.Random, inv: Invocation) -> None:
    """Make some of the outputs exist already, holding the user's data."""
    for name in inv.outputs:
        if rng.random() < 0.5 and name.strip() and not name.endswith("/") and name not in (".", ".."):
            if name in inv.files or name in inv.dirs or Path(name).parent != Path("."):
                continue
            if "--out" in inv.argv and inv.argv[inv.argv.index("--out") + 1] == name:
                inv.files[f"{name}/precious.txt"] = SENTINEL
            else:
                inv.files[name] = SENTINEL
            inv.note += f" {name} exists;"


def plan(seed: int, index: int, command: str, fixtures: dict) -> Invocation:
    """The invocation ``index`` of the campaign ``seed``: a function of the two alone."""
    rng = random.Random(seed * 1_000_003 + index)
    inv = Invocation(index, command, list(BASE[command]))
    _inputs(rng, inv, fixtures)
    roll = rng.random()
    if command == "scene":
        inv.files["scene.toml"] = damage_scene(rng, fixtures["scene.toml"])
    elif roll < 0.85:
        _mutate_options(rng, inv, command_options(command))
    inv.outputs = _outputs(inv.argv)
    if rng.random() < 0.3:
        _existing_outputs(rng, inv)
    if rng.random() < 0.2:
        inv.sigint_after = round(rng.uniform(0.3, 4.0), 2)
    return inv


def _inputs(rng: random.Random, inv: Invocation, fixtures: dict) -> None:
    """Copy (or damage, or leave out) the input files the invocation reads."""
    if "{wav}" in inv.argv:
        wav, sidecar = fixtures["in.wav"], fixtures["in.json"]
        damage = rng.random()
        if damage < 0.25:
            wav, sidecar, inv.note = _damage_audio(rng, wav, sidecar)
        if wav is not None:
            inv.files["in.wav"] = wav
        if sidecar is not None:
            inv.files["in.json"] = sidecar
        inv.argv = [a.replace("{wav}", "in.wav") for a in inv.argv]
    if "{sweep}" in inv.argv:
        for name, data in fixtures.items():
            if name.startswith("sweep/"):
                inv.files[name] = data
        if rng.random() < 0.3:
            victim = rng.choice(sorted(n for n in inv.files if n.startswith("sweep/")))
            inv.files[victim] = _damage_bytes(rng, inv.files[victim])
            inv.note += f" damaged {victim};"
        inv.argv = [a.replace("{sweep}", "sweep") for a in inv.argv]
    if "{scene}" in inv.argv:
        inv.files["scene.toml"] = fixtures["scene.toml"]
        if inv.command == "run" and rng.random() < 0.15:
            del inv.files["scene.toml"]
            inv.note += " scene missing;"
        inv.argv = [a.replace("{scene}", "scene.toml") for a in inv.argv]


def _damage_bytes(rng: random.Random, data: bytes) -> bytes:
    how = rng.choice(["empty", "truncate", "garbage", "flip"])
    if how == "empty":
        return b""
    if how == "truncate":
        return data[: rng.randint(0, max(0, len(data) - 1))]
    if how == "garbage":
        return bytes(rng.randrange(256) for _ in range(rng.randint(1, 2000)))
    out = bytearray(data)
    for _ in range(rng.randint(1, 20)):
        if out:
            out[rng.randrange(len(out))] = rng.randrange(256)
    return bytes(out)


def _damage_audio(rng: random.Random, wav: bytes, sidecar: bytes):
    what = rng.choice(["wav", "sidecar", "no-sidecar", "no-wav", "sidecar-values"])
    if what == "wav":
        return _damage_bytes(rng, wav), sidecar, " damaged in.wav;"
    if what == "sidecar":
        return wav, _damage_bytes(rng, sidecar), " damaged in.json;"
    if what == "no-sidecar":
        return wav, None, " no in.json;"
    if what == "no-wav":
        return None, sidecar, " no in.wav;"
    meta = json.loads(sidecar)
    key = rng.choice(sorted(meta))
    meta[key] = rng.choice([0, -1, None, "text", float("nan"), 1e308, [], {}])
    return wav, json.dumps(meta).encode(), f" in.json {key} = {meta[key]!r};"


def damage_scene(rng: random.Random, text: bytes) -> bytes:
    """A scene file as a careless or hostile user leaves it."""
    lines = text.decode().splitlines()
    how = rng.random()
    if how < 0.08:
        return _damage_bytes(rng, text)
    keyed = [i for i, line in enumerate(lines) if "=" in line and not line.lstrip().startswith("#")]
    for _ in range(rng.randint(1, 3)):
        i = rng.choice(keyed)
        key = lines[i].split("=")[0].strip()
        action = rng.random()
        if action < 0.6:
            lines[i] = f"{key} = {rng.choice(SCENE_VALUES)}"
        elif action < 0.75:
            lines[i] = ""
        elif action < 0.85:
            lines[i] = f"{key[:-1] + key[-1] * 2} = 1.0"
        else:
            lines.insert(i, lines[i])  # a duplicate key
    if rng.random() < 0.2:
        lines += ["", rng.choice(["[outputs.balloon]", "[outputs.map]", "[outputs.wav]", "[nonsense]",
                                  "[outputs.snapshot]\ntimes_s = [nan]", "[[listeners]]\ndistance_m = 0"])]
    return "\n".join(lines).encode()


# ---------------------------------------------------------------- running and classifying


def _hashes(folder: Path) -> dict:
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in folder.rglob("*") if p.is_file()}


def _prepare(inv: Invocation, folder: Path) -> dict:
    folder.mkdir(parents=True)
    for name in inv.dirs:
        (folder / name).mkdir(parents=True, exist_ok=True)
    for name, data in inv.files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_bytes(data)
    return _hashes(folder)


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    env["MPLBACKEND"] = "Agg"
    return env


def execute(inv: Invocation, folder: Path, timeout: float) -> dict:
    """Run the invocation in ``folder``; fill in its status, stderr and duration; return the input hashes."""
    before = _prepare(inv, folder)
    start = time.monotonic()
    proc = subprocess.Popen([sys.executable, "-m", "acoustiviz", *inv.argv], cwd=folder, env=_env(),
                            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True)
    try:
        if inv.sigint_after is not None:
            try:
                proc.wait(timeout=inv.sigint_after)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGINT)
                inv.sigint_sent = True
        _, err = proc.communicate(timeout=timeout)
        inv.status = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        _, err = proc.communicate()
        inv.status = None
    inv.duration = round(time.monotonic() - start, 3)
    text = err.decode(errors="replace")
    inv.stderr_tail = text[-800:]
    inv.traceback = "Traceback" in text
    return before


def _changed_inputs(inv: Invocation, folder: Path, before: dict) -> list:
    after = _hashes(folder)
    out = set(inv.outputs) if inv.status == 0 else set()
    protected = [n for n in before if n not in out and not any(n.startswith(o.rstrip("/") + "/") for o in out)]
    return [n for n in protected if after.get(n) != before[n]]


def _masked(header: list, row: list) -> bool:
    """A grid point inside the sphere: every value but its coordinates is nan (documented for maps)."""
    if not all(c in header for c in COORDINATES):
        return False
    values = [v.strip().lower() for h, v in zip(header, row, strict=False) if h not in COORDINATES]
    return bool(values) and all(v == "nan" for v in values)


def _bad_cells(path: Path) -> str:
    """The first inf, nan or empty cell of a numeric column of a CSV file, or ''.

    Not counted: the rows of grid points inside the sphere (all nan, as documented), ``-inf``
    in a level column (``*_db``: no sound at all, as the forced response reports a motion
    without impacts) and a last contact cut by the end of the run (:func:`_cut_contact`). A header
    without rows is a table of nothing, not a bad cell.
    """
    try:
        rows = list(csv.reader(path.read_text(encoding="utf-8", errors="replace").splitlines()))
    except csv.Error as exc:
        return f"{path.name}: unreadable CSV ({exc})"
    if not rows:
        return f"{path.name}: empty"
    header, data = rows[0], [r for r in rows[1:] if not _masked(rows[0], r)]
    for j, name in enumerate(header):
        cells = [r[j].strip() if j < len(r) else "" for r in data]
        if not any(_finite(c) for c in cells):
            continue  # a text column
        for i, c in enumerate(cells):
            silence = c.lower() == "-inf" and name.endswith("_db")
            if _cut_contact(header, name, i, len(cells), c):
                continue
            if not silence and not _finite(c) and (c == "" or c.lower().lstrip("+-") in ("nan", "inf", "infinity")):
                return f"{path.name}: row {i + 1} column {name!r} holds {c!r}"
    return ""


#: Columns of an impact table that its last contact, cut by the end of the run, leaves nan.
CUT_CONTACT_COLUMNS = ("separation_velocity_m_s", "restitution")


def _cut_contact(header: list, name: str, row: int, rows: int, cell: str) -> bool:
    """Not a defect: the last row of an impact table (``damper --impacts-csv``) with a contact still under
    way when the run ended has nan separation velocity and restitution, documented in ``--help`` and said
    by the run in a note."""
    return (row == rows - 1 and name in CUT_CONTACT_COLUMNS and "approach_velocity_m_s" in header
            and cell.lower() == "nan")


def _finite(cell: str) -> bool:
    try:
        return math.isfinite(float(cell))
    except ValueError:
        return False


def _bad_wav(path: Path) -> str:
    import numpy as np
    import soundfile

    try:
        data, _ = soundfile.read(str(path), always_2d=True)
    except Exception as exc:  # noqa: BLE001 - any unreadable file is the finding
        return f"{path.name}: unreadable WAV ({exc})"
    if not np.all(np.isfinite(data)):
        return f"{path.name}: not finite"
    if data.size == 0 or (not np.any(data) and not _said_silent(path)):
        return f"{path.name}: all zeros"
    return ""


def _said_silent(path: Path) -> bool:
    """Not a defect: a WAV of a run without any impact (``auralize --v0 0.5`` hits no wall within its
    duration) is silence, and says so: its sidecar (``PATH.json``) gives a peak of 0 Pa for every channel
    (and the run prints ``impacts: 0 (silence)``)."""
    try:
        peaks = json.loads(path.with_suffix(".json").read_text(encoding="utf-8"))["peak_pa"]
        return bool(peaks) and all(float(p) == 0.0 for p in peaks)
    except (OSError, ValueError, KeyError, TypeError):
        return False


def _inf_nan(folder: Path, before: dict) -> str:
    after = _hashes(folder)
    for path in sorted(folder.rglob("*")):
        rel = str(path.relative_to(folder))
        if rel not in after or before.get(rel) == after[rel]:
            continue  # not a file, or not written by the run
        bad = _bad_cells(path) if path.suffix == ".csv" else _bad_wav(path) if path.suffix == ".wav" else ""
        if bad:
            return bad
    return ""


def classify(inv: Invocation, folder: Path, before: dict) -> None:
    """Set ``inv.klass`` and ``inv.reason`` from its outcome (the first matching class wins)."""
    status, err = inv.status, inv.stderr_tail
    lines = [line for line in err.splitlines() if line.strip()]
    changed = _changed_inputs(inv, folder, before)
    checks = [
        ("hang", status is None, "time-out"),
        ("traceback", inv.traceback or "Traceback" in err, lines[-1] if lines else ""),
        ("crash", status is not None and status < 0 and not (inv.sigint_sent and status == -signal.SIGINT),
         f"signal {-status if status else 0}"),
        ("changed-input", bool(changed), ", ".join(changed)),
    ]
    for klass, hit, reason in checks:
        if hit:
            inv.klass, inv.reason = klass, reason
            return
    bad = _inf_nan(folder, before) if status in (0, 130) else ""
    if bad:
        inv.klass, inv.reason = "inf-nan", bad
        return
    inv.klass, inv.reason = _by_status(inv, folder, lines)


def _by_status(inv: Invocation, folder: Path, lines: list) -> tuple:
    status = inv.status
    if status == 2:
        return ("refused", lines[0]) if len(lines) == 1 else ("other", f"exit 2 with {len(lines)} lines on stderr")
    if status == 130:
        return ("interrupted", "") if inv.sigint_sent else ("other", "exit 130 without a SIGINT")
    if status == 1:
        return ("failed", lines[-1]) if lines else ("other", "exit 1 without a message")
    if status == 0:
        missing = [o for o in inv.outputs if not (folder / o).exists()]
        return ("worked", "") if not missing else ("other", f"exit 0 but missing {missing}")
    if status is not None and status < 0:
        return "other", f"killed by the SIGINT it was sent (signal {-status}, not exit 130)"
    return "other", f"exit {status}"


def run_one(inv: Invocation, work: Path, timeout: float) -> Invocation:
    """Run, classify and clean up one invocation."""
    folder = work / f"{inv.index:05d}_{inv.command.replace(' ', '_')}"
    before = execute(inv, folder, timeout)
    classify(inv, folder, before)
    if inv.klass not in BAD:
        shutil.rmtree(folder, ignore_errors=True)
    return inv


# ---------------------------------------------------------------- fixtures, the campaign, the report


def make_fixtures(work: Path) -> dict:
    """The valid input files the invocations start from: a WAV with its sidecar, a sweep, a scene."""
    folder = work / "fixtures"
    folder.mkdir(parents=True, exist_ok=True)
    for argv in (["auralize", "--duration", "0.3", "--wav", "in.wav"],
                 ["sweep", "--gap", "0.02,0.04", "--m", "0.02,0.06", "--duration", "2", "--workers", "1",
                  "--out", "sweep", "--quiet"]):
        if not (folder / argv[-1 if argv[0] == "auralize" else -2]).exists():
            subprocess.run([sys.executable, "-m", "acoustiviz", *argv], cwd=folder, env=_env(), check=True,
                           stdout=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
    files = {"in.wav": (folder / "in.wav").read_bytes(), "in.json": (folder / "in.json").read_bytes(),
             "scene.toml": (ROOT / "assets" / "scenes" / "fig2_waveform.toml").read_bytes()}
    for path in sorted((folder / "sweep").rglob("*")):
        if path.is_file():
            files[f"sweep/{path.relative_to(folder / 'sweep')}"] = path.read_bytes()
    return files


def campaign(seed: int, count: int, jobs: int, work: Path, timeout: float) -> list:
    """Plan and run ``count`` invocations, the commands in turn; return them in index order."""
    fixtures = make_fixtures(work)
    names = list(BASE)
    plans = [plan(seed, i, names[i % len(names)], fixtures) for i in range(count)]
    done = []
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        for inv in pool.map(lambda p: run_one(p, work, timeout), plans):
            done.append(inv)
            print(f"[#{inv.index} {len(done)}/{count}] {inv.klass:13s} {inv.duration:6.1f} s  acoustiviz "
                  f"{shlex.join(inv.argv)[:150]}", flush=True)
    return done


def report(done: list) -> str:
    """The table of class counts per command, then every invocation of a bad class."""
    commands = list(BASE)
    width = max(map(len, commands)) + 2
    lines = ["command".ljust(width) + "".join(f"{c:>15s}" for c in CLASSES) + f"{'total':>8s}"]
    for command in [*commands, "all"]:
        rows = [d for d in done if command in ("all", d.command)]
        lines.append(command.ljust(width) + "".join(f"{sum(d.klass == c for d in rows):15d}" for c in CLASSES)
                     + f"{len(rows):8d}")
    bad = [d for d in done if d.klass in BAD]
    lines += ["", f"{len(bad)} invocation(s) of a bad class ({', '.join(BAD)}):"]
    for d in bad:
        sig = f" (SIGINT after {d.sigint_after} s)" if d.sigint_sent else ""
        lines.append(f"  #{d.index} {d.klass}: acoustiviz {shlex.join(d.argv)}{sig}")
        lines.append(f"      {d.reason[:300]}{' | inputs:' + d.note if d.note else ''}")
    return "\n".join(lines)


def write_log(done: list, path: Path) -> None:
    """Every invocation, as JSON (a list of records) or CSV, chosen by the file's suffix."""
    records = []
    for d in done:
        rec = asdict(d)
        rec.pop("files")
        rec["argv"] = ["acoustiviz", *d.argv]
        rec["class"] = rec.pop("klass")
        records.append(rec)
    if path.suffix == ".csv":
        with path.open("w", newline="", encoding="utf-8") as f:
            writer = csv.DictWriter(f, fieldnames=list(records[0]) if records else ["index"])
            writer.writeheader()
            writer.writerows({k: shlex.join(v) if k == "argv" else v for k, v in r.items()} for r in records)
    else:
        path.write_text(json.dumps(records, indent=1), encoding="utf-8")


def main(argv=None) -> int:
    """Parse the options, run the campaign, print the report; exit 1 if any invocation is of a bad class."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0, help="campaign seed (default 0)")
    parser.add_argument("--count", type=int, default=300, help="number of invocations (default 300)")
    parser.add_argument("--jobs", type=int, default=1, help="invocations run at once (default 1)")
    parser.add_argument("--timeout", type=float, default=120.0, help="per-invocation time-out in s (default 120)")
    parser.add_argument("--out", type=Path, help="log of every invocation (.json or .csv)")
    parser.add_argument("--work", type=Path, help="scratch folder (default: a new temporary folder)")
    args = parser.parse_args(argv)
    if args.count < 1 or args.jobs < 1 or not args.timeout > 0:
        parser.error("--count and --jobs must be >= 1 and --timeout > 0")
    work = args.work or Path(tempfile.mkdtemp(prefix="acoustiviz-fuzz-"))
    done = campaign(args.seed, args.count, args.jobs, work, args.timeout)
    print()
    print(report(done))
    print(f"\nscratch folders of the bad invocations: {work}")
    if args.out:
        write_log(done, args.out)
    return 1 if any(d.klass in BAD for d in done) else 0


if __name__ == "__main__":
    sys.exit(main())
