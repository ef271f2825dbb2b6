"""Parameter sweeps: parsing, parallel points, resume, failed and run-away points.

The sweeps run on a Jeffcott rotor with a rub stator (one disk, 2 states of
bending), fast enough to simulate in a fraction of a second per point. Its
unbalance response has a closed form when the rub stiffness is zero:
``e r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2)`` at the spin speed.
"""

import json
import math
import os
import shutil

import numpy as np
import pytest
from rotorkit.analysis.signals import find_peaks
from rotorkit.errors import ParameterError, RotorkitError
from rotorkit.sweep import DATASET_NAME, MANIFEST_NAME, Cascade, load_cascade, parse_range, point_path, run_sweep

from sweep_models import CLEARANCE, SPIN, build_jeffcott, unbalance_amplitude  # noqa: E402

WINDOW = (0.2, 0.5)
STIFFNESSES = [0.0, 1e4, 3e4, 1e5]


def run_cascade(*args, **kwargs):
    return Cascade.from_dataset(run_sweep(*args, **kwargs))


class Recorder:
    """A progress callback that keeps every call."""

    def __init__(self):
        self.calls = []

    def __call__(self, event):
        self.calls.append((event.done, event.total, next(iter(event.point.values())), event.status))

    def statuses(self):
        return {value: status for _, _, value, status in self.calls}


# ---------------------------------------------------------------------------
# parse_range
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("text, name, values", [
    ("rub_stiffness=5e5:2e7:4", "rub_stiffness", [5e5, 7e6, 1.35e7, 2e7]),
    (" lp_speed = 3000 : 500 : 3 ", "lp_speed", [3000.0, 1750.0, 500.0]),
    ("rub_stiffness=log:1e6:1e8:3", "rub_stiffness", [1e6, 1e7, 1e8]),
    ("k=LOG:2:32:5", "k", [2.0, 4.0, 8.0, 16.0, 32.0]),
    ("friction_coefficient=0,0.1,0.2", "friction_coefficient", [0.0, 0.1, 0.2]),
    ("friction_coefficient=0.3", "friction_coefficient", [0.3]),
    ("x=-1e-3, 2e-3", "x", [-1e-3, 2e-3]),
])
def test_parse_range(text, name, values):
    got_name, got = parse_range(text)
    assert got_name == name
    assert isinstance(got, tuple) and all(isinstance(v, float) for v in got)
    np.testing.assert_allclose(got, values, rtol=1e-12)
    assert got[0] == values[0] and got[-1] == values[-1]  # the ends exactly


@pytest.mark.parametrize("text, match", [
    ("rub_stiffness", "expected name=start:stop:n"),
    ("=1:2:3", "is not a parameter name"),
    ("2k=1:2:3", "is not a parameter name"),
    ("k=", "no values"),
    ("k=1:2", "three fields"),
    ("k=1:2:3:4", "three fields"),
    ("k=log:1:2", "three fields"),
    ("k=1:2:1", "integer >= 2"),
    ("k=1:2:2.5", "integer >= 2"),
    ("k=1:2:-3", "integer >= 2"),
    ("k=a:2:3", "start 'a' is not a number"),
    ("k=1:2e6 N/m:3", "stop '2e6 N/m' is not a number"),
    ("k=nan:1:3", "not finite"),
    ("k=1:1:3", "start and stop are equal"),
    ("k=log:0:1e3:3", "start > 0 and stop > 0"),
    ("k=log:-1:1e3:3", "start > 0 and stop > 0"),
    ("k=1,,2", "empty item"),
    ("k=1,2,", "empty item"),
    ("k=1,x", "value 'x' is not a number"),
    ("k=1,inf", "not finite"),
    ("k=1,2,1", "appears twice"),
])
def test_parse_range_rejects(text, match):
    with pytest.raises(ParameterError, match=match):
        parse_range(text)


def test_parse_range_needs_a_string():
    with pytest.raises(ParameterError, match="expected a string"):
        parse_range(5)


# ---------------------------------------------------------------------------
# A real sweep in worker processes
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def jeffcott_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep") / "rub"
    progress = Recorder()
    cascade = run_cascade(build_jeffcott, "rub_stiffness", STIFFNESSES, out_dir=out, window=WINDOW, workers=2,
                        signals=["x1", "y1"], progress=progress)
    return out, cascade, progress


