"""The on-disk cache of generated models: only what rotorkit wrote is ever run.

A model's generated right-hand side depends only on its *structure* (which
elements, on which stations, which effects; not the parameter values), so it
is stored under the model's ``structure_key``::

    <cache>/models/<key>/rhs.py          generated source
    <cache>/models/<key>/meta.json       format, key, HMAC-SHA256 of rhs.py
    <cache>/models/<key>/__pycache__/    numba's machine code (*.nbi, *.nbc)
    <cache>/models/<key>/numba.sig.json  HMAC of every file in __pycache__
    <cache>/models/<key>/numba.saving    present while a process writes and signs numba's files
    <cache>/shared/<name>/               numba's cache of rotorkit's own compiled code (the
                                         integration loop), with its numba.sig.json
    <cache>/shared/<name>.lock           held (flock) while a process loads or compiles it
    <cache>/secret.key                   a random key, readable by this user only; everything
                                         in <cache> is signed and checked with it (even when a
                                         process has since moved to another ROTORKIT_CACHE_DIR)

What is trusted
---------------
* ``rhs.py`` is read once, its HMAC under *this user's* secret key checked,
  and the very text that was checked is compiled and executed: Python's
  import machinery (and so any ``.pyc`` file) is never used.
* numba's cache files are pickles. Before numba reads them (load or save),
  every file in ``__pycache__`` must carry a valid HMAC in
  ``numba.sig.json``; any other file is removed first (planted, damaged or
  left by a crash) and numba recompiles. After numba writes, the files are
  signed. A process writes ``numba.saving`` before numba writes and removes
  it once the files are signed (all under the entry's lock): found by the
  next process, it tells that the unsigned files are those of a process
  killed while saving (SIGKILL cannot be caught), removed without a
  warning. If numba would put its cache anywhere else (``NUMBA_CACHE_DIR``),
  the model is compiled without numba's disk cache.
* Every folder is created ``0o700`` whatever the umask, files ``0o600``. The
  cache folder, ``models/`` and each entry must belong to this user and not
  be writable by others; a cache folder that is not is refused with a warning
  (a private temporary folder is used), an entry that is not is removed with
  a warning and rebuilt.

A damaged cache never stops a run: an entry that does not verify (truncated,
stale format, another user's or machine's key) is rebuilt silently; a folder
that cannot be used (unreadable, replaced by a file, a key file replaced by
a folder, disk full) gives one warning and the model is built in memory.

The cache folder is ``$ROTORKIT_CACHE_DIR`` or ``~/.cache/rotorkit``
(:mod:`rotorkit.codegen.cache_folders`: where, kept private, repaired, its
warnings); the locks are :mod:`rotorkit.codegen.locks`'.
"""

import hashlib
import hmac
import json
import os
import shutil
import sys
import types
from pathlib import Path

from ..files import atomic_write_bytes, atomic_write_text, read_data
from .cache_folders import (CacheWarning, cache_dir, is_private, private_dir, rebuilt_dir, remove_path,  # noqa: F401
                            warn_once)
from .locks import shared_lock

__all__ = ["cache_dir", "load", "store", "clear", "info", "jit", "jit_shared", "shared_lock", "shared_is_current",
           "compile_verified"]

FORMAT = "rotorkit-model-cache-2"
SIGNATURES = "numba.sig.json"
#: written (the saving process's pid) before numba saves, removed once its files are signed
SAVING = "numba.saving"
#: the lock (``<entry>/<NUMBA_LOCK>.lock``) a process holds while it verifies and reads, or writes and signs,
#: numba's cache files of an entry
NUMBA_LOCK = "numba_cache"


def secret_key(root=None):
    """This user's random signing key of the cache folder ``root`` (default :func:`cache_dir`; created on first
    use, mode 0600); OSError if it cannot be kept.

    Processes that start on a new cache at once (a run and the loop it compiles in another process, test
    workers' children) agree on one key: a new key is published only where none exists (a hard link), and the
    one that loses reads the winner's. Were each to keep its own, what the others signed would be removed as
    unsigned by every later process. For the same reason a key that cannot be read for now (an I/O error, no
    file descriptor left) raises OSError and is kept; only a missing or damaged key is replaced."""
    path = Path(root if root is not None else cache_dir()) / "secret.key"
    for _attempt in range(3):
        try:
            key = read_data(path, what="cache metadata", max_bytes=64)
        except FileNotFoundError:
            key = None
        except ValueError:  # not a regular file (a folder, a FIFO in its place) or too long: damaged
            key = b""
        # any other OSError (no descriptor left, an I/O error) is this call's: the key may be sound, and a new one
        # would orphan everything signed with it (the caller does without the cache this time)
        if key is not None:
            if len(key) == 32 and is_private(path) and not path.stat().st_mode & 0o077:
                return key
            remove_path(path)  # damaged, or others could have read or written it: replaced
        key = os.urandom(32)
        if atomic_write_bytes(path, key, mode=0o600, exclusive=True):
            return key
    raise OSError(f"rotorkit cache: the signing key {path} keeps changing under this process")


