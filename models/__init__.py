"""Bundled presets: models built from rotorkit's public elements.

Each module defines ``build(**overrides) -> rotorkit.Model``, a ``DEFAULTS``
mapping (override name -> SI value) and a ``DESCRIPTION``.
"""