def test_sweep_writes_one_file_per_point_and_a_manifest(jeffcott_sweep):
    out, _, progress = jeffcott_sweep
    assert sorted(p.name for p in out.iterdir()) == sorted([MANIFEST_NAME, DATASET_NAME, "points"])
    assert sorted(p.name for p in (out / "points").iterdir()) == [point_path(out, i).name for i in range(4)]
    manifest = json.loads((out / MANIFEST_NAME).read_text())
    assert manifest["space"] == {"kind": "grid", "names": ["rub_stiffness"], "axes": {"rub_stiffness": STIFFNESSES}}
    settings = manifest["settings"]
    assert settings["window"] == list(WINDOW) and settings["t_end"] == 0.5  # from build_jeffcott.OUTPUTS
    assert manifest["scene_name"].endswith("build_jeffcott") and settings["signals"] == ["x1", "y1"]
    assert [c[0] for c in progress.calls] == [1, 2, 3, 4] and {c[1] for c in progress.calls} == {4}
    assert sorted(c[2] for c in progress.calls) == STIFFNESSES
    assert {c[3] for c in progress.calls} == {"ok"}
    with np.load(point_path(out, 2), allow_pickle=False) as data:
        meta = json.loads(str(data["meta"]))
        assert meta["status"] == "ok" and meta["point"] == {"rub_stiffness": 3e4} and meta["index"] == 2
        assert data["amplitude"].shape == (2, data["frequency"].size)
    assert meta["stats"]["nfev"] > 0 and meta["stats"]["pid"] != os.getpid()  # computed in a worker


def test_cascade_shows_the_synchronous_peak(jeffcott_sweep):
    out, cascade, _ = jeffcott_sweep
    assert isinstance(cascade, Cascade)
    assert cascade.parameter == "rub_stiffness" and cascade.signals == ("x1", "y1")
    np.testing.assert_array_equal(cascade.values, STIFFNESSES)
    assert list(cascade.status) == ["ok"] * 4 and np.all(np.isnan(cascade.failure_time))
    n_freq = cascade.frequency.size
    assert cascade.units == "rad/s" and cascade.frequency[-1] == pytest.approx(math.pi * 10_000, rel=1e-3)  # Nyquist
    for signal in cascade.signals:
        rows = cascade.amplitude[signal]
        assert rows.shape == (4, n_freq) and np.all(np.isfinite(rows))
        spacing = cascade.frequency[1]
        assert np.all(np.abs(cascade.frequency[rows.argmax(axis=1)] - SPIN) <= spacing)
    for i in range(4):
        peak = max(find_peaks(cascade.spectrum("x1", i)), key=lambda p: p.amplitude)
        assert peak.frequency == pytest.approx(SPIN, abs=0.5)
    # no rub force: the closed-form unbalance whirl
    peak = max(find_peaks(cascade.spectrum("x1", 0)), key=lambda p: p.amplitude)
    assert peak.amplitude == pytest.approx(unbalance_amplitude(), rel=0.01)
    again = load_cascade(out)
    np.testing.assert_array_equal(again.amplitude["x1"], cascade.amplitude["x1"])
    with pytest.raises(ValueError):
        cascade.amplitude["x1"][0, 0] = 1.0  # read-only


def test_resume_recomputes_only_missing_and_damaged_points(jeffcott_sweep, tmp_path):
    original, cascade, _ = jeffcott_sweep
    out = tmp_path / "rub"
    shutil.copytree(original, out)
    point_path(out, 1).unlink()
    damaged = point_path(out, 2)
    damaged.write_bytes(damaged.read_bytes()[:500])  # truncated
    kept = {i: point_path(out, i).stat().st_mtime_ns for i in (0, 3)}
    progress = Recorder()
    resumed = run_cascade(build_jeffcott, "rub_stiffness", STIFFNESSES, out_dir=out, window=WINDOW, workers=2,
                        signals=["x1", "y1"], progress=progress)
    assert progress.statuses() == {0.0: "cached", 1e4: "ok", 3e4: "ok", 1e5: "cached"}
    assert [c[0] for c in progress.calls] == [1, 2, 3, 4]
    assert {i: point_path(out, i).stat().st_mtime_ns for i in (0, 3)} == kept
    assert list(resumed.status) == ["ok"] * 4
    np.testing.assert_allclose(resumed.amplitude["x1"], cascade.amplitude["x1"], rtol=1e-9, atol=1e-15)


