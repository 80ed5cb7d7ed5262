"""Running a sweep: on a local process pool, on any :class:`concurrent.futures.Executor`, or on Dask.

:func:`run_sweep` computes the designs a directory still lacks and journals each as it finishes
(:mod:`acoustiviz.sweep.store`). A design whose evaluation fails -- an exception in the worker,
an overflow, or a worker process that dies (``BrokenProcessPool``) -- becomes a failed row with
its reason, and the sweep goes on.

Interrupts are deterministic: while a sweep runs, Ctrl-C (SIGINT) raises ``KeyboardInterrupt``
in the calling process even if it inherited SIGINT ignored, and the workers of the local pool
ignore SIGINT (it is blocked while they are forked, then set to ignored), so only the parent
stops, keeping every finished row.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import threading
from concurrent.futures import FIRST_COMPLETED, Executor, wait
from pathlib import Path

from ..errors import ParameterError
from .evaluate import evaluate_or_fail, failed_result, warm_up
from .progress import Progress
from .spec import FixedSettings, SweepSpec
from .store import (
    SWEEP_CSV,
    Journal,
    SweepTable,
    prepare_dir,
    put_in_design_order,
    read_rows,
    sweep_columns,
    table_from_rows,
)

__all__ = ["run_sweep", "make_executor", "check_executor_form", "dask_address", "dask_executor", "local_pool",
           "shutdown_now", "DASK_FORM"]


def _worker_init(initializer, initargs) -> None:
    """Process-pool initializer: leave Ctrl-C to the parent, then run ``initializer(*initargs)``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    if initializer is not None:
        initializer(*initargs)


@contextlib.contextmanager
def _sigint_blocked():
    """Hold SIGINT pending (not lost) while worker processes are forked, so none inherits a handler."""
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


