"""Resource bounds, tolerances that cannot give an answer, and clear errors for odd inputs."""

import io
import zipfile

import numpy as np
import pytest

import rotorkit as rk
import importlib

simulate_module = importlib.import_module("rotorkit.simulate")
from rotorkit.errors import ParameterError
from rotorkit import run_checks


def jeffcott(mass=1.0, speed=50.0):
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=speed),
                     rk.Disk(station=1, mass=mass, radius=0.1, eccentricity=1e-4),
                     rk.ElasticSupport(station=1, stiffness=1e4, damping=2.0)])


@pytest.fixture(scope="module")
def system():
    return jeffcott().compile(backend="python")


@pytest.mark.parametrize("options, match", [
    (dict(rtol=10.0), r"rtol=10\.0 cannot give an answer"),
    (dict(rtol=0.5), r"rtol=0\.5 cannot give an answer"),
    (dict(atol=1e300), r"atol=1e\+300 cannot give an answer"),
    (dict(atol=np.full(4, 0.1)), r"cannot give an answer"),
])
def test_tolerances_that_cannot_give_an_answer_are_refused(system, options, match):
    with pytest.raises(ParameterError, match=match):
        rk.simulate(system, (0.0, 0.01), **options)


def test_loosest_accepted_tolerances_still_run(system):
    result = rk.simulate(system, (0.0, 0.01), rtol=run_checks.MAX_RTOL, atol=run_checks.MAX_ATOL)
    assert result.stats["success"] and np.abs(result.y).max() < simulate_module.DIVERGED


def test_memory_is_estimated_before_allocating(system, monkeypatch):
    n = system.n_states
    need = run_checks.sample_memory(n, 10.0, 1e7)
    assert need == 2 * 8 * (n + 1) * (10**8 + 2)  # (states + time) x samples x float64, twice
    monkeypatch.setattr(run_checks, "_available_memory", lambda: 2 * need - 1)  # half of it is < need
    with pytest.raises(ParameterError, match=r"needs about 8 GB .*lower sample_rate to [\d.e+]+ Hz"):
        rk.simulate(system, (0.0, 10.0), sample_rate=1e7)


def test_the_preset_sample_rate_from_the_issue_is_refused_with_the_estimate():
    system = rk.preset("al31f").compile(backend="python")
    with pytest.raises(ParameterError, match=r"32 states needs about 5\d\d GB"):
        rk.simulate(system, (0.0, 6.0), sample_rate=1.6e8)


def _npz_declaring(shape, tmp_path):
    """A tiny .npz whose y.npy header declares ``shape`` (float64) but holds a few bytes."""
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": shape})
    path = tmp_path / "bomb.npz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("y.npy", header.getvalue() + b"\0" * 64)
        archive.writestr("t.npy", header.getvalue() + b"\0" * 64)
    return path


def test_load_result_checks_declared_sizes_first(tmp_path):
    path = _npz_declaring((10**6, 10**6), tmp_path)  # 8 TB declared in a file of a few hundred bytes
    assert path.stat().st_size < 2000
    with pytest.raises(ParameterError, match=r"declare 1\.6e\+04 GB, more than"):
        rk.load_result(path)


def test_load_result_max_bytes(tmp_path, system):
    result = rk.simulate(system, (0.0, 0.01), sample_rate=1000.0)
    path = result.save(tmp_path / "r.npz")
    assert rk.load_result(path).y.shape == result.y.shape
    with pytest.raises(ParameterError, match="more than"):
        rk.load_result(path, max_bytes=100)


def test_bound_accepts_numpy_scalars(system):
    result = rk.simulate(system, (0.0, 0.01), bound=np.float32(1e-3))
    assert result.stats["success"]
    for bad in (True, float("nan"), -1.0, "big"):
        with pytest.raises(ParameterError, match="bound="):
            rk.simulate(system, (0.0, 0.01), bound=bad)


def test_result_indexed_by_number_says_how(system):
    result = rk.simulate(system, (0.0, 0.01))
    with pytest.raises(TypeError, match=r"index a result by signal name.*result\.y"):
        result[0]


def test_subnormal_mass_is_a_parameter_error():
    # refused when compiled (its reciprocal, prepared once per parameter set, overflows) or else when run
    with pytest.raises(ParameterError, match=r"disk1_mass = 9\.99989e-321.*(too close to zero|too small)"):
        system = jeffcott(mass=1e-320).compile(backend="python")
        rk.simulate(system, (0.0, 0.01))


def test_huge_speed_is_not_blamed_on_a_small_length():
    with pytest.raises(ParameterError, match=r"R_speed.*value too large"):
        jeffcott(speed=1e300).compile(backend="python")


def test_preset_error_names_the_override():
    with pytest.raises(ParameterError, match=r"override rub_stiffness=-1 is refused: RubStator\.contact_stiffness"):
        rk.preset("al31f", rub_stiffness=-1)


def test_names_equal_after_unicode_normalisation_are_refused():
    from rotorkit.errors import TopologyError

    def two_rotors(second):
        return [rk.Rotor(name="R", stations=(1,), speed=50.0), rk.Rotor(name=second, stations=(2,), speed=5.0),
                rk.Disk(station=1, mass=1.0, radius=0.1), rk.Disk(station=2, mass=1.0, radius=0.1),
                rk.ElasticSupport(station=1, stiffness=1e4), rk.ElasticSupport(station=2, stiffness=1e4)]

    assert "\u211b".isidentifier() and "\u211b" != "R"  # script capital R: another string, the same identifier
    with pytest.raises(TopologyError, match=r"the same identifier 'R' after Unicode normalisation"):
        rk.Model(two_rotors("\u211b"))
    assert len(rk.Model(two_rotors("S")).elements) == 6


def test_a_max_step_that_asks_for_too_many_steps_is_refused_before_running(system):
    with pytest.raises(ParameterError, match=r"max_step=1e-09 .* at least 1e\+09 steps"):
        rk.simulate(system, (0.0, 1.0), max_step=1e-9, engine="scipy")
    result = rk.simulate(system, (0.0, 1e-3), max_step=1e-7)  # 1e4 steps: fine
    assert result.stats["success"]


@pytest.mark.parametrize("n_balls", [101, 5000])
def test_a_bearing_with_thousands_of_balls_is_refused_at_construction(n_balls):
    with pytest.raises(ParameterError, match=rf"n_balls={n_balls} is more than 100"):
        rk.BallBearing(inner_station=1, outer_station=2, contact_stiffness=1e9, clearance=1e-6, n_balls=n_balls,
                       inner_race_radius=0.04, outer_race_radius=0.06)
    rk.BallBearing(inner_station=1, outer_station=2, contact_stiffness=1e9, clearance=1e-6, n_balls=100,
                   inner_race_radius=0.04, outer_race_radius=0.06)
