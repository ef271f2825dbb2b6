"""Writing a result's table: CSV text or a file, the same for every linear analysis."""

from __future__ import annotations

__all__ = ["csv_output", "DEFAULT_TABLE_MODES"]

#: modes printed by a table unless ``n_modes`` says otherwise
DEFAULT_TABLE_MODES = 6


def csv_output(text, path=None):
    """``text`` itself when ``path`` is None, else write it to ``path`` (atomically) and return the Path."""
    if path is None:
        return text
    import os
    from pathlib import Path

    from ..errors import ParameterError
    from ..files import atomic_write_bytes

    if not isinstance(path, (str, os.PathLike)):
        raise ParameterError(f"path={path!r} is invalid: expected a file path (str or pathlib.Path) or None")
    path = Path(path)
    atomic_write_bytes(path, text.encode())
    return path
