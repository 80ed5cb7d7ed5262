"""The ``acoustiviz`` command.

Each subcommand lives in its own module of this package and provides two
functions: ``add_parser(subparsers)`` and ``run(args) -> int``. Modules are light
at import (heavy imports happen inside ``run``) so that ``acoustiviz --help``
answers at once. Any :class:`acoustiviz._validate.ParameterError` raised while a
subcommand runs becomes a one-line message on stderr and exit status 2; so does a file that
cannot be written or read (an :class:`OSError`, named by its file) and memory running out.

Every command takes ``--force``, also spelled ``--replace`` (the one spelling on ``forced`` and
``sweep``, whose ``--force`` is the force amplitude): without it an existing output file, named or
derived, is refused before any work (:mod:`acoustiviz.app.outputs`).

Every command takes ``--max-memory MB``: it estimates the memory and the output size of its work
before starting (:mod:`acoustiviz.app.budget`) and refuses work over the cap (default
:data:`acoustiviz.constants.MAX_MEMORY_MB`, 2048 MB), naming the option to change; a scene's run
keeps under both the cap and the scene's own ``grids.memory_limit_mb`` (:func:`~acoustiviz.app.budget.outer_cap`).

A Ctrl-C at any moment, the imports included, ends a command with one line and exit status 130.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import sys

from .._validate import ParameterError
from ..constants import MAX_MEMORY_MB

#: subcommand name -> module implementing it (in the order shown by --help)
SUBCOMMANDS = {
    "run": "acoustiviz.cli.run",
    "waveform": "acoustiviz.cli.waveform",
    "directivity": "acoustiviz.cli.directivity",
    "map": "acoustiviz.cli.map",
    "damper": "acoustiviz.cli.damper",
    "forced": "acoustiviz.cli.forced",
    "sweep": "acoustiviz.cli.sweep",
    "design": "acoustiviz.cli.design",
    "optimize": "acoustiviz.cli.optimize",
    "render": "acoustiviz.cli.render",
    "auralize": "acoustiviz.cli.auralize",
    "levels": "acoustiviz.cli.levels",
}


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line and exit status 2."""

    def error(self, message):  # noqa: D102
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """Build the argument parser with every available subcommand."""
    parser = _Parser(
        prog="acoustiviz",
        description="See and hear the noise of impact dampers. SI units unless an option says otherwise.",
        epilog=f"Every command estimates its memory and output size before starting and refuses work over "
               f"{MAX_MEMORY_MB:g} MB (change the cap with --max-memory MB). Bad input: one line naming the "
               "option, exit status 2. An existing output file, or one written beside it, is replaced only with "
               "--force or --replace (only --replace on forced, sweep and optimize, whose --force is the force "
               "amplitude).",
    )
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"acoustiviz {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for modname in SUBCOMMANDS.values():
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:  # a subcommand not shipped in this build
            if exc.name == modname:
                continue
            raise
        mod.add_parser(sub)
    from ..app.outputs import REPLACE
    from ..app.settings.run import MAX_MEMORY
    from ..app.settings.table import add_option

    for leaf in _leaf_parsers(sub):
        # --force and --replace on every command; --replace alone where --force is an amplitude
        record = REPLACE if REPLACE.option not in leaf._option_string_actions else \
            dataclasses.replace(REPLACE, option=REPLACE.aliases[0], aliases=())
        add_option(leaf, record, dest=REPLACE.name)
        leaf.set_defaults(replace_option=record.option)
        add_option(leaf, MAX_MEMORY)
    return parser


def _leaf_parsers(subparsers_action):
    """The parsers of a subparsers action that run a command (nested views included)."""
    for p in dict.fromkeys(subparsers_action.choices.values()):
        nested = [a for a in p._actions if isinstance(a, argparse._SubParsersAction)]
        if nested:
            for a in nested:
                yield from _leaf_parsers(a)
        else:
            yield p


def main(argv=None) -> int:
    """Entry point of the ``acoustiviz`` console script; returns the exit status.

    Called without ``argv`` (as the console script and ``python -m acoustiviz`` call it, the
    process then ending), the objects alive when it returns are frozen out of the garbage
    collector (:func:`gc.freeze`): the interpreter's exit then skips traversing them again in
    its final collections (figures: ``benchmarks/results/design_timings.md``). Every output file is closed
    by then and exit handlers still run.

    A Ctrl-C at any moment, the imports of the command included, ends it with one line and exit
    status 130 (:func:`interrupted`).
    """
    if argv is None:
        try:
            return _main(sys.argv[1:], standalone=True)
        finally:
            import gc

            gc.freeze()
    return _main(list(argv))


def command_of(argv) -> str:
    """The subcommand named in ``argv`` (its first word that is one), or ``""``."""
    return next((str(tok) for tok in argv if str(tok) in SUBCOMMANDS), "")


