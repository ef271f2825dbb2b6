"""The on-disk cache of generated models, and atomic file writes.

A model's generated right-hand side depends only on its *structure* (which
elements, on which stations, which effects; not the parameter values), so it
is stored under the model's ``structure_key``::

    <cache>/models/<key>/rhs.py      generated source (numba caches its
                                     machine code beside it, in __pycache__)
    <cache>/models/<key>/meta.json   format, key, HMAC-SHA256 of rhs.py
    <cache>/secret.key               a random key, readable by this user only

A warm start loads ``rhs.py`` without deriving anything. An entry is used
only if ``meta.json`` parses as JSON (data, never code), names this format
and key, and the source's HMAC under *this user's* secret key matches;
anything else (truncated file, stale format, an entry copied from another
machine or user, planted content) is discarded and rebuilt, never an error
and never imported.

The cache folder is ``$ROTORKIT_CACHE_DIR`` or ``~/.cache/rotorkit``. Its
entries are Python source that is imported, so the folder must belong to the
current user and not be writable by others; otherwise rotorkit falls back to
a private temporary folder (with a warning) rather than run code others could
have planted.
"""

import hashlib
import hmac
import importlib.util
import json
import os
import shutil
import stat
import sys
import tempfile
import warnings
from pathlib import Path

from ..files import atomic_write_text

__all__ = ["cache_dir", "load", "store", "clear", "info"]

FORMAT = "rotorkit-model-cache-2"


def _private(path):
    """True if ``path`` belongs to this user and only this user can write it."""
    if not hasattr(os, "getuid"):
        return True
    st = path.stat()
    return st.st_uid == os.getuid() and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)


def cache_dir():
    """The cache folder (created private if missing)."""
    env = os.environ.get("ROTORKIT_CACHE_DIR")
    base = Path(env) if env else Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rotorkit"
    try:
        base.mkdir(mode=0o700, parents=True, exist_ok=True)
        if _private(base):
            return base
        warnings.warn(f"rotorkit cache folder {base} is writable by others or not yours; "
                      "using a private temporary folder instead", stacklevel=2)
    except OSError:
        pass
    fallback = Path(tempfile.gettempdir()) / f"rotorkit-cache-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
    fallback.mkdir(mode=0o700, parents=True, exist_ok=True)
    if not _private(fallback):
        fallback = Path(tempfile.mkdtemp(prefix="rotorkit-cache-"))
    return fallback


def _entry(key):
    return cache_dir() / "models" / key


def _secret():
    """This user's random signing key (created on first use, mode 0600)."""
    path = cache_dir() / "secret.key"
    try:
        key = path.read_bytes()
        if len(key) == 32 and _private(path) and not path.stat().st_mode & 0o077:
            return key
    except OSError:
        pass
    key = os.urandom(32)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".secret.")
    with os.fdopen(fd, "wb") as fh:  # mkstemp: mode 0600
        fh.write(key)
    os.replace(tmp, path)
    return key


def _digest(source):
    """HMAC-SHA256 of the source under this user's key: only entries we wrote verify."""
    return hmac.new(_secret(), source.encode("utf-8"), hashlib.sha256).hexdigest()


def _import(key, path):
    name = f"rotorkit_generated_{key}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[name] = module
    return module


def load(key):
    """The cached module for ``key``, or None (missing, stale or damaged entries are removed)."""
    entry = _entry(key)
    source_path, meta_path = entry / "rhs.py", entry / "meta.json"
    if not meta_path.exists():
        return None
    try:
        meta = json.loads(meta_path.read_text(encoding="utf-8"))
        source = source_path.read_text(encoding="utf-8")
        valid = (isinstance(meta, dict) and meta.get("format") == FORMAT and meta.get("key") == key
                 and isinstance(meta.get("hmac"), str) and hmac.compare_digest(meta["hmac"], _digest(source)))
        if valid:
            module = _import(key, source_path)
            if module.STATE_NAMES and len(module.STATE_NAMES) == 2 * module.N_COORDINATES:
                return module
    except Exception:  # damaged entry: whatever it is, rebuild it
        pass
    shutil.rmtree(entry, ignore_errors=True)
    return None


def store(key, source):
    """Write a generated module for ``key`` and import it."""
    entry = _entry(key)
    atomic_write_text(entry / "rhs.py", source)
    atomic_write_text(entry / "meta.json", json.dumps({"format": FORMAT, "key": key, "hmac": _digest(source)}))
    return _import(key, entry / "rhs.py")


def info():
    """(folder, number of cached models, bytes on disk)."""
    base = cache_dir()
    models = base / "models"
    count = sum(1 for p in models.iterdir() if p.is_dir()) if models.exists() else 0
    size = sum(p.stat().st_size for p in base.rglob("*") if p.is_file())
    return base, count, size


def clear():
    """Remove every cached model (and numba's machine code beside it); returns how many."""
    base, count, _ = info()
    shutil.rmtree(base / "models", ignore_errors=True)
    return count
