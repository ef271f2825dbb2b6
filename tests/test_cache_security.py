"""The model cache runs only what rotorkit wrote, and a damaged cache never stops a run.

Each planted file below would run code (create a marker file) if it were
loaded; a control in each test shows that it does, when loaded the way
Python or numba would load it without rotorkit's checks.
"""

import importlib.util
import os
import pickle
import stat
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotorkit as rk
from rotorkit import system as system_module
from rotorkit.codegen import cache, cache_folders
from rotorkit.symbolic import lagrange

pytest.importorskip("numba")
POSIX = pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(cache_folders.tempfile, "tempdir", str(tmp_path / "tmp"))  # fallback folders stay in tmp_path
    (tmp_path / "tmp").mkdir()
    forget(monkeypatch)
    return tmp_path / "cache"


def forget(monkeypatch):
    """A new process: nothing in memory, no warning given yet."""
    monkeypatch.setattr(system_module, "_MODULES", {})
    monkeypatch.setattr(system_module, "_JIT_CACHE", {})
    monkeypatch.setattr(lagrange, "_CACHE", {})
    monkeypatch.setattr(cache_folders, "_WARNED", set())


def jeffcott():
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=50.0),
                     rk.Disk(station=1, mass=1.0, radius=0.1, eccentricity=1e-4),
                     rk.ElasticSupport(station=1, stiffness=1e4, damping=2.0)])


Y = np.r_[1e-3, 0.0, 0.0, 0.0]
EXPECTED = -1e4 * 1e-3 + 1e-4 * 50.0**2  # x'' at t = 0: -k x / m + e w^2


def run(backend="numba"):
    """Compile and evaluate the RHS once (numba compiles, or loads its cache, here)."""
    system = jeffcott().compile(backend=backend)
    return system.rhs(0.0, Y)[2]


def entry_of(folder):
    return folder / "models" / jeffcott().structure_key


