"""Compiling a numba kernel before it runs: the wait is said once, and its time kept apart.

numba compiles a kernel on its first call with new argument types and keeps the machine code in
its on-disk cache (``cache=True``), so a first run on an installation pays the compilation and later
runs load it in milliseconds. :func:`compile_for` compiles (or loads) a kernel for the types of
given arguments without running it, returning the seconds that took, so that run times report the
kernel alone; when the kernel is not in the cache and its compilation is known to be long, it first
prints one line to stderr saying so, where someone is watching (stderr a terminal): in a log or a
pipe the line would only add to what a program reading stderr has to parse, and whether it came
would depend on the state of the cache.

It is also the package's one numba policy: every compiled function is made by :func:`njit`
(:data:`JIT_OPTIONS`, the options all share), :func:`kernel` or :func:`helper` (the impact
damper's entry kernels and inner helpers).

``@kernel`` marks what Python calls (the drivers); ``@helper`` what only other kernels call.
numba builds, for every compiled function, a CPython entry point (argument unboxing, error
return) and a C entry point: for a helper both are dead code that is lowered, optimised and
turned into machine code for nothing. A helper called from Python raises ``TypeError``. Both use
numpy's error model: a float division by zero gives ±inf or nan as in numpy instead of a branch
to a ``ZeroDivisionError`` after every division (code to compile for nothing: the solvers divide
only by quantities they have checked or bounded away from zero; the results are the same IEEE
operations, bit for bit).

A helper is compiled once per distinct argument types: a constant integer argument is typed as
its literal value (``Literal[int](12)``), one more compilation per constant, so call sites pass
``np.int64(k)``.

``inline="always"`` (numba inlining, each call site typed and lowered again) is kept for the
pieces of one caller, where it spares the callee a module of its own: every module that links a
compiled callee optimises and compiles that callee's code again (numba links callees as LLVM IR).

Imports numba only when called.
"""

from __future__ import annotations

import sys
import time

__all__ = ["JIT_OPTIONS", "njit", "kernel", "helper", "compile_for", "in_cache", "announce_long_work"]

#: Options every compiled function of the package shares: its machine code cached on disk beside
#: its source, so only the first run on an installation compiles it. A caller's option overrides.
JIT_OPTIONS = {"cache": True}
#: Options of the impact damper's kernels and helpers on top of :data:`JIT_OPTIONS` (module notes).
_DAMPER_OPTIONS = {"error_model": "numpy"}

def njit(*args, **options):
    """``numba.njit`` with :data:`JIT_OPTIONS` and ``options``; without numba, the plain function.

    Used as ``@njit`` or ``@njit(inline="always")``.
    """
    try:
        from numba import njit as numba_njit
    except ImportError:  # pragma: no cover - numba is a hard dependency in practice
        return args[0] if args and callable(args[0]) else (lambda f: f)
    return numba_njit(*args, **{**JIT_OPTIONS, **options})


def kernel(func):
    """Compile ``func``, an impact-damper kernel called from Python (module notes)."""
    return njit(**_DAMPER_OPTIONS)(func)


def helper(func):
    """Compile ``func``, called only from other kernels: no CPython or C entry point (module notes)."""
    return njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, **_DAMPER_OPTIONS)(func)


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
