"""Shared test helpers (imported by path, tests are not a package)."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def load_handwritten():
    """The independent hand-written AL-31F reference in bench/."""
    spec = importlib.util.spec_from_file_location("al31f_handwritten", ROOT / "bench" / "al31f_handwritten.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
