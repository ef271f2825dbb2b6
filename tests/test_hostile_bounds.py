"""Sizes a user controls are bounded before work starts; wrong kinds of input are named errors.

Each case used to hang, exhaust memory, run for hours or end in a bare
exception (AttributeError, ZeroDivisionError, a TypeError from ``__init__``).
Every check runs before the work it guards, so each case takes milliseconds
(the whole file runs in seconds; a per-test alarm fails a case that hangs).
"""

import signal

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.cli import main
from rotorkit.elements import BallBearing, BeamSegment, LinearBearing, Material
from rotorkit.errors import ArgumentTypeError, ParameterError


@pytest.fixture(autouse=True)
def no_hang():
    def hung(signum, frame):
        raise AssertionError("the check came after the work it should guard")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(60)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def jeffcott(mass=2.0, stiffness=2e4, damping=8.0):
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=300.0), rk.Disk(station=1, mass=mass, radius=0.1),
                     rk.ElasticSupport(station=1, stiffness=stiffness, damping=damping)], name="bounds_jeffcott")


@pytest.fixture(scope="module")
def system():
    return jeffcott().compile(backend="python")


# -- sizes: a named error giving the size and the memory or time it implies -----------
@pytest.mark.parametrize("count", [10**5, 10**9])
def test_beam_element_counts_are_bounded(count):
    with pytest.raises(ParameterError, match=rf"elements = {count}: about .* coordinates.*at most 2000.* GB"):
        BeamSegment(start=1, end=2, length=0.2, outer_diameter=0.05, material=Material.steel(), elements=count)


def test_campbell_speed_counts_are_bounded():
    from rotorkit.analysis.campbell import campbell

    with pytest.raises(ParameterError, match="1000000 speeds, more than the 100000"):
        campbell(jeffcott(), np.linspace(1.0, 1000.0, 10**6), speed_parameter="R_speed", backend="python")


@pytest.mark.parametrize("argv, words", [
    (["campbell", "al31f", "--speeds", "200:3000:100000000"], "COUNT = 100000000 speeds"),
    (["campbell", "al31f", "--cage-samples", "0"], "expected an integer >= 1"),
    (["modes", "al31f", "--shapes", "-1"], "expected an integer >= 0"),
    (["sweep", "al31f", "--param", "rub_stiffness=1e6:2e6:2", "--order", "-1"], "order '-1': the order is not"),
    (["sweep", "al31f", "--param", "rub_stiffness=1e6:2e6:2", "--order", "1/0"], "divides by zero"),
], ids=["speeds", "cage-samples", "shapes", "order -1", "order 1/0"])
def test_cli_counts_and_orders_are_named_errors_before_any_work(tmp_path, capsys, monkeypatch, argv, words):
    def forbidden(*args, **kwargs):
        raise AssertionError("refused too late: the model was compiled")

    monkeypatch.setattr(rk.Model, "compile", forbidden) if argv[0] == "sweep" else None
    code = None
    try:
        code = main(argv + ["--out", str(tmp_path / "out")])
    except SystemExit as exc:  # argparse's own refusal (exit status 2)
        code = exc.code
    assert code == 2
    assert words in capsys.readouterr().err


def test_cage_samples_are_bounded(system):
    from rotorkit.analysis.modes import natural_frequencies

    with pytest.raises(ParameterError, match="cage_samples=1000000000 is too many"):
        natural_frequencies(system, cage_samples=10**9)


def test_sample_times_are_bounded(system):
    with pytest.raises(ParameterError, match=r"sample_times: 100000000 times.*GB"):
        rk.simulate(system, (0.0, 1.0), sample_times=np.broadcast_to(0.5, (10**8,)))


def test_sample_rate_over_the_span_is_bounded(system, monkeypatch):
    from rotorkit import run_checks

    monkeypatch.setattr(run_checks, "_available_memory", lambda: 10**12)  # memory is not what binds here
    with pytest.raises(ParameterError, match=r"1.5e\+08 samples, more than 1e\+08 \(about 12 GB"):
        rk.simulate(system, (0.0, 1.5), sample_rate=1e8)


def test_a_run_that_would_take_about_1e10_explicit_steps_is_refused_before_it_starts():
    stiff = jeffcott(mass=1e-12, stiffness=1e8).compile(backend="python")  # omega = 1e10 rad/s
    with pytest.raises(ParameterError, match=r"steps of about .* s, so \(0, 6\) s takes about .*e\+1\d steps.*Radau"):
        rk.simulate(stiff, (0.0, 6.0), engine="scipy")


def test_equations_of_a_large_model_print_a_summary():
    import sympy as sp

    from rotorkit.symbolic.equations import MAX_DISPLAYED_COORDINATES, MAX_PRINTED_LINES
    from rotorkit.symbolic.lagrange import EquationsOfMotion

    n = 3000
    q = sp.symbols(f"q0:{n}")
    u = sp.symbols(f"u0:{n}")
    diag = sp.ImmutableSparseMatrix(n, n, {(i, i): sp.Symbol("m") for i in range(n)})
    zero = sp.ImmutableSparseMatrix(n, n, {})
    eom = EquationsOfMotion(t=sp.Symbol("t"), coordinates=q, speeds=u, parameters=(sp.Symbol("m"),),
                            mass_matrix=diag, forcing=sp.ImmutableSparseMatrix(n, 1, {}), stiffness=diag,
                            damping=zero)
    assert repr(eom) == ("<EquationsOfMotion: 3000 coordinates, 1 parameters, 3000 non-zero mass entries, "
                         "forces from 0 elements>")
    assert eom._repr_latex_() is None and n > MAX_DISPLAYED_COORDINATES
    text = str(eom)
    assert len(text) < 100 * MAX_PRINTED_LINES
    assert text.endswith("... 5605 more entries (the matrices are mass_matrix, damping, stiffness and forces)")
    assert "q = [q0, q1, q2, q3, q4, q5, ..., q2999]" in text


