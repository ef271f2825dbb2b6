"""The c back end: the generated functions translated to C equal the generated Python, built and cached safely."""

import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.codegen import cbuild, cmodel, csource
from rotorkit.elements import BeamSegment, Disk, Material, SpeedProfile
from rotorkit.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
HAS_CC = cbuild.compiler() is not None
needs_cc = pytest.mark.skipif(not HAS_CC, reason="no C compiler on this machine (the c back end needs one)")


def beam_with_rub(nodes=3):
    """A small unrolled FE rotor: beams (tilt, gyroscopics), two disks, bearings, a rub stator, gravity, run-up."""
    steel = Material.steel()
    stations = tuple(range(1, nodes + 1))
    elements = [rk.Rotor(name="R", stations=stations, speed=SpeedProfile.table(times=[0.0, 0.5, 1.0], speeds=[0.0, 300.0, 350.0]))]
    elements += [BeamSegment(start=s, end=s + 1, length=0.2, outer_diameter=0.05, material=steel)
                 for s in stations[:-1]]
    elements += [Disk.from_geometry(station=s, width=0.05, inner_diameter=0.05, outer_diameter=0.25, material=steel,
                                    eccentricity=2e-5, phase=float(k)) for k, s in enumerate((1, nodes))]
    elements += [rk.ElasticSupport(station=s, stiffness=1e6, damping=100.0) for s in (1, nodes)]
    elements += [rk.RubStator(station=nodes, clearance=1e-5, contact_stiffness=2e6, friction_coefficient=0.2),
                 rk.Maneuver.steady()]
    return rk.Model(elements, name=f"c_backend_beam_{nodes}")


def random_states(system, count, scale, seed=0):
    rng = np.random.default_rng(seed)
    return [rng.normal(size=system.n_states) * scale for _ in range(count)]


@needs_cc
@pytest.mark.parametrize("build", [lambda: rk.preset("al31f"), beam_with_rub], ids=["al31f", "beam_rub_runup"])
def test_c_functions_equal_the_generated_python(build):
    """rhs, switches and the Jacobian in C give the Python functions' numbers (the same operations, in order)."""
    model = build()
    c, py = model.compile(backend="c"), model.compile(backend="python")
    assert c.backend == "c" and isinstance(c.core, cmodel.CFunction)
    for k, y in enumerate(random_states(c, 40, 1e-4)):
        t = 0.15 * k
        np.testing.assert_allclose(c.rhs(t, y), py.rhs(t, y), rtol=1e-13, atol=0)
        np.testing.assert_allclose(c.switch_values(t, y), py.switch_values(t, y), rtol=1e-13, atol=0)
    y = random_states(c, 1, 1e-4, seed=3)[0]
    J_c, J_py = c.jacobian(0.7, y), c.jacobian(0.7, y, compiled=False)
    np.testing.assert_allclose(J_c, J_py, rtol=1e-12, atol=1e-12 * np.abs(J_py).max())
    assert np.count_nonzero(J_c) > c.n_states  # a real Jacobian, not the identity block alone


def test_translation_covers_python_semantics():
    """Conditional expressions, chained comparisons, min/max with Python's rule, powers, two-index outputs."""
    source = (
        "def rhs(t, y, p, dydt):\n"
        "    a = y[0]\n"
        "    b = (1.0 if (p[0]) <= (t) < (p[1]) else 0.0)\n"
        "    dydt[0] = min(max(a, p[0]), p[1]) + b\n"
        "    dydt[1] = (a)**0.75 + sqrt(abs(a)) - (-a)\n"
        "def jac(t, y, p, J):\n"
        "    J[1, 0] = 2.0*y[1]\n"
    )
    text = csource.translate(source, ("rhs", "jac"), row_length=2)
    assert "rk_min(rk_max(a, p[0]), p[1])" in text
    assert "((p[0] <= t) && (t < p[1]))" in text
    assert "pow(a, 0.75)" in text and "J[2] = " in text
    with pytest.raises(csource.Untranslatable, match="For"):
        csource.translate("def rhs(t, y, p, dydt):\n    for i in range(2):\n        dydt[i] = 0.0\n")
    with pytest.raises(csource.Untranslatable, match="call of np.dot"):
        csource.translate("def rhs(t, y, p, dydt):\n    dydt[0] = np.dot(y, y)\n")


