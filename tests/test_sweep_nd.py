"""n-D sweeps: spaces, the labelled dataset, order amplitudes and a rub bifurcation diagram against closed forms.

The Jeffcott rotor (tests/sweep_models.py) without contact whirls at the
closed-form unbalance amplitude ``A(W) = e r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2)``,
``r = W / wn``; the rub starts where ``A(W)`` equals the clearance.
"""

import json
import math

import numpy as np
import pytest

from rotorkit.errors import ParameterError
from rotorkit.sweep import (DATASET_NAME, Grid, PointList, Scene, latin_hypercube, load_sweep, parse_order,
                            run_sweep)
from sweep_models import CLEARANCE, SPIN, build_jeffcott, unbalance_amplitude  # noqa: E402


# ---------------------------------------------------------------------------
# Spaces: lazy, size-checked
# ---------------------------------------------------------------------------


def test_grid_points_are_computed_on_demand():
    grid = Grid({"a": [1.0, 2.0, 3.0], "b": [10.0, 20.0]})
    assert grid.size == 6 and grid.shape == (3, 2) and grid.dims == ("a", "b")
    assert [grid.point(i) for i in (0, 1, 5)] == [{"a": 1.0, "b": 10.0}, {"a": 1.0, "b": 20.0}, {"a": 3.0, "b": 20.0}]


def test_a_huge_grid_is_refused_from_its_axis_lengths_alone():
    class Huge:  # a sequence that cannot be materialised: only its length is asked
        def __len__(self):
            return 10**5

        def __iter__(self):
            raise AssertionError("the grid must not iterate the values of a refused axis")

    with pytest.raises(ParameterError, match=r"100,000 x 100,000 .* 10,000,000,000 points.*max_points=100,000"):
        Grid({"a": Huge(), "b": Huge()})


def test_latin_hypercube_has_one_point_per_stratum_of_each_parameter():
    n = 16
    space = latin_hypercube({"k": (1e5, 1e7), "mu": (0.0, 0.3)}, n, seed=3, log=["k"])
    assert space.kind == "lhs" and space.table.shape == (n, 2)
    strata_k = np.floor(n * (np.log(space.table[:, 0]) - math.log(1e5)) / (math.log(1e7) - math.log(1e5)))
    strata_mu = np.floor(n * space.table[:, 1] / 0.3)
    assert sorted(strata_k) == list(range(n)) and sorted(strata_mu) == list(range(n))
    np.testing.assert_array_equal(latin_hypercube({"k": (1e5, 1e7), "mu": (0.0, 0.3)}, n, seed=3, log=["k"]).table,
                                  space.table)  # reproducible


