"""Files in and out, bounded and atomic.

Reading: every file rotorkit reads as data (model files, result files, sweep
manifests and points, cache entries) goes through :func:`read_data` or
:func:`open_data`, which check the path, the kind (a regular file, after
following symbolic links) and the size before reading, and never read more
than the bound. Writing: a file is either complete or absent, never
half-written (:func:`atomic_write_bytes`), and a run's folder is replaced as a
whole (:func:`write_folder`); nothing that is not a regular file or a folder
of ours is ever replaced.
"""

import os
import stat
import tempfile
from pathlib import Path

__all__ = ["atomic_write_bytes", "atomic_write_text", "check_path", "read_data", "open_data", "check_output_file",
           "check_output_folder", "write_folder", "disk_full", "LIMITS"]

#: largest file of each kind rotorkit reads (bytes); the bound is checked with ``stat`` before reading
LIMITS = {
    "model file": 8 * 2**20,
    "result file": 8 * 10**9,
    "sweep manifest": 16 * 2**20,
    "sweep point": 2**30,
    "cache entry": 2**30,
    "cache metadata": 16 * 2**20,
}


def _kind(mode):
    """The kind of file a ``st_mode`` describes, in words."""
    for test, word in ((stat.S_ISDIR, "folder"), (stat.S_ISFIFO, "named pipe (FIFO)"),
                       (stat.S_ISCHR, "character device"), (stat.S_ISBLK, "block device"),
                       (stat.S_ISSOCK, "socket"), (stat.S_ISREG, "regular file")):
        if test(mode):
            return word
    return "special file"


def check_path(path, what="path"):
    """``path`` as a :class:`~pathlib.Path`; ParameterError for None, bytes, an empty text or a NUL byte.

    Parameters
    ----------
    path : str or os.PathLike
    what : str
        What the path names, for the message (``"model file"``, ``"--out"``).
    """
    from .errors import ParameterError

    if isinstance(path, (bytes, bytearray, memoryview)) or not isinstance(path, (str, os.PathLike)):
        raise ParameterError(f"{what} = {path!r}: expected a path as text or a pathlib.Path")
    text = os.fspath(path)
    if not isinstance(text, str):
        raise ParameterError(f"{what} = {path!r}: expected a path as text or a pathlib.Path, not bytes")
    if text == "":
        raise ParameterError(f"{what} = '': the path is empty; give a file or folder name")
    if "\0" in text:
        raise ParameterError(f"{what} = {text!r}: the path holds a NUL byte, which no file name can")
    return Path(text)


def open_data(path, *, what, max_bytes=None, error=None):
    """Open ``path`` for binary reading once it is known to be a regular file of at most ``max_bytes``.

    The kind and size are checked with ``stat`` (following symbolic links)
    before opening, and again on the open file (so a file swapped in between
    is caught); a FIFO, a device (``/dev/zero``, ``/dev/urandom``, a symbolic
    link to one), a folder or a socket is refused without reading a byte.

    Parameters
    ----------
    path : str or os.PathLike
    what : str
        The kind of file, a key of :data:`LIMITS` or any words for messages.
    max_bytes : int, optional
        Size bound (bytes); default ``LIMITS[what]``.
    error : type, optional
        The ParameterError subclass to raise (default ParameterError).

    Returns
    -------
    file object
        Open in binary mode, positioned at the start; the caller closes it.

    Raises
    ------
    ParameterError
        A bad path, not a regular file, or larger than the bound.
    FileNotFoundError, PermissionError, OSError
        The file cannot be opened.
    """
    from .errors import ParameterError

    error = error or ParameterError
    try:
        path = check_path(path, what)
    except ParameterError as exc:
        raise error(str(exc)) from None
    limit = LIMITS.get(what, LIMITS["cache entry"]) if max_bytes is None else int(max_bytes)

    def check(st):
        if not stat.S_ISREG(st.st_mode):
            raise error(f"{path}: a {what} must be a regular file; this is a {_kind(st.st_mode)}, which is not read")
        if st.st_size > limit:
            raise error(f"{path}: {st.st_size} bytes; a {what} is at most {limit} bytes ({limit / 2**20:.4g} MiB), "
                        "so it is not read")

    check(os.stat(path))
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    fd = os.open(path, flags | getattr(os, "O_BINARY", 0))
    try:
        check(os.fstat(fd))
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_data(path, *, what, max_bytes=None, error=None):
    """The bytes of ``path``, a regular file of at most ``max_bytes`` (see :func:`open_data`).

    Never reads more than the bound, even from a file that grows while it is read.
    """
    limit = LIMITS.get(what, LIMITS["cache entry"]) if max_bytes is None else int(max_bytes)
    with open_data(path, what=what, max_bytes=limit, error=error) as fh:
        data = fh.read(limit + 1)
    if len(data) > limit:
        from .errors import ParameterError

        raise (error or ParameterError)(f"{path}: grew beyond {limit} bytes while it was read; a {what} is at "
                                        f"most {limit} bytes")
    return data


