"""The memory a process can still use: sizes runs and result files before they are allocated."""

import os

__all__ = ["available_memory"]


def available_memory():
    """Bytes of memory free now (Linux/macOS sysconf), or None if unknown."""
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return None