@pytest.mark.parametrize("make, match", [
    (lambda: PointList(["a", "b"], [[1.0, 2.0], [1.0, 2.0]]), "appears twice"),
    (lambda: PointList(["a", "b"], [[1.0, 2.0, 3.0]]), r"shape \(n_points, 2\)"),
    (lambda: PointList(["a", "a"], [[1.0, 2.0]]), "appears twice"),
    (lambda: latin_hypercube({"a": (1.0, 0.0)}, 4), "low < high"),
    (lambda: latin_hypercube({"a": (0.0, 1.0)}, 0), "integer >= 1"),
    (lambda: latin_hypercube({"a": (0.0, 1.0)}, 10**6), "1,000,000 points"),
    (lambda: Grid({}), "dict of parameter name"),
])
def test_bad_spaces(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


@pytest.mark.parametrize("text, rotors, expected", [
    ("1/2", ["LP", "HP"], {"LP": 0.5}),
    ("HP - LP", ["LP", "HP"], {"HP": 1.0, "LP": -1.0}),
    ("3/2 LP + 2*HP", ["LP", "HP"], {"LP": 1.5, "HP": 2.0}),
    ("1", ["R"], {"R": 1.0}),
])
def test_parse_order(text, rotors, expected):
    assert parse_order(text, rotors) == expected


@pytest.mark.parametrize("text, match", [("", "expected"), ("1/2 XX", "'XX' is not a rotor"), ("1 2", "expected")])
def test_parse_order_rejects(text, match):
    with pytest.raises(ParameterError, match=match):
        parse_order(text, ["LP", "HP"])


# ---------------------------------------------------------------------------
# A 2-D sweep as a labelled dataset
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def grid_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("nd") / "grid"
    ds = run_sweep(build_jeffcott, {"eccentricity": [1e-5, 3e-5], "speed": [200.0, 300.0]}, out_dir=out,
                   window=(0.2, 0.5), workers=1, orders=["1", "1/2"], signals=["x1", "y1"], poincare=["x1", "y1"],
                   poincare_revolutions=4, overrides={"rub_stiffness": 1e5}, energy=True)
    return out, ds


def test_the_dataset_is_labelled_and_matches_the_closed_form(grid_sweep):
    import xarray as xr

    out, ds = grid_sweep
    assert ds.amplitude.dims == ("eccentricity", "speed", "signal", "frequency")
    assert ds.eccentricity.attrs["units"] == "m" and ds.speed.attrs["units"] == "rad/s"
    assert ds.frequency.attrs["units"] == "rad/s" and ds.max_displacement.attrs["units"] == "m"
    assert all("long_name" in ds[v].attrs for v in ds.data_vars)
    assert (ds.status == "ok").all()
    # no contact (amplitudes below the clearance): the 1x order is the closed-form unbalance response
    for e in (1e-5, 3e-5):
        for w in (200.0, 300.0):
            got = float(ds.order_amplitude.sel(eccentricity=e, speed=w, signal="x1", order="1"))
            assert got == pytest.approx(unbalance_amplitude(e, w), rel=2e-3)
            radius = np.hypot(ds.poincare.sel(eccentricity=e, speed=w, poincare_signal="x1"),
                              ds.poincare.sel(eccentricity=e, speed=w, poincare_signal="y1"))
            np.testing.assert_allclose(radius[-3:], unbalance_amplitude(e, w), rtol=2e-3)  # once per revolution
            assert float(ds.max_displacement.sel(eccentricity=e, speed=w)) >= unbalance_amplitude(e, w)  # + start
    assert float(ds.order_amplitude.sel(signal="x1", order="1/2").max()) < 0.1 * float(
        ds.order_amplitude.sel(signal="x1", order="1").min())  # only the decaying free whirl near 1/2
    assert float(ds.energy_residual.max()) < 1e-3
    # the netCDF file holds the same
    with xr.open_dataset(out / DATASET_NAME) as nc:
        np.testing.assert_array_equal(nc.order_amplitude.values, ds.order_amplitude.values)
        assert list(nc.status.values.ravel()) == ["ok"] * 4
        assert nc.speed.attrs["units"] == "rad/s"
    again = load_sweep(out)
    np.testing.assert_array_equal(again.amplitude.values, ds.amplitude.values)


def test_maps_and_cascade_of_a_grid(grid_sweep):
    from rotorkit.plotting.maps import plot_bifurcation, plot_order_map, plot_status_map
    from rotorkit.sweep import Cascade

    _, ds = grid_sweep
    ax = plot_order_map(ds, "1", "x1")
    assert ax.get_xlabel() == "speed (rad/s)" and ax.get_ylabel() == "eccentricity (m)"
    assert len(ax.collections) == 1
    ax = plot_status_map(ds)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["ok (4)"]  # with its count
    ax = plot_bifurcation(ds.sel(eccentricity=1e-5), "x1")
    assert ax.get_xlabel() == "speed (rad/s)" and ax.get_ylabel().endswith("(m)")
    cascade = Cascade.from_dataset(ds.sel(eccentricity=3e-5))
    assert cascade.parameter == "speed" and cascade.amplitude["x1"].shape == (2, ds.frequency.size)
    with pytest.raises(ParameterError, match="select all but one"):
        Cascade.from_dataset(ds)
    with pytest.raises(ParameterError, match="orders are"):
        plot_order_map(ds, "3/2")


# ---------------------------------------------------------------------------
# Bifurcation diagram of the rub: contact begins where A(W) = clearance
# ---------------------------------------------------------------------------


def test_rub_onset_speed_against_the_closed_form(tmp_path):
    onset = 80.0  # rad/s: choose the unbalance so that A(onset) = clearance
    eccentricity = CLEARANCE / unbalance_amplitude(1.0, onset)
    speeds = [60.0, 72.0, 77.0, 83.0, 88.0, 95.0]
    ds = run_sweep(build_jeffcott, "speed", speeds, out_dir=tmp_path, t_end=1.0, window=(0.6, 1.0), workers=1,
                   signals=["x1", "y1"], poincare_revolutions=3,
                   overrides={"eccentricity": eccentricity, "rub_stiffness": 1e6, "friction": 0.1})
    radius = np.hypot(ds.poincare.sel(poincare_signal="x1"), ds.poincare.sel(poincare_signal="y1")).values
    for i, w in enumerate(speeds):
        free = unbalance_amplitude(eccentricity, w)
        contact = str(ds.status.values[i]) == "runaway" or np.nanmax(radius[i]) > CLEARANCE
        assert contact == (free > CLEARANCE), (w, free, radius[i])
        if free < CLEARANCE:  # below the onset: the free whirl, one point per revolution
            np.testing.assert_allclose(radius[i], free, rtol=2e-3)
    from rotorkit.plotting.maps import plot_bifurcation

    ax = plot_bifurcation(ds, "x1")
    assert ax.get_xlabel() == "speed (rad/s)"


# ---------------------------------------------------------------------------
# Scenes: a Model built in Python, a Latin hypercube
# ---------------------------------------------------------------------------


def test_a_model_built_from_elements_is_swept_by_its_parameter_names(tmp_path):
    model = build_jeffcott(rub_stiffness=0.0)
    space = latin_hypercube({"disk1_eccentricity": (1e-5, 5e-5)}, 3, seed=1)
    ds = run_sweep(model, space, out_dir=tmp_path, window=(0.2, 0.5), t_end=0.5, workers=1, signals=["x1"],
                   orders=["1"])
    import pickle

    shipped = pickle.loads(pickle.dumps(Scene.from_model(model)))  # what a worker receives: the elements, as data
    assert shipped.build({"disk1_eccentricity": 2e-5}).parameters["disk1_eccentricity"] == 2e-5
    assert ds.status.dims == ("point",) and ds.disk1_eccentricity.attrs["units"] == "m"
    for i in range(3):
        e = float(ds.disk1_eccentricity[i])
        assert float(ds.order_amplitude[i].sel(signal="x1", order="1")) == pytest.approx(
            unbalance_amplitude(e, SPIN), rel=2e-3)
    manifest = json.loads((tmp_path / "sweep.json").read_text())
    assert manifest["scene"]["kind"] == "model" and manifest["space"]["kind"] == "lhs"
    with pytest.raises(ParameterError, match="not a parameter of model"):
        run_sweep(model, "rub_stiffness", [1.0], out_dir=tmp_path / "bad")
    assert Scene.from_model(model).describe()["structure"] == model.structure_key


def test_points_a_model_refuses_are_stored_as_failed(tmp_path):
    ds = run_sweep(build_jeffcott, "eccentricity", [1e-5, -1e-3], out_dir=tmp_path, window=(0.2, 0.5),
                   workers=1)
    assert list(ds.status.values) == ["ok", "failed"]
    assert "refused the point's parameters" in str(ds.message.values[1])