@contextlib.contextmanager
def _interruptible():
    """Make SIGINT raise KeyboardInterrupt here, whatever disposition the process inherited.

    A process started with SIGINT ignored (a background job of a non-interactive shell) would
    otherwise run the whole sweep through a Ctrl-C. A handler the application installed itself
    is left alone. Restored on exit; only possible in the main thread.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.getsignal(signal.SIGINT)
    replace = old in (signal.SIG_IGN, signal.SIG_DFL, None)
    if replace:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        if replace:
            signal.signal(signal.SIGINT, old)


def local_pool(n: int, initializer=None, initargs=()):
    """A local process pool of ``n`` workers that leave Ctrl-C to the parent.

    The workers ignore SIGINT (it is held pending while they are forked, then set to ignored
    before ``initializer(*initargs)`` runs), so a Ctrl-C at the terminal, which reaches every
    process of the foreground group, stops the parent alone; :func:`shutdown_now` then stops
    the workers. The workers are forked at once, not at the first submission.
    """
    from concurrent.futures import ProcessPoolExecutor

    ex = ProcessPoolExecutor(max_workers=int(n), initializer=_worker_init, initargs=(initializer, initargs))
    with _sigint_blocked():  # the first submission forks the workers (every one of them with "fork")
        ex.submit(int)
    return ex


#: Seconds :func:`shutdown_now` lets a process pool's manager thread drop the cancelled tasks
#: before the workers are stopped (it does so at once when woken; a hang detector only).
_CANCEL_WAIT_S = 5.0


def shutdown_now(ex: Executor) -> None:
    """Shut ``ex`` down without waiting: cancel what has not started and stop a local pool's workers.

    A process pool's running tasks are compiled code that a signal cannot stop, and the
    interpreter's exit would wait for them: its worker processes are terminated, after its
    manager thread has dropped the cancelled tasks (a pool broken with cancelled tasks still
    pending fails them again, ``InvalidStateError``, and its manager thread dies without
    cleaning up, which hangs the exit).
    """
    with _sigint_blocked():  # a second Ctrl-C waits until the workers are stopped
        _shutdown_now(ex)


def _shutdown_now(ex: Executor) -> None:
    procs = list((getattr(ex, "_processes", None) or {}).values())
    try:
        ex.shutdown(wait=False, cancel_futures=True)
    except TypeError:  # executors without cancel_futures (e.g. Dask's ClientExecutor)
        ex.shutdown(wait=False)
    if not procs:
        return
    import time

    manager = getattr(ex, "_executor_manager_thread", None)
    deadline = time.monotonic() + _CANCEL_WAIT_S
    while (getattr(ex, "_cancel_pending_futures", False) and manager is not None and manager.is_alive()
           and time.monotonic() < deadline):
        time.sleep(0.005)
    for p in procs:
        with contextlib.suppress(OSError, ValueError):  # already gone
            p.terminate()
    for p in procs:
        p.join(_CANCEL_WAIT_S)
    if manager is not None:
        manager.join(_CANCEL_WAIT_S)


def make_executor(executor, workers, settings: FixedSettings, n_tasks: int):
    """Return ``(executor, kind, cleanup, n)``; kind is ``"local"``, ``"given"`` or ``"dask"``.

    A local pool has ``n`` processes, at most ``n_tasks``; it and a Dask client are owned (shut
    down by the caller, then ``cleanup`` called); a given Executor is used as is. ``n`` is None
    except for a local pool.
    """
    if isinstance(executor, Executor):
        return executor, "given", None, None
    if executor is None or executor == "process":
        n = (os.cpu_count() or 1) if workers is None else int(workers)
        if n < 1:
            raise ParameterError("workers", f"must be >= 1, got {workers}")
        warm_up(settings)  # forked workers inherit the loaded kernels
        n = max(1, min(n, int(n_tasks)))
        return _local_pool(n, settings), "local", None, n
    if isinstance(executor, str) and executor.startswith("dask://"):
        ex, close = dask_executor(executor)
        return ex, "dask", close, None
    raise ParameterError("executor", f"expected 'process', {DASK_FORM} or an Executor, got {executor!r}")


#: The form of a Dask scheduler's address, as error messages state it.
DASK_FORM = "dask://HOST:PORT (PORT an integer in 1..65535; an IPv6 HOST in brackets, dask://[::1]:8786)"
_DASK_ADDRESS = re.compile(r"(?:(?P<scheme>[a-z][a-z0-9+.-]*)://)?"
                           r"(?P<host>\[[0-9A-Fa-f:.]*:[0-9A-Fa-f:.]*\]|[A-Za-z0-9_.-]+):(?P<port>[0-9]{1,5})")


def dask_address(url) -> str:
    """The scheduler address (``tcp://HOST:PORT``) of ``dask://HOST:PORT``, checked without connecting.

    ``dask://SCHEME://HOST:PORT`` keeps its scheme (``tls``, ...). One home of the form of an
    executor address, for the settings checks (before any file is written) and the connection.

    Raises
    ------
    ParameterError
        Named ``executor``, stating the allowed form, for anything else (a port that is not an
        integer in 1..65535, a missing host, unbalanced IPv6 brackets, ...).
    """
    text = url if isinstance(url, str) else ""
    m = _DASK_ADDRESS.fullmatch(text[len("dask://"):]) if text.startswith("dask://") else None
    if m is None or not 1 <= int(m["port"]) <= 65535:
        raise ParameterError("executor", f"expected {DASK_FORM}, got {url!r}")
    return f"{m['scheme'] or 'tcp'}://{m['host']}:{int(m['port'])}"


def check_executor_form(executor) -> None:
    """Refuse, naming ``executor``, what is not None, ``"process"``, an Executor or ``dask://HOST:PORT``.

    A Dask address is checked by :func:`dask_address`, without connecting.
    """
    if executor is None or executor == "process" or isinstance(executor, Executor):
        return
    if isinstance(executor, str) and executor.startswith("dask://"):
        dask_address(executor)
        return
    raise ParameterError("executor", f"expected 'process' or {DASK_FORM}, got {executor!r}")


def dask_executor(url: str):
    """An Executor on the Dask scheduler at ``dask://HOST:PORT`` and the function that closes its client.

    One home for the Dask connection of every parallel front-end (sweeps, frequency responses).

    Raises
    ------
    ParameterError
        Named ``executor``: a malformed address (:func:`dask_address`), the ``distributed``
        extra missing, or a scheduler that cannot be reached.
    """
    address = dask_address(url)
    try:
        from distributed import Client
    except ImportError:
        raise ParameterError(
            "executor", "dask:// needs the optional dependency: pip install 'acoustiviz[distributed]'") from None
    try:
        client = Client(address, timeout=20)
    except (OSError, ValueError) as exc:
        raise ParameterError("executor", f"cannot reach the Dask scheduler at {address}: {exc}") from None
    return client.get_executor(), client.close


def _local_pool(n: int, settings: FixedSettings):
    """A local pool whose workers load the compiled kernels of ``settings`` once."""
    return local_pool(n, warm_up, (settings,))


def _is_broken_pool(exc: BaseException) -> bool:
    from concurrent.futures.process import BrokenProcessPool

    return isinstance(exc, BrokenProcessPool)


class _Runner:
    """Submit designs to an executor and yield their results, failed designs included."""

    def __init__(self, executor, workers, settings: FixedSettings, n_tasks: int):
        self.settings = settings
        self.ex, self.kind, self.cleanup, self.n = make_executor(executor, workers, settings, n_tasks)

    def _submit(self, design):
        if self.kind != "local":
            return self.ex.submit(evaluate_or_fail, design, self.settings)
        with _sigint_blocked():  # the first submission forks the workers
            return self.ex.submit(evaluate_or_fail, design, self.settings)

    def _failed(self, design, exc):
        if _is_broken_pool(exc):
            why = f"the worker process died ({type(exc).__name__}: {exc})"
        else:
            why = f"{type(exc).__name__}: {exc}"
        return failed_result(design, self.settings, why)

    def results(self, designs):
        """Yield one DesignResult per design, in order of completion."""
        queue = list(designs)[::-1]
        limit = len(queue) if self.n is None else 2 * self.n
        running = {}
        try:
            while queue or running:
                suspects, broken = [], False
                while queue and len(running) < limit:
                    try:
                        fut = self._submit(queue[-1])
                    except Exception as exc:  # a pool found broken at submission: the design waits for a new one
                        if self.kind != "local" or not _is_broken_pool(exc):
                            raise
                        broken = True
                        break
                    running[fut] = queue.pop()
                if not broken:
                    done, _ = wait(running, return_when=FIRST_COMPLETED)
                    for fut in [f for f in running if f in done]:  # in submission order, not a set's
                        d = running.pop(fut)
                        res, dead = self._outcome(fut, d)
                        if dead:
                            suspects.append(d)
                            broken = True
                        else:
                            yield res
                if broken:  # every design the dead pool held is suspect; finished ones are kept
                    wait(running, timeout=60)  # a broken pool fails each pending future at once
                    for fut, d in running.items():
                        res, dead = self._outcome(fut, d) if fut.done() else (None, True)
                        if dead:
                            suspects.append(d)
                        else:
                            yield res
                    running.clear()
                    shutdown_now(self.ex)
                    yield from self._isolate(sorted(suspects, key=lambda d: d.design_id))
                    self.ex = _local_pool(self.n, self.settings)
        finally:
            for fut in running:  # interrupted: what has not started never will
                fut.cancel()

    def _outcome(self, fut, design):
        """``(result, dead)``: the design's result, a failed row for its exception, or ``dead``.

        ``dead`` when the local pool broke under it; a caller's broken pool cannot be replaced, so
        it stops the sweep.
        """
        try:
            return fut.result(), False
        except Exception as exc:  # noqa: BLE001 - recorded in the design's row
            if _is_broken_pool(exc):
                if self.kind != "local":
                    raise
                return None, True
            return self._failed(design, exc), False

    def _isolate(self, suspects):
        """Run each design of a broken pool alone in a fresh one-process pool: only the culprit fails."""
        for d in suspects:
            ex = _local_pool(1, self.settings)
            try:
                with _sigint_blocked():
                    fut = ex.submit(evaluate_or_fail, d, self.settings)
                try:
                    res = fut.result()
                except Exception as exc:  # noqa: BLE001
                    res = self._failed(d, exc)
                yield res
            finally:
                shutdown_now(ex)

    def close(self, *, interrupted: bool) -> None:
        """Shut down what this runner owns (at once when interrupted)."""
        if self.kind != "given":
            if interrupted:
                shutdown_now(self.ex)
            else:
                self.ex.shutdown(wait=True)
        if self.cleanup is not None:
            self.cleanup()


def run_sweep(spec: SweepSpec, out_dir, *, executor=None, workers: int | None = None, progress=None,
              bar: bool | None = None, overwrite: bool = False) -> SweepTable:
    """Run (or resume) a sweep, one CSV row per finished design.

    Parameters
    ----------
    spec : SweepSpec
        The designs and settings.
    out_dir : path-like
        Directory for ``sweep.json`` and ``sweep.csv`` (created if needed). If it already holds
        this sweep, only the missing designs are computed; a finished sweep computes nothing.
    executor : None, "process", "dask://HOST:PORT" or concurrent.futures.Executor
        Where designs run. None or ``"process"``: a local process pool of ``workers`` processes
        (default: all cores). ``"dask://HOST:PORT"``: a Dask distributed scheduler (optional
        dependency). An Executor instance is used as given and not shut down; if it is a
        process pool that breaks (a worker died), the sweep stops there, finished rows kept,
        since only a pool of its own can be replaced.
    workers : int, optional
        Processes of the local pool (default ``os.cpu_count()``).
    progress : text stream, optional
        Where to report (e.g. ``sys.stderr``): how many designs earlier runs finished, failed
        designs, and a progress bar; None: silent.
    bar : bool, optional
        Draw the tqdm progress bar on ``progress``; None (default): only if it is a terminal.
    overwrite : bool
        If ``out_dir`` holds a sweep made with other settings, move its ``sweep.csv`` aside to
        the next free ``sweep.previous-N.csv`` (with its ``sweep.json`` as ``sweep.previous-N.json``)
        and start afresh (default: refuse with ``SweepMismatch``).

    Returns
    -------
    SweepTable
        Every row of the directory.

    Notes
    -----
    Each finished design is appended to ``sweep.csv``, flushed and synced before the next one
    is taken, so a kill loses at most the designs being computed. On ``KeyboardInterrupt`` the
    pending designs are cancelled and the interrupt propagates; the rows written stay.
    """
    if not isinstance(spec, SweepSpec):
        raise ParameterError("spec", f"expected a SweepSpec, got {type(spec).__name__}")
    if workers is not None and (int(workers) != workers or workers < 1):
        raise ParameterError("workers", f"must be an integer >= 1, got {workers!r}")
    check_executor_form(executor)  # before sweep.json is written
    out = Path(out_dir)
    prepare_dir(spec, out, overwrite)
    path = out / SWEEP_CSV
    rows = read_rows(path, spec, "out")
    designs = spec.designs()
    pending = [d for d in designs if d.design_id not in rows]
    report = Progress(len(designs), len(rows), progress, bar=bar if pending else False)
    if not pending:
        report.say(f"sweep: all {len(designs)} designs already in {path}; nothing to compute")
        return table_from_rows(spec, rows, "out")
    if rows:
        report.say(f"sweep: resuming {out}: {len(rows)} of {len(designs)} designs done before, "
                   f"{len(pending)} to compute")
    with _interruptible():
        runner = _Runner(executor, workers, spec.settings, len(pending))
        interrupted = True
        try:
            with Journal(path, sweep_columns(spec)) as journal:
                for res in runner.results(pending):
                    rows[res.design.design_id] = journal.append(res.row())
                    report.update()
                    if res.error:
                        report.say(f"sweep: design {res.design.design_id} failed: {res.error}")
            interrupted = False
        finally:
            report.close()
            runner.close(interrupted=interrupted)
            if interrupted:  # count what the journal holds: the interrupt may fall between a row and its count
                kept = len(read_rows(path, spec, "out"))
                report.say(f"sweep: stopped; {kept} of {len(designs)} designs kept in {path}")
    # finished: the same bytes whatever order the workers took
    put_in_design_order(path, rows, designs, sweep_columns(spec))
    return table_from_rows(spec, rows, "out")