@needs_cc
def test_min_max_follow_python_with_nan(tmp_path):
    """min/max keep Python's argument rule, so a NaN flows through exactly as in the Python and numba code."""
    source = "def rhs(t, y, p, dydt):\n    dydt[0] = min(y[0], y[1])\n    dydt[1] = max(y[0], y[1])\n"
    lib = cbuild.library(tmp_path, "minmax", csource.translate(source, ("rhs",)))
    f = cmodel.CFunction(lib, "rhs")
    for a, b in ((np.nan, 1.0), (1.0, np.nan), (2.0, 1.0), (1.0, 2.0)):
        out = np.empty(2)
        f(0.0, np.array([a, b]), np.empty(0), out)
        np.testing.assert_array_equal(out, [min(a, b), max(a, b)])


@needs_cc
def test_library_is_reused_and_a_tampered_one_rebuilt(tmp_path):
    """A signed library is loaded again without compiling; one changed on disk is rebuilt, never loaded."""
    source = "double twice(double x) { return 2.0 * x; }\n"
    cbuild.library(tmp_path, "lib", source)
    assert (tmp_path / "lib.lock").exists()  # the builders' lock lies beside the library, not in <cache>/shared
    assert not (tmp_path.parent.parent / "secret.key").exists()  # a folder outside the cache: the cache's key
    from rotorkit.codegen import cache

    assert not list((cache.cache_dir() / "shared").glob("*lib*.lock"))
    so = tmp_path / "lib.so"
    stamp = so.stat().st_mtime_ns
    cbuild.library(tmp_path, "lib", source)
    assert so.stat().st_mtime_ns == stamp  # reused
    data = bytearray(so.read_bytes())
    data[-1] ^= 0xFF
    planted = tmp_path / "planted.so"  # a new file renamed over it: writing into the loaded one would change this
    planted.write_bytes(bytes(data))   # process's mapped copy under it
    os.replace(planted, so)
    cbuild.library(tmp_path, "lib", source)
    assert so.read_bytes() != bytes(data)  # rebuilt from the source
    cbuild.library(tmp_path, "lib", source.replace("2.0", "3.0"))  # another source: rebuilt, not the old library
    assert "3.0" in (tmp_path / "lib.c").read_text()


@needs_cc
def test_compiler_errors_name_the_file_and_message(tmp_path):
    with pytest.raises(cbuild.CompilerError, match=r"failed on .*broken\.c.*\n.*error"):
        cbuild.library(tmp_path, "broken", "this is not C;\n")


def test_backend_choice(monkeypatch):
    """auto prefers c (unrolled code, a compiler found), then numba, then python; c explicitly without a compiler
    names the fix; c for structured code is refused (auto takes numba there)."""
    from rotorkit.system import resolve_backend, available_backends

    monkeypatch.delenv("ROTORKIT_BACKEND", raising=False)
    if HAS_CC:
        assert resolve_backend("auto") == "c"
    assert resolve_backend("auto", c_ok=False) in ("numba", "python")
    monkeypatch.setenv(cbuild.VARIABLE, "0")
    assert "c" not in available_backends()
    assert resolve_backend("auto") != "c"
    with pytest.raises(ParameterError, match="backend='c' is not available here: install a C compiler"):
        resolve_backend("c")
    monkeypatch.delenv(cbuild.VARIABLE)
    if HAS_CC:
        with pytest.raises(ParameterError, match="unrolled code generation only"):
            resolve_backend("c", c_ok=False)
    with pytest.raises(ParameterError, match="backend='fortran' is unknown"):
        resolve_backend("fortran")