# -- wrong kinds of input: named errors saying what is expected ---------------------
@pytest.mark.parametrize("call, words", [
    (lambda s: rk.simulate(jeffcott(), (0.0, 0.01)), r"got the Model .*simulate\(model.compile\(\)"),
    (lambda s: rk.simulate("jeffcott", (0.0, 0.01)), "got str; expected a compiled system"),
    (lambda s: rk.Result(t=np.zeros(2), y=np.zeros((1, 2)), state_names=("x1",))[0], "index a result by signal"),
    (lambda s: rk.reduce("text", 2), "expected a rotorkit System or Model, got str"),
    (lambda s: LinearBearing(station=1, kzz=1.0), r"unknown field 'kzz' \(fields: name, station, .*kxx"),
], ids=["simulate(Model)", "simulate(str)", "Result[0]", "reduce(text)", "LinearBearing(kzz)"])
def test_objects_of_the_wrong_kind_are_named_errors(system, call, words):
    with pytest.raises(ArgumentTypeError, match=words):
        call(system)
    assert issubclass(ArgumentTypeError, TypeError) and issubclass(ArgumentTypeError, ParameterError)


@pytest.mark.parametrize("call, words", [
    (lambda s: rk.simulate(s, (0.0, 0.01), y0=[1j, 0, 0, 0]), "y0=.* real numbers"),
    (lambda s: BallBearing(inner_station=1, outer_station=2, contact_stiffness=1e9, clearance=5e-6, n_balls=8,
                           inner_race_radius=0.07, outer_race_radius=0.04), "expected R_inner <= R_outer"),
], ids=["complex y0", "inner race > outer"])
def test_impossible_values_are_named_errors(system, call, words):
    with pytest.raises(ParameterError, match=words):
        call(system)


@pytest.mark.parametrize("method", ["banded", "dense"])
def test_unbalance_response_at_an_undamped_critical_speed_names_the_speed_and_the_mode(method):
    """An undamped Jeffcott rotor (k = 2e4 N/m, m = 2 kg: critical speed sqrt(k/m) = 100 rad/s exactly): the dynamic
    stiffness k - m w^2 is singular at 100 rad/s. Before: numpy's LinAlgError (or inf and nan)."""
    from rotorkit.analysis.linear_model import LinearModel
    from rotorkit.analysis.unbalance import Unbalance, unbalance_response

    def jeffcott(c):
        return LinearModel(mass=2.0 * np.eye(2), damping=c * np.eye(2), stiffness=2e4 * np.eye(2),
                           coordinate_names=("x1", "y1"))

    with pytest.raises(ParameterError, match=r"at speed 100 rad/s \(954.93 rpm\) rotor .* excites at 100 rad/s, an "
                                             r"undamped critical speed.*mode at 100 rad/s moving [xy]1.*add damping"):
        unbalance_response(jeffcott(0.0), [Unbalance(station=1, magnitude=1e-4)], [50.0, 100.0, 150.0],
                           method=method)
    r = unbalance_response(jeffcott(0.0), [Unbalance(station=1, magnitude=1e-4)], [50.0, 150.0], method=method)
    expected = [1e-4 * w**2 / abs(2e4 - 2.0 * w**2) for w in (50.0, 150.0)]  # closed form, undamped off resonance
    np.testing.assert_allclose(r.amplitude("x1"), expected, rtol=1e-12)
    damped = unbalance_response(jeffcott(4.0), [Unbalance(station=1, magnitude=1e-4)], [100.0], method=method)
    assert damped.amplitude("x1")[0] == pytest.approx(1e-4 * 100.0**2 / (4.0 * 100.0), rel=1e-12)  # U w^2 / (c w)


@pytest.mark.parametrize("a, b", [("\ufb01", "fi"), ("\uff41", "a"), ("\u211b", "R")], ids=["fi ligature", "full-width",
                                                                                          "script R"])
def test_stations_that_are_the_same_identifier_after_normalisation_are_refused_at_build(a, b):
    """'ﬁ' and 'fi' gave coordinates xﬁ and xfi: distinct strings, one Python identifier, so the energy balance
    (whose generated function takes them as arguments) failed with 'SyntaxError: duplicate argument'."""
    from rotorkit.errors import TopologyError

    def model(second):
        return rk.Model([rk.Rotor(name="S", stations=(a, second), speed=50.0),
                         rk.Disk(station=a, mass=1.0, radius=0.1), rk.LumpedMass(station=second, mass=1.0),
                         rk.ElasticSupport(station=a, stiffness=1e4),
                         rk.ElasticSupport(station=second, stiffness=2e4, name="other")])

    with pytest.raises(TopologyError, match=rf"stations {a!r} and {b!r} name the same coordinates .*the same "
                                            rf"identifier {b!r} after Unicode normalisation"):
        model(b)
    assert model("other_station").coordinate_names[:2] == (f"x{a}", "xother_station")