def entry_key(entry):
    """The signing key of the cache that holds ``entry`` (``<cache>/models/<key>`` or ``<cache>/shared/<name>``).

    Not necessarily the key of today's :func:`cache_dir`: a process keeps the modules it has loaded
    (``system._MODULES``) when ``ROTORKIT_CACHE_DIR`` changes (a test's temporary cache), and what it compiles
    for them later is written into their own entries, so it must be signed with their cache's key (which exists:
    storing the entry made it), else the next process finds it unsigned. A folder outside any cache (a C
    library built in a folder of the caller's) is signed with today's key.
    """
    root = Path(entry).parent.parent
    return secret_key(root if root == cache_dir() or (root / "secret.key").is_file() else None)


def _digest(source, secret=None):
    """HMAC-SHA256 of the source under this user's key: only entries we wrote verify."""
    return hmac.new(secret or secret_key(), source.encode("utf-8"), hashlib.sha256).hexdigest()


def _file_digest(secret, name, data):
    return hmac.new(secret, b"numba-cache-file\0" + name.encode() + b"\0" + data, hashlib.sha256).hexdigest()


def _execute(key, source, path=None):
    """Run the (verified) source text as module ``rotorkit_generated_<key>``; no import machinery, no .pyc."""
    name = f"rotorkit_generated_{key}"
    module = types.ModuleType(name)
    module.__file__ = str(path) if path else f"<rotorkit generated model {key}>"
    module.__rotorkit_entry__ = Path(path).parent if path else None
    module.__rotorkit_source__ = source  # the verified text (the c back end translates it)
    exec(compile_verified(source, module.__file__, module.__rotorkit_entry__, "rhs"), module.__dict__)
    sys.modules[name] = module
    return module


def _code_digest(secret, name, filename, source, data):
    tag = f"{sys.implementation.cache_tag}\0{sys.hexversion}\0{name}\0{filename}\0".encode()
    return hmac.new(secret, b"rotorkit-code\0" + tag + hashlib.sha256(source.encode("utf-8")).digest() + b"\0" + data,
                    hashlib.sha256).hexdigest().encode("ascii")


def compile_verified(source, filename, entry=None, name="rhs"):
    """``compile(source, filename, "exec")``, kept as signed bytecode in the cache entry ``entry``.

    ``source`` must be text already verified (or just generated) by this
    process. Its code object is stored in ``entry/<name>.<python tag>.code``
    as the HMAC (this user's key) of the Python version, ``name``,
    ``filename``, the SHA-256 of ``source`` and the marshalled bytes,
    followed by those bytes; a later process runs the bytes only if that
    HMAC verifies, so bytecode that rotorkit did not write for this very
    source is never loaded (it is compiled again and rewritten). Without an
    entry (a model built in memory) the source is compiled.
    """
    if entry is None:
        return compile(source, filename, "exec", dont_inherit=True)
    import marshal

    path = Path(entry) / f"{name}.{sys.implementation.cache_tag}.code"
    try:
        secret = entry_key(entry)
    except OSError:
        return compile(source, filename, "exec", dont_inherit=True)
    try:
        blob = read_data(path, what="cache entry")
        signature, data = blob[:64], blob[64:]
        if hmac.compare_digest(signature, _code_digest(secret, name, filename, source, data)):
            code = marshal.loads(data)
            if isinstance(code, types.CodeType):
                return code
    except (OSError, ValueError, EOFError, TypeError):  # missing, unreadable, damaged
        pass
    code = compile(source, filename, "exec", dont_inherit=True)
    try:
        if is_private(Path(entry)):
            data = marshal.dumps(code)
            atomic_write_bytes(path, _code_digest(secret, name, filename, source, data) + data, mode=0o600,
                               durable=False)
    except (OSError, ValueError):
        pass  # compiled again next time
    return code


def _models():
    return rebuilt_dir(cache_dir() / "models")