class Planted:
    """Unpickling this creates ``marker``: what a hostile cache file would do."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return open, (self.marker, "w")


def cache_warnings(record):
    return [w for w in record if issubclass(w.category, cache.CacheWarning)]


def numba_files(entry, suffix):
    files = sorted((entry / "__pycache__").glob(f"*{suffix}"))
    assert files, f"numba wrote no {suffix} file in {entry / '__pycache__'}"
    return files


@pytest.mark.parametrize("suffix", [".nbi", ".nbc"])
def test_a_planted_numba_cache_file_is_never_unpickled(fresh_cache, tmp_path, monkeypatch, suffix):
    assert run() == pytest.approx(EXPECTED)
    entry = entry_of(fresh_cache)
    marker = tmp_path / "ran"
    for path in numba_files(entry, suffix):
        path.write_bytes(pickle.dumps(Planted(marker)))
    forget(monkeypatch)
    with pytest.warns(cache.CacheWarning, match="did not sign"):
        assert run() == pytest.approx(EXPECTED)
    assert not marker.exists()
    # control: numba's own loader (pickle) would have run it
    pickle.loads(pickle.dumps(Planted(marker)))
    assert marker.exists()


def test_a_planted_pyc_with_a_matching_header_is_never_loaded(fresh_cache, tmp_path, monkeypatch):
    run(backend="python")
    entry = entry_of(fresh_cache)
    source = entry / "rhs.py"
    marker = tmp_path / "ran"
    hostile = source.read_text() + f"\nopen({str(marker)!r}, 'w').close()\n"
    st = source.stat()
    code = compile(hostile, str(source), "exec")
    pyc = importlib._bootstrap_external._code_to_timestamp_pyc(code, st.st_mtime, st.st_size)
    target = importlib.util.cache_from_source(str(source))
    os.makedirs(os.path.dirname(target), exist_ok=True)
    with open(target, "wb") as fh:
        fh.write(pyc)
    forget(monkeypatch)
    assert run(backend="python") == pytest.approx(EXPECTED)
    assert not marker.exists()
    # control: Python's import machinery (what the cache used before) takes the planted .pyc
    spec = importlib.util.spec_from_file_location("control_module", source)
    spec.loader.exec_module(importlib.util.module_from_spec(spec))
    assert marker.exists()
    marker.unlink()
    with pytest.warns(cache.CacheWarning, match="did not sign"):  # numba's folder holds only signed files
        assert run(backend="numba") == pytest.approx(EXPECTED)
    assert not marker.exists() and not os.path.exists(target)


@pytest.mark.parametrize("damage", ["truncated", "garbage"])
@pytest.mark.parametrize("suffix", [".nbi", ".nbc"])
def test_a_damaged_signed_numba_file_is_rebuilt_with_one_warning(fresh_cache, monkeypatch, damage, suffix):
    """Signed (so they pass the check) but unreadable: numba's bare UnpicklingError becomes one warning."""
    run()
    entry = entry_of(fresh_cache)
    for path in numba_files(entry, suffix):
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 3] if damage == "truncated" else os.urandom(len(data)))
    cache._sign_numba_files(entry)
    forget(monkeypatch)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        assert run() == pytest.approx(EXPECTED)
        forget_only_memory(monkeypatch)
        assert run() == pytest.approx(EXPECTED)
    assert len(cache_warnings(record)) == 1, [str(w.message) for w in record]
    forget(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error", cache.CacheWarning)
        assert run() == pytest.approx(EXPECTED)  # repaired: the next process is quiet


def test_a_ctrl_c_while_numba_writes_leaves_no_unsigned_file(fresh_cache, monkeypatch):
    """Interrupted after numba wrote its files and before rotorkit signed them: they are removed quietly (they
    may be partial), so the next process neither warns of planted files nor reads them."""
    from numba.core import caching

    save = caching.Cache.save_overload

    def interrupted(self, *args, **kwargs):
        save(self, *args, **kwargs)
        raise KeyboardInterrupt

    monkeypatch.setattr(caching.Cache, "save_overload", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run()
    monkeypatch.setattr(caching.Cache, "save_overload", save)
    folder = entry_of(fresh_cache) / "__pycache__"
    assert folder.is_dir() and not any(folder.iterdir()), sorted(p.name for p in folder.iterdir())
    forget(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error", cache.CacheWarning)
        assert run() == pytest.approx(EXPECTED)
    assert numba_files(entry_of(fresh_cache), ".nbi")  # saved and signed this time


def test_files_compiled_after_the_cache_folder_changed_are_signed_with_their_own_caches_key(fresh_cache, tmp_path,
                                                                                           monkeypatch):
    """A process keeps the modules it has loaded when ROTORKIT_CACHE_DIR changes (a test's temporary cache);
    numba then compiles their functions into their own entries, which must be signed with the key of the cache
    holding them: the next process that uses that cache loads them without a warning of unsigned files."""
    from rotorkit.system import jacobian_module

    model = jeffcott()
    system = model.compile(backend="numba")
    entry = jacobian_module(model, "unrolled").__rotorkit_entry__  # generated and stored, numba has not compiled
    assert entry.parent.parent == fresh_cache and not any((entry / "__pycache__").iterdir())
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "another cache"))
    system.jacobian(0.0, Y)  # numba compiles jac and saves it into the first cache's entry
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(fresh_cache))
    assert numba_files(entry, ".nbc")
    with warnings.catch_warnings():
        warnings.simplefilter("error", cache.CacheWarning)
        with cache.shared_lock(cache.NUMBA_LOCK, folder=entry):
            cache._verify_numba_files(entry)  # what the next process does before numba reads them
    assert numba_files(entry, ".nbc") and numba_files(entry, ".nbi")


KILLED_WHILE_SAVING = """
import os, signal
from numba.core import caching
import rotorkit as rk

save = caching.Cache.save_overload


def killed(self, *args, **kwargs):  # numba has written its files; rotorkit has not signed them yet
    save(self, *args, **kwargs)
    os.kill(os.getpid(), signal.SIGKILL)


caching.Cache.save_overload = killed
model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=50.0),
                  rk.Disk(station=1, mass=1.0, radius=0.1, eccentricity=1e-4),
                  rk.ElasticSupport(station=1, stiffness=1e4, damping=2.0)])
model.compile(backend="numba").rhs(0.0, [1e-3, 0.0, 0.0, 0.0])
"""


