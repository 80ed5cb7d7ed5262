"""Sphinx extension: the command-line reference, generated from the argparse parsers.

``.. acoustiviz-cli::`` builds the parser of the ``acoustiviz`` command
(:func:`acoustiviz.cli.build_parser`) and writes one section per subcommand (and per view of a
subcommand such as ``render balloon``): its description, its usage line, and its options group
by group with their metavariables, defaults and help. An option added to a parser appears here
without an edit.
"""

from __future__ import annotations

import argparse
import re

_SPECIAL = re.compile(r"([\\`*_|\[\]<>])")


def escape(text: str) -> str:
    """Text safe inside a reST paragraph (markup characters escaped)."""
    return _SPECIAL.sub(r"\\\1", " ".join(str(text).split()))


def _help(parser, action) -> str:
    if action.help is None or action.help == argparse.SUPPRESS:
        return ""
    fmt = parser._get_formatter()  # argparse's own expansion of %(default)s and friends
    return fmt._expand_help(action)


def _invocation(action) -> str:
    if not action.option_strings:
        return action.metavar or action.dest
    if action.nargs == 0:
        return ", ".join(action.option_strings)
    meta = action.metavar or (("{" + ",".join(map(str, action.choices)) + "}") if action.choices
                              else action.dest.upper())
    if isinstance(meta, tuple):
        meta = " ".join(meta)
    if action.nargs in ("+", "*"):
        meta = f"{meta} [{meta} ...]"
    return ", ".join(f"{o} {meta}" for o in action.option_strings)


def _subparsers(parser):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: a.help for a in action._choices_actions}
            for name, sub in action.choices.items():
                yield name, sub, helps.get(name, "")


def _section(parser, title: str, summary: str, level: int, anchor: str) -> list:
    chars = "=-~^"
    lines = [f".. _cli-{anchor}:", "", title, chars[level] * len(title), ""]
    text = parser.description or summary
    if text:
        lines += [escape(text), ""]
    fmt = argparse.HelpFormatter(prog=parser.prog, width=90)
    fmt.add_usage(parser.usage, parser._actions, parser._mutually_exclusive_groups, prefix="")
    usage = [ln for ln in fmt.format_help().splitlines() if ln.strip()]
    lines += [".. code-block:: text", ""] + ["   " + ln for ln in usage] + [""]
    for group in parser._action_groups:
        actions = [a for a in group._group_actions
                   if not isinstance(a, (argparse._HelpAction, argparse._SubParsersAction))
                   and a.help != argparse.SUPPRESS]
        if not actions:
            continue
        name = group.title or "options"
        lines += [f".. rubric:: {escape(name)}", "", ".. container:: cli-options", ""]
        for a in actions:
            lines += [f"   ``{_invocation(a)}``", f"      {escape(_help(parser, a)) or '(no help)'}"]
            if a.required:
                lines[-1] += " *Required.*"
            lines.append("")
    for name, sub, helptext in _subparsers(parser):
        lines += _section(sub, f"{title} {name}", helptext, min(level + 1, 3), f"{anchor}-{name}")
    return lines


def reference_lines(parser=None) -> list:
    """The reST lines of the whole reference: one section per subcommand of ``parser`` (default: acoustiviz's)."""
    if parser is None:
        from acoustiviz.cli import build_parser

        parser = build_parser()
    lines = []
    for name, sub, helptext in _subparsers(parser):
        lines += _section(sub, f"acoustiviz {name}", helptext, 0, name)
    return lines


def scene_reference_lines() -> list:
    """The reST lines of the scene-file reference: every key with its type, range, unit and default.

    The text is :func:`acoustiviz.scene.schema_help` (``acoustiviz run --help-scene``), built from
    the same records as the options above (:mod:`acoustiviz.app.settings`).
    """
    from acoustiviz.scene import schema_help

    title = "Scene files (acoustiviz run)"
    return ([".. _cli-scene-keys:", "", title, "=" * len(title), "",
             escape("Every key of a scene file, as 'acoustiviz run --help-scene' prints it: its type, allowed "
                    "range and unit, default and meaning. A setting that is also an option takes the same range "
                    "and default from the same record."), "", ".. code-block:: text", ""]
            + ["   " + ln for ln in schema_help().splitlines()] + [""])


def setup(app):
    """Register the ``acoustiviz-cli`` directive."""
    from docutils import nodes
    from docutils.statemachine import StringList
    from sphinx.util.docutils import SphinxDirective
    from sphinx.util.nodes import nested_parse_with_titles

    class CliDirective(SphinxDirective):
        """``.. acoustiviz-cli::`` -- every subcommand of the command line with its options, then the scene keys."""

        has_content = False

        def run(self):
            container = nodes.section()
            container.document = self.state.document
            lines = reference_lines() + scene_reference_lines()
            nested_parse_with_titles(self.state, StringList(lines, source="acoustiviz.cli"), container)
            return container.children

    app.add_directive("acoustiviz-cli", CliDirective)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
