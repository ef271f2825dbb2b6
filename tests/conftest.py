import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # tests/helpers.py


@pytest.fixture(scope="session")
def handwritten():
    from helpers import load_handwritten

    return load_handwritten()