@POSIX
def test_files_of_a_process_killed_while_saving_are_removed_without_a_warning(fresh_cache, monkeypatch):
    """SIGKILL (the OOM killer, a sweep test killing its worker) between numba's writing and rotorkit's signing
    leaves unsigned files and the saving mark: the next process removes them quietly and compiles; files
    without that mark are still removed with a warning (the other tests here)."""
    import signal
    import subprocess
    import sys

    child = subprocess.run([sys.executable, "-c", KILLED_WHILE_SAVING], capture_output=True, text=True, timeout=300,
                           env={**os.environ, "ROTORKIT_CACHE_DIR": str(fresh_cache)})
    assert child.returncode == -signal.SIGKILL, child.stderr
    entry = entry_of(fresh_cache)
    assert (entry / cache.SAVING).exists() and numba_files(entry, ".nbi")  # unsigned: not in numba.sig.json
    forget(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error", cache.CacheWarning)
        assert run() == pytest.approx(EXPECTED)
    assert not (entry / cache.SAVING).exists()
    forget(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error", cache.CacheWarning)
        assert run() == pytest.approx(EXPECTED)  # saved and signed this time: loaded as it is


WRITER = """
import sys, time
from pathlib import Path
from rotorkit.codegen import cache
entry = Path(sys.argv[1])
with cache.shared_lock(cache.NUMBA_LOCK, folder=entry):
    (entry / "__pycache__" / "in_flight.nbi").write_bytes(b"written, not signed yet")
    print("writing", flush=True)
    time.sleep(1.5)
    cache._sign_numba_files(entry)
"""


def test_files_another_process_is_writing_are_not_taken_for_planted_ones(fresh_cache, monkeypatch):
    """A process that loads a model's numba cache waits for one that is writing and signing it (two test workers
    compiling one model): before, it found the other's files unsigned, removed them and warned."""
    import subprocess
    import sys

    run()
    entry = entry_of(fresh_cache)
    forget(monkeypatch)
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(entry)], stdout=subprocess.PIPE, text=True,
                              env={**os.environ, "ROTORKIT_CACHE_DIR": str(fresh_cache)})
    try:
        assert writer.stdout.readline().strip() == "writing"
        with warnings.catch_warnings(record=True) as record:
            warnings.simplefilter("always")
            assert run() == pytest.approx(EXPECTED)
    finally:
        writer.wait(timeout=60)
    assert writer.returncode == 0
    assert not cache_warnings(record), [str(w.message) for w in record]
    assert (entry / "__pycache__" / "in_flight.nbi").exists()


def forget_only_memory(monkeypatch):
    monkeypatch.setattr(system_module, "_MODULES", {})
    monkeypatch.setattr(system_module, "_JIT_CACHE", {})


@POSIX
def test_every_folder_and_file_is_private_under_a_permissive_umask(fresh_cache):
    old = os.umask(0)
    try:
        run()
        run(backend="python")
    finally:
        os.umask(old)
    checked = 0
    for root, dirs, files in os.walk(fresh_cache):
        for name in dirs + files:
            mode = os.lstat(os.path.join(root, name)).st_mode
            assert not mode & 0o077, f"{os.path.join(root, name)} has mode {stat.filemode(mode)}"
            checked += 1
    assert not os.stat(fresh_cache).st_mode & 0o077
    assert checked >= 7  # models, entry, __pycache__, rhs.py, meta.json, secret.key, numba files


@POSIX
@pytest.mark.parametrize("where", ["models", "entry", "__pycache__"])
def test_a_folder_others_can_write_is_refused_and_rebuilt(fresh_cache, tmp_path, monkeypatch, where):
    run()
    entry = entry_of(fresh_cache)
    folder = {"models": fresh_cache / "models", "entry": entry, "__pycache__": entry / "__pycache__"}[where]
    folder.chmod(0o777)
    marker = tmp_path / "ran"
    for path in numba_files(entry, ".nbi"):
        path.write_bytes(pickle.dumps(Planted(marker)))
    cache._sign_numba_files(entry)  # even files that look signed: the folder itself is not trusted
    forget(monkeypatch)
    with pytest.warns(cache.CacheWarning):
        assert run() == pytest.approx(EXPECTED)
    assert not marker.exists()
    assert not folder.stat().st_mode & 0o077


