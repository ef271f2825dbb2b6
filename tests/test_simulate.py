"""simulate(): restarts at discontinuities, sampling, failures with partial results."""

import numpy as np
import pytest

import rotorkit as rk


def jeffcott(speed=50.0):
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=speed),
                     rk.Disk(station=1, mass=1.0, radius=0.1, eccentricity=1e-4),
                     rk.ElasticSupport(station=1, stiffness=1e4, damping=2.0)]).compile()


def test_restarts_at_the_manoeuvre_steps():
    system = rk.preset("al31f").compile()
    result = rk.simulate(system, (1.9, 2.1), sample_rate=2000.0)
    assert result.stats["segments"] == 2
    assert result.t[0] == 1.9 and result.t[-1] == pytest.approx(2.1)
    assert np.all(np.diff(result.t) > 0)  # no duplicated sample at t = 2
    assert len(result.t) == 401


def test_segment_sees_its_own_side_of_a_jump():
    """A step load switched on at t0 must not act before t0 (restart, not straddle)."""
    import sympy as sp

    from rotorkit.symbolic.functions import window

    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=0.0),
                      rk.LumpedMass(station=1, mass=1.0),
                      rk.ElasticSupport(station=1, stiffness=100.0),
                      rk.Maneuver.profile(lambda t: 10 * window(t, 0.5, 10.0), lambda t: sp.S.Zero,
                                          event_times=(0.5,))])
    result = rk.simulate(model.compile(), (0.0, 1.0), rtol=1e-10, atol=1e-12, sample_rate=1000.0)
    x = result["x1"]
    assert np.all(x[result.t <= 0.5] == 0.0)
    tau = result.t[result.t > 0.5] - 0.5
    np.testing.assert_allclose(x[result.t > 0.5], 0.1 * (1 - np.cos(10 * tau)), atol=1e-9)


class _Exploding:
    """A system whose state runs away at t = 0.3 (duck-typed like rotorkit.System)."""

    name, backend, parameters, time_events = "exploding", "python", {}, ()
    state_names = ("x", "x_dot")
    n_states = 2

    def within(self, start, end):
        return self

    def rhs(self, t, y):
        return np.array([y[1], np.nan if t > 0.3 else -y[0]])


def test_failure_raises_with_partial_result():
    with pytest.raises(rk.SimulationError, match=r"failed at t = 0\.3") as info:
        rk.simulate(_Exploding(), (0.0, 1.0), y0=[1.0, 0.0], sample_rate=100.0)
    err = info.value
    assert err.partial is not None and err.partial.t[-1] <= 0.31 and err.time == pytest.approx(0.3, abs=0.01)
    assert np.all(np.isfinite(err.partial.y))


@pytest.mark.parametrize("kwargs, match", [
    ({"method": "Euler"}, "method='Euler' is unknown"),
    ({"t_span": (1.0, 0.0)}, "end time must be after"),
    ({"y0": [0.0]}, r"y0 has shape \(1,\)"),
    ({"sample_rate": 0.0}, "sample_rate"),
])
def test_bad_arguments(kwargs, match):
    kwargs = {"t_span": (0.0, 0.1), **kwargs}
    with pytest.raises(rk.ParameterError, match=match):
        rk.simulate(jeffcott(), **kwargs)


def test_progress_is_reported():
    seen = []
    rk.simulate(jeffcott(), (0.0, 2.0), progress=lambda fraction, t: seen.append(fraction))
    assert seen and seen[-1] == 1.0


numba_only = pytest.mark.skipif("numba" not in rk.available_backends(), reason="the compiled engine needs numba")


