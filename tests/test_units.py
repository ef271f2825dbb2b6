"""Units at the boundary: the bounded quantity grammar and to_si on strings."""

import subprocess
import sys

import pytest

from rotorkit.errors import ParameterError, UnitError
from rotorkit.units import MAX_EXPONENT, parse_quantity, parse_unit, to_si


@pytest.mark.parametrize("text, si_unit, expected", [
    ("2e6 N/m", "N/m", 2e6),
    ("2e3 N/mm", "N/m", 2e6),
    ("3000 rpm", "rad/s", 3000 * 2 * 3.141592653589793 / 60),
    ("1 1/s", "1/s", 1.0),
    ("5 kg*m^2", "kg*m**2", 5.0),
    ("5 kg m**2", "kg*m**2", 5.0),
    ("2 (m/s)**2", "m**2/s**2", 2.0),
    ("1 kg m s^-2", "N", 1.0),
    ("1 m/s/s", "m/s**2", 1.0),
    ("7 µm", "m", 7e-6),
    ("7 um", "m", 7e-6),
    ("+.5 mm", "m", 5e-4),
    ("90 °", "rad", 3.141592653589793 / 2),
    ("3e9 N/m**1.5", "N/m**1.5", 3e9),  # Hertzian contact stiffness
    ("3e9 N/m^(3/2)", "N/m**1.5", 3e9),
    ("4 (m^(1/2))^2", "m", 4.0),
])
def test_parse_quantity_reads_units(text, si_unit, expected):
    quantity = parse_quantity(text, "x")
    assert quantity.to(si_unit).magnitude == pytest.approx(expected, rel=1e-12)


def test_parse_quantity_without_unit_is_a_float():
    assert parse_quantity(" 2.5e-3 ", "x") == 2.5e-3
    assert parse_quantity("inf", "x") == float("inf")  # refused later by the parameter's own check
    assert isinstance(parse_quantity("3", "x"), float)


@pytest.mark.parametrize("text, match", [
    ("abc", "not a number or a quantity"),
    ("nan", "not a number or a quantity"),
    ("0x1", "not a number or a quantity"),
    ("1,5", "not a number or a quantity"),
    ("1 2", "not a number or a quantity"),
    ("1e5000", "not a number or a quantity"),
    ("1 bogus_unit", "not a unit pint knows"),
    ("1 m2", "not a unit name"),
    ("1 m^13", "m to the power 13"),
    ("1 m^0.333", "not a small number"),
    ("1 m^(1/0)", "not a small number"),
    ("1 ((m)", "unbalanced parentheses"),
    ("1 m)", "unexpected"),
    ("1 ((((m))))", "nested parentheses"),
    ("1 (((m^4)^3)^2)", "m to the power 24"),
    ("1 m*m*m*m*m*m*m*m*m*m*m*m*m", "m to the power 13"),
    ("1 m; import os", "unexpected"),
    ("1 " + "m*" * 100 + "m", "longer than"),
])
def test_parse_quantity_refuses_with_a_named_error(text, match):
    with pytest.raises(UnitError, match=match):
        parse_quantity(text, "rub_stiffness")


# every spelling of an exponent tower; pint would evaluate 9**9**9 exactly and run for minutes
TOWERS = ["9**9**9", "1 m**9**9**9", "1 m^9^9^9", "1 m**(9**9)", "1 m^(9^9)", "1 (m**9)**9**9", "1 m**9^9",
          "1 m ** 99999999999", "1 m^-99999999999", "1 (((m^12)^12)^12)", "1 m" + "**9" * 60,
          "1 m**9.0**9", "1 meter**(9*9*9*9*9*9*9*9)"]


@pytest.mark.parametrize("text", TOWERS)
def test_exponent_towers_are_refused(text):
    with pytest.raises(UnitError):
        parse_quantity(text, "x")


