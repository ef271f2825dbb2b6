"""Running sweep points on an executor: local processes, Dask, or any ``concurrent.futures.Executor``.

The calling process keeps at most a few points per worker in flight (a huge
sweep is streamed, never submitted at once), stores each result as it
arrives, and retries a point whose worker died (a killed or crashed
process): a local pool is restarted, Dask reschedules the point on another
worker. Each point is stored exactly once, by the calling process.

Local worker processes end with their parent: they ask the kernel for a
signal when the parent dies (Linux ``PR_SET_PDEATHSIG``) and also watch
their parent process id, so killing ``rotorkit sweep`` (even with
``kill -9``) stops its workers instead of leaving them computing.
"""

from __future__ import annotations

import math
import os
import signal
import sys
import threading
import time as _time
from concurrent.futures import FIRST_COMPLETED, Executor, wait
from dataclasses import dataclass

from ..errors import ArgumentTypeError, ParameterError, RotorkitError

__all__ = ["ProgressEvent", "LocalPool", "connect", "check_worker_versions", "worker_versions"]

#: a point whose worker died this many times is stored as failed (it probably kills any worker: memory, a crash)
MAX_ATTEMPTS = 3


# ---------------------------------------------------------------------------
# Progress
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class ProgressEvent:
    """One point finished (or was found on disk).

    Attributes
    ----------
    done, total : int
        Points finished (including those found on disk) and in the sweep.
    failed, runaway, cached : int
        Points so far that failed, ran away, or were found valid on disk.
    index : int
        The point (flat index).
    point : dict
        Its parameter values.
    status : str
        ``ok``, ``failed``, ``runaway`` or ``cached``.
    elapsed : float
        Wall time since the sweep started (s).
    eta : float or None
        Estimated wall time to the end (s), from the points computed so far.
    """

    done: int
    total: int
    failed: int
    runaway: int
    cached: int
    index: int
    point: dict
    status: str
    elapsed: float
    eta: float | None

    def __str__(self):
        point = ", ".join(f"{k}={v:.4g}" for k, v in self.point.items())
        parts = [f"[{self.done}/{self.total}] {point}: {self.status}"]
        if self.failed or self.runaway:
            parts.append(f"{self.failed} failed, {self.runaway} run away")
        if self.eta is not None and self.done < self.total:
            parts.append(f"ETA {format_duration(self.eta)}")
        return "  ".join(parts)


def format_duration(seconds):
    seconds = max(0.0, float(seconds))
    if seconds < 60:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        return f"{int(seconds // 60)} min {int(seconds % 60)} s"
    return f"{int(seconds // 3600)} h {int(seconds % 3600 // 60)} min"


class Progress:
    """Counts points and calls the user's ``progress(event)``."""

    def __init__(self, total, callback):
        self.total, self.callback = total, callback
        self.done = self.failed = self.runaway = self.cached = self.computed = 0
        self.start = _time.perf_counter()

    def __call__(self, index, point, status):
        self.done += 1
        self.cached += status == "cached"
        self.computed += status != "cached"
        self.failed += status == "failed"
        self.runaway += status == "runaway"
        elapsed = _time.perf_counter() - self.start
        eta = elapsed / self.computed * (self.total - self.done) if self.computed else None
        if self.callback is not None:
            self.callback(ProgressEvent(self.done, self.total, self.failed, self.runaway, self.cached, index,
                                        dict(point), status, elapsed, eta))


# ---------------------------------------------------------------------------
# Local processes that end with their parent
# ---------------------------------------------------------------------------


