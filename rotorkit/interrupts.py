"""Ctrl-C that other code swallowed: noticed again at the next checkpoint.

Python raises ``KeyboardInterrupt`` wherever the main thread happens to be
when SIGINT arrives. Code running there that catches it (a finaliser, whose
exceptions Python only prints; a broad ``except`` in a third-party import)
swallows it, and a run then goes on for minutes as if Ctrl-C had never been
pressed. The command line runs within :func:`watching`, whose handler raises
``KeyboardInterrupt`` as Python's own does and also sets :data:`received`;
long loops call :func:`check` (``simulate`` at every step or piece, ``rotorkit
run`` before it writes its outputs), which raises it again once a SIGINT has
been received. Outside :func:`watching` (rotorkit used as a library)
:data:`received` stays False and :func:`check` does nothing.
"""

import contextlib
import signal
import threading

__all__ = ["watching", "check", "received"]

#: whether a SIGINT reached the handler of :func:`watching` in this process (False again when it ends)
received = False


def _handler(signum, frame):
    global received
    received = True
    raise KeyboardInterrupt


@contextlib.contextmanager
def watching():
    """Within the block, SIGINT is handled by :func:`_handler` if Python's default handler was in place (not when
    SIGINT is ignored, as in a background job, or handled by someone else: IPython) and this is the main thread;
    on leaving, the previous handler is back and :data:`received` is False again (``rotorkit.cli.main`` called
    from a Python session leaves nothing behind)."""
    global received
    mine = threading.current_thread() is threading.main_thread() and \
        signal.getsignal(signal.SIGINT) is signal.default_int_handler
    if mine:
        signal.signal(signal.SIGINT, _handler)
    try:
        yield
    finally:
        if mine:
            signal.signal(signal.SIGINT, signal.default_int_handler)
            received = False


def check():
    """Raise ``KeyboardInterrupt`` if a SIGINT has been received (and swallowed, since we are still running)."""
    if received:
        raise KeyboardInterrupt
