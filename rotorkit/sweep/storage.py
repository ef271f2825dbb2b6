"""Where a sweep lands: a manifest, one file per point, and a labelled dataset.

Files in ``out_dir``::

    sweep.json        the manifest: scene, space, settings (everything that
                      decides a point's result)
    points/p000000.npz  one file per point, written atomically by the calling
                      process as the point's result arrives (``.npz`` without
                      pickles: ``meta`` JSON, ``frequency``, ``amplitude``,
                      ``order_amplitude``, ``poincare``)
    sweep.nc          the whole sweep as a netCDF-4 file (an
                      ``xarray.Dataset``, CF-style ``units``/``long_name``
                      attributes), written when the sweep ends

The point files are the crash-safe store: a killed sweep keeps every point
that finished, and a rerun skips them. ``sweep.nc`` is the self-describing
result for users and other tools; :func:`load_sweep` builds the same Dataset
from the point files (so it also works on an unfinished sweep).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import math
from pathlib import Path

import numpy as np

from ..errors import ParameterError

__all__ = ["load_sweep", "point_path", "MANIFEST_NAME", "DATASET_NAME", "STATUSES"]

MANIFEST_NAME = "sweep.json"
DATASET_NAME = "sweep.nc"
MANIFEST_FORMAT = "rotorkit-sweep-2"
POINT_FORMAT = "rotorkit-sweep-point-2"

#: ``ok`` (spectrum stored), ``failed`` (the integration raised, or the worker died every try),
#: ``runaway`` (displacement past the runaway limit), ``missing`` (no valid file yet)
STATUSES = ("ok", "failed", "runaway", "missing")

_ARRAYS = ("frequency", "amplitude", "order_amplitude", "poincare")


def point_path(out_dir, index):
    """Path of the file of point ``index`` in ``out_dir``."""
    return Path(out_dir) / "points" / f"p{int(index):06d}.npz"


def json_default(value):
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


def fingerprint(manifest):
    text = json.dumps(manifest, sort_keys=True, default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def write_point(out_dir, fingerprint_, result):
    from ..files import atomic_write_bytes

    meta = {**result["meta"], "format": POINT_FORMAT, "fingerprint": fingerprint_}
    buf = io.BytesIO()
    np.savez(buf, meta=np.array(json.dumps(meta, default=json_default)),
             **{k: np.asarray(result["arrays"][k], dtype=float) for k in _ARRAYS})
    path = point_path(out_dir, result["index"])
    path.parent.mkdir(parents=True, exist_ok=True)
    # no fsync per point (it cost more than the rest of storing): read_point recomputes a point whose file a power
    # cut left empty or truncated, and a killed process leaves each file whole or absent (rename)
    atomic_write_bytes(path, buf.getvalue(), durable=False)


def read_point(out_dir, index, fingerprint_, point, shapes):
    """(meta, arrays) of a valid point file of this sweep, or None (missing, damaged or another sweep's)."""
    try:
        from ..files import open_data

        with open_data(point_path(out_dir, index), what="sweep point") as fh, np.load(fh, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            arrays = {k: np.array(data[k], dtype=float) for k in _ARRAYS}
    except Exception:  # missing, truncated or foreign: whatever it is, the point is recomputed
        return None
    if not isinstance(meta, dict) or meta.get("format") != POINT_FORMAT or meta.get("fingerprint") != fingerprint_:
        return None
    if meta.get("index") != index or meta.get("status") not in STATUSES[:3]:
        return None
    got = meta.get("point")
    if not isinstance(got, dict) or set(got) != set(point):
        return None
    if not all(math.isclose(float(got[k]), v, rel_tol=1e-12, abs_tol=0.0) for k, v in point.items()):
        return None
    n_freq = arrays["frequency"].size
    expected = {"amplitude": (shapes["signal"], n_freq), "order_amplitude": (shapes["signal"], shapes["order"]),
                "poincare": (shapes["poincare_signal"], shapes["revolution"])}
    if any(arrays[k].shape != v for k, v in expected.items()):
        return None
    if meta["status"] == "ok" and (n_freq < 2 or not np.all(np.isfinite(arrays["amplitude"]))):
        return None
    return meta, arrays


def read_manifest(out_dir):
    from ..files import check_path, read_data

    path = check_path(out_dir, "out_dir") / MANIFEST_NAME
    try:
        manifest = json.loads(read_data(path, what="sweep manifest").decode("utf-8"))
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{out_dir} is not a sweep folder: cannot read {MANIFEST_NAME} ({exc})") from None
    if not isinstance(manifest, dict) or manifest.get("format") != MANIFEST_FORMAT:
        raise ParameterError(f"{path}: not a rotorkit sweep manifest (format "
                             f"{manifest.get('format') if isinstance(manifest, dict) else None!r})")
    return manifest


def _differences(old, new, prefix=""):
    out = []
    for key in sorted(set(old) | set(new)):
        a, b = old.get(key), new.get(key)
        if a == b:
            continue
        if isinstance(a, dict) and isinstance(b, dict):
            out.extend(_differences(a, b, f"{prefix}{key}."))
            continue
        a, b = (json.dumps(v, default=json_default) for v in (a, b))
        a, b = (s if len(s) < 80 else s[:77] + "..." for s in (a, b))
        out.append(f"{prefix}{key}: {a} there, {b} here")
    return out


def check_manifest(out_dir, manifest):
    """True if ``out_dir`` holds this sweep's manifest, False if none; raises for another sweep's."""
    from ..files import read_data

    path = Path(out_dir) / MANIFEST_NAME
    if not os.path.lexists(path):
        return False
    try:
        old = json.loads(read_data(path, what="sweep manifest").decode("utf-8"))
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{path} is unreadable ({exc}); delete it (or the folder) to start the sweep over") \
            from None
    if not isinstance(old, dict) or not {"format", "scene", "space", "settings"} <= set(old):
        raise ParameterError(f"{path} is damaged: not a rotorkit sweep manifest (expected a JSON object with format, "
                             "scene, space and settings); delete it (or the folder) to start the sweep over")
    if old != manifest:
        diffs = "; ".join(_differences(old if isinstance(old, dict) else {}, manifest))
        raise ParameterError(
            f"{out_dir} holds a different sweep ({diffs}); resuming needs the same scene, parameters, values and "
            "settings. Use another out_dir, or delete the folder to start over"
        )
    return True


def write_manifest(out_dir, manifest):
    from ..files import atomic_write_text

    Path(out_dir).mkdir(parents=True, exist_ok=True)
    atomic_write_text(Path(out_dir) / MANIFEST_NAME, json.dumps(manifest, indent=2, default=json_default) + "\n")


def signal_units(name):
    """SI unit of a state signal or a difference of two (``x2`` m, ``alpha2-alpha5`` rad, ``x1_dot`` m/s)."""
    base = name.split("-", 1)[0].strip()
    dot = base.endswith("_dot")
    angle = base.startswith(("alpha", "theta", "phi", "psi"))
    unit = "rad" if angle else "m"
    return f"{unit}/s" if dot else unit


def shapes_of(manifest):
    s = manifest["settings"]
    return {"signal": len(s["signals"]), "order": len(s["orders"]), "poincare_signal": len(s["poincare_signals"]),
            "revolution": s["poincare_revolutions"]}


def load_sweep(out_dir):
    """The sweep in ``out_dir`` as an :class:`xarray.Dataset` (from its point files).

    Dimensions: one per parameter for a grid (coordinates: the parameter
    values), or ``point`` for a list or Latin hypercube (each parameter a
    coordinate along ``point``); ``signal``, ``frequency`` (rad/s), ``order``,
    ``poincare_signal``, ``revolution``. Variables: ``amplitude``,
    ``order_amplitude``, ``poincare``, ``status`` (``ok``, ``failed``,
    ``runaway``, ``missing``), ``failure_time``, ``max_displacement``,
    ``energy_residual``, ``message``, ``nfev``, ``wall_time``. Every variable
    and coordinate has CF-style ``units`` and ``long_name`` attributes. Points
    without a valid file are ``missing``, their values NaN.

    Raises
    ------
    ParameterError
        No readable ``sweep.json``, or points with different frequency grids.

    Examples
    --------
    ``ds.order_amplitude.sel(signal="x2", order="1/2").plot()`` draws a map
    of the 1/2-order amplitude over a 2-D grid (see docs/sweeps.md).
    """
    import xarray as xr

    from .space import space_from_description

    out_dir = Path(out_dir)
    manifest = read_manifest(out_dir)
    space = space_from_description(manifest["space"])
    s = manifest["settings"]
    shapes = shapes_of(manifest)
    fp = fingerprint(manifest)
    n = space.size
    status = np.full(n, "missing", dtype=object)
    failure_time, max_disp, energy = (np.full(n, np.nan) for _ in range(3))
    nfev, wall = np.full(n, np.nan), np.full(n, np.nan)
    messages = np.full(n, "no valid point file yet", dtype=object)
    order_amp = np.full((n, shapes["signal"], shapes["order"]), np.nan)
    poincare = np.full((n, shapes["poincare_signal"], shapes["revolution"]), np.nan)
    frequency, spectra, spectrum_info = None, {}, None
    for i in range(n):
        found = read_point(out_dir, i, fp, space.point(i), shapes)
        if found is None:
            continue
        meta, arrays = found
        status[i], messages[i] = meta["status"], meta.get("message") or ""
        for arr, key in ((failure_time, "time"), (max_disp, "max_displacement"), (energy, "energy_residual")):
            if meta.get(key) is not None:
                arr[i] = float(meta[key])
        stats = meta.get("stats") or {}
        nfev[i] = stats.get("nfev", np.nan) if isinstance(stats.get("nfev"), (int, float)) else np.nan
        wall[i] = stats.get("point_wall_time", np.nan)
        order_amp[i], poincare[i] = arrays["order_amplitude"], arrays["poincare"]
        if meta["status"] != "ok":
            continue
        freq = arrays["frequency"]
        if frequency is None:
            frequency, spectrum_info = freq, meta.get("spectrum")
        elif freq.shape != frequency.shape or not np.allclose(freq, frequency, rtol=1e-9, atol=0.0):
            raise ParameterError(f"{point_path(out_dir, i)}: its frequency grid differs from the other points' "
                                 f"({freq.size} vs {frequency.size} bins); all points must share the sample rate "
                                 "and window")
        spectra[i] = arrays["amplitude"]
    if frequency is None:
        frequency = np.empty(0)
    amplitude = np.full((n, shapes["signal"], frequency.size), np.nan)
    for i, a in spectra.items():
        amplitude[i] = a

    dims, shape = tuple(space.dims), tuple(space.shape)
    units = manifest.get("parameter_units", {})

    def grid(a):
        return a.reshape(shape + a.shape[1:])

    coords = {}
    if manifest["space"]["kind"] == "grid":
        for name in space.names:
            coords[name] = (name, np.array(space.axes[name]),
                            {"units": units.get(name, "") or "1", "long_name": name.replace("_", " ")})
    else:
        coords["point"] = ("point", np.arange(n), {"long_name": "point index"})
        for j, name in enumerate(space.names):
            coords[name] = ("point", space.table[:, j],
                            {"units": units.get(name, "") or "1", "long_name": name.replace("_", " ")})
    signals = s["signals"]
    coords["signal"] = ("signal", np.array(signals, dtype=object), {"long_name": "output signal"})
    coords["signal_units"] = ("signal", np.array([signal_units(x) for x in signals], dtype=object),
                              {"long_name": "unit of each signal"})
    coords["frequency"] = ("frequency", frequency, {"units": "rad/s", "long_name": "angular frequency"})
    coords["order"] = ("order", np.array(s["orders"], dtype=object), {"long_name": "speed order"})
    coords["poincare_signal"] = ("poincare_signal", np.array(s["poincare_signals"], dtype=object),
                                 {"long_name": "signal sampled once per revolution"})
    coords["poincare_units"] = ("poincare_signal", np.array([signal_units(x) for x in s["poincare_signals"]],
                                                            dtype=object), {"long_name": "unit of each signal"})
    coords["revolution"] = ("revolution", np.arange(-shapes["revolution"] + 1, 1),
                            {"long_name": "revolution before the end of the window", "units": "1"})
    amp_units = "/".join(sorted({signal_units(x) for x in signals})) or "1"
    data = {
        "amplitude": (dims + ("signal", "frequency"), grid(amplitude),
                      {"units": amp_units, "long_name": "amplitude spectrum (high-passed, windowed)",
                       "comment": "unit per signal in the signal_units coordinate"}),
        "order_amplitude": (dims + ("signal", "order"), grid(order_amp),
                            {"units": amp_units, "long_name": "peak amplitude at the speed order"}),
        "poincare": (dims + ("poincare_signal", "revolution"), grid(poincare),
                     {"units": "/".join(sorted({signal_units(x) for x in s["poincare_signals"]})) or "1",
                      "long_name": "once-per-revolution samples"}),
        "status": (dims, grid(status.astype(str)), {"long_name": "point status (ok, failed, runaway, missing)"}),
        "message": (dims, grid(messages.astype(str)), {"long_name": "why a point failed or ran away"}),
        "failure_time": (dims, grid(failure_time), {"units": "s", "long_name": "time the run failed or ran away"}),
        "max_displacement": (dims, grid(max_disp), {"units": "m", "long_name": "largest radial displacement"}),
        "energy_residual": (dims, grid(energy), {"units": "1", "long_name": "relative energy-balance residual"}),
        "nfev": (dims, grid(nfev), {"units": "1", "long_name": "right-hand side evaluations"}),
        "wall_time": (dims, grid(wall), {"units": "s", "long_name": "wall time of the point"}),
    }
    attrs = {"Conventions": "CF-1.8", "title": f"rotorkit sweep of {manifest['scene_name']}",
             "scene": manifest["scene_name"], "window": list(s["window"]), "t_end": s["t_end"],
             "highpass_hz": s["highpass_hz"] if s["highpass_hz"] is not None else "none",
             "parameters": list(space.names), "space_kind": manifest["space"]["kind"],
             "manifest": json.dumps(manifest, default=json_default),
             "spectrum": json.dumps(spectrum_info, default=json_default)}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def write_dataset(out_dir, dataset):
    """Write ``dataset`` as ``out_dir/sweep.nc`` (netCDF-4, through the netCDF4 library), atomically."""
    import os
    import tempfile

    path = Path(out_dir) / DATASET_NAME
    fd, tmp = tempfile.mkstemp(prefix=".sweep-", suffix=".nc", dir=out_dir)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        dataset.to_netcdf(tmp, engine="netcdf4", format="NETCDF4")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path
