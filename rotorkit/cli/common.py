"""Helpers shared by the commands: --set parsing, progress lines, figure files, scene loading."""

import sys

from ..errors import ParameterError

__all__ = ["parse_assignment", "progress_printer", "save_figure", "load_preset", "load_scene", "add_scene_arguments",
           "scene_module", "check_parameter_name", "positive_float", "positive_int", "nonnegative_int", "FileScene"]

_TRUE, _FALSE = {"true", "yes", "on", "1"}, {"false", "no", "off", "0"}


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
    from ..units import parse_quantity

    # a float, or a pint quantity from the bounded grammar of rotorkit.units (no pint string evaluation)
    return name, parse_quantity(raw, f"--set {name}")


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
    """Write ``fig`` as a PNG file (120 dpi), atomically; the path."""
    from ..files import atomic_write_bytes

    atomic_write_bytes(path, save_figure_bytes(fig))
    return path


def save_figure_bytes(fig, dpi=120):
    """``fig`` as PNG bytes."""
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()




def positive_float(text):
    """argparse type: a finite number > 0 (checked before any derivation or compilation)."""
    import argparse
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r}: expected a finite number > 0")
    return value


def _integer_at_least(minimum, name):
    """An argparse type: an integer >= ``minimum``."""

    def parse(text):
        import argparse

        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{text!r}: expected an integer >= {minimum}")
        return value

    parse.__name__ = parse.__qualname__ = name
    parse.__doc__ = f"argparse type: an integer >= {minimum}."
    return parse


positive_int = _integer_at_least(1, "positive_int")
nonnegative_int = _integer_at_least(0, "nonnegative_int")


def add_scene_arguments(parser):
    """The scene a command works on: a preset name or a model file, and ``--set`` overrides."""
    parser.add_argument("preset", metavar="SCENE",
                        help="preset name (e.g. al31f, see 'rotorkit list') or path to a model file (.toml)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="override a parameter (SI number or quantity, e.g. rub_stiffness=2e6 or "
                             "'rub_stiffness=2e6 N/m'); a model file's parameters are named as in "
                             "'rotorkit equations FILE' (e.g. support1_stiffness)")


def is_model_file(scene):
    """A scene argument names a model file (ends in .toml or is an existing file), not a preset."""
    from pathlib import Path

    text = str(scene)
    return text.lower().endswith(".toml") or "/" in text or "\\" in text or Path(text).is_file()


def check_parameter_name(name, known, scene, what="--set"):
    """Raise the same "did you mean" for an unknown parameter name wherever one is given."""
    if name not in known:
        import difflib

        near = difflib.get_close_matches(name, list(known), n=3)
        hint = f"; did you mean {', '.join(near)}?" if near else f" (parameters: {', '.join(known)})"
        raise ParameterError(f"{what} {name!r} is not a parameter of {scene}{hint}")


class FileScene:
    """A model file seen as a preset module: ``build``, ``DEFAULTS``, ``UNITS``, ``OUTPUTS``."""

    SWITCHES = {}

    def __init__(self, path):
        from ..modelfile import read_model_file

        self.path = path
        self.NAME = str(path)  # how errors name the scene
        self.model, run = read_model_file(path)
        self.DESCRIPTION = f"model file {path}"
        self.DEFAULTS = dict(self.model.parameters)
        self.UNITS = dict(self.model.parameter_units)
        self.OUTPUTS = dict(run)
        if "orbit_station" not in run and "bending" not in run:  # default figures: the first disk's station
            from ..elements import Disk

            station = next((e.station for e in self.model.elements if isinstance(e, Disk)), self.model.stations[0])
            self.OUTPUTS.update(orbit_station=station, bending=f"x{station}")

    def build(self, **overrides):
        for name in overrides:
            check_parameter_name(name, self.DEFAULTS, self.path)
        return self.model.with_values(**overrides) if overrides else self.model


def scene_module(args):
    """The preset module, or a :class:`FileScene`, for ``args.preset``.

    For a model file, ``args.preset`` becomes the file's stem (used in output
    folder names) and ``args.scene_path`` keeps the path.
    """
    from pathlib import Path

    from ..presets import list_presets, preset_module

    scene = args.preset
    if scene in list_presets() or not is_model_file(scene):
        try:
            return preset_module(scene)
        except ParameterError as err:
            raise ParameterError(f"{err}; or give the path of a model file (.toml)") from None
    path = Path(scene)
    module = FileScene(path)
    args.scene_path, args.preset = path, path.stem
    return module


def load_preset(args):
    """(preset module or :class:`FileScene`, model, overrides) for ``args.preset`` with ``args.set`` applied."""
    module = scene_module(args)
    from ..presets import build_preset

    overrides = parse_overrides(args, {**module.DEFAULTS, **getattr(module, "SWITCHES", {})})
    return module, build_preset(module, overrides), overrides


def parse_overrides(args, known):
    """``args.set`` as {name: value}: each a known parameter, given once."""
    overrides = {}
    for text in args.set:
        name, value = parse_assignment(text, known)
        check_parameter_name(name, known, args.preset)
        if name in overrides:
            raise ParameterError(f"--set {name} is given twice; give each parameter once")
        overrides[name] = value
    return overrides


#: the same function under the name that says what it does
load_scene = load_preset
