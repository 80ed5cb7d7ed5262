"""The README's commands are the program's: every ``acoustiviz ...`` line of its code blocks parses.

The user guide's commands (``docs/guide/*.md``) are held to the same check. ``tests/test_docs_run.py``
runs every block of both (marked slow where it takes more than a few seconds).

Running them all would take minutes (the quoted figures they print are rerun by
``docs/check_numbers.py``); parsing each with the program's own parser catches what goes stale
first: a renamed command or option, or a value outside an option's choices.
"""

from __future__ import annotations

import contextlib
import io
import re
import shlex
from pathlib import Path

import pytest

from acoustiviz.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GUIDE = sorted((ROOT / "docs" / "guide").glob("*.md"))


def _commands(document: Path = README) -> list[str]:
    """Every ``acoustiviz`` command line of a document's code blocks, continuation lines joined."""
    text = document.read_text(encoding="utf-8")
    lines = []
    for block in re.findall(r"```(?:bash|console|sh)?\n(.*?)```", text, flags=re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = line.strip().removeprefix("$ ")
            if line.startswith("acoustiviz "):
                lines.append(line.split("  #")[0].split(" # ")[0].strip())
    return lines


def test_the_readme_has_commands_to_check():
    cmds = _commands()
    assert len(cmds) >= 15
    assert any(c.startswith("acoustiviz auralize --room") for c in cmds)


@pytest.mark.parametrize("command", _commands())
def test_every_readme_command_parses(command):
    _check_parses(command)


@pytest.mark.parametrize("command", [pytest.param(c, id=f"{doc.name}:{c[:60]}") for doc in GUIDE
                                     for c in _commands(doc)])
def test_every_guide_command_parses(command):
    _check_parses(command)


def _check_parses(command):
    parser = build_parser()
    argv = shlex.split(command)[1:]
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            args = parser.parse_args(argv)
    except SystemExit as exc:  # --help-scene and --version exit 0 after printing; errors exit 2
        assert exc.code in (0, None), f"{command!r}: {err.getvalue().strip()}"
        return
    assert getattr(args, "command", None) == argv[0]
