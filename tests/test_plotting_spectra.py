"""Waterfalls, spectrograms, cascades and spectra on synthetic data (no simulation)."""

import math

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.collections import PathCollection, QuadMesh
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Line3DCollection

from rotorkit.analysis.signals import Peak, amplitude_spectrum, find_peaks, stft
from rotorkit.errors import ParameterError
from rotorkit.plotting.spectra import plot_cascade, plot_spectrogram, plot_spectrum, plot_waterfall, speed_orders
from rotorkit.sweep import Cascade

FS = 4000.0  # Hz


@pytest.fixture(scope="module")
def chirp():
    """A linear chirp from 50 to 250 Hz (314 to 1571 rad/s) over 2 s, and its STFT."""
    t = np.arange(0.0, 2.0, 1.0 / FS)
    x = 2e-5 * np.sin(2 * np.pi * (50.0 * t + 50.0 * t**2))
    return stft(t, x, segment=0.1, overlap=0.5)


def synthetic_cascade(status=("ok", "failed", "ok", "runaway", "ok")):
    """Spectra with a line at half the swept speed and one at the speed (rad/s)."""
    values = np.linspace(1000.0, 2000.0, len(status))
    frequency = np.linspace(0.0, 5000.0, 501)
    rows = np.array([np.exp(-((frequency - v) / 30.0) ** 2) + 0.3 * np.exp(-((frequency - v / 2) / 30.0) ** 2)
                     for v in values])
    status = np.array(status)
    rows[status != "ok"] = np.nan
    fail_time = np.where(status == "ok", np.nan, 3.0)
    return Cascade(parameter="lp_speed", values=values, frequency=frequency,
                   amplitude={"x2": 1e-5 * rows, "alpha2-alpha5": 1e-6 * rows}, status=status,
                   failure_time=fail_time, max_displacement=np.full(len(status), 1e-4),
                   messages=tuple("" if s == "ok" else s for s in status), preset="al31f", window=(2.2, 3.8),
                   highpass_hz=5.0)


def labels(ax):
    return [line.get_label() for line in ax.lines]


# ---------------------------------------------------------------------------
# Waterfall and spectrogram
# ---------------------------------------------------------------------------


def test_waterfall_stacks_one_spectrum_per_time(chirp):
    ax = plot_waterfall(chirp, orders={"100 Hz": 2 * math.pi * 100, "far away": 1e6}, fmax=2000.0)
    assert ax.name == "3d" and isinstance(ax.figure, Figure)
    (spectra,) = ax.collections
    assert isinstance(spectra, Line3DCollection)
    segments = spectra._segments3d
    assert len(segments) == chirp.time.size
    assert labels(ax) == ["100 Hz"]  # the order beyond fmax is not drawn
    first, last = np.asarray(segments[0]), np.asarray(segments[-1])
    assert np.all(first[:, 0] <= 2000.0) and np.all(first[:, 1] == chirp.time[0])
    # the chirp's line moves up in frequency along time
    assert first[np.argmax(first[:, 2]), 0] < 500.0 < 1300.0 < last[np.argmax(last[:, 2]), 0]
    assert ax.get_xlabel() == "frequency (rad/s)" and ax.get_ylabel() == "t (s)"
    assert ax.get_zlim()[1] == pytest.approx(1.05 * chirp.amplitude[chirp.frequency <= 2000.0].max())


def test_waterfall_draws_into_a_given_3d_axes_and_refuses_a_2d_one(chirp):
    ax = Figure().add_subplot(projection="3d")
    assert plot_waterfall(chirp, ax, scale=1e6, amplitude_label="x2 (µm)") is ax
    assert ax.get_zlabel() == "x2 (µm)" and len(ax.lines) == 0
    with pytest.raises(ParameterError, match="3-D axes"):
        plot_waterfall(chirp, Figure().add_subplot())


def test_spectrogram_is_one_mesh_with_order_lines(chirp):
    orders = {"low": 600.0, "high": 1200.0, "above": 5000.0}
    ax = plot_spectrogram(chirp, orders=orders, fmax=2000.0)
    assert isinstance(ax, Axes) and ax.name == "rectilinear"
    meshes = [c for c in ax.collections if isinstance(c, QuadMesh)]
    assert len(meshes) == 1
    kept = np.count_nonzero(chirp.frequency <= 2000.0)
    assert meshes[0].get_array().shape == (kept, chirp.time.size)
    assert labels(ax) == ["low", "high"]
    assert [line.get_ydata()[0] for line in ax.lines] == [600.0, 1200.0]
    assert ax.get_ylabel() == "frequency (rad/s)" and ax.get_xlabel() == "t (s)"
    assert len(ax.figure.axes) == 2  # with its colour bar
    linear = plot_spectrogram(chirp, log=False, colorbar=False)
    assert len(linear.figure.axes) == 1 and linear.collections[0].norm.__class__.__name__ == "Normalize"