def test_exponent_towers_return_quickly_in_a_child():
    """A hang would show as a timeout: the child parses every tower (TimeoutExpired fails the test)."""
    code = ("from rotorkit.units import parse_quantity\nfrom rotorkit.errors import UnitError\n"
            f"for t in {TOWERS!r}:\n    try:\n        parse_quantity(t)\n    except UnitError:\n        pass\n"
            "print('ok')")
    out = subprocess.run([sys.executable, "-c", code], timeout=20, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"


def test_exponent_bound_is_inclusive():
    assert parse_unit(f"m^{MAX_EXPONENT}") == parse_unit("m") ** MAX_EXPONENT
    assert parse_unit(f"m^{MAX_EXPONENT}/m^{MAX_EXPONENT}") == parse_unit("dimensionless")


def test_to_si_reads_strings():
    assert to_si("2e3 N/mm", "N/m", "k") == pytest.approx(2e6)
    assert to_si("12.5", "m", "length") == 12.5
    with pytest.raises(UnitError, match="wrong unit"):
        to_si("2 kg", "N/m", "k")
    with pytest.raises(UnitError, match="Hz is ambiguous"):
        to_si("50 Hz", "rad/s", "speed")
    with pytest.raises(ParameterError, match="not finite"):
        to_si("inf N/m", "N/m", "k")
    with pytest.raises(UnitError, match="exponent of an exponent"):
        to_si("1 m**9**9", "m", "length")


def test_elements_take_quantity_strings():
    from rotorkit.elements import LumpedMass

    assert LumpedMass(station=1, mass="2500 g").mass == pytest.approx(2.5)
    with pytest.raises(UnitError, match=r"LumpedMass\.mass = '2 N' has the wrong unit"):
        LumpedMass(station=1, mass="2 N")


FAST_CASES = ["60 mm", "20 um", "1.5 cm", "3 m", "76.9 kg", "250 g", "2.5 ms", "1.5 min", "3000 rpm", "90 deg",
              "0.5 rad", "2 MN/m", "400 kN*s/m", "211 GPa", "7850 kg/m**3", "2.43 kg*m**2", "9.81 m/s**2",
              "5 N*m", "1e-3 Pa*s", "12 rad/s", "1 N/mm", "100 g*mm", "3 kPa", "4 MPa", "-40 MN/m"]


@pytest.mark.parametrize("text", FAST_CASES)
def test_fast_units_equal_pint(text):
    """The pint-free reading of common units gives pint's value (to one rounding) in the SI unit."""
    from rotorkit.units import fast_si, parse_quantity

    quantity = parse_quantity(text, "q")
    si = quantity.to_base_units()
    expected_unit = str(si.units).replace("meter", "m").replace("kilogram", "kg").replace("second", "s")
    expected_unit = expected_unit.replace("radian", "rad")
    expected_unit = "" if expected_unit == "dimensionless" else expected_unit.replace(" ", "")
    value = fast_si(text, expected_unit)
    assert value is not None, (text, expected_unit)
    assert value == pytest.approx(float(si.magnitude), rel=3e-16, abs=0)


@pytest.mark.parametrize("text, unit", [("3000 m", "rad/s"), ("2 MN/m", "N*s/m"), ("5 kg", "m"), ("1 rpm", "")])
def test_fast_units_refuse_a_wrong_dimension(text, unit):
    from rotorkit.units import fast_si, to_si

    with pytest.raises(UnitError, match="wrong unit"):
        fast_si(text, unit)
    with pytest.raises(UnitError, match="wrong unit"):
        to_si(text, unit, "q")


@pytest.mark.parametrize("text, unit", [("50 Hz", "rad/s"), ("5 furlong", "m"), ("3 m**1.5", "m**1.5"),
                                        ("2 N/m", "N/m**1.5"), ("not a number", "m")])
def test_fast_units_leave_the_rest_to_pint(text, unit):
    from rotorkit.units import fast_si

    assert fast_si(text, unit) is None


def test_loading_a_model_file_of_common_units_does_not_import_pint():
    """pint's import and registry (about 1.5 s) are not paid to read examples/compressor.toml."""
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    code = ("import sys, rotorkit as rk\n"
            f"m = rk.load_model({str(root / 'examples' / 'compressor.toml')!r})\n"
            "assert m.parameters['R_speed'] == 3000 * 0 + 10000 * 2 * 3.141592653589793 / 60\n"
            "print('pint' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=root, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"
