"""Hostile files: every file rotorkit reads is refused at once unless it is a regular file of a bounded size.

One class, one mechanism (:func:`rotorkit.files.open_data`): the readers of
model files, result files, sweep manifests and points, and cache entries are
each given a FIFO (reading it would wait for a writer forever), a symbolic
link to ``/dev/zero`` (endless), a sparse 1.5 GB file (no disk used) and bad
paths (None, bytes, a NUL byte). Each must end in a named error within
seconds, having read nothing.
"""

import json
import os
import signal
import warnings

import pytest

import rotorkit as rk
from rotorkit.errors import ParameterError
from rotorkit.files import LIMITS, read_data

pytestmark = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="POSIX FIFOs")


@pytest.fixture(autouse=True)
def no_hang():
    """A reader that blocks (on a FIFO) or reads forever (/dev/zero) fails the test instead of hanging it."""
    def hung(signum, frame):
        raise AssertionError("the reader blocked or read without a bound")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def hostile(path, kind):
    """Put a hostile file of ``kind`` at ``path``; the words the error must hold."""
    if kind == "fifo":
        os.mkfifo(path)
        return "named pipe"
    if kind == "dev/zero":
        os.symlink("/dev/zero", path)
        return "character device"
    if kind == "sparse":
        with open(path, "wb") as fh:
            fh.truncate(1_500_000_000)  # a hole: no block is written
        return "bytes"
    if kind == "folder":
        os.mkdir(path)
        return "folder"
    raise ValueError(kind)


KINDS = ["fifo", "dev/zero", "sparse", "folder"]


@pytest.mark.parametrize("kind", KINDS)
def test_a_model_file_that_is_not_a_bounded_regular_file_is_refused_unread(tmp_path, kind):
    path = tmp_path / "model.toml"
    words = hostile(path, kind)
    with pytest.raises(rk.modelfile.ModelFileError, match=f"model file.*{words}|{words}.*model file"):
        rk.load_model(path)


@pytest.mark.parametrize("kind", KINDS)
def test_a_result_file_that_is_not_a_bounded_regular_file_is_refused_unread(tmp_path, kind):
    path = tmp_path / "signals.npz"
    words = hostile(path, kind)
    if kind == "sparse":  # within the default bound (half the free memory): its zip directory is looked for, fast
        words = "not a readable rotorkit result file"
        with pytest.raises(ParameterError, match="bytes"):
            rk.load_result(path, max_bytes=10**9)
    with pytest.raises(ParameterError, match=words):
        rk.load_result(path)


@pytest.mark.parametrize("kind", KINDS)
def test_a_sweep_manifest_that_is_not_a_bounded_regular_file_is_refused_unread(tmp_path, kind):
    from rotorkit.sweep.storage import MANIFEST_NAME, check_manifest, read_manifest

    words = hostile(tmp_path / MANIFEST_NAME, kind)
    with pytest.raises(ParameterError, match=words):
        read_manifest(tmp_path)
    with pytest.raises(ParameterError, match=words):
        check_manifest(tmp_path, {"format": "x"})


@pytest.mark.parametrize("kind", KINDS)
def test_a_sweep_point_that_is_not_a_regular_file_counts_as_missing(tmp_path, kind):
    from rotorkit.sweep.storage import point_path, read_point

    path = point_path(tmp_path, 0)
    path.parent.mkdir(parents=True, exist_ok=True)
    hostile(path, kind)
    assert read_point(tmp_path, 0, "fp", {"a": 1.0}, {}) is None  # recomputed, not read


@pytest.mark.parametrize("member", ["meta.json", "rhs.py"])
@pytest.mark.parametrize("kind", KINDS)
def test_a_cache_entry_file_that_is_not_a_bounded_regular_file_is_discarded_unread(kind, member):
    from rotorkit.codegen import cache

    key = f"hostile{KINDS.index(kind)}{member.replace('.', '')}"
    entry = cache.cache_dir() / "models" / key
    entry.mkdir(mode=0o700, parents=True)
    (entry / "meta.json").write_text(json.dumps({"format": cache.FORMAT, "key": key, "hmac": "0"}))
    (entry / "rhs.py").write_text("STATE_NAMES = ()\n")
    os.unlink(entry / member)
    hostile(entry / member, kind)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert cache.load(key) is None
    assert not os.path.lexists(entry)  # removed, to be rebuilt


def test_a_cache_signing_key_that_is_a_fifo_is_replaced(tmp_path, monkeypatch):
    from rotorkit.codegen import cache

    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "cache"))
    cache.cache_dir().mkdir(mode=0o700, parents=True, exist_ok=True)
    os.mkfifo(cache.cache_dir() / "secret.key")
    assert len(cache.secret_key()) == 32
    assert (cache.cache_dir() / "secret.key").is_file()


@pytest.mark.parametrize("bad, words", [(None, "expected a path"), (b"model.toml", "expected a path"),
                                        ("mo\0del.toml", "NUL byte"), ("", "empty"), (3, "expected a path")])
def test_a_path_that_is_none_bytes_or_holds_a_nul_byte_is_a_parameter_error(bad, words):
    from rotorkit.sweep.storage import read_manifest

    with pytest.raises(ParameterError, match=words):
        rk.load_model(bad)
    with pytest.raises(ParameterError, match=words):
        rk.load_result(bad)
    with pytest.raises(ParameterError, match=words):
        read_manifest(bad)
    with pytest.raises(ParameterError, match=words):
        read_data(bad, what="model file")


def test_the_bound_holds_exactly(tmp_path):
    path = tmp_path / "m.toml"
    path.write_bytes(b"x" * LIMITS["model file"])
    assert len(read_data(path, what="model file")) == LIMITS["model file"]
    path.write_bytes(b"x" * (LIMITS["model file"] + 1))
    with pytest.raises(ParameterError, match=f"at most {LIMITS['model file']} bytes"):
        read_data(path, what="model file")
