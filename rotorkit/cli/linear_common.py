"""Options shared by the linear-analysis commands (modes, campbell, unbalance, static)."""

import math
from pathlib import Path

from ..errors import ParameterError
from .common import add_scene_arguments

__all__ = ["add_linear_arguments", "output_folder", "parse_speeds", "write_text", "compiled_scene", "linear_scene"]


def add_linear_arguments(parser, *, speeds=False):
    add_scene_arguments(parser)
    parser.add_argument("--out", help="output folder for figures and CSV (default rotorkit-out/<preset>)")
    parser.add_argument("--units", default="rad/s", type=_display_units, metavar="UNITS",
                        help="frequency and speed units of the printed table, the CSV and the figures: rad/s "
                             "(default), Hz, rpm or another angular speed")
    parser.add_argument("--backend", default="auto", choices=("auto", "c", "numba", "python"),
                        help="code back end (auto: c when a C compiler is found, else numba when installed)")
    parser.add_argument("--speed-parameter", help="swept rotor speed, e.g. LP_speed (default: the first rotor's)")
    if speeds:
        parser.add_argument("--speeds", default=None, metavar="START:STOP:COUNT",
                            help="swept speeds, rad/s unless a unit is given, e.g. 200:3000:15 or "
                                 "'0:15000 rpm:31' (a unit on START or STOP applies to both; "
                                 "default: 0.1 to 2 x the current speed)")


def output_folder(args, name):
    out = Path(args.out) if args.out else Path("rotorkit-out") / args.preset
    out.mkdir(parents=True, exist_ok=True)
    return out


def _display_units(text):
    import argparse

    from ..errors import UnitError
    from ..units import display_factor

    try:
        display_factor(text, "speed", "--units")
    except UnitError as err:
        raise argparse.ArgumentTypeError(str(err)) from None
    return text


def _speed_bound(text, unit, where):
    """A bound of --speeds in rad/s: a number in ``unit`` (rad/s by default) or a quantity."""
    from ..units import parse_quantity, to_si

    value = parse_quantity(text.strip(), where)
    if isinstance(value, float) and unit is not None:
        return to_si(value * unit, "rad/s", where)
    return to_si(text.strip(), "rad/s", where)


def _fast_bounds(texts):
    """START and STOP in rad/s without pint, when each is a number or a number with a common unit, else None.

    The rule of :func:`parse_speeds` holds: one unit on either applies to both.
    """
    from ..units import NUMBER_PATTERN, fast_si

    numbers, units = [], []
    for text in texts:
        text = text.strip()
        match = NUMBER_PATTERN.match(text)
        if not match:
            return None
        numbers.append(float(match.group(0)))
        units.append(text[match.end():].strip())
    given = {u for u in units if u}
    if len(given) > 1:
        return None  # two units: pint says whether they are the same one
    unit = next(iter(given), "rad/s")
    from ..errors import UnitError

    try:  # a wrong dimension or a bound that is not finite: the general path words the error
        values = [fast_si(f"{number!r} {unit}", "rad/s") for number in numbers]
    except UnitError:
        return None
    return None if any(v is None or not math.isfinite(v) for v in values) else values


def speed_bounds(parts, option, text, hint, names):
    """Two speed bounds (texts) in rad/s; a unit on either applies to both (``names``: the bounds, for errors).

    Numbers and the common units are read without pint (:func:`rotorkit.units.fast_si`), others through it.
    """
    bounds = _fast_bounds(parts)
    if bounds is not None:
        return tuple(bounds)
    from ..units import parse_quantity

    try:
        given = [parse_quantity(p.strip(), option) for p in parts]
    except ValueError:
        raise ParameterError(f"{option} {text!r}: {hint}") from None
    units = {str(q.units) for q in given if not isinstance(q, float)}
    if len(units) > 1:
        raise ParameterError(f"{option} {text!r}: {names} carry different units; give one")
    unit = next((q.units for q in given if not isinstance(q, float)), None)
    return tuple(_speed_bound(p, unit, f"{option} {text!r}") for p in parts)


def parse_speeds(text, default_top):
    """``START:STOP:COUNT`` -> COUNT speeds (rad/s); START or STOP may carry a unit (``"0:15000 rpm:31"``).

    Numbers and the common units (rad/s, rpm, Hz ...) are read without pint
    (:func:`rotorkit.units.fast_si`); other units through it.
    """
    import numpy as np

    if text is None:
        top = max(float(default_top), 1.0)
        return np.linspace(0.1 * top, 2.0 * top, 20)
    parts = text.split(":")
    hint = "expected START:STOP:COUNT in rad/s or with a unit, e.g. 200:3000:15 or '0:15000 rpm:31'"
    if len(parts) != 3:
        raise ParameterError(f"--speeds {text!r}: {hint}")
    try:
        count = int(parts[2])
    except ValueError:
        raise ParameterError(f"--speeds {text!r}: {hint}") from None
    start, stop = speed_bounds(parts[:2], "--speeds", text, hint, "START and STOP")
    if not (count >= 2 and stop > start >= 0):
        raise ParameterError(f"--speeds {text!r}: expected 0 <= START < STOP and COUNT >= 2")
    from ..linear.campbell import MAX_SPEEDS

    if count > MAX_SPEEDS:  # before the array is made: 1e8 speeds would be 800 MB and days of eigen-solutions
        raise ParameterError(f"--speeds {text!r}: COUNT = {count} speeds, more than {MAX_SPEEDS} (each an "
                             "eigen-solution of the model): give a smaller COUNT")
    return np.linspace(start, stop, count)


def write_text(path, text):
    from ..files import atomic_write_bytes

    atomic_write_bytes(path, text.encode())
    return path


def compiled_scene(args):
    from .common import load_preset

    _, model, _ = load_preset(args)
    system = model.compile(backend=args.backend)
    available = [p for p in system.parameters if p.endswith("_speed") and p[: -len("_speed")] in model.rotors]
    parameter = args.speed_parameter or (available[0] if available else None)
    if parameter not in available:
        raise ParameterError(f"--speed-parameter {parameter!r}: expected one of {available}")
    return system, parameter


def linear_scene(args):
    """``(model or system, speed parameter)``: the scene's model itself when its equations are linear.

    A linear model (beams, disks, linear bearings) is analysed from its
    cached matrices (:mod:`rotorkit.codegen.linear_cache`): nothing is
    compiled, a warm cache derives nothing. Any other is compiled as by
    :func:`compiled_scene`.
    """
    from ..codegen.linear_cache import linear_module
    from .common import load_preset

    _, model, _ = load_preset(args)
    available = [p for p in model.parameters if p.endswith("_speed") and p[: -len("_speed")] in model.rotors]
    parameter = args.speed_parameter or (available[0] if available else None)
    if parameter not in available:
        raise ParameterError(f"--speed-parameter {parameter!r}: expected one of {available}")
    if linear_module(model).LINEAR:
        return model, parameter
    return model.compile(backend=args.backend), parameter
