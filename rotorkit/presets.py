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
    return preset_module(name).build(**overrides)