@pytest.mark.parametrize("damage", ["entry-is-a-file", "models-is-a-file", "key-is-a-folder", "meta-is-a-folder",
                                    "unreadable-entry", "unreadable-cache"])
def test_a_damaged_cache_folder_is_rebuilt_with_one_warning(fresh_cache, monkeypatch, damage):
    run()
    entry = entry_of(fresh_cache)
    if damage == "entry-is-a-file":
        cache.remove_path(entry)
        entry.write_text("not a folder")
    elif damage == "models-is-a-file":
        cache.remove_path(fresh_cache / "models")
        (fresh_cache / "models").write_text("not a folder")
    elif damage == "key-is-a-folder":
        (fresh_cache / "secret.key").unlink()
        (fresh_cache / "secret.key").mkdir()
    elif damage == "meta-is-a-folder":
        (entry / "meta.json").unlink()
        (entry / "meta.json").mkdir()
    else:
        folder = entry if damage == "unreadable-entry" else fresh_cache
        folder.chmod(0)
        if os.geteuid() == 0:  # root reads anything: make the checks see what a user would
            real_access, real_read = os.access, type(entry).read_text

            def access(path, mode, **kwargs):
                if os.path.abspath(path) == str(folder) and not os.stat(path).st_mode & 0o700:
                    return False
                return real_access(path, mode, **kwargs)

            def read_text(self, *args, **kwargs):
                if str(self).startswith(str(folder) + os.sep) and not folder.stat().st_mode & 0o700:
                    raise PermissionError(13, "Permission denied", str(self))
                return real_read(self, *args, **kwargs)

            real_open = os.open

            def os_open(path, *args, **kwargs):  # rotorkit.files.read_data opens with os.open
                if str(path).startswith(str(folder) + os.sep) and not folder.stat().st_mode & 0o700:
                    raise PermissionError(13, "Permission denied", str(path))
                return real_open(path, *args, **kwargs)

            monkeypatch.setattr(os, "access", access)
            monkeypatch.setattr(type(entry), "read_text", read_text)
            monkeypatch.setattr(os, "open", os_open)
    forget(monkeypatch)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        assert run() == pytest.approx(EXPECTED)
        assert run(backend="python") == pytest.approx(EXPECTED)
    expected_warnings = 0 if damage == "key-is-a-folder" else 1  # a new key: old entries just do not verify
    assert len(cache_warnings(record)) == expected_warnings, [str(w.message) for w in record]
    if damage == "unreadable-cache":
        fresh_cache.chmod(0o700)


def test_numba_cache_elsewhere_is_not_used(fresh_cache, tmp_path, monkeypatch):
    """With NUMBA_CACHE_DIR numba would read files rotorkit does not check: the model compiles without them."""
    from numba.core import config

    elsewhere = tmp_path / "numba-elsewhere"
    monkeypatch.setattr(config, "CACHE_DIR", str(elsewhere))
    assert run() == pytest.approx(EXPECTED)
    assert not elsewhere.exists() or not any(elsewhere.rglob("*.nbi"))
    monkeypatch.setattr(config, "CACHE_DIR", "")
    forget(monkeypatch)
    assert run() == pytest.approx(EXPECTED)
    assert numba_files(entry_of(fresh_cache), ".nbi")  # without it, the verified cache beside rhs.py is used


def _twice(x):
    return 2.0 * x