@pytest.mark.parametrize("bad, match", [
    (dict(orders={"a": -1.0}), "finite number > 0"),
    (dict(orders=[600.0]), "mapping of labels"),
    (dict(orders={"": 600.0}), "non-empty strings"),
    (dict(fmax=0.0), "finite number > 0"),
    (dict(fmax=1.0), "fewer than 2 frequency bins"),
])
def test_time_frequency_plots_reject_bad_options(chirp, bad, match):
    with pytest.raises(ParameterError, match=match):
        plot_spectrogram(chirp, **bad)
    with pytest.raises(ParameterError, match=match):
        plot_waterfall(chirp, **bad)


def test_waterfall_needs_time_frequency_data():
    with pytest.raises(ParameterError, match="expected a TimeFrequency"):
        plot_waterfall(np.zeros((3, 3)))


# ---------------------------------------------------------------------------
# Cascade
# ---------------------------------------------------------------------------


def test_cascade_3d_stacks_ok_points_and_marks_the_others():
    cascade = synthetic_cascade()
    ax = plot_cascade(cascade, "x2", orders={"1500": 1500.0})
    assert ax.name == "3d"
    spectra = [c for c in ax.collections if isinstance(c, Line3DCollection)]
    markers = [c for c in ax.collections if isinstance(c, PathCollection)]
    assert len(spectra) == 1 and len(spectra[0]._segments3d) == 3  # three ok points
    assert sorted(m.get_label() for m in markers) == ["failed", "runaway"]
    assert labels(ax) == ["1500"]
    ys = sorted(np.asarray(s)[0, 1] for s in spectra[0]._segments3d)
    assert ys == [1000.0, 1500.0, 2000.0]
    assert ax.get_ylabel() == "lp_speed (rad/s)" and ax.get_xlabel() == "frequency (rad/s)"
    assert "t in [2.2, 3.8] s" in ax.get_title()


def test_cascade_orders_may_follow_the_swept_value():
    cascade = synthetic_cascade(("ok",) * 4)
    ax = plot_cascade(cascade, "alpha2-alpha5", orders=speed_orders, fmax=3000.0)
    drawn = {line.get_label(): line for line in ax.lines}
    assert set(drawn) == {"1/2 low", "low", "5/4 low", "3/2 low", "high", "high - low"}
    xs, ys, _ = drawn["low"].get_data_3d()
    np.testing.assert_allclose(xs, cascade.values)  # the line follows the speed
    np.testing.assert_allclose(ys, cascade.values)
    xs, _, _ = drawn["high"].get_data_3d()
    assert np.isnan(xs[-1]) and xs[0] == pytest.approx(1800.0)  # 3600 rad/s is past fmax
    assert not [c for c in ax.collections if isinstance(c, PathCollection)]  # nothing failed


def test_cascade_2d_is_a_colour_map_with_blank_failed_rows():
    cascade = synthetic_cascade()
    ax = plot_cascade(cascade, "x2", three_d=False, orders=lambda v: {"half": v / 2}, fmax=3000.0, log=True)
    assert ax.name == "rectilinear"
    meshes = [c for c in ax.collections if isinstance(c, QuadMesh)]
    markers = [c for c in ax.collections if isinstance(c, PathCollection)]
    assert len(meshes) == 1 and len(markers) == 2
    table = meshes[0].get_array()
    assert table.shape == (5, np.count_nonzero(cascade.frequency <= 3000.0))
    assert list(np.ma.getmaskarray(table).all(axis=1)) == [False, True, False, True, False]
    assert labels(ax) == ["half"]
    np.testing.assert_allclose(ax.lines[0].get_xdata(), cascade.values / 2)


def test_cascade_log_values_and_errors():
    cascade = synthetic_cascade()
    ax = plot_cascade(cascade, "x2", log_values=True)
    ys = sorted(np.asarray(s)[0, 1] for s in ax.collections[0]._segments3d)
    np.testing.assert_allclose(ys, np.log10([1000.0, 1500.0, 2000.0]))
    assert ax.get_ylabel() == "log10 lp_speed (rad/s)"
    with pytest.raises(ParameterError, match="no signal 'y2'; signals are x2, alpha2-alpha5"):
        plot_cascade(cascade, "y2")
    with pytest.raises(ParameterError, match="same labels"):
        plot_cascade(cascade, "x2", orders=lambda v: {"a": v} if v < 1600 else {"b": v})
    with pytest.raises(ParameterError, match="3-D axes"):
        plot_cascade(cascade, "x2", Figure().add_subplot())
    with pytest.raises(ParameterError, match="needs a 2-D one"):
        plot_cascade(cascade, "x2", Figure().add_subplot(projection="3d"), three_d=False)


def test_cascade_with_no_successful_point_still_draws_the_markers():
    cascade = synthetic_cascade(("failed", "runaway"))
    cascade = Cascade(parameter="x", values=cascade.values, frequency=np.empty(0),
                      amplitude={"x2": np.empty((2, 0))}, status=cascade.status,
                      failure_time=cascade.failure_time, max_displacement=cascade.max_displacement)
    ax = plot_cascade(cascade, "x2", orders={"a": 0.5})
    assert len([c for c in ax.collections if isinstance(c, PathCollection)]) == 2
    assert labels(ax) == ["a"]


