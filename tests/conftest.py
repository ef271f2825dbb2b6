import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # tests/helpers.py


@pytest.fixture(scope="session", autouse=True)
def temporary_model_cache(tmp_path_factory):
    """Every test (and every command it starts) uses a temporary model cache, never ~/.cache/rotorkit."""
    old = os.environ.get("ROTORKIT_CACHE_DIR")
    folder = tmp_path_factory.mktemp("rotorkit-cache")
    os.environ["ROTORKIT_CACHE_DIR"] = str(folder)
    yield folder
    if old is None:
        os.environ.pop("ROTORKIT_CACHE_DIR", None)
    else:
        os.environ["ROTORKIT_CACHE_DIR"] = old


@pytest.fixture(scope="session")
def handwritten():
    from helpers import load_handwritten

    return load_handwritten()


@pytest.fixture(autouse=True)
def close_pyplot_figures():
    """Plots drawn without ``ax=`` are pyplot figures: close them after each test (no figure piles up)."""
    yield
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")
