"""Locks never hang a user: a stopped holder is named and, past a bound, the build goes on without the lock;
a lock file or a library replaced by something else is repaired."""

import os
import signal
import subprocess
import sys
import textwrap
import time
import warnings

import pytest

from rotorkit.codegen import cache, locks

pytestmark = pytest.mark.skipif(not hasattr(signal, "SIGSTOP") or not sys.platform.startswith("linux"),
                                reason="POSIX job control and /proc")

HOLDER = textwrap.dedent("""
    import sys, time
    from rotorkit.codegen import cache

    with cache.shared_lock("thing", folder=sys.argv[1]) as lock:
        print("held" if lock is not None else "not held", flush=True)
        time.sleep(120)
""")


def test_a_stopped_lock_holder_is_named_and_the_wait_is_bounded(tmp_path, capfd, monkeypatch):
    folder = tmp_path / "entry"
    folder.mkdir(mode=0o700)
    monkeypatch.setattr(locks, "STOPPED_LOCK_WAIT", 1.0)
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, str(folder)], stdout=subprocess.PIPE, text=True, env=env)
    try:
        assert holder.stdout.readline().strip() == "held"
        os.kill(holder.pid, signal.SIGSTOP)  # Ctrl-Z
        start = time.monotonic()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with cache.shared_lock("thing", folder=folder) as lock:
                waited = time.monotonic() - start
                assert lock is None  # not taken: the caller builds on its own
        assert 1.0 <= waited < 30
        err = capfd.readouterr().err
        assert f"waiting for process {holder.pid} to finish building thing" in err
        assert "it is stopped (Ctrl-Z or SIGSTOP" in err
        assert any(f"process {holder.pid} has held the lock" in str(w.message) for w in caught)
    finally:
        os.kill(holder.pid, signal.SIGCONT)
        holder.kill()
        holder.wait(timeout=30)
        holder.stdout.close()
    with cache.shared_lock("thing", folder=folder) as lock:  # the holder is gone: the lock is free again
        assert lock is not None


@pytest.mark.parametrize("damage", ["fifo", "folder", "symlink"])
def test_a_lock_file_that_is_not_a_regular_file_is_repaired(tmp_path, damage):
    folder = tmp_path / "entry"
    folder.mkdir(mode=0o700)
    path = folder / "thing.lock"
    if damage == "fifo":
        os.mkfifo(path)
    elif damage == "folder":
        path.mkdir()
        (path / "inside").write_text("x")
    else:
        os.symlink("/dev/null", path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with cache.shared_lock("thing", folder=folder) as lock:
            assert lock is not None
    assert path.is_file() and not path.is_symlink()
    assert any("was not a regular file; it is replaced" in str(w.message) for w in caught)


@pytest.mark.skipif(__import__("rotorkit.codegen.cbuild", fromlist=["x"]).compiler() is None, reason="no C compiler")
def test_a_folder_in_place_of_a_c_library_is_repaired(tmp_path):
    import ctypes

    from rotorkit.codegen import cbuild

    folder = tmp_path / "entry"
    folder.mkdir(mode=0o700)
    (folder / "lib.so").mkdir()
    source = "double one(void) { return 1.0; }\n"
    library = cbuild.library(folder, "lib", source)
    library.one.restype = ctypes.c_double
    assert library.one() == 1.0
    assert (folder / "lib.so").is_file()
