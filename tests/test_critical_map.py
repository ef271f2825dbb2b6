"""The critical speed map's synchronous eigenproblem against the Campbell sweep and closed forms."""

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.errors import ParameterError


@pytest.fixture(scope="module")
def overhung():
    """A gyroscopic beam rotor: 3 Timoshenko elements, an overhung disk, placeholder supports at 1 and 3."""
    steel = rk.Material.steel()
    elements = [rk.Rotor(name="R", stations=(1, 2, 3, 4), speed=0.0)]
    elements += [rk.BeamSegment(start=s, end=s + 1, length=0.2, outer_diameter=0.04, material=steel)
                 for s in (1, 2, 3)]
    elements += [rk.Disk.from_geometry(station=4, width=0.03, outer_diameter=0.3, material=steel)]
    elements += [rk.ElasticSupport(station=s, stiffness=1.0) for s in (1, 3)]
    return rk.linear_model(rk.Model(elements, name="overhung_map").compile(backend="python"))


def test_synchronous_equals_the_campbell_sweep(overhung):
    ks = np.logspace(5, 8, 4)
    a = rk.critical_speed_map(overhung, (1, 3), ks, (0.0, 2000.0), n_critical=2, n_speeds=60, method="campbell")
    b = rk.critical_speed_map(overhung, (1, 3), ks, (0.0, 2000.0), n_critical=2, method="synchronous")
    auto = rk.critical_speed_map(overhung, (1, 3), ks, (0.0, 2000.0), n_critical=2)
    assert np.isfinite(b.speeds[:, 0]).all() and np.isfinite(b.backward[:, 0]).all()
    assert np.array_equal(np.isnan(a.speeds), np.isnan(b.speeds))
    assert np.allclose(a.speeds, b.speeds, rtol=1e-7, equal_nan=True)
    assert np.allclose(a.backward, b.backward, rtol=1e-7, equal_nan=True)
    assert np.array_equal(auto.speeds, b.speeds, equal_nan=True)
    assert np.all(b.speeds[:, 0] > b.backward[:, 0])  # gyroscopic stiffening of the overhung disk


def test_jeffcott_map_is_sqrt_k_over_m_in_both_directions():
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=0.0), rk.Disk(station=1, mass=2.0, radius=0.1),
                      rk.ElasticSupport(station=1, stiffness=1.0)], name="jeffcott_map")
    lin = rk.linear_model(model.compile(backend="python"))
    ks = np.array([1e4, 4e4, 1e5])
    m = rk.critical_speed_map(lin, (1,), ks, (0.0, 1000.0), n_critical=1)
    expected = np.sqrt((ks + 1.0) / 2.0)
    assert m.speeds[:, 0] == pytest.approx(expected, rel=1e-12)
    assert m.backward[:, 0] == pytest.approx(expected, rel=1e-12)  # no gyroscopics: a double root


def test_synchronous_is_refused_where_it_does_not_apply():
    lin = rk.LinearModel(mass=np.eye(2), damping=np.zeros((2, 2)), stiffness=np.eye(2),
                         circulatory=np.array([[0.0, 1.0], [-1.0, 0.0]]), coordinate_names=("x1", "y1"))
    with pytest.raises(ParameterError, match="synchronous"):
        rk.critical_speed_map(lin, (1,), [1.0], (0.0, 10.0), method="synchronous")
    with pytest.raises(ParameterError, match="method='nope'"):
        rk.critical_speed_map(lin, (1,), [1.0], (0.0, 10.0), method="nope")


def test_map_plot_legend_names_only_drawn_curves_and_tells_bearings_apart():
    """No legend entry for a critical speed order with none in the range; each bearing its own shade (kxx
    dotted, kyy dash-dot); with show_backward an order's backward speeds are drawn even where its forward
    ones are all outside the range."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotorkit.linear.critical_map import CriticalSpeedMap

    k = np.logspace(6, 8, 5)
    forward = np.column_stack([np.sqrt(k / 2.0), np.full(k.size, np.nan)])  # order 2: none in the range
    backward = np.column_stack([np.sqrt(k / 3.0), np.sqrt(k / 1.5)])
    curves = {f"{b} {d}": (np.array([1.0, 2e3]), np.array([2e6, 3e6])) for b in ("brg3", "brg18") for d in
              ("kxx", "kyy")}
    cmap = CriticalSpeedMap(stiffnesses=k, speeds=forward, backward=backward, supports=("3", "18"),
                            bearing_curves=curves)
    ax = cmap.plot(show_backward=True)
    labels = [line.get_label() for line in ax.get_lines()]
    assert "critical speed 1" in labels and "critical speed 2" not in labels
    drawn = [line.get_ydata() for line in ax.get_lines() if line.get_linestyle() == "--"]
    assert len(drawn) == 2  # both backward orders, the second although its forward column is all NaN
    style = {line.get_label(): (line.get_color(), line.get_linestyle()) for line in ax.get_lines()}
    assert style["brg3 kxx"][0] == style["brg3 kyy"][0] != style["brg18 kxx"][0] == style["brg18 kyy"][0]
    assert style["brg3 kxx"][1] == ":" and style["brg3 kyy"][1] == "-."
    plt.close("all")