def _refuse_non_regular(path, what):
    """ParameterError if ``path`` exists and is not a regular file (a device, FIFO, folder, socket): never replaced."""
    from .errors import ParameterError

    try:
        st = os.stat(path)  # follows a symbolic link: the kind of what it points at
    except FileNotFoundError:  # nothing there (or a dangling link, replaced by the file: harmless)
        return
    except OSError:
        return  # the write itself will report it
    if not stat.S_ISREG(st.st_mode):
        raise ParameterError(f"{what} {str(path)!r} exists and is a {_kind(st.st_mode)}, not a regular file; "
                             "rotorkit replaces only regular files: give another path")


def _mount_point(folder):
    """The folder where the file system holding ``folder`` (or its nearest existing parent) is mounted."""
    path = Path(os.path.abspath(folder))
    while not path.exists() and path != path.parent:
        path = path.parent
    try:
        dev = path.stat().st_dev
        while path != path.parent and path.parent.stat().st_dev == dev:
            path = path.parent
    except OSError:
        pass
    return path


def _size(n):
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n} bytes"


def disk_full(exc, folder, what, advice="free space there, or write to a folder on another disk"):
    """A :class:`~rotorkit.errors.DiskFullError` naming ``folder`` if ``exc`` is "no space left" (``ENOSPC``) or
    "quota exceeded" (``EDQUOT``); otherwise ``exc`` itself. ``what`` says what could not be written."""
    import errno
    import shutil

    from .errors import DiskFullError

    if not isinstance(exc, OSError) or exc.errno not in (errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC)):
        return exc
    mount = _mount_point(folder)
    try:
        usage = shutil.disk_usage(mount)
        space = f"{_size(usage.free)} free of {_size(usage.total)}"
    except OSError:
        space = "free space unknown"
    reason = "the disk quota is reached" if exc.errno != errno.ENOSPC else "no space is left"
    return DiskFullError(exc.errno, f"{what} could not be written: {reason} on the disk holding {folder} "
                                    f"(file system mounted at {mount}, {space}); {advice}")


def atomic_write_bytes(path, data, *, mode=None, durable=True, exclusive=False):
    """Write ``data`` to ``path`` through a temporary file in the same folder and a rename.

    ``mode`` (e.g. ``0o600``) sets the file's permissions; by default they
    follow the umask like any new file. ``durable=False`` skips the ``fsync``
    before the rename: the file is still whole or absent after the process is
    killed, but after a power cut it may be empty (for files whose reader
    checks them and recomputes a damaged one, such as sweep points).
    ``exclusive=True`` writes it only if ``path`` does not exist (a hard link
    instead of the rename: of two processes creating it at once, one writes
    it and the other is told so); returns whether it was written (always True
    without ``exclusive``; on a file system without hard links it is replaced).
    """
    path = check_path(path, "file")
    _refuse_non_regular(path, "the file")
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        if mode is None:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.fchmod(fd, mode) if hasattr(os, "fchmod") else None  # mkstemp makes it 0600
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            if durable:
                os.fsync(fh.fileno())
        if exclusive:
            try:
                os.link(tmp, path)
                return True
            except FileExistsError:
                return False
            except OSError:  # no hard links here (some network or FAT file systems)
                pass
        os.replace(tmp, path)
        return True
    except BaseException as exc:
        full = disk_full(exc, path.parent, str(path))
        if full is not exc:
            raise full from exc
        raise
    finally:
        if os.path.exists(tmp):  # an error, or the link made (the file has its own name now)
            os.unlink(tmp)


