"""Fast starts: the integration loop compiled in another process on a cold cache (and the lock a run waits on
for it), the orbit drawn as one polyline per colour, and a cold run giving the warm run's numbers."""

import functools
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rotorkit.codegen import cache, cbuild
from rotorkit.engines import rk_numba

#: the folder holding the rotorkit this test imports (the source tree, or site-packages when installed, as in
#: CI): child processes must import the same copy (from there, as python -c puts its folder first), whose file
#: the loop's disk cache is keyed to
PACKAGE_ROOT = Path(rk_numba.__file__).resolve().parents[2]


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty cache folder, a loop not yet loaded in this process, two cores, background compiling allowed."""
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv(rk_numba.BACKGROUND_VARIABLE, raising=False)
    monkeypatch.setattr(rk_numba, "_compiled_loop", functools.lru_cache(maxsize=None)(rk_numba._compiled_loop.__wrapped__))
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    return tmp_path / "cache"


def python(code, cache_dir, **env):
    env = dict(os.environ, PYTHONPATH=str(PACKAGE_ROOT), ROTORKIT_CACHE_DIR=str(cache_dir), **env)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=PACKAGE_ROOT, timeout=600,
                         env=env)
    assert out.returncode == 0, out.stderr
    return out.stdout


PROBE = """
import numba, numpy as np
from rotorkit.engines import rk_numba

@numba.njit
def decay(t, y, p, dydt):
    dydt[0] = -p[0] * y[0]

