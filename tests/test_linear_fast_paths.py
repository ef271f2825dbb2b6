"""The fast linear paths (issue 24): what they skip (derivation, compilation, scipy, pint) and that they agree."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from rotorkit import BeamSegment, Disk, Material, Model, Rotor
from rotorkit.elements import LinearBearing

ROOT = Path(__file__).resolve().parents[1]


def beam_rotor():
    """Three beam elements, two disks, a tabulated anisotropic cross-coupled bearing and a constant one."""
    steel = Material(density=7850.0, youngs_modulus=2.1e11, shear_modulus=8.1e10)
    elements = [Rotor(name="R", stations=(1, 2, 3, 4), speed=500.0)]
    elements += [BeamSegment(start=s, end=s + 1, length=0.2, outer_diameter=0.05, material=steel) for s in (1, 2, 3)]
    elements += [Disk(station=2, mass=8.0, polar_inertia=0.08, diametral_inertia=0.04),
                 Disk(station=3, mass=5.0, polar_inertia=0.05, diametral_inertia=0.025)]
    elements.append(LinearBearing.tabulated(station=1, speeds=[0.0, 400.0, 1000.0], kxx=[1e7, 2e7, 3e7],
                                            kyy=[8e6, 1.2e7, 2.5e7], cxx=[2e3, 1.5e3, 1e3], cyy=[2e3, 1.6e3, 1.2e3],
                                            kxy=[0.0, 2e6, 5e6], kyx=[0.0, -2e6, -5e6]))
    elements.append(LinearBearing(station=4, kxx=1.5e7, kyy=1e7, cxx=800.0, cyy=800.0))
    return Model(elements, name="beam_rotor_fast")


_WARM = """
import sys
import numpy as np
import rotorkit.symbolic.lagrange as lagrange
from rotorkit.model import Model
calls = []
for owner, name in ((lagrange, "derive"), (lagrange, "_derive"), (lagrange, "element_matrices"), (Model, "compile")):
    original = getattr(owner, name)
    def counted(*args, _original=original, _name=name, **kwargs):
        calls.append(_name)
        return _original(*args, **kwargs)
    setattr(owner, name, counted)
import rotorkit as rk
from rotorkit.analysis.static import static_deflection
from rotorkit.cli import main
model = rk.load_model({path!r})
static_deflection(model)
for argv in (["campbell", {path!r}, "--speeds", "0:9000 rpm:5", "--modes", "4"],
             ["unbalance", {path!r}, "--speeds", "10:1000:7", "--unbalance", "2:1e-4", "--station", "2"],
             ["static", {path!r}], ["modes", {path!r}, "--shapes", "1"]):
    assert main(argv + ["--out", {out!r}]) == 0, argv
