"""Build locks of rotorkit's cache: one process builds or loads a shared piece of compiled code at a time.

:func:`shared_lock` holds an exclusive ``flock`` on ``<cache>/shared/<name>.lock`` (or a lock file in a model's
entry); a process that waits says for whom, and builds without the lock past :data:`LOCK_WAIT` seconds, or
:data:`STOPPED_LOCK_WAIT` once the holder is seen stopped (Ctrl-Z), rather than hang.
"""

import contextlib
import os
import stat
import sys
from pathlib import Path

from .cache_folders import cache_dir, rebuilt_dir, remove_path, warn_once

__all__ = ["shared_lock", "LOCK_WAIT", "STOPPED_LOCK_WAIT"]


def _lock_file(name, folder=None):
    """An open file ``<folder>/<name>.lock`` (default folder ``<cache>/shared``; mode 0o600) to ``flock``; None
    where that is impossible."""
    try:
        import fcntl  # noqa: F401 - POSIX only
    except ImportError:
        return None
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        path = Path(folder if folder is not None else rebuilt_dir(cache_dir() / "shared")) / f"{name}.lock"
    except OSError:
        return None
    for _attempt in range(2):
        try:
            fd = os.open(path, flags, 0o600)
        except OSError:
            fd = None
        if fd is not None and stat.S_ISREG(os.fstat(fd).st_mode):
            os.set_blocking(fd, True)
            return os.fdopen(fd, "r+b")
        if fd is not None:
            os.close(fd)
        # a FIFO, a folder, a link or a device in place of the lock file: a damaged cache, repaired once
        if not os.path.lexists(path):
            return None
        warn_once(f"rotorkit cache: the lock file {path} was not a regular file; it is replaced",
                  topic=("lock", str(path)))
        try:
            remove_path(path)
        except OSError:
            return None
    return None


#: seconds a process waits for another that holds a build lock, before it builds without it
LOCK_WAIT = float(os.environ.get("ROTORKIT_LOCK_WAIT", "600") or 600)
#: seconds it waits for a holder that is stopped (Ctrl-Z, SIGSTOP)
STOPPED_LOCK_WAIT = 10.0


def _process_state(pid):
    """``"running"``, ``"stopped"`` (Ctrl-Z, a debugger) or ``"gone"`` for ``pid``; ``"unknown"`` without /proc."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return "gone"
    except OSError:
        pass
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            state = fh.read(4096).rsplit(b")", 1)[1].split()[0]
    except (OSError, IndexError):
        return "unknown"
    return "stopped" if state in (b"T", b"t") else "running"


def _holder(handle):
    """The pid written in a lock file by its holder, or None."""
    try:
        handle.seek(0)
        text = handle.read(32).decode("ascii", "replace").strip()
        return int(text) if text.isdigit() else None
    except (OSError, ValueError):
        return None


def _wait_for_lock(handle, name, path, wait=None):
    """Take the lock of ``handle``, waiting for its holder with a message naming it; False past the bound.

    The bound is :data:`LOCK_WAIT` seconds, or :data:`STOPPED_LOCK_WAIT` once
    the holder is seen stopped (Ctrl-Z): then the caller builds without the lock
    rather than hang.
    """
    import fcntl
    import time

    wait = LOCK_WAIT if wait is None else wait
    start = time.monotonic()
    told, stopped_since = None, None
    while True:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            pass
        pid = _holder(handle)
        state = _process_state(pid) if pid else "unknown"
        now = time.monotonic()
        if told != (pid, state) and (state == "stopped" or now - start > 2.0):  # a short wait goes unsaid
            told = (pid, state)
            who = f"process {pid}" if pid else "another process"
            how = ("; it is stopped (Ctrl-Z or SIGSTOP: 'fg' or 'kill -CONT' resumes it)" if state == "stopped"
                   else "")
            sys.stderr.write(f"rotorkit: waiting for {who} to finish building {name} (it holds {path}){how}; "
                             f"at most {STOPPED_LOCK_WAIT if state == 'stopped' else wait:g} s, then rotorkit "
                             "builds without the lock\n")
            sys.stderr.flush()
        stopped_since = (stopped_since or now) if state == "stopped" else None
        if now - start > wait or (stopped_since is not None and now - stopped_since > STOPPED_LOCK_WAIT):
            warn_once(f"rotorkit: {('process ' + str(pid)) if pid else 'another process'} has held the lock "
                      f"{path} too long ({'stopped' if state == 'stopped' else f'over {wait:g} s'}); "
                      f"building {name} without it", topic=("lock-wait", str(path)))
            return False
        time.sleep(0.05)


def _lock_path(name, folder):
    return Path(folder if folder is not None else cache_dir() / "shared") / f"{name}.lock"


@contextlib.contextmanager
def shared_lock(name, *, blocking=True, folder=None):
    """Hold the lock of ``<cache>/shared/<name>`` (an exclusive ``flock``) within the block.

    ``folder``: a private folder to keep the lock file ``<name>.lock`` in
    instead (a model's entry, for what is built into it).

    Every process that loads or compiles rotorkit's shared code into the
    cache takes it, so one process never reads (and, finding them unsigned,
    removes) files another is still writing, and a process started while
    another compiles waits for it and then loads its result. Yields the open
    lock file, or None where locking is not available (no ``fcntl``, cache
    folder unusable: then nothing is serialised, as before) or, with
    ``blocking=False``, when another process holds the lock.
    """
    handle = _lock_file(name, folder)
    if handle is None:
        yield None
        return
    import fcntl

    with handle:  # the lock is released when the file is closed (at the latest when the process exits)
        try:
            if blocking:
                locked = _wait_for_lock(handle, name, _lock_path(name, folder))
            else:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                locked = True
        except OSError:  # held elsewhere (non-blocking), or flock not supported by the file system
            locked = False
        if locked:
            try:  # the holder's pid, for the message of a process that waits
                handle.seek(0)
                handle.truncate()
                handle.write(str(os.getpid()).encode())
                handle.flush()
            except OSError:
                pass
        yield handle if locked else None
