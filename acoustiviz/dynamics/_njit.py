"""How the impact-damper kernels are compiled (numba): entry kernels and inner helpers.

``@kernel`` marks what Python calls (the drivers); ``@helper`` what only other kernels call.
numba builds, for every compiled function, a CPython entry point (argument unboxing, error
return) and a C entry point: for a helper both are dead code that is lowered, optimised and
turned into machine code for nothing, about a third of a small helper's compile time. A helper
called from Python raises ``TypeError``. Both are cached on disk (``cache=True``) and use
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
"""

from __future__ import annotations

from numba import njit

__all__ = ["kernel", "helper"]

#: Kernels called from Python.
kernel = njit(cache=True, error_model="numpy")

#: Functions called only from other kernels: no CPython or C entry point.
helper = njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, error_model="numpy")
