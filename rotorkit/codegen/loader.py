"""Write generated source to the cache folder and load it as a module.

numba's own on-disk cache needs the function to live in a real file, so the
generated module is written to ``<cache>/generated/rhs_<key>.py`` (atomic
write) and imported from there.
"""

import hashlib
import importlib.util
import os
import sys
import tempfile
from pathlib import Path

__all__ = ["cache_dir", "load_module", "atomic_write_text", "atomic_write_bytes"]


def cache_dir():
    """The folder for rotorkit's caches: ``$ROTORKIT_CACHE_DIR`` or the user cache."""
    env = os.environ.get("ROTORKIT_CACHE_DIR")
    if env:
        base = Path(env)
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rotorkit"
    try:
        base.mkdir(parents=True, exist_ok=True)
        return base
    except OSError:
        fallback = Path(tempfile.gettempdir()) / f"rotorkit-cache-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
        fallback.mkdir(parents=True, exist_ok=True)
        return fallback


def atomic_write_text(path, text):
    """Write ``text`` to ``path`` through a temporary file and a rename."""
    atomic_write_bytes(path, text.encode("utf-8"))


def atomic_write_bytes(path, data):
    """Write ``data`` to ``path`` through a temporary file and a rename (never half-written)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def load_module(source, key):
    """Write ``source`` (if changed) and import it as a module named after ``key``."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:16]
    name = f"rotorkit_generated_{key}_{digest}"
    if name in sys.modules:
        return sys.modules[name]
    path = cache_dir() / "generated" / f"rhs_{key}_{digest}.py"
    if not path.exists() or path.read_text(encoding="utf-8") != source:
        atomic_write_text(path, source)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[name] = module
    return module
