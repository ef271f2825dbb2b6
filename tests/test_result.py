"""Result: named signals, windows, atomic save and data-only load."""

import numpy as np
import pytest

import rotorkit as rk


@pytest.fixture(scope="module")
def result():
    system = rk.preset("al31f").compile()
    return rk.simulate(system, (0.0, 0.02), sample_rate=5000.0)


def test_named_signals(result):
    assert result["x2"].shape == result.t.shape
    np.testing.assert_array_equal(result["alpha2-alpha5"], result["alpha2"] - result["alpha5"])
    with pytest.raises(rk.ParameterError, match="no signal 'z9'"):
        result["z9"]
    assert result.stats["nfev"] > 0 and result.stats["success"] is True


def test_save_and_load_roundtrip(result, tmp_path):
    path = result.save(tmp_path / "r.npz")
    back = rk.load_result(path)
    np.testing.assert_array_equal(back.y, result.y)
    assert back.state_names == result.state_names and back.parameters == result.parameters
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind


def test_load_rejects_foreign_files(tmp_path):
    np.savez(tmp_path / "other.npz", meta=np.array('{"format": "something"}'), t=np.zeros(1), y=np.zeros((1, 1)))
    with pytest.raises(rk.ParameterError, match="not a rotorkit result"):
        rk.load_result(tmp_path / "other.npz")


def test_plot_methods_return_axes(result):
    ax = result.plot_orbit(2, clearance=1.34e-4)
    assert ax.get_xlabel() == "horizontal displacement x2 (µm)"
    ax = result.plot_signals(["x2", "alpha2-alpha5"], scale=1e6)
    assert len(ax.lines) == 2


def test_spectrum_of_a_signal_after_highpass():
    t = np.arange(0.0, 4.0, 1e-4)
    x = 0.5 * np.sin(1500.0 * t) + 3.0 * t  # a tone on a slow drift
    res = rk.Result(t=t, y=np.vstack([x]), state_names=("x2",))
    spec = res.spectrum("x2", window=(2.2, 3.8), highpass=5.0)
    peak = np.argmax(spec.amplitude)
    assert abs(spec.frequency[peak] - 1500.0) < 2 * (spec.frequency[1] - spec.frequency[0])
    assert spec.amplitude[peak] == pytest.approx(0.5, rel=0.05)
    assert spec.amplitude[spec.frequency < 100].max() < 0.01  # the drift is gone


def test_load_refuses_state_names_that_are_not_text(tmp_path):
    """Found by hypothesis (test_properties): a file naming its states [null] loaded as state_names (None,)."""
    import json

    from rotorkit.result import FILE_FORMAT

    path = tmp_path / "r.npz"
    meta = {"format": FILE_FORMAT, "name": "r", "state_names": [None], "parameters": {}, "stats": {}}
    np.savez(path, t=np.zeros(2), y=np.zeros((1, 2)), meta=np.array(json.dumps(meta)))
    with pytest.raises(rk.ParameterError, match=r"state names \[None\] are not all text"):
        rk.load_result(path)


def test_repr_is_a_summary_not_the_samples():
    """A notebook or a print shows one line, whatever the size (issue 24: the tutorial's print(run))."""
    import numpy as np

    from rotorkit.result import Result

    r = Result(t=np.linspace(0.0, 2.0, 100_001), y=np.zeros((160, 100_001)),
               state_names=tuple(f"x{i}" for i in range(160)), stats={"method": "DOP853", "message": "success"},
               name="big")
    text = repr(r)
    assert "\n" not in text and len(text) < 200
    assert "'big'" in text and "100001 samples" in text and "160 signals" in text and "t = 0 .. 2 s" in text
