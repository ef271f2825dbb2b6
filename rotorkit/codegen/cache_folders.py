"""rotorkit's cache folder: where it is, kept private (``0o700``, this user's), repaired, and its warnings.

The base of :mod:`rotorkit.codegen.cache` (the model cache) and :mod:`rotorkit.codegen.locks` (the build
locks); the folder is ``$ROTORKIT_CACHE_DIR`` or ``~/.cache/rotorkit`` (``$XDG_CACHE_HOME/rotorkit``), a
private temporary folder where that cannot be used.
"""

import os
import shutil
import stat
import tempfile
import warnings
from pathlib import Path

__all__ = ["CacheWarning", "warn_once", "NotPrivate", "is_private", "private_dir", "remove_path", "cache_dir",
           "rebuilt_dir"]

_WARNED = set()


class CacheWarning(UserWarning):
    """The model cache could not be used as is (it is rebuilt or bypassed)."""


def warn_once(message, topic=None):
    """One warning per topic and process: a damaged cache must not flood a sweep's log."""
    topic = topic or message
    if topic not in _WARNED:
        _WARNED.add(topic)
        warnings.warn(message, CacheWarning, stacklevel=3)


class NotPrivate(OSError):
    """A folder or file another user can write (or that is not ours)."""


def is_private(path):
    """True if ``path`` belongs to this user and only this user can write it."""
    if not hasattr(os, "getuid"):
        return True
    st = path.stat()
    return st.st_uid == os.getuid() and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)


def private_dir(path):
    """Create ``path`` (and missing parents) ``0o700`` whatever the umask, or check it; OSError if unusable."""
    path = Path(path)
    missing = []
    probe = path
    while not os.path.lexists(probe) and probe != probe.parent:
        missing.append(probe)
        probe = probe.parent
    for folder in reversed(missing):
        try:
            folder.mkdir(mode=0o700)
            os.chmod(folder, 0o700)  # mkdir's mode is masked by the umask; 0o700 is what we want
        except FileExistsError:
            pass
    if not path.is_dir():
        raise NotADirectoryError(f"{path} is not a folder")
    if not is_private(path):
        raise NotPrivate(f"{path} is writable by others or not yours")
    if not os.access(path, os.R_OK | os.W_OK | os.X_OK):
        raise PermissionError(f"{path} is not readable and writable by you")
    return path


def remove_path(path):
    """Remove a file, link or folder tree (making our own unreadable folders readable); OSError if it cannot."""
    if os.path.islink(path) or not os.path.isdir(path):
        os.unlink(path)
        return

    def make_writable_and_retry(function, failed, _exc_info):
        for folder in {os.path.dirname(failed), failed}:
            if os.path.isdir(folder) and not os.path.islink(folder):
                os.chmod(folder, 0o700)
        function(failed)

    os.chmod(path, 0o700)
    shutil.rmtree(path, onerror=make_writable_and_retry)


def cache_dir():
    """The cache folder (created private if missing; a private temporary folder if it cannot be used)."""
    env = os.environ.get("ROTORKIT_CACHE_DIR")
    base = Path(env) if env else Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rotorkit"
    try:
        return private_dir(base)
    except NotPrivate:
        warn_once(f"rotorkit cache folder {base} is writable by others or not yours; "
                  "using a private temporary folder instead", topic=("base", str(base)))
    except OSError as exc:
        warn_once(f"rotorkit cache folder {base} cannot be used ({exc}); "
                  "using a private temporary folder instead", topic=("base", str(base)))
    fallback = Path(tempfile.gettempdir()) / f"rotorkit-cache-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
    try:
        return private_dir(fallback)
    except OSError:
        return Path(tempfile.mkdtemp(prefix="rotorkit-cache-"))  # mkdtemp: 0o700, ours


def rebuilt_dir(folder):
    """``folder`` as a private folder; replaced (with a warning) if it is not one (others can write it, a file)."""
    try:
        return private_dir(folder)
    except (NotADirectoryError, NotPrivate, PermissionError) as exc:
        warn_once(f"rotorkit cache folder {folder} cannot be trusted or used ({exc}); "
                  "it is removed and rebuilt", topic=("folder", str(folder)))
        remove_path(folder)
        return private_dir(folder)
