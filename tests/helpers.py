"""Shared test helpers (imported by path, tests are not a package)."""

import importlib.util
from dataclasses import dataclass
from pathlib import Path

from rotorkit.elements.base import Element, Terms

ROOT = Path(__file__).resolve().parents[1]


def load_bench(name):
    """The script ``bench/<name>.py`` as a module (neither bench/ nor tests/ is a package)."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "bench" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_handwritten():
    """The independent hand-written AL-31F reference in bench/."""
    return load_bench("al31f_handwritten")


@dataclass(frozen=True, slots=True, kw_only=True)
class Clamp(Element):
    """Test-local: a station tied to the ground in x, y and both tilts."""

    station: int = None
    stiffness: float = None
    _units = {"stiffness": ("N/m", "positive")}

    def attached_stations(self):
        return (self.station,)

    def requires(self):
        return ((self.station, "thx"), (self.station, "thy"))

    def grounds(self):
        return ((self.station, "x"), (self.station, "y")) + self.requires()

    def contribute(self, ctx):
        k = ctx.p["stiffness"]
        return Terms(potential=k * sum(ctx.coord(self.station, a)[0] ** 2 for a in ("x", "y", "thx", "thy")) / 2)