def test_load_sweep_marks_points_not_yet_computed(jeffcott_sweep, tmp_path):
    original, _, _ = jeffcott_sweep
    out = tmp_path / "rub"
    shutil.copytree(original, out)
    point_path(out, 3).unlink()
    cascade = load_cascade(out)
    assert list(cascade.status) == ["ok", "ok", "ok", "missing"]
    assert np.all(np.isnan(cascade.amplitude["x1"][3])) and np.all(np.isfinite(cascade.amplitude["x1"][:3]))
    with pytest.raises(ParameterError, match="status 'missing'"):
        cascade.spectrum("x1", 3)
    with pytest.raises(ParameterError, match="not a sweep folder"):
        load_cascade(tmp_path / "nowhere")


@pytest.mark.parametrize("change, match", [
    (dict(values=[0.0, 1e4, 3e4]), "space.axes.rub_stiffness: "),
    (dict(window=(0.25, 0.5)), "settings.window: "),
    (dict(name="eccentricity", values=[1e-5, 2e-5]), "space.axes.eccentricity: "),
    (dict(signals=["x1"]), "settings.signals: "),
    (dict(overrides={"eccentricity": 2e-4}), "scene.overrides.eccentricity: "),
])
def test_a_folder_of_another_sweep_is_refused(jeffcott_sweep, change, match):
    out, _, _ = jeffcott_sweep
    before = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    args = dict(name="rub_stiffness", values=STIFFNESSES, window=WINDOW, signals=["x1", "y1"])
    args.update(change)
    with pytest.raises(ParameterError, match=f"holds a different sweep.*{match}"):
        run_sweep(build_jeffcott, args.pop("name"), args.pop("values"), out_dir=out, workers=2, **args)
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == before


# ---------------------------------------------------------------------------
# Points that fail or run away
# ---------------------------------------------------------------------------


def _point_arrays(out, index):
    with np.load(point_path(out, index), allow_pickle=False) as data:
        return json.loads(str(data["meta"])), data["frequency"].copy(), data["amplitude"].copy()


def test_a_runaway_point_is_recorded_not_a_garbage_spectrum(tmp_path):
    """A huge unbalance drives the disk 30 mm out: far past 10 x the 0.1 mm clearance."""
    progress = Recorder()
    cascade = run_cascade(build_jeffcott, "eccentricity", [1e-5, 1e-2], out_dir=tmp_path, window=WINDOW, workers=1,
                        progress=progress)
    assert progress.statuses() == {1e-5: "ok", 1e-2: "runaway"}
    assert cascade.signals == ("x1",)  # the build function's OUTPUTS
    assert list(cascade.status) == ["ok", "runaway"]
    assert np.all(np.isfinite(cascade.amplitude["x1"][0])) and np.all(np.isnan(cascade.amplitude["x1"][1]))
    assert cascade.max_displacement[1] > 10 * CLEARANCE and cascade.max_displacement[0] < 10 * CLEARANCE
    assert 0.0 < cascade.failure_time[1] < 0.5 and np.isnan(cascade.failure_time[0])
    assert "runaway limit" in cascade.messages[1] and cascade.messages[0] == ""
    meta, frequency, amplitude = _point_arrays(tmp_path, 1)
    assert meta["status"] == "runaway" and meta["runaway_limit"] == pytest.approx(10 * CLEARANCE)  # the bound
    assert meta["time"] == cascade.failure_time[1] and meta["max_displacement"] > 1e-3
    assert frequency.size == 0 and amplitude.shape == (1, 0)  # no spectrum at all, not NaNs
    assert meta["stats"]["success"] is False  # simulate stopped it (bound=), not integrated to the end
    # a limit given explicitly wins
    again = run_cascade(build_jeffcott, "eccentricity", [1e-2], out_dir=tmp_path / "limit", window=WINDOW,
                      workers=1, runaway_limit=1.0)
    assert list(again.status) == ["ok"]


def test_the_wall_time_limit_holds_for_the_whole_point(tmp_path):
    cascade = run_cascade(build_jeffcott, "rub_stiffness", [1e4], out_dir=tmp_path, window=WINDOW, workers=1,
                        simulate_options={"time_limit": 1e-6})
    assert list(cascade.status) == ["failed"] and "wall-time limit" in cascade.messages[0]