def load(key):
    """The cached module for ``key``, or None (missing, stale or damaged entries are removed)."""
    try:
        entry = _models() / key
        if not os.path.lexists(entry):
            return None
        if entry.is_symlink() or not entry.is_dir():
            raise NotADirectoryError(f"{entry} is not a folder")
        if not is_private(entry):
            warn_once(f"rotorkit cache entry {entry} is writable by others or not yours; "
                      "it is removed and rebuilt", topic=("entry", str(entry)))
            remove_path(entry)
            return None
        meta = json.loads(read_data(entry / "meta.json", what="cache metadata").decode("utf-8"))
        source = read_data(entry / "rhs.py", what="cache entry").decode("utf-8")
    except (OSError, ValueError) as exc:  # unreadable, a file in place of a folder, not UTF-8, not JSON
        return _discard(key, exc)
    try:
        digest = _digest(source)
    except OSError:  # the key cannot be read for now (secret_key): the entry is kept, the model built in memory
        return None
    valid = (isinstance(meta, dict) and meta.get("format") == FORMAT and meta.get("key") == key
             and isinstance(meta.get("hmac"), str) and hmac.compare_digest(meta["hmac"], digest))
    if valid:
        try:
            module = _execute(key, source, entry / "rhs.py")  # the text just verified, not a re-read
            if module.STATE_NAMES and len(module.STATE_NAMES) == 2 * module.N_COORDINATES:
                return module
        except Exception:  # noqa: BLE001 - a verified entry that does not run: rebuild it
            pass
    return _discard(key, None)


def _discard(key, error):
    """Remove a stale or damaged entry (warning once when it was damaged rather than stale)."""
    try:
        entry = cache_dir() / "models" / key
        if os.path.lexists(entry):
            remove_path(entry)
    except OSError:
        pass  # store() will find it unusable and build in memory
    if error is not None and not isinstance(error, (FileNotFoundError, json.JSONDecodeError, UnicodeDecodeError)):
        warn_once(f"rotorkit cache entry for model {key} was damaged ({error}); it is rebuilt",
                  topic=("damaged", key))
    return None


def store(key, source):
    """Write a generated module for ``key`` and run it (in memory, with one warning, if the cache cannot be written)."""
    try:
        entry = _models() / key
        if os.path.lexists(entry) and (entry.is_symlink() or not entry.is_dir() or not is_private(entry)):
            remove_path(entry)
        private_dir(entry)
        private_dir(entry / "__pycache__")  # before numba creates it with the umask
        secret = secret_key()
        atomic_write_text(entry / "rhs.py", source, mode=0o600)
        meta = {"format": FORMAT, "key": key, "hmac": _digest(source, secret)}
        atomic_write_text(entry / "meta.json", json.dumps(meta), mode=0o600)
    except OSError as exc:
        from ..errors import DiskFullError

        if isinstance(exc, DiskFullError):  # names the folder that is full
            warn_once(f"rotorkit cache cannot store model {key}: {exc}, or set ROTORKIT_CACHE_DIR to a folder on "
                       "a disk with space; the model is built in memory meanwhile", topic=("store", "disk full"))
            return _execute(key, source)
        warn_once(f"rotorkit cache cannot store model {key} ({exc}); it is built in memory "
                   "and compiled again in every process until the cache folder is usable "
                   "(see 'rotorkit cache info')", topic=("store", type(exc).__name__))
        return _execute(key, source)
    return _execute(key, source, entry / "rhs.py")


# -- numba's cache files ------------------------------------------------------


class _NotNow(OSError):
    """A read error that says nothing about the files (no file descriptor left, an I/O error): they cannot be
    checked now, and are neither used nor removed."""


def _read_or_none(path, what):
    """The bytes of ``path``; None if it is missing or damaged (not a regular file, too long); :class:`_NotNow`
    for any other error."""
    try:
        return read_data(path, what=what)
    except (FileNotFoundError, ValueError):
        return None
    except OSError as exc:
        raise _NotNow(exc.errno, f"{path}: {exc.strerror or exc}") from exc


def _signing_key(entry):
    """:func:`entry_key`, its read errors as :class:`_NotNow`."""
    try:
        return entry_key(entry)
    except OSError as exc:
        raise _NotNow(exc.errno, f"the signing key: {exc}") from exc


