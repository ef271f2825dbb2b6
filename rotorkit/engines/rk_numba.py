"""Compiled adaptive explicit Runge-Kutta integrator (numba back end).

The whole adaptive loop (stages, error control, step-size selection and
dense output at the requested times) runs in one numba-compiled function, so
the only per-step cost is the arithmetic and the calls of the compiled
right-hand side.

Right-hand side contract
------------------------
The right-hand side ("core") is a numba ``@njit`` function::

    @numba.njit
    def core(t, y, p, dydt):
        dydt[0] = y[1]
        dydt[1] = -p[0] * y[0]

``t`` is a float, ``y`` the state (read only by convention), ``p`` the
parameter vector and ``dydt`` the output array; all arrays are C-contiguous
``float64`` vectors (see `CORE_SIGNATURE`).  The core must write every entry
of ``dydt`` and must not keep references to the arrays.

Methods and error control
-------------------------
``"RK45"`` (Dormand-Prince 5(4), quartic dense output) and ``"DOP853"``
(Hairer's 8(5,3) with the 7th-order dense output) use the coefficients, the
error norms, the initial-step heuristic and the step-size controller of
:func:`scipy.integrate.solve_ivp` (scipy's ``rk.py``, ``common.py``,
``dop853_coefficients.py``), so step sequences and ``nfev`` match scipy up to
floating-point summation order.  One deliberate difference: a sample at ``t0``
is the initial state itself, so DOP853 skips the three dense-output stages
scipy spends on it (``nfev`` 3 lower when ``t_eval`` starts at ``t0`` and the
first step holds no other sample).  Samples that fall exactly on a step end
are that step's state, not an interpolated value.

Non-finite values
-----------------
A stage that yields a non-finite state or derivative is treated as a failed
step: it is retried with the step divided by 5 (the controller's minimum
factor, which is also what scipy does with a NaN error estimate).  The run
stops with status ``-2`` when the step can no longer shrink, so ``t_reached``
converges onto the time at which the core stops being finite.  A non-finite
initial derivative stops the run immediately.

Compilation and caching
-----------------------
The core is passed to the compiled loop as a first-class function
(``numba.types.FunctionType(CORE_SIGNATURE)``), not as a dispatcher type.  The
loop is therefore compiled once for all cores and both methods, and it can be
cached on disk: a new core only costs its own compilation. The disk cache is
kept in rotorkit's private cache folder, verified and signed like a model's
(:func:`rotorkit.codegen.cache.jit_shared`), never beside the package.
Passing the dispatcher itself (the alternative pattern) would make every core
a distinct type, recompile the loop for each model and defeat on-disk caching
because dispatcher types do not survive the process.  The loop is compiled (or
loaded from the cache) on the first call of `integrate`, not at import
(seconds cold, a fraction of that from the cache; ``bench/bench_core.py``).

Pieces
------
With ``pause_after`` the loop returns between two steps (status -4) with the
step size its controller proposes next (``h_next``); a caller continuing from
there with ``first_step=h_next`` takes exactly the steps of an uninterrupted
run. :func:`rotorkit.simulate` runs every compiled segment this way, in
pieces of about a quarter second of wall time, to look at Ctrl-C, the wall
time limit and the displacement bound between them.

The price of the function-pointer call is small (0-10 % per step against a
loop specialised on one core), plus ~30 us per `integrate` call for numba to
look up the core's address.  A core decorated with an explicit signature must
use exactly `CORE_SIGNATURE`.  Exceptions raised inside the core propagate to
the caller.  The loop releases the GIL (``nogil=True``), so independent runs
can execute in threads.
"""

from __future__ import annotations

import functools
import math
import warnings
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, types
from numba.core.dispatcher import Dispatcher

from rotorkit.errors import ParameterError, RotorkitError

__all__ = [
    "CORE_SIGNATURE",
    "METHODS",
    "STATUS_SUCCESS",
    "STATUS_STEP_TOO_SMALL",
    "STATUS_NON_FINITE",
    "STATUS_MAX_STEPS",
    "CoreSignatureError",
    "RKSolution",
    "compile_loop_in_background",
    "integrate",
]

# ---------------------------------------------------------------------------
# Status codes and controller constants (scipy's rk.py values)
# ---------------------------------------------------------------------------

STATUS_SUCCESS = 0
STATUS_STEP_TOO_SMALL = -1
STATUS_NON_FINITE = -2
STATUS_MAX_STEPS = -3
STATUS_PAUSED = -4
_STATUS_RUNNING = 1

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0

_RK45 = 0
_DOP853 = 1
METHODS = ("RK45", "DOP853")
_METHOD_IDS = {"RK45": _RK45, "DOP853": _DOP853}

_EPS = np.finfo(float).eps

# ---------------------------------------------------------------------------
# Coefficients (data transcribed from scipy.integrate._ivp)
# ---------------------------------------------------------------------------

_RK45_N_STAGES = 6
_RK45_ERROR_ORDER = 4
_RK45_C = np.array([0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1], dtype=np.float64)
_RK45_A = np.array([
    [0, 0, 0, 0, 0],
    [1 / 5, 0, 0, 0, 0],
    [3 / 40, 9 / 40, 0, 0, 0],
    [44 / 45, -56 / 15, 32 / 9, 0, 0],
    [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0],
    [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
], dtype=np.float64)
_RK45_B = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
                   dtype=np.float64)
_RK45_E = np.array([-71 / 57600, 0, 71 / 16695, -71 / 1920, 17253 / 339200,
                    -22 / 525, 1 / 40], dtype=np.float64)
