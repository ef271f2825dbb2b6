"""A full disk is a named error (or, under the model cache, a named warning) that says which folder is full.

The disk is filled by refusing writes (``ENOSPC``, as the kernel does) to
files under one folder only: every other file this process writes (the
temporary copy a failed run keeps, pytest's own) is written as usual.
Before, a full disk gave ``OSError: [Errno 28] No space left on device``
with a temporary file name, or a cache warning that did not say which file
system was full nor what to do.
"""

import errno
import os
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.errors import DiskFullError, RotorkitError


@pytest.fixture
def full_disk(monkeypatch):
    if not os.path.isdir("/proc/self/fd"):
        pytest.skip("finds the path of an open file in /proc (Linux)")
    """``full_disk(folder)``: from now on writes through rotorkit's atomic writer under ``folder`` fail (ENOSPC)."""
    full = []
    real_fdopen = os.fdopen

    def fdopen(fd, *args, **kwargs):
        where = os.readlink(f"/proc/self/fd/{fd}") if os.path.exists(f"/proc/self/fd/{fd}") else ""
        writing = any(c in (args[0] if args else kwargs.get("mode", "r")) for c in "wax+")  # a full disk still reads
        if writing and any(where.startswith(str(f) + os.sep) for f in full):
            os.close(fd)
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real_fdopen(fd, *args, **kwargs)

    monkeypatch.setattr(os, "fdopen", fdopen)
    return lambda folder: full.append(Path(os.path.realpath(folder)))


def two_masses():
    """A structure no other test builds (so it is derived and stored here, not found in memory)."""
    return rk.Model([rk.Rotor(name="R", stations=(1, 2), speed=50.0), rk.Disk(station=1, mass=1.0, radius=0.1),
                     rk.LumpedMass(station=2, mass=0.3), rk.ElasticSupport(station=1, stiffness=1e4, damping=2.0),
                     rk.ElasticSupport(station=2, stiffness=3e4, damping=1.0)], name="disk_full_two_masses")


def test_result_save_onto_a_full_disk_names_the_folder(tmp_path, full_disk):
    result = rk.Result(t=np.linspace(0.0, 1.0, 3), y=np.zeros((1, 3)), state_names=("x1",))
    result.save(tmp_path / "ok.npz")  # control: the writer works before the disk fills
    full_disk(tmp_path)
    with pytest.raises(DiskFullError, match=rf"no space is left on the disk holding {tmp_path} \(file system "
                                            r"mounted at /.*free of .*\); free space there, or write to a folder"):
        result.save(tmp_path / "signals.npz")
    err = pytest.raises(OSError, result.save, tmp_path / "again.npz").value
    assert isinstance(err, RotorkitError) and err.errno == errno.ENOSPC  # still an OSError for old callers
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ok.npz"]  # no temporary file left behind


def test_a_run_into_an_output_folder_on_a_full_disk_names_it_and_keeps_the_signals(tmp_path, full_disk, capsys):
    from rotorkit.cli import main

    from test_hostile_outputs import JEFFCOTT

    model = tmp_path / "jeffcott.toml"
    model.write_text(JEFFCOTT)
    disk = tmp_path / "disk"
    disk.mkdir()
    full_disk(disk)
    code = main(["run", str(model), "--t-end", "0.002", "--no-figures", "--backend", "python", "--engine", "scipy",
                 "--out", str(disk / "run")])
    err = capsys.readouterr().err
    assert code == 1, err
    assert f"the outputs of {disk / 'run'} could not be written: no space is left on the disk holding {disk}" in err
    assert "give an output folder on another disk" in err
    kept = Path(err.split("the signals are kept in ")[1].split()[0])
    assert kept.is_file() and rk.load_result(kept).t[-1] == pytest.approx(0.002)
    assert not (disk / "run").exists()


def test_a_full_disk_under_the_model_cache_is_a_warning_naming_it_and_the_model_still_runs(full_disk, monkeypatch):
    cache = Path(os.environ["ROTORKIT_CACHE_DIR"])  # the temporary cache of the test session (conftest)
    from rotorkit.codegen import cache as model_cache
    from rotorkit.codegen import cache_folders

    monkeypatch.setattr(cache_folders, "_WARNED", set())  # one warning per kind and process: this one is new here
    key = model_cache.secret_key()
    full_disk(cache)
    with pytest.warns(model_cache.CacheWarning, match=rf"no space is left on the disk holding {cache}.*free of .*"
                                                      "set ROTORKIT_CACHE_DIR to a folder on a disk with space"):
        system = two_masses().compile(backend="python")
    result = rk.simulate(system, (0.0, 0.01), engine="scipy")
    assert result.stats["success"]
    assert model_cache.secret_key() == key  # kept: what the session signed with it stays valid


def test_other_write_errors_are_unchanged(tmp_path, monkeypatch):
    from rotorkit.files import atomic_write_bytes, disk_full

    def refuse(fd, *args, **kwargs):
        os.close(fd)
        raise PermissionError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(os, "fdopen", refuse)
    with pytest.raises(PermissionError) as info:
        atomic_write_bytes(tmp_path / "f", b"x")
    assert not isinstance(info.value, DiskFullError)
    quota = disk_full(OSError(errno.EDQUOT, "Disk quota exceeded"), tmp_path, "f")
    assert isinstance(quota, DiskFullError) and "the disk quota is reached" in str(quota)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert disk_full(ValueError("x"), tmp_path, "f").args == ("x",)
