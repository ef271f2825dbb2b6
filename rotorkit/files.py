"""Atomic file writes: a file is either complete or absent, never half-written."""

import os
import tempfile
from pathlib import Path

__all__ = ["atomic_write_bytes", "atomic_write_text"]


def atomic_write_bytes(path, data, *, mode=None, durable=True):
    """Write ``data`` to ``path`` through a temporary file in the same folder and a rename.

    ``mode`` (e.g. ``0o600``) sets the file's permissions; by default they
    follow the umask like any new file. ``durable=False`` skips the ``fsync``
    before the rename: the file is still whole or absent after the process is
    killed, but after a power cut it may be empty (for files whose reader
    checks them and recomputes a damaged one, such as sweep points).
    """
    path = Path(path)
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
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def atomic_write_text(path, text, *, mode=None):
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    atomic_write_bytes(path, text.encode("utf-8"), mode=mode)


MANIFEST = "manifest.json"


def check_output_folder(path, option="--out"):
    """The output folder ``path``, checked before any work: ParameterError if it cannot be written.

    Refused: a file (or a device such as ``/dev/null``) where the folder should
    be, a name too long for the file system, a parent that cannot be created
    or written (read-only, not a folder). A probe folder is created and removed
    in the nearest existing ancestor, so a read-only file system is found even
    for a user whose permission bits say "writable".
    """
    import shutil

    from .errors import ParameterError

    path = Path(path)
    where = f"{option} {str(path)!r}"
    for part in path.parts:
        if len(os.fsencode(part)) > 255:
            raise ParameterError(f"{where}: the name {part[:20]!r}... has {len(os.fsencode(part))} bytes; "
                                 "file systems allow 255: choose a shorter name")
    if len(os.fsencode(str(path.absolute()))) > 4000:
        raise ParameterError(f"{where}: the path is too long; choose a shorter one")
    if path.exists() and not path.is_dir():
        raise ParameterError(f"{where} is a file or device, not a folder: give a folder to write the outputs into")
    probe_in = path if path.is_dir() else path.parent
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


def write_folder(out, write):
    """Write a run's outputs so they land together: complete, or absent.

    ``write(folder)`` writes the files into a fresh staging folder beside
    ``out`` and returns their paths (inside it); a ``manifest.json`` listing
    them (name, size, SHA-256) is written last. If ``out`` does not exist the
    staging folder is renamed to it (one atomic step). If it exists, its old
    manifest is removed first, the files are moved in and the manifest last:
    a folder without ``manifest.json`` is incomplete and is not to be read.
    If writing fails, the staging folder is kept and named in the error.

    Returns
    -------
    list of Path
        The files in ``out``, manifest last.
    """
    import hashlib
    import json

    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.rotorkit-"))
    try:
        names = [Path(p).name for p in write(staging)]
        entries = []
        for name in names:
            data = (staging / name).read_bytes()
            entries.append({"name": name, "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()})
        atomic_write_text(staging / MANIFEST, json.dumps({"files": entries}, indent=2))
    except BaseException as exc:
        if isinstance(exc, OSError):
            raise OSError(exc.errno, f"writing the outputs failed ({exc.strerror or exc}); what was written "
                                     f"is in {staging}") from exc
        raise
    if not out.exists():
        os.rename(staging, out)
    else:
        try:
            (out / MANIFEST).unlink(missing_ok=True)
            for name in names:
                os.replace(staging / name, out / name)
            os.replace(staging / MANIFEST, out / MANIFEST)
            staging.rmdir()
        except OSError as exc:
            raise OSError(exc.errno, f"moving the outputs into {out} failed ({exc.strerror or exc}); "
                                     f"they are in {staging}") from exc
    return [out / name for name in names] + [out / MANIFEST]