_RK45_P = np.array([
    [1, -8048581381 / 2820520608, 8663915743 / 2820520608,
     -12715105075 / 11282082432],
    [0, 0, 0, 0],
    [0, 131558114200 / 32700410799, -68118460800 / 10900136933,
     87487479700 / 32700410799],
    [0, -1754552775 / 470086768, 14199869525 / 1410260304,
     -10690763975 / 1880347072],
    [0, 127303824393 / 49829197408, -318862633887 / 49829197408,
     701980252875 / 199316789632],
    [0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
    [0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
], dtype=np.float64)
# The loop works row-wise on the dense-output weights: one row per power of x.
_RK45_PT = np.ascontiguousarray(_RK45_P.T)
# Pad A to a square (n_stages + 1) table so both methods share one layout.
_RK45_A_SQ = np.zeros((_RK45_N_STAGES + 1, _RK45_N_STAGES + 1))
_RK45_A_SQ[:_RK45_N_STAGES, :_RK45_N_STAGES - 1] = _RK45_A
_RK45_C_EXT = np.append(_RK45_C, 1.0)

_DOP853_N_STAGES = 12
_DOP853_N_STAGES_EXTENDED = 16
_DOP853_ERROR_ORDER = 7
_DOP853_INTERPOLATOR_POWER = 7

_DOP853_C = np.array([
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
    1.0,
    0.1,
    0.2,
    0.777777777777777777777777777778,
], dtype=np.float64)

# Non-zero entries of the extended Butcher matrix: {row: {column: value}}.
_DOP853_A_ROWS = {
    1: {
        0: 5.26001519587677318785587544488e-2,
    },
    2: {
        0: 1.97250569845378994544595329183e-2,
        1: 5.91751709536136983633785987549e-2,
    },
    3: {
        0: 2.95875854768068491816892993775e-2,
        2: 8.87627564304205475450678981324e-2,
    },
    4: {
        0: 2.41365134159266685502369798665e-1,
        2: -8.84549479328286085344864962717e-1,
        3: 9.24834003261792003115737966543e-1,
    },
    5: {
        0: 3.7037037037037037037037037037e-2,
        3: 1.70828608729473871279604482173e-1,
        4: 1.25467687566822425016691814123e-1,
    },
    6: {
        0: 3.7109375e-2,
        3: 1.70252211019544039314978060272e-1,
        4: 6.02165389804559606850219397283e-2,
        5: -1.7578125e-2,
    },
    7: {
        0: 3.70920001185047927108779319836e-2,
        3: 1.70383925712239993810214054705e-1,
        4: 1.07262030446373284651809199168e-1,
        5: -1.53194377486244017527936158236e-2,
        6: 8.27378916381402288758473766002e-3,
    },
    8: {
        0: 6.24110958716075717114429577812e-1,
        3: -3.36089262944694129406857109825,
        4: -8.68219346841726006818189891453e-1,
        5: 2.75920996994467083049415600797e1,
        6: 2.01540675504778934086186788979e1,
        7: -4.34898841810699588477366255144e1,
    },
    9: {
        0: 4.77662536438264365890433908527e-1,
        3: -2.48811461997166764192642586468,
        4: -5.90290826836842996371446475743e-1,
        5: 2.12300514481811942347288949897e1,
        6: 1.52792336328824235832596922938e1,
        7: -3.32882109689848629194453265587e1,
        8: -2.03312017085086261358222928593e-2,
    },
    10: {
        0: -9.3714243008598732571704021658e-1,
        3: 5.18637242884406370830023853209,
        4: 1.09143734899672957818500254654,
        5: -8.14978701074692612513997267357,
        6: -1.85200656599969598641566180701e1,
        7: 2.27394870993505042818970056734e1,
        8: 2.49360555267965238987089396762,
        9: -3.0467644718982195003823669022,
    },
    11: {
        0: 2.27331014751653820792359768449,
        3: -1.05344954667372501984066689879e1,
        4: -2.00087205822486249909675718444,
        5: -1.79589318631187989172765950534e1,
        6: 2.79488845294199600508499808837e1,
        7: -2.85899827713502369474065508674,
        8: -8.87285693353062954433549289258,
        9: 1.23605671757943030647266201528e1,
        10: 6.43392746015763530355970484046e-1,
    },
    12: {
        0: 5.42937341165687622380535766363e-2,
        5: 4.45031289275240888144113950566,
        6: 1.89151789931450038304281599044,
        7: -5.8012039600105847814672114227,
        8: 3.1116436695781989440891606237e-1,
        9: -1.52160949662516078556178806805e-1,
        10: 2.01365400804030348374776537501e-1,
        11: 4.47106157277725905176885569043e-2,
    },
    13: {
        0: 5.61675022830479523392909219681e-2,
        6: 2.53500210216624811088794765333e-1,
        7: -2.46239037470802489917441475441e-1,
        8: -1.24191423263816360469010140626e-1,
        9: 1.5329179827876569731206322685e-1,
        10: 8.20105229563468988491666602057e-3,
        11: 7.56789766054569976138603589584e-3,
        12: -8.298e-3,
    },
    14: {
        0: 3.18346481635021405060768473261e-2,
        5: 2.83009096723667755288322961402e-2,
        6: 5.35419883074385676223797384372e-2,
        7: -5.49237485713909884646569340306e-2,
        10: -1.08347328697249322858509316994e-4,
        11: 3.82571090835658412954920192323e-4,
        12: -3.40465008687404560802977114492e-4,
        13: 1.41312443674632500278074618366e-1,
    },
    15: {
        0: -4.28896301583791923408573538692e-1,
        5: -4.69762141536116384314449447206,
        6: 7.68342119606259904184240953878,
        7: 4.06898981839711007970213554331,
        8: 3.56727187455281109270669543021e-1,
        12: -1.39902416515901462129418009734e-3,
        13: 2.9475147891527723389556272149,
        14: -9.15095847217987001081870187138,
    },
}

# Non-zero entries of the dense-output matrix D (rows 3..6 of the interpolant).
_DOP853_D_ROWS = {
    0: {
        0: -0.84289382761090128651353491142e+1,
        5: 0.56671495351937776962531783590,
        6: -0.30689499459498916912797304727e+1,
        7: 0.23846676565120698287728149680e+1,
        8: 0.21170345824450282767155149946e+1,
        9: -0.87139158377797299206789907490,
        10: 0.22404374302607882758541771650e+1,
        11: 0.63157877876946881815570249290,
        12: -0.88990336451333310820698117400e-1,
        13: 0.18148505520854727256656404962e+2,
        14: -0.91946323924783554000451984436e+1,
        15: -0.44360363875948939664310572000e+1,
    },
    1: {
        0: 0.10427508642579134603413151009e+2,
        5: 0.24228349177525818288430175319e+3,
        6: 0.16520045171727028198505394887e+3,
        7: -0.37454675472269020279518312152e+3,
        8: -0.22113666853125306036270938578e+2,
        9: 0.77334326684722638389603898808e+1,
        10: -0.30674084731089398182061213626e+2,
        11: -0.93321305264302278729567221706e+1,
        12: 0.15697238121770843886131091075e+2,
        13: -0.31139403219565177677282850411e+2,
        14: -0.93529243588444783865713862664e+1,
        15: 0.35816841486394083752465898540e+2,
    },
    2: {
        0: 0.19985053242002433820987653617e+2,
        5: -0.38703730874935176555105901742e+3,
        6: -0.18917813819516756882830838328e+3,
        7: 0.52780815920542364900561016686e+3,
        8: -0.11573902539959630126141871134e+2,
        9: 0.68812326946963000169666922661e+1,
        10: -0.10006050966910838403183860980e+1,
        11: 0.77771377980534432092869265740,
        12: -0.27782057523535084065932004339e+1,
        13: -0.60196695231264120758267380846e+2,
        14: 0.84320405506677161018159903784e+2,
        15: 0.11992291136182789328035130030e+2,
    },
    3: {
        0: -0.25693933462703749003312586129e+2,
        5: -0.15418974869023643374053993627e+3,
        6: -0.23152937917604549567536039109e+3,
        7: 0.35763911791061412378285349910e+3,
        8: 0.93405324183624310003907691704e+2,
        9: -0.37458323136451633156875139351e+2,
        10: 0.10409964950896230045147246184e+3,
        11: 0.29840293426660503123344363579e+2,
        12: -0.43533456590011143754432175058e+2,
        13: 0.96324553959188282948394950600e+2,
        14: -0.39177261675615439165231486172e+2,
        15: -0.14972683625798562581422125276e+3,
    },
}


def _matrix_from_rows(shape, rows):
    """Build a dense matrix from ``{row: {column: value}}``.

    Parameters
    ----------
    shape : tuple of int
        Shape of the matrix.
    rows : dict
        Non-zero entries.

    Returns
    -------
    numpy.ndarray
        C-contiguous float64 matrix.
    """
    out = np.zeros(shape, dtype=np.float64)
    for i, row in rows.items():
        for j, value in row.items():
            out[i, j] = value
    return out


def _dop853_error_weights(b):
    """Return scipy's ``(E3, E5)`` error weights for DOP853.

    Parameters
    ----------
    b : numpy.ndarray
        Weights of the 8th-order solution (12 entries).

    Returns
    -------
    e3, e5 : numpy.ndarray
        Weights (13 entries, the last one multiplies ``f(t + h, y_new)``) of
        the 3rd- and 5th-order error estimators.
    """
    e3 = np.zeros(_DOP853_N_STAGES + 1)
    e3[:-1] = b
    e3[0] -= 0.244094488188976377952755905512
    e3[8] -= 0.733846688281611857341361741547
    e3[11] -= 0.220588235294117647058823529412e-1
    e5 = np.zeros(_DOP853_N_STAGES + 1)
    e5[0] = 0.1312004499419488073250102996e-1
    e5[5] = -0.1225156446376204440720569753e+1
    e5[6] = -0.4957589496572501915214079952
    e5[7] = 0.1664377182454986536961530415e+1
    e5[8] = -0.3503288487499736816886487290
    e5[9] = 0.3341791187130174790297318841
    e5[10] = 0.8192320648511571246570742613e-1
    e5[11] = -0.2235530786388629525884427845e-1
    return e3, e5


_DOP853_A = _matrix_from_rows(
    (_DOP853_N_STAGES_EXTENDED, _DOP853_N_STAGES_EXTENDED), _DOP853_A_ROWS)
_DOP853_B = _DOP853_A[_DOP853_N_STAGES, :_DOP853_N_STAGES].copy()
_DOP853_E3, _DOP853_E5 = _dop853_error_weights(_DOP853_B)
_DOP853_D = _matrix_from_rows(
    (_DOP853_INTERPOLATOR_POWER - 3, _DOP853_N_STAGES_EXTENDED), _DOP853_D_ROWS)

# ---------------------------------------------------------------------------
# Numba types
# ---------------------------------------------------------------------------

_VEC = types.float64[::1]
_MAT = types.float64[:, ::1]

#: Numba signature every core must accept: ``core(t, y, p, dydt) -> None``.
CORE_SIGNATURE = types.void(types.float64, _VEC, _VEC, _VEC)

_CORE_TYPE = types.FunctionType(CORE_SIGNATURE)
_LOOP_RESULT = types.Tuple((types.int64, types.int64, types.float64,
                            types.int64, types.int64, types.int64, types.float64))
_LOOP_SIGNATURE = _LOOP_RESULT(
    _CORE_TYPE,      # core
    types.int64,     # method id
    types.float64,   # t0
    types.float64,   # t1
    _VEC,            # y0
    _VEC,            # p
    _VEC,            # t_eval
    types.float64,   # rtol
    _VEC,            # atol (length n)
    types.float64,   # first step (<= 0: automatic)
    types.float64,   # max step
    types.int64,     # max steps
    types.int64,     # pause after this many accepted steps (0: never)
    _MAT,            # samples out (n, len(t_eval))
    _VEC,            # last accepted state out
)

# Helpers are compiled into the loop; ``error_model="numpy"`` gives IEEE
# semantics (inf/nan instead of ZeroDivisionError) and no division checks.
_JIT = dict(cache=False, nogil=True, error_model="numpy")

# ---------------------------------------------------------------------------
# Compiled kernels
# ---------------------------------------------------------------------------


@njit(**_JIT)
def _all_finite(x):
    """Return True when every entry of `x` is finite."""
    for v in x:
        if not math.isfinite(v):
            return False
    return True


#: a state beyond this magnitude has diverged (SI rotor states are many orders smaller)
DIVERGED = 1e10


@njit(**_JIT)
def _all_finite_and_bounded(x):
    """Return True when every entry of `x` is finite and below DIVERGED in magnitude."""
    for v in x:
        if not math.isfinite(v) or abs(v) > DIVERGED:
            return False
    return True


@njit(**_JIT)
def _weighted_sum(rows, weights, n_terms, out):
    """Write ``sum(weights[j] * rows[j] for j < n_terms)`` into `out`.

    Zero weights are skipped (this does not change the rounded result).
    """
    n = out.size
    for i in range(n):
        out[i] = 0.0
    for j in range(n_terms):
        w = weights[j]
        if w != 0.0:
            for i in range(n):
                out[i] += rows[j, i] * w


@njit(**_JIT)
def _rms(x, scale):
    """RMS norm of ``x / scale`` as scipy's ``norm`` computes it."""
    acc = 0.0
    for i in range(x.size):
        v = x[i] / scale[i]
        acc += v * v
    return math.sqrt(acc) / x.size ** 0.5


@njit(**_JIT)
def _error_scale(y, y_new, rtol, atol, out):
    """``atol + rtol * max(|y|, |y_new|)`` into `out`."""
    for i in range(y.size):
        out[i] = atol[i] + max(abs(y[i]), abs(y_new[i])) * rtol


@njit(**_JIT)
def _select_initial_step(core, t0, y0, f0, p, t1, max_step, order, rtol,
                         atol, y1, f1, scale):
    """scipy's ``select_initial_step`` (forward direction, one evaluation).

    Returns
    -------
    h_abs : float
        Suggested first step.
    """
    interval_length = abs(t1 - t0)
    if interval_length == 0.0:
        return 0.0
    n = y0.size
    for i in range(n):
        scale[i] = atol[i] + abs(y0[i]) * rtol
    d0 = _rms(y0, scale)
    d1 = _rms(f0, scale)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, interval_length)
    for i in range(n):
        y1[i] = y0[i] + h0 * f0[i]
    core(t0 + h0, y1, p, f1)
    for i in range(n):
        y1[i] = f1[i] - f0[i]
    d2 = _rms(y1, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        # Python's max/min semantics: a NaN candidate is ignored.
        d_max = d2 if d2 > d1 else d1
        h1 = (0.01 / d_max) ** (1.0 / (order + 1))
    h = 100.0 * h0
    for candidate in (h1, interval_length, max_step):
        if candidate < h:
            h = candidate
    return h


@njit(**_JIT)
def _rk_step(core, t, y, h, p, a, b, c, n_stages, k, y_new, y_stage, work):
    """One explicit RK step; ``k[0]`` must hold ``f(t, y)`` on entry.

    Fills ``k[1:n_stages]`` with the stages, `y_new` with the propagated
    state and ``k[n_stages]`` with ``f(t + h, y_new)``.

    Returns
    -------
    n_evals : int
        Number of core evaluations made.
    ok : bool
        False when a stage, the new state or its derivative is not finite
        (the step then stops early).
    """
    n = y.size
    for s in range(1, n_stages):
        _weighted_sum(k, a[s], s, work)
        for i in range(n):
            y_stage[i] = y[i] + work[i] * h
        core(t + c[s] * h, y_stage, p, k[s])
        if not _all_finite(k[s]):
            return s, False
    _weighted_sum(k, b, n_stages, work)
    for i in range(n):
        y_new[i] = y[i] + h * work[i]
    if not _all_finite_and_bounded(y_new):
        return n_stages - 1, False
    core(t + h, y_new, p, k[n_stages])
    if not _all_finite(k[n_stages]):
        return n_stages, False
    return n_stages, True


@njit(**_JIT)
def _rk45_error_norm(k, e, h, scale, work):
    """scipy's RK45 error norm ``norm(h * K.T @ E / scale)``."""
    _weighted_sum(k, e, e.size, work)
    for i in range(work.size):
        work[i] *= h
    return _rms(work, scale)


@njit(**_JIT)
def _dop853_error_norm(k, e5, e3, h, scale, work5, work3):
    """scipy's DOP853 error norm blending the 5th- and 3rd-order estimates."""
    _weighted_sum(k, e5, e5.size, work5)
    _weighted_sum(k, e3, e3.size, work3)
    n = scale.size
    err5_sq = 0.0
    err3_sq = 0.0
    for i in range(n):
        v5 = work5[i] / scale[i]
        v3 = work3[i] / scale[i]
        err5_sq += v5 * v5
        err3_sq += v3 * v3
    if err5_sq == 0.0 and err3_sq == 0.0:
        return 0.0
    denom = err5_sq + 0.01 * err3_sq
    return abs(h) * err5_sq / math.sqrt(denom * n)


@njit(**_JIT)
def _rk45_dense_prepare(k, pt, q):
    """Dense-output weights ``q[j] = (K.T @ P)[:, j]`` of the last step."""
    for j in range(pt.shape[0]):
        _weighted_sum(k, pt[j], pt.shape[1], q[j])


@njit(**_JIT)
def _rk45_dense_eval(q, y_old, t_old, h, t, out, col):
    """Quartic interpolant at `t` written into ``out[:, col]``."""
    x = (t - t_old) / h
    p1 = x
    p2 = p1 * x
    p3 = p2 * x
    p4 = p3 * x
    for i in range(y_old.size):
        acc = q[0, i] * p1 + q[1, i] * p2 + q[2, i] * p3 + q[3, i] * p4
        out[i, col] = h * acc + y_old[i]


@njit(**_JIT)
def _dop853_dense_prepare(core, t_old, h, y_old, y_new, p, a, c, d, k, f,
                          y_stage, work):
    """Three extra stages and the 7 interpolant rows `f` of the last step.

    Returns
    -------
    n_evals : int
        Number of core evaluations made.
    ok : bool
        False when an extra stage is not finite.
    """
    n = y_old.size
    n_base = _DOP853_N_STAGES + 1
    for s in range(n_base, _DOP853_N_STAGES_EXTENDED):
        _weighted_sum(k, a[s], s, work)
        for i in range(n):
            y_stage[i] = y_old[i] + work[i] * h
        core(t_old + c[s] * h, y_stage, p, k[s])
        if not _all_finite(k[s]):
            return s - n_base + 1, False
    f_old = k[0]
    f_new = k[_DOP853_N_STAGES]
    for i in range(n):
        delta = y_new[i] - y_old[i]
        f[0, i] = delta
        f[1, i] = h * f_old[i] - delta
        f[2, i] = 2.0 * delta - h * (f_new[i] + f_old[i])
    for r in range(d.shape[0]):
        _weighted_sum(k, d[r], d.shape[1], work)
        for i in range(n):
            f[3 + r, i] = h * work[i]
    return _DOP853_N_STAGES_EXTENDED - n_base, True


@njit(**_JIT)
def _dop853_dense_eval(f, y_old, t_old, h, t, out, col):
    """7th-order interpolant at `t` written into ``out[:, col]``."""
    x = (t - t_old) / h
    n_rows = f.shape[0]
    for i in range(y_old.size):
        acc = 0.0
        for r in range(n_rows):
            acc += f[n_rows - 1 - r, i]
            if r % 2 == 0:
                acc *= x
            else:
                acc *= 1.0 - x
        out[i, col] = acc + y_old[i]


@njit(**_JIT)
def _copy_column(src, out, col):
    """``out[:, col] = src``."""
    for i in range(src.size):
        out[i, col] = src[i]


@njit(**_JIT)
def _step_factor(error_norm, error_exponent, rejected_before):
    """scipy's step-size factor for an error norm (accepted or not)."""
    if error_norm < 1.0:
        if error_norm == 0.0:
            factor = MAX_FACTOR
        else:
            factor = SAFETY * error_norm ** error_exponent
            if not factor < MAX_FACTOR:
                factor = MAX_FACTOR
        if rejected_before and factor > 1.0:
            factor = 1.0
        return factor
    factor = SAFETY * error_norm ** error_exponent
    if not factor > MIN_FACTOR:  # also catches NaN, like Python's max()
        factor = MIN_FACTOR
    return factor


def _rk_loop(core, method, t0, t1, y0, p, t_eval, rtol, atol, first_step,
             max_step, max_steps, pause_after, samples, y_out):
    """Adaptive loop; compiled lazily by `_compiled_loop` (see there).

    Mirrors scipy's ``solve_ivp`` driver and ``RungeKutta._step_impl``.  The
    step-attempt and sampling logic stays inline on purpose: moving it into
    helper functions measured 5-15 % slower per step (numba passes every
    array as a multi-field struct across calls LLVM does not inline).

    Returns
    -------
    tuple
        ``(status, n_samples_done, t_reached, nfev, n_accepted,
        n_rejected, h_next)``; the samples and the last accepted state are
        written into `samples` and `y_out`. ``h_next`` is the step size the
        controller proposes next: a paused run (``pause_after``) continued
        from ``t_reached`` with ``first_step=h_next`` takes the same steps
        as one that was never paused.
    """
    n = y0.size
    n_eval = t_eval.size
    if method == _RK45:
        a = _RK45_A_SQ
        b = _RK45_B
        c = _RK45_C_EXT
        n_stages = _RK45_N_STAGES
        n_rows = _RK45_N_STAGES + 1
        error_order = _RK45_ERROR_ORDER
    else:
        a = _DOP853_A
        b = _DOP853_B
        c = _DOP853_C
        n_stages = _DOP853_N_STAGES
        n_rows = _DOP853_N_STAGES_EXTENDED
        error_order = _DOP853_ERROR_ORDER
    error_exponent = -1.0 / (error_order + 1)

    k = np.empty((n_rows, n))  # stages; row n_stages is f(t_new, y_new)
    dense = np.empty((_DOP853_INTERPOLATOR_POWER, n))
    y = y0.copy()
    y_new = np.empty(n)
    f = np.empty(n)
    y_stage = np.empty(n)
    work = np.empty(n)
    work2 = np.empty(n)
    scale = np.empty(n)

    # Samples at t0 are the initial state itself.
    capacity = samples.shape[1]  # == n_eval unless pausing: then a step whose samples overflow it is redone later
    i_eval = 0
    while i_eval < n_eval and i_eval < capacity and t_eval[i_eval] <= t0:
        _copy_column(y0, samples, i_eval)
        i_eval += 1

    t = t0
    n_accepted = 0
    n_rejected = 0
    status = _STATUS_RUNNING
    core(t, y, p, f)
    nfev = 1
    if not _all_finite(f):
        status = STATUS_NON_FINITE
    h_abs = first_step
    if status == _STATUS_RUNNING and first_step <= 0.0:
        h_abs = _select_initial_step(core, t0, y0, f, p, t1, max_step,
                                     error_order, rtol, atol, y_stage, work,
                                     scale)
        nfev += 1

    while status == _STATUS_RUNNING:
        if t >= t1:
            status = STATUS_SUCCESS
            break
        if pause_after > 0 and n_accepted >= pause_after:
            status = STATUS_PAUSED  # between two steps: nothing of the controller's state is lost
            break
        if capacity < n_eval and t_eval[capacity] <= t + min(h_abs, max_step):
            status = STATUS_PAUSED  # the next step might sample past the buffer (a step only shrinks)
            break

        # --- one accepted step (scipy's _step_impl) ---------------------
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        non_finite = False
        t_new = t
        h = 0.0
        while True:
            if not h_abs >= min_step:  # also stops on a NaN step size
                if non_finite:
                    status = STATUS_NON_FINITE
                else:
                    status = STATUS_STEP_TOO_SMALL
                break
            if n_accepted + n_rejected >= max_steps:
                status = STATUS_MAX_STEPS
                break
            t_new = t + h_abs
            if t_new > t1:
                t_new = t1
            h = t_new - t
            h_abs = abs(h)

            for i in range(n):
                k[0, i] = f[i]
            n_evals, ok = _rk_step(core, t, y, h, p, a, b, c, n_stages, k,
                                   y_new, y_stage, work)
            nfev += n_evals
            if not ok:  # non-finite stage: retry with a smaller step
                non_finite = True
                rejected = True
                n_rejected += 1
                h_abs *= MIN_FACTOR
                continue
            non_finite = False

            _error_scale(y, y_new, rtol, atol, scale)
            if method == _RK45:
                error_norm = _rk45_error_norm(k, _RK45_E, h, scale, work)
            else:
                error_norm = _dop853_error_norm(k, _DOP853_E5, _DOP853_E3, h,
                                                scale, work, work2)
            h_abs *= _step_factor(error_norm, error_exponent, rejected)
            if error_norm < 1.0:
                break
            rejected = True
            n_rejected += 1
        if status != _STATUS_RUNNING:
            break
        n_accepted += 1

        # --- samples inside (t, t_new] from the step's dense output -----
        if i_eval < n_eval and t_eval[i_eval] <= t_new:
            if method == _RK45:
                _rk45_dense_prepare(k, _RK45_PT, dense)
            else:
                n_evals, ok = _dop853_dense_prepare(
                    core, t, h, y, y_new, p, a, c, _DOP853_D, k, dense,
                    y_stage, work)
                nfev += n_evals
                if not ok:  # keep t, y at the last step fully sampled
                    status = STATUS_NON_FINITE
                    break
            while i_eval < n_eval and t_eval[i_eval] <= t_new:
                t_sample = t_eval[i_eval]
                if t_sample == t_new:
                    _copy_column(y_new, samples, i_eval)
                elif method == _RK45:
                    _rk45_dense_eval(dense, y, t, h, t_sample, samples, i_eval)
                else:
                    _dop853_dense_eval(dense, y, t, h, t_sample, samples,
                                       i_eval)
                i_eval += 1

        t = t_new
        y, y_new = y_new, y
        for i in range(n):
            f[i] = k[n_stages, i]

    for i in range(n):
        y_out[i] = y[i]
    return status, i_eval, t, nfev, n_accepted, n_rejected, h_abs


def _build_loop():
    """Compile (or load from numba's on-disk cache) the adaptive loop; the caller holds the cache's lock."""
    from ..codegen.cache import jit_shared

    return jit_shared(_rk_loop, "rk_loop", _LOOP_SIGNATURE, nogil=True, error_model="numpy")


@functools.lru_cache(maxsize=None)
def _compiled_loop():
    """Compile (or load from numba's on-disk cache) the adaptive loop.

    Waits, holding the cache's lock, for another process compiling it into
    the same cache (`compile_loop_in_background`), then loads its result.

    Returns
    -------
    numba.core.dispatcher.Dispatcher
        The loop, compiled for `_LOOP_SIGNATURE` only.
    """
    from ..codegen.cache import shared_lock

    with shared_lock("rk_loop") as lock:
        if lock is not None:
            _reap_background()
        return _build_loop()


def _reap_background():
    """Collect the processes `compile_loop_in_background` started: holding the lock, they have finished or are exiting."""
    import subprocess

    for process in _BACKGROUND:
        try:
            process.wait(timeout=5)
        except subprocess.TimeoutExpired:  # pragma: no cover - it released the lock, so it is on its way out
            pass


#: set ROTORKIT_BACKGROUND_COMPILE=0 to never compile the loop in another process
BACKGROUND_VARIABLE = "ROTORKIT_BACKGROUND_COMPILE"
_BACKGROUND = []  # processes this one started (kept so they are not reaped as garbage while running)


def compile_loop_in_background():
    """Start compiling the integration loop into rotorkit's cache in another process, if it needs compiling.

    The loop takes seconds to compile the first time (it is cached on disk
    afterwards). A caller that knows it will integrate soon, but has other
    work first (``rotorkit run`` derives and compiles its model), starts it
    here so the two compilations run on two cores at once. The other process
    holds the cache's lock from before it starts until it has written and
    signed the cache; the first `integrate` of this process waits for that
    lock and loads the result (if the other process failed, it compiles the
    loop itself, as without this call). The other process runs in its own
    session (Ctrl-C here does not interrupt it half-way through writing the
    cache) and finishes even if this one ends first.

    Nothing is started when the loop is already loaded in this process or
    compiled in the cache, when another process holds the lock, on a single
    core, or with ``ROTORKIT_BACKGROUND_COMPILE=0``.

    Returns
    -------
    subprocess.Popen or None
        The process started, if any.
    """
    import os
    import subprocess
    import sys
    from pathlib import Path

    from ..codegen import cache

    if os.environ.get(BACKGROUND_VARIABLE, "").strip() == "0" or _compiled_loop.cache_info().currsize:
        return None
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if cores < 2 or cache.shared_is_current("rk_loop", __file__):
        return None
    root = str(Path(__file__).resolve().parents[2])  # the folder holding the rotorkit package
    code = f"import sys; sys.path.insert(0, {root!r}); from rotorkit.engines import rk_numba; rk_numba._build_loop()"
    with cache.shared_lock("rk_loop", blocking=False) as lock:
        if lock is None:
            return None  # locking unavailable, or another process is compiling it right now
        try:
            process = subprocess.Popen(
                [sys.executable, "-c", code], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL, pass_fds=(lock.fileno(),), start_new_session=True,
                env=dict(os.environ, ROTORKIT_CACHE_DIR=str(cache.cache_dir())))
        except OSError:
            return None
    # the child holds the lock through the inherited descriptor until it exits
    _BACKGROUND.append(process)
    return process


# ---------------------------------------------------------------------------
# Python front end
# ---------------------------------------------------------------------------


class CoreSignatureError(RotorkitError, TypeError):
    """The right-hand side is not a numba function accepting `CORE_SIGNATURE`."""


class RKSolution(NamedTuple):
    """Result of `integrate`.

    Attributes
    ----------
    t : numpy.ndarray, shape (m,)
        The requested output times (``t_eval``).
    y : numpy.ndarray, shape (n_states, m)
        Samples at ``t``.  Only the first ``n_samples_done`` columns are valid;
        the others (times after ``t_reached`` on failure) are NaN.
    n_samples_done : int
        Number of valid columns of ``y``: every ``t_eval`` not after
        ``t_reached``.
    status : int
        0 success; -1 step size fell below ``10 * eps * |t|``; -2 non-finite
        state or derivative; -3 ``max_steps`` exceeded; -4 paused after
        ``pause_after`` accepted steps (continue from ``t_reached``,
        ``y_reached`` with ``first_step=h_next``).
    t_reached : float
        Time of the last accepted step (``t1`` on success).
    y_reached : numpy.ndarray, shape (n_states,)
        State at ``t_reached``.
    nfev : int
        Number of core evaluations (including the initial-step heuristic and
        the DOP853 dense-output stages).
    n_accepted, n_rejected : int
        Number of accepted and rejected step attempts (a step rejected for a
        non-finite value counts as rejected).
    message : str
        Human-readable description of ``status``.
    h_next : float
        The step size the controller proposes after ``t_reached``.
    """

    t: np.ndarray
    y: np.ndarray
    n_samples_done: int
    status: int
    t_reached: float
    y_reached: np.ndarray
    nfev: int
    n_accepted: int
    n_rejected: int
    message: str
    h_next: float = float("nan")

    @property
    def success(self):
        """bool: True when the integration reached ``t1``."""
        return self.status == STATUS_SUCCESS


def _status_message(status, t_reached, max_steps):
    """Human-readable text for a loop status."""
    if status == STATUS_SUCCESS:
        return "The solver successfully reached the end of the integration interval."
    if status == STATUS_STEP_TOO_SMALL:
        return (f"Required step size is less than spacing between numbers "
                f"(step fell below 10*eps*|t|) at t={t_reached!r}.")
    if status == STATUS_NON_FINITE:
        return (f"Non-finite or diverging state (NaN, inf or |y| > {DIVERGED:g}) or non-finite derivative "
                f"just after t={t_reached!r}; integration stopped.")
    if status == STATUS_PAUSED:
        return f"Paused at t={t_reached!r} as asked (pause_after)."
    if status == STATUS_MAX_STEPS:
        return (f"Maximum number of step attempts (max_steps={max_steps}) "
                f"exceeded at t={t_reached!r}.")
    return f"Unknown status {status} at t={t_reached!r}."


def _method_id(method):
    """Map a method name to its loop id (ParameterError if unknown)."""
    try:
        return _METHOD_IDS[method]
    except (KeyError, TypeError):
        raise ParameterError(
            f"method={method!r} is not supported; expected one of "
            f"{', '.join(repr(m) for m in METHODS)}.") from None


def _check_core(core):
    """Reject cores that are not numba dispatchers."""
    if not isinstance(core, Dispatcher):
        raise CoreSignatureError(
            f"core={core!r} must be a numba @njit function "
            f"core(t, y, p, dydt) -> None; got {type(core).__name__}.")


def _raise_if_bad_signature(core):
    """Raise CoreSignatureError when `core` cannot compile for CORE_SIGNATURE.

    Only called after the loop failed, so the happy path pays nothing.
    """
    try:
        core.get_compile_result(CORE_SIGNATURE)
    except (numba.core.errors.NumbaError, TypeError) as exc:
        raise CoreSignatureError(
            f"core={core!r} cannot be compiled as core(t: float64, "
            f"y: float64[::1], p: float64[::1], dydt: float64[::1]) -> None: "
            f"{exc}") from exc


def _as_float(value, name):
    """A finite float, else ParameterError naming `name`."""
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}={value!r} must be a real number.") from None
    if not math.isfinite(out):
        raise ParameterError(f"{name}={value!r} must be finite.")
    return out


def _as_vector(value, name, *, allow_empty):
    """A fresh C-contiguous float64 1-D copy of `value`."""
    try:
        out = np.array(value, dtype=np.float64, ndmin=1)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{name} must be a 1-D array of real numbers; got {value!r}.") from None
    if out.ndim != 1:
        raise ParameterError(
            f"{name} must be 1-D; got an array of shape {out.shape}.")
    if not allow_empty and out.size == 0:
        raise ParameterError(f"{name} must not be empty.")
    return np.ascontiguousarray(out)


def _as_state(y0):
    """Validated initial state."""
    y0 = _as_vector(y0, "y0", allow_empty=False)
    if not np.all(np.isfinite(y0)):
        raise ParameterError(f"y0 must be finite; got {y0!r}.")
    return y0


def _as_t_eval(t_eval, t0, t1):
    """Validated output times (sorted, inside [t0, t1])."""
    t_eval = _as_vector(t_eval, "t_eval", allow_empty=True)
    if t_eval.size and (np.any(np.isnan(t_eval)) or t_eval[0] < t0
                        or t_eval[-1] > t1):
        raise ParameterError(
            f"t_eval values must lie inside [t0, t1] = [{t0!r}, {t1!r}]; got "
            f"range [{t_eval.min()!r}, {t_eval.max()!r}].")
    if np.any(np.diff(t_eval) < 0):
        raise ParameterError("t_eval must be sorted in increasing order.")
    return t_eval


def _as_rtol(rtol):
    """Validated scalar rtol, raised to 100*eps like scipy (with a warning)."""
    rtol = _as_float(rtol, "rtol")
    if rtol < 0:
        raise ParameterError(f"rtol={rtol!r} must be non-negative.")
    if rtol < 100 * _EPS:
        warnings.warn(f"rtol={rtol!r} is too small; using rtol={100 * _EPS!r}.",
                      stacklevel=3)
        rtol = 100 * _EPS
    return rtol


def _as_atol(atol, n):
    """Validated atol as a length-`n` vector."""
    try:
        arr = np.array(atol, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(
            f"atol must be a real scalar or a 1-D array; got {atol!r}.") from None
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    elif arr.shape != (n,):
        raise ParameterError(
            f"atol must be a scalar or have shape ({n},) like y0; got shape "
            f"{arr.shape}.")
    if not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise ParameterError(f"atol must be finite and non-negative; got {atol!r}.")
    return np.ascontiguousarray(arr)


def _as_first_step(first_step, t0, t1):
    """First step as a float; 0.0 means "select automatically"."""
    if first_step is None:
        return 0.0
    first_step = _as_float(first_step, "first_step")
    if first_step <= 0:
        raise ParameterError(f"first_step={first_step!r} must be positive.")
    if first_step > t1 - t0:
        raise ParameterError(
            f"first_step={first_step!r} exceeds the interval length "
            f"t1 - t0 = {t1 - t0!r}.")
    return first_step


def _as_max_step(max_step):
    """Validated max_step (positive, may be inf)."""
    try:
        max_step = float(max_step)
    except (TypeError, ValueError):
        raise ParameterError(f"max_step={max_step!r} must be a real number.") from None
    if not max_step > 0:
        raise ParameterError(f"max_step={max_step!r} must be positive (inf allowed).")
    return max_step


def _as_max_steps(max_steps):
    """Validated max_steps (positive integer)."""
    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)):
        raise ParameterError(f"max_steps={max_steps!r} must be a positive integer.")
    if max_steps <= 0:
        raise ParameterError(f"max_steps={max_steps!r} must be a positive integer.")
    return int(max_steps)


