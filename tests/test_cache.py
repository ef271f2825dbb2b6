"""The on-disk model cache: warm starts derive nothing; damaged entries are rebuilt."""

import json
import os

import numpy as np
import pytest

import rotorkit as rk
from rotorkit import system as system_module
from rotorkit.codegen import cache
from rotorkit.symbolic import lagrange


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(system_module, "_MODULES", {})
    monkeypatch.setattr(lagrange, "_CACHE", {})
    return tmp_path / "cache"


def jeffcott(stiffness=1e4):
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=50.0),
                     rk.Disk(station=1, mass=1.0, radius=0.1, eccentricity=1e-4),
                     rk.ElasticSupport(station=1, stiffness=stiffness, damping=2.0)])


def forget_in_memory(monkeypatch):
    monkeypatch.setattr(system_module, "_MODULES", {})
    monkeypatch.setattr(lagrange, "_CACHE", {})


def forbid_derivation(monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("a warm start must not derive")

    monkeypatch.setattr(lagrange, "derive", forbidden)


def test_warm_start_derives_nothing(fresh_cache, monkeypatch):
    y = np.r_[1e-3, 0.0, 0.0, 0.0]
    jeffcott().compile(backend="python")
    forget_in_memory(monkeypatch)
    forbid_derivation(monkeypatch)
    # same structure, other numbers: still a cache hit
    system = jeffcott(stiffness=2e4).compile(backend="python")
    assert system.rhs(0.1, y)[2] == pytest.approx(-2e4 * 1e-3 + 1e-4 * 50.0**2 * np.cos(5.0), rel=1e-12)
    base, count, size = cache.info()
    assert count == 1 and size > 0 and base == fresh_cache


@pytest.mark.parametrize("damage", ["truncate", "garbage-meta", "other-digest", "stale-format", "syntax-error"])
def test_damaged_entries_are_rebuilt(fresh_cache, monkeypatch, damage):
    jeffcott().compile(backend="python")
    entry = fresh_cache / "models" / jeffcott().structure_key
    source, meta = entry / "rhs.py", entry / "meta.json"
    if damage == "truncate":
        source.write_text(source.read_text()[:200])
    elif damage == "garbage-meta":
        meta.write_text("{not json")
    elif damage == "other-digest":
        source.write_text(source.read_text() + "\nPLANTED = 1\n")
    elif damage == "stale-format":
        data = json.loads(meta.read_text())
        data["format"] = "rotorkit-model-cache-0"
        meta.write_text(json.dumps(data))
    else:  # digest recomputed so only the import fails
        bad = "def rhs(:\n"
        source.write_text(bad)
        data = json.loads(meta.read_text())
        data["hmac"] = cache._digest(bad)
        meta.write_text(json.dumps(data))
    forget_in_memory(monkeypatch)
    system = jeffcott().compile(backend="python")  # rebuilt, no crash
    assert np.all(np.isfinite(system.rhs(0.0, np.r_[1e-3, 0, 0, 0])))
    assert "PLANTED" not in source.read_text()
    assert cache.load(jeffcott().structure_key) is not None


def test_clear(fresh_cache):
    jeffcott().compile(backend="python")
    assert cache.clear() == 1
    assert cache.info()[1] == 0


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")
def test_refuses_a_folder_others_can_write(tmp_path, monkeypatch):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(shared))
    with pytest.warns(UserWarning, match="writable by others"):
        folder = cache.cache_dir()
    assert folder != shared


def test_cli_cache_command(fresh_cache, capsys):
    from rotorkit.cli import main

    jeffcott().compile(backend="python")
    assert main(["cache", "info"]) == 0
    assert "1 cached model" in capsys.readouterr().out
    assert main(["cache", "clear"]) == 0
    assert "removed 1" in capsys.readouterr().out


def test_an_entry_from_elsewhere_is_never_imported(fresh_cache, tmp_path, monkeypatch):
    """A cache copied from another machine (valid format, its own key) is rebuilt, not executed."""
    jeffcott().compile(backend="python")
    entry = fresh_cache / "models" / jeffcott().structure_key
    planted = tmp_path / "planted"
    source = entry.joinpath("rhs.py").read_text() + f"\nopen({str(planted)!r}, 'w').write('ran')\n"
    entry.joinpath("rhs.py").write_text(source)
    meta = json.loads(entry.joinpath("meta.json").read_text())
    import hashlib
    import hmac

    meta["hmac"] = hmac.new(b"another user's key".ljust(32, b"0"), source.encode(), hashlib.sha256).hexdigest()
    entry.joinpath("meta.json").write_text(json.dumps(meta))
    forget_in_memory(monkeypatch)
    jeffcott().compile(backend="python")
    assert not planted.exists()
    assert "open(" not in entry.joinpath("rhs.py").read_text()
    key = fresh_cache / "secret.key"
    assert key.stat().st_mode & 0o077 == 0
