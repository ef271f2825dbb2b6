"""Tables, CSV files, figures and the stability verdict of the linear analyses.

- An undamped rotor has log decrements that are rounding noise (+-1e-13):
  no instability onset is reported (a tolerance scaled to the problem,
  :func:`rotorkit.analysis.campbell.neutral_tolerance`), while a real
  negative log decrement still is.
- ``n_modes`` returns exactly that many modes, dense or sparse solve.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit.analysis.campbell import campbell, neutral_tolerance
from rotorkit.analysis.linear_model import LinearModel


def undamped_chain(n=12, damping=0.0, cross=0.0):
    """A free-free chain of ``n`` tilting stations on two end springs, gyroscopic at each station (48 coordinates).

    ``cross``: a cross-coupled stiffness at the first station (destabilises the forward modes with speed).
    """
    names = []
    for s in range(1, n + 1):
        names += [f"x{s}", f"y{s}", f"thx{s}", f"thy{s}"]
    N = 4 * n
    rng = np.random.default_rng(3)
    M = np.diag(rng.uniform(0.5, 2.0, N))
    M[2::4, 2::4] *= 1e-3
    M[3::4, 3::4] *= 1e-3
    K = np.zeros((N, N))
    for i in range(N - 4):
        k = rng.uniform(1e5, 1e7)
        K[i, i] += k
        K[i + 4, i + 4] += k
        K[i, i + 4] -= k
        K[i + 4, i] -= k
    for i in (0, 1, N - 4, N - 3):
        K[i, i] += 1e6
    K[2::4, 2::4] += np.eye(n) * 1e3
    K[3::4, 3::4] += np.eye(n) * 1e3
    K[0, 1], K[1, 0] = cross, -cross
    G = np.zeros((N, N))
    for s in range(n):
        G[4 * s + 2, 4 * s + 3], G[4 * s + 3, 4 * s + 2] = 2e-3, -2e-3
    return LinearModel(mass=M, damping=damping * np.eye(N), stiffness=K, gyroscopic=G, coordinate_names=tuple(names),
                       rotor_speeds={"R": (0.0, 1.0)}, station_rotors={str(s): "R" for s in range(1, n + 1)},
                       speed_parameter="R_speed")


def test_undamped_rotor_reports_no_instability_onset():
    diagram = campbell(undamped_chain(), np.linspace(0.0, 1000.0, 5), n_modes=6)
    noise = np.abs(diagram.log_decrements)
    assert np.all(noise < 1e-9) and np.any(diagram.log_decrements != 0.0)  # rounding noise of either sign
    assert np.all(noise <= diagram.neutral_log_decrements)
    assert diagram.onsets == ()
    assert diagram.instability_onset is None


def test_a_real_instability_is_still_reported():
    diagram = campbell(undamped_chain(damping=1e-3, cross=-3e4), np.linspace(0.0, 1000.0, 5), n_modes=6)
    assert diagram.instability_onset is not None
    assert np.any(diagram.log_decrements < -10 * diagram.neutral_log_decrements)


def test_neutral_tolerance_scales_with_the_spectral_radius():
    lam = np.array([1e-12 + 100j, -1e-12 + 100j])
    assert neutral_tolerance(lam, 1e3).tolist() == [1e-8, 1e-8]  # the floor
    big = neutral_tolerance(lam, 1e8)  # a stiff model: high modes 1e6 x the low ones
    np.testing.assert_allclose(big, 2 * np.pi * 1e3 * np.finfo(float).eps * 1e8 / 100)


@pytest.mark.parametrize("count", [1, 3, 8, 20])
def test_linear_model_modes_returns_n_modes(count):
    model = undamped_chain(damping=0.1)
    assert len(model.modes(0.0, n_modes=count)) == count  # 2 n > 4 count + 20: sparse solve
    assert len(model.modes(300.0, n_modes=count, left=False)) == count
    small = undamped_chain(n=3, damping=0.1)  # dense solve
    assert len(small.modes(0.0, n_modes=min(count, 12))) == min(count, 12)


# ---------------------------------------------------------------------------
# Tables and CSV
# ---------------------------------------------------------------------------


def beam_positions(n):
    return {str(s): 0.1 * (s - 1) for s in range(1, n + 1)}


def chain_with_positions(**kwargs):
    model = undamped_chain(**kwargs)
    return LinearModel(mass=model.mass, damping=model.damping, stiffness=model.stiffness,
                       gyroscopic=model.gyroscopic, coordinate_names=model.coordinate_names,
                       rotor_speeds=model.rotor_speeds, station_rotors=model.station_rotors,
                       speed_parameter=model.speed_parameter, station_positions=beam_positions(12))


def test_mode_table_lists_a_handful_and_no_cage_column_without_ball_bearings():
    modes = undamped_chain(damping=0.1).modes(0.0)
    text = modes.table(units="rpm")
    rows = [line for line in text.splitlines() if line[:4].strip().isdigit()]
    assert len(rows) == 6 and "higher modes not shown" in text
    assert "cage" not in text
    assert len([line for line in modes.table(n_modes=None).splitlines() if line[:4].strip().isdigit()]) == len(modes)
    f = float(rows[0].split()[1])
    assert f == pytest.approx(modes.frequencies[0] * 60 / (2 * np.pi), rel=1e-5)
    with pytest.raises(ValueError, match="n_modes=0"):
        modes.table(n_modes=0)


def test_dominant_coordinates_rank_displacements_not_radians():
    from rotorkit.analysis.modal import modes_from_matrices

    # one station, x stiff and y soft, y coupled to a light tilt: the first mode tilts more rad than it moves m
    names = ("x1", "y1", "thx1", "thy1")
    M = np.diag([1.0, 1.0, 1e-4, 1e-4])
    K = np.array([[4e6, 0, 0, 0], [0, 1e6, 0, 5e4], [0, 0, 1e6, 0], [0, 5e4, 0, 1e4]])
    modes = modes_from_matrices(M, np.zeros((4, 4)), K, names)
    shape = np.abs(modes.shapes[:, 0])
    assert shape[3] > shape[1] > 0 and shape[0] == 0  # thy1 (rad) > y1 (m): ranking the numbers puts thy1 first
    assert modes.dominant_coordinates(1) == ("y1", "thy1")  # the displacement first; x1 does not move


def beam_rotor(n=7, length=1.2, ky=2e6):
    """Euler-Bernoulli beam elements (steel, 40 mm), a gyroscopic disk in the middle, end supports 2e6 N/m in x."""
    E, d, rho = 2.1e11, 0.04, 7800.0
    I, A = np.pi * d**4 / 64, np.pi * d**2 / 4
    L = length / (n - 1)
    k1 = E * I / L**3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                 [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
    T = np.diag([1.0, -1.0, 1.0, -1.0])  # the y-thx plane: thx = -dy/dz
    N = 4 * n
    K, M, G = np.zeros((N, N)), np.zeros((N, N)), np.zeros((N, N))
    for e in range(n - 1):
        a, b = 4 * e, 4 * (e + 1)
        for plane, ke in (((a, a + 3, b, b + 3), k1), ((a + 1, a + 2, b + 1, b + 2), T @ k1 @ T)):
            K[np.ix_(plane, plane)] += ke
    m_station = rho * A * L
    for s in range(n):
        i = 4 * s
        M[i, i] = M[i + 1, i + 1] = m_station
        M[i + 2, i + 2] = M[i + 3, i + 3] = m_station * L * L / 12
    mid = 4 * (n // 2)
    M[mid, mid] += 10.0
    M[mid + 1, mid + 1] += 10.0
    M[mid + 2, mid + 2] += 0.05
    M[mid + 3, mid + 3] += 0.05
    G[mid + 2, mid + 3], G[mid + 3, mid + 2] = 0.1, -0.1
    for i in (0, N - 4):
        K[i, i] += 2e6
        K[i + 1, i + 1] += ky
    names = [f"{c}{s}" for s in range(1, n + 1) for c in ("x", "y", "thx", "thy")]
    return LinearModel(mass=M, damping=np.zeros((N, N)), stiffness=K, gyroscopic=G, coordinate_names=tuple(names),
                       rotor_speeds={"R": (0.0, 1.0)}, station_rotors={str(s): "R" for s in range(1, n + 1)},
                       speed_parameter="R_speed",
                       station_positions={str(s): (s - 1) * L for s in range(1, n + 1)})


def test_to_csv_writes_the_file(tmp_path):
    from rotorkit.analysis.unbalance import unbalance_response

    model = chain_with_positions(damping=0.1)
    modes = model.modes(100.0, n_modes=4)
    path = modes.to_csv(tmp_path / "modes.csv", units="Hz")
    lines = path.read_text().splitlines()
    assert lines[0].startswith("mode,natural_frequency_Hz") and len(lines) == 5
    assert float(lines[1].split(",")[1]) == pytest.approx(modes.frequencies[0] / (2 * np.pi), rel=1e-9)
    frame = modes.to_dataframe(units="rpm")
    assert list(frame.index) == [1, 2, 3, 4] and frame["whirl"].tolist() == list(modes.whirl)
    diagram = campbell(model, [0.0, 100.0, 200.0], n_modes=3)
    text = diagram.to_csv(tmp_path / "campbell.csv", units="rpm").read_text()
    assert text == diagram.to_csv(units="rpm") and text.startswith("R_speed_rpm,R_spin_rpm,mode1_frequency_rpm")
    ds = diagram.to_xarray(units="rpm")
    np.testing.assert_allclose(ds["frequency"].values, diagram.frequencies * 60 / (2 * np.pi))
    response = unbalance_response(model, [(1, 1e-4, 0.0)], [10.0, 20.0])
    one = response.to_csv(tmp_path / "u1.csv", station=1).read_text()
    assert one == response.to_csv(1) and one.count("\n") == 3
    every = response.to_csv(tmp_path / "u.csv").read_text().splitlines()
    assert every[0].startswith("rotor,station,") and len(every) == 1 + 2 * 12
    assert response.to_xarray()["R_amplitude"].shape == (2, model.n)


# ---------------------------------------------------------------------------
# Figures: drawn through pyplot, so plt.savefig writes them
# ---------------------------------------------------------------------------


def _non_blank(path):
    import matplotlib.image as mpimg

    image = mpimg.imread(path)[..., :3]
    return float(np.mean(np.any(image < 0.9, axis=-1)))  # fraction of pixels that are not (near) white


@pytest.fixture(scope="module")
def results():
    from rotorkit.analysis.critical_map import critical_speed_map
    from rotorkit.analysis.frf import frequency_response
    from rotorkit.analysis.unbalance import unbalance_response

    model = chain_with_positions(damping=0.1)
    return {
        "modes": model.modes(100.0, n_modes=4),
        "campbell": campbell(model, np.linspace(0.0, 500.0, 6), n_modes=3),
        "unbalance": unbalance_response(model, [(1, 1e-4, 0.0)], np.linspace(10.0, 500.0, 20)),
        "frf": frequency_response(model, np.linspace(10.0, 500.0, 20), inputs=["x1"], outputs=["x2"]),
        "map": critical_speed_map(undamped_chain(n=2), [1], [1e5, 1e6], (0.0, 2000.0), n_critical=1, n_speeds=8),
    }


PLOT_CALLS = {
    "Modes.plot_mode_shape": lambda r: r["modes"].plot_mode_shape(1),
    "Modes.plot_orbits": lambda r: r["modes"].plot_orbits(2),
    "Campbell.plot": lambda r: r["campbell"].plot(units="rpm"),
    "Campbell.plot_stability": lambda r: r["campbell"].plot_stability(),
    "UnbalanceResponse.plot_bode": lambda r: r["unbalance"].plot_bode("x1"),
    "UnbalanceResponse.plot_polar": lambda r: r["unbalance"].plot_polar("x1"),
    "FRF.plot": lambda r: r["frf"].plot("x2", "x1"),
    "CriticalSpeedMap.plot": lambda r: r["map"].plot(),
}


@pytest.mark.parametrize("name", list(PLOT_CALLS))
def test_plt_savefig_after_a_plot_call_writes_the_figure(name, results, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.close("all")
    returned = PLOT_CALLS[name](results)
    path = tmp_path / "figure.png"
    plt.savefig(path)
    assert _non_blank(path) > 0.01
    axes = returned if isinstance(returned, tuple) else (returned,)
    assert all(ax.figure is plt.gcf() for ax in axes)
    fig, given = plt.subplots()  # an empty current axes is used, not a new figure
    again = PLOT_CALLS[name](results)
    first = again[0] if isinstance(again, tuple) else again
    assert (first is given) == (not isinstance(again, tuple) and name != "Modes.plot_orbits")


def test_two_plot_calls_do_not_draw_over_each_other(results):
    import matplotlib.pyplot as plt

    a = results["campbell"].plot()
    b = results["campbell"].plot_stability()
    assert a.figure is not b.figure and b.figure is plt.gcf()


def test_standalone_figures_leave_pyplot_alone(results):
    import matplotlib.pyplot as plt

    from rotorkit.plotting.basic import standalone_figures

    plt.close("all")
    with standalone_figures():
        ax = results["modes"].plot_mode_shape(1)
    assert plt.get_fignums() == [] and ax.figure.axes == [ax]


def test_mode_shape_is_normalised_by_the_largest_displacement(results):
    modes = results["modes"]
    ax = modes.plot_mode_shape(1)
    major = ax.lines[0].get_ydata()
    assert max(major) == pytest.approx(1.0, rel=1e-12)
    positions = ax.lines[0].get_xdata()
    assert positions.tolist() == pytest.approx(sorted(beam_positions(12).values()))


def test_plot_markers_agree_with_the_table_whirl():
    from rotorkit.analysis.whirl import LINEAR, MIXED

    modes = beam_rotor(ky=1.5e6).modes(2000.0, n_modes=8)
    for mode in range(1, len(modes) + 1):
        ax = modes.plot_mode_shape(mode)
        marked = {label.split()[-2] for label in ax.get_legend_handles_labels()[1] if label.endswith("whirl")}
        marked.discard("linear")
        kind = modes.whirl[mode - 1]
        expected = {"forward", "backward"} if kind == MIXED else set() if kind == LINEAR else {kind}
        assert marked == expected, (mode, kind, marked)
        assert kind in ax.get_title()
    assert {"forward", "backward", MIXED} <= set(modes.whirl)  # every kind of label is checked


# ---------------------------------------------------------------------------
# The rotor drawn: spools where they are
# ---------------------------------------------------------------------------


def test_spools_are_placed_at_their_inter_shaft_bearing():
    from rotorkit import Model, Rotor
    from rotorkit.elements import BeamSegment, Disk, LinearBearing, Material
    from rotorkit.plotting.rotor import rotor_layout

    steel = Material.steel()
    beam = dict(outer_diameter=0.05, material=steel)
    model = Model([
        Rotor(name="LP", stations=(1, 2, 3), speed=100.0),
        Rotor(name="HP", stations=(11, 12), speed=200.0),
        BeamSegment(start=1, end=2, length=0.4, **beam), BeamSegment(start=2, end=3, length=0.6, **beam),
        BeamSegment(start=11, end=12, length=0.3, **beam),
        Disk(station=2, mass=5.0, radius=0.1), Disk(station=11, mass=3.0, radius=0.08),
        LinearBearing(station=1, kxx=1e7, kyy=1e7), LinearBearing(station=3, kxx=1e7, kyy=1e7),
        LinearBearing(station=11, kxx=1e7, kyy=1e7), LinearBearing(station=12, other_station=2, kxx=1e6, kyy=1e6),
    ])
    layout = rotor_layout(model)
    assert layout.positions["12"] == pytest.approx(layout.positions["2"]) == pytest.approx(0.4)
    assert layout.positions["11"] == pytest.approx(0.1)  # 0.3 m ahead of the bearing at 12
    assert layout.rotors["11"] == "HP" and layout.rotors["3"] == "LP"
    assert len(layout.shafts) == 3 and len(layout.disks) == 2
    assert sorted(inter for *_, inter in layout.bearings) == [False, False, False, True]


# ---------------------------------------------------------------------------
# The command line
# ---------------------------------------------------------------------------


def test_run_with_a_wrong_unit_in_set_is_a_unit_error(tmp_path, capsys, monkeypatch):
    from rotorkit import Disk, ElasticSupport, Model, Rotor
    from rotorkit.cli import main

    monkeypatch.setenv("ROTORKIT_FIGURE_PROCESS", "0")
    path = Model([Rotor(name="R", stations=(1,), speed=100.0), Disk(station=1, mass=2.0, radius=0.1),
                  ElasticSupport(station=1, stiffness=2e4)]).save(tmp_path / "rotor.toml", run={"t_end": 0.1})
    assert main(["run", str(path), "--set", "R_speed=3000 m", "--out", str(tmp_path / "out"), "--engine", "scipy",
                 "--no-figures"]) == 2  # the run stops before simulating: no engine to build
    err = capsys.readouterr().err
    assert "R_speed" in err and "wrong unit" in err and "rad/s" in err


@pytest.mark.parametrize("argv, match", [
    (["campbell", "al31f", "--speeds", "0 m:10:3"], "wrong unit"),
    (["unbalance", "al31f", "--unbalance", "2:3 kg"], "magnitude = '3 kg' has the wrong unit"),
    (["static", "al31f", "--t", "2 m"], "--t = '2 m' has the wrong unit"),
])
def test_cli_quantities_of_the_wrong_dimension_exit_2_before_deriving(argv, match, capsys, monkeypatch):
    import rotorkit.model
    from rotorkit.cli import main

    def forbidden(*args, **kwargs):
        raise AssertionError("derived before the options were checked")

    monkeypatch.setattr(rotorkit.model.Model, "compile", forbidden)
    assert main(argv) == 2
    assert match in capsys.readouterr().err