def integrate(core, t0, t1, y0, p, t_eval, *, method="DOP853", rtol=1e-6,
              atol=1e-9, first_step=None, max_step=np.inf,
              max_steps=50_000_000, pause_after=None, sample_capacity=None):
    """Integrate ``dy/dt = core(t, y, p)`` from `t0` to `t1` in compiled code.

    Parameters
    ----------
    core : numba dispatcher
        ``@njit`` function ``core(t, y, p, dydt) -> None`` writing the
        derivative into ``dydt`` (see `CORE_SIGNATURE`).
    t0, t1 : float
        Start and end time, ``t1 >= t0``.  The last step is clipped to land
        exactly on `t1`.
    y0 : array_like, shape (n,)
        Initial state (finite, non-empty).
    p : array_like, shape (n_p,) or None
        Parameter vector passed unchanged to `core` (``None``: empty).
    t_eval : array_like, shape (m,)
        Sorted output times inside ``[t0, t1]`` (endpoints allowed, may be
        empty).  Samples come from the dense output of each accepted step;
        they never shorten steps.  A sample at a step end is the step's state.
    method : {"DOP853", "RK45"}, optional
        Runge-Kutta pair, with scipy's coefficients and dense output.
    rtol : float, optional
        Relative tolerance (raised to ``100 * eps`` with a warning like scipy).
    atol : float or array_like, shape (n,), optional
        Absolute tolerance, scalar or per state.  With ``atol = 0`` a state
        component that is (or passes through) zero makes the error norm
        undefined and the run stops with status -1.
    first_step : float, optional
        Initial step; by default chosen with scipy's heuristic.
    max_step : float, optional
        Largest allowed step (default unbounded).
    max_steps : int, optional
        Largest number of step attempts (accepted plus rejected).
    pause_after : int, optional
        Return (status -4) after this many accepted steps, between two
        steps. Continuing from ``t_reached``/``y_reached`` with
        ``first_step=h_next`` takes the same steps as an unpaused run, so a
        caller can look at the clock, its samples or Ctrl-C between pieces
        without changing the result.
    sample_capacity : int, optional
        With ``pause_after``: allocate samples for at most this many of the
        ``t_eval`` (a long run's later samples are taken by later pieces).
        The run also pauses, between two steps, when the next step might
        sample past the buffer; a buffer too small for the first step alone
        is enlarged here.

    Returns
    -------
    RKSolution
        Samples, final state, status, counters and message.  Failures are
        reported through ``status``/``message``, never raised.

    Raises
    ------
    ParameterError
        An argument has a bad value (unknown method, t1 < t0, t_eval outside
        the interval, bad tolerance, ...).  It derives from ``ValueError``.
    CoreSignatureError
        `core` is not a numba function accepting `CORE_SIGNATURE`.

    Notes
    -----
    The error control is scipy's: error norm = RMS of
    ``err / (atol + rtol * max(|y|, |y_new|))``, step factor
    ``0.9 * norm ** (-1 / (q + 1))`` clipped to ``[0.2, 10]`` with ``q`` the
    error-estimator order (4 for RK45, 7 for DOP853), no growth right after a
    rejection.  The compiled loop is built on the first call (a few seconds,
    or ~0.1 s when numba's on-disk cache is warm); every later call, with any
    core, reuses it.

    Examples
    --------
    >>> import numba, numpy as np
    >>> @numba.njit
    ... def decay(t, y, p, dydt):
    ...     dydt[0] = -p[0] * y[0]
    >>> sol = integrate(decay, 0.0, 1.0, [1.0], [2.0], [0.5, 1.0])
    >>> sol.status, bool(abs(sol.y[0, -1] - np.exp(-2.0)) < 1e-7)
    (0, True)
    """
    method_id = _method_id(method)
    _check_core(core)
    t0 = _as_float(t0, "t0")
    t1 = _as_float(t1, "t1")
    if t1 < t0:
        raise ParameterError(
            f"t1={t1!r} must not be smaller than t0={t0!r} (only forward "
            f"integration is supported).")
    y0 = _as_state(y0)
    p = _as_vector([] if p is None else p, "p", allow_empty=True)
    t_eval = _as_t_eval(t_eval, t0, t1)
    rtol = _as_rtol(rtol)
    atol = _as_atol(atol, y0.size)
    first_step = _as_first_step(first_step, t0, t1)
    max_step = _as_max_step(max_step)
    max_steps = _as_max_steps(max_steps)
    pause_after = 0 if pause_after is None else _as_max_steps(pause_after)

    columns = t_eval.size
    if pause_after and sample_capacity is not None:
        columns = min(columns, max(1, _as_max_steps(sample_capacity)))
    y_reached = np.empty_like(y0)
    if _compiled_loop.cache_info().currsize:
        loop = _compiled_loop()
    else:
        from ..progress import announce_if_slow

        with announce_if_slow("waiting for the integrator being compiled in another process (once per cache)"
                              if any(p.poll() is None for p in _BACKGROUND) else
                              "loading the compiled integrator (compiled once per installation, ~5-10 s; "
                              "numba caches it on disk)"):
            loop = _compiled_loop()
    spent = 0  # core evaluations and rejected attempts of starts whose first step did not fit the buffer
    rejected_before = 0
    while True:
        samples = np.full((y0.size, columns), np.nan)
        try:
            status, n_done, t_reached, nfev, n_acc, n_rej, h_next = loop(
                core, method_id, t0, t1, y0, p, t_eval, rtol, atol, first_step,
                max_step, max_steps, pause_after, samples, y_reached)
        except (numba.core.errors.NumbaError, TypeError) as exc:
            _raise_if_bad_signature(core)
            raise  # the core compiled fine: the error is its own, keep it as is
        if not (status == STATUS_PAUSED and n_acc == 0 and columns < t_eval.size):
            break
        # the first step's samples alone overflow the buffer: redo it with a larger one
        columns, first_step = min(t_eval.size, 2 * columns), h_next
        spent, rejected_before = spent + nfev, rejected_before + n_rej
    nfev, n_rej = nfev + spent, n_rej + rejected_before
    return RKSolution(
        t=t_eval[:samples.shape[1]], y=samples, n_samples_done=int(n_done), status=int(status),
        t_reached=float(t_reached), y_reached=y_reached, nfev=int(nfev),
        n_accepted=int(n_acc), n_rejected=int(n_rej),
        message=_status_message(status, t_reached, max_steps), h_next=float(h_next))