print("CALLS", len(calls), calls)
"""

_LIGHT = """
import sys
import numpy as np
import rotorkit as rk
from rotorkit.analysis.campbell import campbell
from rotorkit.analysis.static import static_deflection
from rotorkit.analysis.unbalance import unbalance_response
model = rk.load_model({path!r})
campbell(model, np.linspace(0.0, 1000.0, 5), n_modes=4)
unbalance_response(model, [(2, 1e-4, 0.0)], np.linspace(10.0, 1000.0, 7))
static_deflection(model)
print(sorted({{m.split(".")[0] for m in sys.modules}} & {{"scipy", "pint", "sympy", "matplotlib"}}))
"""


@pytest.mark.slow
def test_a_warm_process_neither_derives_nor_compiles_on_the_linear_cli_paths(tmp_path):
    """static_deflection and the campbell, unbalance, static and modes commands of a linear model file."""
    path = beam_rotor().save(tmp_path / "rotor.toml")
    env = dict(os.environ, ROTORKIT_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    script = textwrap.dedent(_WARM).format(path=str(path), out=str(tmp_path / "out"))
    outputs = []
    for _ in range(2):
        out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, cwd=ROOT,
                             timeout=900)
        assert out.returncode == 0, out.stderr
        outputs.append(out.stdout)
    cold, warm = (int(o.split("CALLS")[-1].split()[0]) for o in outputs)
    assert cold >= 1 and "compile" not in outputs[0].split("CALLS")[-1].split("MODULES")[0]  # derives, never compiles
    assert warm == 0  # the warm one reads the cache
    light = subprocess.run([sys.executable, "-c", textwrap.dedent(_LIGHT).format(path=str(path))], env=env,
                           capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert light.returncode == 0, light.stderr
    assert light.stdout.strip() == "[]"  # Campbell, unbalance, static: numpy alone (no scipy, pint, sympy)


def test_linear_modes_of_the_cli_equal_the_compiled_systems_modes():
    from rotorkit.analysis.modes import natural_frequencies
    from rotorkit.cli.modes import linear_modes

    model = beam_rotor()
    fast = linear_modes(model)
    ref = natural_frequencies(model.compile(backend="python"))
    assert len(fast) == len(ref)
    np.testing.assert_allclose(fast.frequencies, ref.frequencies, rtol=1e-9)
    np.testing.assert_allclose(fast.damping_ratios, ref.damping_ratios, rtol=1e-7, atol=1e-12)
    assert fast.whirl == ref.whirl
    for k in range(len(ref)):  # shapes scaled to a largest entry 1: equal up to rounding
        np.testing.assert_allclose(fast.shapes[:, k], ref.shapes[:, k], atol=1e-6)
    np.testing.assert_allclose(fast.operating_point, ref.operating_point, atol=1e-12)
    assert fast.layout is not None


def test_dense_matrices_equal_the_sparse_ones():
    from rotorkit.analysis.linear_matrices import linear_evaluator

    evaluator = linear_evaluator(beam_rotor(), free=("R_speed",))
    for w in (0.0, 333.0, 900.0):
        for A, B in zip(evaluator.dense(R_speed=w), evaluator(R_speed=w)):
            np.testing.assert_allclose(A, B.toarray(), rtol=1e-15, atol=0)


def test_newton_refinement_of_the_critical_speeds_equals_the_full_eigen_solution(monkeypatch):
    """The located speeds with the Newton refinement and with a full eigen-solution at each step agree to xtol."""
    import rotorkit.linear.eigenpair as eigenpair
    from rotorkit.analysis.campbell import campbell

    model = beam_rotor()
    speeds = np.linspace(0.0, 3000.0, 13)
    fast = campbell(model, speeds, n_modes=4)
    monkeypatch.setattr(eigenpair, "follow_mode", lambda *args, **kwargs: None)
    slow = campbell(model, speeds, n_modes=4)
    assert len(fast.crossings) == len(slow.crossings) >= 2
    for a, b in zip(fast.crossings, slow.crossings):
        assert (a.rotor, a.order, a.mode, a.whirl) == (b.rotor, b.order, b.mode, b.whirl)
        assert a.speed == pytest.approx(b.speed, abs=1e-9 * 3000.0 * 10)
    assert [o.mode for o in fast.onsets] == [o.mode for o in slow.onsets]
    for a, b in zip(fast.onsets, slow.onsets):
        assert a.speed == pytest.approx(b.speed, abs=1e-9 * 3000.0 * 10)
    np.testing.assert_array_equal(fast.frequencies, slow.frequencies)  # the grid is solved the same way


def test_newton_eigenpair_converges_to_the_eigenvalue_of_a_jeffcott_rotor():
    """m x'' + c x' + k x = 0 (stiffnesses kx, ky): lambda = -c/2m + i sqrt(k/m - (c/2m)^2) of each direction."""
    from rotorkit.linear.eigenpair import newton_eigenpair

    m, c, kx, ky = 2.0, 4.0, 2e4, 3e4
    M, C, K = np.eye(2) * m, np.eye(2) * c, np.diag([kx, ky])
    for k, start in ((kx, np.array([1.0, 0.2j])), (ky, np.array([0.2, 1.0]))):
        lam, x = newton_eigenpair(M, C, K, -0.5 + 0.95j * np.sqrt(k / m), start)
        assert lam == pytest.approx(complex(-c / (2 * m), np.sqrt(k / m - (c / (2 * m)) ** 2)), rel=1e-14)
        assert np.linalg.norm((lam**2 * M + lam * C + K) @ x) < 1e-10 * k * np.linalg.norm(x)
    assert newton_eigenpair(M, C, K, 0.0, np.array([1.0, 1.0]), maxiter=1) is None  # one step does not converge


