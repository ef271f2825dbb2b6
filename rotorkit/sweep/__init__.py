"""Parameter sweeps: n-D spaces of points, run on local processes or Dask, stored as a labelled dataset.

A sweep simulates a scene (a preset, a build function or a Model) at every
point of a parameter space (:class:`Grid`, :class:`PointList`,
:func:`latin_hypercube`) and stores per point the high-passed amplitude
spectra over a window, peak amplitudes of speed orders, once-per-revolution
(Poincare) samples, the largest displacement, the status with its time and
reason, solver statistics and (optionally) the energy-balance residual.

Modules, one concept each:

- :mod:`~rotorkit.sweep.space`: grids, point lists, Latin hypercubes (lazy, size-checked);
- :mod:`~rotorkit.sweep.scene`: the description a worker rebuilds a model from;
- :mod:`~rotorkit.sweep.point`: one point, from parameters to arrays;
- :mod:`~rotorkit.sweep.executors`: local processes, Dask, retries, progress;
- :mod:`~rotorkit.sweep.storage`: manifest, point files, the xarray Dataset and ``sweep.nc``;
- :mod:`~rotorkit.sweep.cascade`: a 1-D slice as a spectrum cascade;
- :mod:`~rotorkit.sweep.run`: :func:`run_sweep`.

Examples
--------
>>> parse_range("rub_stiffness=5e5:2e7:3")
('rub_stiffness', (500000.0, 10250000.0, 20000000.0))
>>> parse_range("friction_coefficient=0,0.1,0.2")
('friction_coefficient', (0.0, 0.1, 0.2))
"""

from .cascade import Cascade, load_cascade
from .executors import ProgressEvent, connect
from .point import parse_order, run_point
from .run import run_sweep
from .scene import Scene
from .space import MAX_POINTS, Grid, PointList, latin_hypercube, parse_range
from .storage import DATASET_NAME, MANIFEST_NAME, STATUSES, load_sweep, point_path

__all__ = ["run_sweep", "load_sweep", "load_cascade", "parse_range", "parse_order", "Grid", "PointList",
           "latin_hypercube", "Scene", "Cascade", "ProgressEvent", "connect", "point_path", "run_point",
           "STATUSES", "MANIFEST_NAME", "DATASET_NAME", "MAX_POINTS"]
