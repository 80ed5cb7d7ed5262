"""Every code block of the README and of the user guide runs, so none can go stale.

What runs, by the block's info string (the word after the opening fence):

- ``bash``, ``sh``, ``shell``: each command (continuation lines joined, ``#`` comments dropped,
  ``&&`` chains split) runs in the document's scratch folder. An ``acoustiviz ...`` (or
  ``.venv/bin/acoustiviz ...``) command runs as ``python -m acoustiviz ...`` with this
  interpreter and must exit 0. The set-up commands of :data:`SETUP` (making the virtual
  environment, installing, the test suite, the documentation build, removing numba's caches)
  act on the checkout and the environment, not on the program's outputs: they are skipped,
  and any other command fails the check (label the block or add the command here).
- ``python``: the block runs with ``exec`` in a fresh namespace, in the same scratch folder.
- ``toml``: a scene file or a part of one. It must load as a scene (``av.load_scene``, every key
  validated, the rest taken from the defaults); one that asks for outputs (an ``[outputs...]``
  table) runs, ``acoustiviz run`` writing them into a folder of its own.
- ``console`` (a session shown with its output), ``text``, ``json`` (shown output) and MyST
  directives (``{image}``, ``{toctree}``, ...) are shown, not run; the ``acoustiviz`` commands
  of ``console`` blocks are parsed by ``tests/test_readme.py``. A block without an info string
  fails the check: say what it is.

The blocks of one document run in document order in one scratch folder, so a block can read a
file an earlier block wrote. The folder holds a copy of the checkout's ``assets/`` (the commands
are written to be run from the checkout). Nothing is shortened: a document whose blocks take more
than a few seconds is marked slow. ``tests/test_readme.py`` keeps the fast check that every
``acoustiviz`` command of the README and of the guide parses.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]

RUN_SHELL = {"bash", "sh", "shell"}
RUN_PYTHON = {"python"}
RUN_SCENE = {"toml"}
SHOWN = {"console", "text", "json"}

#: Commands that set up the checkout and its environment (regular expressions matched at the start
#: of a command): shown to the reader, never run by the tests.
SETUP = (
    r"python3? -m venv ",
    r"(\S*/)?pip3? install ",
    r"(\S*/)?python3? -m (pytest|sphinx)( |$)",
    r"find \S+ .*-delete$",
)

#: Documents whose blocks, run in order, take more than a few seconds of CPU.
SLOW = {"README.md", "quickstart.md", "outputs.md", "rooms.md", "scenes.md"}

#: Time-out per command in s: a hang detector only, far above any command's run time.
TIMEOUT = 900


@dataclass(frozen=True)
class Block:
    """One fenced code block: its document, first line (1-based), info string and text."""

    document: Path
    line: int
    info: str
    text: str

    @property
    def where(self) -> str:
        return f"{self.document.relative_to(ROOT)}:{self.line}"


_FENCE = re.compile(r"^( *)```([^\n`]*)\n(.*?)^\1```[ \t]*$", flags=re.S | re.M)


def blocks(document: Path) -> list[Block]:
    """The fenced code blocks of ``document`` in order (indented ones included)."""
    text = document.read_text(encoding="utf-8")
    found = []
    for m in _FENCE.finditer(text):
        indent = len(m.group(1))
        body = "\n".join(line[indent:] for line in m.group(3).splitlines())
        found.append(Block(document, text.count("\n", 0, m.start()) + 1, m.group(2).strip(), body))
    return found


def commands(block: Block) -> list[str]:
    """The commands of a shell block: continuation lines joined, comments dropped, ``&&`` split."""
    joined = re.sub(r"\s*\\\n\s*", " ", block.text)
    out = []
    for line in joined.splitlines():
        line = re.split(r"(?:^|\s)#", line, maxsplit=1)[0].strip()
        out += [part.strip() for part in line.split("&&") if part.strip()]
    return out


def is_setup(command: str) -> bool:
    """Whether ``command`` is one of the recognised set-up commands (:data:`SETUP`)."""
    return any(re.match(pattern, command) for pattern in SETUP)


def _argv(command: str) -> list[str] | None:
    """``python -m acoustiviz ...`` for an ``acoustiviz`` command, else None."""
    words = shlex.split(command)
    if words and words[0] in ("acoustiviz", ".venv/bin/acoustiviz"):
        return [sys.executable, "-m", "acoustiviz", *words[1:]]
    return None


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    env["MPLBACKEND"] = "Agg"
    return env


def _run_shell(block: Block, folder: Path) -> None:
    for command in commands(block):
        if is_setup(command):
            continue
        argv = _argv(command)
        assert argv is not None, f"{block.where}: {command!r} is neither an acoustiviz nor a set-up command"
        proc = subprocess.run(argv, cwd=folder, env=_env(), capture_output=True, text=True,
                              timeout=TIMEOUT, stdin=subprocess.DEVNULL)
        assert proc.returncode == 0, (f"{block.where}: {command!r} exited {proc.returncode}\n"
                                      f"{proc.stderr[-3000:]}")


def _run_python(block: Block, folder: Path) -> None:
    code = compile(block.text, block.where, "exec")
    old = Path.cwd()
    os.chdir(folder)
    try:
        exec(code, {"__name__": "__docs__"})  # noqa: S102 - the documentation's own example
    except Exception as exc:
        raise AssertionError(f"{block.where}: {type(exc).__name__}: {exc}") from exc
    finally:
        os.chdir(old)


def _load_scene(block: Block, folder: Path) -> Path:
    from acoustiviz import load_scene

    path = folder / f"scene_line{block.line}.toml"
    path.write_text(block.text, encoding="utf-8")
    try:
        load_scene(path)
    except Exception as exc:
        raise AssertionError(f"{block.where}: {type(exc).__name__}: {exc}") from exc
    return path


def _run_scene(block: Block, folder: Path) -> None:
    path = _load_scene(block, folder)
    if re.search(r"^\[+outputs", block.text, flags=re.M):
        proc = subprocess.run([sys.executable, "-m", "acoustiviz", "run", path.name, "--out", path.stem],
                              cwd=folder, env=_env(), capture_output=True, text=True, timeout=TIMEOUT,
                              stdin=subprocess.DEVNULL)
        assert proc.returncode == 0, f"{block.where}: acoustiviz run exited {proc.returncode}\n{proc.stderr[-3000:]}"
        assert (folder / path.stem / "summary.md").is_file(), f"{block.where}: no summary.md"


def _kind(block: Block) -> str:
    word = block.info.split()[0] if block.info else ""
    if word in RUN_SHELL:
        return "shell"
    if word in RUN_PYTHON:
        return "python"
    if word in RUN_SCENE:
        return "scene"
    if word in SHOWN or word.startswith("{"):
        return "shown"
    return "unknown"


def test_every_block_says_whether_it_runs():
    bad = [f"{b.where}: info string {b.info!r}" for doc in DOCUMENTS for b in blocks(doc) if _kind(b) == "unknown"]
    assert not bad, "label each block (bash/python to run, console/text/json/toml to show):\n" + "\n".join(bad)


def test_the_documents_have_blocks_to_run():
    kinds = [_kind(b) for doc in DOCUMENTS for b in blocks(doc)]
    assert kinds.count("shell") >= 8 and kinds.count("python") >= 4


def test_every_shell_command_is_run_or_a_recognised_setup_command():
    bad = [f"{b.where}: {c}" for doc in DOCUMENTS for b in blocks(doc) if _kind(b) == "shell"
           for c in commands(b) if not is_setup(c) and _argv(c) is None]
    assert not bad, "\n".join(bad)


def test_every_scene_block_loads(tmp_path):
    scenes = [b for doc in DOCUMENTS for b in blocks(doc) if _kind(b) == "scene"]
    assert scenes
    for block in scenes:
        _load_scene(block, tmp_path)


def test_the_setup_rule_skips_only_setup_commands():
    assert is_setup('python3 -m venv .venv')
    assert is_setup('.venv/bin/pip install --quiet ".[test]"')
    assert is_setup(".venv/bin/python -m pytest -p no:cacheprovider")
    assert is_setup(".venv/bin/python -m sphinx -W -b html docs docs/_build/html")
    assert is_setup("find acoustiviz -name '*.nb[ic]' -delete")
    assert not is_setup(".venv/bin/acoustiviz run --out acoustiviz-out")
    assert not is_setup("acoustiviz run --help-scene")


def _params():
    for doc in DOCUMENTS:
        if any(_kind(b) in ("shell", "python", "scene") for b in blocks(doc)):
            marks = [pytest.mark.slow] if doc.name in SLOW else []
            yield pytest.param(doc, id=doc.name, marks=marks)


@pytest.mark.parametrize("document", list(_params()))
def test_every_block_runs(document, tmp_path):
    shutil.copytree(ROOT / "assets", tmp_path / "assets")
    for block in blocks(document):
        kind = _kind(block)
        if kind == "shell":
            _run_shell(block, tmp_path)
        elif kind == "python":
            _run_python(block, tmp_path)
        elif kind == "scene":
            _run_scene(block, tmp_path)


def test_every_fence_opens_or_closes_a_block():
    for doc in DOCUMENTS:
        fences = len(re.findall(r"^ *```", doc.read_text(encoding="utf-8"), flags=re.M))
        assert fences == 2 * len(blocks(doc)), f"{doc.name}: a fence opens no block the runner sees"


def test_commands_join_lines_drop_comments_and_split_chains():
    text = ("# a comment\nacoustiviz waveform --radius 0.01 \\\n    --csv a.csv   # trailing comment\n\n"
            "python3 -m venv .venv && .venv/bin/acoustiviz run --out o\n")
    block = Block(ROOT / "README.md", 1, "bash", text)
    assert commands(block) == ["acoustiviz waveform --radius 0.01 --csv a.csv", "python3 -m venv .venv",
                               ".venv/bin/acoustiviz run --out o"]
    assert _argv(commands(block)[2]) == [sys.executable, "-m", "acoustiviz", "run", "--out", "o"]
    assert _argv("ls -l") is None