def test_a_failed_integration_is_recorded_and_the_sweep_goes_on(tmp_path):
    progress = Recorder()
    cascade = run_cascade(build_jeffcott, "singular_load", [1e-3, 0.0], out_dir=tmp_path, window=WINDOW, workers=1,
                        signals=["x1"], progress=progress)
    assert progress.statuses() == {1e-3: "failed", 0.0: "ok"}
    assert list(cascade.status) == ["failed", "ok"]
    assert cascade.failure_time[0] == pytest.approx(0.3, abs=1e-3)
    assert cascade.max_displacement[0] < 10 * CLEARANCE
    assert "integration failed" in cascade.messages[0]
    assert np.all(np.isnan(cascade.amplitude["x1"][0])) and np.all(np.isfinite(cascade.amplitude["x1"][1]))
    meta, frequency, _ = _point_arrays(tmp_path, 0)
    assert meta["status"] == "failed" and frequency.size == 0
    # failed points are results too: a resume does not recompute them
    resumed = Recorder()
    run_sweep(build_jeffcott, "singular_load", [1e-3, 0.0], out_dir=tmp_path, window=WINDOW, workers=1,
              signals=["x1"], progress=resumed)
    assert set(resumed.statuses().values()) == {"cached"}


# ---------------------------------------------------------------------------
# A preset by name, and bad arguments
# ---------------------------------------------------------------------------


def test_preset_sweep_with_default_signals_and_quantity_overrides(tmp_path):
    from rotorkit.units import registry

    q = registry().Quantity
    cascade = run_cascade("al31f", "friction_coefficient", [0.0, 0.1], out_dir=tmp_path / "a", t_end=0.3,
                        window=(0.1, 0.3), workers=1, overrides={"rub_clearance": q(134.0, "um")})
    assert cascade.preset == "al31f" and cascade.signals == ("x2", "alpha2-alpha5")
    assert list(cascade.status) == ["ok", "ok"]
    manifest = json.loads((tmp_path / "a" / MANIFEST_NAME).read_text())
    assert manifest["scene"]["overrides"] == {"rub_clearance": {"quantity": 134.0, "unit": "micrometer"}}
    no_torsion = run_cascade("al31f", "rub_stiffness", [8e6], out_dir=tmp_path / "b", t_end=0.2, window=(0.1, 0.2),
                           workers=1, overrides={"torsion": False, "maneuver": False})
    assert no_torsion.signals == ("x2",)


@pytest.mark.parametrize("preset, name, values, kwargs, error, match", [
    ("al31f", "rub_stifness", [1e6], {}, ParameterError, "did you mean rub_stiffness"),
    ("al3lf", "rub_stiffness", [1e6], {}, ParameterError, "unknown preset"),
    ("al31f", "rub_stiffness", [-1.0], {}, ParameterError, "rub_stiffness = -1"),
    (build_jeffcott, "rub_stiffness", [], {}, ParameterError, "empty"),
    (build_jeffcott, "rub_stiffness", [1.0, 1.0], {}, ParameterError, "appears twice"),
    (build_jeffcott, "rub_stiffness", [1.0, float("nan")], {}, ParameterError, "finite numbers"),
    (build_jeffcott, "rub stiffness", [1.0], {}, ParameterError, "name of a parameter"),
    (build_jeffcott, "rub_stiffness", list(range(100_001)), {}, ParameterError, "100,001 points.*max_points"),
    (build_jeffcott, {"rub_stiffness": range(10**5), "eccentricity": range(10**5)}, None, {}, ParameterError,
     "10,000,000,000 points.*max_points"),
    (build_jeffcott, "rub_stiffness", [1.0], {"orders": ["1/2 HP"]}, ParameterError, "'HP' is not a rotor"),
    (build_jeffcott, "rub_stiffness", [1.0], {"orders": ["half"]}, ParameterError, "'half' is not a rotor"),
    (build_jeffcott, "rub_stiffness", [1.0], {"poincare": ["q1"]}, ParameterError, "'q1' is not a state"),
    (build_jeffcott, "rub_stiffness", [1.0], {"executor": 3}, TypeError, "concurrent.futures.Executor"),
    (build_jeffcott, "rub_stiffness", [1.0], {"overrides": {"rub_stiffness": 2.0}}, ParameterError,
     "both swept and in overrides"),
    (build_jeffcott, "rub_stiffness", [1.0], {"t_end": 0.4}, ParameterError, "ends after t_end"),
    (build_jeffcott, "rub_stiffness", [1.0], {"window": (0.3, 0.2)}, ParameterError, "t_start < t_end"),
    (build_jeffcott, "rub_stiffness", [1.0], {"workers": 0}, ParameterError, "integer >= 1"),
    (build_jeffcott, "rub_stiffness", [1.0], {"highpass_hz": -5.0}, ParameterError, "cut-off > 0"),
    (build_jeffcott, "rub_stiffness", [1.0], {"signals": ["x2"]}, ParameterError, "'x2' is not a state"),
    (build_jeffcott, "rub_stiffness", [1.0], {"signals": ["x1-z1"]}, ParameterError, "'x1-z1' is not a state"),
    (build_jeffcott, "rub_stiffness", [1.0], {"runaway_limit": 0.0}, ParameterError, "displacement > 0"),
    (build_jeffcott, "rub_stiffness", [1.0], {"simulate_options": {"rtoll": 1e-8}}, TypeError, "unknown keys"),
    (build_jeffcott, "rub_stiffness", [1.0], {"simulate_options": {"method": "RK23", "engine": "compiled"}},
     ParameterError, "engine='compiled' cannot run"),
    (build_jeffcott, "rub_stiffness", [1.0], {"simulate_options": {"sample_rate": 20.0}}, ParameterError,
     "fewer than 16 samples"),
    (build_jeffcott, "rub_stiffness", [1.0], {"overrides": {"eccentricity": object()}}, TypeError,
     "expected a number"),
    (lambda **kw: build_jeffcott(**kw), "rub_stiffness", [1.0, 2.0], {}, TypeError, "module level"),
    (42, "rub_stiffness", [1.0], {}, TypeError, "preset name"),
    (build_jeffcott, "rub_stiffness", [1.0], {"start_method": "thread"}, ParameterError, "start_method='thread'"),
])
def test_bad_arguments_fail_before_anything_runs(tmp_path, preset, name, values, kwargs, error, match):
    kwargs = {"window": WINDOW, **kwargs}
    with pytest.raises(error, match=match):
        run_sweep(preset, name, values, out_dir=tmp_path / "out", **kwargs)
    assert not (tmp_path / "out" / MANIFEST_NAME).exists()