def test_rotorkits_own_compiled_code_is_cached_privately_and_verified(fresh_cache, tmp_path, monkeypatch):
    """The shared integration loop's cache (rotorkit.codegen.cache.jit_shared) is guarded like a model's."""
    import numba

    signature = numba.float64(numba.float64)
    assert cache.jit_shared(_twice, "twice", signature)(2.0) == 4.0
    entry = fresh_cache / "shared" / "twice"
    files = sorted(entry.glob("*/*.nb*"))
    assert files and all(f.stat().st_mode & 0o777 == 0o600 for f in files)
    assert (entry / cache.SIGNATURES).exists()
    marker = tmp_path / "ran"
    for path in files:
        path.write_bytes(pickle.dumps(Planted(marker)))
    forget(monkeypatch)
    with pytest.warns(cache.CacheWarning, match="did not sign"):
        assert cache.jit_shared(_twice, "twice", signature)(3.0) == 6.0
    assert not marker.exists()
    with warnings.catch_warnings():  # signed again: the next process loads it without a word
        warnings.simplefilter("error")
        forget(monkeypatch)
        assert cache.jit_shared(_twice, "twice", signature)(4.0) == 8.0


def test_the_integration_loop_uses_the_private_cache():
    import inspect

    from rotorkit.engines import rk_numba

    assert "jit_shared(_rk_loop" in inspect.getsource(rk_numba._build_loop)
    assert "shared_lock(\"rk_loop\")" in inspect.getsource(rk_numba._compiled_loop)
    loop = rk_numba._compiled_loop()
    # the folder numba keeps the loop in: the cache folder's shared/ of the process's first compile (a test
    # that ran earlier in this process may have had another ROTORKIT_CACHE_DIR), never next to the source
    folder = Path(loop._cache._cache_path)
    assert rk_numba.cache_name() in folder.parts and "shared" in folder.parts
    assert Path(rk_numba.__file__).parent not in folder.parents
    assert any(folder.glob("*.nbi"))


def test_cached_bytecode_runs_only_with_this_users_signature(fresh_cache, tmp_path, monkeypatch):
    """The generated module's code object is kept marshalled beside rhs.py; planted bytes never run."""
    import marshal

    run(backend="python")
    entry = entry_of(fresh_cache)
    (code_file,) = entry.glob("rhs.*.code")
    marker = tmp_path / "ran"
    hostile = marshal.dumps(compile(f"open({str(marker)!r}, 'w').close()\n", "rhs.py", "exec"))
    genuine = code_file.read_bytes()
    for planted in (genuine[:64] + hostile,  # this user's signature of other bytes
                    cache._code_digest(os.urandom(32), "rhs", str(entry / "rhs.py"),
                                       (entry / "rhs.py").read_text(), hostile) + hostile,  # another key
                    hostile):  # no signature
        code_file.write_bytes(planted)
        forget(monkeypatch)
        assert run(backend="python") == pytest.approx(EXPECTED)
        assert not marker.exists()
        assert code_file.read_bytes() == genuine  # compiled again and rewritten
    # control: the planted bytes do run when loaded without the check
    exec(marshal.loads(hostile), {})
    assert marker.exists()


def test_cached_bytecode_of_another_source_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "cache"))
    entry = tmp_path / "cache" / "entry"
    entry.mkdir(parents=True, mode=0o700)
    first = {}
    exec(cache.compile_verified("X = 1\n", "m.py", entry, "m"), first)
    second = {}
    exec(cache.compile_verified("X = 2\n", "m.py", entry, "m"), second)  # same name, new text: not the old code
    def no_compile(*args, **kwargs):
        raise AssertionError("compiled although its signed bytecode is in the entry")

    monkeypatch.setattr(cache, "compile", no_compile, raising=False)
    again = {}
    exec(cache.compile_verified("X = 2\n", "m.py", entry, "m"), again)  # now from the file
    assert (first["X"], second["X"], again["X"]) == (1, 2, 2)


def _first_key(root, barrier, queue):
    barrier.wait()  # both look for the key at once
    queue.put(cache.secret_key(root))