def _verify_numba_files(entry, folder=None, quiet=False):
    """Remove every file of ``folder`` (``entry/__pycache__``) that does not carry this user's signature (with a
    warning, unless ``quiet``: files this process was writing when it was interrupted, or a process that
    left its :data:`SAVING` mark, killed while saving). Called with the entry's lock held. :class:`_NotNow`
    where the key or a file cannot be read for now: nothing is removed then."""
    folder = entry / "__pycache__" if folder is None else folder
    private_dir(folder)
    interrupted = (entry / SAVING).exists()  # under the lock no process is saving: its writer died mid-save
    secret = _signing_key(entry)
    data = _read_or_none(entry / SIGNATURES, "cache metadata")
    try:
        signed = json.loads(data.decode("utf-8")) if data is not None else {}
        signed = signed if isinstance(signed, dict) else {}
    except ValueError:  # not UTF-8, not JSON: damaged
        signed = {}
    removed = []
    for path in folder.iterdir():
        good = False
        if path.is_file() and not path.is_symlink() and isinstance(signed.get(path.name), str):
            data = _read_or_none(path, "cache entry")
            good = data is not None and hmac.compare_digest(signed[path.name], _file_digest(secret, path.name, data))
        if not good:
            remove_path(path)
            removed.append(path.name)
    if interrupted:
        remove_path(entry / SAVING)
    if removed and not (quiet or interrupted):
        warn_once(f"rotorkit cache: removed {len(removed)} file(s) from {folder} that rotorkit did not sign "
                  f"({', '.join(sorted(removed)[:3])}{', ...' if len(removed) > 3 else ''}: damaged, "
                  "left by an interrupted run or planted); numba compiles again", topic=("numba", str(folder)))


def _sign_numba_files(entry, folder=None):
    secret = _signing_key(entry)
    folder = entry / "__pycache__" if folder is None else folder
    signed = {}
    for path in folder.iterdir():
        if path.is_file() and not path.is_symlink():
            os.chmod(path, 0o600)  # numba writes them with the umask
            signed[path.name] = _file_digest(secret, path.name, path.read_bytes())
    atomic_write_text(entry / SIGNATURES, json.dumps(signed, sort_keys=True), mode=0o600)


def _guard(dispatcher, entry, folder=None):
    """Make numba verify its cache files before reading them and sign them after writing; False if impossible.

    ``folder`` is where numba must keep them (default ``entry/__pycache__``);
    the signatures are in ``entry``. Both hold the entry's lock
    (:data:`NUMBA_LOCK`, :func:`shared_lock`): files another process has
    written but not signed yet are never taken for planted ones and removed
    (two processes compiling one model at the same time, as test workers do).
    """
    folder = entry / "__pycache__" if folder is None else folder
    function_cache = getattr(dispatcher, "_cache", None)
    path = getattr(function_cache, "_cache_path", None)
    load_overload = getattr(function_cache, "load_overload", None)
    save_overload = getattr(function_cache, "save_overload", None)
    if path is None or load_overload is None or save_overload is None:
        return False
    if os.path.realpath(path) != os.path.realpath(folder):
        return False  # NUMBA_CACHE_DIR or an unwritable entry: numba would read files we do not check

    def not_now(exc):  # nothing removed: what was signed stays valid for the next process
        warn_once(f"rotorkit cache: numba's cache in {path} cannot be checked now ({exc}); it is not used by this "
                  "process", topic=("numba-now", str(path)))

    def verified_load(*args, **kwargs):
        try:
            with shared_lock(NUMBA_LOCK, folder=entry):  # not while another process writes and signs
                _verify_numba_files(entry, folder)
                return load_overload(*args, **kwargs)
        except _NotNow as exc:
            not_now(exc)
            return None  # numba compiles
        except Exception as exc:  # noqa: BLE001 - a damaged cache file: compile instead
            warn_once(f"rotorkit cache: numba's cache in {path} could not be read ({type(exc).__name__}: {exc}); "
                      "it is removed and numba compiles again", topic=("numba-load", str(path)))
            shutil.rmtree(path, ignore_errors=True)
            return None

    def signed_save(*args, **kwargs):
        try:
            with shared_lock(NUMBA_LOCK, folder=entry):  # its files are unsigned until signed just below
                _verify_numba_files(entry, folder)  # numba reads its index again before adding to it
                atomic_write_text(entry / SAVING, str(os.getpid()), mode=0o600)  # a kill from here on: no warning
                try:
                    save_overload(*args, **kwargs)
                    _sign_numba_files(entry, folder)
                except BaseException:  # Ctrl-C while numba writes: what it wrote is unsigned, maybe partial
                    _verify_numba_files(entry, folder, quiet=True)
                    raise
                remove_path(entry / SAVING)
        except _NotNow as exc:  # unsigned files of this save (if any) keep the SAVING mark: removed quietly later
            not_now(exc)
        except Exception as exc:  # noqa: BLE001 - the compiled code works; only the disk copy is lost
            warn_once(f"rotorkit cache: numba's cache in {path} could not be written ({type(exc).__name__}: "
                      f"{exc}); the model is compiled again in the next process", topic=("numba-save", str(path)))
            shutil.rmtree(path, ignore_errors=True)

    function_cache.load_overload = verified_load
    function_cache.save_overload = signed_save
    return True


