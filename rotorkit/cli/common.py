"""Helpers shared by the commands: --set parsing, progress lines, figure files, scene loading."""

import re
import sys

from ..errors import ParameterError

__all__ = ["parse_assignment", "progress_printer", "save_figure", "load_preset", "add_scene_arguments"]

_TRUE, _FALSE = {"true", "yes", "on", "1"}, {"false", "no", "off", "0"}
#: a --set value: a plain decimal number, optionally followed by a unit expression (letters, /, *, ^, spaces)
_QUANTITY = re.compile(r"^\s*([+-]?(?:inf|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d{1,3})?))\s*"
                       r"((?![eE][+-]?\d)(?:1\s*/\s*)?[A-Za-zµ°Ω][A-Za-zµ°Ω0-9_ /*^.\-]*)?\s*$")


def parse_assignment(text, defaults=None):
    """Parse ``name=value`` strictly: a float, a pint quantity (``"2e6 N/m"``) or a switch.

    Parameters
    ----------
    text : str
    defaults : dict, optional
        Known names -> default values; a bool default makes the value a switch.

    Returns
    -------
    (str, object)
    """
    if "=" not in text:
        raise ParameterError(f"--set {text!r}: expected name=value, e.g. rub_stiffness=2e6")
    name, raw = (s.strip() for s in text.split("=", 1))
    if not name.isidentifier():
        raise ParameterError(f"--set {text!r}: {name!r} is not a parameter name")
    if defaults is not None and isinstance(defaults.get(name), bool):
        low = raw.lower()
        if low in _TRUE | _FALSE:
            return name, low in _TRUE
        raise ParameterError(f"--set {name}={raw!r}: expected true or false")
    match = _QUANTITY.match(raw)
    if not match:
        raise ParameterError(
            f"--set {name}={raw!r}: not a number or a quantity with units (e.g. 2e6 or '2e6 N/m')"
        )
    number, unit = match.group(1), match.group(2)
    value = float(number)  # a non-finite value is refused by the parameter's own check
    if not unit:
        return name, value
    from ..units import registry

    if re.search(r"\d\s*\*\*|\*\*\s*\d{3,}", unit):
        raise ParameterError(f"--set {name}={raw!r}: the unit {unit!r} is not a unit expression")
    try:
        quantity = value * registry().Unit(unit)
    except Exception as exc:
        raise ParameterError(f"--set {name}={raw!r}: {unit!r} is not a unit pint knows (e.g. N/m, mm, rpm)") from exc
    return name, quantity


def progress_printer():
    state = {"last": -1}
    tty = sys.stderr.isatty()

    def report(fraction, t):
        if tty:
            bar = "#" * int(30 * fraction)
            sys.stderr.write(f"\r  simulating [{bar:<30}] {100 * fraction:5.1f} %  t = {t:.3f} s")
            if fraction >= 1:
                sys.stderr.write("\n")
        else:
            decile = int(10 * fraction)
            if decile > state["last"]:
                state["last"] = decile
                sys.stderr.write(f"  simulating: {100 * fraction:5.1f} %  t = {t:.3f} s\n")
        sys.stderr.flush()

    return report


def save_figure(fig, path):
    import io

    from ..files import atomic_write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120)
    atomic_write_bytes(path, buf.getvalue())
    return path




def add_scene_arguments(parser):
    """The scene a command works on: a preset name and ``--set`` overrides."""
    parser.add_argument("preset", help="preset name, e.g. al31f (see 'rotorkit list')")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="override a preset parameter (SI number or quantity, e.g. rub_stiffness=2e6)")


def load_preset(args):
    """(preset module, model, overrides) for ``args.preset`` with ``args.set`` applied."""
    from ..presets import preset_module

    module = preset_module(args.preset)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    overrides = dict(parse_assignment(s, known) for s in args.set)
    return module, module.build(**overrides), overrides
