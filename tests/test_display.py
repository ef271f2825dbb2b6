"""Notebook display (LaTeX of every element, HTML tables) and figure labels that name quantity and unit."""

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.modelfile import element_types
from rotorkit.plotting.basic import plot_orbit, plot_signals, signal_unit


def _sink():
    from test_modelfile import sink_model

    return sink_model()


def test_every_element_type_renders_latex():
    elements = list(_sink().elements) + [rk.Maneuver.steady()]
    seen = {type(e).__name__ for e in elements}
    assert {n for n, c in element_types().items() if issubclass(c, rk.elements.Element)} <= seen
    for e in elements:
        text = e._repr_latex_()
        assert text.startswith("$") and text.endswith("$") and type(e).__name__ in text
        assert text.count("{") == text.count("}")  # balanced groups
        for f, u in e.parameter_units().items():
            if u:
                assert r"\mathrm{" in text, (e, f)


def test_disk_latex_shows_symbols_values_and_units():
    text = rk.Disk(station=2, mass=10.0, radius=0.075, eccentricity=4.635e-5)._repr_latex_()
    assert r"m = 10\,\mathrm{kg}" in text and r"e = 4.635 \times 10^{-5}\,\mathrm{m}" in text


def test_model_and_result_html():
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=300.0), rk.Disk(station=1, mass=2.0, radius=0.1),
                      rk.ElasticSupport(station=1, stiffness=2e4, damping=4.0)], name="jeffcott")
    html = model._repr_html_()
    assert "<table>" in html and "support1_stiffness" in html and "N/m" in html and "Disk" in html
    result = rk.Result(t=np.linspace(0, 1, 11), y=np.zeros((4, 11)), state_names=("x1", "y1", "x1_dot", "y1_dot"),
                       stats={"nfev": 12, "wall_time": 0.5}, name="jeffcott")
    html = result._repr_html_()
    assert "0 - 1 s" in html and "11 samples" in html and "nfev" in html


@pytest.mark.parametrize("name, unit", [("x2", "m"), ("alpha2-alpha5", "rad"), ("y1_dot", "m/s"),
                                        ("alpha5_dot", "rad/s")])
def test_signal_units(name, unit):
    assert signal_unit(name) == unit


def _result():
    t = np.linspace(0.0, 3.0, 301)
    y = np.vstack([1e-4 * np.cos(20 * t), 1e-4 * np.sin(20 * t)])
    return rk.Result(t=t, y=y, state_names=("x1", "y1"), name="demo",
                     parameters={"maneuver_roll_start": 1.0, "maneuver_roll_end": 2.0})


def test_signal_plot_names_quantity_and_unit_and_keeps_legend_off_the_data():
    ax = plot_signals(_result(), ["x1", "y1"])
    assert ax.get_ylabel() == "displacement x1, y1 (m)" and ax.get_xlabel() == "time t (s)"
    legend = ax.get_legend()
    assert legend.get_bbox_to_anchor().x0 >= ax.get_window_extent().x1 - 1  # outside the axes
    assert "manoeuvre" in [t.get_text() for t in legend.get_texts()]
    assert "x1, y1 against time" in ax.get_title()


def test_orbit_shows_time_clearance_and_manoeuvre():
    ax = plot_orbit(_result(), 1, clearance=2e-4)
    assert "(µm)" in ax.get_xlabel() and "horizontal displacement" in ax.get_xlabel()
    assert ax.collections and ax.collections[0].get_array() is not None  # coloured by time
    assert "clearance 200 µm" in ax.get_title() and "manoeuvre 1-2 s" in ax.get_title()
    cbar = ax.figure.axes[-1]
    assert cbar.get_ylabel() == "time t (s)"


def test_campbell_legend_lists_only_existing_modes():
    from rotorkit.analysis.modes import Campbell
    from rotorkit.plotting.campbell import plot_campbell

    speeds = np.array([0.0, 100.0, 200.0])
    freqs = np.array([[50.0, 120.0, np.nan], [52.0, 118.0, np.nan], [54.0, 116.0, np.nan]])
    diagram = Campbell(speeds=speeds, frequencies=freqs, natural_frequencies=freqs,
                       damping_ratios=np.zeros_like(freqs), log_decrements=np.zeros_like(freqs),
                       whirl=np.full(freqs.shape, "forward"), rotor_speeds={"R": speeds}, speed_parameter="R_speed")
    labels = [t.get_text() for t in plot_campbell(diagram).get_legend().get_texts()]
    assert "mode 1" in labels and "mode 2" in labels and "mode 3" not in labels


def test_cascade_axes_name_units_and_orders_sit_in_a_legend():
    from rotorkit.plotting.spectra import plot_cascade, speed_orders
    from rotorkit.sweep import Cascade

    values, f = np.linspace(5e5, 2e7, 4), np.linspace(0.0, 5000.0, 201)
    rows = np.array([np.exp(-((f - 1500.0) / 30.0) ** 2) for _ in values])
    cascade = Cascade(parameter="rub_stiffness", values=values, frequency=f, amplitude={"x2": 1e-5 * rows},
                      status=np.array(["ok"] * 4), failure_time=np.full(4, np.nan),
                      max_displacement=np.full(4, 1e-4), messages=("",) * 4, preset="al31f", window=(2.2, 3.8),
                      highpass_hz=5.0)
    ax = plot_cascade(cascade, "x2", orders=speed_orders(1500.0, 1.8))
    assert ax.get_ylabel() == "rub_stiffness (N/m)" and ax.get_zlabel() == "x2 amplitude (m)"
    ax.figure.canvas.draw()
    assert ax.yaxis.get_offset_text().get_text() == "" and ax.zaxis.get_offset_text().get_text() == ""
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == list(speed_orders(1500.0, 1.8)) and not ax.texts  # no piled-up labels on the plot
    assert "spectra of x2 against rub_stiffness" in ax.get_title()
