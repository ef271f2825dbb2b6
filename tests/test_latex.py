"""LaTeX of the custom functions, of every element and of whole equations (notebook display)."""

import inspect

import pytest
import sympy as sp

import rotorkit as rk
from rotorkit.symbolic import functions

x, y, z = sp.symbols("x y z", real=True)
CUSTOM = [obj for _, obj in inspect.getmembers(functions, inspect.isclass)
          if issubclass(obj, sp.Function) and obj.__module__ == functions.__name__]


def _call(cls):
    return cls(*(x, y, z)[: cls.nargs.args[0] if hasattr(cls.nargs, "args") else cls.nargs])


def test_every_custom_function_is_covered():
    assert {c.__name__ for c in CUSTOM} == set(functions.__all__)


@pytest.mark.parametrize("cls", CUSTOM, ids=lambda c: c.__name__)
@pytest.mark.parametrize("power", [1, 2, sp.Rational(3, 2), sp.Float(1.5)])
def test_powers_of_custom_functions_print(cls, power):
    expr = _call(cls)
    text = sp.latex(expr**power)
    assert text and "ramp" not in text and "safe_div" not in text
    if power != 1:
        # the exponent is printed once, on a bracketed base
        assert text.count("^{") >= 1 and (str(power) in text or sp.latex(power) in text)


def test_al31f_equations_latex_with_ball_bearing():
    """The AL-31F scene has BallBearings (ramp(...)**1.5): its LaTeX used to raise a TypeError."""
    eom = rk.preset("al31f").equations()
    text = eom.latex()
    assert r"\right\rangle_{+}\right)^{\frac{3}{2}}" in text  # the Hertz power of a ramp
    assert eom._repr_latex_().startswith("$$")


def _mathrm_groups(text):
    """The contents of every ``\\mathrm{...}`` group (braces balanced, escaped braces skipped)."""
    out, start = [], 0
    while (i := text.find(r"\mathrm{", start)) >= 0:
        j, depth = i + len(r"\mathrm{"), 1
        while depth:
            if text[j] == "\\":
                j += 2
                continue
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        out.append(text[i + len(r"\mathrm{"): j - 1])
        start = j
    return out


def _bare(group, ch):
    return any(c == ch and (k == 0 or group[k - 1] != "\\") for k, c in enumerate(group))


def _named_model():
    return rk.Model([
        rk.Rotor(name="hp_rotor", stations=("front_end", 1), speed=120.0),
        rk.Disk(name="fan_disk_1", station="front_end", mass=4.0, radius=0.1, eccentricity=2e-3),
        rk.LumpedMass(station=1, mass=1.5),
        rk.ElasticSupport(name="rear_support", station=1, stiffness=2e5, damping=10.0),
        rk.ShaftSegment(start="front_end", end=1, bending_stiffness=3e5),
    ])


@pytest.mark.parametrize("make", [lambda: rk.preset("al31f"), _named_model], ids=["al31f", "named"])
def test_parameter_and_coordinate_names_escape_underscores(make):
    """Labels such as ``bearing4_7`` print as ``\\mathrm{bearing4\\_7}``, not as a subscript inside ``\\mathrm``."""
    from matplotlib.mathtext import MathTextParser

    model = make()
    eom = model.equations()
    parser = MathTextParser("path")
    labels = {e.label() for e in model.elements}
    assert any("_" in label for label in labels)  # the case under test is present
    for symbol, name in eom.latex_names.items():
        groups = _mathrm_groups(name)
        assert not any(_bare(g, "_") or _bare(g, "^") for g in groups), (symbol, name)
        parser.parse(f"${name}$")  # a TeX-like parser accepts it (raises on a double subscript)
    printed = _mathrm_groups(" ".join(eom.latex_names.values()))
    for e in model.elements:
        if "_" in e.label() and e.parameters():
            assert e.label().replace("_", r"\_") in printed
    # the whole rendered system, as shown in a notebook
    assert not any(_bare(g, "_") for g in _mathrm_groups(eom.latex()))
    # sympy's printer uses the names: an underscored label appears escaped in the printed matrix
    text = sp.latex(eom.stiffness, symbol_names=eom.latex_names)
    assert not any(_bare(g, "_") for g in _mathrm_groups(text))


def test_named_model_station_names_escape_in_coordinates():
    eom = _named_model().equations()
    names = {str(q): eom.latex_names[q] for q in eom.coordinates}
    assert any(r"front\_end" in v for v in names.values())
    assert not any("front_end" in v for v in names.values())