@pytest.mark.skipif(not hasattr(os, "fork"), reason="forked processes")
def test_processes_that_start_on_a_new_cache_at_once_agree_on_its_key(tmp_path):
    """A run and the loop it compiles in another process (or two children of a test) that both find no key
    must not each create their own: what the loser signed would be removed as unsigned by every later process
    (the intermittent 'did not sign' warning of CI)."""
    import multiprocessing

    context = multiprocessing.get_context("fork")
    for attempt in range(10):
        root = tmp_path / f"cache{attempt}"
        root.mkdir(mode=0o700)
        barrier, queue = context.Barrier(2), context.Queue()
        processes = [context.Process(target=_first_key, args=(root, barrier, queue)) for _ in range(2)]
        for process in processes:
            process.start()
        keys = [queue.get(timeout=60), queue.get(timeout=60)]
        for process in processes:
            process.join(timeout=60)
        assert keys[0] == keys[1] == (root / "secret.key").read_bytes()
        assert not [p.name for p in root.iterdir() if p.name != "secret.key"]  # no temporary file left


def test_a_signing_key_that_cannot_be_read_for_now_is_kept(fresh_cache, monkeypatch):
    """An error reading the key (no file descriptor left, an I/O error) fails this call (the caller does without
    the cache), never replaces the key: everything signed with it stays valid. Replacing it on a full disk's
    failed read was the intermittent 'did not sign' warning of CI (tests/test_hostile_disk.py)."""
    import errno

    key = cache.secret_key()
    real_open = os.open

    def no_descriptor_left(path, *args, **kwargs):
        if str(path).endswith("secret.key"):
            raise OSError(errno.EMFILE, os.strerror(errno.EMFILE), str(path))
        return real_open(path, *args, **kwargs)

    assert run() == pytest.approx(EXPECTED)  # numba's files written and signed
    files = sorted((entry_of(fresh_cache) / "__pycache__").iterdir())
    monkeypatch.setattr(os, "open", no_descriptor_left)
    with pytest.raises(OSError, match="Too many open files"):
        cache.secret_key()
    monkeypatch.setattr(system_module, "_JIT_CACHE", {})  # the module loaded before, numba's functions not
    monkeypatch.setattr(cache_folders, "_WARNED", set())
    with pytest.warns(cache.CacheWarning, match="cannot be checked now .*signing key.*Too many open files"):
        assert run() == pytest.approx(EXPECTED)  # compiled without the disk cache, nothing removed
    forget(monkeypatch)
    with pytest.warns(cache.CacheWarning, match="cannot store model .*Too many open files.*built in memory"):
        assert run() == pytest.approx(EXPECTED)  # the module too: built in memory, the entry kept
    monkeypatch.setattr(os, "open", real_open)
    assert cache.secret_key() == key == (fresh_cache / "secret.key").read_bytes()
    assert sorted((entry_of(fresh_cache) / "__pycache__").iterdir()) == files
    forget(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error", cache.CacheWarning)
        assert run() == pytest.approx(EXPECTED)  # loaded as signed before


@pytest.mark.parametrize("unreadable", ["numba.sig.json", ".nbc"])
def test_numba_files_that_cannot_be_read_for_now_are_kept(fresh_cache, monkeypatch, unreadable):
    """An I/O error reading the signatures or a numba file is no evidence of tampering: the files are neither used
    nor removed (one warning), and the next process loads them."""
    import errno

    assert run() == pytest.approx(EXPECTED)
    entry = entry_of(fresh_cache)
    files = sorted((entry / "__pycache__").iterdir())
    real_open = os.open

    def io_error(path, *args, **kwargs):
        if str(path).endswith(unreadable):
            raise OSError(errno.EIO, os.strerror(errno.EIO), str(path))
        return real_open(path, *args, **kwargs)

    monkeypatch.setattr(os, "open", io_error)
    monkeypatch.setattr(system_module, "_JIT_CACHE", {})  # the module stays loaded; numba's functions are new
    with pytest.warns(cache.CacheWarning, match="cannot be checked now .*Input/output error"):
        assert run() == pytest.approx(EXPECTED)
    monkeypatch.setattr(os, "open", real_open)
    assert sorted((entry / "__pycache__").iterdir()) == files
    forget(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error", cache.CacheWarning)
        assert run() == pytest.approx(EXPECTED)
