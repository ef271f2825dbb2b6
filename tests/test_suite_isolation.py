"""The test suite never touches the user's model cache (tests/conftest.py sets a temporary one)."""

import os
from pathlib import Path

from rotorkit.codegen import cache


def test_model_cache_is_temporary(temporary_model_cache, tmp_path_factory):
    folder = cache.cache_dir().resolve()
    assert folder == Path(temporary_model_cache).resolve()
    assert Path(tmp_path_factory.getbasetemp()).resolve() in folder.parents
    assert Path(os.path.expanduser("~/.cache/rotorkit")).resolve() not in (folder, *folder.parents)
