"""Ctrl-C that other code swallowed: noticed again at the next checkpoint.

Python raises ``KeyboardInterrupt`` wherever the main thread happens to be
when SIGINT arrives. Code running there that catches it (a finaliser, whose
exceptions Python only prints; a broad ``except`` in a third-party import)
swallows it, and a run then goes on for minutes as if Ctrl-C had never been
pressed. The command line installs :func:`install`'s handler, which raises
``KeyboardInterrupt`` as Python's own does and also sets :data:`received`;
long loops call :func:`check` (``simulate`` at every step or piece, ``rotorkit
run`` before it writes its outputs), which raises it again once a SIGINT has
been received. Without :func:`install` (rotorkit used as a library)
:data:`received` stays False and :func:`check` does nothing.
"""

import signal
import threading

__all__ = ["install", "check", "received"]

#: whether a SIGINT reached the handler of :func:`install` in this process
received = False


def _handler(signum, frame):
    global received
    received = True
    raise KeyboardInterrupt


def install():
    """Handle SIGINT with :func:`_handler` if Python's default handler is in place (not when SIGINT is ignored,
    as in a background job, or handled by someone else) and this is the main thread."""
    if threading.current_thread() is threading.main_thread() and \
            signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _handler)


def check():
    """Raise ``KeyboardInterrupt`` if a SIGINT has been received (and swallowed, since we are still running)."""
    if received:
        raise KeyboardInterrupt