def test_an_unexpected_error_in_a_point_names_the_point(tmp_path, monkeypatch):
    import rotorkit.sweep.run

    def broken(task):
        raise RuntimeError("a bug")

    monkeypatch.setattr(rotorkit.sweep.run, "run_point", broken)
    with pytest.raises(RotorkitError, match=r"sweep point 0 \(rub_stiffness = 1\) raised RuntimeError: a bug.*resume"):
        run_sweep(build_jeffcott, "rub_stiffness", [1.0], out_dir=tmp_path, window=WINDOW, workers=1)


# ---------------------------------------------------------------------------
# The reductions of a point against independent computations
# ---------------------------------------------------------------------------


def test_a_point_stores_the_spectra_and_peak_of_a_direct_run(tmp_path):
    """What the worker stores (one-pass spectra, cheap peak radius) equals Result.spectrum and hypot of a plain run."""
    import rotorkit as rk
    from rotorkit.sweep.point import _order_amplitude

    ds = run_sweep(build_jeffcott, "rub_stiffness", [3e4], out_dir=tmp_path, window=WINDOW, workers=1,
                   signals=["x1", "y1"], orders=["1"])
    meta, frequency, amplitude = _point_arrays(tmp_path, 0)
    result = rk.simulate(build_jeffcott(rub_stiffness=3e4).compile(), (0.0, 0.5),
                         bound=10 * CLEARANCE)
    for row, name in zip(amplitude, ["x1", "y1"]):
        direct = result.spectrum(name, WINDOW, 5.0)
        np.testing.assert_allclose(frequency, direct.frequency, rtol=1e-15)
        np.testing.assert_allclose(row, direct.amplitude, rtol=1e-12, atol=1e-12 * direct.amplitude.max())
        stored = float(ds["order_amplitude"].sel(signal=name, order="1").values.item())
        assert stored == pytest.approx(_order_amplitude(direct, SPIN), rel=1e-12)
    peak = float(np.max(np.hypot(result["x1"], result["y1"])))
    assert meta["max_displacement"] == pytest.approx(peak, rel=1e-12)


@pytest.mark.parametrize("n, n_fft", [(7, 7), (501, 501), (1000, 4096), (16001, 16001)])
@pytest.mark.parametrize("taper", ["hann", "hamming", "boxcar"])
def test_taper_response_closed_form_against_the_direct_sum(n, n_fft, taper):
    """The tone table's response (Dirichlet kernels for Hann) against sum_k w_k exp(-2 pi i d k / n_fft)."""
    from rotorkit.signals.sampling import taper_weights
    from rotorkit.sweep.point import taper_response

    delta = np.linspace(0.0, 1.0, 41)
    _, w = taper_weights(taper, n)
    direct = np.abs(np.exp(-2j * np.pi * np.outer(delta, np.arange(n)) / n_fft) @ w) / w.sum()
    np.testing.assert_allclose(taper_response(taper, n, n_fft, delta), direct, rtol=0, atol=1e-12)