def atomic_write_text(path, text, *, mode=None):
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    atomic_write_bytes(path, text.encode("utf-8"), mode=mode)


MANIFEST = "manifest.json"


def check_output_file(path, option="--out"):
    """The output file ``path``, checked before any work: ParameterError if it must not or cannot be written.

    Refused: ``''``, None, bytes or a NUL byte; an existing path that is not a
    regular file (a folder, a FIFO, a device such as ``/dev/full``, a link to
    one), which is never replaced; a parent that is a file or cannot be
    written.
    """
    from .errors import ParameterError

    path = check_path(path, option)
    where = f"{option} {str(path)!r}"
    if str(path).endswith(("/", os.sep)):
        raise ParameterError(f"{where} names a folder; give a file name")
    if len(os.fsencode(path.name)) > 255:
        raise ParameterError(f"{where}: the name has {len(os.fsencode(path.name))} bytes; file systems allow 255")
    _refuse_non_regular(path, option)
    parent = path.parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise ParameterError(f"{where}: {str(parent)!r} is a file, so the file cannot be created in it")
    if not os.access(parent, os.W_OK):
        raise ParameterError(f"{where}: cannot write in {str(parent)!r}; give a folder you can write")
    return path


def check_output_folder(path, option="--out", *, ours=True):
    """The output folder ``path``, checked before any work: ParameterError if it cannot be written.

    Refused: ``''``, None, bytes or a NUL byte; a file (or a device such as
    ``/dev/null``) where the folder should be; with ``ours`` (the default), an
    existing folder that is neither empty nor an earlier run's (it would be
    replaced as a whole by :func:`write_folder`); a name too long for the file system, a parent that cannot be created
    or written (read-only, not a folder). A probe folder is created and removed
    in the nearest existing ancestor, so a read-only file system is found even
    for a user whose permission bits say "writable".
    """
    import shutil

    from .errors import ParameterError

    path = check_path(path, option)
    where = f"{option} {str(path)!r}"
    for part in path.parts:
        if len(os.fsencode(part)) > 255:
            raise ParameterError(f"{where}: the name {part[:20]!r}... has {len(os.fsencode(part))} bytes; "
                                 "file systems allow 255: choose a shorter name")
    if len(os.fsencode(str(path.absolute()))) > 4000:
        raise ParameterError(f"{where}: the path is too long; choose a shorter one")
    if path.exists() and not path.is_dir():
        raise ParameterError(f"{where} is a file or device, not a folder: give a folder to write the outputs into")
    if path.is_dir() and ours:
        _check_ours(path, option)
    probe_in = Path(os.path.abspath(path)).parent  # the run is staged beside the folder, then moved in
    while not probe_in.exists():
        probe_in = probe_in.parent
    if not probe_in.is_dir():
        raise ParameterError(f"{where}: {str(probe_in)!r} is a file, so the folder cannot be created")
    try:
        shutil.rmtree(tempfile.mkdtemp(dir=probe_in, prefix=".rotorkit-probe-"))
    except OSError as exc:
        raise ParameterError(f"{where}: cannot write in {str(probe_in)!r} ({exc.strerror or exc}); "
                             "give a folder you can write") from exc
    return path


#: files rotorkit itself may leave in a run's folder beside those its manifest lists
_OURS_UNLISTED = ("signals-partial.npz",)


def _stage(name):
    """A hook at each step of moving a run into place (the tests kill the process here); does nothing."""


