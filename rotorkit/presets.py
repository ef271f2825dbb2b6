"""Bundled presets (the ``models/`` folder, installed as ``rotorkit.models``)."""

import difflib
import importlib
import importlib.util
import sys
from pathlib import Path

from .errors import ParameterError

__all__ = ["preset", "list_presets", "preset_module"]


def _models_dir():
    try:
        import rotorkit.models as models  # installed package

        return Path(next(iter(models.__path__)))
    except ImportError:  # source checkout: models/ beside the package
        return Path(__file__).resolve().parent.parent / "models"


def list_presets():
    """Names of the bundled presets."""
    return sorted(p.stem for p in _models_dir().glob("*.py") if not p.stem.startswith("_"))


def preset_module(name):
    """The module defining preset ``name`` (``build``, ``DEFAULTS``, ``DESCRIPTION``)."""
    names = list_presets()
    if name not in names:
        near = difflib.get_close_matches(str(name), names, n=3)
        hint = f"; did you mean {', '.join(near)}?" if near else ""
        raise ParameterError(f"unknown preset {name!r}{hint} (presets: {', '.join(names)})")
    module_name = f"rotorkit.models.{name}"
    if module_name in sys.modules:
        return sys.modules[module_name]
    try:
        return importlib.import_module(module_name)
    except ImportError:
        spec = importlib.util.spec_from_file_location(module_name, _models_dir() / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[module_name] = module
        spec.loader.exec_module(module)
        return module


def preset(name, **overrides):
    """Build a bundled preset model.

    Parameters
    ----------
    name : str
        Preset name, e.g. ``"al31f"``.
    **overrides
        Preset parameters (SI floats or pint quantities), e.g.
        ``rub_stiffness=2e6``; see the preset's ``DEFAULTS``.

    Returns
    -------
    rotorkit.Model

    Examples
    --------
    >>> m = preset("al31f", rub_stiffness=2e6)
    >>> len(m.coordinate_names)
    16
    """
    return build_preset(preset_module(name), overrides, name)


def build_preset(module, overrides, name=None):
    """``module.build(**overrides)``; an error caused by one override names that override.

    The preset turns its overrides into element fields (``rub_stiffness`` ->
    ``RubStator.contact_stiffness``); an element's error names its field, which
    the user never typed, so the override that triggers it alone is found and named.
    """
    from .errors import ParameterError

    try:
        return module.build(**overrides)
    except ParameterError as err:
        label = name or getattr(module, "NAME", None) or getattr(module, "__name__", "scene").rsplit(".", 1)[-1]
        for key, value in overrides.items():
            if key in str(err):
                raise
            try:
                module.build(**{key: value})
            except ParameterError:
                raise type(err)(f"{label}: override {key}={value!r} is refused: {err}") from err
        raise
