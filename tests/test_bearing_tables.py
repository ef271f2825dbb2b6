"""Bearing coefficient tables: PCHIP and linear interpolation, extrapolation, added mass, CSV.

- PCHIP tables equal ``scipy.interpolate.PchipInterpolator`` on the same
  knots (to 1e-12) in the linear matrices (stiffness, cross-coupling,
  damping) and in the compiled right-hand side of every back end here.
- Outside the table: held end values, or the end values continued along the
  end slope (the end segment's, or PCHIP's end derivative from scipy).
- Added mass ``m_a`` on a single mass ``m`` on a spring ``k``:
  ``w = sqrt(k / (m + m_a))`` (constant and tabulated against speed).
- CSV: a written table reads back equal; units in the header are converted.
- Campbell diagram of a mass on a PCHIP bearing with PCHIP added mass:
  ``sqrt(k(W) / (m + m_a(W)))`` at every speed ``W``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.interpolate import PchipInterpolator

from rotorkit import LumpedMass, Model, Rotor
from rotorkit.analysis.linear_matrices import linear_evaluator
from rotorkit.elements import LinearBearing
from rotorkit.errors import ParameterError
from rotorkit.system import available_backends

SPEEDS = [0.0, 150.0, 300.0, 420.0, 700.0, 1000.0]  # rad/s, uneven
KXX = [1.0e7, 1.6e7, 1.5e7, 1.5e7, 3.0e7, 2.0e7]  # non-monotone, a flat part
KXY = [0.0, 2e6, 5e6, 9e6, 1.2e7, 1.3e7]
CYY = [4e3, 3e3, 2.5e3, 2.6e3, 2.0e3, 1.0e3]
MASS = 20.0


def model(**options):
    bearing = LinearBearing.tabulated(station=1, speeds=SPEEDS, kxx=KXX, kyy=KXX, kxy=KXY, kyx=[-v for v in KXY],
                                      cxx=CYY, cyy=CYY, name="brg", **options)
    return Model([Rotor(name="R", stations=(1,), speed=100.0), LumpedMass(station=1, mass=MASS), bearing])


def matrices_at(evaluator, speed):
    return [a.toarray() for a in evaluator(R_speed=speed)]


@pytest.fixture(scope="module")
def pchip_model():
    return model(interpolation="pchip")


def test_pchip_in_linear_matrices_equals_scipy(pchip_model):
    evaluator = linear_evaluator(pchip_model, free=("R_speed",))
    k, kxy, c = (PchipInterpolator(SPEEDS, v) for v in (KXX, KXY, CYY))
    for w in np.linspace(0.0, 1000.0, 37):
        M, C, K = matrices_at(evaluator, w)
        np.testing.assert_allclose(K, [[k(w), kxy(w)], [-kxy(w), k(w)]], rtol=1e-12, atol=1e-12 * 3e7)
        np.testing.assert_allclose(np.diag(C), [c(w), c(w)], rtol=1e-12)
        np.testing.assert_allclose(M, MASS * np.eye(2), rtol=1e-15)


@pytest.mark.parametrize("backend", available_backends())
def test_pchip_in_compiled_rhs_equals_scipy(pchip_model, backend):
    system = pchip_model.compile(backend=backend)
    assert system.backend == backend
    k, kxy = PchipInterpolator(SPEEDS, KXX), PchipInterpolator(SPEEDS, KXY)
    for w in (37.0, 222.0, 555.5, 999.0):
        sys_w = system.with_parameters(R_speed=w)
        y = sys_w.initial_state(x1=1e-3)
        dydt = sys_w.rhs(0.0, y)
        ax, ay = dydt[sys_w.state_index("x1_dot")], dydt[sys_w.state_index("y1_dot")]
        assert ax == pytest.approx(-k(w) * 1e-3 / MASS, rel=1e-12)
        assert ay == pytest.approx(kxy(w) * 1e-3 / MASS, rel=1e-12)


@pytest.mark.parametrize("interpolation", ["linear", "pchip"])
def test_extrapolation_hold_and_linear(interpolation):
    held = linear_evaluator(model(interpolation=interpolation), free=("R_speed",))
    slope = linear_evaluator(model(interpolation=interpolation, extrapolation="linear"), free=("R_speed",))
    if interpolation == "pchip":
        d = PchipInterpolator(SPEEDS, KXX).derivative()
        first, last = d(SPEEDS[0]), d(SPEEDS[-1])
    else:
        first = (KXX[1] - KXX[0]) / (SPEEDS[1] - SPEEDS[0])
        last = (KXX[-1] - KXX[-2]) / (SPEEDS[-1] - SPEEDS[-2])
    for w, end, s, dw in ((-50.0, KXX[0], first, -50.0), (1300.0, KXX[-1], last, 300.0)):
        assert matrices_at(held, w)[2][0, 0] == pytest.approx(end, rel=1e-12)
        assert matrices_at(slope, w)[2][0, 0] == pytest.approx(end + s * dw, rel=1e-12)
    inside = 555.0
    assert matrices_at(slope, inside)[2][0, 0] == pytest.approx(matrices_at(held, inside)[2][0, 0], rel=1e-14)


def _frequencies(model_, speed=None):
    evaluator = linear_evaluator(model_, free=("R_speed",))
    M, _, K = matrices_at(evaluator, 0.0 if speed is None else speed)
    return np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True))


def test_added_mass_lowers_the_natural_frequency():
    k, ma = 4e6, 5.0
    m = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=MASS),
               LinearBearing(station=1, kxx=k, kyy=k, mxx=ma, myy=ma)])
    np.testing.assert_allclose(_frequencies(m), math.sqrt(k / (MASS + ma)), rtol=1e-12)


def test_tabulated_added_mass_against_speed():
    k, masses = 4e6, [0.0, 2.0, 8.0, 3.0]
    speeds = [0.0, 100.0, 200.0, 400.0]
    m = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=MASS),
               LinearBearing.tabulated(station=1, speeds=speeds, kxx=[k] * 4, kyy=[k] * 4, mxx=masses, myy=masses,
                                       mxy=[0.5] * 4, myx=[0.5] * 4, interpolation="pchip")])
    ma = PchipInterpolator(speeds, masses)
    for w in (50.0, 250.0):
        M = np.array([[MASS + ma(w), 0.5], [0.5, MASS + ma(w)]])
        exact = np.sqrt(scipy.linalg.eigh(k * np.eye(2), M, eigvals_only=True))
        np.testing.assert_allclose(_frequencies(m, w), exact, rtol=1e-12)


def test_csv_round_trip(tmp_path):
    b = LinearBearing.tabulated(station=3, speeds=SPEEDS, kxx=KXX, kyy=KXX, kxy=KXY, cyy=CYY, mxx=[1.0] * 6,
                                myy=[1.5] * 6, interpolation="pchip")
    path = tmp_path / "bearing.csv"
    b.to_csv(path)
    back = LinearBearing.from_csv(path, station=3, interpolation="pchip")
    assert back == b


def test_csv_units_in_the_header(tmp_path):
    path = tmp_path / "b.csv"
    path.write_text("# from the supplier\nspeed [rpm],kxx [MN/m],kyy [N/m], cxx [kN*s/m]\n\n"
                    "0,1.5,2e6,3\n6000,2.5,3e6,4\n")
    b = LinearBearing.from_csv(path, station=1)
    assert b.speeds == pytest.approx((0.0, 6000 * math.pi / 30))
    assert b.kxx == pytest.approx((1.5e6, 2.5e6)) and b.cxx == pytest.approx((3e3, 4e3))
    assert b.interpolation == "linear" and b.extrapolation == "hold"


@pytest.mark.parametrize("make, match", [
    (lambda: model(interpolation="cubic"), r"interpolation = 'cubic': expected one of \('linear', 'pchip'\)"),
    (lambda: model(extrapolation="nearest"), r"extrapolation = 'nearest': expected one of \('hold', 'linear'\)"),
    (lambda: LinearBearing(station=1, kxx=1e6, kyy=1e6, interpolation="pchip"), r"only used with a table"),
    (lambda: LinearBearing(station=1, kxx=1e6, kyy=1e6, mxy=1.0, myx=2.0), r"mxy = 1.0 and myx = 2.0 differ"),
    (lambda: LinearBearing(station=1, kxx=1e6, kyy=1e6, mxx=-1.0), r"mxx"),
])
def test_bad_table_input_is_a_named_error(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


@pytest.mark.parametrize("text, match", [
    ("speed,kzz\n0,1\n1,2\n", r"column 'kzz': expected 'speed' or a coefficient"),
    ("kxx,kyy\n0,1\n1,2\n", r"no 'speed' column"),
    ("speed,kxx,kyy\n0,1,x\n1,2,3\n", r"data row 1, column 'kyy': 'x' is not a number"),
    ("speed,kxx,kyy\n0,1,1\n", r"at least two rows"),
])
def test_bad_csv_is_a_named_error(tmp_path, text, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ParameterError, match=match):
        LinearBearing.from_csv(path, station=1)


def test_table_bearing_model_file_round_trip(pchip_model):
    from rotorkit.modelfile import dumps_model, loads_model

    back, _ = loads_model(dumps_model(pchip_model))
    assert back.parameters == pchip_model.parameters and back.structure_key == pchip_model.structure_key
    assert back.elements[-1].interpolation == "pchip"


def test_campbell_follows_pchip_stiffness_and_added_mass():
    from rotorkit.analysis.campbell import campbell

    speeds, ks, mas = [0.0, 200.0, 500.0, 900.0], [2e6, 6e6, 5e6, 9e6], [0.0, 4.0, 1.0, 2.0]
    model_ = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=MASS),
                    LinearBearing.tabulated(station=1, speeds=speeds, kxx=ks, kyy=ks, mxx=mas, myy=mas,
                                            interpolation="pchip")])
    sweep = np.linspace(0.0, 1000.0, 11)
    result = campbell(model_, sweep, n_modes=2, refine=False, backend="python")
    k, ma = PchipInterpolator(speeds, ks), PchipInterpolator(speeds, mas)
    exact = np.sqrt(k(np.minimum(sweep, 900.0)) / (MASS + ma(np.minimum(sweep, 900.0))))  # held above 900
    np.testing.assert_allclose(result.natural_frequencies, np.column_stack([exact, exact]), rtol=1e-10)