def _check_ours(out, option="--out"):
    """ParameterError unless the existing folder ``out`` is empty or holds a rotorkit run (so it may be replaced)."""
    import json

    from .errors import ParameterError

    names = sorted(os.listdir(out))
    if not names:
        return
    listed = set()
    if MANIFEST in names:
        try:
            manifest = json.loads(read_data(out / MANIFEST, what="run manifest", max_bytes=LIMITS["sweep manifest"]))
            listed = {f["name"] for f in manifest["files"]}
        except (OSError, ValueError, KeyError, TypeError):
            raise ParameterError(f"{option} {str(out)!r}: its {MANIFEST} is damaged, so it is not known which "
                                 "files are an earlier run's; give another folder, or remove this one") from None
    foreign = [n for n in names if n not in listed and n != MANIFEST and n not in _OURS_UNLISTED
               and not n.startswith(".rotorkit-probe-")]
    if foreign:
        shown = ", ".join(foreign[:5]) + (", ..." if len(foreign) > 5 else "")
        raise ParameterError(f"{option} {str(out)!r} holds files that are not a rotorkit run's ({shown}); the "
                             "folder would be replaced as a whole: give a new or empty folder, or an earlier "
                             "run's folder")


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def _remove_abandoned(out):
    """Remove staging folders beside ``out`` that a killed run left (their process is gone)."""
    import re
    import shutil

    pattern = re.compile(rf"^\.{re.escape(out.name)}\.rotorkit-(\d+)-")
    try:
        siblings = os.listdir(out.parent)
    except OSError:
        return
    for name in siblings:
        match = pattern.match(name)
        if match and int(match.group(1)) != os.getpid() and not _alive(int(match.group(1))):
            shutil.rmtree(out.parent / name, ignore_errors=True)


def _exchange(a, b):
    """Swap the folders ``a`` and ``b`` in one atomic step (Linux ``renameat2``); False where it is not possible."""
    import sys

    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = (ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint)
    at_fdcwd, rename_exchange = -100, 2
    if renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
        return True
    import errno

    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.EPERM):
        return False  # the file system cannot exchange: fall back to two renames
    raise OSError(err, os.strerror(err), str(b))


def write_folder(out, write):
    """Write a run's outputs so they land together: the complete new run, or the complete old one.

    ``write(folder)`` writes the files into a fresh staging folder beside
    ``out`` and returns their paths (inside it); a ``manifest.json`` listing
    them (name, size, SHA-256) is written last. If ``out`` does not exist the
    staging folder is renamed to it (one atomic step). If it exists (empty, or
    an earlier run's folder: anything else is refused before writing), the two
    folders are exchanged in one atomic step (``renameat2(RENAME_EXCHANGE)``
    on Linux; elsewhere two renames) and the old run is removed: a process
    killed at any moment leaves the complete old run or the complete new one
    in ``out``, never a mix, and no file of the old run stays beside the new
    one. If writing fails, the staging folder is kept and named in the error.

    Returns
    -------
    list of Path
        The files in ``out``, manifest last.
    """
    import hashlib
    import json
    import shutil

    out = Path(os.path.abspath(check_output_folder(out)))
    out.parent.mkdir(parents=True, exist_ok=True)
    _remove_abandoned(out)
    staging = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.rotorkit-{os.getpid()}-"))
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(staging, 0o777 & ~umask)  # mkdtemp makes it 0700; the run's folder gets a new folder's mode
    try:
        names = [Path(p).name for p in write(staging)]
        entries = []
        for name in names:
            data = (staging / name).read_bytes()
            entries.append({"name": name, "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()})
        atomic_write_text(staging / MANIFEST, json.dumps({"files": entries}, indent=2))
    except BaseException as exc:
        full = disk_full(exc, out.parent, f"the outputs of {out}",
                         f"what was written is in {staging}; free space there, or give an output folder on "
                         "another disk")
        if full is not exc:
            raise full from exc
        if isinstance(exc, OSError):
            raise OSError(exc.errno, f"writing the outputs failed ({exc.strerror or exc}); what was written "
                                     f"is in {staging}") from exc
        raise
    _stage("staged")
    try:
        if not out.exists():
            os.rename(staging, out)
            _stage("moved")
        elif _exchange(staging, out):  # staging now holds the old run
            _stage("exchanged")
            shutil.rmtree(staging)
            _stage("removed")
        else:
            old = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.rotorkit-{os.getpid()}-old-"))
            os.rename(out, old / "run")
            _stage("old moved aside")
            os.rename(staging, out)
            _stage("moved")
            shutil.rmtree(old)
            _stage("removed")
    except OSError as exc:
        raise OSError(exc.errno, f"moving the outputs into {out} failed ({exc.strerror or exc}); "
                                 f"they are in {staging}") from exc
    return [out / name for name in names] + [out / MANIFEST]
