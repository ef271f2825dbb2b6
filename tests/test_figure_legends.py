"""Legends sit beside the data, never over it (issue: figures a reader trusts)."""

import numpy as np

import rotorkit as rk
from rotorkit.analysis.campbell import campbell
from rotorkit.analysis.energy import energy_balance
from rotorkit.elements import LinearBearing


def beside(ax):
    """True when the axes' legend lies wholly to the right of the axes (after the figure's layout)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(ax.figure)
    canvas.draw()
    renderer = canvas.get_renderer()
    legend = ax.get_legend()
    assert legend is not None
    return legend.get_window_extent(renderer).x0 >= ax.get_window_extent(renderer).x1


def test_campbell_stability_and_energy_legends_are_beside_the_axes():
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=0.0), rk.Disk(station=1, mass=2.0, radius=0.1),
                      LinearBearing(station=1, kxx=2e4, kyy=3e4, cxx=20.0, cyy=20.0)], name="jeffcott")
    diagram = campbell(model, np.linspace(0.0, 200.0, 11), n_modes=2, speed_parameter="R_speed")
    system = model.compile(backend="python")
    result = rk.simulate(system, (0.0, 0.2), y0=system.initial_state(x1=1e-3), sample_rate=2000.0)
    balance = energy_balance(model, result)
    for ax in (diagram.plot(), diagram.plot_stability(), balance.plot()):
        assert beside(ax), ax.get_title()
        assert ax.get_title()  # a title says what it shows
