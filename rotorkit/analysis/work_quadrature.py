"""Work of sampled power: the piecewise-cubic quadrature of the energy balance, with kinks and time events.

Each sample interval integrates the cubic through the 4 samples around it (fourth order; ``(-1, 13, 13, -1) h / 24``
on a uniform grid). Where a contact switch changes sign between two samples (a kink or jump of the power), the
interval is split at the interpolated crossing and each part, like its neighbours, uses samples of its own side
only; at time events the integration is split into segments (:func:`cumulative_work`). Used by
:mod:`rotorkit.analysis.energy`, whose docstring gives the method and its error bound (:func:`quadrature_error`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CHUNK", "Piece", "rule", "apply_rule", "kinks_of", "segment_work", "cumulative_work", "quadrature_error"]

#: rows of quadrature systems (and samples of lambdified functions) handled per call: bounds the memory
CHUNK = 32768

_UNIFORM_WEIGHTS = {
    (-1.0, 0.0, 1.0, 2.0): np.array([-1.0, 13.0, 13.0, -1.0]) / 24.0,
    (0.0, 1.0, 2.0, 3.0): np.array([9.0, 19.0, -5.0, 1.0]) / 24.0,
    (-2.0, -1.0, 0.0, 1.0): np.array([1.0, -5.0, 19.0, 9.0]) / 24.0,
}


def rule(t, lo, hi, start, count):
    """A quadrature rule: ``(idx, w)`` of shape (k, 4) such that ``sum_j w[i, j] f[idx[i, j]]``
    integrates over ``[lo[i], hi[i]]`` the polynomial through the ``count[i]`` (1..4) samples
    ``start[i] ..`` of ``f`` (extrapolated where the interval lies outside them)."""
    k = len(lo)
    idx = np.repeat(np.asarray(start)[:, None], 4, axis=1)
    w = np.zeros((k, 4))
    width = hi - lo
    scale = np.where(width > 0, width, 1.0)
    for m in np.unique(count):
        m = int(m)
        powers = np.arange(m)
        rows_m = np.flatnonzero(count == m)
        for s in range(0, rows_m.size, CHUNK):  # chunks bound the memory of the (k, m, m) systems
            rows = rows_m[s:s + CHUNK]
            cols = start[rows, None] + powers[None, :]
            nodes = (t[cols] - lo[rows, None]) / scale[rows, None]  # the interval maps to [0, 1]
            weights = np.empty((rows.size, m))
            todo = np.ones(rows.size, dtype=bool)
            if m == 4:  # equally spaced samples (the usual case): known weights
                for pattern, known in _UNIFORM_WEIGHTS.items():
                    hit = np.all(np.abs(nodes - np.array(pattern)) < 1e-9, axis=1)
                    weights[hit] = known
                    todo &= ~hit
            if np.any(todo):
                vander = nodes[todo][:, None, :] ** powers[None, :, None]  # (k, power, node)
                moments = np.broadcast_to(1.0 / (powers + 1.0), (int(todo.sum()), m))[..., None]
                weights[todo] = np.linalg.solve(vander, moments)[..., 0]
            idx[rows, :m] = cols
            w[rows, :m] = width[rows, None] * weights
    return idx, w


def apply_rule(weights, f):
    """``sum_j w[i, j] f[idx[i, j]]`` for a rule ``(idx, w)`` of :func:`rule`: one integral per row."""
    idx, w = weights
    return np.einsum("kj,kj->k", w, f[idx])


def kinks_of(t, switches):
    """(intervals, times): the sample intervals in which a contact switch changes sign,
    and the time of the change (linear interpolation of the switch's argument)."""
    none = (np.empty(0, dtype=int), np.empty(0))
    if switches.shape[0] == 0 or t.size < 2:
        return none
    on = switches > 0.0
    change = on[:, 1:] != on[:, :-1]
    j = np.flatnonzero(change.any(axis=0))
    if j.size == 0:
        return none
    which = np.argmax(change[:, j], axis=0)
    a0, a1 = switches[which, j], switches[which, j + 1]
    with np.errstate(all="ignore"):
        frac = np.clip(np.nan_to_num(a0 / (a0 - a1), nan=0.5), 0.0, 1.0)
    return j, t[j] + frac * (t[j + 1] - t[j])


def _stencils(n, kinks):
    """Per interval ``j`` of ``n`` samples: the first and last sample on its side of
    the neighbouring kinks (``first[j] <= j < j + 1 <= last[j]`` off kinks)."""
    m = n - 1
    j = np.arange(m)
    is_kink = np.zeros(m, dtype=bool)
    is_kink[kinks] = True
    last_left = np.maximum.accumulate(np.where(is_kink, j, -1))
    kink_left = np.concatenate(([-1], last_left[:-1]))  # last kink interval < j
    first_right = np.minimum.accumulate(np.where(is_kink, j, m)[::-1])[::-1]
    kink_right = np.concatenate((first_right[1:], [m]))  # first kink interval > j (m: none)
    return kink_left + 1, kink_right  # samples kink_left + 1 .. kink_right are on one side


def _segment_rule(t, kinks):
    """The rule integrating each sample interval of one segment (see :func:`segment_work`).

    Returns ``(main, split)``: ``main`` a rule per interval; ``split`` ``None`` or
    ``(k, left, right)``, the kink intervals ``k`` and the rules of their parts.
    """
    n = t.size
    j = np.arange(n - 1)
    first, last = _stencils(n, kinks[0])
    count = np.minimum(4, last - first + 1)
    start = np.clip(j - 1, first, last - count + 1)
    main = rule(t, t[:-1], t[1:], start, count)
    k, tk = kinks
    if not k.size:
        return main, None
    left = np.minimum(4, k - first[k] + 1)  # samples first .. k
    right = np.minimum(4, last[k] - k)  # samples k + 1 .. last
    return main, (k, rule(t, t[k], tk, k - left + 1, left), rule(t, tk, t[k + 1], k + 1, right))


def segment_work(t, fs, kinks):
    """Cumulative integrals of each of ``fs`` over the samples ``t`` (all (n,)), from 0.

    Each interval integrates the cubic through the 4 samples around it; near a
    kink of the power (``kinks``: intervals and times) the stencil takes only
    samples on the interval's side, and a kink's own interval is split at the
    kink and each part integrated with its side's samples.
    """
    n = t.size
    if n < 2:
        return [np.zeros(n) for _ in fs]
    main, split = _segment_rule(t, kinks)
    out = []
    for f in fs:
        pieces = apply_rule(main, f)
        if split is not None:
            k, left, right = split
            pieces[k] = apply_rule(left, f) + apply_rule(right, f)
        out.append(np.concatenate(([0.0], np.cumsum(pieces))))
    return out


def _edge_work(t, f, kinks, lo, hi, at_start):
    """Integral of the segment's interpolant over ``[lo, hi]`` beyond its first or last sample."""
    if hi <= lo or t.size == 0:
        return 0.0
    k = kinks[0]
    if at_start:
        m = min(4, int(k[0]) + 1 if k.size else t.size)
        start = 0
    else:
        m = min(4, t.size - 1 - int(k[-1]) if k.size else t.size)
        start = t.size - m
    edge = rule(t, np.array([lo]), np.array([hi]), np.array([start]), np.array([m]))
    return float(apply_rule(edge, f)[0])


@dataclass
class Piece:
    """Samples of one segment between time events, evaluated as the solver saw them."""

    idx: np.ndarray  # sample indices (boundary samples shared with the neighbours)
    powers: dict  # name -> power at those samples
    kinks: tuple  # (interval indices within the segment, times)


def cumulative_work(t, pieces, cuts, names):
    """Cumulative work (J) of each named power channel over the samples, segment by segment."""
    work = {name: np.zeros(t.size) for name in names}
    prev = None
    for (a, _), piece in zip(zip(cuts[:-1], cuts[1:]), pieces):
        if piece.idx.size == 0:
            continue
        ts = t[piece.idx]
        cumulative = segment_work(ts, [piece.powers[name] for name in names], piece.kinks)
        for name, w in zip(names, cumulative):
            base = 0.0
            if prev is not None:
                base = work[name][prev.idx[-1]]
                if ts[0] > t[prev.idx[-1]]:  # the event lies between two samples: integrate each side
                    base += _edge_work(t[prev.idx], prev.powers[name], prev.kinks, t[prev.idx[-1]], a,
                                       at_start=False)
                    base += _edge_work(ts, piece.powers[name], piece.kinks, a, ts[0], at_start=True)
            work[name][piece.idx] = base + w
        prev = piece
    return work


def quadrature_error(t, pieces, switches, cuts, total):
    """max |W - W'| where W' integrates every second sample (segment boundaries kept)."""
    keep = np.zeros(t.size, dtype=bool)
    keep[::2] = True
    keep[-1] = True
    for piece in pieces:
        if piece.idx.size:
            keep[piece.idx[0]] = keep[piece.idx[-1]] = True
    sub = np.flatnonzero(keep)
    if sub.size < 3 or sub.size == t.size:
        return 0.0
    remap = -np.ones(t.size, dtype=int)
    remap[sub] = np.arange(sub.size)
    coarse = []
    for piece in pieces:
        mask = keep[piece.idx]
        idx = piece.idx[mask]
        summed = sum(piece.powers.values(), np.zeros(piece.idx.size))[mask]
        coarse.append(Piece(idx=remap[idx], powers={"all": summed}, kinks=kinks_of(t[idx], switches[:, idx])))
    w = cumulative_work(t[sub], coarse, cuts, ["all"])["all"]
    return float(np.max(np.abs(total[sub] - w)))
