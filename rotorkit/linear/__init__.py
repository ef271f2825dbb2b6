"""Linear analyses of a model or of matrices ``M, C + W G, K + W H``.

One module for each analysis, each with one entry (the entries the user reaches for
first are also importable from :mod:`rotorkit` itself: ``rk.campbell``,
``rk.unbalance_response``, ...):

- :func:`linear_model`, :class:`LinearModel` (:mod:`~rotorkit.linear.linear_model`): the
  matrices of a model, exact at every speed; built on :mod:`~rotorkit.linear.linear_matrices`
  (the symbolic or cached numeric assembly; spin speeds in :mod:`~rotorkit.linear.rotor_speeds`,
  station positions in :mod:`~rotorkit.linear.station_positions`) and :mod:`~rotorkit.linear.linearize`
  (:func:`static_equilibrium` and :func:`linearize` of a compiled system);
- :func:`natural_frequencies` (:mod:`~rotorkit.linear.modes`): the modes of a compiled system at its
  operating point, as :class:`Modes` (:mod:`~rotorkit.linear.modal`: eigen-solutions;
  :mod:`~rotorkit.linear.modal_result`: the result, its tables; whirl from :mod:`~rotorkit.linear.whirl`);
- :func:`campbell` (:mod:`~rotorkit.linear.campbell`): Campbell and stability diagrams (the result in
  :mod:`~rotorkit.linear.campbell_result`, the modes at each speed in :mod:`~rotorkit.linear.speed_modes`);
- :func:`critical_speed_map` (:mod:`~rotorkit.linear.critical_map`);
- :func:`unbalance_response` (:mod:`~rotorkit.linear.unbalance`) and :func:`frequency_response`
  (:mod:`~rotorkit.linear.frf`), both solved by :mod:`~rotorkit.linear.harmonic`;
- :func:`static_deflection` (:mod:`~rotorkit.linear.static`): deflection and bearing reactions.

Helpers: :mod:`~rotorkit.linear.roots` (root bracketing, mode assignment between speeds),
:mod:`~rotorkit.linear.tables` (CSV output of result tables).

These modules lived in :mod:`rotorkit.analysis` before; the old import paths
(``rotorkit.analysis.campbell`` and so on) still give the same modules.

This ``__init__`` imports nothing: importing one analysis (or one helper, as the
plotting functions import :mod:`~rotorkit.linear.whirl`) loads only what it
needs, and the package's functions do not shadow its modules of the same name
(``campbell``, ``linear_model``, ``linearize``).
"""

__all__ = []