def _end_with_parent(parent_pid):
    """Worker initializer: die when the parent process dies."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent_pid:  # the parent died before the line above
        os._exit(1)

    def watch():
        while True:
            _time.sleep(0.5)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name="rotorkit-parent-watch", daemon=True).start()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C goes to the parent, which stops the workers


def check_start_method(start_method, workers=2):
    import multiprocessing

    methods = multiprocessing.get_all_start_methods()
    if start_method not in methods:
        raise ParameterError(f"start_method={start_method!r}: expected one of {', '.join(methods)}")
    main_file = getattr(sys.modules.get("__main__"), "__file__", None)
    if workers > 1 and start_method != "fork" and main_file and not os.path.exists(main_file):
        raise ParameterError(
            f"worker processes ({start_method!r} start) re-import the main module, and {main_file!r} is not a "
            "file (code run from stdin?); run it from a script file, or use workers=1 or start_method='fork'"
        )


def check_executor(executor):
    if not (isinstance(executor, Executor) or (hasattr(executor, "get_executor") and hasattr(executor, "scheduler_info"))):
        raise ArgumentTypeError(f"executor={executor!r}: expected a concurrent.futures.Executor or a dask.distributed.Client")


class LocalPool(Executor):
    """A process pool whose workers end with their parent and that restarts after a worker died."""

    def __init__(self, workers, start_method="spawn"):
        import multiprocessing

        check_start_method(start_method)
        self.workers, self.context = workers, multiprocessing.get_context(start_method)
        self.restarts = 0
        self._pool = self._new()

    def _new(self):
        from concurrent.futures import ProcessPoolExecutor

        return ProcessPoolExecutor(max_workers=self.workers, mp_context=self.context, initializer=_end_with_parent,
                                   initargs=(os.getpid(),))

    @property
    def broken(self):
        return bool(getattr(self._pool, "_broken", False))

    def restart(self):
        self.kill()
        self.restarts += 1
        self._pool = self._new()

    def submit(self, fn, /, *args, **kwargs):
        if self.broken:
            self.restart()
        return self._pool.submit(fn, *args, **kwargs)

    def kill(self):
        """Stop the workers now (a point in progress is lost; its result was never stored)."""
        processes = list((getattr(self._pool, "_processes", None) or {}).values())
        for p in processes:
            if p.is_alive():
                p.kill()
        self._pool.shutdown(wait=True, cancel_futures=True)

    def shutdown(self, wait=True, *, cancel_futures=False):
        self._pool.shutdown(wait=wait, cancel_futures=cancel_futures)


# ---------------------------------------------------------------------------
# Dask
# ---------------------------------------------------------------------------


def worker_versions():
    """What must agree between the calling process and the workers."""
    import rotorkit

    return {"rotorkit": rotorkit.__version__, "python": "%d.%d" % sys.version_info[:2]}


def check_worker_versions(client, timeout=10.0, local=None):
    """Raise if the cluster has no worker within ``timeout`` s or a worker runs another rotorkit or Python.

    ``local``: the versions to compare with (default :func:`worker_versions` of this process).
    """
    try:
        client.wait_for_workers(1, timeout=timeout)
    except Exception as exc:  # distributed raises its own TimeoutError
        raise RotorkitError(
            f"the Dask scheduler at {client.scheduler.address} has no workers after {timeout:g} s ({exc}); "
            f"start some with 'dask worker {client.scheduler.address}'"
        ) from None
    local = worker_versions() if local is None else local
    found = client.run(worker_versions)
    wrong = {addr: v for addr, v in found.items() if v != local}
    if wrong:
        listed = "; ".join(f"{addr}: " + ", ".join(f"{k} {v[k]}" for k in sorted(v)) for addr, v in wrong.items())
        raise RotorkitError(
            "Dask workers run a different version than this process (here: "
            + ", ".join(f"{k} {v}" for k, v in sorted(local.items())) + f"; {listed}): install the same rotorkit "
            "and Python on the workers (see docs/cluster.md)"
        )


def connect(address, timeout=8.0):
    """A ``dask.distributed.Client`` connected to the scheduler at ``address``, checked.

    Raises
    ------
    RotorkitError
        Dask is not installed, the scheduler cannot be reached within
        ``timeout`` seconds, it has no workers, or they run another rotorkit
        or Python version.
    """
    try:
        from distributed import Client
    except ImportError:
        raise RotorkitError("a Dask scheduler needs the 'distributed' package: pip install 'rotorkit[distributed]'") \
            from None
    if not isinstance(address, str) or not address.strip():
        raise ParameterError(f"scheduler={address!r}: expected an address such as tcp://10.0.0.5:8786")
    try:
        client = Client(address, timeout=f"{timeout:g}s", set_as_default=False)
    except Exception as exc:  # OSError, TimeoutError, ValueError for a malformed address
        raise RotorkitError(
            f"cannot reach the Dask scheduler at {address!r} within {timeout:g} s ({type(exc).__name__}: {exc}); "
            "start one with 'dask scheduler' and pass the address it prints (tcp://HOST:8786)"
        ) from None
    try:
        check_worker_versions(client, timeout=timeout)
    except BaseException:
        client.close()
        raise
    return client


def as_executor(executor):
    """(a concurrent.futures.Executor, number of workers) for an Executor or a dask Client."""
    if hasattr(executor, "get_executor") and hasattr(executor, "scheduler_info"):  # a dask.distributed.Client
        n = max(1, sum(w.get("nthreads", 1) for w in executor.scheduler_info().get("workers", {}).values()))
        return executor.get_executor(pure=False), n
    if isinstance(executor, Executor):
        return executor, max(1, int(getattr(executor, "_max_workers", 0) or os.cpu_count() or 1))
    raise ArgumentTypeError(f"executor={executor!r}: expected a concurrent.futures.Executor or a dask.distributed.Client")


def _worker_died(exc):
    from concurrent.futures.process import BrokenProcessPool

    return isinstance(exc, BrokenProcessPool) or type(exc).__name__ in ("KilledWorker", "CommClosedError")


def run_tasks(tasks, executor, workers, func, on_result, describe):
    """Run ``func(task)`` for each task of the iterator ``tasks``, at most ~2 per worker in flight.

    ``on_result(result)`` stores a result; a task whose worker died is
    retried (up to MAX_ATTEMPTS in all, then stored as failed through
    ``on_result``). Any other exception stops the sweep, naming the point.
    """
    pending, attempts, retry = {}, {}, []
    in_flight = max(2, 2 * workers)
    tasks = iter(tasks)

    def submit(task):
        pending[executor.submit(func, task)] = task

    def fill():
        while retry and len(pending) < in_flight:
            submit(retry.pop())
        while len(pending) < in_flight:
            task = next(tasks, None)
            if task is None:
                return
            submit(task)

    try:
        fill()
        while pending:
            finished, _ = wait(list(pending), return_when=FIRST_COMPLETED)
            for future in finished:
                task = pending.pop(future)
                try:
                    result = future.result()
                except Exception as exc:
                    if not _worker_died(exc):
                        raise RotorkitError(
                            f"sweep point {task['index']} ({describe(task)}) raised {type(exc).__name__}: {exc}; "
                            "the finished points are kept, run the sweep again to resume"
                        ) from exc
                    n = attempts[task["index"]] = attempts.get(task["index"], 0) + 1
                    dask_gave_up = type(exc).__name__ == "KilledWorker"
                    if n >= MAX_ATTEMPTS or dask_gave_up:
                        on_result(died(task, n, exc))
                    else:
                        retry.append(task)
                else:
                    on_result(result)
            fill()
    except BaseException:
        for future in pending:
            future.cancel()
        if isinstance(executor, LocalPool):
            executor.kill()
        raise


def died(task, attempts, exc):
    """The stored result of a point whose worker died every time it ran it."""
    import numpy as np

    s = task["settings"]
    message = (f"the worker process died {attempts} time(s) running this point ({type(exc).__name__}; "
               "out of memory, or a crash in compiled code?)")
    meta = {"index": task["index"], "point": task["point"], "status": "failed", "time": None,
            "max_displacement": None, "runaway_limit": None, "message": message, "spectrum": None,
            "energy_residual": math.nan, "stats": {"attempts": attempts}}
    return {"index": task["index"], "meta": meta, "arrays": {
        "frequency": np.empty(0), "amplitude": np.empty((len(s["signals"]), 0)),
        "order_amplitude": np.full((len(s["signals"]), len(s["orders"])), np.nan),
        "poincare": np.full((len(s["poincare_signals"]), s["poincare_revolutions"]), np.nan)}}