@numba_only
@pytest.mark.parametrize("method", ["RK45", "DOP853"])
def test_engines_agree_on_a_short_preset_run(method):
    system = rk.preset("al31f").compile(backend="numba")
    span = (1.95, 2.1)  # across the roll start
    ref = rk.simulate(system, span, method="DOP853", rtol=1e-12, atol=1e-15, engine="scipy")
    a = rk.simulate(system, span, method=method, rtol=1e-9, atol=1e-13, engine="compiled")
    b = rk.simulate(system, span, method=method, rtol=1e-9, atol=1e-13, engine="scipy")
    assert a.stats["engine"] == "compiled" and b.stats["engine"] == "scipy"
    scale = np.abs(ref["x2"]).max()
    for res in (a, b):
        np.testing.assert_array_equal(res.t, ref.t)
        assert np.abs(res["x2"] - ref["x2"]).max() < 1e-5 * scale
        assert np.abs(res["alpha2-alpha5"] - ref["alpha2-alpha5"]).max() < 1e-5 * np.abs(ref["alpha2-alpha5"]).max()
    # same error control: step counts within a few percent
    assert abs(a.stats["nfev"] - b.stats["nfev"]) <= 0.05 * b.stats["nfev"]


@numba_only
def test_compiled_engine_on_jeffcott_closed_form():
    """Steady unbalance amplitude e r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2) with the compiled engine."""
    m, k, c, e = 2.0, 2e4, 20.0, 1e-4
    wn, zeta = np.sqrt(k / m), c / (2 * np.sqrt(k * m))
    for ratio in (0.5, 1.5):
        system = rk.Model([rk.Rotor(name="R", stations=(1,), speed=ratio * wn),
                           rk.Disk(station=1, mass=m, radius=0.1, eccentricity=e),
                           rk.ElasticSupport(station=1, stiffness=k, damping=c)]).compile(backend="numba")
        res = rk.simulate(system, (0.0, 3.0), rtol=1e-9, atol=1e-13, engine="compiled")
        late = res.window(2.5, 3.0)
        radius = np.hypot(late["x1"], late["y1"])
        expected = e * ratio**2 / np.sqrt((1 - ratio**2) ** 2 + (2 * zeta * ratio) ** 2)
        np.testing.assert_allclose(radius, expected, rtol=1e-5)


@numba_only
def test_compiled_engine_failure_is_explained():
    system = rk.preset("al31f").compile(backend="numba")
    with pytest.raises(rk.ParameterError, match="engine='compiled' cannot run method 'Radau'"):
        rk.simulate(system, (0.0, 0.01), method="Radau", engine="compiled")
    with pytest.raises(rk.ParameterError, match="engine='warp' is unknown"):
        rk.simulate(system, (0.0, 0.01), engine="warp")


@pytest.mark.parametrize("engine", ["scipy"] + (["compiled"] if "numba" in rk.available_backends() else []))
def test_wall_time_limit_stops_cleanly_with_partial_result(engine):
    system = rk.preset("al31f").compile()
    with pytest.raises(rk.SimulationError, match="wall-time limit reached") as info:
        rk.simulate(system, (0.0, 30.0), engine=engine, time_limit=0.3)
    partial = info.value.partial
    assert partial is not None and partial.t.size > 10 and np.all(np.isfinite(partial.y))
    assert 0.0 < info.value.time < 30.0 and partial.t[-1] <= info.value.time + 1e-12
    assert partial.stats["wall_time"] < 5.0


def test_scipy_engine_keeps_samples_before_a_failure():
    with pytest.raises(rk.SimulationError) as info:
        rk.simulate(_Exploding(), (0.0, 1.0), y0=[1.0, 0.0], sample_rate=100.0, engine="scipy")
    partial = info.value.partial
    # samples up to the blow-up are kept, and they are the exact solution cos(t)
    assert partial.t.size >= 25
    np.testing.assert_allclose(partial["x"], np.cos(partial.t), atol=1e-4)


def test_implicit_methods_use_the_analytic_jacobian():
    system = rk.preset("al31f").compile()
    res = rk.simulate(system, (0.0, 0.005), method="Radau", rtol=1e-6, engine="scipy")
    assert res.stats["njev"] > 0 and res.stats["success"]
    ref = rk.simulate(system, (0.0, 0.005), method="DOP853", rtol=1e-10, atol=1e-14, engine="scipy")
    assert np.abs(res["x2"] - ref["x2"]).max() < 1e-3 * np.abs(ref["x2"]).max()