@needs_cc
def test_auto_falls_back_when_the_compiler_fails(monkeypatch, tmp_path):
    """A compiler that fails: backend='auto' warns and compiles with the next back end; backend='c' raises."""
    broken = tmp_path / "cc"
    broken.write_text("#!/bin/sh\necho 'cc: internal error' >&2\nexit 1\n")
    broken.chmod(0o755)
    monkeypatch.setenv(cbuild.VARIABLE, str(broken))
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("ROTORKIT_BACKEND", raising=False)
    from rotorkit import system as system_module
    from rotorkit.codegen import cmodel as cm

    monkeypatch.setattr(cm, "_LOADED", {})
    monkeypatch.setattr(system_module, "_MODULES", {})  # else a module of this structure loaded earlier, whose
    # entry (in the session's cache) holds a C library built and signed before, is used: nothing to compile
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=100.0), Disk(station=1, mass=2.0, radius=0.1),
                      rk.ElasticSupport(station=1, stiffness=2e4)], name="c_backend_fallback")
    with pytest.warns(RuntimeWarning, match="(?s)the c back end failed .*internal error"):
        system = model.compile()
    assert system.backend in ("numba", "python")
    with pytest.raises(cbuild.CompilerError, match="internal error"):
        model.compile(backend="c")


@needs_cc
def test_c_backend_imports_no_numba(tmp_path):
    """Compiling and evaluating with the c back end never imports numba (nor sympy on a warm cache)."""
    code = (
        "import sys, numpy as np, rotorkit as rk\n"
        "s = rk.preset('al31f').compile(backend='c')\n"
        "s.rhs(0.1, np.zeros(s.n_states))\n"
        "print('numba' in sys.modules, 'sympy' in sys.modules)\n"
    )
    env = dict(os.environ, ROTORKIT_CACHE_DIR=str(tmp_path), PYTHONPATH=str(ROOT))
    first = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert first.stdout.split()[0] == "False"
    second = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert second.stdout.split() == ["False", "False"]  # warm: nothing derived or generated, so no sympy either


def test_no_warning_without_a_compiler(monkeypatch):
    """Without a compiler auto quietly takes numba or python: no warning, no error."""
    monkeypatch.setenv(cbuild.VARIABLE, "0")
    monkeypatch.delenv("ROTORKIT_BACKEND", raising=False)
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=100.0), Disk(station=1, mass=2.0, radius=0.1),
                      rk.ElasticSupport(station=1, stiffness=2e4)], name="c_backend_none")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert model.compile().backend in ("numba", "python")


@needs_cc
def test_loop_built_in_a_background_thread(tmp_path, monkeypatch):
    """rotorkit run starts the C loop's build in a thread; integrate then uses that loop, built once."""
    import functools

    from rotorkit.engines import rk_c

    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(rk_c, "_loop", functools.lru_cache(maxsize=None)(rk_c._loop.__wrapped__))
    thread = rk_c.build_in_background()
    assert thread is not None
    thread.join(timeout=600)
    assert rk_c._loop.cache_info().currsize == 1 and rk_c.build_in_background() is None
    assert list((tmp_path / "shared" / "rk_c_loop").glob("rk_loop.so"))
    system = rk.Model([rk.Rotor(name="R", stations=(1,), speed=0.0), Disk(station=1, mass=2.0, radius=0.1),
                       rk.ElasticSupport(station=1, stiffness=2e4)], name="c_backend_thread").compile(backend="c")
    result = rk.simulate(system, (0.0, 0.1), y0=system.initial_state(x1=1e-4), sample_rate=1000.0)
    assert result.stats["engine"] == "compiled" and rk_c._loop.cache_info().misses == 1
    np.testing.assert_allclose(result["x1"], 1e-4 * np.cos(100.0 * result.t), rtol=0, atol=1e-9)
