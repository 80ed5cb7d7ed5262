"""Compiling a numba kernel before it runs: the wait is said once, and its time kept apart.

numba compiles a kernel on its first call with new argument types and keeps the machine code in
its on-disk cache (``cache=True``), so a first run on an installation pays the compilation and later
runs load it in milliseconds. :func:`compile_for` compiles (or loads) a kernel for the types of
given arguments without running it, returning the seconds that took, so that run times report the
kernel alone; when the kernel is not in the cache and its compilation is known to be long, it first
prints one line to stderr saying so, where someone is watching (stderr a terminal): in a log or a
pipe the line would only add to what a program reading stderr has to parse, and whether it came
would depend on the state of the cache.

Imports numba only when called.
"""

from __future__ import annotations

import sys
import time

__all__ = ["compile_for", "in_cache", "announce_long_work"]

#: kernels whose "compiling ..." line was printed in this process
_ANNOUNCED: set[str] = set()


def _signature(args) -> tuple:
    from numba import typeof

    return tuple(typeof(a) for a in args)


def in_cache(dispatcher, args) -> bool:
    """True if ``dispatcher`` is compiled, or in numba's disk cache, for the types of ``args``.

    Reads the cache index the way numba does on a call (its key: signature, CPU and the bytecode of
    the function); any failure to read it counts as not cached.
    """
    sig = _signature(args)
    if dispatcher.overloads.get(sig) is not None:
        return True
    try:
        cache = dispatcher._cache
        key = cache._index_key(sig, dispatcher.targetctx.codegen())
        return key in cache._cache_file._load_index()
    except Exception:  # noqa: BLE001 - a private numba API: any change means "not known to be cached"
        return False


def _watched() -> bool:
    """True when stderr is a terminal."""
    try:
        return bool(sys.stderr is not None and sys.stderr.isatty())
    except (AttributeError, ValueError):  # replaced or closed stream
        return False


def compile_for(dispatcher, args, name: str | None = None, seconds: float = 0.0,
                announce: bool | None = None) -> float:
    """Compile ``dispatcher`` for the types of ``args`` (or load it from the cache); return the wall s.

    Parameters
    ----------
    dispatcher : numba dispatcher
        The kernel (an ``@njit`` function).
    args : sequence
        Arguments of the coming call; only their numba types are used, the kernel is not run.
    name : str, optional
        What the kernels are called for the user (``"event solver"``). With ``seconds`` above 2 s
        and the kernel not cached, one line is printed to stderr first (once per process):
        ``compiling the <name> kernels (once per installation, about N s)``.
    seconds : float, optional
        The typical compile time in s (CPU, ``benchmarks/bench_startup.py``) quoted in that line.
    announce : bool, optional
        Whether that line may be printed; default: when stderr is a terminal.
    """
    if not hasattr(dispatcher, "overloads"):  # numba's NUMBA_DISABLE_JIT: a plain function, nothing to compile
        return 0.0
    sig = _signature(args)
    if dispatcher.overloads.get(sig) is not None:
        return 0.0
    if announce is None:
        announce = _watched()
    if announce and name and seconds > 2.0 and name not in _ANNOUNCED and not in_cache(dispatcher, args):
        _ANNOUNCED.add(name)
        print(f"compiling the {name} kernels (once per installation, about {seconds:.0f} s)",
              file=sys.stderr, flush=True)
    t0 = time.perf_counter()
    dispatcher.compile(sig)
    return time.perf_counter() - t0


def announce_long_work(line: str) -> None:
    """Print ``line`` to stderr at once: a long computation, judged by its size, is about to start.

    Said whether or not stderr is a terminal: it depends on the work asked for alone (not on
    a cache or the machine), and it is what a person or a program watching stderr sees before
    minutes of compiled code, which Ctrl-C can stop (the kernels run in batches).
    """
    print(line, file=sys.stderr, flush=True)