def jit(module, name, **options):
    """numba dispatcher for function ``name`` of a generated module, its on-disk cache verified.

    Only a module stored in a private cache entry gets numba's disk cache
    (``cache=True``), guarded as described in the module docstring; any other
    module (built in memory) is compiled without it.
    """
    import numba

    function = getattr(module, name)
    entry = getattr(module, "__rotorkit_entry__", None)
    if entry is not None:
        try:
            rebuilt_dir(entry / "__pycache__")
            dispatcher = numba.njit(cache=True, **options)(function)
            if _guard(dispatcher, entry):
                return dispatcher
        except (OSError, RuntimeError) as exc:  # numba: "cannot cache function ...: no locator available"
            warn_once(f"rotorkit cache: numba's disk cache cannot be used for {entry} ({exc}); "
                      "compiling in memory", topic=("numba-jit", str(entry)))
    return numba.njit(cache=False, **options)(function)


def shared_dir(name):
    """``<cache>/shared/<name>``, created private (rebuilt if it is not); OSError if it cannot be used."""
    return rebuilt_dir(rebuilt_dir(cache_dir() / "shared") / name)


def jit_shared(function, name, signature, **options):
    """numba dispatcher for a function of rotorkit itself (the integration loop), compiled for ``signature``.

    numba would keep its cache beside the package (or, where that is not
    writable, in a per-user folder it creates with the umask) and read it
    unchecked. Here it is kept in the private cache, ``<cache>/shared/<name>``,
    verified and signed like a model's (see the module docstring).
    """
    import numba

    try:
        entry = shared_dir(name)
        saved = numba.config.CACHE_DIR
        numba.config.CACHE_DIR = str(entry)  # read when the dispatcher's cache is set up, just below
        try:
            dispatcher = numba.njit(cache=True, **options)(function)
        finally:
            numba.config.CACHE_DIR = saved
        folder = Path(getattr(getattr(dispatcher, "_cache", None), "_cache_path", "") or entry / "missing")
        if _guard(dispatcher, entry, folder):
            dispatcher.compile(signature.args)  # loads the verified cache, or compiles and signs
            dispatcher.disable_compile()  # as njit(signature) does: arguments convert to it, no specialisations
            return dispatcher
    except (OSError, RuntimeError) as exc:
        warn_once(f"rotorkit cache: numba's disk cache cannot be used for {name} ({exc}); compiling in memory",
                  topic=("numba-shared", name))
    dispatcher = numba.njit(cache=False, **options)(function)
    dispatcher.compile(signature.args)
    dispatcher.disable_compile()
    return dispatcher


def shared_is_current(name, source):
    """True if ``<cache>/shared/<name>`` holds signed numba cache files newer than the Python file ``source``.

    A cheap look at file names and times (nothing is read or verified): used
    only to decide whether compiling ahead in another process is worth it;
    loading still verifies everything.
    """
    try:
        entry = cache_dir() / "shared" / name
        signed = json.loads(read_data(entry / SIGNATURES, what="cache metadata").decode("utf-8"))
        newest_source = os.stat(source).st_mtime
        index = [p for p in entry.glob("*/*.nbi") if p.name in signed]
        data = [p for p in entry.glob("*/*.nbc") if p.name in signed]
        return bool(data) and any(p.stat().st_mtime >= newest_source for p in index)
    except (OSError, ValueError, TypeError):
        return False


def info():
    """(folder, number of cached models, bytes on disk)."""
    base = cache_dir()
    models = base / "models"
    try:
        count = sum(1 for p in models.iterdir() if p.is_dir()) if models.is_dir() else 0
    except OSError:
        count = 0
    size = 0
    for root, _dirs, files in os.walk(base):
        for name in files:
            try:
                size += os.lstat(os.path.join(root, name)).st_size
            except OSError:
                pass
    return base, count, size


def clear():
    """Remove every cached model (and numba's machine code beside it); returns how many."""
    base, count, _ = info()
    models = base / "models"

    if os.path.lexists(models):
        remove_path(models)
    return count
