"""Writing a result's table: CSV text or a file, the same for every linear analysis."""

from __future__ import annotations

__all__ = ["csv_output", "DEFAULT_TABLE_MODES"]

#: modes printed by a table unless ``n_modes`` says otherwise
DEFAULT_TABLE_MODES = 6


def csv_output(text, path=None):
    """``text`` itself when ``path`` is None, else write it to ``path`` (atomically) and return the Path.

    The one place the ``to_csv(path=None, *, units=...)`` methods of the
    linear results (:class:`~rotorkit.analysis.modal.Modes`,
    :class:`~rotorkit.analysis.campbell.Campbell`,
    :class:`~rotorkit.analysis.critical_map.CriticalSpeedMap`,
    :class:`~rotorkit.analysis.unbalance.UnbalanceResponse`,
    :class:`~rotorkit.analysis.static.StaticDeflection`) write through, and
    where their common arguments are described:

    Parameters
    ----------
    text : str
        The CSV text (header row first).
    path : str, os.PathLike or None
        Where to write; None returns the text.

    Returns
    -------
    str or pathlib.Path
        The text, or the path written.

    Notes
    -----
    A ``units`` argument of a ``to_csv`` (``"rad/s"``, ``"Hz"``, ``"rpm"`` or
    another angular speed; Hz and rpm count cycles) sets the speed and
    frequency columns, and their names carry it (``speed_rpm``,
    ``mode1_frequency_Hz``); ``length_units`` likewise for amplitudes.
    """
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