def test_contact_events_restart_at_every_onset_and_loss():
    """A Jeffcott rotor whose orbit crosses the rub clearance twice per revolution."""
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=100.0),
                      rk.Disk(station=1, mass=1.0, radius=0.1, eccentricity=1e-4),
                      rk.ElasticSupport(station=1, stiffness=1e4, damping=2.0),
                      rk.RubStator(station=1, clearance=1e-4, contact_stiffness=1e5, friction_coefficient=0.1),
                      rk.Maneuver.steady(gravity=9.81)])
    system = model.compile()
    ref = rk.simulate(system, (0.0, 0.5), rtol=1e-12, atol=1e-16, engine="scipy", contact_events=True)
    res = rk.simulate(system, (0.0, 0.5), rtol=1e-7, atol=1e-11, contact_events=True)
    assert res.stats["engine"] == "scipy" and res.stats["contact_events"] is True
    r = np.hypot(ref["x1"], ref["y1"])
    crossings = np.count_nonzero(np.diff(np.sign(r - 1e-4)) != 0)
    assert crossings > 10 and abs(res.stats["events"] - crossings) <= 2  # one restart per onset/loss
    assert np.abs(res["x1"] - ref["x1"]).max() < 1e-4 * np.abs(ref["x1"]).max()


def test_contact_events_need_the_scipy_engine():
    system = rk.preset("al31f").compile()
    if system.backend == "numba":
        with pytest.raises(rk.ParameterError, match="contact_events=True needs engine='scipy'"):
            rk.simulate(system, (0.0, 0.01), engine="compiled", contact_events=True)


@pytest.mark.parametrize("engine", ["scipy"] + (["compiled"] if "numba" in rk.available_backends() else []))
def test_run_away_is_stopped_and_explained(engine):
    """MODEL_NOTES: at mu = 0.3 with k_r = 8e6 N/m the disk runs away into dry-friction whirl after the roll starts."""
    system = rk.preset("al31f", friction_coefficient=0.3).compile()
    with pytest.raises(rk.SimulationError, match="run-away: .* exceeds the bound 0.002 m") as info:
        rk.simulate(system, (1.9, 3.0), y0=rk.simulate(system, (0.0, 1.9)).y[:, -1], engine=engine, bound=2e-3,
                    time_limit=120)
    assert 2.0 < info.value.time < 2.6  # shortly after the roll starts at 2 s
    assert np.all(np.isfinite(info.value.partial.y))


@pytest.mark.parametrize("span", [(0.2, 0.3), (0.0, 0.1), (1.05, 1.2)])
def test_samples_cover_the_span_exactly(span):
    res = rk.simulate(jeffcott(), span, sample_rate=1e4)
    assert res.t[0] == span[0] and res.t[-1] == span[1]
    assert len(res.t) == round((span[1] - span[0]) * 1e4) + 1


def test_default_bound_never_returns_a_run_away_as_a_result():
    """A rub scene that runs away (mu = 0.3, MODEL_NOTES) raises by default instead of returning metre amplitudes."""
    system = rk.preset("al31f", friction_coefficient=0.3).compile()
    with pytest.raises(rk.SimulationError, match="run-away at t = 2.1") as info:
        rk.simulate(system, (0.0, 2.3))
    assert np.abs(info.value.partial["y1"]).max() <= 0.0134
    result = rk.simulate(system, (0.0, 2.3), bound=None)  # the caller accepts it explicitly
    assert np.abs(result["y1"]).max() > 0.0134


def test_run_away_bound_reads_displacements_only():
    """Tilts (rad) and modal coordinates are not compared with a bound in metres; x, y and pedestals are."""
    from types import SimpleNamespace

    from rotorkit.simulate import _escaped

    system = SimpleNamespace(coordinate_names=("x1", "thx1", "thy1", "alpha1", "eta1", "px1"))
    samples = np.zeros((6, 3))
    samples[1:5, 2] = 0.5  # half a radian of tilt and twist, a large modal amplitude
    assert _escaped(system, samples, 0.01) == ""
    samples[5, 1] = 0.02
    assert _escaped(system, samples, 0.01).startswith("run-away: |px1| = 0.02 m exceeds the bound 0.01 m")