def interrupted(command: str, standalone: bool) -> int:
    """Say that ``command`` was interrupted; return its exit status, 130.

    When the process ends here (``standalone``) a second Ctrl-C is ignored from now on, so that it
    cannot turn the message into a traceback, and the interpreter's record of an unhandled
    Ctrl-C is cleared: a Ctrl-C that landed in code the interpreter runs from C (an extension
    module's initialisation) leaves that record set, and ``python -m`` would then end the process
    by the signal itself instead of with status 130 (:func:`_forget_unhandled_interrupt`).
    """
    if standalone:
        import signal

        signal.signal(signal.SIGINT, signal.SIG_IGN)
        _forget_unhandled_interrupt()
    name = f"acoustiviz {command}" if command else "acoustiviz"
    print(f"{name}: interrupted; finished outputs were kept", file=sys.stderr)
    return 130


def _forget_unhandled_interrupt() -> None:
    """Clear CPython's flag of a KeyboardInterrupt left unhandled by code run from C.

    CPython sets it when a KeyboardInterrupt leaves code run by ``PyRun_String`` (as some
    extension modules run at import) and, at the end of ``python -m``, kills its own process by
    SIGINT when it is set, whatever the exit status asked for. Running an empty string the same
    way clears it.
    """
    try:
        import ctypes

        ctypes.pythonapi.PyRun_SimpleString(b"")
    except (ImportError, AttributeError, OSError):  # another interpreter: no such flag
        pass


def _unraisable_interrupts(previous, swallowed: list):
    """A :data:`sys.unraisablehook` that delivers a Ctrl-C swallowed by a finaliser again.

    A KeyboardInterrupt raised inside a ``__del__``, a weak-reference callback or a garbage
    collection cannot propagate (Python prints "Exception ignored in ..." and carries on): it is
    noted in ``swallowed`` (the command then ends interrupted, whatever it returns) and raised again
    in the main thread, so that work still going on stops.
    """
    import _thread

    def hook(unraisable):
        if not isinstance(unraisable.exc_value, KeyboardInterrupt):
            previous(unraisable)
            return
        swallowed.append(unraisable.exc_value)
        # from another thread, as a signal arriving: that thread runs once the main thread lets go of the
        # interpreter, after this hook has returned (tripped here, it would interrupt this hook instead)
        _thread.start_new_thread(_thread.interrupt_main, ())

    return hook


def _main(argv: list, standalone: bool = False) -> int:
    swallowed = []
    if standalone:
        sys.unraisablehook = _unraisable_interrupts(sys.unraisablehook, swallowed)
    try:
        status = _command(argv, standalone)
    except KeyboardInterrupt:
        return interrupted(command_of(argv), standalone)
    except Exception as exc:
        if _raised_by_interrupt(exc):
            return interrupted(command_of(argv), standalone)
        raise
    return interrupted(command_of(argv), standalone) if swallowed else status


def _raised_by_interrupt(exc: BaseException) -> bool:
    """True when a KeyboardInterrupt caused ``exc``.

    Python wraps some exceptions raised while it builds a class (a Ctrl-C landing in a dataclass
    field's ``__set_name__`` becomes a ``RuntimeError``), so a Ctrl-C during the imports can
    arrive as another exception whose cause is the interrupt.
    """
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _command(argv: list, standalone: bool) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    # the options typed (not defaulted): errors about work too large name one of these first
    args.given_options = frozenset(str(tok).split("=", 1)[0] for tok in argv if str(tok).startswith("--"))
    if not getattr(args, "command", None):
        parser.print_help()
        return 2
    import warnings

    def one_line(message, category, filename, lineno, file=None, line=None):
        # a warning from the computation is one line naming the command, not a source listing
        text = " ".join(str(message).split())
        print(f"acoustiviz {args.command}: warning: {text}", file=sys.stderr if file is None else file)

    try:
        with warnings.catch_warnings():
            warnings.showwarning = one_line
            from ..app.budget import outer_cap
            from ..app.outputs import replacing

            # --max-memory bounds every budget check of the command, a scene's too; a cap that is not
            # a positive number of MB is refused here, before any work
            with replacing(getattr(args, "replace", False), getattr(args, "replace_option", "--force")), \
                    outer_cap(getattr(args, "max_memory", None)):
                return int(args.func(args) or 0)
    except ParameterError as exc:
        print(f"acoustiviz {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into a reader that stopped early (e.g. `| head`)
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except OSError as exc:  # a file that could not be written or read, named by the writer
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"acoustiviz {args.command}: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"acoustiviz {args.command}: error: out of memory; ask for less work or lower --max-memory "
              "so that it is refused before it starts", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
