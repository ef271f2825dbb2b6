"""C shared libraries built by the system's C compiler into rotorkit's private cache.

The ``c`` back end (:mod:`rotorkit.codegen.csource`, :mod:`rotorkit.engines.rk_c`)
compiles generated C with the compiler found on the machine (``$CC``, else
``cc`` or ``gcc``) instead of numba: gcc builds the preset's right-hand side
in well under a second where numba takes seconds, and loading a built library
costs milliseconds where numba's cache costs most of a second (its import and
target set-up). Without a compiler the numba back end is used.

A library lives in a private cache folder beside what it was built from::

    <folder>/<name>.c          the source compiled
    <folder>/<name>.so         the library
    <folder>/<name>.sig.json   HMAC-SHA256 (this user's key) of the source and of the library
    <folder>/<name>.lock       held (flock) while a process checks, builds or loads it

It is loaded only if both signatures verify and the source is the one asked
for; otherwise it is built again (in a temporary file, renamed into place, so
a concurrent process never loads half a library). The folders are this user's
and nobody else can write them (:mod:`rotorkit.codegen.cache`).
"""

import ctypes
import functools
import hashlib
import hmac
import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from ..errors import RotorkitError
from ..files import atomic_write_bytes, atomic_write_text, read_data

__all__ = ["compiler", "library", "CompilerError", "FLAGS"]

#: ISO C99 (no FMA contraction: the same rounding as numba's code), position independent, optimised.
FLAGS = ("-O2", "-std=c99", "-fPIC", "-shared", "-fno-math-errno")
#: Set to ``0`` to never use a C compiler (the numba or Python back end is used instead).
VARIABLE = "ROTORKIT_C_COMPILER"
COMPILE_TIMEOUT = 600.0


class CompilerError(RotorkitError):
    """The C compiler failed on generated code (a bug in rotorkit: please report it with the message)."""


@functools.lru_cache(maxsize=None)
def _find_compiler(setting, cc):
    if setting.strip() == "0":
        return None
    for candidate in (setting.strip() or None, cc, "cc", "gcc", "clang"):
        if candidate and shutil.which(candidate):
            return shutil.which(candidate)
    return None


def compiler():
    """The C compiler's path, or None (none found, or ``ROTORKIT_C_COMPILER=0``)."""
    return _find_compiler(os.environ.get(VARIABLE, ""), os.environ.get("CC"))


def _signature(secret, what, data):
    return hmac.new(secret, b"rotorkit-c-library\0" + what.encode() + b"\0" + data, hashlib.sha256).hexdigest()


def _verified(folder, name, source_bytes, secret):
    """The library's path if it is there, signed, and built from ``source_bytes``; else None."""
    lib, sig = folder / f"{name}.so", folder / f"{name}.sig.json"
    try:
        signed = json.loads(read_data(sig, what="cache metadata").decode("utf-8"))
        data = read_data(lib, what="cache entry")  # a FIFO or a link to /dev/zero is refused, not read
    except (OSError, ValueError):
        return None
    ok = (isinstance(signed, dict)
          and hmac.compare_digest(str(signed.get("source")), _signature(secret, "source", source_bytes))
          and hmac.compare_digest(str(signed.get("library")), _signature(secret, "library", data)))
    return lib if ok else None


def _compile(folder, name, source_bytes, secret):
    cc = compiler()
    if cc is None:
        raise CompilerError("no C compiler found (set $CC, or install gcc)")
    atomic_write_bytes(folder / f"{name}.c", source_bytes, mode=0o600, durable=False)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{name}.", suffix=".so")
    os.close(fd)
    try:
        done = subprocess.run([cc, *FLAGS, "-o", tmp, str(folder / f"{name}.c"), "-lm"], capture_output=True,
                              text=True, timeout=COMPILE_TIMEOUT, stdin=subprocess.DEVNULL)
        if done.returncode:
            raise CompilerError(f"{cc} failed on {folder / (name + '.c')} (exit {done.returncode}):\n"
                                f"{done.stderr.strip()[-4000:]}")
        os.chmod(tmp, 0o700)
        data = Path(tmp).read_bytes()
        target = folder / f"{name}.so"
        if os.path.lexists(target) and (target.is_symlink() or not target.is_file()):
            from . import cache

            cache.remove_path(target)  # a folder or a FIFO in the library's place: a damaged cache, repaired
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    signed = {"source": _signature(secret, "source", source_bytes), "library": _signature(secret, "library", data)}
    atomic_write_text(folder / f"{name}.sig.json", json.dumps(signed), mode=0o600)
    return folder / f"{name}.so"


def library(folder, name, source):
    """The loaded library ``<folder>/<name>.so`` built from the C ``source``: from the cache, else compiled now.

    Parameters
    ----------
    folder : pathlib.Path or None
        A private cache folder (a model's entry, or ``<cache>/shared/<name>``);
        None builds in a new private temporary folder.
    name : str
        File stem.
    source : str
        The complete C translation unit.

    Returns
    -------
    ctypes.CDLL

    Raises
    ------
    CompilerError
        No compiler, or it failed (with its message).
    """
    from . import cache

    source_bytes = source.encode("utf-8")
    secret = None
    if folder is None:  # a model built in memory: build in a new folder, trust only what this process builds
        folder = Path(tempfile.mkdtemp(prefix="rotorkit-c-"))
    else:
        folder = Path(folder)
        try:
            secret = cache.entry_key(folder)  # folder: <cache>/models/<key> or <cache>/shared/<name>
        except OSError:
            pass  # no usable cache: as in memory
    secret = secret or os.urandom(32)
    with cache.shared_lock(name, folder=folder):  # <folder>/<name>.lock: one builder at a time, others then load
        path = _verified(folder, name, source_bytes, secret) or _compile(folder, name, source_bytes, secret)
        return ctypes.CDLL(str(path))
