"""Work-precision diagram: error against wall time, one line per engine and method."""

import numpy as np

from .basic import new_axes

__all__ = ["plot_work_precision", "plot_error_growth"]


def plot_work_precision(runs, signal, kind="spectral", ax=None):
    """Error (``kind``: ``"pointwise"`` or ``"spectral"``) of ``signal`` against wall time, log-log.

    Parameters
    ----------
    runs : sequence of rotorkit.accuracy.AccuracyRun
    signal : str
    kind : {"pointwise", "spectral"}
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax, figsize=(6.0, 4.5))
    cases = []
    for run in runs:
        if (run.engine, run.method) not in cases:
            cases.append((run.engine, run.method))
    for engine, method in cases:
        pts = [r for r in runs if (r.engine, r.method) == (engine, method) and r.success]
        if not pts:
            continue
        wall = np.array([r.wall_time for r in pts])
        err = np.array([getattr(r, kind)[signal] for r in pts])
        style = "-o" if engine == "compiled" else "--s"
        line, = ax.loglog(wall, np.maximum(err, 1e-16), style, ms=4, label=f"{method} ({engine})")
        for r, w, e in zip(pts, wall, err):
            ax.annotate(f"{r.rtol:.0e}", (w, max(e, 1e-16)), fontsize=6, color=line.get_color(),
                        xytext=(3, 2), textcoords="offset points")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel(f"{kind} relative error of {signal}")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    return ax


def plot_error_growth(results, reference, signal, ax=None):
    """|s(t) - s_ref(t)| over time for a few runs (labels -> Result): pointwise errors grow in rub."""
    ax = new_axes(ax, figsize=(6.0, 4.5))
    r = reference[signal]
    scale = np.abs(r).max()
    for label, res in results.items():
        err = np.abs(res[signal] - r) / scale
        # running maximum over 0.05 s blocks keeps the figure light and readable
        n = max(1, int(0.05 * res.sample_rate))
        m = len(err) // n * n
        ax.semilogy(res.t[:m:n], np.maximum(err[:m].reshape(-1, n).max(axis=1), 1e-16), label=label)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"|{signal} - reference| / max|reference|")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    return ax
