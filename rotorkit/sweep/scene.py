"""The scene of a sweep: a description from which a worker rebuilds the model.

A worker never receives a closure or a compiled system: it receives a
:class:`Scene` (plain data) and the point's parameter values, rebuilds the
model with :meth:`Scene.build` and compiles it from the on-disk model cache
(generated source, derived once per structure). Three kinds of scene:

- a bundled preset by name, with overrides (``Scene.preset("al31f", rub_clearance=1.3e-4)``);
- a module-level build function ``build(**parameters) -> Model``, imported by
  module and name (or from its file) in the worker;
- a :class:`~rotorkit.Model` built in Python from its elements (frozen
  dataclasses: picklable data), whose parameters (``rub1_contact_stiffness``)
  are set per point with :meth:`Model.with_values`.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import math
import numbers
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import ArgumentTypeError, ParameterError

__all__ = ["Scene", "as_scene"]


def _is_quantity(value):
    return hasattr(value, "magnitude") and hasattr(value, "units") and hasattr(value, "dimensionality")


def plain_override(name, value):
    """An override as JSON-able plain data (pint quantities as magnitude and unit)."""
    if isinstance(value, (bool, str)) or value is None:
        return value
    if isinstance(value, numbers.Real):
        value = value.item() if hasattr(value, "item") else value
        if isinstance(value, float) and not math.isfinite(value):
            raise ParameterError(f"overrides[{name!r}] = {value!r} is not finite")
        return value
    if _is_quantity(value):
        magnitude = value.magnitude
        if not isinstance(magnitude, numbers.Real):
            raise ParameterError(f"overrides[{name!r}] = {value!r}: expected a scalar quantity")
        return {"quantity": float(magnitude), "unit": str(value.units)}
    raise ArgumentTypeError(
        f"overrides[{name!r}] = {value!r} ({type(value).__name__}): expected a number, bool, string or pint "
        "quantity (overrides are sent to worker processes and saved in sweep.json)"
    )


def revive_override(value):
    if isinstance(value, dict) and set(value) == {"quantity", "unit"}:
        from ..units import registry

        return registry().Quantity(value["quantity"], value["unit"])
    return value


_BUILDERS = {}  # target key -> build function, per process


def _load_file_module(name, file):
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def _import_build(target):
    module = None
    try:
        module = importlib.import_module(target["module"])
        if target["file"] and Path(getattr(module, "__file__", "") or "").resolve() != Path(target["file"]).resolve():
            module = None
    except ImportError:
        module = None
    if module is None:
        if not target["file"]:
            raise ImportError(f"cannot import the build function {target['module']}:{target['qualname']}")
        digest = hashlib.sha256(target["file"].encode()).hexdigest()[:12]
        module = _load_file_module(f"_rotorkit_sweep_build_{digest}", target["file"])
    obj = module
    for part in target["qualname"].split("."):
        obj = getattr(obj, part)
    return obj


@dataclass(frozen=True, eq=False)
class Scene:
    """What a worker needs to rebuild a point's model: plain data, no closures.

    Use the constructors :meth:`preset`, :meth:`function` and :meth:`model`
    (or pass a preset name, a build function or a Model to
    :func:`~rotorkit.sweep.run_sweep`).

    Attributes
    ----------
    target : dict
        ``{"preset": name}``, ``{"module", "qualname", "file", "importable"}``
        of a build function, or ``{"model": name, "structure": key}``.
    overrides : dict
        Parameters fixed for every point, as plain data.
    model : rotorkit.Model or None
        The model of a ``model`` scene (elements: frozen dataclasses).
    """

    target: dict
    overrides: dict = field(default_factory=dict)
    model: object = None
    local: object = field(default=None, repr=False, compare=False)  # the build function, in the calling process
    run: dict = field(default_factory=dict)  # a model scene's OUTPUTS (t_end, bending, torsion), e.g. from its file

    @classmethod
    def preset(cls, name, **overrides):
        from ..presets import preset_module

        if not isinstance(name, str):
            raise ArgumentTypeError(f"preset={name!r}: expected a preset name")
        preset_module(name)  # unknown names fail here, with suggestions
        return cls({"preset": name}, _plain(overrides))

    @classmethod
    def function(cls, build, **overrides):
        if not callable(build):
            raise ArgumentTypeError(f"preset={build!r}: expected a preset name (str), a build(**parameters) -> Model "
                            "callable or a rotorkit.Model")
        module = getattr(build, "__module__", None)
        qualname = getattr(build, "__qualname__", None)
        file = getattr(sys.modules.get(module), "__file__", None) if isinstance(module, str) else None
        importable = isinstance(module, str) and isinstance(qualname, str) and "<" not in qualname
        target = {"module": module, "qualname": qualname, "file": file, "importable": importable}
        return cls(target, _plain(overrides), local=build)

    @classmethod
    def from_model(cls, model, outputs=None, **overrides):
        """A Model built from elements (or read from a model file; ``outputs``: its run settings)."""
        from ..model import Model

        if not isinstance(model, Model):
            raise ArgumentTypeError(f"model={model!r}: expected a rotorkit.Model")
        run = {k: v for k, v in dict(outputs or {}).items() if k in ("t_end", "bending", "torsion")}
        return cls({"model": model.name, "structure": model.structure_key}, _plain(overrides), model=model, run=run)

    @property
    def kind(self):
        return "preset" if "preset" in self.target else "model" if "model" in self.target else "function"

    @property
    def display(self):
        if self.kind == "preset":
            return self.target["preset"]
        if self.kind == "model":
            return f"model {self.target['model']!r}"
        return f"{self.target['module']}:{self.target['qualname']}"

    def describe(self):
        """Plain data for the manifest (a model scene: its structure and parameter values)."""
        out = {"kind": self.kind, **self.target, "overrides": self.overrides}
        if self.model is not None:
            out["parameters"] = {k: float(v) for k, v in self.model.parameters.items()}
        return out

    @property
    def outputs(self):
        """The preset's or build function's ``OUTPUTS`` (t_end, bending and torsion signals), or {}."""
        if self.kind == "preset":
            from ..presets import preset_module

            outputs = getattr(preset_module(self.target["preset"]), "OUTPUTS", None)
        elif self.kind == "function":
            build = self.local or self._builder()
            outputs = getattr(build, "OUTPUTS", None) or getattr(sys.modules.get(self.target["module"]), "OUTPUTS",
                                                                 None)
        else:
            outputs = self.run
        return outputs if isinstance(outputs, Mapping) else {}

    def parameter_names(self):
        """Names a point may set, or None if the build function does not say."""
        if self.kind == "preset":
            from ..presets import preset_module

            module = preset_module(self.target["preset"])
            return set(module.DEFAULTS) | set(getattr(module, "SWITCHES", {}))
        if self.kind == "model":
            return set(self.model.parameters)
        return None

    def parameter_units(self):
        """Parameter name -> SI unit string (from the preset's or build function's ``UNITS``, or the elements)."""
        if self.kind == "model":
            return {f"{e.label()}_{f}": u for e in self.model.elements for f, u in e.parameter_units().items()}
        if self.kind == "preset":
            from ..presets import preset_module

            units = getattr(preset_module(self.target["preset"]), "UNITS", None)
        else:
            build = self.local or self._builder()
            units = getattr(build, "UNITS", None) or getattr(sys.modules.get(self.target["module"]), "UNITS", None)
        return dict(units) if isinstance(units, Mapping) else {}

    def _builder(self):
        if self.local is not None:
            return self.local
        key = repr(sorted(self.target.items()))
        if key not in _BUILDERS:
            if self.kind == "preset":
                from ..presets import preset_module

                _BUILDERS[key] = preset_module(self.target["preset"]).build
            else:
                _BUILDERS[key] = _import_build(self.target)
        return _BUILDERS[key]

    def build(self, point):
        """The model of one point (``point``: parameter name -> SI value)."""
        overrides = {k: revive_override(v) for k, v in self.overrides.items()}
        if self.kind == "model":
            return self.model.with_values(**overrides, **point) if overrides or point else self.model
        return self._builder()(**overrides, **point)

    def __getstate__(self):  # the local build function stays behind: workers import it
        return {"target": self.target, "overrides": self.overrides, "model": self.model, "local": None,
                "run": self.run}

    def __setstate__(self, state):
        for k, v in state.items():
            object.__setattr__(self, k, v)


def _plain(overrides):
    return {str(k): plain_override(k, v) for k, v in overrides.items()}


def as_scene(scene, overrides=None):
    """A :class:`Scene` from a Scene, a preset name, a build function or a Model (plus overrides)."""
    from ..model import Model

    if overrides is not None and not isinstance(overrides, Mapping):
        raise ArgumentTypeError(f"overrides={overrides!r}: expected a dict of build parameters")
    overrides = dict(overrides or {})
    if isinstance(scene, Scene):
        if overrides:
            return Scene(scene.target, {**scene.overrides, **_plain(overrides)}, scene.model, scene.local, scene.run)
        return scene
    if isinstance(scene, str):
        return Scene.preset(scene, **overrides)
    if isinstance(scene, Model):
        return Scene.from_model(scene, **overrides)
    return Scene.function(scene, **overrides)