sol = rk_numba.integrate(decay, 0.0, 1.0, [1.0], [2.0], [1.0])
stats = rk_numba._compiled_loop().stats
print(repr(float(sol.y[0, -1])), sum(stats.cache_hits.values()), sum(stats.cache_misses.values()))
"""


def test_a_run_waits_for_the_loop_compiled_in_the_background_and_loads_it(fresh_cache):
    process = rk_numba.compile_loop_in_background()
    assert process is not None
    assert rk_numba.compile_loop_in_background() is None  # its lock is held: no second compilation
    # a process that integrates now blocks on the lock until the other has written the cache, then loads it
    value, hits, misses = python(PROBE, fresh_cache).split()
    assert process.wait(timeout=600) == 0
    assert (int(hits), int(misses)) == (1, 0)  # loaded from the cache, not compiled a second time
    assert float(value) == pytest.approx(np.exp(-2.0), rel=1e-7)
    assert cache.shared_is_current(rk_numba.cache_name(), rk_numba.__file__)
    assert rk_numba.compile_loop_in_background() is None  # compiled already: nothing to do
    assert (fresh_cache / "shared" / "rk_loop.lock").stat().st_mode & 0o777 == 0o600


def test_a_failed_background_compilation_frees_the_lock(fresh_cache, monkeypatch):
    monkeypatch.setattr(sys, "executable", "/bin/false")  # the other process exits at once, compiling nothing
    process = rk_numba.compile_loop_in_background()
    assert process is not None and process.wait(timeout=60) != 0
    assert not cache.shared_is_current(rk_numba.cache_name(), rk_numba.__file__)
    with cache.shared_lock("rk_loop", blocking=False) as lock:
        assert lock is not None  # free again: the run compiles the loop itself, as without the other process


@pytest.mark.parametrize("why", ["switched off", "one core", "loaded here"])
def test_nothing_is_started_when_it_cannot_help(fresh_cache, monkeypatch, why):
    if why == "switched off":
        monkeypatch.setenv(rk_numba.BACKGROUND_VARIABLE, "0")
    elif why == "one core":
        monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0}, raising=False)
    else:
        monkeypatch.setattr(rk_numba._compiled_loop, "cache_info", lambda: type("Info", (), {"currsize": 1})())
    assert rk_numba.compile_loop_in_background() is None
    assert not (fresh_cache / "shared" / rk_numba.cache_name()).exists()


def test_the_shared_lock_excludes_a_second_holder(fresh_cache):
    with cache.shared_lock("rk_loop") as first:
        assert first is not None
        with cache.shared_lock("rk_loop", blocking=False) as second:
            assert second is None  # flock locks belong to the open file: a second one waits (here: refused)
    with cache.shared_lock("rk_loop", blocking=False) as again:
        assert again is not None


def test_the_orbit_polylines_give_every_segment_the_colour_of_its_mid_time():
    from matplotlib import colormaps
    from matplotlib.colors import Normalize

    from rotorkit.plotting.basic import _time_coloured_path

    rng = np.random.default_rng(3)
    t = np.sort(rng.uniform(0.0, 2.0, 5000))
    x, y = rng.normal(size=t.size), rng.normal(size=t.size)
    lines = _time_coloured_path(x, y, t)
    mid = 0.5 * (t[:-1] + t[1:])
    expected = colormaps["viridis"](Normalize(mid.min(), mid.max())(mid))  # one line per segment
    got, covered = [], []
    for path, colour in zip(lines.get_segments(), lines.to_rgba(lines.get_array())):
        got += [colour] * (len(path) - 1)
        covered.append(path[:-1])
    assert np.array_equal(np.array(got), expected)
    assert np.array_equal(np.concatenate(covered + [path[-1:]]), np.column_stack([x, y]))
    assert len(lines.get_segments()) <= 256 < t.size


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["c", "numba"])
def test_a_cold_run_gives_the_numbers_of_a_warm_one(tmp_path, backend):
    """Cold (empty cache: the loop built, for numba in the background; the model derived and compiled) and warm runs
    agree exactly, with either compiled back end."""
    if backend == "c" and cbuild.compiler() is None:
        pytest.skip("no C compiler on this machine")
    env = dict(os.environ, PYTHONPATH=str(PACKAGE_ROOT), ROTORKIT_CACHE_DIR=str(tmp_path / "cache"), MPLBACKEND="Agg",
               ROTORKIT_BACKEND=backend)
    env.pop(rk_numba.BACKGROUND_VARIABLE, None)
    for name in ("cold", "warm"):
        out = subprocess.run([sys.executable, "-m", "rotorkit.cli", "run", "al31f", "--t-end", "0.3", "--out",
                              str(tmp_path / name)], capture_output=True, text=True, cwd=tmp_path, env=env,
                             timeout=900)
        assert out.returncode == 0, out.stderr
        assert f"(backend {backend})" in out.stdout
    cold, warm = np.load(tmp_path / "cold" / "signals.npz"), np.load(tmp_path / "warm" / "signals.npz")
    assert cold["y"].shape == warm["y"].shape and cold["y"].shape[1] == 3001
    assert np.array_equal(cold["t"], warm["t"]) and np.array_equal(cold["y"], warm["y"])
    shared = tmp_path / "cache" / "shared"
    if backend == "numba":
        assert any((shared / rk_numba.cache_name()).glob("*/*.nbc"))  # the loop was compiled into it
    else:
        assert any((shared / "rk_c_loop").glob("*.so")) and not list(shared.glob("rk_loop*"))


def test_the_numba_loop_cache_follows_the_shared_tables(tmp_path, monkeypatch):
    """numba's cache index checks rk_numba.py's time stamp only; the loop's folder name carries a digest of both
    rk_numba.py and rk_common.py, whose constants the machine code freezes, so a changed table is never stale."""
    from rotorkit.engines import rk_common

    before = rk_numba.cache_name()
    changed = tmp_path / "rk_common.py"
    changed.write_text(Path(rk_common.__file__).read_text() + "\n# a changed table\n")
    monkeypatch.setattr(rk_common, "__file__", str(changed))
    rk_numba.cache_name.cache_clear()
    try:
        assert rk_numba.cache_name() != before and rk_numba.cache_name().startswith("rk_loop-")
    finally:
        monkeypatch.undo()
        rk_numba.cache_name.cache_clear()
    assert rk_numba.cache_name() == before