# ---------------------------------------------------------------------------
# One spectrum
# ---------------------------------------------------------------------------


def test_spectrum_with_orders_and_peaks():
    t = np.arange(0.0, 1.0, 1.0 / FS)
    x = 3e-5 * np.sin(1500.0 * t) + 1e-5 * np.sin(750.0 * t)
    spectrum = amplitude_spectrum(t, x, units="rad/s")
    ax = plot_spectrum(spectrum, orders={"1/2 low": 750.0, "low": 1500.0, "far": 1e5}, peaks=True, fmax=3000.0,
                       scale=1e6, amplitude_label="x2 (µm)")
    assert labels(ax) == ["spectrum", "1/2 low", "low", "peaks"]
    peak_line = ax.lines[-1]
    np.testing.assert_allclose(peak_line.get_xdata(), [750.0, 1500.0], atol=0.5)
    np.testing.assert_allclose(peak_line.get_ydata(), [10.0, 30.0], rtol=0.01)
    assert ax.get_xlabel() == "frequency (rad/s)" and ax.get_ylabel() == "x2 (µm)"
    assert ax.get_xlim()[1] <= 3000.0
    given = plot_spectrum(spectrum, peaks=[Peak(1500.0 / (2 * math.pi), 3e-5, "Hz"), (750.0, 1e-5)])
    np.testing.assert_allclose(given.lines[-1].get_xdata(), [1500.0, 750.0])
    assert labels(plot_spectrum(spectrum)) == ["spectrum"]
    assert len(find_peaks(spectrum, min_relative_height=0.2)) == 2
    with pytest.raises(ParameterError, match="Peak objects or"):
        plot_spectrum(spectrum, peaks="many")
    with pytest.raises(ParameterError, match="expected a Spectrum"):
        plot_spectrum(x)


def test_speed_orders():
    orders = speed_orders(1500.0)
    assert orders == {"1/2 low": 750.0, "low": 1500.0, "5/4 low": 1875.0, "3/2 low": 2250.0, "high": 2700.0,
                      "high - low": pytest.approx(1200.0)}
    assert speed_orders(1000.0, 2.0, ratios=(1,)) == {"low": 1000.0, "high": 2000.0, "high - low": 1000.0}
    with pytest.raises(ParameterError, match="low_speed"):
        speed_orders(-1.0)
    with pytest.raises(ParameterError, match="ratios contains"):
        speed_orders(1500.0, ratios=("half",))


# ---------------------------------------------------------------------------
# Default labels: quantity and unit on every amplitude axis
# ---------------------------------------------------------------------------


def _colorbar_label(ax):
    (cbar_ax,) = [a for a in ax.figure.axes if a is not ax]
    return cbar_ax.get_ylabel()


@pytest.mark.parametrize("signal, scale, expected", [
    ("x2", 1.0, "x2 amplitude (m)"), ("x2", 1e6, "x2 amplitude (µm)"), ("alpha2-alpha5", 1e3, "alpha2-alpha5 "
                                                                          "amplitude (mrad)"),
    ("x1_dot", 1.0, "x1_dot amplitude (m/s)"), ("y3", 4.0, "y3 amplitude (0.25 m)"),
    (None, 1.0, "amplitude ([signal unit])"), (None, 1e6, "amplitude (µ[signal unit])"),
])
def test_default_amplitude_labels_name_quantity_and_unit(chirp, signal, scale, expected):
    spectrum = amplitude_spectrum(np.arange(0.0, 1.0, 1e-3), np.sin(2 * np.pi * 50 * np.arange(0.0, 1.0, 1e-3)))
    ax = plot_spectrum(spectrum, signal=signal, scale=scale)
    assert ax.get_ylabel() == expected
    assert plot_waterfall(chirp, signal=signal, scale=scale).get_zlabel() == expected
    assert _colorbar_label(plot_spectrogram(chirp, signal=signal, scale=scale)) == expected
    if signal is not None:
        assert signal in ax.get_title() and "spectrum" in ax.get_title()
    else:
        assert ax.get_title() == ""


def test_an_explicit_amplitude_label_wins(chirp):
    assert plot_spectrogram(chirp, signal="x2", amplitude_label="x2 (µm)").figure.axes[1].get_ylabel() == "x2 (µm)"


def test_cascade_label_scales_its_unit():
    ax = plot_cascade(synthetic_cascade(), "x2", scale=1e6)
    assert ax.get_zlabel() == "x2 amplitude (µm)"


def test_label_helpers_doctests():
    import doctest

    from rotorkit.plotting import basic, spectra

    for module in (basic, spectra):
        failures, tried = doctest.testmod(module, verbose=False)
        assert tried >= 1 and failures == 0