@pytest.mark.parametrize("text, expected", [
    ("0:15000 rpm:3", [0.0, 7500 * np.pi / 30, 15000 * np.pi / 30]),
    ("0 rpm:1500:2", [0.0, 1500 * np.pi / 30]),  # a unit on START applies to STOP too
    ("10:20:3", [10.0, 15.0, 20.0]),
    ("1 rad/s:3 rad/s:3", [1.0, 2.0, 3.0]),
])
def test_speeds_of_the_cli_are_read_with_a_unit_on_either_bound(text, expected):
    from rotorkit.cli.linear_common import parse_speeds

    np.testing.assert_allclose(parse_speeds(text, None), expected, rtol=1e-15)


def test_speeds_of_the_cli_need_no_pint_for_the_common_units():
    code = ("import sys\nfrom rotorkit.cli.linear_common import parse_speeds\n"
            "parse_speeds('0:15000 rpm:31', None)\nprint('pint' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=str(ROOT)), cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize("text, message", [
    ("0:15000 m:3", r"--speeds '0:15000 m:3'"),
    ("0 rpm:15 rad/s:3", "different units"),
    ("5:1:3", "START < STOP"),
])
def test_bad_speeds_of_the_cli_are_refused(text, message):
    from rotorkit.cli.linear_common import parse_speeds
    from rotorkit.errors import RotorkitError

    with pytest.raises(RotorkitError, match=message):
        parse_speeds(text, None)


def test_the_static_deflection_plot_draws_the_rotor_under_the_deflection():
    """Shaft outline, disks and bearings as patches below the curves (as under the mode shapes)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from rotorkit import Maneuver
    from rotorkit.analysis.static import static_deflection

    model = Model(list(beam_rotor().elements) + [Maneuver.steady(gravity=9.81)], name="beam_rotor_fast_gravity")
    result = static_deflection(model)
    assert result.layout is not None
    fig, ax = plt.subplots()
    assert result.plot(ax=ax) is ax
    lowest = min(min(line.get_ydata()) for line in ax.get_lines() if len(line.get_ydata()) > 2)
    patches = ax.patches
    assert len(patches) >= 3 + 2 + 2  # three shaft segments, two disks, two bearings
    assert all(p.get_window_extent().y1 <= ax.transData.transform((0.0, lowest))[1] + 1e-6 for p in patches)
    fig_without, ax_without = plt.subplots()
    result.plot(ax=ax_without, rotor=False)
    assert not ax_without.patches
    plt.close(fig)
    plt.close(fig_without)


_READ = """
import sys
import rotorkit as rk
model = rk.load_model({path!r})
print(sorted(m for m in sys.modules if m.startswith("rotorkit.elements.")))
print(sorted({{m.split(".")[0] for m in sys.modules}} & {{"scipy", "pint", "sympy", "matplotlib", "numba"}}))
rk.elements.Seal  # noqa: B018 (control: a name of the package imports its module on use)
print("rotorkit.elements.seal" in sys.modules)
"""


def test_reading_a_model_file_imports_only_the_element_modules_it_uses():
    """compressor.toml holds beams, disks, linear bearings, a maneuver: no seal, fluid film, rub or taper module."""
    out = subprocess.run([sys.executable, "-c", _READ.format(path=str(ROOT / "examples" / "compressor.toml"))],
                         env=dict(os.environ, PYTHONPATH=str(ROOT)), capture_output=True, text=True, cwd=ROOT,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    loaded, heavy, control = out.stdout.strip().splitlines()
    assert heavy == "[]"  # the model file read with numpy alone
    for used in ("beam", "masses", "linear_bearing", "material", "rotor", "maneuver"):
        assert f"'rotorkit.elements.{used}'" in loaded
    for unused in ("seal", "journal_bearing", "squeeze_film", "tapered", "rub", "intershaft_rub", "bearing"):
        assert f"'rotorkit.elements.{unused}'" not in loaded
    assert control == "True"
