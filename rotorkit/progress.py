"""One-line notices for slow one-off steps (derivation, code generation, numba compilation).

The first use of a new model structure derives its equations, generates
code and, with numba, compiles it: seconds to minutes for a large rotor.
:func:`announce_if_slow` prints one line to stderr when such a step is still
running after :data:`AFTER` seconds, and its duration when it ends, so a
first ``simulate`` or modal analysis does not sit silent. Steps that end
sooner print nothing. ``ROTORKIT_QUIET=1`` silences the notices.
"""

import contextlib
import os
import sys
import threading
import time

__all__ = ["announce_if_slow", "AFTER"]

#: seconds a step may run before it is announced
AFTER = 2.0


@contextlib.contextmanager
def announce_if_slow(what, after=None, stream=None):
    """Within the block, announce ``what`` on stderr if it takes longer than ``after`` s.

    Parameters
    ----------
    what : str
        What is happening, e.g. ``"compiling al31f with numba (first use; cached afterwards)"``.
    after : float, optional
        Seconds before the notice (default :data:`AFTER`).
    stream : file, optional
        Where to write (default ``sys.stderr`` at the time of writing).
    """
    if os.environ.get("ROTORKIT_QUIET", "").strip() not in ("", "0"):
        yield
        return
    start = time.perf_counter()
    shown = threading.Event()
    lock = threading.Lock()

    def show():
        with lock:
            if not done:
                out = stream or sys.stderr
                out.write(f"rotorkit: {what} ...\n")
                out.flush()
                shown.set()

    done = False
    timer = threading.Timer(AFTER if after is None else after, show)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        with lock:
            done = True
        timer.cancel()
        if shown.is_set():
            out = stream or sys.stderr
            out.write(f"rotorkit: {what}: done in {time.perf_counter() - start:.1f} s\n")
            out.flush()
